"""The README's Python example runs and prints what its comments say."""

import contextlib
import io
import pathlib
import re

README = pathlib.Path(__file__).resolve().parents[2] / "README.md"


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


BENCHMARKS_PAGE = README.parent / "docs" / "benchmarks.md"


def _check_quotes(path, required):
    """Every quote of ``path`` is a block of a generated file, verbatim, and the quotes
    include ``required`` ((file, block) pairs)."""
    from benchmarks.report import extract_blocks, readme_quotes

    quotes = readme_quotes(path.read_text(encoding="utf-8"))
    assert {(p, n) for p, n, _ in quotes} >= required
    for quoted, name, body in quotes:
        blocks = extract_blocks((README.parent / quoted).read_text(encoding="utf-8"))
        assert name in blocks, (quoted, name)
        assert body == blocks[name], (
            f"{path.name}'s quote of {quoted} {name} differs: run python -m benchmarks readme")


def test_benchmarks_page_quotes_the_generated_benchmark_files():
    """Every figure of the site's benchmarks page is a block of a generated file,
    quoted verbatim (``python -m benchmarks readme`` copies them; nothing is typed by hand)."""
    _check_quotes(BENCHMARKS_PAGE, {
        ("docs/benchmark.md", "machine"),
        ("docs/benchmark.md", "summary-python-rhs"), ("docs/benchmark.md", "summary-compiled"),
        ("docs/benchmark.md", "findings"), ("docs/benchmark_overheads.md", "overheads-fixed"),
        ("docs/benchmark_overheads.md", "overheads-kernels"),
        ("docs/benchmark_extras.md", "extras-undamped"), ("docs/benchmark_extras.md", "extras-ensemble"),
        ("docs/first_calls.md", "first-calls"), ("docs/unseen.md", "summary")})


def test_readme_quotes_its_headline_figure():
    """The README's one figure against heyoka is quoted from the generated file it links."""
    _check_quotes(README, {("docs/unseen.md", "summary")})
    assert "(docs/unseen.md)" in README.read_text(encoding="utf-8")


def test_quotes_are_refreshed_by_the_benchmarks_command():
    """``python -m benchmarks readme`` refreshes both files that quote (README, the page)."""
    from benchmarks.__main__ import QUOTING

    assert set(QUOTING) == {README, BENCHMARKS_PAGE}


def _unquoted(text):
    from benchmarks.report import readme_quotes

    for _, _, body in readme_quotes(text):
        text = text.replace(body, "")
    return text


def test_benchmarks_page_has_no_unquoted_tables():
    """Tables of measurements on the benchmarks page come only through quotes."""
    text = BENCHMARKS_PAGE.read_text(encoding="utf-8")
    assert not [line for line in _unquoted(text).splitlines() if line.startswith("|")]
    assert "python -m benchmarks" in text and "mbm.bench" not in text


def test_readme_performance_section_has_no_unquoted_tables():
    text = README.read_text(encoding="utf-8")
    section = text[text.index("## Performance"):text.index("## The papers")]
    assert not [line for line in _unquoted(section).splitlines() if line.startswith("|")]
    assert "mbm.bench" not in text


def test_readme_is_short():
    assert len(README.read_text(encoding="utf-8").splitlines()) <= 150
