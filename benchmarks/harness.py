"""Timing and sweeps: medians with the garbage collector paused, compile time apart.

For every knob value of a solver (:mod:`benchmarks.registry`) the harness times the
whole call a user would make (solver set-up, integration, output at the 201 times)
on inputs built once per scene, takes the median of ``repeats`` runs after one
warm-up run, and records the error ``max |θ − θ_ref|`` over the 201 times.  A
work-precision curve is the list of (error, median time) pairs.  At each target
error (1e-3, 1e-6, 1e-9) the report shows the cheapest *measured* point whose error
is at or below the target (nothing is interpolated).

What a solver does once before it can run (numba's JIT compile of the peers written
here, heyoka's integrator build, MBM's numba cache load) is measured apart
(:func:`first_call_seconds`, ``Solver.prepare``) and never enters a point's time.
"""

import contextlib
import datetime
import gc
import json
import math
import os
import platform
import statistics
import sys
import time

import numpy as np

from mbm.junction.progress import Progress

from . import peers, references
from .registry import solver_registry
from .scenes import N_OUTPUT, SCENES

__all__ = [
    "TARGETS",
    "DEFAULT_REPEATS",
    "QUICK_REPEATS",
    "MAX_POINT_SECONDS",
    "gc_paused",
    "timed_runs",
    "median_time",
    "round_robin_medians",
    "error",
    "run_sweep",
    "cheapest_at_target",
    "first_call_seconds",
    "cold_first_call_seconds",
    "machine_info",
    "run_benchmark",
]

# Target errors of the tables: three accuracy regimes.
TARGETS = (1e-3, 1e-6, 1e-9)

# Timed runs per point after the warm-up run (medians of >= 5).
DEFAULT_REPEATS = 5
QUICK_REPEATS = 3

# A sweep stops after the first point whose warm-up run exceeds this many seconds
# (that point is recorded with its error but not timed): later points of a sweep
# are more accurate and cost more, and 5 repeats of a 2 s point already make a
# scene-solver pair cost ~25 s.  Overridden by --max-seconds.
MAX_POINT_SECONDS = 2.0

# A sweep also stops once the error is this small: 100x below the tightest target,
# further points only measure round-off and cost more.
STOP_ERROR = 1e-11

# --cold-compile: limit on the subprocess that compiles MBM's kernels from an empty
# numba cache (a few tens of seconds on a loaded 2-core machine).
COLD_COMPILE_TIMEOUT = 600

# Calls timed in a row per turn by round_robin_medians: enough for warm caches and
# branch predictors (as in the sweeps' repeated runs; one call per turn, round robin
# over 23 entries, read 2-3x slower), few enough that turns interleave.
ROUND_ROBIN_BLOCK = 20


# ---------------------------------------------------------------------------
# Timing
# ---------------------------------------------------------------------------


def error(theta, ref_theta):
    """``max |θ − θ_ref|``; inf when ``theta`` has the wrong shape or a non-finite value."""
    theta = np.asarray(theta, dtype=float).reshape(-1)
    if theta.shape != ref_theta.shape or not np.all(np.isfinite(theta)):
        return math.inf
    return float(np.max(np.abs(theta - ref_theta)))


def _timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


@contextlib.contextmanager
def gc_paused():
    """Keep the garbage collector off for the block (as ``timeit`` does).

    Only the youngest generation is collected first: a full collection costs in
    proportion to every object alive (up to a second in a big process, such as the
    test suite), and with the collector off none can start inside the block anyway.
    """
    gc_was = gc.isenabled()
    gc.collect(0)
    gc.disable()
    try:
        yield
    finally:
        if gc_was:
            gc.enable()


def entry_calls(entry):
    """A compiled loop that calls the loop entry ``entry`` (``mbm.core.loop.entry_for``'s) ``n``
    times as a fresh run: ``calls(n, buf, t0, theta0, v0, t1, h, t_eval, out, win_t,
    win_y, win_coef, cancel)`` returns the sum of its returns; the entry's cost without
    Python's dispatch (``entry`` is a constant of the loop)."""
    import numba

    @numba.njit
    def calls(n, buf, t0, theta0, v0, t1, h, t_eval, out, win_t, win_y, win_coef, cancel):
        total = 0
        for _ in range(n):
            total += entry(buf, True, (t0, theta0, v0, t1, h), (t_eval, out, win_t, win_y, win_coef, cancel))
        return total

    return calls

def timed_runs(fn, repeats):
    """Seconds of ``repeats`` calls of ``fn`` with the garbage collector off (as ``timeit``)."""
    with gc_paused():
        return [_timed(fn)[0] for _ in range(repeats)]


