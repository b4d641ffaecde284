"""Events at compiled speed: phase slips of the running scene, mbm against heyoka.

``python -m benchmarks.events_bench [--repeat 7] [--out docs/events_bench.md]``

The scene of issue 29: β = 0.1, γ = 1.2 from rest over T = 1000, the event
cos(θ/2) = 0 (θ ≡ π mod 2π: 1889 slips).  Reference: heyoka in long double at tol
1e-19 with an ``nt_event``.  mbm: ``mbm.solve(..., events=mbm.angle_event(π))``;
heyoka: one ``taylor_adaptive`` with the ``nt_event``, built once and reset per run
(``ta.time``, ``ta.state``).  Medians of ``--repeat`` warm runs in one process (the
first call's compile and JIT apart); error: the largest event-time difference from
the reference.
"""

import argparse
import math
import platform
import time

import numpy as np

import mbm

BETA, GAMMA, T_END = 0.1, 1.2, 1000.0
MBM_RTOLS = (1e-9, 1e-12)
HEYOKA_TOLS = (1e-9, 1e-12, 1e-13, 1e-14, 1e-15)


def _heyoka(tol, fp):
    import heyoka as hy

    x, v = hy.make_vars("x", "v")
    found = []
    ev = hy.nt_event(hy.cos(x / 2.0), lambda ta, t, d: found.append(t), fp_type=fp)
    ta = hy.taylor_adaptive([(x, v), (v, GAMMA - BETA * v - hy.sin(x))], [fp(0), fp(0)], fp_type=fp,
                            tol=fp(tol), nt_events=[ev])
    return ta, found


def _median(run, repeat):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = run()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), out


def _error(t, ref):
    return float(np.max(np.abs(np.asarray(t, dtype=np.longdouble) - ref))) if len(t) == ref.size else math.nan


def rows(repeat):
    """(solver, tolerance, median ms, max event-time error, count) rows."""
    import heyoka as hy

    ta, found = _heyoka(1e-19, np.longdouble)
    ta.propagate_until(np.longdouble(T_END))
    ref = np.array(found, dtype=np.longdouble)
    out = []
    model = mbm.Pendulum(BETA, GAMMA)
    ev = mbm.angle_event(math.pi)
    for rtol in MBM_RTOLS:
        def run(rtol=rtol):
            return mbm.solve(model, (0.0, T_END), [0.0, 0.0], rtol=rtol, atol=rtol, events=ev).t_events[0]
        run()  # compile / warm
        ms, t = _median(run, repeat)
        out.append(("mbm", rtol, 1e3 * ms, _error(t, ref), len(t)))
    for tol in HEYOKA_TOLS:
        ta, found = _heyoka(tol, float)

        def run(ta=ta, found=found):
            found.clear()
            ta.time = 0.0
            ta.state[:] = [0.0, 0.0]
            ta.propagate_until(T_END)
            return list(found)
        ms, t = _median(run, repeat)
        out.append((f"heyoka {hy.__version__} nt_event", tol, 1e3 * ms, _error(t, ref), len(t)))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    lines = [f"Machine: {platform.machine()}, {platform.python_version()}; "
             f"`python -m benchmarks.events_bench --repeat {args.repeat}`", "",
             "| solver | tol | median ms | max event-time error | events |", "|---|---|---|---|---|"]
    for name, tol, ms, err, n in rows(args.repeat):
        lines.append(f"| {name} | {tol:g} | {ms:.2f} | {err:.2g} | {n} |")
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        with open(args.out, "w", encoding="utf-8") as f:
            f.write(text)


if __name__ == "__main__":
    main()
