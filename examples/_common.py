"""Shared plumbing of the figure examples: output directory and a file-only backend."""

import os
import sys
from pathlib import Path

# The repository root (mbm itself is imported as installed: `pip install -e .`).
ROOT = Path(__file__).resolve().parents[1]

# Environment variable naming the directory the examples write their PNGs to.
OUT_ENV = "MBM_EXAMPLES_OUT"
# Default output directory (git-ignored): generated files stay out of the sources.
DEFAULT_OUT = ROOT / "examples" / "out"


def out_dir(path=None):
    """The directory to save figures in, created if needed.

    Parameters
    ----------
    path : str or Path, optional
        Explicit directory; else ``$MBM_EXAMPLES_OUT``; else ``examples/out/``.

    Returns
    -------
    Path
    """
    d = Path(path or os.environ.get(OUT_ENV) or DEFAULT_OUT)
    d.mkdir(parents=True, exist_ok=True)
    return d


def pyplot():
    """matplotlib.pyplot on the Agg backend (files only; no display needed or assumed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def cli_out(argv=None):
    """The output directory from the command line (first argument), if any."""
    argv = sys.argv[1:] if argv is None else argv
    return argv[0] if argv else None
