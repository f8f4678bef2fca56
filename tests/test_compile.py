"""The compile notice: announced when the kernels' machine code is not cached, silent when it is."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import fretwear.compile as compiled
from fretwear import cli, paper_model, sweep

ROOT = Path(__file__).resolve().parents[1]
NOTICE = "compiling numerical kernels, first run only, about "
ASK = "import fretwear.compile as c; print(c.notice('sweep'))"


def _notice_in_new_process(env: dict) -> str:
    """What :func:`fretwear.compile.notice` says in a new interpreter (which has compiled nothing)."""
    env = {**env, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))}
    run = subprocess.run([sys.executable, "-c", ASK], env=env, cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return run.stdout.strip()


def test_a_new_process_reads_the_on_disk_cache(tmp_path):
    """Empty cache: the notice; the cache this process filled: none. Neither compiles anything."""
    empty = _notice_in_new_process({**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)})
    seconds = compiled.KERNELS["sweep"].seconds
    assert empty == NOTICE + f"{seconds:.0f} s"
    assert not list(tmp_path.rglob("*.nbc"))  # asking compiled nothing (no machine code written)
    sweep(paper_model(), 2 * np.pi * np.array([0.6, 0.7]), 3)  # compiles, or loads the cache it wrote
    assert compiled.cached("sweep")
    assert _notice_in_new_process(dict(os.environ)) == "None"


def test_notice_sums_the_pending_groups(monkeypatch):
    seconds = {name: kernel.seconds for name, kernel in compiled.KERNELS.items()}
    monkeypatch.setattr(compiled, "cached", lambda name: name == "sweep")
    assert compiled.pending() == [name for name in compiled.KERNELS if name != "sweep"]
    assert compiled.notice("sweep") is None
    assert compiled.notice("sweep", "solver") == NOTICE + f"{seconds['solver']:.0f} s"
    assert compiled.notice() == NOTICE + f"{sum(seconds.values()) - seconds['sweep']:.0f} s"
    monkeypatch.setattr(compiled, "cached", lambda name: False)
    assert compiled.notice("sweep", "solver") == NOTICE + f"{seconds['sweep'] + seconds['solver']:.0f} s"
    with pytest.raises(ValueError, match="kernel names must be among"):
        compiled.notice("nonsense")


@pytest.mark.parametrize("cache_empty", [True, False])
def test_cli_prints_the_notice_once_only_when_kernels_must_compile(monkeypatch, capsys, cache_empty):
    monkeypatch.setattr(compiled, "_in_cache", lambda dispatcher: not cache_empty)  # the cache state
    assert cli.main(["point", "--f", "0.7", "--harmonics", "3"]) == 0
    err = capsys.readouterr().err.splitlines()
    notices = [line for line in err if NOTICE in line]
    assert notices == ([f"fretwear point: {compiled.notice_for('sweep')}"] if cache_empty else [])


@pytest.mark.parametrize(
    ("argv", "needs"),
    [
        (["frf", "--fmin", "0.5", "--fmax", "0.7", "--out", "-"], ("sweep",)),
        (["frf", "--fmin", "0.5", "--fmax", "0.7", "--out", "-", "--continuation"], ("solver",)),
        (["point", "--f", "0.7", "--method", "shooting"], ("shooting",)),
        (["wear", "--f", "0.7", "--out", "-"], ("shooting",)),  # the exact answer
        (["wear", "--f", "0.7", "--out", "-", "--harmonics", "7"], ("solver", "shooting")),  # and its error
        (
            ["wear", "--f", "0.7", "--out", "-", "--method", "polynomial"],
            ("solver", "polynomial", "shooting"),
        ),
        (
            ["wear", "--f", "0.7", "--out", "-", "--method", "polynomial", "--basis", "monomial"],
            ("solver", "galerkin", "shooting"),
        ),
        (["wear", "--f", "0.7", "--out", "-", "--dynamics", "shooting"], ("shooting",)),
        (["map", "--out", "-", "--method", "exact", "--dynamics", "shooting"], ("shooting",)),
        (["wear", "--f", "0.7", "--out", "-", "--method", "time"], ("shooting", "time")),
        (["interface", "--f", "50"], ("interface",)),
        (["interface", "--static"], ()),
    ],
)
def test_each_command_announces_the_kernels_it_runs(argv, needs):
    args = cli.build_parser().parse_args(argv)
    assert cli.COMMANDS[args.command].kernel_needs(args, paper_model()) == needs


def test_warm_in_processes_runs_each_part_in_a_process_of_its_own(monkeypatch):
    """Every pending group is warmed, each part by its own process (here loading the suite's cache)."""
    monkeypatch.setattr(compiled, "pending", lambda *names: list(names))  # as on a cold cache
    done = compiled.warm_in_processes(env={**os.environ, "FRETWEAR_CACHE_DIR": ""})
    assert done == [(list(part), True) for part in compiled.PARTS]
    assert sorted(name for part in compiled.PARTS for name in part) == sorted(compiled.KERNELS)
    monkeypatch.setattr(compiled, "pending", lambda *names: [])
    assert compiled.warm_in_processes() == []


AHEAD = """
import json, numpy as np, fretwear.compile as c
from fretwear import paper_model, sweep
from fretwear.hbm import compiled_sweep as cs
c.compile_ahead("sweep")
callees = [kernel for kernel, _ in cs._callee_arguments()]
signatures = lambda: [len(kernel._cache._cache_file._load_index()) for kernel in callees]
before = signatures()
sweep(paper_model(), 2 * np.pi * np.array([0.6, 0.7]), 3)
print(json.dumps([before, signatures(), c.cached("sweep")]))
"""


@pytest.mark.slow
@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="compile_ahead splits the work over two cores")
def test_compile_ahead_caches_each_callee_once_for_the_types_the_sweep_passes(tmp_path):
    """Empty cache: both shares are compiled before the sweep runs, and the sweep compiles no callee anew.

    A callee compiled for other argument types than the sweep passes would
    leave a second signature in its cache index.
    """
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    run = subprocess.run([sys.executable, "-c", AHEAD], env=env, cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    before, after, cached = json.loads(run.stdout)
    assert before == after == [1] * len(before) and len(before) == 8
    assert cached


PROBE = """
import sys, numpy as np, fretwear.compile as c
from fretwear.hbm.condensation import condense_loop, condense_sweep
from fretwear.hbm.problem import Problem
from fretwear import paper_model
if sys.argv[1] == "run":
    p = Problem(paper_model(), 2 * np.pi * 0.7, 3)
    condense_sweep(p.model, p.B, np.array([4.0, 4.4]), p.basis)
print(c._in_cache(condense_loop))
"""


@pytest.mark.slow
def test_an_edit_of_a_callee_module_makes_its_callers_cached_code_stale(tmp_path):
    """Numba stamps a kernel's cache with its own file; fretwear adds the sources of every kernel module.

    ``condense_loop`` (hbm/condensation.py) calls ``lu_factor`` (hbm/dense.py):
    an edit of dense.py alone must make its cached machine code stale, an
    edit of a module without kernels must not.
    """
    src = tmp_path / "src"
    shutil.copytree(ROOT / "fretwear", src / "fretwear", ignore=shutil.ignore_patterns("__pycache__"))
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH": str(src)}

    def probe(*args: str) -> str:
        run = subprocess.run([sys.executable, "-c", PROBE, *args], env=env, cwd=tmp_path, capture_output=True,
                             text=True)  # fmt: skip
        assert run.returncode == 0, run.stderr
        return run.stdout.strip()

    assert probe("ask") == "False"  # an empty cache
    assert probe("run") == "True"  # compiled and cached
    with open(src / "fretwear" / "cli" / "shared.py", "a") as f:
        f.write("\n# an edit of a module without kernels\n")
    assert probe("ask") == "True"
    with open(src / "fretwear" / "hbm" / "dense.py", "a") as f:
        f.write("\n# an edit of the callee's module only\n")
    assert probe("ask") == "False"


EVERY_GROUP = """
import json, fretwear.compile as c
missed = {}
for name, kernel in c.KERNELS.items():
    kernel.run()
    missed[name] = [e for e in kernel.entry_points if not c._dispatcher(e).overloads]
print(json.dumps(missed))
"""


def test_each_groups_run_calls_every_entry_point_it_lists():
    """A new process: after each group's run, each of its entry points has machine code (compiled or
    loaded). An entry point the run never calls would stay uncached after a warm-up, its group's
    notice shown at every first run, and its compilation left to the user's first computation."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    command = [sys.executable, "-c", EVERY_GROUP]
    run = subprocess.run(command, env=env, cwd=ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout.splitlines()[-1]) == dict.fromkeys(compiled.KERNELS, [])
