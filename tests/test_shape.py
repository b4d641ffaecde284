"""The project's shape rule: no module in mbm/ over 800 lines, no function over 100.

A function's length is ``end_lineno - lineno + 1`` (decorators excluded, docstring
included).  A generated file is exempt only when its first line says it is generated.
"""

import ast
from pathlib import Path

MODULE_MAX = 800
FUNCTION_MAX = 100

PACKAGE = Path(__file__).resolve().parents[1] / "mbm"


def _sources():
    for path in sorted(PACKAGE.rglob("*.py")):
        text = path.read_text(encoding="utf-8")
        first = text.split("\n", 1)[0].lower()
        if "generated" in first:
            continue
        yield path, text


def test_modules_are_at_most_800_lines():
    long = [(str(p.relative_to(PACKAGE.parent)), len(t.splitlines())) for p, t in _sources()
            if len(t.splitlines()) > MODULE_MAX]
    assert not long, f"modules over {MODULE_MAX} lines: {long}"


def test_functions_are_at_most_100_lines():
    long = []
    for path, text in _sources():
        for node in ast.walk(ast.parse(text, filename=str(path))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = node.end_lineno - node.lineno + 1
                if n > FUNCTION_MAX:
                    long.append((f"{path.relative_to(PACKAGE.parent)}:{node.name}", n))
    assert not long, f"functions over {FUNCTION_MAX} lines: {long}"


def test_the_walk_sees_the_package():
    # guards against a vacuous pass (a wrong root finds no files)
    assert sum(1 for _ in _sources()) > 20
