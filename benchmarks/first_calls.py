"""First calls from an empty numba cache: what a new user waits for, measured.

Each measurement runs in a fresh Python process whose ``NUMBA_CACHE_DIR`` is a new
empty directory (so every kernel it needs is compiled, none loaded), on the second
paper's Example 1 (P2: β = 0.1, γ = 0.3, θ₀ = 30°, rtol = atol = 1e-9, 201 outputs on
[0, 80]):

* ``solve_ivp(method=mbm.MBM)`` alone;
* ``mbm.solve`` alone;
* ``solve_ivp`` then ``mbm.solve`` in one process (the second's own compile);
* ``mbm.solve`` with fixed windows (τ = 0.5, the step-size studies' runs) alone;
* ``solve_ivp`` then a further approximant kind, the further kind's own compile:
  ``salas-torque`` (τ = 0.25: the demo's third row), ``split4`` (adaptive, rtol = atol
  = 1e-9) and the exact flow (``auto`` on the undamped, untorqued scene β = γ = 0);
* ``mbm.solve`` alone on a running scene (β = 0.1, γ = 1.2, from rest, 201 outputs on
  [0, 400]): the run switches to its limit cycle's stored period (a second entry);
* ``mbm.solve_batch`` alone on 64 damped scenes (locked and running ones);
* the junction toolkit's and the noise's entry points alone (``iv_curve``, ``shapiro_steps``,
  ``sweep``, ``escape_times``, ``switching_currents``, ``retrapping_currents``), and ``mbm.solve`` with
  ``error_estimate=True``;
* ``python -m mbm demo`` as a whole (wall time of the command);
* ``solve_ivp`` and ``mbm.solve`` alone again with ``MBM_COMPILE_HELPER=0``.

The rows but the last two run as a user's first call does: with the compile helper
(:mod:`mbm.compile.warm`), a second process that compiles the call's kernels on the second
core beside it; the last two are the call compiling alone on one core.

Run ``python -m benchmarks.first_calls`` (``--repeat N`` for the median of N fresh
processes per row; ``--out FILE``, default ``docs/first_calls.md``).  The machine and
versions are stated in the file it writes.  The entry points' medians also go to
``mbm/compile/first_calls.json`` (``--entries-out``), from which the compile notice
quotes the first call's measured seconds.
"""

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks.report import block

ROOT = Path(__file__).resolve().parent.parent
# A fresh process's compile is tens of seconds on 2 cores; past this a row is reported
# as timed out rather than waited on.
ROW_TIMEOUT = 600

_SETUP = """
import json, math, os, sys, time
import numpy as np
from scipy.integrate import solve_ivp
import mbm
m = mbm.Pendulum(beta=0.1, gamma=0.3)
y0 = [math.radians(30), 0.0]
t = np.linspace(0.0, 80.0, 201)
def ivp():
    solve_ivp(m, (0.0, 80.0), y0, method=mbm.MBM, rtol=1e-9, atol=1e-9, t_eval=t, dense_output=True)
def solve():
    mbm.solve(m, (0.0, 80.0), y0, rtol=1e-9, atol=1e-9, t_eval=t)
def fixed():
    mbm.solve(m, (0.0, 80.0), y0, tau=0.5, t_eval=t)
def salas():
    solve_ivp(m, (0.0, 80.0), y0, method=mbm.MBM, approximant="salas-torque", tau=0.25, t_eval=t)
def split():
    solve_ivp(m, (0.0, 80.0), y0, method=mbm.MBM, approximant="split4", rtol=1e-9, atol=1e-9, t_eval=t)
def exact():
    solve_ivp(mbm.Pendulum(beta=0.0, gamma=0.0), (0.0, 80.0), y0, method=mbm.MBM, t_eval=t)
def running():
    mbm.solve(mbm.Pendulum(beta=0.1, gamma=1.2), (0.0, 400.0), [0.0, 0.0], rtol=1e-9, atol=1e-9,
              t_eval=np.linspace(0.0, 400.0, 201))
def batch():
    mbm.solve_batch(0.1, np.linspace(0.05, 1.5, 64), 1.0, y0, (0.0, 80.0), t, rtol=1e-9, atol=1e-9)
def iv():
    mbm.iv_curve(0.5, np.linspace(0.0, 1.4, 8))
def shapiro():
    mbm.shapiro_steps(0.5, (0.0, 1.5), amplitude=0.8, frequency=0.5, points=9)
def sweep():
    mbm.sweep(beta=np.array([0.2, 1.0]), gamma=np.linspace(0.0, 1.4, 8), t_span=(0.0, 200.0),
              reduce="mean_velocity")
def escape():
    mbm.escape_times(1.0, 0.7, 0.2, 64, seed=1)
def switching():
    mbm.switching_currents(0.2, 0.05, 1e-2, 64, seed=1)
def retrapping():
    mbm.retrapping_currents(0.2, 0.01, 1e-3, 16, seed=1)
def estimate():
    mbm.solve(m, (0.0, 80.0), y0, rtol=1e-9, atol=1e-9, t_eval=t, error_estimate=True)
def timed(fn):
    t0 = time.perf_counter(); fn(); return time.perf_counter() - t0
"""

