"""Figure 1 of Salas (2021), "Elementary Solution to the Damped Pendulum"
======================================================================

x'' + 0.4 x' + sin x = 0, x(0) = 0, x'(0) = 0.25, 0 <= t <= 20 (2ε = 0.4, (3.11)):
Runge–Kutta (dashed; scipy's RK45 at rtol 1e-10), Johannessen's sn approximant (3.9)
(black) and the elementary solution (2.2) (blue; the paper's f(t) ≈ f'(0) t, and the
closed-form f of (2.6) dotted).  Each approximant is one formula anchored at t = 0,
with no re-anchoring, as in the paper.

Usage::

    python fig_salas2021.py [OUT_DIR]   # PNGs to OUT_DIR, else $MBM_EXAMPLES_OUT, else ./out
"""

import os
import sys
from pathlib import Path

import matplotlib
import numpy as np
from scipy.integrate import solve_ivp

import mbm
import mbm.scenes

matplotlib.use("Agg")  # the figures go to PNG files: no display needed
import matplotlib.pyplot as plt  # noqa: E402

# The paper's scene (3.10): ε = 0.2 (β = 2ε), θ₀ = 0, θ̇₀ = 0.25, ω = 1, T = 20
# (mbm.scenes: P1, alias "paper1").
SCENE = mbm.scenes.get("paper1")
BETA, (THETA0, V0), T_END = SCENE.beta, SCENE.y0, SCENE.t_end
# Output points: smooth curves at this time scale (period ≈ 2π).
N_POINTS = 401
# Tolerances of the Runge–Kutta curve: tight enough to stand for "the numerical solution".
RK_TOL = 1e-10
APPROXIMANTS = ("johannessen", "salas-damped-linear", "salas-damped")


def out_dir(path=None):
    """The folder the PNGs go to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def compute(n_points=N_POINTS):
    """The curves of Figure 1.

    Parameters
    ----------
    n_points : int, optional
        Number of times on [0, 20].

    Returns
    -------
    dict
        ``t``, ``runge_kutta`` (θ from RK45) and one θ array per name in
        :data:`APPROXIMANTS`.
    """
    model = mbm.Pendulum(beta=BETA)
    t = np.linspace(0.0, T_END, n_points)
    rk = solve_ivp(model, (0.0, T_END), [THETA0, V0], method="RK45", t_eval=t, rtol=RK_TOL, atol=RK_TOL)
    data = {"t": t, "runge_kutta": rk.y[0]}
    for name in APPROXIMANTS:
        data[name] = mbm.get_approximant(name).anchor(model, THETA0, V0)(t)[0]
    return data


def main(out=None, n_points=N_POINTS):
    """Draw Figure 1 and save ``salas2021_fig1.png``.

    Parameters
    ----------
    out : str or Path, optional
        Output directory (see :func:`out_dir`).
    n_points : int, optional

    Returns
    -------
    (dict, Path)
        The plotted data (:func:`compute`) and the PNG written.
    """
    d = compute(n_points)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(d["t"], d["runge_kutta"], "r--", lw=2.2, label="Runge–Kutta (RK45, 1e-10)")
    ax.plot(d["t"], d["johannessen"], "k", lw=1.0, label="Johannessen (3.9)")
    ax.plot(d["t"], d["salas-damped-linear"], "b", lw=1.0, label="elementary (2.2), f ≈ f'(0)t")
    ax.plot(d["t"], d["salas-damped"], "c:", lw=1.2, label="elementary (2.2), f from (2.6)")
    ax.axhline(0.0, color="0.7", lw=0.5)
    ax.set_xlabel("t")
    ax.set_ylabel(r"$\theta(t)$")
    ax.set_title(r"Salas (2021) Fig. 1: $\theta''+0.4\theta'+\sin\theta=0$, $\theta(0)=0$, $\theta'(0)=0.25$")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = out_dir(out) / "salas2021_fig1.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return d, path


if __name__ == "__main__":
    data, png = main(sys.argv[1] if len(sys.argv) > 1 else None)
    for k in APPROXIMANTS:
        print(f"{k:<22s} max |theta - RK| = {np.max(np.abs(data[k] - data['runge_kutta'])):.3e}")
    print(f"wrote {png}")
