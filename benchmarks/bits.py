"""One hash of mbm.solve's outputs on a fixed set of runs, to compare two checkouts bit for bit.

Run from the root of each checkout, one after the other::

    python -m benchmarks.bits [--random N] [--verbose] [--save FILE | --against FILE]

The runs: the benchmark's scenes P1-P6 (:mod:`benchmarks.scenes`) at four tolerances,
over their span and over seven times it (so that the runs reach their regimes), and
``N`` random damped scenes near locking (torque |γ| < 0.9ω², far wells, random
tolerances; a fixed seed).  The hash covers each run's output states, window count,
regime, switch time and status, so that two checkouts print the same hash exactly
when every run took the same windows to the bit.  A change meant to keep the windows
(a cheaper test, a restructured loop) is checked by running this before and after it.

A change that is allowed to move output bits (a faster output evaluation after a
regime switch) is checked with ``--save FILE`` on the old checkout and ``--against
FILE`` on the new one: :func:`compare` lists each run that differs, with the largest
difference in ulps of θ and of θ' among its outputs before the run's regime switch
(``t_regime``; these must stay 0) and among those at or after it, and whether its
window count, regime, switch time or status moved.
"""

import argparse
import hashlib
import pickle

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


def ulps(a, b):
    """The distance in units in the last place between float64 arrays ``a`` and ``b``.

    0 where both are NaN or equal (+0 and −0 count as equal); a huge value where one
    alone is NaN.
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)

    def ordered(x):
        # The IEEE bit patterns, made monotonic: negative floats count down from 0.
        i = x.view(np.int64)
        return np.where(i < 0, np.int64(-(2**63)) - i, i)

    # int64 differences can wrap; long double holds every int64 exactly on x86.
    d = np.abs(ordered(a).astype(np.longdouble) - ordered(b).astype(np.longdouble)).astype(np.float64)
    both_nan = np.isnan(a) & np.isnan(b)
    one_nan = np.isnan(a) ^ np.isnan(b)
    d = np.where(both_nan | (a == b), 0.0, d)
    return np.where(one_nan, np.inf, d)


def snapshot(n_random=RANDOM_SCENES):
    """``{label: record}`` of every run: its ``t``, ``y`` and the hashed scalars."""
    out = {}
    for label, call in runs(n_random):
        r = call()
        out[label] = {"t": np.array(r["t"]), "y": np.array(r["y"]), "n_windows": r["n_windows"],
                      "regime": r["regime"], "t_regime": r["t_regime"], "status": r["status"],
                      "approximant": r["approximant"]}
    return out


def _split_ulps(old, new):
    """Largest ulps of θ and θ' over the outputs before ``t_regime`` and at or after it."""
    t = old["t"]
    t_sw = old["t_regime"] if old["t_regime"] is not None else float("nan")
    forward = t.size < 2 or t[-1] >= t[0]
    after = np.zeros(t.size, dtype=bool)
    if np.isfinite(t_sw):
        after = t >= t_sw if forward else t <= t_sw
    d = ulps(old["y"], new["y"]) if old["y"].shape == new["y"].shape else np.full(old["y"].shape, np.inf)

    def worst(mask):
        return tuple(float(d[i][mask].max()) if mask.any() else 0.0 for i in range(d.shape[0]))

    return worst(~after), worst(after)


def compare(old, new):
    """The runs of ``new`` that differ from ``old`` (two :func:`snapshot` dicts).

    Returns
    -------
    list of dict
        One per differing run: ``label``, ``kind`` (its approximant and regime),
        ``before`` and ``after`` (the largest ulps of θ and θ' before the regime switch
        and at or after it; a run without a switch has all its outputs before),
        ``moved`` (the names of the scalars that differ).  Empty when every run is the same to the bit.
    """
    rows = []
    for label, o in old.items():
        n = new.get(label)
        if n is None:
            rows.append({"label": label, "before": (np.inf, np.inf), "after": (np.inf, np.inf), "moved": ["missing"],
                         "kind": "?"})
            continue
        moved = [k for k in ("n_windows", "regime", "t_regime", "status") if repr(o[k]) != repr(n[k])]
        same_y = o["y"].shape == n["y"].shape and o["y"].tobytes() == n["y"].tobytes()
        if same_y and not moved:
            continue
        before, after = _split_ulps(o, n)
        rows.append({"label": label, "before": before, "after": after, "moved": moved,
                     "kind": f"{o['approximant']}, regime {o['regime']}"})
    return rows


def format_compare(rows, n_runs):
    """:func:`compare`'s rows as lines of text."""
    if not rows:
        return [f"all {n_runs} runs the same to the bit"]
    lines = [f"{len(rows)} of {n_runs} runs differ (ulps of theta, theta'; before the switch | at or after it):"]
    for r in rows:
        b, a = r["before"], r["after"]
        moved = f"  moved: {', '.join(r['moved'])}" if r["moved"] else ""
        lines.append(f"  {r['label']:28s} ({r['kind']}) before {b[0]:g}, {b[1]:g} | after {a[0]:g}, {a[1]:g}{moved}")
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m benchmarks.bits", description=__doc__.split("\n")[0])
    parser.add_argument("--random", type=int, default=RANDOM_SCENES, help="random damped scenes (default %(default)s)")
    parser.add_argument("--verbose", action="store_true", help="each run's own hash too")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--save", metavar="FILE", help="also write every run's outputs to FILE (pickle)")
    group.add_argument("--against", metavar="FILE",
                       help="compare every run with FILE (from --save) and list the ulps moved")
    args = parser.parse_args(argv)
    if args.random < 0:
        parser.error(f"--random must be >= 0, got {args.random}")
    if args.save or args.against:
        snap = snapshot(args.random)
        if args.save:
            with open(args.save, "wb") as f:
                pickle.dump(snap, f)
            print(f"{len(snap)} runs saved to {args.save}")
        else:
            with open(args.against, "rb") as f:
                old = pickle.load(f)
            print("\n".join(format_compare(compare(old, snap), len(old))))
        return
    n, hexdigest = digest(args.random, args.verbose)
    print(f"{n} runs {hexdigest}")


if __name__ == "__main__":
    main()
