r"""The fixed cost per call of mbm's compiled path (issue 12: ≤ 3 µs), in seconds of running.

Run from the root of a checkout::

    python -m benchmarks overheads [--repeats N] [--update docs/benchmark_overheads.md]

It times, on P1's model (β = 0.4, γ = 0, ω = 1; y0 = (0, 0.25); rtol = atol = 1e-4,
approximant "auto", the Taylor series), calls with one output time:

* ``Integrator.solve`` (prepared) and :func:`mbm.solve` (one-shot: its cache of
  Integrators, argument checks) on a zero-length span (no window: the fixed cost
  before the first window) and on a span of 1e-9 (one window);
* the compiled part alone: Integrator.solve's compiled entry (the loop's own,
  ``mbm.core.loop.entry_for``: the t_eval check, the record set-up, the loop) called from
  Python with its arguments ready (dispatch included), and called from a compiled loop
  (no dispatch);
* for scale, P1 whole (0 ≤ t ≤ 20) with its 201 outputs.

Each figure is the median (and the minimum) over ``repeats`` samples, a sample being
the mean of a block of calls in a Python loop; the samples of all calls are taken in
turns, so a slow spell of a shared machine lands on each alike.  The loop's own cost
per call (a no-op in the same loop) is reported, not subtracted.  The derived rows
(the Python side, the dispatch, mbm.solve's layer, the first window) are differences
of the minima.

``benchmarks.extras --overheads`` (the full overheads section of
docs/benchmark_overheads.md) includes this table; ``--update`` rewrites only its
block there.
"""

import argparse
import re
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import mbm
from mbm.frontends import solve as fast
from mbm.core import loop

from . import harness
from .report import block

__all__ = ["fixed_costs", "format_fixed_costs", "main"]

# The issue's measurement: P1's model and state, tolerances, spans and one output.
MODEL_PARAMS = (0.4, 0.0, 1.0)
Y0 = (0.0, 0.25)
RTOL = ATOL = 1e-4
TINY_SPAN = (0.0, 1e-9)  # one window
P1_SPAN = (0.0, 20.0)
N_OUTPUTS = 201
# Calls per sample (a sample is their mean: perf_counter's own cost is then nothing).
BLOCK = 200
# Calls per sample of the compiled loop.
COMPILED_BLOCK = 1_000
DEFAULT_REPEATS = 200
BLOCK_NAME = "overheads-per-call"


# The entry of mbm.solve's scene (undriven Taylor at its default degree, β > 0: the
# damped regime set).
_ENTRY_TAYLOR = loop.SIMD_RUNNERS[loop.RS_DAMPED]


# The entry n times from compiled code: its cost without the dispatch.
_entry_loop = harness.entry_calls(_ENTRY_TAYLOR)


def _samples(calls, repeats, block):
    """Per-call seconds of each of ``calls`` (name -> (callable, calls per sample)):
    ``repeats`` samples each, taken in turns with the garbage collector off."""
    times = {k: [] for k in calls}
    with harness.gc_paused():
        for _ in range(repeats):
            for k, (fn, per) in calls.items():
                n = block if per is None else 1
                t0 = time.perf_counter()
                for _ in range(n):
                    fn()
                dt = time.perf_counter() - t0
                times[k].append(dt / (n if per is None else per))
    return times


