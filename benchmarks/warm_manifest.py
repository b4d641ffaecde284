"""Regenerate mbm's compile-helper manifest (``mbm/compile/manifest.pkl``, :mod:`mbm.compile.warm`).

    python -m benchmarks.warm_manifest

Each first-call scene of ``mbm.compile.warm.SCENES`` runs in a fresh process with an empty
numba cache; the kernels it compiled, with their signatures, are written in the order a
helper compiles them.  Run it after a change to a kernel's signature or to the kernels an
entry calls (``tests/compile/test_warm.py`` says when), and with each numba upgrade.
"""

from mbm.compile import warm as _warm


def main():
    for key, entries in _warm.regenerate().items():
        print(key, len(entries), "kernels")


if __name__ == "__main__":
    main()
