"""What several ``fretwear`` commands use: the exit statuses, the parser and its shared options (model,
band, solver, slow-time method, settings file), the checks before any work, the model the options select,
the records and whole-file writing of the results, the compile notice and the hard stop on Ctrl-C.

Every numeric option reads its range from the one parameter table (:func:`fretwear.arguments.number`).
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import os
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TextIO, TypeVar

import numpy as np

from .. import compile as compiled
from ..arguments import atomic, check_output, number, remove_partial
from ..hbm.solution import PeriodicSolution
from ..model import Model, paper_model
from ..model.modelfile import example_names, example_path, read_model_file
from ..parameters import PARAMETERS
from ..time import ShootingSolution
from ..wear import DYNAMICS, METHODS, exact_answer_applies, method_options, resolve_dynamics, resolve_method
from ..wear.polynomial import BASES

#: exit statuses: every result converged; an internal error; bad input; some result did not converge or is
#: incomplete; interrupted (Ctrl-C)
EXIT_OK, EXIT_ERROR, EXIT_USAGE, EXIT_NOT_CONVERGED, EXIT_INTERRUPTED = 0, 1, 2, 3, 130

#: the paper's values (section 2.1) of the paper-model options
PAPER_DEFAULTS = {"fex": 10.0, "mu": 1.0, "fn": 10.0, "kn": 1e7}
_PAPER_OPTIONS = ("fex", "mu", "fn", "kn", "u0")

#: the paper model's band (Hz), the --fmin / --fmax of frf, linear and map without --model: its two modes
PAPER_BAND = (0.3, 1.3)

#: the suffixes of --out that are a figure (``wear``, ``map``)
FIGURE_SUFFIXES = (".png", ".svg", ".pdf", ".html")

R = TypeVar("R")


class UsageError(Exception):
    """Bad command-line input; the message names the option and its valid range."""


class Parser(argparse.ArgumentParser):
    """Argument parser whose errors are one line on stderr and exit status 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


# -- options ------------------------------------------------------------------------
def option(parser: argparse.ArgumentParser | argparse._ArgumentGroup, flag: str, help: str, *,
           name: str | None = None, low: float | None = None, **kwargs) -> argparse.Action:  # fmt: skip
    """The numeric option ``flag``, checked against parameter ``name`` of the table (default: the flag's
    name, ``--fixed-step`` -> ``fixed_step``; ``low`` narrows its range); ``kwargs`` go to argparse."""
    name = name or flag.removeprefix("--").replace("-", "_")
    return parser.add_argument(flag, type=number(name, low), help=help, **kwargs)


#: the named export sizes (``fretwear.figures.export.SIZES``, without importing the plotting layer)
SIZES = {"column": "3.5 x 2.5 in, 7 pt", "page": "7 x 4 in, 10 pt", "slide": "10 x 6 in, 14 pt"}


def add_export_options(
    parser: argparse.ArgumentParser, own: tuple[str, str] = ("each figure's own", "each figure's own")
) -> None:
    """``--size`` (a named size) and ``--width --height --dpi --fontsize`` of a figure file; ``own``: the
    width and height without them, as the help says."""
    group = parser.add_argument_group("figure", "size, resolution and fonts of the figure files")
    group.add_argument("--size", choices=tuple(SIZES), default=None,
                       help="named size: " + "; ".join(f"{k}: {v}" for k, v in SIZES.items())
                       + "; --width, --height, --fontsize override its values")  # fmt: skip
    option(group, "--width", f"figure width (in); default: --size's, else {own[0]}")
    option(group, "--height", f"figure height (in); default: --size's, else {own[1]}")
    dpi = PARAMETERS["dpi"].default
    option(group, "--dpi", f"resolution of the PNG files (dots per inch); default {dpi}", default=dpi)
    option(group, "--fontsize", "font size of the axis labels (pt); default: --size's, else Matplotlib's")


def export_options(args: argparse.Namespace):
    """The :class:`fretwear.figures.ExportOptions` of :func:`add_export_options`' options (the defaults for
    a command without them)."""
    from ..figures import ExportOptions

    names = ("width", "height", "fontsize", "size")
    values = {name: getattr(args, name, None) for name in names}
    return ExportOptions(dpi=getattr(args, "dpi", None) or PARAMETERS["dpi"].default, **values)


