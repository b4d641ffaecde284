"""Figures 1–4 of Salas, Martínez & Ocampo (2022), the pendulum with a constant torque
===================================================================================

* Figure 1: Example 1 (β = 0.1, γ = 0.3, θ₀ = 30°, θ̇₀ = 0, 0 ≤ t ≤ 80): the
  numerical solution (Runge–Kutta: scipy's RK45 at rtol 1e-10) against the single ℘
  approximant (4.33) (dashed), and the phase portrait with the equilibrium θ = d dashed.
* Figure 2: Example 2 (γ = 0.6, θ₀ = 90°): the single approximant (4.37) is poor.
* Figure 3: Example 2 by the moving boundary method: successive approximants Θ_j of
  (3.31) (windows τ, the j-th formula continued past jτ).
* Figure 4: Example 2 by the event-point variant (3.32): windows between the event
  points (θ = d crossings, green; turning points θ' = 0, yellow) found by CVODE's root
  finder, each window one ℘ formula anchored at CVODE's state.

Usage::

    python fig_salas2022.py [OUT_DIR]   # PNGs to OUT_DIR, else $MBM_EXAMPLES_OUT, else ./out
"""

import math
import os
import sys
from pathlib import Path

import matplotlib
import numpy as np
from scipy.integrate import solve_ivp

import mbm
import mbm.scenes
from mbm.events.points import (
    KIND_BOTH,
    KIND_CROSSING,
    KIND_TURNING,
    event_function_d,
    event_point_solution,
    hybrid_event_points,
    successive,
)

matplotlib.use("Agg")  # the figures go to PNG files: no display needed
import matplotlib.pyplot as plt  # noqa: E402

# The paper's Examples 1 and 2 (mbm.scenes: P2 and P3), by their catalogue aliases.
EXAMPLES = {"ex1": mbm.scenes.get("ex1"), "ex2": mbm.scenes.get("ex2")}
# Output points on [0, 80]: resolves the ~6.5-long periods smoothly.
N_POINTS = 801
# Tolerances of the "Runge–Kutta" curve: tight enough to stand for the exact solution.
RK_TOL = 1e-10
APPROXIMANT = "salas-torque"
# Window of the successive approximants (Figure 3) and the j shown: Θ_j is exact to
# the cubic model on [0, jτ] and drifts after it, so growing j extends the good part.
TAU = 2.0
JS = (0, 3, 10, 40)


