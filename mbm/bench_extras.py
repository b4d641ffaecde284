r"""Two speed targets that the work-precision tables of :mod:`mbm.bench` do not cover.

Run ``python -m mbm.bench_extras --out docs/benchmark_extras.md`` (about 10 minutes on
2 cores; ``--quick`` for a short smoke run).

1. **Undamped, t = 10⁶** (β = γ = 0, ω = 1, θ₀ = 1 rad, θ̇₀ = 0).  Reference: the exact
   solution sin(θ/2) = k·cd(t | k²), k = sin(θ₀/2), evaluated by mpmath at 40 digits.
   MBM ("auto": the exact elliptic flow in one window) through ``solve_ivp`` and
   :func:`mbm.solve`, against scipy's DOP853 (one run: over 10⁶ it takes minutes) and
   the numba DOP853 of :mod:`mbm.bench` over a range of rtol.  MBM's error is below
   every peer's, so each time ratio is a lower bound on the speed-up at equal error.
2. **Ensemble: an I–V sweep of 10⁴ scenes** (β = 0.1, γ = 0 … 2, ω = 1, from rest,
   0 ≤ t ≤ 1000, output at t = 0, 500, 1000 — what ⟨θ′⟩ over the second half needs).
   :func:`mbm.solve_batch` on one thread and on all threads, against the numba DOP853
   and RK4 of :mod:`mbm.bench` called in a loop over the scenes (one thread).  Error:
   max |θ − θ_ref| over the outputs of every 1000th scene, θ_ref from the 128-bit
   fixed-point Taylor reference of :mod:`mbm.bench`.  Each solver's knob is the
   cheapest of its sweep that meets the target error on that subset.

3. ``--overheads``: where a short run's time goes (fixed per-call costs, the cost of
   the 201 outputs, the Taylor degree), :func:`overheads`, and each degree's cheapest
   time at equal error, :func:`degrees_at_equal_error`.

Times are medians of ``repeats`` runs after a warm-up (single runs where marked).
"""

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from . import bench

__all__ = ["undamped_long_horizon", "ensemble_iv", "parallel_baseline", "overheads",
           "kernel_costs", "degrees_at_equal_error", "format_overheads",
           "format_report", "main"]

# Horizon of the undamped scene: the 10⁶.
T_LONG = 1e6
# θ₀ of the undamped scene (a libration of amplitude 1 rad; θ̇₀ = 0).
THETA0_LONG = 1.0
# rtol = atol of the single scipy DOP853 run over 10⁶ (≈ 4 min here; tighter costs more).
SCIPY_DOP853_RTOL = 1e-8
# rtol sweep of the numba DOP853 over 10⁶ (each run 0.4-2 s).
NUMBA_DOP853_RTOLS = (1e-6, 1e-9, 1e-12)
# Ensemble size, damping, torque range and horizon from the speed issue.
N_ENSEMBLE = 10_000
BETA_IV = 0.1
GAMMA_IV_MAX = 2.0
T_IV = 1000.0
# Output times: ⟨θ′⟩ over the second half is (θ(1000) − θ(500)) / 500.
T_EVAL_IV = np.array([0.0, 500.0, 1000.0])
# Every SUBSET_STRIDE-th scene is checked against the fixed-point reference (~10 s a
# scene over t = 1000: 10 scenes, γ = 0, 0.2, …, 1.8).
SUBSET_STRIDE = 1000
# Target errors of the ensemble comparison.
IV_TARGETS = (1e-3, 1e-6)
# Knob sweeps (cheap to expensive) of the ensemble solvers.
MBM_RTOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-13)
DOP853_RTOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
RK4_STEPS = (0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625)
# Taylor degrees compared in the fixed-cost study (all registered "taylor<N>").
OVERHEAD_DEGREES = (8, 12, 16, 20, 24)
# rtol = atol of the fixed-cost study: the loosest target of the tables.
OVERHEAD_RTOL = 1e-3
# Calls timed in a row per turn by the overheads table: enough for warm caches and
# branch predictors (as in the benchmark's repeated runs; one call per turn, round
# robin over 23 entries, read 2-3x slower), few enough that turns interleave.
ROUND_ROBIN_BLOCK = 20
# Scenes and targets of the equal-error degree comparison: the two short scenes,
# where the fixed cost matters most, and the long weakly damped one, where it does not.
DEGREE_SCENES = ("P1", "P2", "P4")
DEGREE_TARGETS = (1e-3, 1e-6)
# Calls in a row per turn there: 5 x 21 sweep points per scene, so short turns.
DEGREE_BLOCK = 5
# Calls per compiled loop in the kernel-cost table: ~10 ms a loop, far above the
# timer's resolution and the loop's one dispatch.
KERNEL_LOOP = 20_000


