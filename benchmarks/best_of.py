"""Best-of timing of one mbm.solve call on a benchmark scene, for A/B tests of a few per cent.

    python -m benchmarks.best_of [--scene P4] [--rtol 1e-6] [--batches 7] [--calls 200]

Run it from each checkout in turn (``PYTHONPATH=<checkout>``), alternating a few times:
the best of ``batches`` batches of ``calls`` warm calls (201 outputs over the scene's
span) is steadier on a shared machine than ``benchmarks.compare_checkouts``' medians,
which move ±5-10 % between identical runs.  Prints µs per call and the run's windows.
"""

import argparse
import time

import numpy as np

#: Warm-up calls before timing (compile or cache load, first-call effects).
WARMUP = 50


def best_us(run, batches, calls, warmup=1):
    """Best µs per call of ``run()`` over ``batches`` batches of ``calls`` calls, after ``warmup``."""
    for _ in range(warmup):
        run()
    best = np.inf
    for _ in range(batches):
        t0 = time.perf_counter()
        for _ in range(calls):
            run()
        best = min(best, (time.perf_counter() - t0) / calls)
    return best * 1e6


def best_of(scene="P4", rtol=1e-6, batches=7, calls=200):
    """(best µs per call, windows) of ``mbm.solve`` on ``scene`` at rtol = atol = ``rtol``."""
    import mbm

    from .scenes import SCENES

    s = SCENES[scene]
    te = np.linspace(*s.t_span, 201)

    def run():
        return mbm.solve(s.model, s.t_span, s.y0, rtol=rtol, atol=rtol, t_eval=te)

    return best_us(run, batches, calls, warmup=WARMUP), int(run().n_windows)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m benchmarks.best_of", description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="P4")
    parser.add_argument("--rtol", type=float, default=1e-6)
    parser.add_argument("--batches", type=int, default=7)
    parser.add_argument("--calls", type=int, default=200)
    args = parser.parse_args(argv)
    us, windows = best_of(args.scene, args.rtol, args.batches, args.calls)
    print(f"{args.scene} rtol {args.rtol:g}: {us:.1f} us per call (best of {args.batches} x {args.calls}), "
          f"{windows} windows")


if __name__ == "__main__":
    main()
