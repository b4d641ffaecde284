"""Figures 1–6 of Beléndez et al. (2007), "Exact solution for the nonlinear pendulum"
==================================================================================

θ'' + ω₀² sin θ = 0, θ(0) = θ₀, θ'(0) = 0: the exact solution (31) (bold) against the
harmonic approximation (32) with the exact frequency (33) (thin), as functions of
ω₀t, for the paper's amplitudes θ₀ = 0.1π, 0.25π, 0.5π, 0.75π, 0.9π and 0.99π
(18°, 45°, 90°, 135°, 162°, 178.2°).  The two share the period, so they agree at
every half period; in between the harmonic curve departs visibly from 0.75π on.

Usage::

    python fig_belendez2007.py [OUT_DIR]   # PNGs to OUT_DIR, else $MBM_EXAMPLES_OUT, else ./out
"""

import math
import os
import sys
from pathlib import Path

import matplotlib
import numpy as np

import mbm

matplotlib.use("Agg")  # the figures go to PNG files: no display needed
import matplotlib.pyplot as plt  # noqa: E402

# The amplitudes of Figs. 1-6, in units of π, as printed in the captions.
AMPLITUDES_PI = (0.1, 0.25, 0.5, 0.75, 0.9, 0.99)
# ω₀t range: the paper plots a few periods; 0 ≤ ω₀t ≤ 30 shows 1.3 to 4.7 of them.
T_END = 30.0
# Output points: resolves the steep, nearly square wave at 0.99π.
N_POINTS = 601


def out_dir(path=None):
    """The folder the PNGs go to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def compute(n_points=N_POINTS, amplitudes_pi=AMPLITUDES_PI):
    """The curves of Figures 1–6 (ω₀ = 1, so t is ω₀t).

    Parameters
    ----------
    n_points : int, optional
        Times on [0, 30].
    amplitudes_pi : sequence of float, optional
        Amplitudes θ₀/π.

    Returns
    -------
    dict
        ``t`` and ``curves``: {θ₀/π: (θ exact (31), θ harmonic (32), period (26))}.
    """
    model = mbm.Pendulum()
    t = np.linspace(0.0, T_END, n_points)
    curves = {}
    for a in amplitudes_pi:
        th0 = a * math.pi
        exact = mbm.get_approximant("belendez").anchor(model, th0, 0.0)(t)[0]
        harmonic = mbm.get_approximant("harmonic").anchor(model, th0, 0.0)(t)[0]
        curves[a] = (exact, harmonic, float(mbm.period(model, [th0, 0.0])))
    return {"t": t, "curves": curves}


def main(out=None, n_points=N_POINTS, amplitudes_pi=AMPLITUDES_PI):
    """Draw Figures 1–6 and save ``belendez2007_fig1.png`` … (one per amplitude).

    Parameters
    ----------
    out : str or Path, optional
        Output directory.
    n_points : int, optional
    amplitudes_pi : sequence of float, optional

    Returns
    -------
    (dict, list of Path)
        The plotted data (:func:`compute`) and the PNGs written.
    """
    d = compute(n_points, amplitudes_pi)
    out = out_dir(out)
    paths = []
    for k, (a, (exact, harmonic, per)) in enumerate(d["curves"].items(), start=1):
        fig, ax = plt.subplots(figsize=(7, 3.6))
        ax.plot(d["t"], exact, "k", lw=2.2, label="exact (31)")
        ax.plot(d["t"], harmonic, "k", lw=0.8, label="harmonic, exact frequency (32)–(33)")
        ax.axhline(0.0, color="0.7", lw=0.5)
        ax.set_xlabel(r"$\omega_0 t$")
        ax.set_ylabel(r"$\theta$ (rad)")
        ax.set_title(rf"Beléndez et al. (2007) Fig. {k}: $\theta_0$ = {a:g}π "
                     rf"({math.degrees(a * math.pi):.1f}°), period {per:.4f}")
        ax.legend(fontsize=8, loc="lower left")
        fig.tight_layout()
        paths.append(out / f"belendez2007_fig{k}.png")
        fig.savefig(paths[-1], dpi=110)
        plt.close(fig)
    return d, paths


if __name__ == "__main__":
    data, pngs = main(sys.argv[1] if len(sys.argv) > 1 else None)
    for a, (exact, harmonic, per) in data["curves"].items():
        print(f"theta0 = {a:5.2f} pi: period {per:.6f}, max |exact - harmonic| = "
              f"{np.max(np.abs(exact - harmonic)):.4f} rad")
    print("wrote", *pngs)
