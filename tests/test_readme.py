"""The README's shell examples run as written, top to bottom, in an empty folder (issue 22).

Every ```bash block of README.md is read line by line: ``mkdir -p DIR``,
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
as written; any other kind of line fails the test, so the README cannot gain
an example this test does not run.
"""

import re
import shlex
from pathlib import Path

import pytest

from fretwear import cli

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")

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
    return re.findall(rf"^```{language}\n(.*?)^```", README, flags=re.S | re.M)


def shrink(argv: list[str]) -> list[str]:
    """``argv`` under the shrink rule of the module docstring."""
    out = [
        SHRINK[prev] if prev in SHRINK else word for prev, word in zip(["", *argv[:-1]], argv, strict=True)
    ]
    for option, value in EXTRA.get(out[0], ()):
        if option not in out:
            out += [option] if value is None else [option, value]
    return out


def test_the_readme_examples_run_as_written(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "fretwear").mkdir()
    (tmp_path / "fretwear" / "data").symlink_to(ROOT / "fretwear" / "data")
    ran = []
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
    exec(compile(reading[0], "README.md: Reading a result", "exec"), {})
    assert Path("out/life.png").stat().st_size > 0


def test_the_written_outputs_do_not_share_a_name():
    """Issue 22: three examples wrote out/wear.csv with different columns."""
    lines = [line for line in "\n".join(blocks("bash")).splitlines() if "--scheduler" not in line]
    outs = re.findall(r"^fretwear .*--out (\S+)", "\n".join(lines), flags=re.M)  # a cluster: the same study
    assert len(outs) == len(set(outs)), sorted(o for o in outs if outs.count(o) > 1)
