"""Sphinx configuration of fretwear's documentation.

Build (no network access needed; warnings are errors)::

    python -m sphinx -W --keep-going -b html docs docs/_build/html

The gallery (``examples/``) is executed; an example whose source did not change
since the last build in this checkout is not run again, unless
``FRETWEAR_DOCS_RERUN=1`` (``tests/test_docs.py`` sets it). ``FRETWEAR_DOCS_FAST=1``
executes only the first example (the others are rendered with their code).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # the gallery shares the cores with the Numba kernels

import fretwear  # noqa: E402

project = "fretwear"
author = "the fretwear developers"
copyright = "fretwear developers"  # noqa: A001 - Sphinx's name
release = fretwear.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax copied into the site: the equations render without network access
    "sphinx.ext.viewcode",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "gallery/*.ipynb", "gallery/*.py", "gallery/*.md5", "gallery/*.json"]
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3

# autodoc and numpydoc: every public name, with the docstring as written (NumPy style)
autodoc_default_options = {"member-order": "bysource"}  # ":members:" per package page
autodoc_typehints = "none"  # the numpydoc sections give the types, with their units
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks: set[str] = set()

# sphinx-gallery: examples/ -> docs/gallery/, executed at build time
FAST = os.environ.get("FRETWEAR_DOCS_FAST", "") not in ("", "0")
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "gallery",
    "filename_pattern": r"plot_01_" if FAST else r"plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "show_memory": False,
    "abort_on_example_error": True,
    "run_stale_examples": os.environ.get("FRETWEAR_DOCS_RERUN", "") not in ("", "0"),
    "write_computation_times": False,
}

html_theme = "pydata_sphinx_theme"
html_title = f"fretwear {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 6,
}
html_static_path = ["_static"]
html_css_files = ["fretwear.css"]
html_show_sourcelink = False
