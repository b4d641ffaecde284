"""The per-window cost of watching for regimes on short scenes (issue 27: ≤ 10 % of a window).

Run from the root of a checkout::

    python -m benchmarks.watch_cost [--repeats N] [--out docs/watch_cost.md]

A damped undriven run (RS_DAMPED) tests the locked regime before each window and
watches the return map after it (:mod:`mbm.regimes`); a run without regimes (RS_PLAIN)
takes the same windows without either.  For P1–P3 (:mod:`benchmarks.scenes`) at each
tolerance, both compiled entries of the Taylor kind at its default degree
(``mbm.core.loop.SIMD_RUNNERS``) run the scene's windows before its switch to a regime:
the span is cut at ``t_regime`` of ``mbm.solve`` (the whole span where the scene never
switches), so both runs take the same windows; the script checks that they do (window count and end state bit for bit)
and refuses to report otherwise.  The entries are called from a compiled loop (no
dispatch), with no output times (the windows alone), from the Integrator's template
record (its first window, tolerances and degree, mbm.solve's).

Each figure is the median of ``repeats`` samples, a sample the mean of a block of
calls; the two entries' samples are taken in turns (a slow spell of the shared machine
lands on both alike).  The watch's share is (watched − plain) / plain: the cost the
regimes add to each window before the switch (their per-call set-up included), as a
fraction of a window without them.
"""

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import mbm
from mbm.frontends import solve as fast
from mbm.core import loop
from mbm import status
from mbm.core.record import WORD

from . import harness
from .report import block
from .scenes import SCENES

__all__ = ["watch_costs", "format_watch_costs", "main"]

SCENE_NAMES = ("P1", "P2", "P3")
TOLERANCES = (1e-6, 1e-9)
# Samples per row (median), and calls per sample (their mean).
DEFAULT_REPEATS = 101
BLOCK = 200
# The target: the watch's share of a window.
TARGET_SHARE = 0.10
BLOCK_NAME = "watch-cost"

_WATCHED = loop.SIMD_RUNNERS[loop.RS_DAMPED]
_PLAIN = loop.SIMD_RUNNERS[loop.RS_PLAIN]
# The entries' empty arguments, as Integrator.solve passes them: no outputs, no window
# store, never cancelled.
_EMPTY = (fast._NO_T, fast._NO_OUT, fast._NO_T, fast._NO_Y, fast._NO_COEF, fast._NEVER)


# Each entry n times from a compiled loop (a fresh run from buf's template each time).
_calls_watched, _calls_plain = harness.entry_calls(_WATCHED), harness.entry_calls(_PLAIN)


def _buffers(scene, tol):
    """Two (2, words) buffers (row 0 the template: regimes on, off), the first window's
    h_abs and the span's cut (``t_regime`` of mbm.solve, or the span's end)."""
    model, (t0, t1) = scene.model, scene.t_span
    ig = mbm.Integrator(model, rtol=tol, atol=tol)
    if ig._entry is not _WATCHED:  # pragma: no cover - P1-P3 are damped Taylor runs, default degree
        raise RuntimeError(f"{scene.name}: not a damped Taylor run")
    r = mbm.solve(model, (t0, t1), scene.y0, rtol=tol, atol=tol)
    cut = r.t_regime if math.isfinite(r.t_regime) else t1
    watched = np.empty((2, ig._words.size))
    watched[0] = ig._words
    plain = watched.copy()
    plain[0].view(np.int64)[WORD["regimes"]] = 0
    return watched, plain, ig._h, cut


