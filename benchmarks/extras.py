r"""Speed targets that the work-precision tables do not cover.

Run ``python -m benchmarks extras --out docs/benchmark_extras.md`` (about 15 minutes on
2 cores; ``--quick`` for a short smoke run).

1. **Undamped, t = 10⁶** (the catalogue's ``undamped-long``: β = γ = 0, ω = 1,
   θ₀ = 1 rad, θ̇₀ = 0).  Reference: the exact solution sin(θ/2) = k·cd(t | k²),
   k = sin(θ₀/2), evaluated by mpmath at 40 digits.  MBM ("auto": the exact elliptic
   flow in one window) through ``solve_ivp`` and :func:`mbm.solve`, against scipy's
   DOP853 (one run: over 10⁶ it takes minutes), the numba DOP853 of
   :mod:`benchmarks.peers` and heyoka (prepared) over a range of tolerances.
2. **Ensemble: an I–V sweep of 10⁴ scenes** (β = 0.1, γ = 0 … 2, ω = 1, from rest,
   0 ≤ t ≤ 1000, output at t = 0, 500, 1000 — what ⟨θ′⟩ over the second half needs).
   :func:`mbm.solve_batch` on one thread and on all threads, against the numba DOP853
   and RK4 and heyoka's scalar integrator called in a loop over the scenes, and
   heyoka's SIMD batch mode (``taylor_adaptive_batch``), all on one thread.  Error:
   max |θ − θ_ref| over the outputs of every 1000th scene, θ_ref from the 128-bit
   fixed-point Taylor reference (or heyoka in long double, ``--reference heyoka-ld``).
   Each solver's knob is the cheapest of its sweep that meets the target on that
   subset.  heyoka's integrators are built before the timing (build times reported).
3. ``--overheads``: where a short run's time goes (fixed per-call costs, the cost of
   the 201 outputs, the Taylor degree), :func:`overheads`, and each degree's cheapest
   time at equal error, :func:`degrees_at_equal_error`.  The fixed cost is split by
   timing *public* calls that differ in one thing (no window, one window, a whole
   run; with and without outputs), not mbm's internals.  With it, the fixed cost per call of
   ``Integrator.solve`` and :func:`mbm.solve` and of their compiled part alone
   (:mod:`benchmarks.overheads`, which also runs on its own in seconds).

Times are medians of ``repeats`` runs after a warm-up (single runs where marked).
"""

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

import mbm
from mbm import scenes as catalogue

from . import harness, peers, references
from . import overheads as per_call
from .registry import RTOL_SWEEP
from .report import block, json_default
from .scenes import N_OUTPUT, SCENES, BenchScene

__all__ = ["undamped_long_horizon", "ensemble_iv", "parallel_baseline", "overheads",
           "kernel_costs", "degrees_at_equal_error", "format_overheads",
           "format_report", "main"]

