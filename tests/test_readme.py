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


def test_readme_quotes_the_generated_benchmark_files():
    """Every figure of the README's benchmark section is a block of a generated file,
    quoted verbatim (``python -m benchmarks readme`` copies them; nothing is typed by hand)."""
    from benchmarks.report import extract_blocks, readme_quotes

    quotes = readme_quotes(README.read_text(encoding="utf-8"))
    assert {(p, n) for p, n, _ in quotes} >= {
        ("docs/benchmark.md", "summary-python-rhs"), ("docs/benchmark.md", "summary-compiled"),
        ("docs/benchmark.md", "findings"), ("docs/benchmark_overheads.md", "overheads-fixed"),
        ("docs/benchmark_extras.md", "extras-undamped"), ("docs/benchmark_extras.md", "extras-ensemble")}
    for path, name, body in quotes:
        blocks = extract_blocks((README.parent / path).read_text(encoding="utf-8"))
        assert name in blocks, (path, name)
        assert body == blocks[name], f"README's quote of {path} {name} differs: run python -m benchmarks readme"


def test_readme_benchmark_section_has_no_unquoted_tables():
    """Tables of measurements in the benchmark section come only through quotes."""
    from benchmarks.report import readme_quotes

    text = README.read_text(encoding="utf-8")
    section = text[text.index("## Benchmark"):text.index("## Development notes")]
    outside = section
    for _, _, body in readme_quotes(section):
        outside = outside.replace(body, "")
    assert not [line for line in outside.splitlines() if line.startswith("|")]
    assert "python -m benchmarks" in section and "mbm.bench" not in text
