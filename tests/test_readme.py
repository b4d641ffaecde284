"""The README's Python example runs and prints what its comments say."""

import contextlib
import io
import pathlib
import re

README = pathlib.Path(__file__).resolve().parents[1] / "README.md"


def test_readme_example_runs():
    text = README.read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, "README has no python example"
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(blocks[0], "README.md", "exec"), {})
    lines = out.getvalue().splitlines()
    assert float(lines[0]) < 1e-9  # "≈ 6e-10"
    assert lines[1].startswith("taylor - ")
    g2, g3, D = (float(x) for x in lines[2].split())
    assert abs(g2 - 0.0794131) < 1e-7 and abs(g3 - 0.00345555) < 1e-8 and abs(D - 3.17128) < 1e-5


BENCH = README.parent / "docs" / "benchmark.md"
# README row label -> the row of docs/benchmark.md it quotes (None: the fastest mbm.solve row).
README_ROWS = {
    "scipy DOP853": "scipy DOP853",
    "scipy LSODA": "scipy LSODA",
    "CVODE Adams": "CVODE Adams",
    "MBM auto, solve_ivp": "MBM auto (rtol, windows_per_step=None)",
    "MBM auto, solve_ivp, one window per step (default)": "MBM auto (rtol)",
    "numba RK4 (fixed step, written in the benchmark)": "numba RK4",
    "numba RK4": "numba RK4",
    "numba DOP853 (written in the benchmark)": "numba DOP853",
    "numba DOP853": "numba DOP853",
    "numbalsoda DOP853": "numbalsoda DOP853",
    "mbm.solve (best of its rows)": None,
}


def _cells(line):
    return [c.strip().replace("**", "") for c in line.strip().strip("|").split("|")]


def _bench_tables():
    """{target: {solver: [cell text per scene]}} from the first table of each target."""
    tables = {}
    for block in re.split(r"^## Target error ", BENCH.read_text(encoding="utf-8"), flags=re.M)[1:]:
        target = float(block.split("\n", 1)[0])
        rows = {}
        for line in block.split("\n\n", 3)[2].splitlines()[2:]:
            c = _cells(line)
            rows[c[0]] = [x.split(" (")[0] for x in c[1:]]
        tables[target] = rows
    return tables


def _best_solve(rows, col):
    vals = [r[col] for name, r in rows.items() if name.startswith("mbm.solve")]
    nums = [v for v in vals if v not in ("—", "> budget")]
    return min(nums, key=float) if nums else "—"


def test_readme_benchmark_tables_quote_docs_benchmark():
    """Every time in the README's two benchmark tables is the cell of docs/benchmark.md
    (the run the README cites), so the README cannot drift from the measurement."""
    text = README.read_text(encoding="utf-8")
    section = text[text.index("## Benchmark"):text.index("Two targets the tables do not cover")]
    tables = _bench_tables()
    checked = 0
    for table in re.findall(r"(\| solver \|.*?)\n\n", section, flags=re.S):
        lines = table.splitlines()
        head = _cells(lines[0])
        has_target = head[1] == "target"
        scenes = head[2:] if has_target else head[1:]
        for line in lines[2:]:
            c = _cells(line)
            target = float(c[1]) if has_target else 1e-6
            values = c[2:] if has_target else c[1:]
            rows = tables[target]
            source = README_ROWS[c[0]]
            for scene, value in zip(scenes, values):
                col = int(scene[1:]) - 1
                expect = _best_solve(rows, col) if source is None else rows[source][col]
                assert value == expect, (c[0], target, scene)
                checked += 1
    assert checked >= 60


def test_readme_overheads_quote_docs_benchmark_overheads():
    """The per-call costs the README quotes are docs/benchmark_overheads.md's."""
    text = " ".join(README.read_text(encoding="utf-8").split())
    para = text[text.index("Why it loses on cheap targets"):text.index("Two targets the tables do not cover")]
    fixed, runs, kernels, eq = {}, {}, {}, {}
    for line in (README.parent / "docs" / "benchmark_overheads.md").read_text(encoding="utf-8").splitlines():
        c = _cells(line) if line.startswith("|") else []
        if len(c) == 2 and c[1][:1].isdigit():
            fixed[c[0].strip()] = c[1]
        elif len(c) == 5 and c[1].isdigit():
            runs[(c[0], int(c[1]))] = c[3]
        elif len(c) == 3 and c[0].isdigit():
            kernels[int(c[0])] = c[1:]
        elif len(c) == 4 and c[1].isdigit():
            eq[(c[0], int(c[1]))] = float(c[2].split(" (")[0])
    assert f"costs {fixed['mbm.solve, empty span']} µs before its first window" in para
    assert f"({fixed['of which: argument checks (mbm.fast._setup)']} µs of argument checks" in para
    assert f"{fixed['of which: the compiled run (mbm.fast._run, one window)']} µs for the compiled call" in para
    assert f"`solve_ivp(method=mbm.MBM)` {fixed['solve_ivp(method=mbm.MBM, windows_per_step=None), empty span']} µs" in para
    assert f"On P1 the whole run is {runs[('P1', 24)]} µs" in para and f"on P2 {runs[('P2', 24)]} µs" in para
    assert f"anchor costs {kernels[24][0]} ns and one output {kernels[24][1]} ns" in para
    for scene in ("P1", "P2"):
        ts = [v for (s, _), v in eq.items() if s == scene]
        assert f"{min(ts):.1f}–{max(ts):.1f} µs on {scene}" in para
    assert f"degree 8: {eq[('P4', 8)]:.0f} µs, degree 24: {eq[('P4', 24)]:.0f} µs" in para
    assert max(eq[("P4", d)] for d in (8, 12, 16, 20, 24)) == eq[("P4", 8)]  # "the dearest"


def test_readme_extras_quote_docs_benchmark_extras():
    """The undamped-10⁶ and ensemble figures in the README are docs/benchmark_extras.md's."""
    text = " ".join(README.read_text(encoding="utf-8").split())
    para = text[text.index("Two targets the tables do not cover"):text.index("First calls (same run")]
    und, ens = {}, {}
    for line in (README.parent / "docs" / "benchmark_extras.md").read_text(encoding="utf-8").splitlines():
        c = _cells(line) if line.startswith("|") else []
        if len(c) == 5 and c[2][:1].isdigit():
            und[(c[0], c[1])] = (c[2], float(c[3].split(" ")[0]))
        elif len(c) == 7 and c[2].isdigit():
            ens[(c[0], c[1], int(c[2]))] = (float(c[5]), float(c[6]))
    mbm_s = und[("MBM auto, solve_ivp", "-")][1]
    assert f"{mbm_s * 1e3:.2f} ms through `solve_ivp`" in para
    scipy_err, scipy_s = und[("scipy DOP853", "rtol=1e-08")]
    assert f"{scipy_s:.0f} s, error {float(scipy_err):.2f}" in para
    nb_err, nb_s = und[("numba DOP853", "rtol=1e-12")]
    assert f"{nb_s:.1f} s, error {float(nb_err):.1e}".replace("e-04", "e-4") in para
    for target, names in (("0.001", ("mbm.solve_batch", "numba RK4, looped", "numba DOP853, looped")),
                          ("1e-06", ("mbm.solve_batch", "numba DOP853, looped", "numba RK4, looped"))):
        for name in names:
            per_core = ens[(target, name, 1)][1]
            assert f" {per_core:.0f}" in para, (target, name)
        one, two = ens[(target, "mbm.solve_batch", 1)][0], ens[(target, "mbm.solve_batch", 2)][0]
        assert f"{one / two:.2f}×" in para, target