def add_model_options(parser: argparse.ArgumentParser) -> None:
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
    option(group, "--fex", "excitation amplitude on mass 1 (N); default 10")
    option(group, "--mu", "friction coefficient (-); default 1")
    load = group.add_mutually_exclusive_group()
    option(load, "--fn", "normal load F_N (N); default 10")
    option(load, "--u0", "normal interference u0 (m), instead of --fn: F_N = kn u0")
    option(group, "--kn", "normal contact stiffness (N/m); default 1e7")


def add_solver_options(parser: argparse.ArgumentParser, default: int | None = 7) -> None:
    """``--harmonics`` and ``--samples`` (``default``: of ``--harmonics``; None: the exact dynamics)."""
    harmonics = "highest harmonic Nh (-); default 7" if default else (
        "highest harmonic Nh (-) of the DLFT dynamics (giving it asks for them); "
        "default: the exact dynamics where they apply, else Nh = 21 (polynomial: 3)")  # fmt: skip
    option(parser, "--harmonics", harmonics, default=default, metavar="NH")
    option(parser, "--samples", "time samples per period N (-), at least 2 Nh + 1; default: next power of "
           "2 >= 16 Nh", metavar="N")  # fmt: skip


def add_band_options(parser: argparse.ArgumentParser, count: str = "n", default: int = 101,
                     counted: str = "number of equally spaced frequencies (-)") -> None:  # fmt: skip
    """``--fmin --fmax`` and the number of frequencies ``--{count}`` (``--n``, or ``--nf`` of ``map``)."""
    option(parser, "--fmin", "lowest frequency (Hz); default 0.3 with the paper model, required with --model")
    option(parser, "--fmax", "highest frequency (Hz), not below --fmin; default 1.3 with the paper model, "
           "required with --model")  # fmt: skip
    option(parser, f"--{count}", f"{counted}; default {default}", default=default)


def add_out_option(parser: argparse.ArgumentParser, help: str = "CSV file to write ('-': stdout)",
                   metavar: str = "FILE.csv", required: bool = True) -> None:  # fmt: skip
    """``--out``: the file the command writes."""
    parser.add_argument("--out", required=required, metavar=metavar, help=help)


def add_method_option(parser: argparse.ArgumentParser) -> None:
    """``--method {dlft,shooting}`` of the periodic solver."""
    parser.add_argument(
        "--method",
        choices=("dlft", "shooting"),
        default="dlft",
        help="periodic solver: HBM + DLFT (default) or shooting on the exact event-driven time "
        "integrator (no truncation error; needs a positive definite mass matrix)",
    )


def add_wear_options(parser: argparse.ArgumentParser) -> None:
    """Slow-time options of ``wear`` and ``map``."""
    option(parser, "--kw", "Archard coefficient K_w (1/N); default 1e-11", default=1e-11)
    option(parser, "--cycles", "horizon: number of vibration cycles N (-); default 1e5", default=1e5)
    parser.add_argument("--method", choices=("auto", *METHODS), default="auto",
                        help="slow-time method: "
                        + "; ".join(f"{m.name}: {m.title}" for m in METHODS.values())
                        + "; auto (default): exact when it applies, else stepping")  # fmt: skip
    parser.add_argument("--dynamics", choices=DYNAMICS,
                        help="periodic dynamics of the exact and stepping methods: shooting (the exact "
                        "event-driven dynamics) or dlft (HBM + DLFT, an approximation); auto (default): "
                        "shooting where it applies (friction contacts only) unless --harmonics or "
                        "--samples ask for harmonic balance")  # fmt: skip
    add_solver_options(parser, default=None)
    option(parser, "--degree", "degree m of the polynomial method (-); default 4")
    parser.add_argument("--basis", choices=BASES,
                        help="slow-time basis of the polynomial method; default saturating")  # fmt: skip
    option(parser, "--tol", "local error tolerance on w/u0 of stepping and of the cycle jumps of time "
           "integration (-); default 1e-3")  # fmt: skip
    option(parser, "--fixed-step", "stepping with a fixed step of DN cycles (explicit Euler; 1 = the paper's "
           "per-period update, eq. 24) instead of the adaptive pair", metavar="DN")  # fmt: skip


