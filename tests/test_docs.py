"""The documentation builds with warnings as errors, executing every gallery example (issue 27).

The build is the README's command (``python -m sphinx -W --keep-going -b html
docs ...``), into a temporary folder, with ``FRETWEAR_DOCS_RERUN=1`` so that
every example of ``examples/`` runs even if an earlier build in this checkout
ran it: a failing example, a broken link between pages or cross-reference
(nitpicky, type fields included), an undocumented public name, a missing image
or a docstring that does not render fails the test. About 30 s on the 2-core
machine under load (the Numba kernels from the cache). Skipped, with the
reason, when the ``docs`` extra is not installed (``pip install -e ".[docs]"``;
``.ci/run`` installs it).
"""

import importlib
import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import fretwear

ROOT = Path(__file__).resolve().parents[1]
NEEDS = (
    "sphinx",
    "numpydoc",
    "pydata_sphinx_theme",
    "sphinx_gallery",
    "myst_parser",
    "sphinx-mathjax-offline",
)
MISSING = [name for name in NEEDS if importlib.util.find_spec(name) is None]
pytestmark = pytest.mark.skipif(
    bool(MISSING), reason=f"docs build: {', '.join(MISSING)} not installed (pip install -e '.[docs]')"
)

#: every page of the docs, as built (user guide, theory, benchmarks, API reference of each package)
PAGES = (
    "index", "getting_started", "theory", "benchmarks", "gallery/index",
    "user_guide/model", "user_guide/periodic", "user_guide/wear", "user_guide/interfaces",
    "user_guide/bladed_disk", "user_guide/studies", "user_guide/dashboard", "user_guide/cli",
    "user_guide/model_files", "api/index", "api/fretwear", "api/fretwear.model", "api/fretwear.hbm",
    "api/fretwear.time", "api/fretwear.wear", "api/fretwear.interface", "api/fretwear.disk",
    "api/fretwear.studies", "api/fretwear.figures", "api/fretwear.cli",
)  # fmt: skip
#: the gallery: each example and the number of figures it draws
EXAMPLES = {"plot_01_paper_frf_wear": 2, "plot_02_exact_vs_dlft": 1, "plot_03_interface_scar": 1,
            "plot_04_wear_life": 1, "plot_05_paper_frfs": 2, "plot_06_paper_wear_maps": 4,
            "plot_07_paper_harmonics_and_methods": 2, "plot_08_paper_polynomial_map": 2}  # fmt: skip


@pytest.fixture(scope="module")
def build(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("docs")
    env = {**os.environ, "FRETWEAR_DOCS_RERUN": "1", "FRETWEAR_DOCS_FAST": ""}
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
           "-d", str(out / "doctrees"), "docs", str(out / "html")]  # fmt: skip
    run = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    assert run.returncode == 0, f"sphinx failed (warnings are errors):\n{run.stderr[-6000:]}"
    return out / "html"


def test_every_page_builds_without_a_warning(build):
    missing = [page for page in PAGES if not (build / f"{page}.html").is_file()]
    assert not missing
    assert (build / "_static" / "mathjax" / "tex-chtml.js").is_file()  # the equations render offline


def test_the_api_reference_documents_every_public_name(build):
    """Each name of ``fretwear.__all__`` and of a subpackage's ``__all__`` has its entry (an HTML id)."""
    html = "".join(p.read_text(encoding="utf-8") for p in (build / "api").glob("*.html"))
    packages = ("model", "hbm", "time", "wear", "interface", "disk", "studies", "figures", "cli")
    undocumented = []
    for name in ("fretwear", *(f"fretwear.{p}" for p in packages)):
        for member in importlib.import_module(name).__all__:
            if f'id="{name}.{member}"' not in html:
                undocumented.append(f"{name}.{member}")
    # the classes fretwear re-exports are documented in their subpackage (linked from fretwear's page)
    exported = {f"fretwear.{n}" for n in ("Model", "FrictionContact", "NormalContact", "ContactPairs",
                                          "PeriodicSolution", "ShootingSolution", "WearHistory",
                                          "METHODS", "reduce")}  # fmt: skip
    assert sorted(set(undocumented) - exported) == []
    assert len(fretwear.__all__) > 20


def test_every_gallery_example_ran_and_drew_its_figures(build):
    for name, figures in EXAMPLES.items():
        page = (build / "gallery" / f"{name}.html").read_text(encoding="utf-8")
        for k in range(1, figures + 1):
            image = f"sphx_glr_{name}_{k:03d}.png"
            assert image in page, f"{name}: figure {k} not drawn"
            assert (build / "_images" / image).stat().st_size > 10_000
    assert len(EXAMPLES) == len(list((ROOT / "examples").glob("plot_*.py")))