def median_time(fn, repeats):
    """One warm-up call, then the median of ``repeats`` timed calls (:func:`timed_runs`)."""
    fn()
    return statistics.median(timed_runs(fn, repeats))


def round_robin_medians(calls, repeats, block=ROUND_ROBIN_BLOCK):
    """Median seconds of each of ``calls`` (name -> callable), timed in turns.

    Each round times every call ``block`` times in a row, after one untimed call
    (as the sweeps do: the same call repeated, warm); rounds repeat until each call
    has ``repeats`` timings (:func:`timed_runs`: garbage collector off).  A slow
    spell of a shared machine then lands on every entry alike instead of on the few
    timed during it.
    """
    times = {k: [] for k in calls}
    while any(len(v) < repeats for v in times.values()):
        for k, fn in calls.items():
            fn()
            times[k] += timed_runs(fn, min(block, repeats - len(times[k])))
    return {k: statistics.median(v) for k, v in times.items()}


# ---------------------------------------------------------------------------
# Sweeps
# ---------------------------------------------------------------------------


def run_sweep(solver, scene, ref_theta, repeats=DEFAULT_REPEATS, quick=False,
              max_seconds=MAX_POINT_SECONDS, stop_error=STOP_ERROR):
    """Work-precision points of one solver on one scene.

    For each knob value (cheap to expensive): ``solver.prepare(knob)`` if the
    solver has one (untimed; its seconds recorded as ``prepare``), one warm-up run
    (gives the error), then ``repeats`` timed runs with the garbage collector off
    (as ``timeit``), whose median is the point's time.  The sweep stops after a
    point whose warm-up run took more than ``max_seconds`` (recorded, not timed) or
    whose error is at most ``stop_error``; a warm-up over ``max_seconds`` is run once
    more before that, so that a numba compile in a first call does not end the sweep.

    Parameters
    ----------
    solver : benchmarks.registry.Solver
    scene : benchmarks.scenes.BenchScene
    ref_theta : ndarray
        Reference θ at ``scene.t_eval``.
    repeats : int
        Timed runs per point (median).
    quick : bool
        Use the solver's ``quick_sweep``.
    max_seconds, stop_error : float
        Stopping rules, see above.

    Returns
    -------
    list of dict
        One per point: ``knob``, ``error`` (inf when the run failed), ``time``
        (median seconds, None when not timed), ``times`` (all timed runs),
        ``status`` (``"ok"``, ``"failed"``, ``"over budget"``), ``message`` and,
        for solvers with a ``prepare`` step, ``prepare`` (seconds).
    """
    points = []
    seen = set()
    for knob in (solver.quick_sweep if quick else solver.sweep):
        if solver.knob == "h":
            # Fixed steps are rounded to divide the output spacing: skip duplicates.
            key = peers.steps_per_output(scene, knob)
            if key in seen:
                continue
            seen.add(key)
        point = {"knob": float(knob), "error": math.inf, "time": None, "times": [],
                 "status": "ok", "message": ""}
        dt = None
        try:
            if solver.prepare is not None:
                point["prepare"] = _timed(lambda: solver.prepare(knob))[0]
            dt, theta = _timed(lambda: solver.run(scene, knob))
            point["error"] = error(theta, ref_theta)
        except Exception as exc:  # a failed run is a data point, not a crash
            dt = None
            point["status"] = "failed"
            point["message"] = f"{type(exc).__name__}: {exc}"[:200]
        if point["status"] == "ok" and not math.isfinite(point["error"]):
            point["status"] = "failed"
            point["message"] = "non-finite or missing output"
        if dt is not None and dt > max_seconds and point["status"] == "ok":
            # A warm-up over budget may be a first call's compile (a knob that takes a
            # code path no earlier point took): a second run tells which.
            dt2 = _timed(lambda: solver.run(scene, knob))[0]
            if dt2 <= max_seconds:
                point["message"] = f"first warm-up {dt:.2f} s (a compile), second {dt2:.2f} s"
                dt = dt2
        if dt is not None and dt > max_seconds:
            point["status"] = "over budget"
            point["message"] = f"warm-up run took {dt:.2f} s > {max_seconds:g} s"
            points.append(point)
            break
        if point["status"] == "ok":
            times = timed_runs(lambda: solver.run(scene, knob), repeats)
            point["times"] = times
            point["time"] = statistics.median(times)
        points.append(point)
        if point["error"] <= stop_error:
            break
    return points