def _round_robin_medians(calls, repeats, block=ROUND_ROBIN_BLOCK):
    """Median seconds of each of ``calls`` (name -> callable), timed in turns.

    Each round times every call ``block`` times in a row, after one untimed call
    (as the benchmark's sweeps do: the same call repeated, warm); rounds repeat
    until each call has ``repeats`` timings (:func:`mbm.bench.timed_runs`: garbage
    collector off).  A slow spell
    of a shared machine then lands on every entry alike instead of on the few
    timed during it.
    """
    times = {k: [] for k in calls}
    while any(len(v) < repeats for v in times.values()):
        for k, fn in calls.items():
            fn()
            times[k] += bench.timed_runs(fn, min(block, repeats - len(times[k])))
    return {k: statistics.median(v) for k, v in times.items()}


def _median_time(fn, repeats):
    # One warm-up call, then the benchmark's own timing (gc off, median).
    fn()
    return statistics.median(bench.timed_runs(fn, repeats))


def exact_undamped(theta0, t, dps=40):
    """θ(t) of θ'' + sin θ = 0 from rest at θ₀ (|θ₀| < π), by mpmath at ``dps`` digits."""
    import mpmath as mp

    with mp.workdps(dps):
        k = mp.sin(mp.mpf(theta0) / 2)
        return float(2 * mp.asin(k * mp.ellipfun("cd", mp.mpf(t), k * k)))


def undamped_long_horizon(repeats=5, quick=False):
    """Time and error at t = 10⁶ (``quick``: 10⁴) of MBM and the DOP853 peers.

    Returns
    -------
    dict
        ``t_end``, ``reference`` θ(t_end), ``rows``: list of dicts (solver, knob,
        error, seconds, single_run).
    """
    import mbm
    from scipy.integrate import solve_ivp

    t_end = 1e4 if quick else T_LONG
    ref = exact_undamped(THETA0_LONG, t_end)
    model = mbm.Pendulum()
    y0 = [THETA0_LONG, 0.0]
    rows = []

    def mbm_ivp():
        return solve_ivp(model, (0.0, t_end), y0, method=mbm.MBM, t_eval=[t_end]).y[0, -1]

    def mbm_solve():
        return mbm.solve(model, (0.0, t_end), y0, t_eval=[t_end]).y[0, -1]

    for name, fn in (("MBM auto, solve_ivp", mbm_ivp), ("MBM auto, mbm.solve", mbm_solve)):
        rows.append(dict(solver=name, knob="-", error=abs(fn() - ref),
                         seconds=_median_time(fn, repeats), single_run=False))
    bench._compile_numba_peers()
    te = np.array([0.0, t_end])
    for rtol in NUMBA_DOP853_RTOLS:
        def run(rtol=rtol):
            return bench.dop853_run(0.0, 0.0, 1.0, THETA0_LONG, 0.0, te, rtol, rtol, 10**10)[0, -1]
        rows.append(dict(solver="numba DOP853", knob=f"rtol={rtol:g}", error=abs(run() - ref),
                         seconds=_median_time(run, 1 if not quick else repeats), single_run=not quick))

    def rhs(t, y):
        return [y[1], -math.sin(y[0])]

    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=SCIPY_DOP853_RTOL,
                    atol=SCIPY_DOP853_RTOL, t_eval=[t_end])
    seconds = time.perf_counter() - t0
    rows.append(dict(solver="scipy DOP853", knob=f"rtol={SCIPY_DOP853_RTOL:g}",
                     error=abs(sol.y[0, -1] - ref), seconds=seconds, single_run=True))
    return {"t_end": t_end, "reference": ref, "rows": rows}


def _spin_kernel():
    import numba

    @numba.njit(parallel=True)
    def spin(n, work):
        out = np.empty(n)
        for i in numba.prange(n):
            acc = 0.0
            for j in range(work):
                acc += math.sin(j * 1e-3 + i)
            out[i] = acc
        return out

    return spin


