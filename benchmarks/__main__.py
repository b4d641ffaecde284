"""``python -m benchmarks``: the work-precision benchmark, its extras, the README's quotes.

From the root of a checkout::

    python -m benchmarks [--quick] [--out docs/benchmark.md] ...   # the tables
    python -m benchmarks extras [--overheads] [--out FILE] ...     # benchmarks.extras
    python -m benchmarks overheads [--update FILE] ...              # benchmarks.overheads
    python -m benchmarks readme [--check]                          # README, docs/benchmarks.md quotes <- docs/
"""

import argparse
import json
import os
import shlex
import sys
from pathlib import Path

from . import extras, harness, overheads, references, report
from .scenes import SCENES

__all__ = ["main", "tables_main", "readme_main"]

# The checkout's root; the files whose quotes `python -m benchmarks readme` refreshes
# (quoted paths are relative to the root): the README and the site's benchmarks page.
ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
QUOTING = (README, ROOT / "docs" / "benchmarks.md")
# How results recorded before the move out of the package name their command.
_OLD_COMMAND = "python -m mbm.bench"


def tables_main(argv=None):
    """``python -m benchmarks``: run the benchmark and write the Markdown report.

    Parameters
    ----------
    argv : list of str or None
        Command-line arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status.
    """
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks",
        description="Work-precision benchmark of MBM against scipy, SUNDIALS and compiled peers "
                    "(numba, numbalsoda, heyoka).  Subcommands: `extras` (python -m benchmarks "
                    "extras --help), `readme` (copy the blocks the README quotes from docs/).",
    )
    parser.add_argument("--scenes", default=",".join(SCENES),
                        help="comma-separated scene names (default all: %(default)s)")
    parser.add_argument("--repeats", type=int, default=None,
                        help=f"timed runs per point (default {harness.DEFAULT_REPEATS}, "
                             f"--quick {harness.QUICK_REPEATS})")
    parser.add_argument("--quick", action="store_true",
                        help="three knob values per solver, 3 repeats (a smoke run, not a benchmark)")
    parser.add_argument("--out", default=None, help="write the Markdown report here (default: stdout)")
    parser.add_argument("--plot", default=None, metavar="DIR",
                        help="write error-vs-time PNGs per scene here (needs matplotlib)")
    parser.add_argument("--json", default=None, metavar="PATH", help="write all sweep points as JSON")
    parser.add_argument("--solvers", default=None,
                        help="comma-separated substrings: keep solvers whose name contains one")
    parser.add_argument("--max-seconds", type=float, default=harness.MAX_POINT_SECONDS,
                        help="stop a sweep after a point whose single run exceeds this "
                             "(default %(default)s)")
    parser.add_argument("--reference", default="auto", choices=references.REFERENCE_METHODS,
                        help="reference where beta or gamma is non-zero (default auto: 128-bit "
                             "fixed point with mpmath, else heyoka in long double, else CVODE)")
    parser.add_argument("--cache", default=None, metavar="DIR",
                        help=f"reference cache directory (default {references.default_cache_dir()})")
    parser.add_argument("--no-cache", action="store_true", help="recompute references, store nothing")
    parser.add_argument("--cold-compile", action="store_true",
                        help="also time MBM's JIT compile from an empty numba cache (subprocess)")
    parser.add_argument("--from-json", default=None, metavar="PATH",
                        help="render the report (and plots) from a saved --json file; run nothing")
    parser.add_argument("--note", default=None, help="a line to put under the report's title")
    args = parser.parse_args(argv)
    repeats = args.repeats if args.repeats is not None else (
        harness.QUICK_REPEATS if args.quick else harness.DEFAULT_REPEATS)
    if repeats < 1:
        parser.error("--repeats must be >= 1")
    if not args.max_seconds > 0:
        parser.error("--max-seconds must be > 0")
    scenes = [s.strip() for s in args.scenes.split(",") if s.strip()]
    unknown = [s for s in scenes if s not in SCENES]
    if unknown or not scenes:
        parser.error(f"unknown scene(s) {unknown}; choose from {','.join(SCENES)}")
    cache = False if args.no_cache else (args.cache or None)
    solver_filter = [s.strip() for s in args.solvers.split(",")] if args.solvers else None
    if args.from_json:
        result = json.loads(Path(args.from_json).read_text())
        command = result.get("command")
        if command and command.startswith(_OLD_COMMAND):
            # Results recorded when the benchmark lived in the package (same options).
            command = "python -m benchmarks" + command[len(_OLD_COMMAND):]
    else:
        result = harness.run_benchmark(scenes=scenes, repeats=repeats, quick=args.quick,
                                       max_seconds=args.max_seconds, solver_filter=solver_filter,
                                       cache_dir=cache, cold_compile=args.cold_compile,
                                       log=sys.stderr, reference=args.reference)
        command = "python -m benchmarks " + " ".join(
            shlex.quote(a) for a in (argv if argv is not None else sys.argv[1:]))
        result["command"] = command.strip()
    text = report.format_report(result, command=command, note=args.note)
    if args.plot:
        files = report.write_plots(result, args.plot)
        if files:
            text += "\n## Plots\n\n" + "\n".join(
                f"![{Path(f).stem}]({os.path.relpath(f, Path(args.out).parent) if args.out else f})"
                for f in files) + "\n"
        else:
            text += "\n(matplotlib is not importable: no plots.)\n"
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(text)
        print(f"wrote {args.out}", file=sys.stderr)
    else:
        print(text)
    if args.json:
        Path(args.json).write_text(json.dumps(result, default=report.json_default, indent=1))
    return 0


