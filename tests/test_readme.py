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
