"""The ``fretwear interface`` command: the cylinder-on-flat benchmark or an interface model file.

``add_arguments(parser)`` declares the options on an ``argparse`` (sub)parser
and ``run(args)`` executes them and returns the exit status (0 success, 2
bad input, 3 a solve did not converge, static gross slip included, 130
interrupted by Ctrl-C: one line, no output file). Three modes:

* ``--static``: the quasi-static limit (normal load, then the tangential load
  ``Q0 = q_ratio mu P``, ``q_ratio < 1``: beyond, no static equilibrium
  exists), JSON on stdout or in ``--out`` (``.json``; ``.csv``: one row of the
  same keys) (SI units): ``contact_half_width``,
  ``stick_half_width``, ``peak_pressure``, ``normal_load_per_length``,
  ``tangential_load_per_length``, ``radius``, ``effective_modulus``, ``mu``,
  the Hertz and Mindlin values and the relative errors; ``--geometry sphere``: the 3-D
  sphere on flat (``fretwear.interface.sphere``), ``contact_radius``, ``stick_radius``,
  ``peak_pressure``, ``normal_load``, ``tangential_load`` (N), ``radius``,
  ``effective_modulus``, ``mu``, ``pairs`` and the errors against Hertz and Mindlin;
* ``--kw K --cycles N``: a wear history at ``--f`` (``--method stepping`` or
  ``polynomial --degree D``), one CSV row per (record, pair): ``cycles, x, w,
  pressure, slip, state_fraction_stick``;
* otherwise one periodic solve at ``--f``: the same CSV columns at ``cycles = 0``.

The numerical modules are imported when the command runs, so that declaring
the options costs nothing to the rest of the command line.
"""

from __future__ import annotations

import argparse
import csv
import json
import sys

import numpy as np

from .shared import (
    EXIT_INTERRUPTED,
    EXIT_NOT_CONVERGED,
    EXIT_OK,
    EXIT_USAGE,
    add_out_option,
    compile_notice,
    option,
    text_output,
)

#: the suffixes of --out ("-" or none: stdout); .json: the quasi-static limit (--static)
OUT_SUFFIXES = (".csv", ".json")

#: CSV columns of the per-pair output
COLUMNS = ("cycles", "x", "w", "pressure", "slip", "state_fraction_stick")