#: row label -> Python statements printing one JSON number (the row's seconds).
ROWS = {
    "solve_ivp(method=mbm.MBM), first call": "print(json.dumps(timed(ivp)))",
    "mbm.solve, first call": "print(json.dumps(timed(solve)))",
    "mbm.solve after solve_ivp (its own compile)": "timed(ivp); print(json.dumps(timed(solve)))",
    "mbm.solve with fixed windows (tau = 0.5), first call": "print(json.dumps(timed(fixed)))",
    "salas-torque after solve_ivp (a further kind)": "timed(ivp); print(json.dumps(timed(salas)))",
    "split4 after solve_ivp (a further kind)": "timed(ivp); print(json.dumps(timed(split)))",
    "the exact flow (β = γ = 0) after solve_ivp (a further kind)": "timed(ivp); print(json.dumps(timed(exact)))",
    "mbm.solve, first call on a running scene (γ = 1.2: it reaches its limit cycle)":
        "print(json.dumps(timed(running)))",
    "mbm.solve_batch, first call (64 damped scenes, γ 0.05 to 1.5)": "print(json.dumps(timed(batch)))",
    "mbm.iv_curve, first call (β = 0.5, 8 bias points)": "print(json.dumps(timed(iv)))",
    "mbm.shapiro_steps, first call (β = 0.5, A = 0.8, Ω = 0.5, 9 points)": "print(json.dumps(timed(shapiro)))",
    "mbm.sweep, first call (2 × 8 scenes, mean velocity)": "print(json.dumps(timed(sweep)))",
    "mbm.escape_times, first call (64 escapes)": "print(json.dumps(timed(escape)))",
    "mbm.switching_currents, first call (64 ramps)": "print(json.dumps(timed(switching)))",
    "mbm.retrapping_currents, first call (16 ramps down)": "print(json.dumps(timed(retrapping)))",
    "mbm.solve with error_estimate=True, first call": "print(json.dumps(timed(estimate)))",
}
#: row label -> the entry point the compile notice names (mbm.compile.cache._entry_point):
#: these rows' medians go to mbm/compile/first_calls.json, which the notice quotes.
ENTRIES = {
    "solve_ivp(method=mbm.MBM), first call": ("MBM.__init__", "MBM._step_impl"),
    "mbm.solve, first call": ("solve", "Integrator.__init__", "Integrator.solve"),
    "mbm.solve_batch, first call (64 damped scenes, γ 0.05 to 1.5)": ("solve_batch",),
    "mbm.iv_curve, first call (β = 0.5, 8 bias points)": ("iv_curve",),
    "mbm.shapiro_steps, first call (β = 0.5, A = 0.8, Ω = 0.5, 9 points)": ("shapiro_steps",),
    "mbm.sweep, first call (2 × 8 scenes, mean velocity)": ("sweep",),
    "mbm.escape_times, first call (64 escapes)": ("escape_times",),
    # switching_grid runs switching_currents' kernels: the same compile.
    "mbm.switching_currents, first call (64 ramps)": ("switching_currents", "switching_grid"),
    "mbm.retrapping_currents, first call (16 ramps down)": ("retrapping_currents",),
}
ENTRIES_OUT = ROOT / "mbm" / "compile" / "first_calls.json"
# The same first calls compiling on one core (the last rows of the table).
NO_HELPER = "os.environ['MBM_COMPILE_HELPER'] = '0'; "
HELPERLESS_ROWS = {
    "solve_ivp(method=mbm.MBM), first call, no compile helper": NO_HELPER + "print(json.dumps(timed(ivp)))",
    "mbm.solve, first call, no compile helper": NO_HELPER + "print(json.dumps(timed(solve)))",
}
DEMO_ROW = "python -m mbm demo, whole command"
# The block the README quotes (benchmarks.report's quoting).
BLOCK_NAME = "first-calls"


