"""The shell examples of the README and the docs pages run as written, top to bottom, in an empty folder.

(Issue 22; the README's long sections moved into ``docs/`` with issue 27, their
examples are still run here.) Every ```bash block of README.md, then of the
Markdown pages under ``docs/`` (in path order), is read line by line: ``mkdir -p DIR``,
``cat > FILE <<'EOF'`` ... ``EOF`` and ``fretwear ...`` lines run (the last
in-process through :func:`fretwear.cli.main`, in the folder, with the package's
``fretwear/data`` beside it) and must exit 0; then the Python block of
"Reading a result" runs on the study they wrote. Skipped, and only these: the
cluster lines (``dask scheduler``, ``dask worker``, ``--scheduler``), ``panel
serve``, ``pip install``, the benchmark and test lines (``python ...``).

Shrink rule, so that the whole README runs in well under a minute: the sizes
of :data:`SHRINK` replace those written (frequencies, cycle counts,
harmonics), and the commands of :data:`EXTRA` get the options listed there
(fewer random draws and a local worker for ``study``, the ``--quick`` ladder of
``cost``, the smallest figure set, fewer contact pairs). Every other option is
as written; any other kind of line fails the test, so neither the README nor
the docs can gain an example this test does not run. A command line written
twice (the README repeats some of the docs' examples) runs once.
"""

import re
import shlex
from pathlib import Path

import pytest

from fretwear import cli

ROOT = Path(__file__).resolve().parents[1]
#: the README, then every Markdown page of the docs
PAGES = [ROOT / "README.md", *sorted(p for p in (ROOT / "docs").rglob("*.md") if "_build" not in p.parts)]
TEXTS = [page.read_text(encoding="utf-8") for page in PAGES]

#: sizes written in the README -> sizes run here
SHRINK = {"--n": "5", "--nf": "3", "--ncycles": "4", "--harmonics": "3", "--samples": "8"}
#: options added per command, when not written (a written size is shrunk by SHRINK)
EXTRA = {
    "study": (("--samples", "8"), ("--workers", "1"), ("--quiet", None)),
    "cost": (("--quick", None),),
    "figures": (("--harmonics", "3"), ("--nf", "3"), ("--ncycles", "3"), ("--formats", "csv")),
    "interface": (("--contact-nodes", "8"), ("--harmonics", "3")),
    "disk": (("--n", "5"), ("--harmonics", "3")),
}
SKIP = ("dask ", "panel serve", "pip install", "python ")


def blocks(language: str) -> list[str]:
    return [b for text in TEXTS for b in re.findall(rf"^```{language}\n(.*?)^```", text, flags=re.S | re.M)]


def test_the_readme_and_the_docs_pages_are_read():
    """The examples this module runs are where the docs say they are (a moved page must stay found)."""
    names = {page.relative_to(ROOT).as_posix() for page in PAGES}
    assert {"README.md", "docs/user_guide/cli.md", "docs/user_guide/studies.md"} <= names
    lines = {line.split(" #")[0].strip() for block in blocks("bash") for line in block.splitlines()}
    assert sum(line.startswith("fretwear ") for line in lines) >= 28  # as the README before issue 27


def test_the_readme_is_one_screen_with_the_two_commands_and_links_into_the_docs():
    """Issue 27: at most about 120 lines; the quick start's commands as they were; every link resolves."""
    readme = TEXTS[0]
    assert len(readme.splitlines()) <= 120
    commands = 'pip install -e . && panel serve app/app.py\npip install -e ".[test]" && python -m pytest\n'
    assert f"```bash\n{commands}```" in readme
    links = re.findall(r"\]\(((?:docs|examples|assets)/[^)#]*)\)", readme)
    assert len(links) >= 12 and [link for link in links if not (ROOT / link).exists()] == []
    assert "python -m sphinx -W" in readme  # how to build the docs


def shrink(argv: list[str]) -> list[str]:
    """``argv`` under the shrink rule of the module docstring."""
    out = [
        SHRINK[prev] if prev in SHRINK else word for prev, word in zip(["", *argv[:-1]], argv, strict=True)
    ]
    extra = EXTRA.get(out[0], ())
    if out[0] == "interface" and "sphere" in out:  # the sphere's mesh is set by its divisions
        extra = (("--divisions", "6"), *extra[1:])
    for option, value in extra:
        if option not in out:
            out += [option] if value is None else [option, value]
    return out


def test_the_readme_examples_run_as_written(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "fretwear").mkdir()
    (tmp_path / "fretwear" / "data").symlink_to(ROOT / "fretwear" / "data")
    ran, seen = [], set()
    for block in blocks("bash"):
        lines = iter(block.splitlines())
        for raw in lines:
            line = raw.split(" #")[0].strip() if not raw.lstrip().startswith("#") else ""
            if not line or line.startswith(SKIP) or "--scheduler" in line:
                continue
            words = shlex.split(line)
            if words[:2] == ["mkdir", "-p"]:
                for folder in words[2:]:
                    Path(folder).mkdir(parents=True, exist_ok=True)
            elif words[0] == "cat" and words[1] == ">" and words[3].startswith("<<"):
                end = words[3][2:].strip("'\"")
                body = []
                for text in lines:
                    if text == end:
                        break
                    body.append(text)
                Path(words[2]).write_text("\n".join(body) + "\n")
            elif words[0] == "fretwear":
                if line in seen:
                    continue
                seen.add(line)
                argv = shrink(words[1:])
                code = cli.main(argv)
                err = capsys.readouterr().err
                assert code == 0, f"{line}\n(run as fretwear {' '.join(argv)})\n{err}"
                assert "Traceback" not in err
                ran.append(words[1])
            else:
                pytest.fail(f"a README shell line this test does not know how to run: {raw!r}")
    assert {"frf", "linear", "point", "wear", "map", "cost", "figures", "interface", "study"} <= set(ran)
    reading = [b for b in blocks("python") if "open_zarr" in b]
    assert len(reading) == 1
    exec(compile(reading[0], "docs/user_guide/studies.md: Reading a result", "exec"), {})
    assert Path("out/life.png").stat().st_size > 0


def test_the_written_outputs_do_not_share_a_name():
    """Issue 22: three examples wrote out/wear.csv with different columns (a command written twice is one)."""
    lines = [line for line in "\n".join(blocks("bash")).splitlines() if "--scheduler" not in line]
    commands = {line.split(" #")[0].strip() for line in lines}  # a cluster: the same study
    outs = re.findall(r"^fretwear .*--out (\S+)", "\n".join(sorted(commands)), flags=re.M)
    assert len(outs) == len(set(outs)), sorted(o for o in outs if outs.count(o) > 1)


def test_the_getting_started_python_runs_as_written():
    """The first FRF and wear history of docs/getting_started.md, then its plot, as written (Agg backend)."""
    import matplotlib

    matplotlib.use("Agg")
    text = (ROOT / "docs" / "getting_started.md").read_text(encoding="utf-8")
    code = re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)
    assert len(code) == 2
    namespace: dict = {}
    for block in code:
        exec(compile(block, "docs/getting_started.md", "exec"), namespace)
    assert namespace["hist"].label == "exact" and 4e3 < namespace["hist"].cycles_to(0.5) < 6e3
    assert len(namespace["fig"].axes) == 2
