"""Shapiro steps of a microwave-driven Josephson junction (RCSJ model), with :func:`mbm.shapiro_steps`
===================================================================================================

The bias current is γ + A sin(Ωt): θ'' + βθ' + sin θ = γ + A sin(Ωt) in reduced units
(θ the phase, ⟨θ'⟩ the dc voltage).  The drive locks the phase's rotation to the drive,
and the I–V curve shows plateaus ⟨θ'⟩ = nΩ (Shapiro steps).  Left: the I–V curve at a
few amplitudes A (:func:`mbm.iv_curve`).  Right: the widths of the steps n = 0, 1, 2
against A/Ω, each edge bisected to ``CURRENT_TOL`` by :func:`mbm.shapiro_steps` (a step
in two pieces counts both), beside the high-frequency limit 2|J_n(A/(βΩ))| of the
overdamped junction (a guide: at β = 2, Ω = 1 the drive is not yet fast, βΩ = 2): the
first of the Bessel-like lobes, the zero step shrinking as the steps n = 1, 2 open.

Usage::

    python shapiro_steps.py [OUT_DIR] [--quick]   # PNGs to OUT_DIR, else $MBM_EXAMPLES_OUT, else ./out
"""

import os
import sys
import warnings
from pathlib import Path

import matplotlib
import numpy as np

import mbm

matplotlib.use("Agg")  # the figures go to PNG files: no display needed
import matplotlib.pyplot as plt  # noqa: E402

BETA = 2.0
FREQ = 1.0
IV_AMPLITUDES = (0.0, 0.5, 1.0, 1.5)
STEPS = (0, 1, 2)
# A point of an I–V curve is drawn on step n when its ⟨θ'⟩ is nΩ to this (on a step it
# is nΩ to round-off).
ON_STEP = 1e-6
# The edges' bisection width: a hundredth of the widths drawn (the figure's resolution).
CURRENT_TOL = 1e-3


def out_dir(path=None):
    """The folder the PNGs go to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def step_widths(beta, freq, amplitudes, gamma_max, points):
    """Widths of the steps n = 0, 1, 2 at each amplitude (:func:`mbm.shapiro_steps`,
    ``points`` grid points over [0, gamma_max]); undriven (A = 0) the zero step is
    |γ| ≤ ω² = 1 and there are no others.  Returns ``(widths, results)``: ``widths[i, j]``
    for step ``STEPS[i]`` at ``amplitudes[j]``, ``results`` amplitude → ShapiroSteps."""
    widths = np.zeros((len(STEPS), len(amplitudes)))
    results = {}
    for j, a in enumerate(amplitudes):
        if a == 0.0:
            widths[0, j] = 2.0
            continue
        s = mbm.shapiro_steps(beta, (0.0, gamma_max), amplitude=a, frequency=freq, orders=STEPS,
                              current_tol=CURRENT_TOL, points=points)
        results[a] = s
        for i, n in enumerate(STEPS):
            widths[i, j] = sum(x.width for x in s.steps if (x.p, x.q) == (n, 1) and np.isfinite(x.width))
    return widths, results


def main(out=None, beta=BETA, freq=FREQ, n_gamma=161, n_amp=11, n_grid=41):
    """Draw the steps and their widths; save ``shapiro_steps.png``.

    Returns ``(data, path)``: ``data`` holds the I–V curves (``iv``: amplitude →
    IVCurve, ``n_gamma`` points), the amplitudes, the widths (``widths[i, j]``: step
    ``STEPS[i]`` at ``amplitudes[j]``) and the step tables (``steps``: amplitude →
    ShapiroSteps, ``n_grid`` grid points each: a step narrower than their spacing can
    fall between two of them, and is then missing, drawn as width 0).
    """
    from scipy.special import jv

    gammas = np.linspace(0.0, 2.6 * beta * freq, n_gamma)
    with warnings.catch_warnings():
        # points between the steps that did not settle are drawn as measured (their
        # IVCurve.converged is False)
        warnings.simplefilter("ignore", RuntimeWarning)
        iv = {a: mbm.iv_curve(beta, gammas, drive_amplitude=a, drive_frequency=freq) for a in IV_AMPLITUDES}
    amplitudes = np.linspace(0.0, 4.0 * freq, n_amp)
    widths, steps = step_widths(beta, freq, amplitudes, gammas[-1], n_grid)

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 5))
    for a, c in iv.items():
        ax1.plot(c.mean_velocity / freq, c.gamma, ".-", ms=2, lw=0.8, label=f"A = {a:g}")
    for n in STEPS[1:]:
        ax1.axvline(n, color="0.6", ls=":", lw=0.7)
    ax1.set_xlabel(r"$\langle\theta'\rangle / \Omega$")
    ax1.set_ylabel(r"bias $\gamma$")
    ax1.set_title(rf"I–V under a drive: $\beta$ = {beta:g}, $\Omega$ = {freq:g}")
    ax1.legend(fontsize=8)
    x = np.linspace(0.0, amplitudes[-1], 400)
    for i, n in enumerate(STEPS):
        line, = ax2.plot(amplitudes / freq, widths[i], "o-", ms=3, lw=1, label=f"n = {n}")
        ax2.plot(x / freq, 2.0 * np.abs(jv(n, x / (beta * freq))), "--", lw=0.8, color=line.get_color())
    ax2.set_xlabel(r"$A/\Omega$")
    ax2.set_ylabel(r"step width $\Delta\gamma$")
    ax2.set_title(r"step widths (dashed: $2|J_n(A/\beta\Omega)|$, the high-frequency limit)")
    ax2.legend(fontsize=8)
    path = out_dir(out) / "shapiro_steps.png"
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return {"iv": iv, "amplitudes": amplitudes, "widths": widths, "gammas": gammas, "steps": steps}, path


if __name__ == "__main__":
    quick = "--quick" in sys.argv[1:]
    args = [a for a in sys.argv[1:] if a != "--quick"]
    data, png = main(args[0] if args else None, **(dict(n_gamma=41, n_amp=4, n_grid=21) if quick else {}))
    for a, w in zip(data["amplitudes"], data["widths"].T):
        print(f"A/Omega = {a / FREQ:5.2f}: widths " + ", ".join(f"n={n}: {x:.3f}" for n, x in zip(STEPS, w)))
    print("wrote", png)