def _same_windows(scene, watched, plain, h, cut):
    """Windows of one call of each entry; raises unless both took the same windows."""
    th0, v0 = scene.y0
    n_w = _calls_watched(1, watched, 0.0, th0, v0, cut, h, *_EMPTY)
    n_p = _calls_plain(1, plain, 0.0, th0, v0, cut, h, *_EMPTY)
    ends = [(b[1].view(np.int64)[WORD["status"]], b[1].view(np.int64)[WORD["regime"]], b[1][WORD["t"]],
             b[1][WORD["theta"]], b[1][WORD["v"]]) for b in (watched, plain)]
    if n_w != n_p or ends[0] != ends[1] or ends[0][0] != status.STATUS_OK:
        raise RuntimeError(f"{scene.name}: the entries took different windows ({n_w}: {ends[0]}; "
                           f"{n_p}: {ends[1]})")
    return n_w


def watch_costs(scene_names=SCENE_NAMES, tolerances=TOLERANCES, repeats=DEFAULT_REPEATS, block_size=BLOCK):
    """The rows of the table: one dict per (scene, tolerance).

    Returns
    -------
    list of dict
        ``scene``, ``tol``, ``cut`` (the span's end used), ``windows``, ``plain`` and
        ``watched`` (median seconds per call), ``per_window`` (the watch's seconds per
        window) and ``share`` ((watched − plain) / plain).
    """
    rows = []
    for name in scene_names:
        scene = SCENES[name]
        for tol in tolerances:
            watched, plain, h, cut = _buffers(scene, tol)
            n = _same_windows(scene, watched, plain, h, cut)
            th0, v0 = scene.y0
            times = {"watched": [], "plain": []}
            with harness.gc_paused():
                for _ in range(repeats):
                    for key, fn, buf in (("watched", _calls_watched, watched), ("plain", _calls_plain, plain)):
                        t_start = time.perf_counter()
                        fn(block_size, buf, 0.0, th0, v0, cut, h, *_EMPTY)
                        times[key].append((time.perf_counter() - t_start) / block_size)
            w, p = statistics.median(times["watched"]), statistics.median(times["plain"])
            rows.append(dict(scene=name, tol=tol, cut=cut, windows=n, plain=p, watched=w,
                             per_window=(w - p) / n, share=(w - p) / p))
    return rows


def format_watch_costs(rows, repeats, block_size):
    """The Markdown page of :func:`watch_costs`' rows (the table a named block)."""
    table = ["| scene | rtol = atol | span | windows | no regimes (µs) | watching (µs) | watch per window (ns) "
             "| watch's share of a window |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        table.append(f"| {r['scene']} | {r['tol']:g} | [0, {r['cut']:.4g}] | {r['windows']} | "
                     f"{r['plain'] * 1e6:.2f} | {r['watched'] * 1e6:.2f} | {r['per_window'] * 1e9:.1f} | "
                     f"{100 * r['share']:.1f} % |")
    machine = harness.machine_info()
    lines = ["# The cost of watching for regimes on short scenes", "",
             "Generated by `python -m benchmarks.watch_cost` (do not edit by hand); the method is in",
             "that module's docstring.  Each figure is the median of "
             f"{repeats} samples of {block_size} calls; the target",
             f"(issue 27) is a share of at most {100 * TARGET_SHARE:.0f} %.", "",
             *block(BLOCK_NAME, table), "",
             "Machine: " + ", ".join(f"{k} {v}" for k, v in machine.items()) + "."]
    return "\n".join(lines) + "\n"


def main(argv=None):
    """Command line: ``python -m benchmarks.watch_cost [--repeats N] [--out FILE]``."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks.watch_cost", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=DEFAULT_REPEATS, help="samples per row (default %(default)s)")
    parser.add_argument("--block", type=int, default=BLOCK, help="calls per sample (default %(default)s)")
    parser.add_argument("--out", default=None, help="write the Markdown page here (default: stdout)")
    args = parser.parse_args(argv)
    if args.repeats < 1 or args.block < 1:
        parser.error("--repeats and --block must be >= 1")
    page = format_watch_costs(watch_costs(repeats=args.repeats, block_size=args.block), args.repeats, args.block)
    if args.out:
        Path(args.out).write_text(page, encoding="utf-8")
        print(f"wrote {args.out}", file=sys.stderr)
    else:
        print(page)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
