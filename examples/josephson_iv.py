"""Current–voltage curve of a Josephson junction in the RCSJ model, with hysteresis.

In reduced units the resistively and capacitively shunted junction is the driven,
damped pendulum θ'' + βθ' + sin θ = γ: θ is the phase difference, γ = I/I_c the bias
current, ⟨θ'⟩ the dc voltage (in units of the ω_p Φ₀/2π scale) and β = 1/√(Stewart–
McCumber parameter) the damping.  The bias is swept 0 → 2 → 0 at β = 0.1; every point
starts from the state where the previous one ended, and ⟨θ'⟩ is the mean of θ' over
a window after a transient.

* Going up, the junction stays in the zero-voltage (trapped) state until the bias
  passes the critical current γ = 1, where the stable equilibrium arcsin γ disappears:
  the switching current γ_s ≈ 1.
* Coming down, the running state survives far below 1, down to the retrapping
  current, which for small β is γ_r ≈ 4β/π (Melnikov's energy balance: the work of
  γ over one revolution, 2πγ, pays the damping along the separatrix, 8β).

The curve is computed with the compiled :func:`mbm.solve` (about a millisecond a point).

Usage::

    python examples/josephson_iv.py [OUT_DIR]      # or set MBM_EXAMPLES_OUT
"""

import math

import numpy as np

from _common import cli_out, out_dir, pyplot

import mbm
from mbm.cli_progress import Progress

BETA = 0.1
GAMMA_MAX = 2.0
# Coarse bias step away from the transitions, and the fine step near them: the fine
# step (0.2 % of I_c, 2 % of 4β/π) sets the resolution of γ_s and γ_r.
COARSE = 0.05
FINE_SWITCH = 0.002
FINE_RETRAP = 0.0025
# Bias windows refined with the fine steps (switching near 1, retrapping near 4β/π).
SWITCH_BAND = (0.9, 1.05)
RETRAP_BAND = (0.05, 0.25)
# Transient discarded before averaging: the trapped state's oscillation decays like
# exp(-βt/2), so 200 time units leave e^-10 of it.
T_TRANSIENT = 200.0
# Averaging window for ⟨θ'⟩: many periods of any running orbit above γ_r.
T_AVERAGE = 200.0
# ⟨θ'⟩ above this is the running (voltage) state: a trapped state moves θ by less than
# 2π over T_AVERAGE (≤ 0.03), in practice by ~1e-5; a running orbit with a period
# shorter than T_AVERAGE has ⟨θ'⟩ ≥ 2π/200.
V_THRESHOLD = 0.01
# MBM tolerances: ⟨θ'⟩ to ~1e-8, far below what the plot or the thresholds need.
TOL = 1e-8


def _grid(lo, hi, coarse, fine, band):
    """Increasing bias values on [lo, hi]: ``coarse`` steps, ``fine`` inside ``band``."""
    parts = [np.arange(lo, band[0], coarse), np.arange(band[0], band[1], fine),
             np.arange(band[1], hi + coarse / 2, coarse)]
    # Rounded before filtering: arange's accumulated 1e-16 must not drop the end point.
    g = np.round(np.concatenate(parts), 10)
    return np.unique(g[(g >= lo) & (g <= hi)])


def bias_sweeps(coarse=COARSE, fine_switch=FINE_SWITCH, fine_retrap=FINE_RETRAP):
    """The bias values of the up sweep (0 → 2) and of the down sweep (2 → 0).

    Returns
    -------
    (ndarray, ndarray)
    """
    up = _grid(0.0, GAMMA_MAX, coarse, fine_switch, SWITCH_BAND)
    down = _grid(0.0, GAMMA_MAX, coarse, fine_retrap, RETRAP_BAND)[::-1]
    return up, down


def mean_velocity(beta, gamma, y0, t_transient=T_TRANSIENT, t_average=T_AVERAGE):
    """⟨θ'⟩ over [t_transient, t_transient + t_average] from ``y0``, and the end state.

    Parameters
    ----------
    beta, gamma : float
    y0 : array_like, shape (2,)
    t_transient, t_average : float

    Returns
    -------
    (float, ndarray)
        The mean of θ' (= Δθ / t_average) and the state at the end.
    """
    model = mbm.Pendulum(beta=beta, gamma=gamma)
    t1 = t_transient + t_average
    sol = mbm.solve(model, (0.0, t1), y0, rtol=TOL, atol=TOL, t_eval=[t_transient, t1])
    if not sol.success:
        raise RuntimeError(f"gamma={gamma}: {sol.message}")
    v = (sol.y[0, 1] - sol.y[0, 0]) / t_average
    return float(v), sol.y[:, 1].copy()


