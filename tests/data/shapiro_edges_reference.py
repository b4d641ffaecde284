"""Reference edges of the Shapiro steps n = 1, 2 at β = 1, A = 0.5, Ω = 0.6 (ω = 1, φ = 0).

Writes ``tests/data/shapiro_edges_reference.json``, read by ``tests/junction/test_shapiro.py``.
Independent of mbm: scipy's DOP853 at rtol = atol = 1e-10 throughout.

How it was made (``python tests/data/shapiro_edges_reference.py``; two processes, 40
minutes on a loaded 2-core machine):

* each step's interior point (n = 1: γ = 1.04, n = 2: γ = 1.39) is settled from rest
  over SETTLE_PERIODS drive periods and checked to be on the step (the mean of θ' over
  the last 200 periods is nΩ to 1e-6);
* from there each edge is approached adiabatically (a walk in bias steps of 0.02, 200
  periods each, to the start bracket's inner end): a probe at bias γ runs from the
  state of the nearest bias known to be on the step, for ``periods`` drive periods,
  sampling θ_k = θ(kT_d), and is on the step when the means of
  d_k = θ_k − θ_0 − 2πnk over its first and last 24 samples differ by less than π (no
  net phase slip; the means remove the swing of a period-doubled orbit);
* the start bracket of each edge (0.02 wide, around where a coarse 0.04 grid put the
  edge) is checked end by end (its inner end on the step, its outer end off it), then
  bisected to BRACKET_TOL = 1e-5, ten times below the test's current_tol.

Just outside an edge the motion is intermittent (laminar phases on the ghost of the
vanished orbit, of length ∝ ε^{-1/2} at a distance ε), so a probe of finite length reads
"on the step" within some distance of the edge: each edge is bisected with
``periods`` = 4000 and 16000, and the reference is the 16000-period bracket; the
difference between the two (which bounds the 4000-period bias, 16 times the
16000-period one by the ε^{-1/2} law) is stored as ``window_shift``, and the
reference's own error as ``error`` = window_shift / 15 + the bracket's half width.
"""

import json
import math
import multiprocessing
import pathlib

import numpy as np
from scipy.integrate import solve_ivp

BETA, OMEGA, AMP, FREQ, PHASE = 1.0, 1.0, 0.5, 0.6, 0.0
RTOL = ATOL = 1e-10
SETTLE_PERIODS = 1500
CHUNK = 500
MEAN_SAMPLES = 24
BRACKET_TOL = 1e-5
WINDOWS = (4000, 16000)
# the adiabatic walk from a step's interior point to a bracket's inner end
WALK_STEP = 0.02
WALK_PERIODS = 200
# step n, its interior point, and per edge the start bracket (inner end, outer end)
STEPS = {
    1: (1.04, {"lower": (0.91, 0.89), "upper": (1.19, 1.21)}),
    2: (1.39, {"lower": (1.33, 1.31), "upper": (1.45, 1.47)}),
}
PERIOD = 2.0 * math.pi / FREQ


def _rhs(gamma):
    def f(t, y):
        return [y[1], gamma + AMP * math.sin(FREQ * t + PHASE) - BETA * y[1] - OMEGA**2 * math.sin(y[0])]
    return f


def _run(gamma, y, periods):
    # θ at the stroboscopic times over `periods` drive periods from y at t = 0, and the end state.
    te = np.arange(periods + 1) * PERIOD
    sol = solve_ivp(_rhs(gamma), (0.0, te[-1]), y, method="DOP853", rtol=RTOL, atol=ATOL, t_eval=te)
    assert sol.success, sol.message
    return sol.y[0], sol.y[:, -1].copy()


def on_step(gamma, y, n, periods):
    """(on the step n, end state) for a probe of `periods` drive periods from y."""
    y = np.array(y, dtype=float)
    theta0, offset, head = y[0], 0.0, None
    for c in range(periods // CHUNK):
        theta, y = _run(gamma, y, CHUNK)
        d = theta + offset - theta0 - 2.0 * math.pi * n * (c * CHUNK + np.arange(CHUNK + 1))
        if head is None:
            head = np.mean(d[:MEAN_SAMPLES])
        if abs(np.mean(d[-MEAN_SAMPLES:]) - head) >= math.pi:
            return False, None
        r = math.remainder(y[0], 2.0 * math.pi)
        offset += y[0] - r
        y[0] = r
    return True, y


def settled(n):
    gamma = STEPS[n][0]
    theta, y = _run(gamma, [0.0, 0.0], SETTLE_PERIODS)
    v = (theta[-1] - theta[-201]) / (200 * PERIOD)
    assert abs(v - n * FREQ) < 1e-6, (n, v)
    y[0] = math.remainder(y[0], 2.0 * math.pi)
    return y


def edge(task):
    n, side, periods = task
    y = settled(n)
    g_on, g_off = STEPS[n][1][side]
    # walk from the interior point to the inner end in bias steps of at most WALK_STEP
    start = STEPS[n][0]
    for g in np.linspace(start, g_on, int(math.ceil(abs(g_on - start) / WALK_STEP)) + 1)[1:-1]:
        y = _run(g, y, WALK_PERIODS)[1]
        y[0] = math.remainder(y[0], 2.0 * math.pi)
    on, y = on_step(g_on, y, n, periods)
    assert on, (n, side, "inner end off the step")
    assert not on_step(g_off, y, n, periods)[0], (n, side, "outer end on the step")
    probes = 2
    while abs(g_off - g_on) > BRACKET_TOL:
        mid = 0.5 * (g_on + g_off)
        on, y_mid = on_step(mid, y, n, periods)
        probes += 1
        if on:
            g_on, y = mid, y_mid
        else:
            g_off = mid
    print(f"n = {n} {side} ({periods} periods): [{min(g_on, g_off)!r}, {max(g_on, g_off)!r}]", flush=True)
    return task, (min(g_on, g_off), max(g_on, g_off)), probes


def main():
    tasks = [(n, side, w) for w in WINDOWS[::-1] for n in STEPS for side in ("lower", "upper")]
    with multiprocessing.Pool(2) as pool:
        results = pool.map(edge, tasks, chunksize=1)
    found = {(n, side, w): bracket for (n, side, w), bracket, _ in results}
    edges = []
    for n in STEPS:
        for side in ("lower", "upper"):
            short, long_ = found[(n, side, WINDOWS[0])], found[(n, side, WINDOWS[1])]
            mid = 0.5 * (long_[0] + long_[1])
            shift = abs(mid - 0.5 * (short[0] + short[1]))
            edges.append(dict(n=n, side=side, edge=mid, bracket=list(long_), bracket_4000=list(short),
                              window_shift=shift, error=shift / 15.0 + 0.5 * (long_[1] - long_[0])))
    out = dict(beta=BETA, omega=OMEGA, amplitude=AMP, frequency=FREQ, phase=PHASE, method="DOP853",
               rtol=RTOL, atol=ATOL, probe_periods=list(WINDOWS), settle_periods=SETTLE_PERIODS,
               bracket_tol=BRACKET_TOL, edges=edges)
    path = pathlib.Path(__file__).with_name("shapiro_edges_reference.json")
    path.write_text(json.dumps(out, indent=1) + "\n")
    print("wrote", path)


if __name__ == "__main__":
    main()
