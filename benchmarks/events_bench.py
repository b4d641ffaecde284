"""Events at compiled speed: phase slips of the running scene, mbm against heyoka and DOP853.

``python -m benchmarks.events_bench [--repeat 5] [--scenes 10000] [--out docs/events_benchmark.md]``
(about 2 minutes on 2 cores at the defaults; ``--scenes 1000 --repeat 3`` in seconds).

The scene of issue 29: β = 0.1, γ = 1.2 from rest over T = 1000, the event
cos(θ/2) = 0 (θ ≡ π mod 2π: 1889 slips).  Reference: heyoka in long double at tol
1e-19 with an ``nt_event``.  mbm: ``mbm.solve(..., events=mbm.angle_event(π))``, and with
the event function cos(θ/2) (a ``numba.njit`` g(t, θ, θ'), no regime switch);
heyoka: one ``taylor_adaptive`` with the ``nt_event``, built once and reset per run
(``ta.time``, ``ta.state``).  Medians of ``--repeat`` warm runs in one process (the
first call's compile and JIT apart); error: the largest event-time difference from
the reference.  scipy's DOP853 with the same event function (``solve_ivp(events=g)``).

Counting: the same scene over T = 10⁶ with ``max_events=100`` (the count of every
slip, the first 100 stored), against T = 10³.

First slip over an I–V ensemble (the extras' ensemble: β = 0.1, γ = 0 … 2, ω = 1, from
rest, T = 1000, ``--scenes`` of them): the time of each scene's first θ ≡ π, a terminal
event.  mbm: ``solve_batch(..., events=angle_event(π, terminal=True))`` on one thread;
heyoka: ``taylor_adaptive_batch`` (its SIMD width) with a terminal ``t_event_batch``
cos(θ/2) = 0, ``propagate_until(T)`` called again until every lane has fired or
reached T (a batch stops all lanes at any lane's terminal event), one thread.  Error:
the largest first-slip-time difference from heyoka long double over 20 evenly spaced scenes,
and the slip counts equal.  mbm ends a scene that its energy has trapped out of the
event's reach (docs/guide/events.md); heyoka runs it to T.  So the table is repeated
over the slipping scenes only, where both integrate every scene to its first slip.
"""

import argparse
import math
import platform
import sys
import time

import numpy as np

import mbm

from .report import block, write_page

BETA, GAMMA, T_END = 0.1, 1.2, 1000.0
MBM_RTOLS = (1e-9, 1e-12)
HEYOKA_TOLS = (1e-9, 1e-12, 1e-13, 1e-14, 1e-15)
DOP853_TOLS = (1e-9, 1e-12)
# The counting run's horizon and stored slips.
T_LONG, KEEP = 1e6, 100
# Scenes of the ensemble checked against heyoka long double (evenly spaced).
REF_SCENES = 20


def _heyoka_version():
    import heyoka

    return heyoka.__version__


def _scipy_version():
    import scipy

    return scipy.__version__


def _heyoka(tol, fp):
    import heyoka as hy

    x, v = hy.make_vars("x", "v")
    found = []
    ev = hy.nt_event(hy.cos(x / 2.0), lambda ta, t, d: found.append(t), fp_type=fp)
    ta = hy.taylor_adaptive([(x, v), (v, GAMMA - BETA * v - hy.sin(x))], [fp(0), fp(0)], fp_type=fp,
                            tol=fp(tol), nt_events=[ev])
    return ta, found


def _slip_function():
    # The slip as a numba.njit event function g(t, θ, θ') (mbm.events.functions).
    import numba

    @numba.njit
    def slip(t, theta, theta_dot):
        return math.cos(0.5 * theta)

    return slip


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
    for name, ev in (("mbm", mbm.angle_event(math.pi)), ("mbm, event function cos(θ/2)", _slip_function())):
        for rtol in MBM_RTOLS:
            def run(rtol=rtol, ev=ev):
                return mbm.solve(model, (0.0, T_END), [0.0, 0.0], rtol=rtol, atol=rtol, events=ev).t_events[0]
            run()  # compile / warm
            ms, t = _median(run, repeat)
            out.append((name, rtol, 1e3 * ms, _error(t, ref), len(t)))
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
    out += _dop853_rows(ref, repeat)
    return out


