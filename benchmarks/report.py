"""The benchmark's report: Markdown tables, JSON, plots, and the blocks the README quotes.

Generated Markdown marks the parts the README shows as named blocks::

    <!-- block NAME -->
    ...
    <!-- /block -->

and the README quotes them verbatim between::

    <!-- quote docs/benchmark.md NAME -->
    ...
    <!-- /quote -->

:func:`sync_readme` copies every quoted block from its file into the README
(``python -m benchmarks readme``); ``tests/docs_and_examples/test_readme.py`` checks that the two
agree.  So a rerun changes ``docs/`` and, through one command, the README; no figure
of the README is typed by hand.
"""

import re
from pathlib import Path

import numpy as np

from .harness import cheapest_at_target
from .references import REF_MARGIN, reference_uncertainty
from .registry import KNOB_LABELS
from .scenes import SCENES

__all__ = [
    "write_page",
    "format_report",
    "readme_blocks",
    "write_plots",
    "json_default",
    "block",
    "extract_blocks",
    "readme_quotes",
    "sync_readme",
]

# The rows of the README's first summary table (solve_ivp against Python-RHS peers),
# label in the README -> row of the report.  Absent rows are left out.
README_PYTHON_ROWS = {
    "scipy DOP853": "scipy DOP853",
    "scipy LSODA": "scipy LSODA",
    "CVODE Adams": "CVODE Adams",
    "MBM auto, solve_ivp": "MBM auto (rtol, windows_per_step=None)",
    "MBM auto, solve_ivp, default windows_per_step": "MBM auto (rtol)",
}
# Its target error.
README_PYTHON_TARGET = 1e-6
# Rows of the README's second summary table (compiled solvers); None: the fastest
# mbm.solve row of each cell.
README_COMPILED_ROWS = {
    "numba RK4 (fixed step, written in the benchmark)": "numba RK4",
    "numba DOP853 (written in the benchmark)": "numba DOP853",
    "numbalsoda DOP853": "numbalsoda DOP853",
    "heyoka (prepared integrator)": "heyoka",
    "mbm.solve (best of its rows)": None,
}
# Its target errors.
README_COMPILED_TARGETS = (1e-6, 1e-9)

_BLOCK_RE = re.compile(r"<!-- block (?P<name>[\w.-]+) -->\n(?P<body>.*?)<!-- /block -->", re.S)
_QUOTE_RE = re.compile(
    r"(?P<head><!-- quote (?P<path>\S+) (?P<name>[\w.-]+) -->\n)(?P<body>.*?)(?P<tail><!-- /quote -->)",
    re.S)


# ---------------------------------------------------------------------------
# Blocks and quotes
# ---------------------------------------------------------------------------


def block(name, lines):
    """``lines`` (a list of str) wrapped as the named block, as a list of lines."""
    return [f"<!-- block {name} -->", *lines, "<!-- /block -->"]


def write_page(lines, out=None):
    """Print a generated page (``lines`` joined) and write it to ``out`` where given."""
    text = "\n".join(lines) + "\n"
    print(text)
    if out:
        with open(out, "w", encoding="utf-8") as f:
            f.write(text)
    return text


def extract_blocks(text):
    """The named blocks of a generated file: name -> body (ends with a newline)."""
    return {m["name"]: m["body"] for m in _BLOCK_RE.finditer(text)}


def readme_quotes(text):
    """The quotes of a README: list of (path, name, body)."""
    return [(m["path"], m["name"], m["body"]) for m in _QUOTE_RE.finditer(text)]


def sync_readme(readme, root=None):
    """Copy every block the README quotes from its generated file into the README.

    Parameters
    ----------
    readme : path-like
        The README; quoted paths are relative to ``root`` (default its directory).
    root : path-like, optional

    Returns
    -------
    list of str
        ``"path name"`` of every quote whose text changed (the file is rewritten
        only then).

    Raises
    ------
    KeyError
        If a quoted file has no block of that name.
    """
    readme = Path(readme)
    root = Path(root) if root is not None else readme.parent
    text = readme.read_text(encoding="utf-8")
    cache = {}
    changed = []

    def replace(m):
        path, name = m["path"], m["name"]
        if path not in cache:
            cache[path] = extract_blocks((root / path).read_text(encoding="utf-8"))
        if name not in cache[path]:
            raise KeyError(f"{path} has no block {name!r} (README quotes it)")
        body = cache[path][name]
        if body != m["body"]:
            changed.append(f"{path} {name}")
        return m["head"] + body + m["tail"]

    new = _QUOTE_RE.sub(replace, text)
    if new != text:
        readme.write_text(new, encoding="utf-8")
    return changed


