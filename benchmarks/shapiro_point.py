"""Issue 52's Shapiro bias point, timed in any checkout (mbm, numpy and scipy only).

    PYTHONPATH=CHECKOUT python benchmarks/shapiro_point.py [--repeats N]

One bias point on the n = 1 step (β 0.2, γ 0.3, ω 1, A 2, Ω 1, φ 0; y0 = (0.1, 0); T = 4000;
40,001 outputs) by ``mbm.solve`` and ``solve_ivp(method=mbm.MBM)`` at rtol/atol 1e-3/1e-6
and 1e-6/1e-9, best of ``--repeats`` calls after one untimed call.  The file imports no
other part of ``benchmarks``, so it runs unchanged against an older checkout (a
``git worktree`` of the base commit): run both in turn in one sitting and divide.
"""

import argparse
import time

import numpy as np
from scipy.integrate import solve_ivp

import mbm

PARAMS, Y0, SPAN, N_OUT = (0.2, 0.3, 1.0, 2.0, 1.0, 0.0), (0.1, 0.0), 4000.0, 40_001
TOLS = ((1e-3, 1e-6), (1e-6, 1e-9))


def _best(call, repeats):
    call()
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        best = min(best, time.perf_counter() - start)
    return best


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args(argv)
    model, te = mbm.Pendulum(*PARAMS), np.linspace(0.0, SPAN, N_OUT)
    for rtol, atol in TOLS:
        a = _best(lambda: mbm.solve(model, (0.0, SPAN), Y0, rtol=rtol, atol=atol, t_eval=te), args.repeats)
        b = _best(lambda: solve_ivp(model, (0.0, SPAN), Y0, method=mbm.MBM, rtol=rtol, atol=atol, t_eval=te),
                  args.repeats)
        print(f"rtol {rtol:g}: mbm.solve {a * 1e3:.3f} ms  solve_ivp {b * 1e3:.3f} ms")


if __name__ == "__main__":
    main()