# -- the settings file --------------------------------------------------------------------
def add_settings_option(parser: argparse.ArgumentParser) -> None:
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


def apply_settings(parser: argparse.ArgumentParser, argv: Sequence[str]) -> None:
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
    from ..figures.record import read_settings

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


# -- checks and the model ----------------------------------------------------------------
def check(
    args: argparse.Namespace,
    suffixes: tuple[str, ...] = (),
    *,
    strict: bool = False,
    folder: bool = False,
    more: Callable[[argparse.Namespace], None] | None = None,
) -> None:
    """Checks that involve several options, and the output path (one of ``suffixes``, or a ``folder``),
    before any work. The band: the paper model's without ``--model``, ``fmax >= fmin`` (``>`` if
    ``strict`` or along a continuation). ``more``: the command's own checks, before the output's."""
    if hasattr(args, "fmin"):
        for name, default in zip(("fmin", "fmax"), PAPER_BAND, strict=True):
            if getattr(args, name) is None:
                if args.model is not None:
                    band = f"{PAPER_BAND[0]:g}-{PAPER_BAND[1]:g} Hz"
                    raise UsageError(f"argument --{name}: required with --model (default {band} without)")
                setattr(args, name, default)
        strict = strict or getattr(args, "continuation", False)
        if args.fmax < args.fmin or (strict and args.fmax == args.fmin):
            raise UsageError(f"argument --fmax: must be {'>' if strict else '>='} --fmin = {args.fmin:g} Hz, "
                             f"got {args.fmax:g}")  # fmt: skip
    if more is not None:
        more(args)
    out = getattr(args, "out", None)
    if out not in (None, "-"):
        try:
            check_output(out, suffixes, folder=folder)
        except ValueError as exc:
            raise UsageError(f"argument --out: {exc}") from None
    if getattr(args, "samples", None) is not None and args.samples < 2 * args.harmonics + 1:
        raise UsageError(
            f"argument --samples: must be >= 2 Nh + 1 = {2 * args.harmonics + 1} "
            f"for --harmonics {args.harmonics}, got {args.samples}"
        )


@dataclass(frozen=True)
class Names:
    """Column-name stems: DOFs, contacts and the suffixes of the friction-contact columns."""

    dofs: tuple[str, ...]
    contacts: tuple[str, ...]
    friction: tuple[str, ...]


def model_and_names(args: argparse.Namespace) -> tuple[Model, Names]:
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
        return model, Names(
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
    return model, Names(dofs=("x1", "x2"), contacts=("xr",), friction=("",))


#: slow-time options of ``wear`` and ``map`` that only some methods take (registry: fretwear.wear.METHODS)
_METHOD_OPTIONS = ("dynamics", "degree", "basis", "tol", "fixed_step")


def wear_options(args: argparse.Namespace, model: Model) -> tuple[str, dict]:
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


def wear_result(args: argparse.Namespace, model: Model, compute: Callable[..., R],
                notes: Callable[[R], list[str]]) -> tuple[R, str, dict]:  # fmt: skip
    """``compute(method, **options)`` (a wear history or map) with the slow-time method and options of the
    command line (:func:`wear_options`), its warnings printed (:func:`say_warnings`): ``notes(result)``,
    led by the result's error against the exact answer ``compute("exact")`` when it is an approximation
    and the exact answer applies. Returns the result, the method and its options."""
    method, options = wear_options(args, model)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = compute(method, **options)
    said = list(notes(result))
    if result.label != "exact" and exact_answer_applies(model):  # an approximation
        with warnings.catch_warnings():  # the reference's warnings repeat those of the approximation
            warnings.simplefilter("ignore")
            exact = compute("exact")
            said.insert(0, result.error_note(exact) or "its error against the exact answer is unknown")
    say_warnings(args.command, said, caught)
    return result, method, options


# -- results ---------------------------------------------------------------------------
def record(sol: PeriodicSolution | ShootingSolution, names: Names, model: Model) -> dict:
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


@contextlib.contextmanager
def text_output(out: str | None) -> Iterator[TextIO]:
    """A text file to write ``out`` in whole or not at all (written aside, then renamed:
    :func:`fretwear.arguments.atomic`), or stdout for ``-`` and None."""
    if out in (None, "-"):
        yield sys.stdout
        return
    with atomic(out) as temp, open(temp, "w", newline="", encoding="utf-8") as fh:
        yield fh


def write_csv(rows: Iterable[dict], out: str) -> None:
    """Write ``rows`` (dicts with the same keys) as CSV to the file ``out`` or, for ``-``, to stdout."""
    rows = list(rows)
    with text_output(out) as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)