def test_the_gallery_draws_the_papers_figures_5_to_14(build):
    """Each of the paper's Fig. 5-14 is drawn by an executed example (its figure's title names it)."""
    pages = "".join((build / "gallery" / f"{name}.html").read_text(encoding="utf-8") for name in EXAMPLES)
    drawn = {int(n) for n in re.findall(r"Fig\. (\d+)", re.sub(r"<[^>]+>", "", pages))}
    assert drawn >= set(range(5, 15)), sorted(set(range(5, 15)) - drawn)
    # the approximations are named as such: the harmonics of Fig. 10 against the exact answer
    page = (build / "gallery" / "plot_07_paper_harmonics_and_methods.html").read_text(encoding="utf-8")
    errors = dict(re.findall(r"(Nh = \d+): \d+ cycles to 0.5 u0, ([-+][\d.]+)% against the exact", page))
    assert [float(errors[f"Nh = {n}"]) for n in (1, 3, 7, 15, 21)] == sorted(
        float(errors[f"Nh = {n}"]) for n in (1, 3, 7, 15, 21))  # fmt: skip
    assert -8 < float(errors["Nh = 21"]) < -5


def test_the_examples_print_the_exact_answer_and_the_error_of_each_approximation(build):
    """The exact-versus-DLFT example prints its cycles to 0.5 u0 and each method's error (the wear page's)."""
    page = (build / "gallery" / "plot_02_exact_vs_dlft.html").read_text(encoding="utf-8")
    found = re.findall(r"(Nh = \d+): \d+ cycles to 0.5 u0, ([-+][\d.]+)% against the exact", page)
    errors = dict(found)
    assert abs(float(errors["Nh = 7"]) + 18.13) < 0.05  # the wear page: 18 % early at Nh = 7
    assert -8 < float(errors["Nh = 21"]) < -6  # 7 % early at Nh = 21


def _conf():
    """``docs/conf.py`` as a module (its checks of the public names, its reference settings)."""
    spec = importlib.util.spec_from_file_location("fretwear_docs_conf", ROOT / "docs" / "conf.py")
    conf = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(conf)
    return conf


def test_broken_references_fail_the_build_and_only_other_libraries_are_ignored():
    conf = _conf()
    assert conf.nitpicky and conf.numpydoc_xref_param_type
    own = ["fretwear", "fretwear.hbm.sweep", "fretwear.model.Model", "fretwear.front.SOLVERS"]
    for _, pattern in conf.nitpick_ignore_regex:
        assert not any(re.fullmatch(pattern, name) for name in own), pattern
    assert re.fullmatch(conf.nitpick_ignore_regex[1][1], "numpy.ndarray")
    public = {n for p in conf.API_PACKAGES for n in importlib.import_module(p).__all__}
    assert not public & set(conf.numpydoc_xref_ignore)  # fretwear's names in a type field are links


def test_an_undocumented_public_name_fails_the_build(build, monkeypatch):
    from sphinx.util.inventory import InventoryFile

    with open(build / "objects.inv", "rb") as f:
        inventory = InventoryFile.load(f, "", lambda base, uri: uri)
    objects = {name for kind, entries in inventory.items() if kind.startswith("py:") for name in entries}
    conf = _conf()
    assert conf.undocumented(objects) == []
    assert conf.undocumented(objects - {"fretwear.hbm.sweep"}) == ["fretwear.hbm.sweep"]
    assert conf.undocumented(objects - {"fretwear.model.craig_bampton"}) == [
        "fretwear.reduce", "fretwear.model.craig_bampton"]  # fmt: skip
    warned = []
    monkeypatch.setattr(conf._log, "warning", lambda msg, **kw: warned.append(msg))
    conf._no_docstring(None, "function", "fretwear.hbm.sweep", None, {}, ["", "  "])
    numpydoc = ["", "..", "    !! processed by numpydoc !!"]  # its mark, on an empty docstring
    conf._no_docstring(None, "function", "fretwear.wear_map", None, {}, numpydoc)
    conf._no_docstring(None, "function", "fretwear.hbm.sweep", None, {}, ["Sweep."])
    conf._no_docstring(None, "method", "fretwear.hbm.Sweep.to_xarray", None, {}, [])  # a member: its class's
    assert warned == [
        f"public name {n} has no docstring" for n in ("fretwear.hbm.sweep", "fretwear.wear_map")
    ]