# ---------------------------------------------------------------------------
# Tables
# ---------------------------------------------------------------------------


def _fmt_ms(seconds):
    ms = seconds * 1e3
    if ms >= 100:
        return f"{ms:.0f}"
    if ms >= 10:
        return f"{ms:.1f}"
    if ms >= 1:
        return f"{ms:.2f}"
    return f"{ms:.3f}"


def _fmt_ratio(r):
    return f"{r:.2g}×" if r < 10 else f"{r:.0f}×"


def _cell(points, target, ref_time):
    best = cheapest_at_target(points, target)
    if best is None:
        if any(p["status"] == "over budget" for p in points):
            return "> budget"
        return "—"
    text = _fmt_ms(best["time"])
    if ref_time is not None:
        text += f" ({_fmt_ratio(best['time'] / ref_time)})"
    return text


def _best(points_by_solver, names, target):
    """(seconds, name) of the cheapest of ``names`` at ``target``, or None."""
    best = None
    for n in names:
        p = cheapest_at_target(points_by_solver.get(n, []), target)
        if p is not None and (best is None or p["time"] < best[0]):
            best = (p["time"], n)
    return best


def _best_time(points_by_solver, names, target):
    best = _best(points_by_solver, names, target)
    return None if best is None else best[0]


def _missing(result):
    """Optional peers not in the result: name -> reason."""
    missing = dict(result.get("missing") or {})
    if "heyoka" not in result["solvers"] and "heyoka" not in missing:
        missing["heyoka"] = "not in this run (the result was recorded before heyoka was a peer)"
    return missing


def _target_table(result, target, names, ratio_family, missing=None):
    scenes = result["scenes"]
    fam = [n for n, s in result["solvers"].items() if s["family"] == ratio_family]
    header = "| solver | " + " | ".join(scenes) + " |"
    lines = [header, "|---|" + "---:|" * len(scenes)]
    ref_times = {sc: _best_time(result["points"][sc], fam, target) for sc in scenes}
    for n in names:
        cells = [_cell(result["points"][sc][n], target, ref_times[sc]) for sc in scenes]
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    for n in (missing or {}):
        lines.append(f"| {n} | " + " | ".join("n/a" for _ in scenes) + " |")
    flags = []
    for sc in scenes:
        unc = reference_uncertainty(result["references"][sc])
        if target < REF_MARGIN * unc:
            flags.append(f"{sc} (reference discrepancy {unc:.1e})")
    return lines, flags


def _summary_table(result, rows, targets, bold="fastest"):
    """README-style table: plain ms, the fastest entry of each cell in bold."""
    scenes = result["scenes"]
    solve_names = [n for n, s in result["solvers"].items() if s["family"] == "mbm-compiled"]
    missing = _missing(result)
    many = len(targets) > 1
    head = "| solver | " + ("target | " if many else "") + " | ".join(scenes) + " |"
    lines = [head, "|---|" + ("---|" if many else "") + "---:|" * len(scenes)]
    for target in targets:
        table = []
        for label, name in rows.items():
            if name is not None and name not in result["solvers"]:
                if name in missing:
                    table.append((label, [None] * len(scenes), True))
                continue
            cells = []
            for sc in scenes:
                pts = result["points"][sc]
                best = (_best(pts, solve_names, target) if name is None
                        else _best(pts, [name], target))
                cells.append(None if best is None else best[0])
            table.append((label, cells, False))
        fastest = [min((c[i] for _, c, _m in table if c[i] is not None), default=None)
                   for i in range(len(scenes))]
        for label, cells, is_missing in table:
            texts = []
            for i, c in enumerate(cells):
                if is_missing:
                    texts.append("n/a")
                elif c is None:
                    texts.append("—")
                elif bold == "fastest" and c == fastest[i]:
                    texts.append(f"**{_fmt_ms(c)}**")
                else:
                    texts.append(_fmt_ms(c))
            row_label = label
            if bold == "row" and rows.get(label) == README_PYTHON_ROWS.get("MBM auto, solve_ivp"):
                row_label = f"**{label}**"
                texts = [f"**{t}**" if t not in ("—", "n/a") else t for t in texts]
            tgt = f"{target:.0e}".replace("e-0", "e-") + " | " if many else ""
            lines.append(f"| {row_label} | {tgt}" + " | ".join(texts) + " |")
    return lines


