"""Event-point moving boundary method (3.32) on the second paper's examples
========================================================================

Compares, over 0 ≤ t ≤ 80 against CVODE at 1e-12 (max abs(θ − θ_ref) on 4001 points):

* the single approximant θ₀ (no re-anchoring),
* the hybrid mode: windows between CVODE's event points, anchored at CVODE's states,
* the analytic mode: windows between the formula's own events, anchored at its states,
* fixed windows τ (3.29)–(3.30) through ``solve_ivp(method=mbm.MBM)``, including
  the τ that gives as many windows as there are event points.

Usage::

    python event_points.py

(prints the tables and writes ``out/event_points.png``: the error of each mode against
its number of windows).
"""

import math
import os
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp

import mbm
import mbm.scenes
from mbm.events.points import (
    analytic_event_points,
    event_function_d,
    event_point_solution,
    hybrid_event_points,
)
from mbm.frontends.reference import reference

# The paper's Examples 1 and 2 (mbm.scenes: P2 and P3).
SCENES = {"Example 1": mbm.scenes.get("ex1"), "Example 2": mbm.scenes.get("ex2")}
# Points of the error grid (as the paper's-error test of Example 1 uses).
N_GRID = 4001
FIXED_TAUS = (0.1, 0.25, 0.5, 1.0)


def max_error(f, t, ref):
    return float(np.max(np.abs(f(t)[0] - ref)))


def run(name, scene, approximant="salas-torque"):
    model, y0, T = scene.model, list(scene.y0), scene.t_end
    beta, gamma, th0_deg = scene.beta, scene.gamma, math.degrees(scene.theta0)
    t = np.linspace(0.0, T, N_GRID)
    ref = reference(model, (0.0, T), y0, t_eval=t).y[0]
    ap = mbm.get_approximant(approximant)
    d = event_function_d(model, ap)
    rows = [("single approximant", 1, max_error(ap.anchor(model, *y0), t, ref), float("nan"))]

    c = time.perf_counter()
    te, ye, _ = hybrid_event_points(model, (0.0, T), y0, d)
    pw = event_point_solution(model, 0.0, y0, te, ye, ap)
    rows.append(("hybrid (3.32), CVODE events", len(te) + 1, max_error(pw, t, ref), time.perf_counter() - c))

    c = time.perf_counter()
    ta, ya, _ = analytic_event_points(model, (0.0, T), y0, d, approximant=ap)
    pa = event_point_solution(model, 0.0, y0, ta, ya, ap)
    rows.append(("analytic, formula events", len(ta) + 1, max_error(pa, t, ref), time.perf_counter() - c))

    for tau in FIXED_TAUS + (T / (len(te) + 1),):
        c = time.perf_counter()
        sol = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, tau=tau, approximant=ap, t_eval=t)
        err = float(np.max(np.abs(sol.y[0] - ref)))
        rows.append((f"fixed tau = {tau:.4g}", math.ceil(T / tau - 1e-9), err, time.perf_counter() - c))

    print(f"\n{name}: beta={beta}, gamma={gamma}, theta0={th0_deg:g} deg, 0 <= t <= {T:g}, d = {d:.6f}")
    print(f"  {'mode':32s} {'windows':>8s} {'max |error|':>12s} {'seconds':>8s}")
    for label, n, err, sec in rows:
        print(f"  {label:32s} {n:8d} {err:12.4e} {sec:8.3f}")
    dt = np.abs(ta[: min(len(ta), len(te))] - te[: min(len(ta), len(te))])
    print(f"  formula events vs CVODE events: {len(ta)} vs {len(te)}, first 5 |dt| = {np.round(dt[:5], 4)}")
    return rows


def out_dir(path=None):
    """The folder the PNG goes to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def plot(results, path):
    """Max error against windows for each mode and Example (``results``: name → rows of :func:`run`)."""
    fig, axes = plt.subplots(1, len(results), figsize=(5 * len(results), 4), sharey=True)
    for ax, (name, rows) in zip(np.atleast_1d(axes), results.items()):
        fixed = [(n, err) for label, n, err, _ in rows if label.startswith("fixed")]
        ax.loglog(*zip(*sorted(fixed)), "C0o-", label="fixed τ (3.29)–(3.30)")
        for (label, n, err, _), style in zip(rows[:3], ("C3s", "C1^", "C2v")):
            ax.loglog([n], [err], style, ms=8, label=label)
        ax.set_title(name)
        ax.set_xlabel("windows")
    np.atleast_1d(axes)[0].set_ylabel("max |θ − θ_ref|")
    np.atleast_1d(axes)[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(out=None):
    """Print each Example's table and save ``event_points.png``; returns (rows per Example, path)."""
    results = {name: run(name, scene) for name, scene in SCENES.items()}
    return results, plot(results, out_dir(out) / "event_points.png")


if __name__ == "__main__":
    main()