# The undamped scene (θ₀ = 1 rad from rest, t ≤ 10⁶) of the catalogue.
UNDAMPED = catalogue.get("undamped-long")
# rtol = atol of the single scipy DOP853 run over 10⁶ (≈ 4 min here; tighter costs more).
SCIPY_DOP853_RTOL = 1e-8
# rtol sweep of the numba DOP853 over 10⁶ (each run 0.4-2 s).
NUMBA_DOP853_RTOLS = (1e-6, 1e-9, 1e-12)
# tol sweep of heyoka over 10⁶.
HEYOKA_LONG_TOLS = (1e-9, 1e-12, 1e-15)
# Ensemble size, damping, torque range and horizon of the I–V sweep.
N_ENSEMBLE = 10_000
BETA_IV = 0.1
GAMMA_IV_MAX = 2.0
T_IV = 1000.0
# Output times: ⟨θ′⟩ over the second half is (θ(1000) − θ(500)) / 500.
T_EVAL_IV = np.array([0.0, 500.0, 1000.0])
# Every SUBSET_STRIDE-th scene is checked against the reference (~10 s a scene over
# t = 1000 in fixed point: 10 scenes, γ = 0, 0.2, …, 1.8).
SUBSET_STRIDE = 1000
# Target errors of the ensemble comparison.
IV_TARGETS = (1e-3, 1e-6)
# Knob sweeps (cheap to expensive) of the ensemble solvers.
MBM_RTOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-13)
DOP853_RTOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
HEYOKA_TOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-13, 1e-14)
RK4_STEPS = (0.2, 0.1, 0.05, 0.025, 0.0125, 0.00625)
# Taylor degrees compared in the fixed-cost study (all registered "taylor<N>").
OVERHEAD_DEGREES = (8, 12, 16, 20, 24)
# rtol = atol of the fixed-cost study: the loosest target of the tables.
OVERHEAD_RTOL = 1e-3
# A span short enough for exactly one window at OVERHEAD_RTOL.
ONE_WINDOW_SPAN = (0.0, 1e-9)
# Scenes and targets of the equal-error degree comparison: the two short scenes,
# where the fixed cost matters most, and the long weakly damped one, where it does not.
DEGREE_SCENES = ("P1", "P2", "P4")
DEGREE_TARGETS = (1e-3, 1e-6)
# Calls in a row per turn there: 5 x 21 sweep points per scene, so short turns.
DEGREE_BLOCK = 5
# Calls per compiled loop in the kernel-cost table: ~10 ms a loop, far above the
# timer's resolution and the loop's one dispatch.
KERNEL_LOOP = 20_000


def exact_undamped(theta0, t, dps=40):
    """θ(t) of θ'' + sin θ = 0 from rest at θ₀ (|θ₀| < π), by mpmath at ``dps`` digits."""
    import mpmath as mp

    with mp.workdps(dps):
        k = mp.sin(mp.mpf(theta0) / 2)
        return float(2 * mp.asin(k * mp.ellipfun("cd", mp.mpf(t), k * k)))


def undamped_long_horizon(repeats=5, quick=False):
    """Time and error at t = 10⁶ (``quick``: 10⁴) of MBM, the DOP853 peers and heyoka.

    Returns
    -------
    dict
        ``t_end``, ``reference`` θ(t_end), ``rows``: list of dicts (solver, knob,
        error, seconds, single_run), ``builds`` (heyoka tol -> build seconds).
    """
    from scipy.integrate import solve_ivp

    scene = UNDAMPED.until(1e4) if quick else UNDAMPED
    t_end = scene.t_end
    theta0 = scene.theta0
    ref = exact_undamped(theta0, t_end)
    model = scene.model
    y0 = list(scene.y0)
    rows = []

    def mbm_ivp():
        return solve_ivp(model, (0.0, t_end), y0, method=mbm.MBM, t_eval=[t_end]).y[0, -1]

    def mbm_solve():
        return mbm.solve(model, (0.0, t_end), y0, t_eval=[t_end]).y[0, -1]

    for name, fn in (("MBM auto, solve_ivp", mbm_ivp), ("MBM auto, mbm.solve", mbm_solve)):
        rows.append(dict(solver=name, knob="-", error=abs(fn() - ref),
                         seconds=harness.median_time(fn, repeats), single_run=False))
    peers.compile_numba_peers()
    te = np.array([0.0, t_end])
    for rtol in NUMBA_DOP853_RTOLS:
        def run(rtol=rtol):
            return peers.dop853_run(0.0, 0.0, 1.0, theta0, 0.0, te, rtol, rtol, 10**10)[0, -1]
        rows.append(dict(solver="numba DOP853", knob=f"rtol={rtol:g}", error=abs(run() - ref),
                         seconds=harness.median_time(run, 1 if not quick else repeats),
                         single_run=not quick))
    builds = {}
    if peers.heyoka_module() is not None:
        hy = peers.HeyokaPeer()
        bs = BenchScene(scene)
        for tol in HEYOKA_LONG_TOLS:
            hy.integrator(tol)  # built before the timing: prepared, as in the tables

            def run(tol=tol):
                return hy.propagate(bs, tol, te)[-1, 0]
            rows.append(dict(solver="heyoka (prepared)", knob=f"tol={tol:g}",
                             error=abs(run() - ref),
                             seconds=harness.median_time(run, 1 if not quick else repeats),
                             single_run=not quick))
        builds = dict(hy.build_seconds)

    def rhs(t, y):
        return [y[1], -math.sin(y[0])]

    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, t_end), y0, method="DOP853", rtol=SCIPY_DOP853_RTOL,
                    atol=SCIPY_DOP853_RTOL, t_eval=[t_end])
    seconds = time.perf_counter() - t0
    rows.append(dict(solver="scipy DOP853", knob=f"rtol={SCIPY_DOP853_RTOL:g}",
                     error=abs(sol.y[0, -1] - ref), seconds=seconds, single_run=True))
    return {"t_end": t_end, "theta0": theta0, "reference": ref, "rows": rows, "builds": builds,
            "heyoka": peers.heyoka_module() is not None}


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
            times[th] = harness.median_time(lambda: spin(n, work), 3)
        finally:
            numba.set_num_threads(threads)
    return {"threads": threads, "speedup": times[1] / times[threads]}


