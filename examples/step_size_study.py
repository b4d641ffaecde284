"""Step-size study: MBM error against the window length τ, with fitted orders
==========================================================================

Runs :func:`mbm.cli.study.run_study` (the engine of ``mbm study``) on the second
paper's Example 1 for a convergent Taylor approximant, a 4th-order splitting and the
paper's own ℘ approximant, prints the table and saves error-vs-τ and error-vs-time
plots.  The ℘ approximant levels off at the model error of the Chebyshev cubic (2.3)
(~3e-3): re-anchoring does not remove a model error.

The table states the reference's own error (heyoka in long double, or DOP853 without
heyoka, checked against mbm at its tightest tolerance), marks the points within 10× of
it as at the reference's floor and fits the order over the asymptotic range only, with
its standard error (:mod:`mbm.cli.orderfit`).

Usage::

    python step_size_study.py [OUT_DIR]   # PNGs to OUT_DIR, else $MBM_EXAMPLES_OUT, else ./out
"""

import os
import sys
from pathlib import Path

from mbm.cli import study as cli_study

# Scene: the second paper's Example 1 (β = 0.1, γ = 0.3, θ₀ = 30°, 0 ≤ t ≤ 80).
SCENE = cli_study.SCENES["ex1"]
# One convergent high-order family, one classical-order splitting, the paper's formula.
APPROXIMANTS = ("taylor8", "split4", "salas-torque")
TAUS = cli_study.DEFAULT_TAUS


def out_dir(path=None):
    """The folder the PNGs go to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def compute(taus=TAUS, approximants=APPROXIMANTS, n_out=201):
    """The study behind the figure.

    Parameters
    ----------
    taus : sequence of float, optional
    approximants : sequence of str, optional
    n_out : int, optional
        Output times where the error is measured.

    Returns
    -------
    dict
        As :func:`mbm.cli.study.run_study` (``rows``, ``fits``, ``orders``, ``curves``, ``t``,
        ``ref``, ``ref_error``).
    """
    return cli_study.run_study(SCENE, list(approximants), taus=list(taus), n_out=n_out,
                               show_progress=False)


def main(out=None, taus=TAUS, approximants=APPROXIMANTS):
    """Run the study, print its table and save ``step_size_study.png``.

    Parameters
    ----------
    out : str or Path, optional
        Output directory.
    taus, approximants : sequence, optional

    Returns
    -------
    (dict, Path)
        The study and the PNG written.
    """
    study = compute(taus, approximants)
    path = out_dir(out) / "step_size_study.png"
    cli_study.plot_study(study, path)
    return study, path


if __name__ == "__main__":
    s, png = main(sys.argv[1] if len(sys.argv) > 1 else None)
    print(cli_study.format_table(s))
    print("wrote", png)
