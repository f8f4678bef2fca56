"""Command line: ``fretwear frf``, ``linear``, ``point``, ``wear``, ``map``, ``cost``, ``figures``, ``study``,
``interface``.

The commands are thin wrappers around the library's front functions, the same
the dashboard and the benchmarks call (:func:`fretwear.sweep`,
:func:`fretwear.continuation`, :func:`fretwear.linear_frf`,
:func:`fretwear.solve_periodic`, :func:`fretwear.shooting`,
:func:`fretwear.wear_history`, :func:`fretwear.wear_map`,
:func:`fretwear.cost_ladder`; ``figures`` draws with :mod:`fretwear.figures`).
Frequencies are given and written in Hz (the library works in rad/s); every
other quantity is SI (m, N, N/m, J).

The model is the 2-DOF example of the paper (:func:`fretwear.paper_model`,
options ``--fex --mu --fn --kn --u0``) or a TOML model file (``--model``, see
:mod:`fretwear.model.modelfile`).

Output columns (CSV) and keys (JSON)
------------------------------------
``f_hz``
    Excitation frequency (Hz).
``x{i}_h1``, ``x{i}_half_p2p``
    First-harmonic amplitude and half peak-to-peak displacement (m) of DOF
    ``i`` (from 1).
``xr_h1``, ``xr_half_p2p`` (paper model) or ``xr{j}_h1``, ``xr{j}_half_p2p`` (model file)
    The same for the relative displacement of contact ``j`` (from 1, friction
    contacts first); for the paper model ``xr = x1 - x2``.
``sliding_distance``, ``friction_energy`` (or ``...{j}`` per friction contact of a model file)
    Distance slid (m) and energy dissipated (J) per period.
``converged``, ``residual``, ``iterations``, ``path``, ``message``
    Solver status: relative residual, Newton iterations, solution path
    (``linear-stuck``, ``dlft``, ...) and the reason of a failure.
``state`` (``linear`` only)
    ``stuck`` or ``open``; a linear response is sinusoidal, so ``h1`` and
    ``half_p2p`` are both the modulus of the complex amplitude.

Exit status
-----------
0 when every result converged; 1 on an internal error (a bug: one line names
the command and the error, never a traceback); 2 on bad input or an output
that cannot be written (a one-line message on stderr names the option, its
valid range from :mod:`fretwear.parameters` and the value), checked before any
work starts; 3 when some result did not converge or is incomplete (its row is
still written, with ``converged=False`` and its residual) or a continuation
stopped before the end of the band; 130 when interrupted (Ctrl-C): nothing
partial is written (files are renamed into place when whole), and ``study``
resumes when rerun.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import json
import os
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import compile as compiled
from .arguments import atomic, check_output, document, number, remove_partial, staged_folder
from .hbm.continuation import continuation, sweep
from .hbm.linear import linear_frf
from .hbm.periodic import solve_periodic
from .hbm.solution import PeriodicSolution
from .interface import cli as interface_command
from .model import Model, paper_model
from .model.modelfile import example_names, example_path, read_model_file
from .studies import study as study_command
from .studies import wear_map
from .studies.accuracy import QUANTITIES, cost_ladder
from .studies.maps import LazyHistories
from .time import ShootingSolution, shooting, shooting_sweep
from .wear import (
    DYNAMICS,
    METHODS,
    cycle_grid,
    exact_answer_applies,
    method_options,
    resolve_dynamics,
    resolve_method,
    wear_history,
)
from .wear.polynomial import BASES

__all__ = [
    "main",
    "build_parser",
    "EXIT_OK",
    "EXIT_ERROR",
    "EXIT_USAGE",
    "EXIT_NOT_CONVERGED",
    "EXIT_INTERRUPTED",
]

#: exit statuses: every result converged; an internal error; bad input; some result did not converge or is
#: incomplete; interrupted (Ctrl-C)
EXIT_OK, EXIT_ERROR, EXIT_USAGE, EXIT_NOT_CONVERGED, EXIT_INTERRUPTED = 0, 1, 2, 3, 130

#: the paper's values (section 2.1) of the paper-model options
PAPER_DEFAULTS = {"fex": 10.0, "mu": 1.0, "fn": 10.0, "kn": 1e7}
_PAPER_OPTIONS = ("fex", "mu", "fn", "kn", "u0")


class UsageError(Exception):
    """Bad command-line input; the message names the option and its valid range."""


class _Parser(argparse.ArgumentParser):
    """Argument parser whose errors are one line on stderr and exit status 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def _add_model_options(parser: argparse.ArgumentParser) -> None:
    """``--model`` or the paper-model options ``--fex --mu --fn/--u0 --kn``."""
    group = parser.add_argument_group(
        "model", "the paper's 2-DOF example (section 2.1) with the options below, or --model FILE"
    )
    group.add_argument(
        "--model",
        metavar="FILE",
        help="TOML model file (format: fretwear.model.modelfile) or a bundled example: "
        + ", ".join(example_names())
        + "; excludes the paper-model options",
    )
    group.add_argument("--fex", type=number("fex"), help="excitation amplitude on mass 1 (N); default 10")
    group.add_argument("--mu", type=number("mu"), help="friction coefficient (-); default 1")
    load = group.add_mutually_exclusive_group()
    load.add_argument("--fn", type=number("fn"), help="normal load F_N (N); default 10")
    load.add_argument(
        "--u0",
        type=number("u0"),
        help="normal interference u0 (m), instead of --fn: F_N = kn u0",
    )
    group.add_argument(
        "--kn",
        type=number("kn"),
        help="normal contact stiffness (N/m); default 1e7",
    )


def _add_solver_options(parser: argparse.ArgumentParser, default: int | None = 7) -> None:
    """``--harmonics`` and ``--samples`` (``default``: of ``--harmonics``; None: the exact dynamics)."""
    parser.add_argument(
        "--harmonics",
        type=number("harmonics"),
        default=default,
        metavar="NH",
        help="highest harmonic Nh (-); default 7"
        if default
        else "highest harmonic Nh (-) of the DLFT dynamics (giving it asks for them); "
        "default: the exact dynamics where they apply, else Nh = 21 (polynomial: 3)",
    )
    parser.add_argument(
        "--samples",
        type=number("samples"),
        metavar="N",
        help="time samples per period N (-), at least 2 Nh + 1; default: next power of 2 >= 16 Nh",
    )


