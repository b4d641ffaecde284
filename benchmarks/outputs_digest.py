"""Digests of mbm's outputs on every path, to check that a change keeps them bit for bit.

    python -m benchmarks.outputs_digest OUT.json          # in each checkout
    python -m benchmarks.outputs_digest --compare A.json B.json

Runs 8 scenes (damped, running, conservative, undamped, locking, driven, phase-locked,
near the top) through 7 approximants on ``mbm.solve`` (with t_eval, window ends,
backward), ``solve_ivp(method=mbm.MBM)`` (t_eval and dense output), ``solve_batch``
and ``solve_batch`` with a terminal event, and writes the SHA-256 of each output's
bytes (of its error message's length where a call raises).  ``--compare`` lists the keys
whose digests differ.
"""

import argparse
import hashlib
import json
import math
import sys

import numpy as np

SCENES = [
    ((0.1, 0.3), (math.radians(30), 0.0)),
    ((0.1, 1.2), (0.0, 0.0)),
    ((0.0, 0.4), (0.5, 0.0)),
    ((0.0, 0.0), (1.0, 0.3)),
    ((0.3, 0.2), (2.0, 0.0)),
    ((0.2, 0.3, 1.0, 0.8, 0.7, 0.4), (0.0, 0.0)),
    ((2.0, 0.95, 1.0, 1.0, 1.0), (0.0, 0.0)),
    ((0.05, 0.0), (3.0, 0.0)),
]
APPROXIMANTS = (("auto", None), ("taylor", None), ("taylor8", 0.3), ("split4", 0.1), ("split4", None),
                ("salas-torque", 0.25), ("belendez", None))
# Backward runs stop here: a damped scene grows backwards, and its windows shrink.
BACK_WINDOWS = 20000


def _digest(*arrays):
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(np.asarray(a, dtype=np.float64)).tobytes())
    return h.hexdigest()


def _try(out, key, fn):
    try:
        out[key] = _digest(*fn())
    except Exception as exc:  # a refused combination: the same refusal on both sides
        out[key] = f"error {type(exc).__name__} {len(str(exc))}"


def digests():
    """{key: digest} of every run."""
    import mbm
    from scipy.integrate import solve_ivp

    te = np.linspace(0.0, 60.0, 121)
    out = {}
    for si, (params, y0) in enumerate(SCENES):
        m = mbm.Pendulum(*params)
        for ap, tau in APPROXIMANTS:
            key = f"{si}-{ap}-{tau}"
            kw = dict(rtol=1e-9, atol=1e-9, approximant=ap, tau=tau)

            def solve(**more):
                r = mbm.solve(m, more.pop("span", (0.0, 60.0)), y0, **kw, **more)
                return r.t, r.y, [r.status, r.n_windows]
            _try(out, key + "-solve", lambda: solve(t_eval=te))
            _try(out, key + "-ends", lambda: solve())
            _try(out, key + "-back", lambda: solve(span=(0.0, -20.0), max_windows=BACK_WINDOWS))
            ivp = {} if tau is None else {"tau": tau}
            _try(out, key + "-ivp", lambda: (lambda r: (r.y, r.sol(np.linspace(0.0, 60.0, 37))))(
                solve_ivp(m, (0.0, 60.0), y0, method=mbm.MBM, rtol=1e-9, atol=1e-9, approximant=ap, t_eval=te,
                          dense_output=True, **ivp)))
    b = mbm.solve_batch(np.array([0.1, 0.1, 0.0, 0.3]), np.array([0.3, 1.2, 0.4, 0.2]), 1.0,
                        np.array([[0.5, 0.0], [0.0, 0.0], [0.5, 0.0], [2.0, 0.0]]), (0.0, 60.0), te, rtol=1e-9,
                        atol=1e-9)
    out["batch"] = _digest(b.y, b.n_windows)
    b = mbm.solve_batch(0.1, np.linspace(0.2, 1.5, 16), 1.0, np.zeros((16, 2)), (0.0, 200.0), np.array([200.0]),
                        rtol=1e-9, atol=1e-9, events=mbm.angle_event(math.pi, terminal=True), max_events=1)
    out["batch-events"] = _digest(b.t_events, b.y, b.n_windows)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?")
    ap.add_argument("--compare", nargs=2, metavar=("A", "B"))
    args = ap.parse_args(argv)
    if args.compare:
        a, b = (json.load(open(p, encoding="utf-8")) for p in args.compare)
        differ = sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))
        print(f"{len(a)} and {len(b)} runs; {len(differ)} differ" + (": " + ", ".join(differ) if differ else ""))
        return 1 if differ else 0
    d = digests()
    with open(args.out, "w", encoding="utf-8") as f:
        json.dump(d, f, indent=0, sort_keys=True)
    print(f"{len(d)} runs, {sum(v.startswith('error') for v in d.values())} refused")
    return 0


if __name__ == "__main__":
    sys.exit(main())