def _stamp(args: argparse.Namespace, method: str, options: dict) -> tuple[dict, str]:
    """The parameter record (and model) of a figure of ``wear`` or ``map``."""
    from ..figures.record import MODEL

    values = {"kw": args.kw, "cycles": args.cycles, "method": method, **options}
    if args.model is None:
        values |= {"fex": args.fex or PAPER_DEFAULTS["fex"], "mu": args.mu or PAPER_DEFAULTS["mu"]}
        values["fn"] = args.fn if args.fn is not None else PAPER_DEFAULTS["fn"]
        kn = args.kn or PAPER_DEFAULTS["kn"]
        return values, MODEL if kn == PAPER_DEFAULTS["kn"] else MODEL.replace("1e7", f"{kn:g}")
    return values, f"model file {Path(args.model).name}"


def write_figure(fig, args: argparse.Namespace, method: str, options: dict, **extra) -> None:
    """Save the figure ``fig`` of ``wear`` or ``map`` to ``--out`` whole, its parameters as caption."""
    from ..figures import caption, save_figure

    values, model = _stamp(args, method, options)
    with atomic(args.out) as temp:
        save_figure(fig, temp, options=export_options(args),
                    caption=lambda markup: caption({**values, **extra}, model, markup))  # fmt: skip


def say_warnings(command: str, notes: Iterable[str], caught: list, limit: int = 3) -> None:
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


# -- the compile notice ----------------------------------------------------------------------
def wear_kernel_needs(args: argparse.Namespace, model: Model | None = None) -> tuple[str, ...]:
    """The computations of :data:`fretwear.compile.NEEDS` that ``wear`` or ``map`` runs."""
    if model is None:
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


def compile_notice(command: str, needs: tuple[str, ...]) -> None:
    """One line on stderr when a kernel of ``needs`` (the computations the command runs) is not in Numba's
    cache yet (it will compile)."""
    message = compiled.notice_for(*needs) if needs else None
    if message:
        print(f"fretwear {command}: {message}", file=sys.stderr, flush=True)
        if "sweep" in needs:
            compiled.compile_ahead("sweep")


# -- Ctrl-C -----------------------------------------------------------------------------
#: seconds between Ctrl-C and the hard stop, if the command has not unwound by then
INTERRUPT_GRACE = 0.5
#: set once the interrupt's line is printed
INTERRUPT_SAID = threading.Event()


def hard_stop_on_interrupt(name: str) -> Callable[[], None] | None:
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
            if not INTERRUPT_SAID.is_set():
                print(f"{name}: interrupted; nothing was written", file=sys.stderr, flush=True)
            os._exit(EXIT_INTERRUPTED)

    threading.Thread(target=watch, name="fretwear-interrupt", daemon=True).start()
    hook = sys.unraisablehook

    def quiet(unraisable) -> None:
        # Ctrl-C that lands in a finaliser (a weakref callback) is "ignored" with a traceback; the hard
        # stop ends the process anyway, so the traceback would only alarm
        if not isinstance(unraisable.exc_value, KeyboardInterrupt):
            hook(unraisable)

    sys.unraisablehook = quiet

    def undo() -> None:
        sys.unraisablehook = hook
        signal.set_wakeup_fd(previous)
        with contextlib.suppress(OSError):
            os.write(write, b"\0")  # wakes the watcher, which ends

    return undo