def _fresh_env(tmp):
    env = dict(os.environ, NUMBA_CACHE_DIR=tmp, MBM_COMPILE_NOTICE="0")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    return env


def measure_row(code):
    """Seconds the row's statements report in a fresh process with an empty cache, or None."""
    with tempfile.TemporaryDirectory() as tmp:
        try:
            proc = subprocess.run([sys.executable, "-c", _SETUP + code], env=_fresh_env(tmp), cwd=ROOT,
                                  capture_output=True, text=True, timeout=ROW_TIMEOUT)
        except subprocess.TimeoutExpired:
            return None
    if proc.returncode != 0:
        return None
    return float(json.loads(proc.stdout.strip().splitlines()[-1]))


def measure_demo():
    """Wall seconds of ``python -m mbm demo`` in a fresh process with an empty cache, or None."""
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        try:
            proc = subprocess.run([sys.executable, "-m", "mbm", "demo"], env=_fresh_env(tmp), cwd=ROOT,
                                  capture_output=True, text=True, timeout=ROW_TIMEOUT)
        except subprocess.TimeoutExpired:
            return None
        wall = time.perf_counter() - t0
    return wall if proc.returncode == 0 else None


def machine():
    """The machine and versions, one line."""
    import numba
    import numpy
    import scipy

    return (f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores; Python "
            f"{platform.python_version()}, numpy {numpy.__version__}, scipy {scipy.__version__}, "
            f"numba {numba.__version__}")


def format_table(rows, repeat, machine_line):
    """The Markdown page of the measurements: ``rows`` is a list of (label, [seconds or None])."""
    table = ["| call (fresh process, empty numba cache) | seconds |", "|---|---:|"]
    for label, values in rows:
        got = [v for v in values if v is not None]
        cell = f"{statistics.median(got):.1f}" if got else "failed"
        table.append(f"| {label} | {cell} |")
    out = ["# First calls from an empty numba cache", "",
           "Generated by `python -m benchmarks.first_calls` (do not edit by hand): each row is a fresh",
           "process with an empty `NUMBA_CACHE_DIR`, the second paper's Example 1 (rtol = atol = 1e-9);",
           "all rows but the last two with the compile helper (`mbm.compile.warm`: a second process compiles",
           "the call's kernels on another core), the last two with `MBM_COMPILE_HELPER=0`.",
           f"Median of {repeat} process(es) per row. Machine: {machine_line}.", "",
           *block(BLOCK_NAME, table)]
    return "\n".join(out) + "\n"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=1, help="fresh processes per row (median)")
    parser.add_argument("--out", default=str(ROOT / "docs" / "first_calls.md"))
    parser.add_argument("--entries-out", default=str(ENTRIES_OUT),
                        help="the entry points' seconds, quoted by the compile notice")
    args = parser.parse_args(argv)
    if args.repeat < 1:
        parser.error(f"--repeat must be >= 1, got {args.repeat}")
    rows = []
    for label, code in ROWS.items():
        rows.append((label, [measure_row(code) for _ in range(args.repeat)]))
        print(label, rows[-1][1], flush=True)
    rows.append((DEMO_ROW, [measure_demo() for _ in range(args.repeat)]))
    print(DEMO_ROW, rows[-1][1], flush=True)
    for label, code in HELPERLESS_ROWS.items():
        rows.append((label, [measure_row(code) for _ in range(args.repeat)]))
        print(label, rows[-1][1], flush=True)
    Path(args.out).write_text(format_table(rows, args.repeat, machine()))
    print("wrote", args.out)
    write_entries(rows, args.entries_out)


def write_entries(rows, out):
    """The entry points' medians as the compile notice reads them (mbm.compile.cache.first_call_seconds)."""
    entries = {}
    for label, values in rows:
        got = [v for v in values if v is not None]
        for entry in ENTRIES.get(label, ()):
            if got:
                entries[entry] = round(statistics.median(got), 1)
    Path(out).write_text(json.dumps({"generated_by": "python -m benchmarks.first_calls", "machine": machine(),
                                     "entries": entries}, indent=1, ensure_ascii=False) + "\n")
    print("wrote", out)


if __name__ == "__main__":
    main()