def _versus(result, target, ours, theirs, scenes):
    """Per scene: (ours seconds, theirs seconds, their fastest name), None where missing."""
    out = {}
    for sc in scenes:
        a = _best(result["points"][sc], ours, target)
        b = _best(result["points"][sc], theirs, target)
        out[sc] = (a, b)
    return out


def _verdict(pairs, ours_label):
    """``ours_label``: where it is faster (by how much) and where not (and who is)."""
    wins, losses, only_ours, only_theirs = [], [], [], []
    for sc, (a, b) in pairs.items():
        if a is None and b is None:
            continue
        if b is None:
            only_ours.append(sc)
        elif a is None:
            only_theirs.append(f"{sc} ({b[1]})")
        elif a[0] <= b[0]:
            wins.append(f"{sc} {_fmt_ratio(b[0] / a[0])}")
        else:
            losses.append(f"{sc} ({b[1]} {_fmt_ratio(a[0] / b[0])} faster)")
    parts = []
    if wins:
        parts.append("faster on " + ", ".join(wins))
    if only_ours:
        parts.append("the only one to reach the target on " + ", ".join(only_ours))
    if losses:
        parts.append("slower on " + ", ".join(losses))
    if only_theirs:
        parts.append("does not reach it on " + ", ".join(only_theirs))
    return f"{ours_label}: " + ("; ".join(parts) if parts else "no solver reached the target")


def findings(result):
    """Generated sentences: where MBM wins and loses at each target, with ratios.

    Ratios are the other solver's time over MBM's (> 1: MBM faster) for a win, and
    MBM's over the other's for a loss, between the cheapest measured points at or
    below the target (as in the tables).

    Returns
    -------
    list of str
        Markdown list items.
    """
    solvers = result["solvers"]
    scenes = result["scenes"]
    py_peers = [n for n, s in solvers.items() if s["family"] == "peer" and not s["compiled"]]
    c_peers = [n for n, s in solvers.items() if s["family"] == "peer" and s["compiled"]]
    ivp = [n for n, s in solvers.items() if s["family"] == "mbm"]
    fast = [n for n, s in solvers.items() if s["family"] == "mbm-compiled"]
    lines = []
    for target in result["settings"]["targets"]:
        t = f"{target:.0e}".replace("e-0", "e-")
        items = []
        if py_peers and ivp:
            items.append(_verdict(_versus(result, target, ivp, py_peers, scenes),
                                  "`solve_ivp(method=mbm.MBM)` (best of its rows) against the "
                                  "fastest of scipy and CVODE"))
        if c_peers and fast:
            items.append(_verdict(_versus(result, target, fast, c_peers, scenes),
                                  "`mbm.solve` (best of its rows) against the fastest compiled peer"))
        lines.append(f"- At {t}: " + ". ".join(items) + ".")
    return lines


def readme_blocks(result):
    """The blocks of ``docs/benchmark.md`` that the README quotes.

    Returns
    -------
    list of str
        Lines: blocks ``machine``, ``summary-python-rhs``, ``summary-compiled``,
        ``findings`` and (with a cold-compile measurement) ``first-calls``.
    """
    st, mi = result["settings"], result["machine"]
    out = []
    versions = ", ".join(f"{k} {mi.get(k, 'not recorded')}"
                         for k in ("numpy", "scipy", "numba", "scikit-sundae", "numbalsoda", "heyoka"))
    out += block("machine", [
        f"Machine: {mi['cpu']}, {mi['logical cores']} logical cores, {mi['platform']}, "
        f"Python {mi['python']}, {versions}; run {st['date']}"
        + ("; **quick run** (3 knob values per solver): not a benchmark" if st["quick"] else "")
        + "."])
    out.append("")
    t_py = f"{README_PYTHON_TARGET:.0e}".replace("e-0", "e-")
    out += block("summary-python-rhs", [
        "Python-RHS peers against `solve_ivp(method=mbm.MBM, windows_per_step=None)`, "
        f"target {t_py}, ms:", "",
        *_summary_table(result, README_PYTHON_ROWS, (README_PYTHON_TARGET,), bold="row")])
    out.append("")
    out += block("summary-compiled", [
        "Compiled peers against the compiled whole-run solver `mbm.solve`, ms (fastest in "
        "bold; n/a: not installed or not run):", "",
        *_summary_table(result, README_COMPILED_ROWS, README_COMPILED_TARGETS)])
    out.append("")
    out += block("findings", findings(result))
    cold = result.get("cold_compile")
    if cold:
        out.append("")
        out += block("first-calls", [
            "First calls, in a fresh process with an empty numba cache (once per installation; "
            "afterwards the cache loads in well under a second): "
            + ", ".join(f"{k} {v:.2f} s" for k, v in cold.items()) + "."])
    return out