def compute(beta=BETA, coarse=COARSE, fine_switch=FINE_SWITCH, fine_retrap=FINE_RETRAP,
            t_transient=T_TRANSIENT, t_average=T_AVERAGE):
    """The I–V curve: up and down sweeps, the switching and retrapping currents.

    Parameters
    ----------
    beta : float, optional
    coarse, fine_switch, fine_retrap : float, optional
        Bias steps (see :data:`COARSE`); larger values for a quicker, coarser run.
    t_transient, t_average : float, optional

    Returns
    -------
    dict
        ``beta``; ``up`` and ``down``, each a dict with ``gamma``, ``v`` (⟨θ'⟩) and
        ``y0`` (the start state of each point, shape (n, 2)); ``switching`` (the first
        running bias going up), ``retrapping`` (the last running bias coming down),
        ``retrapping_estimate`` (4β/π), ``t_transient``, ``t_average``.
    """
    up_g, down_g = bias_sweeps(coarse, fine_switch, fine_retrap)
    y = np.array([0.0, 0.0])
    out = {"beta": beta, "t_transient": t_transient, "t_average": t_average}
    # A progress bar on stderr (silent unless it is a terminal): the sweep is sequential.
    bar = Progress(up_g.size + down_g.size, "I-V sweep")
    for name, grid in (("up", up_g), ("down", down_g)):
        vs, starts = [], []
        for g in grid:
            bar.update()
            starts.append(y.copy())
            v, y = mean_velocity(beta, g, y, t_transient, t_average)
            # Hand over θ mod 2π: the equation is 2π-periodic in θ, and a small θ keeps
            # the absolute tolerance meaningful after thousands of revolutions.
            y[0] = math.remainder(y[0], 2.0 * math.pi)
            vs.append(v)
        out[name] = {"gamma": grid, "v": np.array(vs), "y0": np.array(starts)}
    bar.close()
    run_up = out["up"]["v"] > V_THRESHOLD
    run_down = out["down"]["v"] > V_THRESHOLD
    out["switching"] = float(out["up"]["gamma"][np.argmax(run_up)]) if run_up.any() else float("nan")
    # Coming down, the last running point before the first trapped one.
    trapped = np.flatnonzero(~run_down)
    out["retrapping"] = (float(out["down"]["gamma"][trapped[0] - 1]) if trapped.size and trapped[0] > 0
                         else float("nan"))
    out["retrapping_estimate"] = 4.0 * beta / math.pi
    return out


def main(out=None, **kw):
    """Compute the I–V curve and save ``josephson_iv.png``.

    Parameters
    ----------
    out : str or Path, optional
        Output directory.
    **kw
        Passed to :func:`compute`.

    Returns
    -------
    (dict, Path)
        The plotted data and the PNG written.
    """
    plt = pyplot()
    d = compute(**kw)
    fig, ax = plt.subplots(figsize=(7.5, 5))
    ax.plot(d["up"]["v"], d["up"]["gamma"], "b.-", ms=3, lw=0.8, label="bias up 0 → 2")
    ax.plot(d["down"]["v"], d["down"]["gamma"], "r.-", ms=3, lw=0.8, label="bias down 2 → 0")
    vmax = max(d["up"]["v"].max(), d["down"]["v"].max())
    vv = np.linspace(0.0, vmax, 50)
    ax.plot(vv, d["beta"] * vv, "0.6", ls=":", lw=1, label=r"ohmic $\gamma = \beta\langle\theta'\rangle$")
    ax.axhline(d["retrapping_estimate"], color="g", ls="--", lw=0.8,
               label=rf"$4\beta/\pi$ = {d['retrapping_estimate']:.4f}")
    ax.axhline(1.0, color="k", ls="--", lw=0.6, label=r"critical current $\gamma = 1$")
    ax.set_xlabel(r"voltage $\langle\theta'\rangle$")
    ax.set_ylabel(r"bias current $\gamma = I/I_c$")
    ax.set_title(rf"RCSJ I–V, $\beta$={d['beta']:g}: switching {d['switching']:.3f}, "
                 rf"retrapping {d['retrapping']:.4f}")
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    path = out_dir(out) / "josephson_iv.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return d, path


if __name__ == "__main__":
    data, png = main(cli_out())
    n = data["up"]["gamma"].size + data["down"]["gamma"].size
    print(f"beta = {data['beta']:g}, {n} bias points")
    print(f"switching current  gamma_s = {data['switching']:.4f}  (critical current 1)")
    print(f"retrapping current gamma_r = {data['retrapping']:.4f}  (4 beta / pi = "
          f"{data['retrapping_estimate']:.4f}, ratio {data['retrapping'] / data['retrapping_estimate']:.4f})")
    print("wrote", png)
