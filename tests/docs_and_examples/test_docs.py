"""The documentation site: it builds with warnings as errors, every public name has an
API page whose numpydoc sections match its signature, and the pages that restate code
tables agree with the code."""

import importlib.util
import inspect
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import mbm

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
# numpydoc's codes for a Parameters section that does not match the signature:
# a parameter not documented, a documented one that does not exist, the wrong order.
PARAMETER_MISMATCH = {"PR01", "PR02", "PR03"}
# The examples the gallery runs (conf.py's ignore_pattern leaves out the measurement
# script behind docs/convergent.md), each with the figures it draws.
GALLERY_FIGURES = {
    "fig_salas2021": 1, "fig_salas2022": 4, "fig_belendez2007": 6, "josephson_iv": 1,
    "shapiro_steps": 1, "stability_map": 1, "step_size_study": 1, "convergence_orders": 1,
    "thermal_switching": 1, "fit_iv_curve": 1, "fit_trajectory": 1,
}


def _need(*modules):
    missing = [m for m in modules if importlib.util.find_spec(m) is None]
    if missing:
        pytest.skip(f"the docs extra is not installed ({', '.join(missing)}): "
                    "pip install -e '.[docs]'")


def _build(out, *options, timeout):
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
           "-d", str(out / "doctrees"), *options, str(DOCS), str(out / "html")]
    run = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=timeout,
                         env={**os.environ, "MBM_COMPILE_NOTICE": "0"})
    assert run.returncode == 0, f"sphinx failed:\n{run.stdout[-4000:]}\n{run.stderr[-8000:]}"
    return out / "html"


def _public_objects():
    names = []
    for name in mbm.__all__:
        obj = getattr(mbm, name)
        names.append(f"mbm.{name}")
        if inspect.isclass(obj):
            names += [f"mbm.{name}.{m}" for m, v in vars(obj).items()
                      if not m.startswith("_") and (inspect.isfunction(v) or isinstance(v, property))]
    return names


def test_numpydoc_parameters_match_signatures():
    """numpydoc's validation reports no parameter mismatch on the public API."""
    _need("numpydoc")
    from numpydoc.validate import validate

    names = _public_objects() + ["mbm.junction.iv.integrate_mbm", "mbm.junction.iv.driven_mean_velocity"]
    assert "mbm.MBM" in names and "mbm.Pendulum.energy" in names
    bad = [(n, code, msg) for n in names for code, msg in validate(n)["errors"]
           if code in PARAMETER_MISMATCH]
    assert not bad, "\n".join(f"{n}: {code} {msg}" for n, code, msg in bad)


def test_api_page_lists_every_public_name():
    text = (DOCS / "api.rst").read_text(encoding="utf-8")
    listed = set(re.findall(r"^   (\w+)$", text, flags=re.M))
    assert listed == set(mbm.__all__)


def test_statuses_page_is_the_status_table():
    from mbm.status import STATUS_TABLE

    text = (DOCS / "guide" / "statuses.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (\d+) \| `(\w+)` \| (.*) \|$", text, flags=re.M)
    assert [(int(c), n, m) for c, n, m in rows] == [(c, n, m) for c, n, _, m in STATUS_TABLE]


def test_site_builds_without_the_gallery(tmp_path):
    """``sphinx -W`` with ``-D plot_gallery=0``: a broken reference, a docstring that
    does not parse, a page outside the toctree fails here."""
    _need("sphinx", "numpydoc", "myst_parser", "sphinx_gallery", "sphinx_copybutton",
          "pydata_sphinx_theme")
    html = _build(tmp_path, "-D", "plot_gallery=0", timeout=600)
    for name in mbm.__all__:
        assert (html / "generated" / f"mbm.{name}.html").is_file(), name
    for page in ("index", "getting_started", "guide/index", "theory/regimes", "benchmarks",
                 "contributing", "auto_examples/index", *(f"auto_examples/{e}" for e in GALLERY_FIGURES)):
        assert (html / f"{page}.html").is_file(), page
    # the benchmarks page shows the generated work-precision plots
    assert "benchmark_P2.png" in (html / "benchmarks.html").read_text(encoding="utf-8")
    # the front page has its figure; the gallery is in the top bar, not under "More"
    index = (html / "index.html").read_text(encoding="utf-8")
    assert "benchmark_P2.png" in index
    navbar = re.search(r'<ul class="bd-navbar-elements navbar-nav">(.*?)</nav>', index, flags=re.S).group(1)
    shown = navbar.split('<li class="nav-item dropdown')[0]  # the "More" dropdown, if any
    assert 'href="auto_examples/index.html"' in shown


@pytest.mark.slow
def test_site_builds_with_the_gallery_executed(tmp_path):
    """The full build: every example runs and its figures are on its gallery page."""
    _need("sphinx", "numpydoc", "myst_parser", "sphinx_gallery", "sphinx_copybutton",
          "pydata_sphinx_theme", "matplotlib", "xarray")
    # run every example even where sphinx-gallery's MD5 record of an earlier build says
    # its output is current (docs/auto_examples lives in the source tree)
    html = _build(tmp_path, "-D", "sphinx_gallery_conf.run_stale_examples=True", timeout=1800)
    for example, n in GALLERY_FIGURES.items():
        page = (html / "auto_examples" / f"{example}.html").read_text(encoding="utf-8")
        figures = set(re.findall(rf"sphx_glr_{example}_\d+\.png", page))
        assert len(figures) == n, (example, sorted(figures))


def test_front_page_example_runs():
    """The front page's ten lines run and print what their comments say."""
    import contextlib
    import io

    text = (DOCS / "index.md").read_text(encoding="utf-8")
    block = re.search(r"```python\n(.*?)```", text, flags=re.S).group(1)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(block, "index.md", "exec"), {})
    lines = out.getvalue().splitlines()
    assert abs(float(lines[0]) - 0.30141) < 1e-5  # θ(80)
    assert float(lines[1]) < 1e-9  # "its error bar: below 1e-9"
    assert len(lines[2].strip("[]").split()) == 2  # ∂θ(80)/∂β, ∂θ(80)/∂γ


def test_getting_started_example_runs():
    """The first run of the getting-started page prints what its comments say."""
    import contextlib
    import io

    text = (DOCS / "getting_started.md").read_text(encoding="utf-8")
    block = re.search(r"```python\n(.*?)```", text, flags=re.S).group(1)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(block, "getting_started.md", "exec"), {})
    lines = out.getvalue().splitlines()
    assert float(lines[0]) < 1e-9  # "below 1e-9"
    assert lines[1].startswith("taylor - ")