def _add_band_options(parser: argparse.ArgumentParser) -> None:
    """``--fmin --fmax --n --out``."""
    parser.add_argument(
        "--fmin",
        type=number("fmin"),
        help="lowest frequency (Hz); default 0.3 with the paper model, required with --model",
    )
    parser.add_argument("--fmax", type=number("fmax"),
                        help="highest frequency (Hz), not below --fmin; default 1.3 with the paper model, "
                        "required with --model")  # fmt: skip
    parser.add_argument(
        "--n",
        type=number("n"),
        default=101,
        help="number of equally spaced frequencies (-); default 101",
    )
    parser.add_argument("--out", required=True, metavar="FILE.csv", help="CSV file to write ('-': stdout)")


def build_parser() -> argparse.ArgumentParser:
    """The ``fretwear`` argument parser and its subcommands."""
    parser = _Parser(
        prog="fretwear",
        description="Periodic response of structures with dry-friction contacts (HBM + DLFT). "
        "Frequencies in Hz, everything else in SI units.",
        epilog="Exit status: 0 every result converged; 1 internal error (a bug, one line on stderr); "
        "2 bad input or an output that cannot be written (one line names the option, its valid range and "
        "the value), checked before any work; 3 some result did not converge or is incomplete (its row is "
        "still written, with converged=False); 130 interrupted by Ctrl-C (nothing partial is written; "
        "study resumes when rerun).",
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    parser.commands = commands.choices  # type: ignore[attr-defined]  # name -> subcommand parser

    frf = commands.add_parser(
        "frf",
        help="nonlinear frequency response (CSV)",
        description="Nonlinear frequency response by HBM + DLFT, written as CSV (one row per frequency).",
    )
    _add_model_options(frf)
    _add_band_options(frf)
    _add_solver_options(frf)
    _add_method_option(frf)
    frf.add_argument(
        "--continuation",
        action="store_true",
        help="follow the branch by arc-length continuation from --fmin to --fmax, through folds: "
        "rows are the branch points in arc-length order (--n is then unused)",
    )

    linear = commands.add_parser(
        "linear",
        help="linear FRFs with every contact stuck or open (CSV)",
        description="Linear frequency responses with every contact stuck (rigid) or open, written as CSV.",
    )
    _add_model_options(linear)
    _add_band_options(linear)
    linear.add_argument(
        "--state",
        choices=("stuck", "open", "both"),
        default="both",
        help="contact state; default both (stuck rows first)",
    )

    point = commands.add_parser(
        "point",
        help="response at one frequency (JSON on stdout)",
        description="Periodic response at one frequency, printed as JSON.",
    )
    point.add_argument(
        "--f",
        type=number("f"),
        required=True,
        metavar="HZ",
        help="excitation frequency (Hz)",
    )
    _add_model_options(point)
    _add_solver_options(point)
    _add_method_option(point)

    wear = commands.add_parser(
        "wear",
        help="wear evolution at one frequency (CSV)",
        description="Fretting wear w(N) over the cycle count N at one frequency, by slow-time stepping, "
        "the polynomial slow-time DLFT or direct time integration, written as CSV.",
    )
    wear.add_argument("--f", type=number("f"), required=True, metavar="HZ",
                      help="excitation frequency (Hz)")  # fmt: skip
    _add_model_options(wear)
    _add_wear_options(wear)
    wear.add_argument(
        "--out",
        required=True,
        metavar="FILE.csv",
        help="CSV file to write ('-': stdout), or the figure of w(N): .png, .svg, .html",
    )

    wmap = commands.add_parser(
        "map",
        help="wear map over frequency x cycles (CSV long format, NPZ, or the figure)",
        description="Wear map W(f, N) (paper Fig. 7) with the response, over linspace(fmin, fmax, nf) "
        "and the cycle counts 0 then ncycles - 1 log-spaced over the four decades up to --cycles (the "
        "dashboard's grid). CSV long format (f_hz, cycles, w, ...), NumPy NPZ arrays when --out ends in "
        ".npz, or the figure when it ends in .png, .svg or .html (with its parameters as caption).",
    )
    _add_model_options(wmap)
    wmap.add_argument(
        "--fmin",
        type=number("fmin"),
        help="lowest frequency (Hz); default 0.3 with the paper model, required with --model",
    )
    wmap.add_argument("--fmax", type=number("fmax"),
                      help="highest frequency (Hz), not below --fmin; default 1.3 with the paper model, "
                      "required with --model")  # fmt: skip
    wmap.add_argument("--nf", type=number("nf"), default=41,
                      help="number of frequencies (-); default 41")  # fmt: skip
    wmap.add_argument("--ncycles", type=number("ncycles"), default=60,
                      help="number of log-spaced cycle counts (-); default 60")  # fmt: skip
    _add_wear_options(wmap)
    wmap.add_argument("--out", required=True, metavar="FILE",
                      help="CSV (long format), .npz, or a figure: .png, .svg, .html")  # fmt: skip
    cost = commands.add_parser(
        "cost",
        help="what accuracy costs: error vs wall time over a ladder of settings (CSV)",
        description="Runs a ladder of discretisations (Nh, samples, slow-time tolerance, polynomial degree, "
        "methods) at one frequency against a converged reference (shooting; with --kw and --cycles also "
        "w(N) against stepping with shooting dynamics) and writes error vs wall time per rung.",
    )
    cost.add_argument("--f", type=number("f"), required=True, metavar="HZ",
                      help="excitation frequency (Hz)")  # fmt: skip
    _add_model_options(cost)
    cost.add_argument("--kw", type=number("kw"), help="Archard coefficient (1/N): adds wear rungs")
    cost.add_argument("--cycles", type=number("cycles"), help="wear horizon (cycles), with --kw")
    cost.add_argument("--target", type=number("target"), default=1e-2,
                      help="target relative error for the recommendation (-); default 1e-2")  # fmt: skip
    cost.add_argument("--quick", action="store_true", help="a shorter ladder")
    cost.add_argument("--out", required=True, metavar="FILE.csv", help="CSV file to write ('-': stdout)")

    figures = commands.add_parser(
        "figures",
        help="the paper's figure set (Fig. 5-14 equivalents), headless",
        description="Computes the paper's figures 5-14 for the 2-DOF example and writes figNN.{png,svg,csv} "
        "(and .html with --formats) to --out. Needs matplotlib and holoviews (installed with fretwear).",
    )
    figures.add_argument("--out", required=True, metavar="DIR", help="folder to write (created if missing)")
    figures.add_argument("--harmonics", type=number("harmonics"), default=21, metavar="NH",
                         help="highest harmonic Nh (-); default 21")  # fmt: skip
    figures.add_argument("--kw", type=number("kw"), default=1e-11,
                         help="Archard coefficient K_w (1/N); default 1e-11")  # fmt: skip
    figures.add_argument("--cycles", type=number("cycles"), default=1e5,
                         help="wear horizon (cycles); default 1e5")  # fmt: skip
    figures.add_argument("--nf", type=number("nf", low=2), default=41,
                         help="frequencies of the maps (-); default 41")  # fmt: skip
    figures.add_argument("--ncycles", type=number("ncycles", low=3), default=60,
                         help="cycle counts of the maps (-); default 60")  # fmt: skip
    figures.add_argument("--fmin", type=number("fmin"), default=0.3,
                         help="lowest frequency (Hz); default 0.3")  # fmt: skip
    figures.add_argument("--fmax", type=number("fmax"), default=1.3,
                         help="highest frequency (Hz), above --fmin; default 1.3")  # fmt: skip
    figures.add_argument(
        "--f",
        type=number("f"),
        default=0.7,
        metavar="HZ",
        help="frequency of the wear histories of Fig. 10 and 11 (Hz); default 0.7",
    )
    figures.add_argument("--method", choices=("auto", *METHODS), default="auto",
                         help="slow-time method of the wear maps; default auto (exact)")  # fmt: skip
    figures.add_argument(
        "--tol",
        type=number("tol"),
        default=1e-3,
        help="tolerance of stepping and time integration (fraction of u0); default 1e-3",
    )
    figures.add_argument(
        "--degree",
        type=number("degree"),
        default=4,
        help="degree of the polynomial method (Fig. 11, 12, 14); default 4",
    )
    figures.add_argument("--formats", default="png,svg,csv",
                         help="formats, comma-separated: png, svg, html, csv")  # fmt: skip
    figures.add_argument("--width", type=number("width"),
                         help="figure width (in); default: each figure's own")  # fmt: skip
    figures.add_argument("--height", type=number("height"),
                         help="figure height (in); default: each figure's own")  # fmt: skip
    figures.add_argument(
        "--dpi",
        type=number("dpi"),
        default=120,
        help="resolution of the PNG files (dots per inch); default 120",
    )
    figures.add_argument(
        "--fontsize",
        type=number("fontsize"),
        help="font size of the axis labels (pt); default Matplotlib's",
    )

    for name in ("frf", "linear", "point", "wear", "map", "cost", "figures"):
        _add_settings_option(commands.choices[name])
    interface_command.add_arguments(
        commands.add_parser(
            "interface",
            help="a contact interface of many nodes: cylinder on flat, or an interface model file",
            description="The cylinder-on-flat fretting benchmark (2-D plane strain, scikit-fem) or an "
            "interface model file: the quasi-static limit (--static, JSON), one periodic solve, or a "
            "wear history with pressure redistribution (CSV, one row per record and contact node).",
        )
    )
    study_command.add_arguments(
        commands.add_parser(
            "study",
            help="parameter study on Dask, results in Zarr",
            description="Runs the parameter study of a TOML spec on a Dask cluster (local by default) and "
            "writes an xarray Dataset to a Zarr store, chunk by chunk; rerun the same command to finish "
            "an interrupted study. Read the result with xarray.open_zarr(RESULT).",
        )
    )
    for sub in commands.choices.values():
        document(sub)
    return parser


def _add_settings_option(parser: argparse.ArgumentParser) -> None:
    """``--settings FILE``: defaults of the options from a settings file of the dashboard."""
    parser.add_argument(
        "--settings",
        metavar="FILE",
        help="JSON settings file saved by the dashboard (or written by hand: keys named like these "
        'options, e.g. {"fex": 14, "mu": 0.8, "kw": 1e-10}): the values of the options it names '
        "that this command takes; options given here win, the other keys are ignored",
    )


#: settings-file keys (fretwear.figures.record) that are options of the commands, by option dest
_SETTINGS_DESTS = ("fex", "mu", "fn", "kw", "cycles", "harmonics", "method", "dynamics", "degree", "tol",
                   "fmin", "fmax", "nf", "ncycles", "f", "target")  # fmt: skip


def _on_command_line(action: argparse.Action, argv: Sequence[str]) -> bool:
    return any(a == o or a.startswith(o + "=") for a in argv for o in action.option_strings)


def _settings_path(argv: Sequence[str]) -> str | None:
    for i, arg in enumerate(argv):
        if arg == "--settings" and i + 1 < len(argv):
            return argv[i + 1]
        if arg.startswith("--settings="):
            return arg.split("=", 1)[1]
    return None


def _apply_settings(parser: argparse.ArgumentParser, argv: Sequence[str]) -> None:
    """Make the values of the ``--settings`` file the defaults of the command's options.

    Each value goes through its option's own check (an invalid one is a usage
    error naming the option and the file). The slow-time method applies to the
    commands whose ``--method`` is one; ``kw`` and ``cycles`` to ``cost`` only
    when the file asks for the wear rungs (``"rungs": true``). Options given on
    the command line win. The command remembers which options came from the file
    (``args.from_settings``): a slow-time option the method does not take is then
    left out, not an error.
    """
    path = _settings_path(argv)
    command = next((a for a in argv if a in parser.commands), None)  # type: ignore[attr-defined]
    if path is None or command is None:
        return
    from .figures.record import read_settings

    try:
        record = read_settings(path)
    except ValueError as exc:
        raise UsageError(f"argument --settings: {exc}") from None
    sub = parser.commands[command]  # type: ignore[attr-defined]
    taken = []
    for action in sub._actions:
        key = action.dest
        if key not in _SETTINGS_DESTS or key not in record or _on_command_line(action, argv):
            continue
        if command == "cost" and key in ("kw", "cycles") and not record.get("rungs", False):
            continue
        value = record[key]
        if key == "method" and action.choices is not None and value not in action.choices:
            continue  # a slow-time method; this command's --method is the periodic solver
        flag = action.option_strings[0]
        text = repr(value) if isinstance(value, float) else str(value)
        try:
            converted = action.type(text) if action.type is not None else text
        except argparse.ArgumentTypeError as exc:
            raise UsageError(f"argument {flag} (from --settings {Path(path).name}): {exc}") from None
        if action.choices is not None and converted not in action.choices:
            raise UsageError(f"argument {flag} (from --settings {Path(path).name}): must be one of "
                             f"{', '.join(map(str, action.choices))}, got {converted!r}")  # fmt: skip
        action.default, action.required = converted, False
        taken.append(key)
    sub.set_defaults(from_settings=tuple(taken))


def _add_method_option(parser: argparse.ArgumentParser) -> None:
    """``--method {dlft,shooting}`` of the periodic solver."""
    parser.add_argument(
        "--method",
        choices=("dlft", "shooting"),
        default="dlft",
        help="periodic solver: HBM + DLFT (default) or shooting on the exact event-driven time "
        "integrator (no truncation error; needs a positive definite mass matrix)",
    )


def _add_wear_options(parser: argparse.ArgumentParser) -> None:
    """Slow-time options of ``wear`` and ``map``."""
    parser.add_argument("--kw", type=number("kw"), default=1e-11,
                        help="Archard coefficient K_w (1/N); default 1e-11")  # fmt: skip
    parser.add_argument("--cycles", type=number("cycles"), default=1e5,
                        help="horizon: number of vibration cycles N (-); default 1e5")  # fmt: skip
    parser.add_argument("--method", choices=("auto", *METHODS), default="auto",
                        help="slow-time method: "
                        + "; ".join(f"{m.name}: {m.title}" for m in METHODS.values())
                        + "; auto (default): exact when it applies, else stepping")  # fmt: skip
    parser.add_argument("--dynamics", choices=DYNAMICS,
                        help="periodic dynamics of the exact and stepping methods: shooting (the exact "
                        "event-driven dynamics) or dlft (HBM + DLFT, an approximation); auto (default): "
                        "shooting where it applies (friction contacts only) unless --harmonics or "
                        "--samples ask for harmonic balance")  # fmt: skip
    _add_solver_options(parser, default=None)
    parser.add_argument("--degree", type=number("degree"),
                        help="degree m of the polynomial method (-); default 4")  # fmt: skip
    parser.add_argument("--basis", choices=BASES,
                        help="slow-time basis of the polynomial method; default saturating")  # fmt: skip
    parser.add_argument("--tol", type=number("tol"),
                        help="local error tolerance on w/u0 of stepping and of the cycle jumps of time "
                        "integration (-); default 1e-3")  # fmt: skip
    parser.add_argument("--fixed-step", type=number("fixed_step"), metavar="DN",
                        help="stepping with a fixed step of DN cycles (explicit Euler; 1 = the paper's "
                        "per-period update, eq. 24) instead of the adaptive pair")  # fmt: skip


# -- model and checks ---------------------------------------------------------
@dataclass(frozen=True)
class _Names:
    """Column-name stems: DOFs, contacts and the suffixes of the friction-contact columns."""

    dofs: tuple[str, ...]
    contacts: tuple[str, ...]
    friction: tuple[str, ...]


def _model(args: argparse.Namespace) -> tuple[Model, _Names]:
    """The model selected by the options, and its column names."""
    given = [f"--{name}" for name in _PAPER_OPTIONS if getattr(args, name) is not None]
    if args.model is not None:
        if given:
            raise UsageError(f"argument --model: not allowed with the paper-model options {', '.join(given)}")
        path = Path(args.model)
        if not path.exists() and args.model.removesuffix(".toml") in example_names():
            path = example_path(args.model)
        try:
            model = read_model_file(path).model
        except ValueError as exc:
            raise UsageError(f"argument --model: {exc}") from None
        n, nc, nf = model.n_dofs, len(model.contacts), len(model.friction)
        return model, _Names(
            tuple(f"x{i}" for i in range(1, n + 1)),
            tuple(f"xr{j}" for j in range(1, nc + 1)),
            tuple(str(j) for j in range(1, nf + 1)),
        )
    values = {
        name: PAPER_DEFAULTS[name] if getattr(args, name) is None else getattr(args, name)
        for name in PAPER_DEFAULTS
    }
    kn = values["kn"]
    fn = values["fn"] if args.u0 is None else kn * args.u0
    model = paper_model(fex=values["fex"], mu=values["mu"], normal_load=fn, kn=kn)
    return model, _Names(dofs=("x1", "x2"), contacts=("xr",), friction=("",))


#: the paper model's band (Hz), the --fmin / --fmax of frf, linear and map without --model: its two modes
PAPER_BAND = (0.3, 1.3)

#: the suffixes of --out that each command writes ("-" is stdout for the CSV ones)
OUT_SUFFIXES = {
    "frf": (".csv",),
    "linear": (".csv",),
    "cost": (".csv",),
    "interface": (".csv", ".json"),  # .json: the quasi-static limit (--static)
    "wear": (".csv", *(".png", ".svg", ".html")),
    "map": (".csv", ".npz", ".png", ".svg", ".html"),
}


def _check(args: argparse.Namespace) -> None:
    """Checks that involve several options, and the output path, before any work."""
    if hasattr(args, "fmin") and args.command != "figures":
        for name, default in zip(("fmin", "fmax"), PAPER_BAND, strict=True):
            if getattr(args, name) is None:
                if args.model is not None:
                    band = f"{PAPER_BAND[0]:g}-{PAPER_BAND[1]:g} Hz"
                    raise UsageError(f"argument --{name}: required with --model (default {band} without)")
                setattr(args, name, default)
    if getattr(args, "fmax", None) is not None:
        strict = args.command == "figures" or getattr(args, "continuation", False)
        if args.fmax < args.fmin or (strict and args.fmax == args.fmin):
            raise UsageError(f"argument --fmax: must be {'>' if strict else '>='} --fmin = {args.fmin:g} Hz, "
                             f"got {args.fmax:g}")  # fmt: skip
    out = getattr(args, "out", None)
    if args.command == "figures":
        _formats(args.formats)
    if out not in (None, "-") and args.command != "study":
        try:
            check_output(out, OUT_SUFFIXES.get(args.command, ()), folder=args.command == "figures")
        except ValueError as exc:
            raise UsageError(f"argument --out: {exc}") from None
    if getattr(args, "samples", None) is not None and args.samples < 2 * args.harmonics + 1:
        raise UsageError(
            f"argument --samples: must be >= 2 Nh + 1 = {2 * args.harmonics + 1} "
            f"for --harmonics {args.harmonics}, got {args.samples}"
        )


# -- records -----------------------------------------------------------------------
def _record(sol: PeriodicSolution | ShootingSolution, names: _Names, model: Model) -> dict:
    """CSV row / JSON object of one periodic solution (HBM + DLFT or shooting: the same attributes)."""
    rel_amp, path, message = sol.relative_amplitude, sol.path, sol.message
    row: dict = {"f_hz": float(sol.omega / (2 * np.pi))}
    for name, h1, p2p in zip(names.dofs, sol.amplitude, sol.half_peak_to_peak, strict=True):
        row[f"{name}_h1"], row[f"{name}_half_p2p"] = float(h1), float(p2p)
    for name, h1, p2p in zip(names.contacts, rel_amp, sol.relative_half_peak_to_peak, strict=True):
        row[f"{name}_h1"], row[f"{name}_half_p2p"] = float(h1), float(p2p)
    for suffix, dist, energy in zip(names.friction, sol.sliding_distance, sol.friction_energy, strict=True):
        row[f"sliding_distance{suffix}"], row[f"friction_energy{suffix}"] = float(dist), float(energy)
    row.update(
        converged=bool(sol.converged),
        residual=float(sol.residual),
        iterations=int(sol.iterations),
        path=path,
        message=message,
    )
    return row


def _linear_records(model: Model, names: _Names, freqs: np.ndarray, states: Sequence[str]) -> list[dict]:
    """CSV rows of the linear FRFs at ``freqs`` (Hz), one block per contact state."""
    rows = []
    B = model.relative_map()
    for state in states:
        U = linear_frf(model, 2 * np.pi * freqs, state=state)
        dof_amp, rel_amp = np.abs(U), np.abs(U @ B.T)
        for f, u, r in zip(freqs, dof_amp, rel_amp, strict=True):
            row: dict = {"f_hz": float(f), "state": state}
            for stems, amps in ((names.dofs, u), (names.contacts, r)):
                for name, a in zip(stems, amps, strict=True):
                    row[f"{name}_h1"] = row[f"{name}_half_p2p"] = float(a)
            rows.append(row)
    return rows


def _write_csv(rows: Iterable[dict], out: str) -> None:
    """Write ``rows`` (dicts with the same keys) as CSV to the file ``out`` or, for ``-``, to stdout.

    A file is written under a temporary name and renamed when whole (:func:`fretwear.arguments.atomic`).
    """
    rows = list(rows)
    if out == "-":
        _csv_to(sys.stdout, rows)
        return
    with atomic(out) as temp, open(temp, "w", newline="", encoding="utf-8") as fh:
        _csv_to(fh, rows)


def _csv_to(fh, rows: list[dict]) -> None:
    writer = csv.DictWriter(fh, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)


# -- commands -----------------------------------------------------------------------
def _frf(args: argparse.Namespace, model: Model, names: _Names) -> int:
    """``fretwear frf``: sweep or arc-length continuation, one CSV row per solution."""
    complete, note = True, ""
    if args.method == "shooting":
        if args.continuation:
            raise UsageError("argument --continuation: not available with --method shooting")
        omegas = 2 * np.pi * np.linspace(args.fmin, args.fmax, args.n)
        solutions = shooting_sweep(model, omegas)
    elif args.continuation:
        band = 2 * np.pi * args.fmin, 2 * np.pi * args.fmax
        branch = continuation(model, *band, args.harmonics, samples=args.samples)
        solutions, complete = branch.solutions, branch.converged
        if not complete:
            note = f"; continuation stopped at {solutions[-1].frequency:g} Hz: {branch.message}"
    else:
        omegas = 2 * np.pi * np.linspace(args.fmin, args.fmax, args.n)
        solutions = sweep(model, omegas, args.harmonics, samples=args.samples).solutions
    _write_csv((_record(s, names, model) for s in solutions), args.out)
    failed = sum(not s.converged for s in solutions)
    worst = max(s.residual for s in solutions)
    print(
        f"fretwear frf: {len(solutions)} points, {len(solutions) - failed} converged, {failed} not converged "
        f"(largest residual {worst:.3g}){note}; wrote {args.out}",
        file=sys.stderr,
    )
    return EXIT_OK if complete and not failed else EXIT_NOT_CONVERGED


def _linear(args: argparse.Namespace, model: Model, names: _Names) -> int:
    """``fretwear linear``: stuck and/or open linear FRFs as CSV."""
    states = ("stuck", "open") if args.state == "both" else (args.state,)
    rows = _linear_records(model, names, np.linspace(args.fmin, args.fmax, args.n), states)
    _write_csv(rows, args.out)
    print(f"fretwear linear: {len(rows)} rows ({', '.join(states)}); wrote {args.out}", file=sys.stderr)
    return EXIT_OK


def _point(args: argparse.Namespace, model: Model, names: _Names) -> int:
    """``fretwear point``: one periodic solve, JSON on stdout."""
    omega = 2 * np.pi * args.f
    if args.method == "shooting":
        sol = shooting(model, omega)
        record = _record(sol, names, model)
        record.update(omega_rad_s=float(omega), input_work=float(sol.input_work),
                      viscous_dissipation=float(sol.viscous_dissipation),
                      floquet_max=float(np.abs(sol.floquet_multipliers).max()),
                      stable=bool(sol.stable))  # fmt: skip
    else:
        sol = solve_periodic(model, omega, args.harmonics, samples=args.samples)
        record = _record(sol, names, model)
        record.update(
            omega_rad_s=float(sol.omega),
            harmonics=int(sol.harmonics),
            samples=int(sol.samples),
            half_wave=bool(sol.half_wave),
            input_work=float(sol.input_work),
            viscous_dissipation=float(sol.viscous_dissipation),
            contact_work=float(sol.contact_work),
        )
    json.dump(record, sys.stdout, indent=2)
    sys.stdout.write("\n")
    status = "converged" if sol.converged else f"NOT converged ({record['message']})"
    print(f"fretwear point: {status}, residual {sol.residual:.3g}, path {record['path']}", file=sys.stderr)
    return EXIT_OK if sol.converged else EXIT_NOT_CONVERGED


#: slow-time options of ``wear`` and ``map`` that only some methods take (registry: fretwear.wear.METHODS)
_METHOD_OPTIONS = ("dynamics", "degree", "basis", "tol", "fixed_step")


def _wear_options(args: argparse.Namespace, model: Model) -> tuple[str, dict]:
    """The slow-time method that will run and its options; a given option it does not take is an error."""
    if args.degree is not None and args.degree > 12:
        raise UsageError(f"argument --degree: must be an integer in [1, 12], got {args.degree}")
    if args.tol is not None and not 0 < args.tol < 1:
        raise UsageError(f"argument --tol: must be in (0, 1), got {args.tol:g}")
    method = resolve_method(model, args.method, args.fixed_step)
    given = {k: getattr(args, k) for k in _METHOD_OPTIONS if getattr(args, k) is not None}
    from_file = getattr(args, "from_settings", ())
    given = {k: v for k, v in given.items() if k in METHODS[method].options or k not in from_file}
    unused = [k for k in given if k not in METHODS[method].options]
    if unused:
        flags = ", ".join("--" + k.replace("_", "-") for k in unused)
        raise UsageError(f"argument {flags}: not taken by method {method!r} "
                         f"(it takes {', '.join(METHODS[method].options)})")  # fmt: skip
    settings = {"harmonics": args.harmonics, "samples": args.samples, **given}
    if given.get("dynamics") == "shooting" and "harmonics" in from_file:  # the app's Nh is for its DLFT parts
        settings["harmonics"] = None
    return method, method_options(method, settings)


_FIGURE_SUFFIXES = (".png", ".svg", ".html")


def _stamp(args: argparse.Namespace, method: str, options: dict) -> tuple[dict, str]:
    """The parameter record (and model) of a figure of ``wear`` or ``map``."""
    from .figures.record import MODEL

    values = {"kw": args.kw, "cycles": args.cycles, "method": method, **options}
    if args.model is None:
        values |= {"fex": args.fex or PAPER_DEFAULTS["fex"], "mu": args.mu or PAPER_DEFAULTS["mu"]}
        values["fn"] = args.fn if args.fn is not None else PAPER_DEFAULTS["fn"]
        kn = args.kn or PAPER_DEFAULTS["kn"]
        return values, MODEL if kn == PAPER_DEFAULTS["kn"] else MODEL.replace("1e7", f"{kn:g}")
    return values, f"model file {Path(args.model).name}"


def _write_figure(fig, args: argparse.Namespace, method: str, options: dict, **extra) -> None:
    from .figures import caption, save_figure

    values, model = _stamp(args, method, options)
    with atomic(args.out) as temp:
        save_figure(fig, temp, caption=lambda markup: caption({**values, **extra}, model, markup))


def _say_warnings(command: str, notes: Iterable[str], caught: list, limit: int = 3) -> None:
    """Print the wear histories' ``notes`` (at most ``limit``, the rest counted), then the ``caught``
    Python warnings they do not already say, one line each (never Python's ``file:line`` format)."""
    notes = list(dict.fromkeys(notes))
    for note in notes[:limit]:
        print(f"fretwear {command}: warning: {note}", file=sys.stderr)
    if len(notes) > limit:
        print(f"fretwear {command}: warning: and {len(notes) - limit} more of the same kind", file=sys.stderr)
    said = " ".join(notes)
    for message in dict.fromkeys(" ".join(str(w.message).split()) for w in caught):
        if message not in said:
            print(f"fretwear {command}: warning: {message}", file=sys.stderr)


def _wear(args: argparse.Namespace, model: Model, names: _Names) -> int:
    """``fretwear wear``: one wear history as CSV, one row per record (or its figure)."""
    method, options = _wear_options(args, model)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        hist = wear_history(model, 2 * np.pi * args.f, method, kw=args.kw, cycles=args.cycles, **options)
    if hist.label != "exact" and args.kw > 0 and exact_answer_applies(model):  # an approximation
        with warnings.catch_warnings():  # the reference's warnings repeat those of the approximation
            warnings.simplefilter("ignore")
            exact = wear_history(model, 2 * np.pi * args.f, "exact", kw=args.kw, cycles=args.cycles)
        hist.warnings.insert(0, hist.error_note(exact) or "its error against the exact answer is unknown")
    _say_warnings("wear", hist.warnings, caught)
    if args.out.lower().endswith(_FIGURE_SUFFIXES):
        from .figures import line_figure, load_backend, wear_curve

        load_backend("bokeh" if args.out.lower().endswith(".html") else "matplotlib")
        curve = wear_curve(hist, cycle_grid(args.cycles))
        fig = line_figure(
            {"wear history": curve},
            xlabel="cycles N",
            ylabel="w / u₀",
            logx=True,
            padding=0.05,
            title=f"Wear history at {args.f:.4g} Hz ({hist.label})",
        )
        _write_figure(fig, args, hist.method, options, f=args.f)
        print(f"fretwear wear: {hist.label}, status {hist.status}; wrote {args.out}", file=sys.stderr)
        return EXIT_OK if hist.converged else EXIT_NOT_CONVERGED
    rows = []
    for k, N in enumerate(hist.cycles):
        row: dict = {"cycles": float(N)}
        for j, suffix in enumerate(names.friction):
            row[f"w{suffix}"] = float(hist.wear[k, j])
            row[f"w{suffix}_over_u0"] = float(hist.wear_fraction[k, j])
            row[f"fn{suffix}"] = float(hist.normal_load[k, j])
            row[f"dw_dn{suffix}"] = float(hist.rate[k, j])
            row[f"sliding_distance{suffix}"] = float(hist.sliding_distance[k, j])
        for i, name in enumerate(names.dofs):
            row[f"{name}_h1"] = float(hist.amplitude[k, i])
            row[f"{name}_half_p2p"] = float(hist.half_peak_to_peak[k, i])
        for j, name in enumerate(names.contacts):
            row[f"{name}_half_p2p"] = float(hist.relative_half_peak_to_peak[k, j])
        rows.append(row)
    _write_csv(rows, args.out)
    print(f"fretwear wear: {hist.label}, {len(rows)} records to N = {hist.cycles[-1]:g}, "
          f"status {hist.status}, "
          f"{hist.solves} solves, {hist.wall_time:.2f} s; wrote {args.out}", file=sys.stderr)  # fmt: skip
    return EXIT_OK if hist.converged else EXIT_NOT_CONVERGED


def _map(args: argparse.Namespace, model: Model, names: _Names) -> int:
    """``fretwear map``: wear map as a long CSV table, NPZ arrays or its figure."""
    freqs = np.linspace(args.fmin, args.fmax, args.nf)
    cycles = cycle_grid(args.cycles, args.ncycles)
    method, options = _wear_options(args, model)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        wmap = wear_map(model, freqs, cycles, method=method, kw=args.kw, **options)
    notes = [] if isinstance(wmap.histories, LazyHistories) else [
        f"{h.frequency:.4g} Hz: {w}" for h in wmap.histories for w in h.warnings]  # fmt: skip
    if wmap.label != "exact" and args.kw > 0 and exact_answer_applies(model):  # an approximation
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            exact = wear_map(model, freqs, cycles, method="exact", kw=args.kw)
            notes.insert(0, wmap.error_note(exact) or "its error against the exact answer is unknown")
    _say_warnings("map", notes, caught)
    if args.out.lower().endswith(_FIGURE_SUFFIXES):
        from .figures import load_backend, wear_map_figure

        load_backend("bokeh" if args.out.lower().endswith(".html") else "matplotlib")
        title = f"Wear map ({wmap.label}, wear coefficient {args.kw:.3g} 1/N)"
        fig = wear_map_figure(freqs, cycles, wmap.wear_fraction[:, :, 0], title=title)
        _write_figure(fig, args, method, options)
    elif args.out.lower().endswith(".npz"):
        with atomic(args.out) as temp:
            np.savez_compressed(temp, frequency_hz=wmap.frequency, cycles=wmap.cycles, wear=wmap.wear,
                            wear_fraction=wmap.wear_fraction, amplitude=wmap.amplitude,
                            half_peak_to_peak=wmap.half_peak_to_peak,
                                relative_half_peak_to_peak=wmap.relative_half_peak_to_peak)  # fmt: skip
    else:
        table = wmap.long_table()
        keys = list(table)
        _write_csv(({k: float(table[k][r]) for k in keys} for r in range(len(table["f_hz"]))), args.out)
    failed = int(np.sum(~wmap.converged))
    print(f"fretwear map: {wmap.label}, {args.nf} frequencies x {args.ncycles} cycle counts, "
          f"{failed} incomplete; wrote {args.out}", file=sys.stderr)  # fmt: skip
    return EXIT_OK if not failed else EXIT_NOT_CONVERGED


def _cost(args: argparse.Namespace, model: Model, names: _Names) -> int:
    """``fretwear cost``: the cost ladder as CSV, the recommendation on stderr."""
    if (args.kw is None) != (args.cycles is None):
        raise UsageError("arguments --kw and --cycles: give both (wear rungs) or neither")
    ladder = dict(harmonics=(1, 3, 7, 21, 41), sample_factors=(8, 16), tolerances=(1e-1, 1e-2),
                  degrees=(2, 4), wear_harmonics=(3, 21)) if args.quick else {}  # fmt: skip
    study = cost_ladder(model, args.f, kw=args.kw, cycles=args.cycles, **ladder)
    best = study.recommend(args.target)
    rows = []
    for r in study.rungs:
        row = {"method": r.method, "settings": r.label, "wall_time_s": r.wall_time}
        row.update({f"err_{q}": r.errors.get(q, float("nan")) for q in QUANTITIES})
        row.update(converged=r.converged, recommended=r is best)
        rows.append(row)
    _write_csv(rows, args.out)
    for name, ref in study.reference.items():
        print(f"fretwear cost: reference ({name}): {ref}", file=sys.stderr)
    print(f"fretwear cost: {study.summary(args.target)}; wrote {args.out}", file=sys.stderr)
    return EXIT_OK


_FIGURE_FORMATS = ("png", "svg", "html", "csv")


def _formats(text: str) -> tuple[str, ...]:
    """The ``--formats`` of ``figures``, checked."""
    formats = tuple(f.strip().lower() for f in text.split(",") if f.strip())
    bad = [f for f in formats if f not in _FIGURE_FORMATS]
    if bad or not formats:
        valid = ", ".join(_FIGURE_FORMATS)
        raise UsageError(f"argument --formats: must be a comma-separated list of {valid}, got {text!r}")
    return formats


def _figures(args: argparse.Namespace) -> int:
    """``fretwear figures``: the paper's figure set, written headlessly.

    Warnings of the computations are printed as one line each, like those of
    ``fretwear wear`` (never as Python's ``file:line: RuntimeWarning`` with a source line).
    """
    from .figures import ExportOptions, paper_figures

    formats = _formats(args.formats)
    options = ExportOptions(width=args.width, height=args.height, dpi=args.dpi, fontsize=args.fontsize)
    out = Path(args.out)
    said: set[str] = set()

    def say(message: str) -> None:
        said.add(message)
        print(f"fretwear figures: {message}", file=sys.stderr)

    # written in a temporary folder, moved into --out when all are done: an interrupt leaves nothing
    with staged_folder(out) as staging, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        written = paper_figures(
            staging,
            harmonics=args.harmonics,
            kw=args.kw,
            cycles=args.cycles,
            frequencies=args.nf,
            cycle_points=args.ncycles,
            fmin=args.fmin,
            fmax=args.fmax,
            f_study=args.f,
            method=args.method,
            tol=args.tol,
            degree=args.degree,
            formats=formats,
            options=options,
            log=say,
        )
    reported = " ".join(said)
    for message in dict.fromkeys(" ".join(str(w.message).split()) for w in caught):
        if message not in reported:  # the wear histories' warnings were reported with where they arose
            print(f"fretwear figures: warning: {message}", file=sys.stderr)
    print(f"fretwear figures: wrote {len(written)} files to {out}", file=sys.stderr)
    return EXIT_OK


def _kernel_needs(args: argparse.Namespace, model: Model | None = None) -> tuple[str, ...]:
    """The computations of :data:`fretwear.compile.NEEDS` that the command runs (exactly their kernels)."""
    method = getattr(args, "method", None)
    if args.command == "interface":
        return () if args.static else ("interface",)
    if args.command in ("frf", "point"):
        if method == "shooting":
            return ("shooting",)
        return ("solver",) if getattr(args, "continuation", False) else ("sweep",)
    if args.command not in ("wear", "map") or model is None:
        return ()
    method = resolve_method(model, args.method, args.fixed_step)
    # an approximation is shown with its error against the exact answer: the exact dynamics run too
    exact = ("shooting",) if exact_answer_applies(model) else ()
    if method == "time":
        return ("shooting", "time")
    if method == "polynomial":
        basis = args.basis or ("saturating" if len(model.friction) == 1 else "legendre")
        return ("solver", "polynomial" if basis == "saturating" else "galerkin", *exact)
    try:
        dynamics = resolve_dynamics(model, args.dynamics or "auto", args.harmonics, args.samples)
    except ValueError:  # the command says why when it runs
        return ()
    return ("shooting",) if dynamics == "shooting" else ("solver", *exact)


def _compile_notice(args: argparse.Namespace, model: Model | None = None) -> None:
    """One line on stderr when a kernel the command runs is not in Numba's cache yet (it will compile)."""
    needs = _kernel_needs(args, model)
    message = compiled.notice_for(*needs) if needs else None
    if message:
        print(f"fretwear {args.command}: {message}", file=sys.stderr, flush=True)
        if "sweep" in needs:
            compiled.compile_ahead("sweep")


_COMMANDS = {"frf": _frf, "linear": _linear, "point": _point, "wear": _wear, "map": _map, "cost": _cost}


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line ``argv`` (default ``sys.argv[1:]``) and return the exit status.

    No traceback reaches the user: every failure is one line on stderr that names the command.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments after the program name.

    Returns
    -------
    int
        ``0`` every result converged, ``1`` an internal error (a bug: please report the line),
        ``2`` bad input or an output that cannot be written, ``3`` some result did not converge or
        is incomplete, ``130`` interrupted (Ctrl-C; nothing partial is left, ``study`` resumes).
    """
    interactive = argv is None  # a real command line: Ctrl-C also gets a hard stop (_interrupt)
    argv = list(sys.argv[1:] if argv is None else argv)
    # One OpenBLAS thread (unless set): fretwear's dense solves gain nothing from more on an idle machine,
    # and threads waiting for a busy core made them 3-25x slower under load (measured). SciPy's BLAS reads
    # this when it loads, at the first computation; study workers inherit it.
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    parser = build_parser()
    command = next((a for a in argv if a in parser.commands), "")  # type: ignore[attr-defined]
    name = f"fretwear {command}".strip()
    undo = _interrupt(name) if interactive and command != "study" else None  # study: its own handler
    try:
        try:
            _apply_settings(parser, argv)
        except UsageError as exc:
            print(f"{name}: error: {exc}", file=sys.stderr)
            return EXIT_USAGE
        try:
            args = parser.parse_args(argv)
        except SystemExit as exc:  # --help, or a usage error already printed
            return exc.code if isinstance(exc.code, int) else EXIT_USAGE
        return _run(args)
    except (UsageError, ValueError) as exc:
        print(f"{name}: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        resume = "; rerun the same command to resume" if command == "study" else "; nothing was written"
        print(f"{name}: interrupted{resume}", file=sys.stderr, flush=True)
        _SAID.set()  # the pools' threads may still hold the exit: the hard stop then says nothing more
        return EXIT_INTERRUPTED
    except BrokenPipeError:  # stdout closed early, e.g. `fretwear frf ... --out - | head`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no second error at exit
        return EXIT_OK
    except MemoryError:
        print(f"{name}: error: out of memory; choose smaller sizes (see '{name} --help')", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:
        where = f": {exc.filename!r}" if exc.filename else ""
        print(f"{name}: error: {exc.strerror or exc}{where}", file=sys.stderr)
        return EXIT_USAGE
    except Exception as exc:  # noqa: BLE001 - a bug: one line, not a traceback
        text = " ".join(str(exc).split())
        print(f"{name}: internal error: {type(exc).__name__}: {text} (please report it with the command)",
              file=sys.stderr)  # fmt: skip
        return EXIT_ERROR
    finally:
        if undo is not None:
            undo()


#: seconds between Ctrl-C and the hard stop, if the command has not unwound by then
INTERRUPT_GRACE = 0.5
_SAID = threading.Event()  # the interrupt's line is printed


def _interrupt(name: str) -> Callable[[], None] | None:
    """Ctrl-C raises KeyboardInterrupt, as usual, and stops the process ``INTERRUPT_GRACE`` s later if it
    is still running; returns the function that undoes this (None off the main thread).

    A compiled kernel holds the interpreter until it returns (Python runs signal handlers between
    bytecodes only), and a thread pool finishes its tasks before Python exits: either could hold the
    process for seconds or minutes. A thread woken by the signal itself (``signal.set_wakeup_fd``, written
    by the interpreter's C handler; fretwear's kernels release the GIL) gives the hard stop, which
    removes the partial outputs first (:data:`fretwear.arguments.PARTIAL`).
    """
    if threading.current_thread() is not threading.main_thread():
        return None
    read, write = os.pipe()
    os.set_blocking(write, False)
    try:
        previous = signal.set_wakeup_fd(write, warn_on_full_buffer=False)
    except ValueError:  # not the main interpreter
        os.close(read), os.close(write)
        return None

    def watch() -> None:
        while (byte := os.read(read, 1)) and byte[0] not in (0, signal.SIGINT):
            pass  # another signal
        if byte and byte[0] == signal.SIGINT:
            time.sleep(INTERRUPT_GRACE)
            remove_partial()
            if not _SAID.is_set():
                print(f"{name}: interrupted; nothing was written", file=sys.stderr, flush=True)
            os._exit(EXIT_INTERRUPTED)

    threading.Thread(target=watch, name="fretwear-interrupt", daemon=True).start()

    def undo() -> None:
        signal.set_wakeup_fd(previous)
        with contextlib.suppress(OSError):
            os.write(write, b"\0")  # wakes the watcher, which ends

    return undo


def _run(args: argparse.Namespace) -> int:
    """Check ``args`` across options and outputs, then run the command."""
    _check(args)
    if args.command == "figures":
        return _figures(args)
    if args.command == "study":
        return study_command.run(args)
    if args.command == "interface":
        _compile_notice(args)
        return interface_command.run(args)
    model, names = _model(args)
    _compile_notice(args, model)
    return _COMMANDS[args.command](args, model, names)


if __name__ == "__main__":
    sys.exit(main())
