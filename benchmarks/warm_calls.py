"""Warm-call times of mbm's paths, to compare two checkouts of mbm (compile apart).

Run from the root of each checkout, one after the other on the same machine::

    python -m benchmarks.warm_calls [--repeats N] [--only TEXT]

Each row is the median (and the minimum) of ``repeats`` calls after one warm-up call (which compiles or
loads the kernels), on scenes where the per-call and per-window costs show: P1 (a
short locked run), a running scene, the second paper's Example 1 through ``solve_ivp``
with dense output, a driven scene, a ``solve_batch`` ensemble, the other kinds, and
the benchmark's damped scenes P2-P4 (every window takes the locked test).  The tolerance of
each row is in its label.  mbm alone: heyoka's figures at matched error are in
``python -m benchmarks``.
"""

import argparse
import math
import statistics
import time

import numpy as np

#: Warm calls per row (median).
REPEATS = 21


def cases():
    """Row label -> a call of no arguments."""
    from scipy.integrate import solve_ivp

    import mbm

    p1 = mbm.Pendulum(beta=0.4, gamma=0.0)
    t1 = np.linspace(0.0, 20.0, 201)
    run = mbm.Pendulum(beta=0.1, gamma=1.2)
    t2 = np.linspace(0.0, 1000.0, 201)
    ex1 = mbm.Pendulum(beta=0.1, gamma=0.3)
    t3 = np.linspace(0.0, 80.0, 201)
    y3 = [math.radians(30), 0.0]
    drv = mbm.Pendulum(1.0, 0.8, 1.0, 0.5, 0.6)
    t4 = np.linspace(0.0, 300.0, 201)
    gammas = np.linspace(0.05, 1.5, 512)
    return {
        "P1 mbm.solve, rtol = atol = 1e-4": lambda: mbm.solve(p1, (0, 20), [0, 0.25], rtol=1e-4, atol=1e-4,
                                                              t_eval=t1),
        "running β 0.1 γ 1.2, T 1000, 1e-9": lambda: mbm.solve(run, (0, 1000), [0, 0], rtol=1e-9, atol=1e-9,
                                                               t_eval=t2),
        "Example 1 solve_ivp dense, 1e-9": lambda: solve_ivp(ex1, (0, 80), y3, method=mbm.MBM, rtol=1e-9,
                                                             atol=1e-9, t_eval=t3, dense_output=True),
        "driven β 1 γ 0.8 A 0.5 Ω 0.6, T 300, 1e-9": lambda: mbm.solve(drv, (0, 300), [0, 0], rtol=1e-9,
                                                                       atol=1e-9, t_eval=t4),
        "solve_batch 512 scenes, T 80, 1e-9": lambda: mbm.solve_batch(0.1, gammas, 1.0, y3, (0.0, 80.0), t3,
                                                                      rtol=1e-9, atol=1e-9),
        # The kinds other than taylor (their pieces called through mbm.core.kind_ops' table).
        "Example 1 mbm.solve split4, 1e-9": lambda: mbm.solve(ex1, (0, 80), y3, approximant="split4", rtol=1e-9,
                                                              atol=1e-9, t_eval=t3),
        "Example 1 mbm.solve salas-torque, τ 0.25": lambda: mbm.solve(ex1, (0, 80), y3, approximant="salas-torque",
                                                                      tau=0.25, t_eval=t3),
        "exact flow mbm.solve, T 80": lambda: mbm.solve(mbm.Pendulum(0.0, 0.0), (0, 80), y3, t_eval=t3),
        # The benchmark's damped scenes whose every window takes the locked test.
        **{f"{name} mbm.solve, 1e-6": _scene_call(name) for name in LOCKED_TEST_SCENES},
    }


#: The benchmark's scenes (benchmarks.scenes) with a row of their own: damped, |γ| < ω².
LOCKED_TEST_SCENES = ("P2", "P3", "P4")


def _scene_call(name, tol=1e-6):
    """mbm.solve on the benchmark's scene ``name`` at rtol = atol = ``tol``, its outputs."""
    import mbm

    from .scenes import SCENES

    s = SCENES[name]
    return lambda: mbm.solve(s.model, s.t_span, s.y0, rtol=tol, atol=tol, t_eval=s.t_eval)


def call_seconds(fn, repeats):
    """The wall times of ``repeats`` calls of ``fn`` after one warm-up call."""
    fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return times


def median_seconds(fn, repeats):
    """The median wall time of ``repeats`` calls of ``fn`` after one warm-up call."""
    return statistics.median(call_seconds(fn, repeats))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=REPEATS, help="warm calls per row (median)")
    parser.add_argument("--only", default="", help="the rows whose label contains this text")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error(f"--repeats must be >= 1, got {args.repeats}")
    rows = {k: fn for k, fn in cases().items() if args.only in k}
    if not rows:
        parser.error(f"--only {args.only!r} matches no row")
    for label, fn in rows.items():
        times = call_seconds(fn, args.repeats)
        print(f"{label:46s} {statistics.median(times) * 1e3:10.4f} ms  (min {min(times) * 1e3:.4f})", flush=True)


if __name__ == "__main__":
    main()