def _dop853_rows(ref, repeat):
    from scipy.integrate import solve_ivp

    def g(t, y):
        return math.cos(y[0] / 2.0)

    def f(t, y):
        return [y[1], GAMMA - BETA * y[1] - math.sin(y[0])]

    out = []
    for tol in DOP853_TOLS:
        def run(tol=tol):
            return solve_ivp(f, (0.0, T_END), [0.0, 0.0], method="DOP853", rtol=tol, atol=tol, events=g).t_events[0]
        ms, t = _median(run, max(1, repeat // 3))
        out.append(("scipy DOP853 events=", tol, 1e3 * ms, _error(t, ref), len(t)))
    return out


def counting_rows(repeat):
    """(horizon, median ms, slips counted, slips stored) of mbm with ``max_events``."""
    model = mbm.Pendulum(BETA, GAMMA)
    ev = mbm.angle_event(math.pi)
    out = []
    for t_end in (T_END, T_LONG):
        def run(t_end=t_end):
            return mbm.solve(model, (0.0, t_end), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=ev, max_events=KEEP)
        run()
        ms, r = _median(run, repeat)
        out.append((t_end, 1e3 * ms, int(r.n_events[0]), r.t_events[0].size))
    return out


def _ensemble(n):
    return np.linspace(0.0, 2.0, n)


def _first_slips_heyoka(gamma, tol, fp=float):
    import heyoka as hy

    b = hy.recommended_simd_size()
    x, v = hy.make_vars("x", "v")
    sys_ = [(x, v), (v, hy.par[1] - hy.par[0] * v - hy.par[2] * hy.sin(x))]
    ev = hy.t_event_batch(hy.cos(x / 2.0))
    ta = hy.taylor_adaptive_batch(sys_, np.zeros((2, b)), tol=tol, pars=np.zeros((3, b)), t_events=[ev])

    def run():
        first = np.full(gamma.size, np.nan)
        for s in range(0, gamma.size, b):
            idx = np.minimum(np.arange(s, s + b), gamma.size - 1)
            ta.pars[:] = np.stack([np.full(b, BETA), gamma[idx], np.ones(b)])
            ta.set_time(np.zeros(b))
            ta.state[:] = 0.0
            got = np.full(b, np.nan)
            while True:
                ta.propagate_until(T_END)
                fired = np.array([r[0] == hy.taylor_outcome(-1) for r in ta.propagate_res])
                new = fired & np.isnan(got)
                got[new] = ta.time[new]
                if np.all(~np.isnan(got) | (ta.time >= T_END)):
                    break
            k = min(b, gamma.size - s)
            first[s:s + k] = got[:k]
        return first
    return run, b


def _first_slips_reference(gamma):
    import heyoka as hy

    L = np.longdouble
    x, v = hy.make_vars("x", "v")
    sys_ = [(x, v), (v, hy.par[1] - hy.par[0] * v - hy.par[2] * hy.sin(x))]
    ta = hy.taylor_adaptive(sys_, np.zeros(2, dtype=L), pars=np.zeros(3, dtype=L), tol=L(1e-19), fp_type=L,
                            t_events=[hy.t_event(hy.cos(x / 2.0), fp_type=L)])
    ref = np.full(gamma.size, np.nan, dtype=L)
    for i, g in enumerate(gamma):
        ta.pars[:] = [L(BETA), L(g), L(1)]
        ta.state[:] = [L(0), L(0)]
        ta.time = L(0)
        outcome = ta.propagate_until(L(T_END))[0]
        if outcome == hy.taylor_outcome(-1):
            ref[i] = ta.time
    return ref


def _slipping(gamma):
    # The scenes of the ensemble that slip before T (mbm's count; the rows check it).
    r = mbm.solve_batch(BETA, gamma, 1.0, [0.0, 0.0], (0.0, T_END), [], rtol=1e-12, atol=1e-12,
                        events=mbm.angle_event(math.pi, terminal=True))
    return gamma[r.n_events[:, 0] > 0]


def first_slip_rows(n, repeat, slipping_only=False):
    """(solver, tol, median ms on one thread, max first-slip error, scenes that slip) rows;
    ``slipping_only``: over the scenes of the ensemble that slip (no trapped scene to end)."""
    import numba
    import heyoka as hy

    gamma = _ensemble(n)
    if slipping_only:
        gamma = _slipping(gamma)
        n = gamma.size
    sub = np.arange(0, n, max(1, n // REF_SCENES))
    ref = _first_slips_reference(gamma[sub])

    def err(first):
        same = np.array_equal(np.isnan(first[sub]), np.isnan(ref))
        d = np.abs(first[sub].astype(np.longdouble) - ref)
        return float(np.nanmax(d)) if same and np.isfinite(d).any() else math.nan

    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    out = []
    try:
        ev = mbm.angle_event(math.pi, terminal=True)
        for rtol in MBM_RTOLS:
            def run(rtol=rtol):
                r = mbm.solve_batch(BETA, gamma, 1.0, [0.0, 0.0], (0.0, T_END), [], rtol=rtol, atol=rtol, events=ev)
                return np.where(r.n_events[:, 0] > 0, r.t_events[:, 0, 0], np.nan)
            run()
            ms, first = _median(run, repeat)
            out.append(("mbm solve_batch", rtol, 1e3 * ms, err(first), int(np.count_nonzero(~np.isnan(first)))))
    finally:
        numba.set_num_threads(threads)
    for tol in HEYOKA_TOLS:
        run, b = _first_slips_heyoka(gamma, tol)
        ms, first = _median(run, max(1, repeat // 2))
        out.append((f"heyoka {hy.__version__} batch ({b} lanes)", tol, 1e3 * ms, err(first),
                    int(np.count_nonzero(~np.isnan(first)))))
    return out


def _cpu():
    # The CPU's model name (heyoka's batch width, its SIMD size, depends on it).
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def main(argv=None):
    """``python -m benchmarks.events_bench``: the three tables, printed and optionally written."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--scenes", type=int, default=10000, help="scenes of the first-slip ensemble")
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    import numba

    argv_text = " ".join(sys.argv[1:]) if argv is None else " ".join(argv)
    lines = ["# Events benchmark", "",
             f"Generated by `python -m benchmarks.events_bench {argv_text}` — {platform.machine()}, "
             f"Python {platform.python_version()}, mbm {mbm.__version__}, numba {numba.__version__}, "
             f"heyoka {_heyoka_version()}, scipy {_scipy_version()}; CPU {_cpu()}.", "",
             f"## Phase slips, β = {BETA}, γ = {GAMMA} from rest, T = {T_END:g}", "",
             "Medians of warm runs (DOP853: fewer); error: largest event-time difference from heyoka long double "
             "(tol 1e-19).", ""]
    table = ["| solver | tol | median ms | max event-time error | events |", "|---|---|---|---|---|"]
    for name, tol, ms, err, n in rows(args.repeat):
        table.append(f"| {name} | {tol:g} | {ms:.2f} | {err:.2g} | {n} |")
    lines += block("events-slips", table)
    lines += ["", f"## Counting slips over T = {T_LONG:g} (`max_events={KEEP}`, rtol 1e-9)", ""]
    table = ["| T | median ms | slips counted | stored |", "|---|---|---|---|"]
    for t_end, ms, hits, kept in counting_rows(args.repeat):
        table.append(f"| {t_end:g} | {ms:.2f} | {hits} | {kept} |")
    lines += block("events-counting", table)
    lines += ["", f"## First slip over a {args.scenes}-scene I–V ensemble (terminal event, one thread)", "",
              f"Error: largest first-slip-time difference from heyoka long double over {REF_SCENES} evenly "
              "spaced scenes (NaN where the slipping scenes differ).", ""]
    table = ["| solver | tol | median ms | max first-slip error | scenes that slip |", "|---|---|---|---|---|"]
    for name, tol, ms, err, n in first_slip_rows(args.scenes, args.repeat):
        table.append(f"| {name} | {tol:g} | {ms:.1f} | {err:.2g} | {n} |")
    lines += block("events-first-slip", table)
    lines += ["", "The same, over the ensemble's scenes that slip only: every scene is integrated to its first "
              "slip by both (mbm's trapped-scene end, docs/guide/events.md, takes no part).", ""]
    table = ["| solver | tol | median ms | max first-slip error | scenes that slip |", "|---|---|---|---|---|"]
    for name, tol, ms, err, n in first_slip_rows(args.scenes, args.repeat, slipping_only=True):
        table.append(f"| {name} | {tol:g} | {ms:.1f} | {err:.2g} | {n} |")
    lines += block("events-first-slip-slipping", table)
    write_page(lines, args.out)


if __name__ == "__main__":
    main()
