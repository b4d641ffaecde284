"""The cost of one output time in each regime (issue 52: after a switch ≤ 2× the integrating path's).

Run from the root of a checkout::

    python -m benchmarks.output_cost [--full] [--batches N] [--out docs/output_cost.md]

One scene per regime (:data:`SCENES`), each solved over [0, T] by ``mbm.solve`` at
rtol = atol = :data:`TOL` (its cache of Integrators: a prepared run) twice, with
``n`` output times spread evenly over the span and with the span's two ends alone;
an output's cost is the difference divided by ``n`` (the windows cost the same in
both).  Each time is the best of ``batches`` calls, taken in turns (a slow spell of
the shared machine lands on both alike); the first calls (compile, cache load) are
not timed.  The script checks that each scene reaches its regime and refuses to
report otherwise.  Default: T = 2000, 20,001 outputs (under a minute); ``--full``:
200,001 outputs (issue 52's figures).  Then issue 52's Shapiro-step client
(:data:`SHAPIRO`): one bias point, 40,001 outputs, by ``mbm.solve`` and by
``solve_ivp(method=mbm.MBM)``, with its outputs and without.
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import mbm

from . import harness
from .report import block

__all__ = ["SCENES", "output_costs", "format_output_costs", "main"]

#: (name, expected regime, model parameters (β, γ, ω, A, Ω, φ), y0) per row.
SCENES = (
    # A chaotic driven run (tests/regimes/test_strobe.py, NOT_PERIOD_ONE): never switches.
    ("integrating", "none", (0.2, 0.2, 1.0, 1.0, 1.0, 0.0), (0.0, 0.0)),
    ("locked", "locked", (0.5, 0.2, 1.0, 0.0, 0.0, 0.0), (1.0, 0.0)),
    ("running cycle", "running", (0.1, 1.2, 1.0, 0.0, 0.0, 0.0), (0.0, 0.0)),
    ("libration", "libration", (0.0, 0.4, 1.0, 0.0, 0.0, 0.0), (1.0, 0.0)),
    # β = γ = 0: "auto" takes the exact flow, one window for the span (no regime).
    ("exact flow", "none", (0.0, 0.0, 1.0, 0.0, 0.0, 0.0), (1.0, 0.0)),
    # The n = 1 Shapiro step of tests/regimes/test_strobe.py (STEP).
    ("phase-locked", "phase-locked", (0.2, 0.2, 1.0, 2.0, 1.0, 0.0), (0.0, 0.0)),
)
TOL = 1e-9
SPAN = 2000.0
# Outputs per scene: the default (under a minute in all) and --full (issue 52's).
N_DEFAULT = 20_001
N_FULL = 200_001
BATCHES = 7
BLOCK_NAME = "output-cost"
# Issue 52's Shapiro-step client: one bias point on the n = 1 step (β, γ, ω, A, Ω, φ),
# 40,000 outputs over T = 4000, at the client tolerances (rtol, atol).
SHAPIRO = ((0.2, 0.3, 1.0, 2.0, 1.0, 0.0), (0.1, 0.0), 4000.0, 40_001)
SHAPIRO_TOLS = ((1e-3, 1e-6), (1e-6, 1e-9))
SHAPIRO_BLOCK = "output-cost-shapiro"


def _solve(model, y0, t_eval):
    return mbm.solve(model, (0.0, SPAN), y0, rtol=TOL, atol=TOL, t_eval=t_eval)


def output_costs(n=N_DEFAULT, batches=BATCHES):
    """The rows of the table: one dict per scene (``name``, ``regime``, ``t_regime``,
    ``windows``, ``ends`` and ``outputs`` (best seconds per call), ``per_output`` (s))."""
    rows = []
    dense, ends = np.linspace(0.0, SPAN, n), np.array([0.0, SPAN])
    for name, want, params, y0 in SCENES:
        model = mbm.Pendulum(*params)
        r = _solve(model, y0, dense)  # compile / cache load, not timed
        _solve(model, y0, ends)
        got = str(r.regime)
        if not (r.success and (got == want or (want == "none" and got == "None"))):
            raise RuntimeError(f"{name}: regime {got!r}, expected {want!r} (success {r.success})")
        best = {"ends": np.inf, "outputs": np.inf}
        with harness.gc_paused():
            for _ in range(batches):
                for key, te in (("ends", ends), ("outputs", dense)):
                    t0 = time.perf_counter()
                    _solve(model, y0, te)
                    best[key] = min(best[key], time.perf_counter() - t0)
        rows.append(dict(name=name, regime=got, t_regime=float(r.t_regime), windows=int(r.n_windows),
                         ends=best["ends"], outputs=best["outputs"],
                         per_output=(best["outputs"] - best["ends"]) / (n - 2)))
    return rows


def shapiro_costs(batches=BATCHES):
    """Issue 52's bias point (:data:`SHAPIRO`) by ``mbm.solve`` and ``solve_ivp(method=mbm.MBM)``:
    one dict per (front end, tolerance) with ``outputs`` and ``ends`` (best seconds per
    call with the outputs and with the span's ends alone) and the ``regime``."""
    from scipy.integrate import solve_ivp

    params, y0, span, n = SHAPIRO
    model = mbm.Pendulum(*params)
    dense, ends = np.linspace(0.0, span, n), np.array([0.0, span])
    rows = []
    for rtol, atol in SHAPIRO_TOLS:
        calls = {"mbm.solve": lambda te: mbm.solve(model, (0.0, span), y0, rtol=rtol, atol=atol, t_eval=te),
                 "solve_ivp": lambda te: solve_ivp(model, (0.0, span), y0, method=mbm.MBM, rtol=rtol, atol=atol,
                                                   t_eval=te)}
        for name, call in calls.items():
            regime = mbm.solve(model, (0.0, span), y0, rtol=rtol, atol=atol).regime
            call(dense)
            best = {"ends": np.inf, "outputs": np.inf}
            with harness.gc_paused():
                for _ in range(batches):
                    for key, te in (("ends", ends), ("outputs", dense)):
                        t0 = time.perf_counter()
                        call(te)
                        best[key] = min(best[key], time.perf_counter() - t0)
            rows.append(dict(front=name, rtol=rtol, atol=atol, regime=str(regime), **best))
    return rows


def format_output_costs(rows, n, batches, shapiro=()):
    """The Markdown page of :func:`output_costs`' rows (the table a named block)."""
    base = rows[0]["per_output"]
    table = ["| regime | scene (β, γ, ω, A, Ω, φ), y0 | t_regime | windows | run, 2 outputs (ms) "
             f"| run, {n:,} outputs (ms) | ns per output | × integrating |", "|---|---|---:|---:|---:|---:|---:|---:|"]
    for r, (_, _, params, y0) in zip(rows, SCENES):
        table.append(f"| {r['name']} | {params}, {y0} | {r['t_regime']:.4g} | {r['windows']} | "
                     f"{r['ends'] * 1e3:.3f} | {r['outputs'] * 1e3:.3f} | {r['per_output'] * 1e9:.1f} | "
                     f"{r['per_output'] / base:.1f} |")
    machine = harness.machine_info()
    lines = ["# The cost of an output time in each regime", "",
             "Generated by `python -m benchmarks.output_cost` (do not edit by hand); the method is in",
             f"that module's docstring.  T = {SPAN:g}, rtol = atol = {TOL:g}, {n:,} outputs, best of {batches} calls.",
             "The target (issue 52): at most 2× the integrating path's cost per output in the locked, running,",
             "libration and phase-locked regimes, 4× in the exact flow.", "",
             *block(BLOCK_NAME, table), ""]
    if shapiro:
        params, y0, span, n_s = SHAPIRO
        sh = ["| front end | rtol, atol | regime | run, 2 outputs (ms) | run, {:,} outputs (ms) |".format(n_s),
              "|---|---|---|---:|---:|"]
        for r in shapiro:
            sh.append(f"| {r['front']} | {r['rtol']:g}, {r['atol']:g} | {r['regime']} | {r['ends'] * 1e3:.3f} | "
                      f"{r['outputs'] * 1e3:.3f} |")
        lines += [f"Issue 52's Shapiro bias point: {params}, y0 = {y0}, T = {span:g}, {n_s:,} outputs.", "",
                  *block(SHAPIRO_BLOCK, sh), ""]
    lines += ["Machine: " + ", ".join(f"{k} {v}" for k, v in machine.items()) + "."]
    return "\n".join(lines) + "\n"


def main(argv=None):
    """Command line: ``python -m benchmarks.output_cost [--full] [--batches N] [--out FILE]``."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks.output_cost", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--full", action="store_true", help=f"{N_FULL:,} outputs (default {N_DEFAULT:,})")
    parser.add_argument("--batches", type=int, default=BATCHES, help="calls per figure (default %(default)s)")
    parser.add_argument("--out", default=None, help="write the Markdown page here (default: stdout)")
    args = parser.parse_args(argv)
    if args.batches < 1:
        parser.error("--batches must be >= 1")
    n = N_FULL if args.full else N_DEFAULT
    page = format_output_costs(output_costs(n, args.batches), n, args.batches, shapiro_costs(args.batches))
    if args.out:
        Path(args.out).write_text(page, encoding="utf-8")
        print(f"wrote {args.out}", file=sys.stderr)
    else:
        print(page)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
