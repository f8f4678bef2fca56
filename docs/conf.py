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

from sphinx.util import logging  # noqa: E402

import fretwear  # noqa: E402

_log = logging.getLogger("fretwear.docs")

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

# Broken references fail the build: every cross-reference of the docs and of the docstrings resolves,
# type fields included (numpydoc links their names). The only names left unresolved on purpose are
# other libraries' (no intersphinx: the build runs without network access); fretwear's own never are.
nitpicky = True
numpydoc_xref_param_type = True
#: short names in the type fields, and where they point
numpydoc_xref_aliases = {
    "Model": "fretwear.model.Model",
    "PeriodicSolution": "fretwear.hbm.PeriodicSolution",
    "ShootingSolution": "fretwear.time.ShootingSolution",
    "WearHistory": "fretwear.wear.WearHistory",
    "ndarray": "numpy.ndarray",
    "Path": "pathlib.Path",
    "int8": "numpy.int8",
    "STICK": "fretwear.model.STICK",
    "SLIP": "fretwear.model.SLIP",
    "Receptance": "fretwear.hbm.condensation.Receptance",
    "ModelFileError": "fretwear.model.ModelFileError",
    "InterfaceSolution": "fretwear.interface.InterfaceSolution",
    "InterfaceWearHistory": "fretwear.interface.InterfaceWearHistory",
    "CylinderOnFlat": "fretwear.interface.CylinderOnFlat",
    "CostStudy": "fretwear.studies.CostStudy",
    "Condensed": "fretwear.hbm.condensation.Condensed",
}
#: the words of a type field that are not names: "float, optional", "ndarray, shape (n, N)", ...
numpydoc_xref_ignore = {
    "optional", "or", "of", "shape", "default", "with", "the", "len",
    # the sizes in the shapes: DOFs, contacts, pairs, samples, harmonics, records, ...
    "n", "m", "k", "p", "K", "H", "N", "nN", "nc", "nf", "n_friction", "n_contacts", "N_samples",
    "sectors", "omegas", "draws", "matrix", "state", "normal_force",
    # a parameter's (start, end, step) and its check(context, value)
    "start", "end", "step", "context", "value",
}  # fmt: skip
#: other libraries' names (and Python's builtins): no intersphinx without network access
nitpick_ignore_regex = [
    (r".*", r"(python|numpy):.*"),  # numpydoc's links of the builtins and of "array_like"
    (r"py:.*", r"(numpy|np|scipy|xarray|xr|pandas|dask|distributed|matplotlib|panel|holoviews|bokeh|zarr"
               r"|numba|skfem|pathlib|collections|typing|concurrent)(\..*)?"),
]  # fmt: skip

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

# Undocumented public names fail the build: every name of the ``__all__`` of each package of the API
# reference has its entry, with a docstring (a ``#:`` comment for data).
API_PACKAGES = ("fretwear", "fretwear.model", "fretwear.hbm", "fretwear.time", "fretwear.wear",
                "fretwear.interface", "fretwear.disk", "fretwear.studies", "fretwear.figures", "fretwear.cli",
                "fretwear.parameters", "fretwear.slow_time", "fretwear.response")  # fmt: skip


def undocumented(objects: set[str]) -> list[str]:
    """The public names of :data:`API_PACKAGES` without an entry among the documented ``objects``.

    A name ``fretwear`` re-exports from a subpackage counts as documented where that subpackage
    documents it (``fw.reduce`` is ``fretwear.model.craig_bampton``).
    """
    import importlib

    missing = []
    for package in API_PACKAGES:
        module = importlib.import_module(package)
        for name in module.__all__:
            obj = getattr(module, name)
            own = getattr(obj, "__name__", name) if callable(obj) else name
            if f"{package}.{name}" in objects:
                continue
            if package == "fretwear" and any(o.endswith(f".{own}") for o in objects):
                continue
            missing.append(f"{package}.{name}")
    return missing


def _no_docstring(app, what, name, obj, options, lines) -> None:
    """Warn about a public module-level name of the API packages that has no docstring."""
    package, _, member = name.rpartition(".")
    text = [line for line in lines if line.strip() not in ("", "..", "!! processed by numpydoc !!")]
    if package in API_PACKAGES and not member.startswith("_") and not text:
        _log.warning(f"public name {name} has no docstring", type="fretwear", subtype="undocumented")


def _check_public_names(app, env) -> None:
    for name in undocumented(set(env.get_domain("py").objects)):
        _log.warning(f"public name {name} is not in the API reference", type="fretwear", subtype="missing")


def setup(app) -> None:
    app.connect("autodoc-process-docstring", _no_docstring, priority=400)  # before numpydoc's (500)
    app.connect("env-check-consistency", _check_public_names)
