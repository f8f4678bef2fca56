"""Packaging: ``python -m build`` makes a wheel and an sdist that carry the model files, the wheel works
installed in a fresh environment, and the version is written in one place."""

import json
import re
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import zipfile
from pathlib import Path

import pytest

import fretwear
from fretwear._version import __version__

ROOT = Path(__file__).resolve().parents[1]
MODEL_FILES = sorted(p.name for p in (ROOT / "fretwear" / "data").glob("*.toml"))
#: what the installed wheel is asked (run outside the checkout, so that only the wheel can answer)
CHECK = """
import json, sys
from importlib.metadata import version
import numpy as np
import fretwear
from fretwear.model.modelfile import DATA_DIR, example_names, example_path
model = fretwear.paper_model()
from_file = fretwear.read_model(example_path("paper_2dof"))
print(json.dumps({
    "file": fretwear.__file__, "version": fretwear.__version__, "metadata": version("fretwear"),
    "data": sorted(p.name for p in DATA_DIR.glob("*.toml")), "examples": list(example_names()),
    "same_model": bool(np.array_equal(model.K, from_file.K) and np.array_equal(model.M, from_file.M)),
    "u0": model.friction[0].u0,
}))
"""


def test_the_version_is_written_once():
    """pyproject reads it from fretwear/_version.py; no other file of the package writes a version."""
    text = (ROOT / "pyproject.toml").read_text()
    project = text.split("[project]", 1)[1].split("\n[", 1)[0]
    assert 'dynamic = ["version"]' in project and not re.search(r"^version\s*=", project, re.M)
    assert 'version = { attr = "fretwear._version.__version__" }' in text
    writers = [p.relative_to(ROOT).as_posix() for p in (ROOT / "fretwear").rglob("*.py")
               if re.search(r"^__version__\s*=", p.read_text(encoding="utf-8"), re.M)]  # fmt: skip
    assert writers == ["fretwear/_version.py"] and fretwear.__version__ == __version__
    assert re.fullmatch(r"\d+\.\d+\.\d+", __version__)


@pytest.mark.slow
def test_the_wheel_and_the_sdist_install_with_the_model_files(tmp_path):
    pytest.importorskip("build")
    # build from a copy: the build leaves its files (build/, *.egg-info) where it runs
    src = tmp_path / "src"
    skip = (".git", "__pycache__", "*.egg-info", "build", "dist", ".*_cache", "*.nbi", "*.nbc", ".hypothesis")
    shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(*skip))
    dist = tmp_path / "dist"
    build = [sys.executable, "-m", "build", "--outdir", str(dist), str(src)]
    run = subprocess.run(build, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    wheel, sdist = dist / f"fretwear-{__version__}-py3-none-any.whl", dist / f"fretwear-{__version__}.tar.gz"
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
    assert (
        sorted(n.removeprefix("fretwear/data/") for n in names if n.startswith("fretwear/data/"))
        == MODEL_FILES
    )
    assert "fretwear/_version.py" in names and "fretwear/_xarray.py" in names
    with tarfile.open(sdist) as t:
        members = t.getnames()
        pkg_info = t.extractfile(f"fretwear-{__version__}/PKG-INFO").read().decode()
    top = f"fretwear-{__version__}/"
    assert sorted(m.removeprefix(top + "fretwear/data/") for m in members
                  if m.startswith(top + "fretwear/data/")) == MODEL_FILES  # fmt: skip
    assert f"{top}pyproject.toml" in members and f"\nVersion: {__version__}\n" in pkg_info

    # a fresh environment: the wheel alone is fretwear; the dependencies are this environment's (no download)
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    site = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                          capture_output=True, text=True, check=True).stdout.strip()  # fmt: skip
    # a path entry, not a site directory: this environment's editable fretwear (a .pth finder) stays off
    Path(site, "dependencies.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    pip = [
        sys.executable,
        "-m",
        "pip",
        "--python",
        str(python),
        "install",
        "--no-deps",
        "--no-index",
        str(wheel),
    ]
    run = subprocess.run(pip, capture_output=True, text=True, stdin=subprocess.DEVNULL)
    assert run.returncode == 0, run.stderr[-2000:]
    out = subprocess.run([str(python), "-c", CHECK], capture_output=True, text=True, cwd=tmp_path,
                         stdin=subprocess.DEVNULL)  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    info = json.loads(out.stdout.strip().splitlines()[-1])
    assert Path(info["file"]).is_relative_to(venv)  # the installed wheel, not the checkout
    assert info["version"] == info["metadata"] == __version__
    assert info["data"] == MODEL_FILES and "paper_2dof" in info["examples"]
    assert info["same_model"] and info["u0"] == pytest.approx(1e-6)
    cli = subprocess.run([str(venv / "bin" / "fretwear"), "--help"], capture_output=True, text=True,
                         cwd=tmp_path, stdin=subprocess.DEVNULL)  # fmt: skip
    assert cli.returncode == 0 and "usage: fretwear" in cli.stdout