def cheapest_at_target(points, target):
    """The cheapest timed point whose error is at or below ``target``.

    Nothing is interpolated: only measured points count.

    Parameters
    ----------
    points : list of dict
        As returned by :func:`run_sweep` (keys ``error``, ``time``, ``status``).
    target : float

    Returns
    -------
    dict or None
        The point, or None when no timed point reaches the target.
    """
    ok = [p for p in points
          if p.get("time") is not None and p.get("status", "ok") == "ok" and p["error"] <= target]
    if not ok:
        return None
    return min(ok, key=lambda p: p["time"])


# ---------------------------------------------------------------------------
# First calls: JIT compile, cache load, integrator build
# ---------------------------------------------------------------------------


def first_call_seconds(solver, scene):
    """What the solver pays once before its warm runs, on ``scene``, in seconds.

    With a ``prepare`` step (heyoka): that step's time at the first quick knob, from
    scratch.  Otherwise: the first call minus the fastest of three warm calls (JIT
    compile or numba cache load; imports).  None if the solver fails.
    """
    knob = solver.quick_sweep[0]
    try:
        if solver.prepare is not None:
            return _timed(lambda: solver.prepare(knob))[0]
        cold = _timed(lambda: solver.run(scene, knob))[0]
        warm = min(_timed(lambda: solver.run(scene, knob))[0] for _ in range(3))
    except Exception:
        return None
    return max(0.0, cold - warm)


_COLD_SCRIPT = r"""
import json, math, sys, time
t0 = time.perf_counter()
import numpy as np
from scipy.integrate import solve_ivp
import mbm
out = {"import mbm": time.perf_counter() - t0}
model = mbm.Pendulum(0.1, 0.3)
y0 = [math.radians(30.0), 0.0]
t = np.linspace(0.0, 80.0, 201)
calls = [("MBM (solve_ivp), first call",
          lambda: solve_ivp(model, (0.0, 80.0), y0, method=mbm.MBM, model=model, t_eval=t,
                            rtol=1e-6, atol=1e-6)),
         ("mbm.solve after it (its own compile)",
          lambda: mbm.solve(model, (0.0, 80.0), y0, t_eval=t, rtol=1e-6, atol=1e-6))]
for name, fn in calls:
    t0 = time.perf_counter()
    fn()
    cold = time.perf_counter() - t0
    t0 = time.perf_counter()
    fn()
    out[name] = cold - (time.perf_counter() - t0)
print(json.dumps(out))
"""