#: the line of ``fretwear --help``, and the description of ``fretwear interface --help``
HELP = "a contact interface of many nodes: cylinder on flat, or an interface model file"
DESCRIPTION = (
    "The cylinder-on-flat fretting benchmark (2-D plane strain, scikit-fem) or an "
    "interface model file: the quasi-static limit (--static, JSON), one periodic solve, or a "
    "wear history with pressure redistribution (CSV, one row per record and contact node)."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Declare the options of ``fretwear interface`` on ``parser``."""
    parser.add_argument("--model", metavar="FILE.toml",
                        help="interface model file (matrices + contact pairs); default: the cylinder-on-flat "
                        "benchmark")  # fmt: skip
    parser.add_argument("--static", action="store_true", help="quasi-static limit: normal load, then the "
                        "tangential load; JSON on stdout")  # fmt: skip
    parser.add_argument("--geometry", choices=("cylinder", "sphere"), default="cylinder",
                        help="benchmark: the 2-D cylinder on flat (default) or the 3-D sphere on flat (half "
                        "model, --static only)")  # fmt: skip
    option(parser, "--q-ratio", "benchmark tangential load Q0 / (mu P) (-), >= 0, < 1 with --static; "
           "default 0.5", default=0.5, metavar="Q")  # fmt: skip
    option(parser, "--contact-nodes", "cylinder benchmark: pairs across the contact window (-); default 32",
           metavar="NC")  # fmt: skip
    option(parser, "--divisions", "sphere benchmark: grid spacings across the contact window radius (-); "
           "default 18 (523 pairs)", metavar="D")  # fmt: skip
    option(parser, "--window", "benchmark contact window half-width (radius) / Hertz a (-); default 1.25",
           default=1.25)  # fmt: skip
    option(parser, "--normal-load", "benchmark normal load: per unit length for the cylinder (N/m, default "
           "2e5), the whole load for the sphere (N, default 100)", name="line_load", metavar="P")  # fmt: skip
    option(parser, "--mu", "benchmark friction coefficient; default 0.6", name="interface_mu", default=0.6)
    option(parser, "--drive", "benchmark displacement control: amplitude of the loading arm's end (m), with "
           "--arm-stiffness (replaces --q-ratio)", metavar="DELTA")  # fmt: skip
    option(parser, "--arm-stiffness", "benchmark loading arm stiffness (N/m per m); default 2e10 (with "
           "--drive)", default=2e10, metavar="KA")  # fmt: skip
    option(parser, "--f", "excitation frequency (Hz); default 50", default=50.0, metavar="HZ")
    option(parser, "--harmonics", "highest harmonic Nh (-); default 7", default=7, metavar="NH")
    option(parser, "--kw", "Archard coefficient K_w (1/Pa), > 0: runs a wear history", name="interface_kw")
    option(parser, "--cycles", "wear horizon (cycles); default 1e6", default=1e6)
    option(parser, "--converge", "stop the wear history once the profile has converged to TOL (-)",
           metavar="TOL")  # fmt: skip
    option(parser, "--rtol", "slow-time step tolerance on the worn depth (-); default 1e-2", default=1e-2)
    parser.add_argument("--method", choices=("stepping", "polynomial"), default="stepping",
                        help="slow-time method of the wear history: adaptive stepping (default) or the "
                        "polynomial method (one nonlinear solve over [0, --cycles])")  # fmt: skip
    option(parser, "--degree", "polynomial degree in slow time of --method polynomial; default 6",
           metavar="D")  # fmt: skip
    add_out_option(parser, "CSV file to write ('-' or omitted: stdout); with --static a .json or a .csv file",
                   required=False)  # fmt: skip


def kernel_needs(args: argparse.Namespace, model=None) -> tuple[str, ...]:
    """The computations of :data:`fretwear.compile.NEEDS` that the command runs."""
    return () if args.static else ("interface",)


def _model(args: argparse.Namespace):
    from ..interface.fe import cylinder_on_flat
    from ..interface.modelfile import read_interface_model

    if args.model:
        return read_interface_model(args.model)
    changes = dict(
        contact_nodes=32 if args.contact_nodes is None else args.contact_nodes,
        window=args.window,
        normal_load=2.0e5 if args.normal_load is None else args.normal_load,
        mu=args.mu,
        q_ratio=max(args.q_ratio, 1e-3),
    )
    if args.drive is not None:
        changes.update(drive_displacement=args.drive, arm_stiffness=args.arm_stiffness)
    return cylinder_on_flat(**changes)


def _static_summary(cond) -> dict:
    """Quasi-static state of a model file: its static load, then its ``cos`` pattern applied statically."""
    from ..interface.contact import SLIP, STICK
    from ..interface.static import second_moment_half_width, solve_static

    res = solve_static(cond, tangential_scale=1.0)
    out = dict(converged=res.converged, message=res.message, regime="gross slip" if res.gross_slip else None)
    if not res.states:
        return out
    s = res.states[-1]
    c = cond.model.pairs
    mu = c.mu
    stick = s.state == STICK
    sign = np.sign(s.tangential_force.sum()) or 1.0
    deficit = np.where(stick, mu * s.normal_force - sign * s.tangential_force, 0.0)
    out.update(
        contact_half_width=second_moment_half_width(c.position, s.normal_force),
        stick_half_width=0.0 if res.gross_slip else second_moment_half_width(c.position, deficit),
        peak_pressure=float(np.max(s.normal_force / c.area)), normal_force_sum=float(s.normal_force.sum()),
        tangential_force_sum=float(s.tangential_force.sum()), mu=float(mu.mean()),
    )  # fmt: skip
    if res.converged:
        out["regime"] = (
            "partial slip" if stick.any() and (s.state == SLIP).any() else "stick" if stick.any() else "slip"
        )
    return out


def _rows(cycles: float, x: np.ndarray, w, pressure, slip, stick):
    for i in range(len(x)):
        yield (repr(float(cycles)), repr(float(x[i])), repr(float(w[i])), repr(float(pressure[i])),
               repr(float(slip[i])), repr(float(stick[i])))  # fmt: skip


def _write(path: str | None, rows, columns=COLUMNS) -> None:
    """CSV on stdout, or in ``path`` whole or not at all (written aside, then renamed)."""
    with text_output(path) as fh:
        writer = csv.writer(fh)
        writer.writerow(columns)
        writer.writerows(rows)


def _write_static(path: str | None, out: dict) -> None:
    """The static result as JSON (stdout or ``.json``) or one CSV row of the same keys (``.csv``)."""
    if path not in (None, "-") and path.lower().endswith(".csv"):
        _write(path, [["" if v is None else v for v in out.values()]], columns=tuple(out))
        return
    with text_output(path) as fh:
        fh.write(json.dumps(out, indent=2) + "\n")


def _run_sphere(args: argparse.Namespace) -> int:
    """``--geometry sphere --static``: the 3-D sphere-on-flat benchmark's quasi-static test, JSON."""
    from ..interface.interrupt import catch_interrupt
    from ..interface.reduction import ContactCondensation
    from ..interface.sphere import sphere_static_benchmark, sphere_static_model

    if not args.static or args.model:
        raise ValueError(
            "--geometry sphere runs with --static only and without --model (the quasi-static test)"
        )
    if args.contact_nodes is not None:
        raise ValueError(
            "--contact-nodes applies to --geometry cylinder only (the sphere's mesh is set by --divisions)"
        )
    if args.q_ratio >= 1:
        raise ValueError(
            f"argument --q-ratio: must be in [0, 1) with --static (Q >= mu P has no static equilibrium: "
            f"gross slip), got {args.q_ratio:g}"
        )
    if args.out not in (None, "-") and not args.out.lower().endswith((".json", ".csv")):
        raise ValueError(f"argument --out: with --static, a .json or .csv file or '-', got {args.out!r}")
    model = sphere_static_model(
        divisions=18 if args.divisions is None else int(args.divisions), window=args.window,
        normal_load=100.0 if args.normal_load is None else args.normal_load, mu=args.mu,
        q_ratio=max(args.q_ratio, 1e-3),
    )  # fmt: skip
    with catch_interrupt():
        out = sphere_static_benchmark(args.q_ratio, condensation=ContactCondensation(model))
    return _finish_static(args.out, out)


def _finish_static(path: str | None, out: dict) -> int:
    """Write a static result and return the exit status (a one-line message when it did not converge)."""
    _write_static(path, out)
    if not out.get("converged"):
        message = " ".join(str(out.get("message") or "did not converge").split())
        print(f"fretwear interface: no static equilibrium: {message}", file=sys.stderr)
        return EXIT_NOT_CONVERGED
    return EXIT_OK


def run(args: argparse.Namespace) -> int:
    """Execute ``fretwear interface`` with parsed ``args``; returns the exit status."""
    from ..interface.contact import STICK
    from ..interface.interrupt import catch_interrupt
    from ..interface.periodic import InterfaceProblem, solve_interface
    from ..interface.reduction import ContactCondensation
    from ..interface.static import static_benchmark
    from ..interface.wear import wear_interface
    from ..model import craig_bampton

    compile_notice("interface", kernel_needs(args))
    try:
        if args.geometry == "sphere":
            return _run_sphere(args)
        if args.divisions is not None:
            raise ValueError(
                "--divisions applies to --geometry sphere only (the cylinder's is --contact-nodes)"
            )
        if args.static and not args.model and args.q_ratio >= 1:
            raise ValueError(
                f"argument --q-ratio: must be in [0, 1) with --static (Q0 >= mu P has no static equilibrium: "
                f"gross slip), got {args.q_ratio:g}"
            )
        if args.static and args.out not in (None, "-") and not args.out.lower().endswith((".json", ".csv")):
            raise ValueError(f"argument --out: with --static, a .json or .csv file or '-', got {args.out!r}")
        model = _model(args)
        f_max = 0.0 if args.static else args.harmonics * args.f
        cond = ContactCondensation(craig_bampton(model, f_max))
        if args.static:
            with catch_interrupt():
                if args.model:
                    out = _static_summary(cond)
                else:
                    out = static_benchmark(args.q_ratio, condensation=cond)
            return _finish_static(args.out, out)
        prob = InterfaceProblem(cond, 2 * np.pi * args.f, harmonics=args.harmonics)
        x = cond.model.pairs.position
        if args.kw is None:
            with catch_interrupt():
                sol = solve_interface(prob)
            _write(args.out, _rows(0.0, x, prob.wear, sol.mean_pressure, sol.slip_distance,
                                   sol.state_fraction(STICK)))  # fmt: skip
            if not sol.converged:
                print(f"fretwear interface: no convergence: {sol.message}", file=sys.stderr)
                return EXIT_NOT_CONVERGED
            return EXIT_OK
        if args.method == "polynomial":
            if args.converge is not None:
                raise ValueError("--converge applies to --method stepping only")
            with catch_interrupt():
                hist = wear_interface(prob, args.kw, args.cycles, method="polynomial", degree=args.degree)
        else:
            if args.degree is not None:
                raise ValueError("--degree applies to --method polynomial only")
            with catch_interrupt():
                hist = wear_interface(prob, args.kw, args.cycles, rtol=args.rtol, converge=args.converge)
        rows = (
            row
            for k, N in enumerate(hist.cycles)
            for row in _rows(N, x, hist.wear[k], hist.pressure[k], hist.slip[k], hist.stick_fraction[k])
        )
        _write(args.out, rows)
        print(f"fretwear interface: {len(hist.cycles)} records to N = {hist.cycles[-1]:.6g}, {hist.solves} "
              f"periodic solves; {hist.message or 'done'}", file=sys.stderr)  # fmt: skip
        return EXIT_OK if hist.converged else EXIT_NOT_CONVERGED
    except ValueError as exc:
        print(f"fretwear interface: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:
        print(f"fretwear interface: cannot write output: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("fretwear interface: interrupted (Ctrl-C); nothing written", file=sys.stderr)
        return EXIT_INTERRUPTED
