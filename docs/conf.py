"""Sphinx configuration of mbm's documentation site.

Build: ``python -m sphinx -W -b html docs docs/_build/html`` (``-D plot_gallery=0``
skips running the examples).
"""

import os
import shutil
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(DOCS))  # _gallery_scraper

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("MBM_COMPILE_NOTICE", "0")

import mbm  # noqa: E402
from _gallery_scraper import PngScraper  # noqa: E402

project = "mbm"
author = "mbm developers"
copyright = "mbm developers"
version = release = mbm.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "sphinx_copybutton",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "auto_examples/*.ipynb", "auto_examples/*.py",
                    "auto_examples/*.zip", "auto_examples/*.md5", "auto_examples/*.json"]

# Markdown: $...$ math, ::: fences, anchors for ## and ###.
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

autosummary_generate = True
autodoc_default_options = {"members": False}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    # Every example is a page, run, and self-contained: a reader downloads one file and
    # runs it with mbm installed (tests/docs_and_examples/test_examples_standalone.py).
    # Left out: the measurement script behind docs/convergent.md, a tool of the
    # repository (it reads and writes tests/data; its sweeps are far past the build budget).
    "filename_pattern": r"\.py$",
    "ignore_pattern": r"convergence_study\.py$",
    "image_scrapers": (PngScraper(), "matplotlib"),
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "show_memory": False,
    "abort_on_example_error": False,
    "only_warn_on_example_error": False,
    "capture_repr": (),
}

html_theme = "pydata_sphinx_theme"
html_title = "mbm"
html_static_path = ["_static"]
html_theme_options = {
    "navbar_align": "left",
    # the root toctree's seven pages all in the top bar (the gallery third), none
    # hidden under "More"
    "header_links_before_dropdown": 7,
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "secondary_sidebar_items": ["page-toc"],
}
html_sidebars = {"index": [], "getting_started": []}


def _gallery_out(app):
    """The examples save their PNGs to ``$MBM_EXAMPLES_OUT``: a fresh folder beside this
    build's output, set before sphinx-gallery runs them (``_gallery_scraper`` moves
    each block's files into the gallery)."""
    out = Path(app.outdir).parent / "gallery_png"
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    os.environ["MBM_EXAMPLES_OUT"] = str(out)


# Module-level constants of the API page: autodoc would show the docstring of their
# type (a tuple's "Built-in immutable sequence ...") in place of one of their own.
_DATA_DOCS = {
    "mbm.SENSITIVITY_NAMES": [
        "The parameter names ``sensitivities=`` accepts on :func:`mbm.solve`,",
        ":meth:`mbm.Integrator.solve` and :func:`mbm.solve_batch`: θ₀, θ'₀, β, γ, ω",
        "and the AC drive's A, Ω, φ.  The result's ``sensitivities`` has one row per",
        "name asked, in the order asked (its ``sensitivity_names``).",
    ],
}


def _data_doc(app, what, name, obj, options, lines):
    if what == "data" and name in _DATA_DOCS:
        lines[:] = list(_DATA_DOCS[name])


def setup(app):
    app.connect("builder-inited", _gallery_out, priority=100)  # before sphinx-gallery (500)
    app.connect("autodoc-process-docstring", _data_doc)