def _iv_scene(gamma, t_end):
    return BenchScene.from_params("iv", BETA_IV, float(gamma), 1.0, 0.0, 0.0, t_end, "I-V scene")


def _subset_reference(gammas, t_end, method="fixed-point"):
    """θ at t = 0, t_end/2, t_end for each γ (from rest, β = BETA_IV).

    The fixed-point reference samples N_OUTPUT = 201 equally spaced times: the outputs
    t_end/2 and t_end are samples 100 and 200.  heyoka in long double
    (``method="heyoka-ld"``) is evaluated at the three times directly.
    """
    if method not in ("fixed-point", "heyoka-ld"):
        raise ValueError(f"subset reference must be 'fixed-point' or 'heyoka-ld', got {method!r}")
    idx = [0, (N_OUTPUT - 1) // 2, N_OUTPUT - 1]
    times = np.array([0.0, t_end / 2, t_end])
    refs = []
    for g in gammas:
        scene = _iv_scene(g, t_end)
        if method == "heyoka-ld":
            refs.append(references.heyoka_ld_reference(scene, times))
        else:
            refs.append(references.fixed_point_reference(scene)[idx])
    return np.array(refs)


def ensemble_iv(n=N_ENSEMBLE, repeats=1, quick=False, reference="fixed-point"):
    """Scenes per second per core of the I–V ensemble for MBM and the peers.

    Returns
    -------
    dict
        ``n``, ``t_end``, ``rows`` (solver, threads, target, knob, subset error,
        seconds, per_core), ``subset`` size, ``sweeps`` (subset error per knob),
        ``builds`` (heyoka: solver -> tol -> build seconds), ``parallel``
        (:func:`parallel_baseline`), ``reference``.
    """
    import numba

    t_end = 100.0 if quick else T_IV
    t_eval = T_EVAL_IV * (t_end / T_IV)
    gammas = np.linspace(0.0, GAMMA_IV_MAX, n)
    sub = gammas[::SUBSET_STRIDE] if not quick else gammas[:: max(1, n // 5)]
    ref = _subset_reference(sub, t_end, reference)
    peers.compile_numba_peers()

    def err(theta):  # theta: (len(sub), len(t_eval))
        return float(np.max(np.abs(theta - ref)))

    def mbm_batch(g, rtol):
        r = mbm.solve_batch(BETA_IV, g, 1.0, [0.0, 0.0], (0.0, t_end), t_eval, rtol=rtol, atol=rtol)
        if not np.all(r.success):
            raise RuntimeError("solve_batch failed on some scenes")
        return r.y[:, 0, :]

    def dop_loop(g, rtol):
        return np.array([peers.dop853_run(BETA_IV, x, 1.0, 0.0, 0.0, t_eval, rtol, rtol, 10**9)[0]
                         for x in g])

    def rk4_loop(g, h):
        k = max(1, math.ceil((t_eval[1] - t_eval[0]) / h - 1e-9))
        return np.array([peers.rk4_run(BETA_IV, x, 1.0, 0.0, 0.0, t_eval[1] - t_eval[0],
                                       t_eval.size, k)[0] for x in g])

    solvers = [("mbm.solve_batch", mbm_batch, MBM_RTOLS, "rtol"),
               ("numba DOP853, looped", dop_loop, DOP853_RTOLS, "rtol"),
               ("numba RK4, looped", rk4_loop, RK4_STEPS, "h")]
    heyokas = {}
    if peers.heyoka_module() is not None:
        scalar = peers.HeyokaPeer()
        batch = peers.HeyokaBatch()
        y0 = np.zeros(2)

        def hy_loop(g, tol):
            ta = scalar.integrator(tol)
            out = np.empty((len(g), t_eval.size))
            limit = peers.heyoka_module().taylor_outcome.time_limit
            for i, x in enumerate(g):
                ta.time = 0.0
                ta.state[:] = y0
                ta.pars[0], ta.pars[1], ta.pars[2] = BETA_IV, x, 1.0
                outcome, *_, res = ta.propagate_grid(t_eval)
                if outcome != limit:
                    raise RuntimeError(f"heyoka stopped: {outcome}")
                out[i] = res[:, 0]
            return out

        def hy_batch(g, tol):
            return batch.theta(BETA_IV, g, 1.0, y0, t_eval, tol)

        solvers += [("heyoka scalar, looped", hy_loop, HEYOKA_TOLS, "tol"),
                    (f"heyoka batch ({batch.batch_size} lanes)", hy_batch, HEYOKA_TOLS, "tol")]
        heyokas = {"heyoka scalar, looped": scalar, f"heyoka batch ({batch.batch_size} lanes)": batch}
    all_threads = numba.get_num_threads()
    # Subset error of every knob (cheap: 10 scenes), recorded for the report.  This also
    # builds heyoka's integrators, so that none is built inside a timed run.
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
                    s = harness.median_time(lambda: fn(gammas, knob), repeats)
                finally:
                    numba.set_num_threads(all_threads)
                rows.append(dict(solver=name, threads=th, target=target, knob=f"{kname}={knob:g}",
                                 error=e, seconds=s, per_core=n / s / th))
    sweeps = {name: [(float(k), e) for k, e in pts] for name, pts in sweeps.items()}
    builds = {name: {float(k): v for k, v in h.build_seconds.items()} for name, h in heyokas.items()}
    return {"n": n, "t_end": t_end, "subset": int(sub.size), "rows": rows, "sweeps": sweeps,
            "builds": builds, "reference": reference, "heyoka": bool(heyokas),
            "parallel": parallel_baseline(n=40 if quick else 400, work=20_000 if quick else 200_000)}


def overheads(repeats=200):
    """Where the time of a short MBM run goes: fixed per-call costs and output cost.

    Measured at rtol = atol = :data:`OVERHEAD_RTOL` with public calls only, each
    differing from the next in one thing: :func:`mbm.solve` on a zero-length span
    (no window: argument checks, set-up, result), on :data:`ONE_WINDOW_SPAN` (one
    window), and on the whole of P1 (t ≤ 20) without and with its 201 output times;
    ``solve_ivp(method=mbm.MBM, windows_per_step=None)`` on the one-window span and
    ``MBM(...)`` construction alone.  Differences of these give the cost of the first
    window, of each further window and of each output (``derived``).  Then
    :func:`mbm.solve` on P1 and P2 with and without the outputs for each Taylor degree.

    Returns
    -------
    dict
        ``fixed`` (name -> seconds), ``derived`` (name -> seconds), ``degrees``
        (rows: scene, degree, seconds with t_eval, seconds without, windows) and
        ``kernels`` (:func:`kernel_costs`).
    """
    from scipy.integrate import solve_ivp

    p1 = SCENES["P1"]
    model, y0 = p1.model, p1.y0
    opts = dict(rtol=OVERHEAD_RTOL, atol=OVERHEAD_RTOL)
    n_p1 = mbm.solve(model, p1.t_span, y0, **opts).n_windows
    candidates = {
        "solve_ivp(method=mbm.MBM, windows_per_step=None), one window":
            lambda: solve_ivp(model, ONE_WINDOW_SPAN, y0, method=mbm.MBM, windows_per_step=None,
                              t_eval=list(ONE_WINDOW_SPAN), **opts),
        "mbm.MBM(...) construction":
            lambda: mbm.MBM(model, 0.0, y0, 20.0, windows_per_step=None, **opts),
        "mbm.solve, zero-length span (no window)": lambda: mbm.solve(model, (0.0, 0.0), y0, **opts),
        "mbm.solve, one window": lambda: mbm.solve(model, ONE_WINDOW_SPAN, y0, **opts),
        f"mbm.solve, P1 without outputs ({n_p1} windows)":
            lambda: mbm.solve(model, p1.t_span, y0, **opts),
        f"mbm.solve, P1 with its {N_OUTPUT} outputs":
            lambda: mbm.solve(model, p1.t_span, y0, t_eval=p1.t_eval, **opts),
    }
    calls, unavailable = {}, {}
    for name, fn in candidates.items():
        try:
            fn()
        except Exception as exc:  # e.g. a zero-length span refused: a row saying so
            unavailable[name] = f"{type(exc).__name__}: {exc}"[:120]
        else:
            calls[name] = fn
    fixed_names = list(calls)
    windows = {}
    for name in ("P1", "P2"):
        sc = SCENES[name]
        for d in OVERHEAD_DEGREES:
            ap = f"taylor{d}"

            def run(te=sc.t_eval, ap=ap, sc=sc):
                return mbm.solve(sc.model, sc.t_span, sc.y0, approximant=ap, t_eval=te, **opts)

            calls[(name, d, True)] = run
            calls[(name, d, False)] = lambda run=run: run(None)
            windows[(name, d)] = run().n_windows
    seconds = harness.round_robin_medians(calls, repeats)
    fixed = {k: seconds[k] for k in fixed_names}
    keys = list(candidates)
    zero, one, run_no, run_out = (fixed.get(k) for k in keys[2:6])
    derived = {}
    if zero is not None and one is not None:
        derived["first window (one window − no window)"] = one - zero
    if one is not None and run_no is not None and n_p1 > 1:
        derived[f"each further window (P1 without outputs − one window) / {n_p1 - 1}"] = (
            (run_no - one) / (n_p1 - 1))
    if run_no is not None and run_out is not None:
        derived[f"each output (P1 with − without outputs) / {N_OUTPUT}"] = (run_out - run_no) / N_OUTPUT
    rows = [dict(scene=name, degree=d, with_outputs=seconds[(name, d, True)],
                 without_outputs=seconds[(name, d, False)], windows=windows[(name, d)])
            for name, d in windows]
    return {"fixed": fixed, "derived": derived, "unavailable": unavailable, "degrees": rows,
            "kernels": kernel_costs()}


def _kernel_loops():
    import numba

    from mbm.approximants.taylor import taylor_coefficients, taylor_eval_kernel

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
    with mbm's public Taylor kernels (:func:`mbm.approximants.taylor.taylor_coefficients`,
    ``taylor_eval_kernel``): ``repeats`` rounds, each timing every degree once, and the
    minimum over the rounds (a slow spell of a shared machine then lands on every
    degree alike).  Degree :data:`mbm.approximants.taylor_simd.SIMD_ORDER` anchors by
    its emitted recurrence, the others by the generic one.

    Returns
    -------
    list of dict
        ``degree``, ``anchor_ns``, ``output_ns``.
    """
    anchors, outputs = _kernel_loops()
    best = {d: [math.inf, math.inf] for d in OVERHEAD_DEGREES}
    for d in OVERHEAD_DEGREES:
        anchors(2, d)
        outputs(2, d)
    for _ in range(repeats):
        for d in OVERHEAD_DEGREES:
            a = harness.timed_runs(lambda: anchors(n, d), 1)[0] / n
            o = harness.timed_runs(lambda: outputs(n, d), 1)[0] / n
            best[d] = [min(best[d][0], a), min(best[d][1], o)]
    return [dict(degree=d, anchor_ns=best[d][0] * 1e9, output_ns=best[d][1] * 1e9) for d in OVERHEAD_DEGREES]


def degrees_at_equal_error(scenes=DEGREE_SCENES, targets=DEGREE_TARGETS, repeats=20):
    """Cheapest :func:`mbm.solve` time of each Taylor degree at equal error.

    For each scene and degree, rtol = atol is swept over the benchmark's
    ``RTOL_SWEEP``; each point's error is max |θ − θ_ref| over the 201 output
    times (the benchmark's reference), its time a median of ``repeats`` calls timed
    in turns (:func:`benchmarks.harness.round_robin_medians`).  The cell of a target
    is the cheapest point at or below it, as in the benchmark's tables.

    Returns
    -------
    list of dict
        ``scene``, ``degree`` and, per target, ``(seconds, rtol)`` or None.
    """
    rows = []
    for name in scenes:
        sc = SCENES[name]
        ref = references.scene_reference(sc)["theta"]
        calls, errors = {}, {}
        for d in OVERHEAD_DEGREES:
            for r in RTOL_SWEEP:
                def run(d=d, r=r):
                    return mbm.solve(sc.model, sc.t_span, sc.y0, t_eval=sc.t_eval,
                                     approximant=f"taylor{d}", rtol=r, atol=r)

                res = run()
                errors[(d, r)] = harness.error(res.y[0], ref) if res.success else math.inf
                calls[(d, r)] = run
        seconds = harness.round_robin_medians(calls, repeats, block=DEGREE_BLOCK)
        for d in OVERHEAD_DEGREES:
            row = {"scene": name, "degree": d}
            for target in targets:
                ok = [(seconds[(d, r)], r) for r in RTOL_SWEEP if errors[(d, r)] <= target]
                row[target] = min(ok) if ok else None
            rows.append(row)
    return rows


def _us(seconds):
    return f"{seconds * 1e6:.1f}"


def format_overheads(ov):
    """Markdown section of :func:`overheads` (and ``equal_error``)."""
    lines = [f"## Fixed costs of a short run (rtol = atol = {OVERHEAD_RTOL:g})", "",
             "Public calls only, each differing from the previous in one thing; the differences "
             "below the table split the fixed cost (mbm's internals are not timed apart).", ""]
    table = ["| call | µs |", "|---|---:|"]
    table += [f"| {k} | {_us(v)} |" for k, v in ov["fixed"].items()]
    table += [f"| {k} | not measured ({why}) |" for k, why in ov.get("unavailable", {}).items()]
    table += [f"| derived: {k} | {v * 1e6:.3g} |" for k, v in ov.get("derived", {}).items()]
    lines += block("overheads-fixed", table)
    lines += ["", "`mbm.solve` on P1 (t ≤ 20) and P2 (t ≤ 80) by Taylor degree: with the 201 "
              "output times of the benchmark, and with none (window ends only).", "",
              "| scene | degree | windows | with 201 outputs (µs) | without (µs) |",
              "|---|---:|---:|---:|---:|"]
    lines += [f"| {r['scene']} | {r['degree']} | {r['windows']} | {_us(r['with_outputs'])} | "
              f"{_us(r['without_outputs'])} |" for r in ov["degrees"]]
    if ov.get("kernels"):
        lines += ["", "Taylor kernels inside a compiled loop (no dispatch; P2's parameters; best of 7 "
                  "loops, timed in rounds over the degrees): one anchor (coefficients a_0 … a_{N+2}) and one "
                  "output (θ, θ' by Horner).  Degree 24 anchors by its emitted (SIMD) recurrence, the "
                  "others by the generic one.", ""]
        lines += block("overheads-kernels", [
            "| degree | anchor (ns) | output (ns) |", "|---:|---:|---:|",
            *[f"| {r['degree']} | {r['anchor_ns']:.0f} | {r['output_ns']:.0f} |" for r in ov["kernels"]]])
    eq = ov.get("equal_error")
    if eq:
        targets = [k for k in eq[0] if isinstance(k, float)]
        lines += ["", "At equal error: the cheapest `mbm.solve` time of each degree whose max error "
                  "over the 201 outputs is at or below the target (rtol = atol swept as in the "
                  "benchmark; in parentheses the rtol it took).", ""]
        table = ["| scene | degree | " + " | ".join(f"{t:g} (µs)" for t in targets) + " |",
                 "|---|---:|" + "---:|" * len(targets)]
        for r in eq:
            cells = [("—" if r[t] is None else f"{_us(r[t][0])} ({r[t][1]:g})") for t in targets]
            table.append(f"| {r['scene']} | {r['degree']} | " + " | ".join(cells) + " |")
        lines += block("overheads-equal-error", table)
    text = "\n".join(lines) + "\n"
    if ov.get("per_call"):
        text += "\n" + per_call.format_fixed_costs(ov["per_call"])
    return text


def _machine_lines(machine):
    return [f"- {k}: {v}" for k, v in machine.items()]


def format_report(und, ens, machine, command):
    """Markdown report of :func:`undamped_long_horizon` and :func:`ensemble_iv`."""
    lines = ["# Speed targets outside the work-precision tables", "",
             f"Generated by `benchmarks/extras.py`; regenerate with `{command}`.", "",
             "## Machine", ""]
    lines += _machine_lines(machine)
    if und is None:
        return "\n".join(lines) + "\n"
    lines += ["", f"## Undamped, t = {und['t_end']:g} (β = γ = 0, θ₀ = {und['theta0']} rad, θ̇₀ = 0)", "",
              f"Reference θ(t_end) = {und['reference']!r} (mpmath, 40 digits).  Error = |θ − θ_ref| "
              "at t_end.  Ratio = the peer's time over MBM's (solve_ivp); where MBM's error is below "
              "the peer's, it bounds the speed-up at equal error from below.  heyoka: integrator "
              "built before the timing.", ""]
    table = ["| solver | knob | error | time (s) | ratio to MBM solve_ivp |", "|---|---|---:|---:|---:|"]
    base = und["rows"][0]["seconds"]
    for r in und["rows"]:
        mark = " (single run)" if r["single_run"] else ""
        table.append(f"| {r['solver']} | {r['knob']} | {r['error']:.1e} | {r['seconds']:.4g}{mark} | "
                     f"{r['seconds'] / base:,.3g}× |")
    lines += block("extras-undamped", table)
    if not und.get("heyoka", True):
        lines += ["", f"({peers.HEYOKA_MISSING})"]
    ref_name = ("heyoka in long double at tol 1e-19" if ens.get("reference") == "heyoka-ld"
                else "the 128-bit fixed-point Taylor reference")
    lines += ["", f"## Ensemble: I–V sweep, {ens['n']} scenes (β = {BETA_IV}, γ = 0 … {GAMMA_IV_MAX}, "
              f"from rest, 0 ≤ t ≤ {ens['t_end']:g})", "",
              f"Error: max |θ − θ_ref| at t = 0, t_end/2, t_end over {ens['subset']} scenes "
              f"(every 1000th), against {ref_name}.  Knob: the cheapest of each solver's sweep "
              "meeting the target on that subset.  Time: the whole ensemble; heyoka's integrators "
              "(one per tolerance, scalar and batch) are built before it.", ""]
    table = ["| target | solver | threads | knob | subset error | time (s) | scenes/s per core |",
             "|---|---|---:|---|---:|---:|---:|"]
    for r in ens["rows"]:
        if r["seconds"] is None:
            table.append(f"| {r['target']:g} | {r['solver']} | - | — | — | — | — |")
            continue
        table.append(f"| {r['target']:g} | {r['solver']} | {r['threads']} | {r['knob']} | "
                     f"{r['error']:.1e} | {r['seconds']:.3g} | {r['per_core']:,.0f} |")
    lines += block("extras-ensemble", table)
    if not ens.get("heyoka", True):
        lines += ["", f"({peers.HEYOKA_MISSING})"]
    lines += ["", "Subset error of each knob of the sweeps (the knob is rtol = atol, heyoka's tol, "
              "or the RK4 step h):", ""]
    for name, pts in ens.get("sweeps", {}).items():
        lines.append(f"- {name}: " + ", ".join(f"{k:g} → {e:.1e}" for k, e in pts))
    builds = {"heyoka (undamped)": und["builds"]} if und.get("builds") else {}
    builds.update(ens.get("builds", {}))
    if builds:
        lines += ["", "heyoka integrator builds (seconds, not in the times above): " + "; ".join(
            f"{name}: " + ", ".join(f"tol {float(k):g} {v:.3f}" for k, v in b.items())
            for name, b in builds.items())]
    par = ens.get("parallel")
    if par:
        lines += ["", f"Threads: {par['threads']} (numba's default here).  A compute-only `prange` "
                  f"loop runs {par['speedup']:.2f}× faster on {par['threads']} threads than on 1 on "
                  "this machine (`parallel_baseline`): that is the ceiling for the multi-thread row; "
                  "the 1-thread rows are the per-core figures to compare with the looped and batch "
                  "peers."]
    return "\n".join(lines) + "\n"


def _load_json(path):
    """A saved ``--json`` file, with the float keys JSON turned into strings turned back."""
    def keys(d):
        return {(float(k) if k[:1].isdigit() else k): v for k, v in d.items()}

    return json.loads(Path(path).read_text(), object_hook=keys)


def main(argv=None):
    """Command line: ``python -m benchmarks extras [--quick] [--overheads] [--out FILE]``."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks extras", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="short horizons and a small ensemble")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs per point (default 5)")
    parser.add_argument("--out", default=None, help="write the Markdown report here")
    parser.add_argument("--json", default=None, metavar="PATH", help="also write the results as JSON")
    parser.add_argument("--reference", default="fixed-point", choices=("fixed-point", "heyoka-ld"),
                        help="reference of the ensemble's subset (default %(default)s)")
    parser.add_argument("--from-json", default=None, metavar="PATH",
                        help="render the report from a saved --json file; run nothing")
    parser.add_argument("--overheads", action="store_true",
                        help="instead: the fixed per-call costs and output cost of short runs, "
                             "and each Taylor degree at equal error (a few minutes)")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error("--repeats must be >= 1")
    command = "python -m benchmarks extras " + " ".join(argv if argv is not None else sys.argv[1:])
    machine = harness.machine_info()
    if args.from_json:
        data = _load_json(args.from_json)
        machine, command = data.get("machine", machine), data.get("command", command)
        text = format_report(data.get("undamped"), data.get("ensemble"), machine, command)
        if "overheads" in data:
            text += "\n" + format_overheads(data["overheads"])
        args.json = None
    elif args.overheads:
        text = format_report(None, None, machine, command.strip())
        ov = overheads(repeats=20 if args.quick else 200)
        ov["equal_error"] = degrees_at_equal_error(scenes=("P1",) if args.quick else DEGREE_SCENES,
                                                   repeats=3 if args.quick else 20)
        ov["per_call"] = per_call.fixed_costs(repeats=20 if args.quick else per_call.DEFAULT_REPEATS)
        text += "\n" + format_overheads(ov)
        data = {"overheads": ov}
    else:
        und = undamped_long_horizon(repeats=args.repeats, quick=args.quick)
        ens = ensemble_iv(n=200 if args.quick else N_ENSEMBLE, quick=args.quick,
                          reference=args.reference)
        text = format_report(und, ens, machine, command.strip())
        data = {"undamped": und, "ensemble": ens}
    if args.out:
        Path(args.out).write_text(text)
        print(f"wrote {args.out}", file=sys.stderr)
    else:
        print(text)
    if args.json:
        data["machine"], data["command"] = machine, command.strip()
        Path(args.json).write_text(json.dumps(data, default=json_default, indent=1))
    return 0