def parallel_baseline(n=400, work=200_000):
    """Speed-up of a compute-only ``prange`` loop on all threads over one thread.

    What the machine gives a perfectly parallel numba loop: the ceiling for
    :func:`mbm.solve_batch` on it.
    """
    import numba

    spin = _spin_kernel()
    spin(4, 10)
    threads = numba.get_num_threads()
    times = {}
    for th in sorted({1, threads}):
        numba.set_num_threads(th)
        try:
            times[th] = _median_time(lambda: spin(n, work), 3)
        finally:
            numba.set_num_threads(threads)
    return {"threads": threads, "speedup": times[1] / times[threads]}


def _subset_reference(gammas, t_end):
    # The fixed-point reference samples N_OUTPUT = 201 equally spaced times: the
    # outputs t_end/2 and t_end are samples 100 and 200.
    idx = [0, (bench.N_OUTPUT - 1) // 2, bench.N_OUTPUT - 1]
    refs = []
    for g in gammas:
        scene = bench.Scene("iv", BETA_IV, float(g), 1.0, 0.0, 0.0, t_end, "I-V scene")
        refs.append(bench.fixed_point_reference(scene)[idx])
    return np.array(refs)


def ensemble_iv(n=N_ENSEMBLE, repeats=1, quick=False):
    """Scenes per second per core of the I–V ensemble for MBM and the looped peers.

    Returns
    -------
    dict
        ``n``, ``t_end``, ``rows`` (solver, threads, target, knob, subset error,
        seconds, scenes_per_s_per_core), ``subset`` size.
    """
    import numba

    import mbm

    t_end = 100.0 if quick else T_IV
    t_eval = T_EVAL_IV * (t_end / T_IV)
    gammas = np.linspace(0.0, GAMMA_IV_MAX, n)
    sub = gammas[::SUBSET_STRIDE] if not quick else gammas[:: max(1, n // 5)]
    ref = _subset_reference(sub, t_end)
    bench._compile_numba_peers()

    def err(theta):  # theta: (len(sub), len(t_eval))
        return float(np.max(np.abs(theta - ref)))

    def mbm_batch(g, rtol):
        r = mbm.solve_batch(BETA_IV, g, 1.0, [0.0, 0.0], (0.0, t_end), t_eval, rtol=rtol, atol=rtol)
        if not np.all(r.success):
            raise RuntimeError("solve_batch failed on some scenes")
        return r.y[:, 0, :]

    def dop_loop(g, rtol):
        return np.array([bench.dop853_run(BETA_IV, x, 1.0, 0.0, 0.0, t_eval, rtol, rtol, 10**9)[0]
                         for x in g])

    def rk4_loop(g, h):
        k = max(1, math.ceil((t_eval[1] - t_eval[0]) / h - 1e-9))
        return np.array([bench.rk4_run(BETA_IV, x, 1.0, 0.0, 0.0, t_eval[1] - t_eval[0],
                                       t_eval.size, k)[0] for x in g])

    solvers = [("mbm.solve_batch", mbm_batch, MBM_RTOLS, "rtol"),
               ("numba DOP853, looped", dop_loop, DOP853_RTOLS, "rtol"),
               ("numba RK4, looped", rk4_loop, RK4_STEPS, "h")]
    all_threads = numba.get_num_threads()
    # Subset error of every knob (cheap: 10 scenes), recorded for the report.
    sweeps = {name: [(knob, err(fn(sub, knob))) for knob in knobs] for name, fn, knobs, _ in solvers}
    rows = []
    for target in IV_TARGETS:
        for name, fn, knobs, kname in solvers:
            chosen = next(((k, e) for k, e in sweeps[name] if e <= target), None)
            if chosen is None:
                rows.append(dict(solver=name, threads=1, target=target, knob="—", error=None,
                                 seconds=None, per_core=None))
                continue
            knob, e = chosen
            thread_counts = (1, all_threads) if name == "mbm.solve_batch" and all_threads > 1 else (1,)
            for th in thread_counts:
                numba.set_num_threads(th)
                try:
                    s = _median_time(lambda: fn(gammas, knob), repeats)
                finally:
                    numba.set_num_threads(all_threads)
                rows.append(dict(solver=name, threads=th, target=target, knob=f"{kname}={knob:g}",
                                 error=e, seconds=s, per_core=n / s / th))
    sweeps = {name: [(float(k), e) for k, e in pts] for name, pts in sweeps.items()}
    return {"n": n, "t_end": t_end, "subset": int(sub.size), "rows": rows, "sweeps": sweeps,
            "parallel": parallel_baseline(n=40 if quick else 400, work=20_000 if quick else 200_000)}


def overheads(repeats=200):
    """Where the time of a short MBM run goes: fixed per-call costs and output cost.

    Measured on the benchmark's scenes P1 (t ≤ 20) and P2 (t ≤ 80) at rtol = atol =
    :data:`OVERHEAD_RTOL`: ``solve_ivp(method=mbm.MBM, windows_per_step=None)`` and
    :func:`mbm.solve` on an empty-length span (what a call costs before any window),
    ``MBM(...)`` construction alone, and :func:`mbm.solve` on each scene with and
    without the 201 output times, for each Taylor degree.

    Returns
    -------
    dict
        ``fixed`` (name -> seconds; two entries split up mbm.solve's), ``degrees``
        (rows: scene, degree, seconds with t_eval, seconds without, windows) and
        ``kernels`` (:func:`kernel_costs`).
    """
    from scipy.integrate import solve_ivp

    import mbm

    from . import fast

    p1 = bench.SCENES["P1"]
    model, y0, tiny = p1.model, p1.y0, (0.0, 1e-9)
    opts = dict(rtol=OVERHEAD_RTOL, atol=OVERHEAD_RTOL)
    # the compiled call of mbm.solve on the empty span, with its own packed arguments
    _, kind, karg, order, *_ = fast._setup(model, tiny, y0, None, OVERHEAD_RTOL, OVERHEAD_RTOL,
                                           "auto", None, math.inf)
    packed = np.array([model.beta, model.gamma, model.omega, 0.0, y0[0], y0[1], tiny[1], -1.0,
                       math.inf, OVERHEAD_RTOL, OVERHEAD_RTOL, 1.0])
    out = np.empty((2, 0))
    calls = {
        "solve_ivp(method=mbm.MBM, windows_per_step=None), empty span":
            lambda: solve_ivp(model, tiny, y0, method=mbm.MBM, windows_per_step=None,
                              t_eval=list(tiny), **opts),
        "mbm.MBM(...) construction":
            lambda: mbm.MBM(model, 0.0, y0, 20.0, windows_per_step=None, **opts),
        "mbm.solve, empty span": lambda: mbm.solve(model, tiny, y0, **opts),
        "  of which: argument checks (mbm.fast._setup)": lambda: fast._setup(
            model, tiny, y0, None, OVERHEAD_RTOL, OVERHEAD_RTOL, "auto", None, math.inf),
        "  of which: the compiled run (mbm.fast._run, one window)": lambda: fast._run(
            kind, karg, order, packed, fast._NO_TIMES, out[0], out[1], True),
    }
    fixed_names = list(calls)
    windows = {}
    for name in ("P1", "P2"):
        sc = bench.SCENES[name]
        for d in OVERHEAD_DEGREES:
            ap = f"taylor{d}"

            def run(te=sc.t_eval, ap=ap, sc=sc):
                return mbm.solve(sc.model, sc.t_span, sc.y0, approximant=ap, t_eval=te, **opts)

            calls[(name, d, True)] = run
            calls[(name, d, False)] = lambda run=run: run(None)
            windows[(name, d)] = run().n_windows
    seconds = _round_robin_medians(calls, repeats)
    fixed = {k: seconds[k] for k in fixed_names}
    rows = [dict(scene=name, degree=d, with_outputs=seconds[(name, d, True)],
                 without_outputs=seconds[(name, d, False)], windows=windows[(name, d)])
            for name, d in windows]
    return {"fixed": fixed, "degrees": rows, "kernels": kernel_costs()}


def _kernel_loops():
    import numba

    from .approximants.taylor import taylor_coefficients, taylor_eval_kernel

    @numba.njit
    def anchors(n, degree):
        acc = 0.0
        for i in range(n):
            acc += taylor_coefficients(0.1, 0.3, 1.0, 0.5 + i * 1e-12, 0.1, degree)[6]
        return acc

    @numba.njit
    def outputs(n, degree):
        coef = taylor_coefficients(0.1, 0.3, 1.0, 0.5, 0.1, degree)
        acc = 0.0
        for i in range(n):
            a, b = taylor_eval_kernel(coef, 1.5 * i / n)
            acc += a + b
        return acc

    return anchors, outputs


def kernel_costs(n=KERNEL_LOOP, repeats=7):
    """Nanoseconds of one Taylor anchor and of one output evaluation, by degree.

    Timed inside a compiled loop of ``n`` calls (no dispatch), on P2's parameters,
    minimum over ``repeats`` loops.

    Returns
    -------
    list of dict
        ``degree``, ``anchor_ns``, ``output_ns``.
    """
    anchors, outputs = _kernel_loops()
    rows = []
    for d in OVERHEAD_DEGREES:
        anchors(2, d)
        outputs(2, d)
        a = min(bench.timed_runs(lambda: anchors(n, d), repeats)) / n
        o = min(bench.timed_runs(lambda: outputs(n, d), repeats)) / n
        rows.append(dict(degree=d, anchor_ns=a * 1e9, output_ns=o * 1e9))
    return rows


def degrees_at_equal_error(scenes=DEGREE_SCENES, targets=DEGREE_TARGETS, repeats=20):
    """Cheapest :func:`mbm.solve` time of each Taylor degree at equal error.

    For each scene and degree, rtol = atol is swept over the benchmark's
    ``RTOL_SWEEP``; each point's error is max |θ − θ_ref| over the 201 output
    times (the benchmark's fixed-point reference), its time a median of
    ``repeats`` calls timed in turns (:func:`_round_robin_medians`).  The cell of
    a target is the cheapest point at or below it, as in the benchmark's tables.

    Returns
    -------
    list of dict
        ``scene``, ``degree`` and, per target, ``(seconds, rtol)`` or None.
    """
    import mbm

    rows = []
    for name in scenes:
        sc = bench.SCENES[name]
        ref = bench.scene_reference(sc)["theta"]
        calls, errors = {}, {}
        for d in OVERHEAD_DEGREES:
            for r in bench.RTOL_SWEEP:
                def run(d=d, r=r):
                    return mbm.solve(sc.model, sc.t_span, sc.y0, t_eval=sc.t_eval,
                                     approximant=f"taylor{d}", rtol=r, atol=r)

                res = run()
                errors[(d, r)] = bench._error(res.y[0], ref) if res.success else math.inf
                calls[(d, r)] = run
        seconds = _round_robin_medians(calls, repeats, block=DEGREE_BLOCK)
        for d in OVERHEAD_DEGREES:
            row = {"scene": name, "degree": d}
            for target in targets:
                ok = [(seconds[(d, r)], r) for r in bench.RTOL_SWEEP if errors[(d, r)] <= target]
                row[target] = min(ok) if ok else None
            rows.append(row)
    return rows


def format_overheads(ov):
    """Markdown section of :func:`overheads`."""
    lines = [f"## Fixed costs of a short run (rtol = atol = {OVERHEAD_RTOL:g})", "",
             "| call | µs |", "|---|---:|"]
    lines += [f"| {k} | {v * 1e6:.1f} |" for k, v in ov["fixed"].items()]
    lines += ["", "`mbm.solve` on P1 (t ≤ 20) and P2 (t ≤ 80) by Taylor degree: with the 201 "
              "output times of the benchmark, and with none (window ends only).", "",
              "| scene | degree | windows | with 201 outputs (µs) | without (µs) |",
              "|---|---:|---:|---:|---:|"]
    lines += [f"| {r['scene']} | {r['degree']} | {r['windows']} | {r['with_outputs'] * 1e6:.1f} | "
              f"{r['without_outputs'] * 1e6:.1f} |" for r in ov["degrees"]]
    if ov.get("kernels"):
        lines += ["", "Taylor kernels inside a compiled loop (no dispatch; P2's parameters; best of 7 "
                  "loops): one anchor (coefficients a_0 … a_{N+2}) and one output (θ, θ' by Horner).", "",
                  "| degree | anchor (ns) | output (ns) |", "|---:|---:|---:|"]
        lines += [f"| {r['degree']} | {r['anchor_ns']:.0f} | {r['output_ns']:.0f} |" for r in ov["kernels"]]
    eq = ov.get("equal_error")
    if eq:
        targets = [k for k in eq[0] if isinstance(k, float)]
        lines += ["", "At equal error: the cheapest `mbm.solve` time of each degree whose max error "
                  "over the 201 outputs is at or below the target (rtol = atol swept as in the "
                  "benchmark; in parentheses the rtol it took).", "",
                  "| scene | degree | " + " | ".join(f"{t:g} (µs)" for t in targets) + " |",
                  "|---|---:|" + "---:|" * len(targets)]
        for r in eq:
            cells = [("—" if r[t] is None else f"{r[t][0] * 1e6:.1f} ({r[t][1]:g})") for t in targets]
            lines.append(f"| {r['scene']} | {r['degree']} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def format_report(und, ens, machine, command):
    """Markdown report of :func:`undamped_long_horizon` and :func:`ensemble_iv`."""
    lines = ["# Speed targets outside the work-precision tables", "",
             f"Generated by `mbm/bench_extras.py`; regenerate with `{command}`.", "",
             "## Machine", ""]
    lines += [f"- {k}: {v}" for k, v in machine.items()]
    if und is None:
        return "\n".join(lines) + "\n"
    lines += ["", f"## Undamped, t = {und['t_end']:g} (β = γ = 0, θ₀ = {THETA0_LONG} rad, θ̇₀ = 0)", "",
              f"Reference θ(t_end) = {und['reference']!r} (mpmath, 40 digits).  Error = |θ − θ_ref| "
              "at t_end.  Ratio = the peer's time over MBM's (solve_ivp); MBM's error is below "
              "every peer's, so it bounds the speed-up at equal error from below.", "",
              "| solver | knob | error | time (s) | ratio to MBM solve_ivp |", "|---|---|---:|---:|---:|"]
    base = und["rows"][0]["seconds"]
    for r in und["rows"]:
        mark = " (single run)" if r["single_run"] else ""
        lines.append(f"| {r['solver']} | {r['knob']} | {r['error']:.1e} | {r['seconds']:.4g}{mark} | "
                     f"{r['seconds'] / base:,.3g}× |")
    lines += ["", f"## Ensemble: I–V sweep, {ens['n']} scenes (β = {BETA_IV}, γ = 0 … {GAMMA_IV_MAX}, "
              f"from rest, 0 ≤ t ≤ {ens['t_end']:g})", "",
              f"Error: max |θ − θ_ref| at t = 0, t_end/2, t_end over {ens['subset']} scenes "
              "(every 1000th), against the 128-bit fixed-point Taylor reference.  Knob: the "
              "cheapest of each solver's sweep meeting the target on that subset.  Time: the "
              "whole ensemble.", "",
              "| target | solver | threads | knob | subset error | time (s) | scenes/s per core |",
              "|---|---|---:|---|---:|---:|---:|"]
    for r in ens["rows"]:
        if r["seconds"] is None:
            lines.append(f"| {r['target']:g} | {r['solver']} | - | — | — | — | — |")
            continue
        lines.append(f"| {r['target']:g} | {r['solver']} | {r['threads']} | {r['knob']} | {r['error']:.1e} | "
                     f"{r['seconds']:.3g} | {r['per_core']:,.0f} |")
    lines += ["", "Subset error of each knob of the sweeps (the knob is rtol = atol, or the RK4 step h):", ""]
    for name, pts in ens.get("sweeps", {}).items():
        lines.append(f"- {name}: " + ", ".join(f"{k:g} → {e:.1e}" for k, e in pts))
    par = ens.get("parallel")
    if par:
        lines += ["", f"Threads: {par['threads']} (numba's default here).  A compute-only `prange` "
                  f"loop runs {par['speedup']:.2f}× faster on {par['threads']} threads than on 1 on "
                  "this machine (`parallel_baseline`): that is the ceiling for the multi-thread row; "
                  "the 1-thread row is the per-core figure to compare with the looped peers."]
    return "\n".join(lines) + "\n"


def main(argv=None):
    """Command line: ``python -m mbm.bench_extras [--quick] [--out FILE]``."""
    parser = argparse.ArgumentParser(prog="python -m mbm.bench_extras", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="short horizons and a small ensemble")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs per point (default 5)")
    parser.add_argument("--out", default=None, help="write the Markdown report here")
    parser.add_argument("--overheads", action="store_true",
                        help="instead: the fixed per-call costs and output cost of short runs, "
                             "and each Taylor degree at equal error (about 1 minute)")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error("--repeats must be >= 1")
    command = "python -m mbm.bench_extras " + " ".join(argv if argv is not None else sys.argv[1:])
    if args.overheads:
        report = format_report(None, None, bench.machine_info(), command.strip())
        ov = overheads(repeats=20 if args.quick else 200)
        ov["equal_error"] = degrees_at_equal_error(scenes=("P1",) if args.quick else DEGREE_SCENES,
                                                   repeats=3 if args.quick else 20)
        report += "\n" + format_overheads(ov)
    else:
        und = undamped_long_horizon(repeats=args.repeats, quick=args.quick)
        ens = ensemble_iv(n=200 if args.quick else N_ENSEMBLE, quick=args.quick)
        report = format_report(und, ens, bench.machine_info(), command.strip())
    if args.out:
        Path(args.out).write_text(report)
        print(f"wrote {args.out}", file=sys.stderr)
    else:
        print(report)
    return 0


if __name__ == "__main__":
    sys.exit(main())
