"""The project's shape rules: no module in mbm/ over 800 lines, no function over 100; the package as a map.

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


# The package as a map (docs/contributing.md): its folders, not a flat top level.
TOP_LEVEL_MAX = 8
# Named results past this many values (collections.namedtuple; numba passes them by value).
TUPLE_RETURN_MAX = 6


def _module_name(path):
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports_at_module_level(path, modules):
    # the package's modules ``path`` imports at its top level (not inside functions)
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                parts = parts[: len(parts) - (node.level - 1)]
                base = ".".join(parts) + ("." + node.module if node.module else "")
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                found.add(sub if sub in modules else base)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
    return {m for m in found if m in modules and m != name}


def test_the_top_level_holds_at_most_8_modules():
    top = sorted(p.name for p in PACKAGE.glob("*.py"))
    assert len(top) <= TOP_LEVEL_MAX, f"{len(top)} modules at the top of mbm/: {top}"


def test_no_import_circle_between_modules():
    paths = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    graph = {m: _imports_at_module_level(p, paths) for m, p in paths.items()}
    # a module reaches itself only through a circle (depth-first, colours)
    state, circles = {}, []

    def visit(m, stack):
        state[m] = 1
        for n in sorted(graph[m]):
            if state.get(n) == 1:
                circles.append(stack[stack.index(n):] + [n])
            elif n not in state:
                visit(n, stack + [n])
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m, [m])
    # a package's __init__ importing its own modules is not a circle of concerns
    circles = [c for c in circles if not all(x.startswith(c[0] + ".") or x == c[0] for x in c)]
    assert not circles, f"import circles: {circles}"


def test_no_function_returns_a_tuple_of_more_than_6():
    long = []
    for path, text in _sources():
        for node in ast.walk(ast.parse(text, filename=str(path))):
            if isinstance(node, ast.Return) and isinstance(node.value, ast.Tuple):
                if len(node.value.elts) > TUPLE_RETURN_MAX:
                    long.append(f"{path.relative_to(PACKAGE.parent)}:{node.lineno}")
    assert not long, f"tuples of more than {TUPLE_RETURN_MAX} returned (name them): {long}"


# More than 8 positional parameters is a record waiting to be named.  The exception: the
# public numba entries, called positionally from users' own njit code (numba has no
# keyword-only parameters, and mbm.__all__'s signatures stay; docs/contributing.md).
POSITIONAL_MAX = 8
PUBLIC_NJIT_ENTRIES = {"mbm/frontends/solve.py:solve_njit", "mbm/events/njit.py:solve_njit_events",
                       "mbm/events/njit.py:solve_njit_function_events"}


def test_no_function_takes_more_than_8_positional_parameters():
    long = set()
    for path, text in _sources():
        for node in ast.walk(ast.parse(text, filename=str(path))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                if len(node.args.posonlyargs) + len(node.args.args) > POSITIONAL_MAX:
                    long.add(f"{path.relative_to(PACKAGE.parent)}:{node.name}")
    assert long == PUBLIC_NJIT_ENTRIES, f"over {POSITIONAL_MAX} positional parameters: {sorted(long)}"


def test_library_modules_do_not_import_the_cli():
    paths = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    offenders = []
    for name, path in paths.items():
        if name.startswith("mbm.cli") or name == "mbm.__main__":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and ((node.module or "").startswith("cli")
                                                      or (node.module or "").startswith("mbm.cli")):
                offenders.append(name)
    assert not offenders, f"library modules importing mbm.cli: {offenders}"


def test_the_inline_option_is_defined_once():
    spelled = [str(p.relative_to(PACKAGE.parent)) for p, t in _sources()
               if ('inline="always"' in t or "'inline': 'always'" in t or '"inline": "always"' in t)]
    assert spelled == ["mbm/compile/jit.py"], spelled