def cold_first_call_seconds():
    """MBM's import and first-call seconds in a fresh process with an empty numba cache.

    MBM's kernels are cached on disk (``cache=True``), so in the benchmark process
    their first call is a cache load; this measures the one-off JIT compile a new
    installation pays, in a subprocess whose ``NUMBA_CACHE_DIR`` is a new empty
    directory (P2, ``approximant="auto"``, rtol = 1e-6; first call minus second).

    Returns
    -------
    dict or None
        ``{"import mbm": s, "MBM (solve_ivp), first call": s, "mbm.solve after it (its own
        compile)": s}`` (the two paths share the loop's entries, so the second is ~0),
        or None if the subprocess failed.
    """
    import subprocess
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, NUMBA_CACHE_DIR=tmp)
        try:
            proc = subprocess.run([sys.executable, "-c", _COLD_SCRIPT], env=env, capture_output=True,
                                  text=True, timeout=COLD_COMPILE_TIMEOUT)
        except subprocess.TimeoutExpired:
            return None
    if proc.returncode != 0:
        return None
    try:
        return json.loads(proc.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        return None


# ---------------------------------------------------------------------------
# The run
# ---------------------------------------------------------------------------


def machine_info():
    """CPU model, core counts and library versions, for the report.

    Returns
    -------
    dict
    """
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    info = {
        "cpu": cpu,
        "logical cores": os.cpu_count(),
        "usable cores": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None,
        "platform": platform.platform(),
        "python": platform.python_version(),
    }
    from importlib import metadata

    for dist in ("numpy", "scipy", "numba", "scikit-sundae", "mbm", "numbalsoda", "heyoka",
                 "matplotlib"):
        try:
            info[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            info[dist] = "not installed"
    return info


class _stdout_to_stderr:
    """Point file descriptor 1 at stderr for the duration (one dup2 each way).

    numbalsoda's Fortran DOP853 prints "the problem seems to become stiff" to the
    process's stdout on the running scene; this keeps such lines out of a report
    printed to stdout, without a per-call cost inside the timed runs.
    """

    def __enter__(self):
        sys.stdout.flush()
        try:
            self._saved = os.dup(1)
            os.dup2(2, 1)
        except OSError:
            self._saved = None
        return self

    def __exit__(self, *exc):
        if self._saved is not None:
            sys.stdout.flush()
            os.dup2(self._saved, 1)
            os.close(self._saved)
        return False


def run_benchmark(scenes=None, repeats=DEFAULT_REPEATS, quick=False, max_seconds=MAX_POINT_SECONDS,
                  solver_filter=None, cache_dir=None, cold_compile=False, log=None,
                  show_progress=True, reference="auto"):
    """Run every solver's sweep on every scene.

    Parameters
    ----------
    scenes : list of str or None
        Scene names (default all of :data:`benchmarks.scenes.SCENES`).
    repeats : int
        Timed runs per point.
    quick : bool
        Short sweeps (for tests).
    max_seconds : float
        Per-point budget of :func:`run_sweep`.
    solver_filter : list of str or None
        Keep solvers whose name contains one of these (case-insensitive).
    cache_dir : path-like, None or False
        Reference cache, see :func:`benchmarks.references.scene_reference`.
    cold_compile : bool
        Also measure MBM's compile from an empty numba cache
        (:func:`cold_first_call_seconds`, a subprocess).
    log : file-like or None
        Progress lines go here.
    show_progress : bool or file-like
        Draw a progress bar over the (scene, solver) sweeps on stderr when it is a
        terminal (True), never (False), or always on the given stream.
    reference : str
        Reference method (:data:`benchmarks.references.REFERENCE_METHODS`).

    Returns
    -------
    dict
        ``scenes``, ``solvers`` (name -> family, compiled, knob, note),
        ``missing`` (optional peers not installed: name -> reason),
        ``references``, ``points`` (scene -> solver -> list of points),
        ``first_call`` (solver -> seconds), ``cold_compile`` (dict or None),
        ``notes``, ``machine``, ``settings``.
    """
    scenes = list(SCENES) if scenes is None else list(scenes)
    for s in scenes:
        if s not in SCENES:
            raise ValueError(f"unknown scene {s!r}; choose from {sorted(SCENES)}")

    solvers, notes, missing = solver_registry()
    if solver_filter:
        keys = [f.lower() for f in solver_filter]
        solvers = [s for s in solvers if any(k in s.name.lower() for k in keys)]
        missing = {n: r for n, r in missing.items() if any(k in n.lower() for k in keys)}
    if show_progress is True or show_progress is False:
        bar = Progress(len(scenes) * len(solvers), "bench", enabled=None if show_progress else False)
    else:
        bar = Progress(len(scenes) * len(solvers), "bench", stream=show_progress, enabled=True)

    def say(msg):
        # Log lines go above the bar when both share a terminal.
        if log is not None:
            bar.message(msg, stream=log)
    # JIT compile times first, before anything else in this process calls the peers.
    compile_s = peers.compile_numba_peers()
    first_scene = SCENES[scenes[0]]
    first_call = {}
    for s in solvers:
        if s.name in compile_s:
            first_call[s.name] = compile_s[s.name]
        else:
            first_call[s.name] = first_call_seconds(s, first_scene)
    cold = None
    if cold_compile:
        say("MBM compile from an empty numba cache (subprocess) ...")
        cold = cold_first_call_seconds()
    refs = {}
    points = {}
    for name in scenes:
        scene = SCENES[name]
        t0 = time.perf_counter()
        ref = references.scene_reference(scene, cache_dir, method=reference)
        refs[name] = {k: v for k, v in ref.items() if k != "theta"}
        say(f"{name}: reference {ref['method']} ({time.perf_counter() - t0:.1f} s), "
            f"check {ref['check_method']}: {ref['check']:.1e}")
        points[name] = {}
        for s in solvers:
            t0 = time.perf_counter()
            with _stdout_to_stderr():
                pts = run_sweep(s, scene, ref["theta"], repeats=repeats, quick=quick,
                                max_seconds=max_seconds)
            points[name][s.name] = pts
            best = min((p["error"] for p in pts), default=math.inf)
            say(f"  {s.name:<24} {len(pts):2d} points, best error {best:.1e}, "
                f"{time.perf_counter() - t0:.1f} s")
            bar.update()
    bar.close()
    return {
        "scenes": scenes,
        "solvers": {s.name: {"family": s.family, "compiled": s.compiled, "knob": s.knob,
                             "note": s.note} for s in solvers},
        "missing": missing,
        "references": refs,
        "points": points,
        "first_call": first_call,
        "cold_compile": cold,
        "notes": notes,
        "machine": machine_info(),
        "settings": {"repeats": repeats, "quick": quick, "max_seconds": max_seconds,
                     "targets": list(TARGETS), "n_output": N_OUTPUT,
                     "ref_tol": references.REF_TOL, "reference": reference,
                     "date": datetime.datetime.now().isoformat(timespec="seconds")},
    }
