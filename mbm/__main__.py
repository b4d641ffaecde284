"""``python -m mbm``: the command line of :mod:`mbm.cli.main`."""

import sys

from .cli.main import main

if __name__ == "__main__":
    sys.exit(main())
