"""Command line: ``fretwear frf``, ``linear``, ``point``, ``wear``, ``map``, ``cost``, ``figures``, ``study``,
``interface``, ``disk``.

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
``fretwear.model.modelfile``).

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

Layout
------
One module per command (``fretwear.cli.frf``, ``linear``, ``point``,
``wear``, ``map``, ``cost``, ``figures``, ``interface``, ``study``, ``disk``), each with
its ``HELP`` and ``DESCRIPTION``, ``add_arguments(parser)`` and ``run(args)``
(and ``kernel_needs(args, model)`` where it runs compiled kernels); what
several use is in ``fretwear.cli.shared``.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

from ..arguments import document
from . import cost, disk, figures, frf, interface, linear, point, study, wear
from . import map as wear_map_command
from .shared import (
    EXIT_ERROR,
    EXIT_INTERRUPTED,
    EXIT_NOT_CONVERGED,
    EXIT_OK,
    EXIT_USAGE,
    INTERRUPT_SAID,
    Parser,
    UsageError,
    apply_settings,
    check,
    hard_stop_on_interrupt,
)

__all__ = [
    "main",
    "build_parser",
    "COMMANDS",
    "EXIT_OK",
    "EXIT_ERROR",
    "EXIT_USAGE",
    "EXIT_NOT_CONVERGED",
    "EXIT_INTERRUPTED",
]

#: the commands, by name, in the order of ``fretwear --help``: the module of each
COMMANDS = {
    "frf": frf,
    "linear": linear,
    "point": point,
    "wear": wear,
    "map": wear_map_command,
    "cost": cost,
    "figures": figures,
    "interface": interface,
    "study": study,
    "disk": disk,
}


def build_parser() -> argparse.ArgumentParser:
    """The ``fretwear`` argument parser; each command module adds its subcommand."""
    parser = Parser(
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
    for name, command in COMMANDS.items():
        command.add_arguments(commands.add_parser(name, help=command.HELP, description=command.DESCRIPTION))
    for sub in commands.choices.values():
        document(sub)
    return parser


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
    interactive = argv is None  # a real command line: Ctrl-C also gets a hard stop (hard_stop_on_interrupt)
    argv = list(sys.argv[1:] if argv is None else argv)
    # One OpenBLAS thread (unless set): fretwear's dense solves gain nothing from more on an idle machine,
    # and threads waiting for a busy core made them 3-25x slower under load (measured). SciPy's BLAS reads
    # this when it loads, at the first computation; study workers inherit it.
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    parser = build_parser()
    command = next((a for a in argv if a in parser.commands), "")  # type: ignore[attr-defined]
    name = f"fretwear {command}".strip()
    # study has its own handler
    undo = hard_stop_on_interrupt(name) if interactive and command != "study" else None
    try:
        try:
            apply_settings(parser, argv)
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
        # the pools' threads may still hold the exit: the hard stop then says nothing more
        INTERRUPT_SAID.set()
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


def _run(args: argparse.Namespace) -> int:
    """Check ``args`` across options and outputs, then run the command."""
    command = COMMANDS[args.command]
    if hasattr(command, "check_args"):
        command.check_args(args)
    else:
        check(args, getattr(command, "OUT_SUFFIXES", ()))
    return command.run(args)