def readme_main(argv=None):
    """``python -m benchmarks readme``: copy the quoted blocks from ``docs/`` into the
    README and the site's benchmarks page (:data:`QUOTING`).

    With ``--check``, change nothing and exit 1 if a quote differs from its block.
    """
    parser = argparse.ArgumentParser(prog="python -m benchmarks readme",
                                     description="Refresh the quotes of generated files in the README "
                                                 "and docs/benchmarks.md.")
    parser.add_argument("--readme", action="append", default=None,
                        help="a file to refresh (repeatable; default the README and "
                             "docs/benchmarks.md, quoted paths relative to the checkout's root)")
    parser.add_argument("--root", default=None,
                        help="what quoted paths are relative to (default: the checkout's root for "
                             "the default files, else each file's directory)")
    parser.add_argument("--check", action="store_true",
                        help="report quotes that differ from their blocks; change nothing")
    args = parser.parse_args(argv)
    files = [Path(f) for f in args.readme] if args.readme else list(QUOTING)

    def root_of(f):
        return Path(args.root) if args.root else (f.parent if args.readme else ROOT)

    if args.check:
        stale = []
        for f in files:
            for path, name, body in report.readme_quotes(f.read_text(encoding="utf-8")):
                blocks = report.extract_blocks((root_of(f) / path).read_text(encoding="utf-8"))
                if blocks.get(name) != body:
                    stale.append(f"{f.name}: {path} {name}")
        for s in stale:
            print(f"stale quote: {s}", file=sys.stderr)
        return 1 if stale else 0
    for f in files:
        for s in report.sync_readme(f, root=root_of(f)):
            print(f"updated quote in {f.name}: {s}", file=sys.stderr)
    return 0


def main(argv=None):
    """Dispatch: ``extras ...`` to :func:`benchmarks.extras.main`, ``overheads ...`` to
    :func:`benchmarks.overheads.main`, ``readme ...`` to :func:`readme_main`, anything
    else to :func:`tables_main`."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "extras":
        return extras.main(argv[1:])
    if argv and argv[0] == "overheads":
        return overheads.main(argv[1:])
    if argv and argv[0] == "readme":
        return readme_main(argv[1:])
    return tables_main(argv)


if __name__ == "__main__":
    sys.exit(main())
