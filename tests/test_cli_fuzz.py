"""Every command of the command line under a careless user (issue 22).

Each case runs ``fretwear.cli.main`` in-process in an empty folder and asserts
the exit status, one line on stderr naming the option (never a traceback) and
that nothing was written; a property draws out-of-range values for every
numeric option of every command from the parameter table; a few subprocess
cases interrupt long runs with SIGINT (exit 130 within 2 s, nothing partial).
"""

import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fretwear import cli
from fretwear.parameters import PARAMETERS

ROOT = Path(__file__).resolve().parents[1]
SPEC = str(ROOT / "fretwear" / "data" / "wear_life.toml")

#: the least each command needs besides the option under test (outputs in the current folder)
BASE = {
    "frf": ["--out", "x.csv"],
    "linear": ["--out", "x.csv"],
    "point": ["--f", "0.7"],
    "wear": ["--f", "0.7", "--out", "x.csv"],
    "map": ["--out", "x.csv"],
    "cost": ["--f", "0.7", "--out", "x.csv"],
    "figures": ["--out", "figs"],
    "study": [SPEC, "--out", "s.zarr"],
    "interface": [],
    "disk": ["mistuning", "--out", "x.csv"],
}

#: (argv, what the one line must name); exit status 2, nothing written, before any work
BAD = [
    # sizes and times without bound (issue 22)
    (["frf", "--n", "100000000", "--out", "x.csv"], "--n: must be an integer in [1, 10001]"),
    (["frf", "--harmonics", "1000", "--out", "x.csv"], "--harmonics: must be an integer in [1, 64]"),
    (["point", "--f", "0.7", "--harmonics", "1000"], "--harmonics"),
    (["figures", "--harmonics", "1000", "--out", "figs"], "--harmonics"),
    (["map", "--nf", "1e8", "--out", "x.csv"], "--nf: must be an integer in [2, 401], got '1e8'"),
    (["map", "--ncycles", "1e8", "--out", "x.csv"], "--ncycles"),
    (["study", SPEC, "--samples", "1e8", "--out", "s.zarr"], "--samples"),
    (["figures", "--nf", "1e5", "--out", "figs"], "--nf"),
    (["study", SPEC, "--workers", "100", "--out", "s.zarr"], "--workers"),
    (["figures", "--degree", "0", "--out", "figs"], "--degree: must be an integer in [1, 12], got '0'"),
    (["interface", "--contact-nodes", "100000"], "--contact-nodes"),
    (["frf", "--samples", "100000", "--out", "x.csv"], "--samples"),
    # wrong answers with exit status 0 before
    (["wear", "--f", "0.7", "--kw", "0", "--out", "w.csv"], "--kw: must be a number > 0"),
    (["map", "--fmin", "0.3", "--fmax", "1.3", "--nf", "5", "--kw", "0", "--out", "m.csv"], "--kw"),
    (["cost", "--f", "0.7", "--kw", "0", "--cycles", "1e4", "--out", "c.csv"], "--kw"),
    (["frf", "--fex", "-10", "--out", "x.csv"], "--fex: must be a number > 0 and <= 1000 N, got '-10'"),
    (["interface", "--q-ratio", "5", "--static"], "--q-ratio"),
    # every command at its boundaries
    (["frf", "--fex", "0", "--out", "x.csv"], "--fex"),
    (["frf", "--fex", "nan", "--out", "x.csv"], "--fex"),
    (["frf", "--mu", "inf", "--out", "x.csv"], "--mu"),
    (["frf", "--kn", "0", "--out", "x.csv"], "--kn"),
    (["frf", "--u0", "-1e-6", "--out", "x.csv"], "--u0"),
    (["frf", "--harmonics", "2.5", "--out", "x.csv"], "--harmonics"),
    (["frf", "--fmin", "0.5", "--fmax", "0.4", "--out", "x.csv"], "--fmax"),
    (["frf", "--model", "jenkins", "--out", "x.csv"], "--fmin: required with --model"),
    (["linear", "--n", "0", "--out", "x.csv"], "--n"),
    (["point", "--f", "0"], "--f"),
    (["point", "--f", "1e9"], "--f"),
    (["wear", "--f", "0.7", "--cycles", "0", "--out", "x.csv"], "--cycles"),
    (["wear", "--f", "0.7", "--cycles", "1e31", "--out", "x.csv"], "--cycles"),
    (["wear", "--f", "0.7", "--kw", "1", "--out", "x.csv"], "--kw"),
    (["wear", "--f", "0.7", "--tol", "0.6", "--method", "stepping", "--out", "x.csv"], "--tol"),
    (["wear", "--f", "0.7", "--method", "polynomial", "--degree", "13", "--out", "x.csv"], "--degree"),
    (["wear", "--f", "0.7", "--fixed-step", "0", "--out", "x.csv"], "--fixed-step"),
    (["map", "--nf", "0", "--out", "x.csv"], "--nf"),
    (["map", "--ncycles", "1", "--out", "x.csv"], "--ncycles"),
    (["cost", "--f", "0.7", "--target", "1", "--out", "x.csv"], "--target"),
    (["cost", "--f", "0.7", "--kw", "1e-11", "--out", "x.csv"], "--kw and --cycles"),
    (["figures", "--nf", "1", "--out", "figs"], "--nf"),
    (["figures", "--ncycles", "2", "--out", "figs"], "--ncycles"),
    (["figures", "--dpi", "10", "--out", "figs"], "--dpi"),
    (["figures", "--width", "1", "--out", "figs"], "--width"),
    (["figures", "--fontsize", "100", "--out", "figs"], "--fontsize"),
    (["figures", "--formats", "eps", "--out", "figs"], "--formats"),
    (["figures", "--fmin", "1.3", "--fmax", "1.3", "--out", "figs"], "--fmax"),
    (["study", SPEC, "--workers", "0", "--out", "s.zarr"], "--workers"),
    (["study", SPEC, "--retries", "-1", "--out", "s.zarr"], "--retries"),
    (["study", SPEC, "--points-per-task", "0", "--out", "s.zarr"], "--points-per-task"),
    (["interface", "--contact-nodes", "2"], "--contact-nodes"),
    (["interface", "--harmonics", "65"], "--harmonics"),
    (["interface", "--kw", "0"], "--kw"),
    (["interface", "--window", "1"], "--window"),
    (["interface", "--rtol", "0", "--kw", "1e-14"], "--rtol"),
    # outputs, checked before any work
    (["map", "--out", "m.eps"], "--out: must end in .csv, .npz, .png, .svg, .pdf, .html"),
    (["frf", "--out", "x.png"], "--out"),
    (["wear", "--f", "0.7", "--out", "w.npz"], "--out"),
    (["frf", "--out", "folder.csv"], "--out: 'folder.csv' is a folder"),
    (["frf", "--out", "/nonexistent/x.csv"], "--out: the folder of"),
    (["frf", "--out", "/proc/x.csv"], "--out: cannot write in '/proc'"),
    (["interface", "--out", "i.txt"], "--out"),
    (["figures", "--out", "file.txt"], "--out: 'file.txt' is an existing file"),
    (["figures", "--out", "/proc/figs"], "--out: cannot write in '/proc'"),
    (["study", SPEC, "--out", "/proc/x.zarr"], "--out: cannot write in '/proc'"),
    (["study", SPEC, "--out", "file.txt"], "--out"),
    (["study", SPEC, "--out", "s.zarr", "--figure", "/nonexistent/f.png"], "--figure"),
    (["study", SPEC, "--out", "s.zarr", "--figure", "f.txt"], "--figure"),
]


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """An empty working folder but for a sub-folder ``folder.csv`` and a file ``file.txt``."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "folder.csv").mkdir()
    (tmp_path / "file.txt").write_text("keep\n")
    return tmp_path


def _listing(path: Path) -> list[str]:
    return sorted(str(p.relative_to(path)) for p in path.rglob("*"))


def _usage_error(capsys, folder: Path, argv: list[str]) -> str:
    before = _listing(folder)
    code = cli.main(argv)
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert out == ""
    assert _listing(folder) == before  # nothing written, not even a partial file
    return err


@pytest.mark.parametrize(("argv", "needle"), BAD, ids=[" ".join(a[:1] + a[-3:]) for a, _ in BAD])
def test_bad_input_is_refused_up_front(capsys, folder, argv, needle):
    t0 = time.perf_counter()
    err = _usage_error(capsys, folder, argv)
    assert needle in err
    assert time.perf_counter() - t0 < 5  # before any work (the study's spec is read, no cluster started)


def test_settings_files_go_through_the_same_checks(capsys, folder):
    (folder / "s.json").write_text('{"fex": -14, "mu": 0.8}')
    err = _usage_error(capsys, folder, ["map", "--settings", "s.json", "--out", "m.csv"])
    assert "--fex (from --settings s.json): must be a number > 0 and <= 1000 N" in err
    (folder / "s.json").write_text('{"harmonics": 1000}')
    assert "--harmonics" in _usage_error(capsys, folder, ["frf", "--settings", "s.json", "--out", "x.csv"])


@pytest.mark.parametrize(
    ("line", "needle"),
    [
        ("kw = 0.0", "parameters.kw: must be a number > 0 and <= 0.0001 1/N, got 0.0"),
        ("fex = -14.0", "parameters.fex: must be a number > 0 and <= 1000 N, got -14.0"),
        ("harmonics = 1000", "parameters.harmonics: must be an integer in [1, 64], got 1000"),
        ("frequency = { start = 0.3, stop = 1.3, num = 100000 }", "parameters.frequency.num"),
    ],
)
def test_a_study_spec_goes_through_the_same_checks(capsys, folder, line, needle):
    spec = '[study]\nquantities = ["wear_life"]\n[parameters]\ncycles = 1e5\n' + line + "\n"
    if not line.startswith("frequency"):
        spec += "frequency = 0.7\n"
    (folder / "spec.toml").write_text(spec)
    assert needle in _usage_error(capsys, folder, ["study", "spec.toml", "--out", "s.zarr"])


def test_an_unreachable_scheduler_leaves_no_store(capsys, folder, monkeypatch):
    from fretwear.studies import run
    from fretwear.studies.spec import SpecError

    def unreachable(scheduler, workers):
        raise SpecError("--scheduler", f"cannot reach a Dask scheduler at {scheduler!r}: timed out")

    monkeypatch.setattr(run, "_start_client", unreachable)
    argv = ["study", SPEC, "--samples", "4", "--out", "s.zarr", "--scheduler", "tcp://127.0.0.1:9"]
    before = _listing(folder)
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "--scheduler: cannot reach" in err.splitlines()[-1]
    assert _listing(folder) == before  # no 21-file store


# -- every numeric option of every command, against the table ------------------------------------------
def _numeric_options() -> list[tuple[str, str, object]]:
    parser = cli.build_parser()
    out = []
    for command, sub in parser.commands.items():  # type: ignore[attr-defined]
        for action in sub._actions:
            param = getattr(action.type, "parameter", None)
            if param is not None:
                out.append((command, action.option_strings[-1], param))
    return out


OPTIONS = _numeric_options()


def test_every_numeric_option_reads_the_table():
    """Issue 22: no numeric option without its range (the table names each once)."""
    parser = cli.build_parser()
    for command, sub in parser.commands.items():  # type: ignore[attr-defined]
        for action in sub._actions:
            if action.type is not None and action.type not in (str,):
                assert getattr(action.type, "parameter", None) is not None, (command, action.option_strings)
    assert {p.name for _, _, p in OPTIONS} <= set(PARAMETERS)
    assert len(OPTIONS) > 60


def _beyond(bound: float, strict: bool, up: bool) -> tuple[float, bool]:
    """The float at which the outside of an inclusive/strict bound starts, and whether to exclude it:
    a bound beyond 2**53 (the seed's 2**63 - 1) has no float of its own."""
    edge = float(bound)
    if edge == bound:
        return edge, not strict
    inside = edge < bound if up else edge > bound
    return (math.nextafter(edge, math.inf if up else -math.inf) if inside else edge), False


def _outside(param) -> st.SearchStrategy[str]:
    low, low_exclude = _beyond(param.low, param.low_strict, up=False)
    high, high_exclude = _beyond(param.high, param.high_strict, up=True)
    values = [
        st.floats(max_value=low, exclude_max=low_exclude, allow_nan=False, allow_infinity=False),
        st.floats(min_value=high, exclude_min=high_exclude, allow_nan=False, allow_infinity=False),
        st.sampled_from(["nan", "inf", "-inf", "", "abc", "1,5", "0x10"]),
    ]
    if param.integer:
        inner = st.floats(min_value=float(param.low), max_value=float(min(param.high, 2**53)))
        values.append(inner.filter(lambda v: not float(v).is_integer()))
    return st.one_of(values).map(lambda v: v if isinstance(v, str) else repr(v))


@settings(suppress_health_check=[HealthCheck.function_scoped_fixture])  # capsys is read at every draw
@given(data=st.data())
def test_any_value_outside_an_options_range_is_one_line_and_exit_2(capsys, data):
    command, flag, param = data.draw(st.sampled_from(OPTIONS))
    text = data.draw(_outside(param))
    code = cli.main([command, *BASE[command], f"{flag}={text}"])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert flag in err and param.range_text() in err


@given(data=st.data())
def test_any_value_inside_an_options_range_parses_to_itself(data):
    command, flag, param = data.draw(st.sampled_from(OPTIONS))
    if param.integer:
        value: float = data.draw(st.integers(int(param.low), int(min(param.high, 2**53))))
    else:
        value = data.draw(st.floats(param.low, param.high, exclude_min=param.low_strict,
                                    exclude_max=param.high_strict))  # fmt: skip
    args = cli.build_parser().parse_args([command, *BASE[command], f"{flag}={value!r}"])
    dest = next(a.dest for a in cli.build_parser().commands[command]._actions if flag in a.option_strings)
    assert getattr(args, dest) == value and math.isfinite(getattr(args, dest))


# -- interrupts ----------------------------------------------------------------------------------------
def interrupt_limit() -> float:
    """2 s from Ctrl-C to the exit (0.5-1 s measured), stretched by the machine's load: at load 6 on 2
    cores each process gets a third of a core (2.7 s was seen once)."""
    return 2.0 * max(1.0, os.getloadavg()[0] / (os.cpu_count() or 1))


# as the `fretwear` script: main() reads sys.argv; "ready" once imported, when Ctrl-C reaches main
READY = "import sys, fretwear.cli as c; print('ready', flush=True); sys.exit(c.main())"


def _interrupt(tmp_path: Path, argv: list[str], ready=lambda: True, pid=None) -> tuple[int, str, float]:
    """Start ``fretwear ARGV`` in ``tmp_path``, wait until it runs ``main`` and ``ready()``, send SIGINT;
    the exit status, stderr and the seconds from the signal to the exit (``pid`` receives the process id)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    # SIGINT at its default in the child: a runner started in the background (``cmd &`` without job
    # control) ignores it, and the child would inherit that and never see Ctrl-C
    proc = subprocess.Popen([sys.executable, "-c", READY, *argv], cwd=tmp_path, env=env, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # fmt: skip
    if pid is not None:
        pid.append(proc.pid)
    try:
        assert proc.stdout.readline().strip() == "ready"
        deadline = time.monotonic() + 60
        while not ready():
            assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()[1]
            time.sleep(0.02)
        time.sleep(0.3)  # inside the computation
        assert proc.poll() is None, "finished before the interrupt: make the case longer"
        proc.send_signal(signal.SIGINT)
        t0 = time.monotonic()
        _, err = proc.communicate(timeout=30)
        return proc.returncode, err, time.monotonic() - t0
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_ctrl_c_in_map_exits_130_at_once_and_writes_nothing(tmp_path):
    argv = ["map", "--nf", "401", "--ncycles", "400", "--method", "stepping", "--harmonics", "21",
            "--out", "m.csv"]  # fmt: skip
    code, err, seconds = _interrupt(tmp_path, argv)
    assert "Traceback" not in err and code == 130, err
    assert err.strip().splitlines()[-1] == "fretwear map: interrupted; nothing was written"
    assert seconds < interrupt_limit()
    assert list(tmp_path.iterdir()) == []


def test_ctrl_c_in_figures_exits_130_at_once_and_leaves_no_file(tmp_path):
    staging = lambda: any(tmp_path.glob(".figs.partial-*/*"))  # noqa: E731 - a first figure is written
    code, err, seconds = _interrupt(tmp_path, ["figures", "--out", "figs", "--harmonics", "7"], staging)
    assert "Traceback" not in err and code == 130, err
    assert seconds < interrupt_limit()
    assert list(tmp_path.iterdir()) == []


def _cpu_seconds(pid: int) -> float:
    """User + system CPU time of process ``pid`` (s), from /proc."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def test_ctrl_c_in_a_compiled_interface_wear_history_exits_130_at_once(tmp_path):
    """Issue 22: Ctrl-C was swallowed inside a compiled Newton call; the run went on and exited 0."""
    # 48 pairs: about 9 s of CPU (32 pairs, 4.9 s since the penalty continuation, ended before the signal)
    argv = ["interface", "--kw", "1e-14", "--cycles", "1e8", "--converge", "1e-3", "--contact-nodes", "48",
            "--out", "i.csv"]  # fmt: skip
    pid = []
    code, err, seconds = _interrupt(tmp_path, argv, lambda: _cpu_seconds(pid[0]) > 4.0, pid)
    assert "Traceback" not in err and code == 130, err
    assert seconds < interrupt_limit()
    assert list(tmp_path.iterdir()) == []