def out_dir(path=None):
    """The folder the PNGs go to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def _scene(name):
    sc = EXAMPLES[name]
    return sc.model, list(sc.y0), sc.t_end


def compute(n_points=N_POINTS, js=JS, tau=TAU):
    """The curves of Figures 1–4.

    Parameters
    ----------
    n_points : int, optional
        Times on [0, 80].
    js : sequence of int, optional
        Numbers of re-anchorings j of the successive approximants (Figure 3).
    tau : float, optional
        Their window length.

    Returns
    -------
    dict
        ``t``; per example ``ex1``/``ex2`` a dict with ``numerical`` (θ, θ' from RK45),
        ``approximant`` (θ, θ' of the single formula) and ``d`` (the equilibrium of
        the cubic model); under ``ex2`` also ``successive`` ({j: θ}), ``tau``,
        ``event_t``, ``event_y``, ``event_kind`` and ``event_solution`` (θ of (3.32)).
    """
    ap = mbm.get_approximant(APPROXIMANT)
    t_end = EXAMPLES["ex1"].t_end
    t = np.linspace(0.0, t_end, n_points)
    data = {"t": t}
    for name in EXAMPLES:
        model, y0, t_end = _scene(name)
        rk = solve_ivp(model, (0.0, t_end), y0, method="RK45", t_eval=t, rtol=RK_TOL, atol=RK_TOL)
        anchored = ap.anchor(model, *y0)
        data[name] = {"numerical": rk.y, "approximant": np.asarray(anchored(t)),
                      "d": float(event_function_d(model, ap))}
    model, y0, t_end = _scene("ex2")
    ex2 = data["ex2"]
    ex2["tau"] = tau
    ex2["successive"] = {j: successive(model, y0, tau, j, APPROXIMANT)(t)[0] for j in js}
    te, ye, kinds = hybrid_event_points(model, (0.0, t_end), y0, ex2["d"])
    ex2["event_t"], ex2["event_y"], ex2["event_kind"] = te, ye, kinds
    ex2["event_solution"] = event_point_solution(model, 0.0, y0, te, ye, APPROXIMANT)(t)[0]
    return data


def main(out=None, n_points=N_POINTS, js=JS):
    """Draw Figures 1–4 and save ``salas2022_fig1.png`` … ``salas2022_fig4.png``.

    Parameters
    ----------
    out : str or Path, optional
        Output directory.
    n_points : int, optional
    js : sequence of int, optional

    Returns
    -------
    (dict, list of Path)
        The plotted data (:func:`compute`) and the PNGs written.
    """
    d = compute(n_points, js)
    t = d["t"]
    out = out_dir(out)
    paths = []

    for fig_no, name in ((1, "ex1"), (2, "ex2")):
        e = d[name]
        sc = EXAMPLES[name]
        beta, gamma, th0 = sc.beta, sc.gamma, math.degrees(sc.theta0)
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
        a1.plot(t, e["numerical"][0], "r", lw=1.3, label="Runge–Kutta (RK45, 1e-10)")
        a1.plot(t, e["approximant"][0], "k--", lw=1.1, label="℘ approximant (2.16)")
        a1.axhline(e["d"], color="0.5", ls="--", lw=0.8)
        a1.set_xlabel("t")
        a1.set_ylabel(r"$\theta$")
        a1.legend(fontsize=8)
        a2.plot(e["numerical"][0], e["numerical"][1], "r", lw=1.0, label="Runge–Kutta")
        a2.plot(e["approximant"][0], e["approximant"][1], "k--", lw=0.9, label="approximant")
        a2.axvline(e["d"], color="0.5", ls="--", lw=0.8)
        a2.set_xlabel(r"$\theta$")
        a2.set_ylabel(r"$\theta'$")
        a2.set_title("phase portrait")
        fig.suptitle(f"Salas et al. (2022) Fig. {fig_no}: β={beta:g}, γ={gamma:g}, θ₀={th0:g}°, "
                     f"d={e['d']:.6f}")
        fig.tight_layout()
        paths.append(out / f"salas2022_fig{fig_no}.png")
        fig.savefig(paths[-1], dpi=110)
        plt.close(fig)

    e = d["ex2"]
    fig, ax = plt.subplots(figsize=(9, 4.5))
    ax.plot(t, e["numerical"][0], "r", lw=2.0, alpha=0.6, label="Runge–Kutta")
    for j, th in e["successive"].items():
        ax.plot(t, th, lw=0.9, label=rf"$\Theta_{{{j}}}$ (j={j}, τ={e['tau']:g})")
    # Clip Θ_0's excursions so the converged curves stay readable.
    ax.set_ylim(np.min(e["numerical"][0]) - 0.3, np.max(e["numerical"][0]) + 0.3)
    ax.set_xlabel("t")
    ax.set_ylabel(r"$\theta$")
    ax.set_title("Salas et al. (2022) Fig. 3: Example 2, successive approximants (3.31)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    paths.append(out / "salas2022_fig3.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(9, 4.5))
    ax.plot(t, e["numerical"][0], "r", lw=2.0, alpha=0.6, label="Runge–Kutta")
    ax.plot(t, e["event_solution"], "k--", lw=1.0, label="event-point MBM (3.32)")
    cross = np.isin(e["event_kind"], (KIND_CROSSING, KIND_BOTH))
    turn = np.isin(e["event_kind"], (KIND_TURNING, KIND_BOTH))
    ax.plot(e["event_t"][cross], e["event_y"][cross, 0], "o", color="green", ms=5, label="θ = d")
    ax.plot(e["event_t"][turn], e["event_y"][turn, 0], "o", color="gold", mec="0.4", ms=5, label="θ' = 0")
    ax.axhline(e["d"], color="0.5", ls="--", lw=0.8)
    ax.set_xlabel("t")
    ax.set_ylabel(r"$\theta$")
    ax.set_title(f"Salas et al. (2022) Fig. 4: Example 2, {e['event_t'].size} event points (CVODE)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    paths.append(out / "salas2022_fig4.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)
    return d, paths


if __name__ == "__main__":
    data, pngs = main(sys.argv[1] if len(sys.argv) > 1 else None)
    for name in EXAMPLES:
        e = data[name]
        print(f"{name}: single approximant max error {np.max(np.abs(e['approximant'][0] - e['numerical'][0])):.3e}")
    e = data["ex2"]
    for j, th in e["successive"].items():
        print(f"ex2: Theta_{j} (tau={e['tau']:g}) max error {np.max(np.abs(th - e['numerical'][0])):.3e}")
    print(f"ex2: event-point MBM max error {np.max(np.abs(e['event_solution'] - e['numerical'][0])):.3e}"
          f" ({e['event_t'].size} events)")
    print("wrote", *pngs)
