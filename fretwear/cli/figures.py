"""``fretwear figures``: the paper's figure set (Fig. 5-14 equivalents), written headlessly to a folder."""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

from ..arguments import staged_folder
from ..wear import METHODS
from .shared import (
    EXIT_OK,
    UsageError,
    add_export_options,
    add_settings_option,
    check,
    export_options,
    option,
)

_FORMATS = ("png", "svg", "pdf", "html", "csv")


#: the line of ``fretwear --help``, and the description of ``fretwear figures --help``
HELP = "the paper's figure set (Fig. 5-14 equivalents), headless"
DESCRIPTION = (
    "Computes the paper's figures 5-14 for the 2-DOF example and writes figNN.{png,svg,csv} "
    "(and .pdf, .html with --formats) to --out, at --size column, page or slide if asked. Needs "
    "matplotlib and holoviews (installed with fretwear)."
)


def add_arguments(figures: argparse.ArgumentParser) -> None:
    """Declare the options of ``fretwear figures`` on ``figures``."""
    figures.add_argument("--out", required=True, metavar="DIR", help="folder to write (created if missing)")
    option(figures, "--harmonics", "highest harmonic Nh (-); default 21", default=21, metavar="NH")
    option(figures, "--kw", "Archard coefficient K_w (1/N); default 1e-11", default=1e-11)
    option(figures, "--cycles", "wear horizon (cycles); default 1e5", default=1e5)
    option(figures, "--nf", "frequencies of the maps (-); default 41", low=2, default=41)
    option(figures, "--ncycles", "cycle counts of the maps (-); default 60", low=3, default=60)
    option(figures, "--fmin", "lowest frequency (Hz); default 0.3", default=0.3)
    option(figures, "--fmax", "highest frequency (Hz), above --fmin; default 1.3", default=1.3)
    option(figures, "--f", "frequency of the wear histories of Fig. 10 and 11 (Hz); default 0.7", default=0.7,
           metavar="HZ")  # fmt: skip
    figures.add_argument("--method", choices=("auto", *METHODS), default="auto",
                         help="slow-time method of the wear maps; default auto (exact)")  # fmt: skip
    option(figures, "--tol", "tolerance of stepping and time integration (fraction of u0); default 1e-3",
           default=1e-3)  # fmt: skip
    option(figures, "--degree", "degree of the polynomial method (Fig. 11, 12, 14); default 4", default=4)
    figures.add_argument("--formats", default="png,svg,csv",
                         help="formats, comma-separated: png, svg, pdf, html, csv")  # fmt: skip
    add_export_options(figures)
    add_settings_option(figures)


def _formats(text: str) -> tuple[str, ...]:
    """The ``--formats``, checked."""
    formats = tuple(f.strip().lower() for f in text.split(",") if f.strip())
    bad = [f for f in formats if f not in _FORMATS]
    if bad or not formats:
        valid = ", ".join(_FORMATS)
        raise UsageError(f"argument --formats: must be a comma-separated list of {valid}, got {text!r}")
    return formats


def check_args(args: argparse.Namespace) -> None:
    """Before any work: the band (``fmax > fmin``), the formats, the output folder."""
    check(args, strict=True, folder=True, more=lambda args: _formats(args.formats))


def run(args: argparse.Namespace) -> int:
    """The paper's figure set, written headlessly.

    Warnings of the computations are printed as one line each, like those of
    ``fretwear wear`` (never as Python's ``file:line: RuntimeWarning`` with a source line).
    """
    from ..figures import paper_figures

    formats = _formats(args.formats)
    options = export_options(args)
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
