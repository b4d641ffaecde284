"""The gallery's examples run as downloaded: one file alone in an empty folder, mbm installed.

Every gallery page offers its script for download; the script must then need nothing of
the repository (no sibling module of ``examples/``, no test data, no path relative to
a checkout).  Each import is checked to resolve to an installed package (the standard
library, numpy, scipy, matplotlib, mbm, ...), and a few quick examples are copied to an
empty folder and run there as a reader would run them.
"""

import ast
import importlib.util
import sysconfig
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import mbm

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
# The scripts of examples/ that are not gallery pages (docs/conf.py's ignore_pattern):
# tools of the repository, run from a checkout.
REPOSITORY_SCRIPTS = {"convergence_study"}
# Quick examples (a few seconds each with warm numba caches) run as downloaded, with the
# figures they write to ./out by default.
RUN_AS_DOWNLOADED = {"josephson_iv": ["josephson_iv.png"], "convergence_orders": ["convergence_orders.png"],
                     "fit_iv_curve": ["fit_iv_curve.png"], "fit_trajectory": ["fit_trajectory.png"]}


def _gallery():
    return sorted(p for p in EXAMPLES.glob("*.py") if p.stem not in REPOSITORY_SCRIPTS)


def _imports(path):
    """(line, top-level module name, relative level) of every import in the script."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name.split(".")[0], 0
        elif isinstance(node, ast.ImportFrom):
            yield node.lineno, (node.module or "").split(".")[0], node.level


def _installed(name):
    """Where ``name`` imports from, or None where only a checkout of mbm provides it.

    mbm itself may run from the checkout (an editable install, PYTHONPATH); any other
    module found inside the repository (examples/, tests/data, benchmarks/) is not
    there for a reader who downloaded one script.
    """
    spec = importlib.util.find_spec(name)
    if spec is None:
        return None
    if name == "mbm" or spec.origin in (None, "built-in", "frozen"):
        return spec.origin or name
    origin = Path(spec.origin).resolve()
    # An installed package may sit inside the checkout too (CI's and a developer's .venv).
    installed = {Path(sysconfig.get_paths()[k]).resolve() for k in ("purelib", "platlib")}
    if any(p in origin.parents for p in installed):
        return str(origin)
    return None if ROOT in origin.parents else str(origin)


def test_the_gallery_leaves_out_only_the_repository_scripts():
    conf = (ROOT / "docs" / "conf.py").read_text(encoding="utf-8")
    ignore = re.search(r'"ignore_pattern":\s*r"([^"]+)"', conf).group(1)
    ignored = {p.stem for p in EXAMPLES.glob("*.py") if re.search(ignore, p.name)}
    assert ignored == REPOSITORY_SCRIPTS
    assert _gallery(), "no examples found"


@pytest.mark.parametrize("path", _gallery(), ids=lambda p: p.stem)
def test_example_imports_only_installed_packages(path):
    siblings = {p.stem for p in EXAMPLES.iterdir() if p.suffix == ".py" or p.is_dir()}
    bad = []
    for line, name, level in _imports(path):
        if level:
            bad.append(f"line {line}: relative import")
        elif name in siblings:
            bad.append(f"line {line}: {name} is a file of examples/, not downloaded with the script")
        elif _installed(name) is None:
            bad.append(f"line {line}: {name} is not an installed package")
    assert not bad, f"{path.name}: " + "; ".join(bad)


@pytest.mark.parametrize("path", _gallery(), ids=lambda p: p.stem)
def test_example_needs_no_checkout(path):
    """No path into a checkout: no sys.path edits, nothing found relative to the script."""
    src = path.read_text(encoding="utf-8")
    for needle in ("sys.path", "__file__", "tests/data", "_common"):
        assert needle not in src, f"{path.name} uses {needle!r}"


@pytest.mark.parametrize("name", sorted(RUN_AS_DOWNLOADED))
def test_example_runs_as_downloaded(name, tmp_path):
    """Copied alone into an empty folder and run there with ``python NAME.py``: it
    writes its figures to ./out.  Only mbm's own folder is added to the path (where mbm
    runs from a checkout): never examples/ or tests/data."""
    script = tmp_path / f"{name}.py"
    shutil.copy(EXAMPLES / script.name, script)
    env = {k: v for k, v in os.environ.items() if k not in ("MBM_EXAMPLES_OUT", "PYTHONPATH")}
    env.update(MPLBACKEND="Agg", MBM_COMPILE_NOTICE="0",
               PYTHONPATH=str(Path(mbm.__file__).resolve().parents[1]))
    run = subprocess.run([sys.executable, script.name], cwd=tmp_path, env=env, capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-3000:]
    assert "wrote" in run.stdout
    for png in RUN_AS_DOWNLOADED[name]:
        assert (tmp_path / "out" / png).stat().st_size > 10_000