def format_report(result, command=None, note=None):
    """The Markdown report: settings, machine, references, one table per target.

    Parameters
    ----------
    result : dict
        From :func:`benchmarks.harness.run_benchmark`.
    command : str or None
        The command line that produced it (shown so that it can be rerun).
    note : str or None
        A line put under the title (e.g. "development run on a loaded machine").

    Returns
    -------
    str
    """
    st, mi = result["settings"], result["machine"]
    missing = _missing(result)
    out = ["# Work-precision benchmark", ""]
    if note:
        out += [f"> {note}", ""]
    out.append("Generated by `benchmarks/` (run from a checkout); regenerate with")
    out.append("")
    out.append("```bash")
    out.append(command or "python -m benchmarks --out docs/benchmark.md")
    out.append("```")
    out.append("")
    out.append(
        f"Error = max |θ − θ_ref| over {st['n_output']} equally spaced times.  Time = median of "
        f"{st['repeats']} runs (after one warm-up run) of the whole solver call on inputs built once "
        "per scene (model, y0, the 201 output times): solver set-up, integration, output at the 201 "
        "times; heyoka's integrator is built once per tolerance and reused (its build time is "
        "reported apart with the first calls).  Each cell: the cheapest *measured* point whose "
        "error is at or below the target (nothing interpolated), in ms, and in parentheses its time "
        "divided by the best MBM entry's at that target (> 1: slower than MBM).  "
        "`—`: the sweep never reached the target; `> budget`: the sweep stopped at a point whose "
        f"single run took more than {st['max_seconds']:g} s before reaching it; `n/a`: not "
        "installed or not run (see Notes)."
        + ("  **Quick run** (3 knob values per solver): not a benchmark." if st["quick"] else "")
    )
    out.append("")
    out.append("## Machine")
    out.append("")
    out.append(f"- CPU: {mi['cpu']}, {mi['logical cores']} logical cores "
               f"({mi['usable cores']} usable by this process)")
    out.append(f"- {mi['platform']}, Python {mi['python']}")
    out.append("- " + ", ".join(f"{k} {mi.get(k, 'not recorded')}"
                                for k in ("numpy", "scipy", "numba", "scikit-sundae", "mbm",
                                          "numbalsoda", "heyoka")))
    out.append(f"- run {st['date']}")
    out.append("")
    out.append("## Summary (quoted by the README)")
    out.append("")
    out += readme_blocks(result)
    out.append("")
    out.append("## Scenes and references")
    out.append("")
    out.append("Max difference: max |θ_ref − θ_check| over the 201 times; with an exact, "
               "fixed-point or heyoka reference it is the check's own error.")
    out.append("")
    out.append("| scene | problem | reference | independent check | max difference |")
    out.append("|---|---|---|---|---:|")
    for sc in result["scenes"]:
        r = result["references"][sc]
        title = SCENES[sc].title if sc in SCENES else sc
        out.append(f"| {sc} | {title} | {r['method']} | {r['check_method']} | "
                   f"{r['check']:.1e} |")
    out.append("")
    names = list(result["solvers"])
    compiled_names = [n for n, s in result["solvers"].items() if s["compiled"]]
    have_compiled_mbm = any(s["family"] == "mbm-compiled" for s in result["solvers"].values())
    for target in st["targets"]:
        out.append(f"## Target error {target:.0e}")
        out.append("")
        out.append("Times in ms; ratio to the best `MBM` (solve_ivp) entry.")
        out.append("")
        lines, flags = _target_table(result, target, names, "mbm", missing)
        out += lines
        out.append("")
        if have_compiled_mbm and compiled_names:
            out.append("Compiled solvers only; ratio to the best compiled MBM entry.")
            out.append("")
            out += _target_table(result, target, compiled_names, "mbm-compiled", missing)[0]
            out.append("")
        if flags:
            out.append(f"Caution: at {target:.0e} the reference is within {REF_MARGIN:g}× of its "
                       "check on " + ", ".join(flags) + ": errors there are not resolved.")
            out.append("")
    out.append("## First-call overhead (JIT compile, numba cache load, integrator build, imports)")
    out.append("")
    out.append("Seconds; not included in the times above.  Numba peers written here are compiled "
               "afresh in each process (`cache=False`); MBM's kernels are cached on disk by numba, "
               "so their first call is a cache load after the first ever run, and variants sharing "
               "kernels pay once.  heyoka: the build (decomposition and LLVM JIT) of one "
               "integrator, at the first knob; each tolerance of a sweep builds its own "
               "(see below).  Others: first call minus a warm call.")
    out.append("")
    out.append("| solver | first call − warm call (s) |")
    out.append("|---|---:|")
    for n in names:
        v = result["first_call"].get(n)
        out.append(f"| {n} | {'n/a' if v is None else f'{v:.3f}'} |")
    out.append("")
    builds = [p["prepare"] for sc in result["scenes"] for n, pts in result["points"][sc].items()
              for p in pts if p.get("prepare") is not None and p["prepare"] > 1e-4]
    if builds:
        out.append(f"Integrator builds during the sweeps (heyoka, one per tolerance): {len(builds)}, "
                   f"median {float(np.median(builds)):.3f} s, longest {max(builds):.3f} s.")
        out.append("")
    cold = result.get("cold_compile")
    if cold:
        out.append("From an empty numba cache (a fresh process; what a new installation pays "
                   "once): " + ", ".join(f"{k} {v:.2f} s" for k, v in cold.items()) + ".")
        out.append("")
    out.append("## Solvers")
    out.append("")
    out.append("| solver | knob | notes |")
    out.append("|---|---|---|")
    for n, s in result["solvers"].items():
        out.append(f"| {n} | {KNOB_LABELS[s['knob']]} | {s['note']} |")
    out.append("")
    failures = []
    for sc in result["scenes"]:
        for n, pts in result["points"][sc].items():
            msgs = {p["message"] for p in pts if p["status"] == "failed"}
            if msgs:
                failures.append(f"- {sc} {n}: {len([p for p in pts if p['status'] == 'failed'])} "
                                f"failed point(s), e.g. {sorted(msgs)[0]}")
    notes = list(result["notes"])
    notes += [f"{n}: {r}" for n, r in missing.items() if not any(r in x for x in notes)]
    if notes or failures:
        out.append("## Notes")
        out.append("")
        out += [f"- {n}" for n in notes]
        out += failures
        out.append("")
    return "\n".join(out)


