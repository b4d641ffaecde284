"""One hash of mbm.solve's outputs on a fixed set of runs, to compare two checkouts bit for bit.

Run from the root of each checkout, one after the other::

    python -m benchmarks.bits [--random N] [--verbose]

The runs: the benchmark's scenes P1-P6 (:mod:`benchmarks.scenes`) at four tolerances,
over their span and over seven times it (so that the runs reach their regimes), and
``N`` random damped scenes near locking (torque |γ| < 0.9ω², far wells, random
tolerances; a fixed seed).  The hash covers each run's output states, window count,
regime, switch time and status, so that two checkouts print the same hash exactly
when every run took the same windows to the bit.  A change meant to keep the windows
(a cheaper test, a restructured loop) is checked by running this before and after it.
"""

import argparse
import hashlib

import numpy as np

#: Random damped scenes by default.
RANDOM_SCENES = 60
#: The tolerances (rtol = atol) of the benchmark's scenes.
TOLERANCES = (1e-3, 1e-6, 1e-9, 1e-12)
#: The random scenes' seed (fixed: both checkouts run the same scenes).
SEED = 5
#: Output times per run.
N_TIMES = 97


def runs(n_random=RANDOM_SCENES):
    """Yield ``(label, call)`` for every run, ``call()`` returning mbm.solve's result."""
    import mbm

    from .scenes import SCENE_NAMES, SCENES

    for name in SCENE_NAMES:
        s = SCENES[name]
        for tol in TOLERANCES:
            for stretch in (1, 7):
                span = (s.t_span[0], s.t_span[1] * stretch)
                te = np.linspace(span[0], span[1], N_TIMES)
                yield (f"{name} tol {tol:g} span x{stretch}",
                       lambda s=s, span=span, te=te, tol=tol: mbm.solve(s.model, span, s.y0, rtol=tol, atol=tol,
                                                                        t_eval=te))
    rng = np.random.default_rng(SEED)
    for i in range(n_random):
        model = mbm.Pendulum(beta=rng.uniform(0.05, 1.0), gamma=rng.uniform(-0.9, 0.9), omega=rng.uniform(0.5, 2.0))
        y0 = (rng.uniform(-3, 3) + 2 * np.pi * rng.integers(-5, 5), rng.uniform(-3, 3))
        tol = 10.0 ** rng.uniform(-11, -4)
        t_end = rng.uniform(20, 200)
        yield (f"random {i}", lambda m=model, y0=y0, tol=tol, t_end=t_end: mbm.solve(
            m, (0.0, t_end), y0, rtol=tol, atol=tol, t_eval=np.linspace(0, 20, 41)))


def result_bytes(r):
    """The bytes of one result that the hash covers."""
    head = repr((r["n_windows"], r["regime"], r["t_regime"], r["status"])).encode()
    return np.ascontiguousarray(r["y"]).tobytes() + head


def digest(n_random=RANDOM_SCENES, verbose=False):
    """``(number of runs, hex digest)`` of :func:`runs`; ``verbose`` prints each run's own."""
    h = hashlib.sha256()
    n = 0
    for label, call in runs(n_random):
        b = result_bytes(call())
        h.update(b)
        n += 1
        if verbose:
            print(f"{label:32s} {hashlib.sha256(b).hexdigest()[:16]}")
    return n, h.hexdigest()


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m benchmarks.bits", description=__doc__.split("\n")[0])
    parser.add_argument("--random", type=int, default=RANDOM_SCENES, help="random damped scenes (default %(default)s)")
    parser.add_argument("--verbose", action="store_true", help="each run's own hash too")
    args = parser.parse_args(argv)
    if args.random < 0:
        parser.error(f"--random must be >= 0, got {args.random}")
    n, hexdigest = digest(args.random, args.verbose)
    print(f"{n} runs {hexdigest}")


if __name__ == "__main__":
    main()