def fixed_costs(repeats=DEFAULT_REPEATS, block=BLOCK):
    """Seconds per call of the calls of the module docstring.

    Returns
    -------
    dict
        ``rows``: list of (name, median seconds, minimum seconds); ``derived``: list of
        (name, seconds), differences of the minima; ``setup``: the measurement's parameters.
    """
    model = mbm.Pendulum(*MODEL_PARAMS)
    ig = mbm.Integrator(model, rtol=RTOL, atol=ATOL)
    if ig._entry is not _ENTRY_TAYLOR:  # pragma: no cover - "auto" is Taylor here
        raise RuntimeError(f"expected the Taylor entry, got {ig._entry}")
    te1 = np.array([0.0])
    te_tiny = np.array([TINY_SPAN[1]])
    te_p1 = np.linspace(*P1_SPAN, N_OUTPUTS)
    opts = dict(rtol=RTOL, atol=ATOL)
    # The entry's arguments, ready (a buffer of the Integrator's pool: its template row).
    ig.solve((0.0, 0.0), Y0, te1)
    buf = ig._records[-1][0]
    out = np.empty((2, 1))
    h = ig._h
    entry = ig._entry
    empty = (fast._NO_T, fast._NO_Y, fast._NO_COEF, fast._NEVER)

    def compiled(t1, te):
        _entry_loop(1, buf, 0.0, Y0[0], Y0[1], t1, h, te, out, *empty)  # compiled before timing
        return (lambda: _entry_loop(COMPILED_BLOCK, buf, 0.0, Y0[0], Y0[1], t1, h, te, out, *empty),
                COMPILED_BLOCK)

    calls = {
        "Integrator.solve, zero-length span (no window)": (lambda: ig.solve((0.0, 0.0), Y0, te1), None),
        "Integrator.solve, span 1e-9 (one window)": (lambda: ig.solve(TINY_SPAN, Y0, te_tiny), None),
        "mbm.solve, zero-length span (no window)":
            (lambda: mbm.solve(model, (0.0, 0.0), Y0, t_eval=te1, **opts), None),
        "mbm.solve, span 1e-9 (one window)":
            (lambda: mbm.solve(model, TINY_SPAN, Y0, t_eval=te_tiny, **opts), None),
        "compiled entry from Python, zero-length span":
            (lambda: entry(buf, True, (0.0, Y0[0], Y0[1], 0.0, h), (te1, out, *empty)), None),
        "compiled entry from Python, span 1e-9":
            (lambda: entry(buf, True, (0.0, Y0[0], Y0[1], TINY_SPAN[1], h), (te_tiny, out, *empty)), None),
        "compiled entry in a compiled loop, zero-length span": compiled(0.0, te1),
        "compiled entry in a compiled loop, span 1e-9": compiled(TINY_SPAN[1], te_tiny),
        f"Integrator.solve, P1 (t ≤ 20) with {N_OUTPUTS} outputs":
            (lambda: ig.solve(P1_SPAN, Y0, te_p1), None),
        "the timing loop itself (a no-op call)": (lambda: None, None),
    }
    for fn, _ in calls.values():  # warm: compiled, cached Integrator built
        fn()
    times = _samples(calls, repeats, block)
    rows = [(k, statistics.median(v), min(v)) for k, v in times.items()]
    # Differences of the minima: on a shared machine the least disturbed sample is the
    # better estimate of a call's own cost (the medians carry the other loads).
    lo = {k: m for k, _, m in rows}
    derived = [
        ("Integrator.solve's Python side (zero-length span − entry from Python)",
         lo["Integrator.solve, zero-length span (no window)"]
         - lo["compiled entry from Python, zero-length span"]),
        ("the entry's dispatch (from Python − in a compiled loop, zero-length span)",
         lo["compiled entry from Python, zero-length span"]
         - lo["compiled entry in a compiled loop, zero-length span"]),
        ("mbm.solve's layer (mbm.solve − Integrator.solve, zero-length span)",
         lo["mbm.solve, zero-length span (no window)"]
         - lo["Integrator.solve, zero-length span (no window)"]),
        ("the first window (span 1e-9 − zero-length span, compiled loop)",
         lo["compiled entry in a compiled loop, span 1e-9"]
         - lo["compiled entry in a compiled loop, zero-length span"]),
    ]
    setup = dict(model=f"Pendulum{MODEL_PARAMS}", y0=Y0, rtol=RTOL, atol=ATOL,
                 approximant=ig.approximant.name, repeats=repeats, block=block)
    return {"rows": rows, "derived": derived, "setup": setup}


def format_fixed_costs(fc):
    """Markdown section of :func:`fixed_costs` (its table a named block)."""
    s = fc["setup"]
    lines = ["## Fixed cost per call (`python -m benchmarks overheads`)", "",
             f"{s['model']}, y0 = {s['y0']}, rtol = atol = {s['rtol']:g}, approximant "
             f"{s['approximant']!r}, one output time; per call, the median and minimum of "
             f"{s['repeats']} samples (each the mean of a block of calls, all calls in turns).", ""]
    table = ["| call | median µs | min µs |", "|---|---:|---:|"]
    table += [f"| {k} | {m * 1e6:.2f} | {lo * 1e6:.2f} |" for k, m, lo in fc["rows"]]
    table += [f"| derived (from the minima): {k} | | {v * 1e6:.2f} |" for k, v in fc["derived"]]
    lines += block(BLOCK_NAME, table)
    return "\n".join(lines) + "\n"


def update_file(path, section):
    """Replace the ``overheads-per-call`` block of ``path`` by ``section``'s (or append
    ``section`` when the file has none)."""
    path = Path(path)
    text = path.read_text(encoding="utf-8") if path.exists() else ""
    pattern = re.compile(rf"<!-- block {BLOCK_NAME} -->\n.*?<!-- /block -->", re.S)
    new_block = pattern.search(section).group(0)
    if pattern.search(text):
        text = pattern.sub(lambda _: new_block, text, count=1)
    else:
        text = text.rstrip("\n") + ("\n\n" if text else "") + section
    path.write_text(text, encoding="utf-8")


def main(argv=None):
    """Command line: ``python -m benchmarks overheads [--repeats N] [--update FILE]``."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks overheads", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=DEFAULT_REPEATS,
                        help="samples per call (default %(default)s)")
    parser.add_argument("--update", default=None, metavar="FILE",
                        help="also rewrite this file's overheads-per-call block (e.g. "
                             "docs/benchmark_overheads.md)")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error("--repeats must be >= 1")
    fc = fixed_costs(repeats=args.repeats)
    section = format_fixed_costs(fc)
    machine = harness.machine_info()
    print("\n".join(f"- {k}: {v}" for k, v in machine.items()) + "\n")
    print(section)
    if args.update:
        update_file(args.update, section)
        print(f"updated {args.update}", file=sys.stderr)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