def write_plots(result, directory):
    """One PNG per scene: error against median time, log-log, one line per solver.

    Parameters
    ----------
    result : dict
        From :func:`benchmarks.harness.run_benchmark`.
    directory : path-like

    Returns
    -------
    list of Path
        The files written; empty when matplotlib is not importable.
    """
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return []
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    files = []
    for sc in result["scenes"]:
        fig, ax = plt.subplots(figsize=(8, 5.5))
        for i, (n, pts) in enumerate(result["points"][sc].items()):
            xs = [p["time"] * 1e3 for p in pts if p["time"] is not None]
            ys = [max(p["error"], 1e-16) for p in pts if p["time"] is not None]
            if not xs:
                continue
            fam = result["solvers"][n]["family"]
            style = "-" if fam == "peer" else ("--" if fam == "mbm" else ":")
            marker = "os^vD<>ph*x+"[i % 12]
            ax.loglog(xs, ys, style, marker=marker, ms=4, lw=1.2 if fam == "peer" else 2, label=n,
                      color=plt.cm.tab20(i % 20))
        for target in result["settings"]["targets"]:
            ax.axhline(target, color="0.6", lw=0.8, ls=":")
        # errors above 10 rad are divergent runs; keep them from squashing the axis
        ax.set_ylim(top=10.0)
        ax.set_xlabel("median time per solve (ms)")
        ax.set_ylabel(r"max $|\theta-\theta_{ref}|$ over 201 times")
        title = SCENES[sc].title if sc in SCENES else sc
        ax.set_title(f"{sc}: {title}", fontsize=10)
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
        fig.tight_layout()
        path = directory / f"benchmark_{sc}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        files.append(path)
    return files


def json_default(x):
    """``json.dumps`` ``default=``: numpy scalars and paths."""
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    if isinstance(x, Path):
        return str(x)
    raise TypeError(type(x).__name__)
