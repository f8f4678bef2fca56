"""``fretwear study SPEC.toml --out RESULT.zarr``: a parameter study of a TOML spec on Dask, in Zarr.

The spec (``fretwear.studies.spec``) defines the points of the study: the
outer product of its grid axes, times ``samples`` random draws when some
parameters are random. The points are cut into rectangular blocks
(:mod:`fretwear.studies.layout`), one Dask task each
(:func:`fretwear.studies.compute.compute_block`); the tasks run on a local
cluster (one single-threaded worker process per core) or on an existing
scheduler (``--scheduler ADDRESS``), and the client writes each block into a
Zarr store (:mod:`fretwear.studies.store`) as soon as it comes back
(:mod:`fretwear.studies.run`). This module is the command;
:func:`~fretwear.studies.summary.wear_life_summary` summarizes a result and
:func:`fretwear.figures.wear_life_figure` draws it (``--figure``).

Reading a result
----------------
``xarray.open_zarr(RESULT)`` gives the Dataset. Its dimensions are the study's
axes: ``sample`` (random draws; the drawn values are coordinates along it)
and the grid axes, by name (``frequency`` last), then the dimensions of the
quantities: ``fraction`` (``cycles_to``), ``cycles`` (the wear grid), ``dof``,
``contact`` and ``friction_contact``. Variables:

``cycles_to`` (``wear_life``)
    Cycles to ``w = fraction * u0``; ``inf`` where the contact sticks (no wear),
    NaN where the fraction is not reached within the horizon (status
    ``horizon``) or the point failed. For a model with contact pairs: cycles to
    the worn ``depth`` (m) at the deepest pair.
``wear_fraction``, ``wear_amplitude`` (``wear``)
    ``w / u0`` and first-harmonic amplitudes (m) at the cycle counts ``cycles``.
``amplitude``, ``relative_amplitude``, ``sliding_distance``, ``friction_energy`` (``frf``)
    Periodic response without wear: first-harmonic amplitude of each DOF and of
    each contact's relative displacement (m), distance slid (m) and energy
    dissipated (J) per period by each friction contact.
``amplitude``, ``slip_distance``, ``mean_pressure``, ``friction_energy`` (``frf``, contact pairs)
    Periodic response of a model with contact pairs without wear: first-harmonic
    amplitude of each reported DOF (``dof``: the model's named DOFs, else its
    loaded DOFs; m), distance slid (m) and mean pressure (Pa) of each pair
    (``pair``, with its ``position`` along the interface), energy dissipated by
    the interface per period (J, J/m in 2-D).
``wear_depth``, ``wear_pressure``, ``wear_amplitude`` (``wear``, contact pairs)
    Worn depth (m) and mean pressure (Pa) of each pair, amplitude of each
    reported DOF (m), at the cycle counts ``cycles``.
``status``
    Per point, the worst of its quantities' codes (:data:`STATUS`, also in the
    variable's ``flag_values`` and ``flag_meanings``): 0 not computed yet, 1 ok,
    2 stuck, 3 horizon, 4 not converged, 5 invalid parameters (e.g. a negative
    draw of ``mu``), 6 error. A point that fails is NaN with its status; the
    study goes on.
``magnification``, ``peak_frequency``, ``peak_blade``, ``delta`` (``magnification``, the bladed disk)
    Per point (``level``, ``sample``): the amplitude magnification factor (-), where the largest
    blade-tip amplitude is (Hz) and on which blade (``-1``: not computed), and the draw's pattern
    ``delta_i`` (dimension ``blade``); the attributes hold the band (``band_hz``), the tuned peak
    (``tuned_amplitude``, m, at ``tuned_frequency``, Hz) and Whitehead's bound (``whitehead``).
    :func:`~fretwear.studies.summary.magnification_summary` gives the curve against the level.
``task_seconds``
    Compute time of each task (s), NaN for a task not computed yet: the record
    of completed blocks that a rerun uses to resume.

Attributes: ``title``, ``quantities``, ``fretwear_version``, ``spec`` (the TOML
file as written), ``spec_resolved`` (JSON: every value, defaults included),
``study_key`` (its hash), ``wear_method`` (with the wear quantities and one method: what ran, the
slow-time scheme and the dynamics apart, e.g. ``"exact"`` for the exact answer, as
:func:`fretwear.wear.describe` says), ``units`` and ``long_name`` of every variable.

Resuming and failures
---------------------
Rerunning the same command after an interruption computes only the tasks
whose ``task_seconds`` is NaN (a block is marked done after its data is
written). A store made by another spec, another ``--samples`` or another
fretwear version is refused (``--overwrite`` replaces it). A worker process
that dies is replaced (by its nanny) and its tasks are rerun by the scheduler;
a task that raises is retried (``--retries``). Tasks are deterministic and the
draws seeded, so the result does not depend on the cluster, the interruptions
or the failures.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from ..arguments import atomic, check_output
from ..studies.layout import layout
from ..studies.run import run_study
from ..studies.spec import SpecError, read_spec
from ..studies.summary import magnification_summary, wear_depth_summary, wear_life_summary
from .shared import EXIT_INTERRUPTED, EXIT_NOT_CONVERGED, EXIT_OK, EXIT_USAGE, option

__all__ = ["HELP", "DESCRIPTION", "add_arguments", "check_args", "run"]

#: the line of ``fretwear --help``, and the description of ``fretwear study --help``
HELP = "parameter study on Dask, results in Zarr"
DESCRIPTION = (
    "Runs the parameter study of a TOML spec on a Dask cluster (local by default) and "
    "writes an xarray Dataset to a Zarr store, chunk by chunk; rerun the same command to finish "
    "an interrupted study. Read the result with xarray.open_zarr(RESULT)."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``fretwear study`` (see :func:`run`)."""
    parser.add_argument(
        "spec",
        metavar="SPEC.toml",
        help="study spec (format: fretwear.studies.spec), e.g. fretwear/data/wear_life.toml",
    )
    parser.add_argument(
        "--out",
        required=True,
        metavar="RESULT.zarr",
        help="Zarr store to write (read it with xarray.open_zarr); if it holds the same study, "
        "only what is missing is computed",
    )
    where = parser.add_mutually_exclusive_group()
    where.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="address of a running Dask scheduler (e.g. tcp://host:8786); default: a local cluster",
    )
    option(where, "--workers", "worker processes of the local cluster; default: one per core", metavar="N")
    # dest "draws", not "samples": the other commands' --samples is the time samples per period
    option(parser, "--samples", "number of random draws (overrides study.samples)",
           name="draws", dest="draws", metavar="N")  # fmt: skip
    option(parser, "--points-per-task", "points computed by one task; default: about 2 s of work, "
           ">= 32 tasks", metavar="N")  # fmt: skip
    option(parser, "--retries", "reruns of a task that raises; default 2", default=2, metavar="N")
    parser.add_argument("--overwrite", action="store_true", help="replace a store that holds another study")
    parser.add_argument(
        "--figure",
        metavar="FILE",
        help="wear_life: write the histogram of the cycles to 0.5 u0 (PNG, SVG or PDF)",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def check_args(args: argparse.Namespace) -> None:
    """Nothing before the run: it checks the spec and ``--out`` / ``--figure`` itself."""


#: the formats of ``--figure`` (Matplotlib's, by suffix)
_FIGURE_SUFFIXES = (".png", ".svg", ".pdf")


def run(args: argparse.Namespace) -> int:
    """Run ``fretwear study`` with parsed ``args``.

    Returns
    -------
    int
        0 success; 2 bad input (one line on stderr names the key or option);
        3 some point did not converge or failed (NaN with its status in the store),
        or some task failed (rerun to complete); 130 interrupted (rerun to resume).
    """

    def say(message: str) -> None:
        print(f"fretwear study: {message}", file=sys.stderr, flush=True)

    try:
        for option, path, suffixes in (("--out", args.out, ()), ("--figure", args.figure, _FIGURE_SUFFIXES)):
            if path is not None:  # before any work: the study must not run to find it cannot be written
                try:
                    check_output(path, suffixes, folder=option == "--out")
                except ValueError as exc:
                    raise SpecError(option, str(exc)) from None
        spec = read_spec(args.spec, samples=args.draws, points_per_task=args.points_per_task)
        if args.figure is not None and "wear_life" not in spec.quantities:
            raise SpecError("--figure", "needs the quantity 'wear_life'")
        if args.figure is not None and (set(spec.dims) - {"sample"} or 0.5 not in spec.fractions):
            raise SpecError("--figure", "needs a study over random samples only, with fraction 0.5")
        lay = layout(spec)
        axes = " x ".join(f"{d} {n}" for d, n in zip(spec.dims, spec.shape, strict=True)) or "one point"
        per_task = int(np.prod(lay.chunks))
        say(
            f"{spec.title}: {spec.n_points} points ({axes}) in {lay.n_tasks} tasks of up to {per_task} points"
        )
        result = run_study(
            spec,
            args.out,
            scheduler=args.scheduler,
            workers=args.workers,
            retries=args.retries,
            overwrite=args.overwrite,
            progress=not args.quiet,
            log=say,
        )
    except SpecError as exc:
        say(f"error: {' '.join(str(exc).split())}")
        return EXIT_USAGE
    except KeyboardInterrupt:
        say(f"interrupted; the blocks computed so far are in {args.out}: rerun the same command to resume")
        return EXIT_INTERRUPTED
    counts = ", ".join(f"{k} {v}" for k, v in result.status_counts.items())
    if result.computed:
        say(
            f"computed {len(result.computed)} tasks ({result.resumed} already in the store) on "
            f"{result.workers} workers (ready in {result.startup_seconds:.1f} s) in {result.wall_time:.2f} s;"
            f" compute {result.compute_seconds:.2f} s, "
            f"overhead {result.overhead_per_task * 1e3:.1f} ms per task "
            f"({100 * result.overhead_fraction:.1f} % of the workers' time)"
        )
    else:
        say(f"all {result.n_tasks} tasks already in the store: nothing to compute")
    say(f"points: {counts}; wrote {args.out}")
    for task, reason in result.failed_tasks.items():
        say(f"task {task} failed: {reason} (rerun the same command to retry it)")
    if spec.pairs and "wear" in spec.quantities:
        import xarray as xr

        s = wear_depth_summary(xr.open_zarr(args.out))
        if s["n"]:
            where = ", ".join(f"{k} = {v:g}" for k, v in s["point"].items())
            say(
                f"deepest wear at N = {spec.fixed['cycles']:g}: {s['max']:.4g} m at x = {s['position']:.4g} m"
                f"{f' ({where})' if where else ''}; over the {s['n']} points: min {s['min']:.4g} m, "
                f"median {s['median']:.4g} m"
            )
    if "wear_life" in spec.quantities and set(spec.dims) == {"sample"}:
        import xarray as xr

        ds = xr.open_zarr(args.out)
        levels = [(f"{d:g} m", {"depth": d}) for d in spec.depths] if spec.pairs else [
            (f"{f:g} u0", {"fraction": f}) for f in spec.fractions]  # fmt: skip
        for text, level in levels:
            s = wear_life_summary(ds, **level)
            say(
                f"cycles to {text}: median {s['median']:.4g}, 5 % {s['q05']:.4g}, 95 % {s['q95']:.4g} "
                f"({s['n']} samples, {s['stuck']} stuck, {s['beyond_horizon']} beyond the horizon)"
            )
        if args.figure is not None:
            from ..figures.study import wear_life_figure  # the command's figure: plotting only here

            with atomic(args.figure) as temp:
                wear_life_figure(ds, 0.5).savefig(temp, dpi=150)
            say(f"wrote {args.figure}")
    if spec.mistuning:
        import xarray as xr

        s = magnification_summary(xr.open_zarr(args.out))
        say(f"tuned peak {s['tuned_amplitude']:.4g} m at {s['tuned_frequency']:.4f} Hz in "
            f"{s['band'][0]:g}-{s['band'][1]:g} Hz; Whitehead's bound {s['whitehead']:.3f}")  # fmt: skip
        say("level %   mean    95 %  largest  draws  above the bound")
        for row in zip(s["levels"], s["mean"], s["p95"], s["max"], s["n"], s["above"], strict=True):
            level, mean, p95, top, n, above = row
            say(f"{100 * level:7.3g} {mean:7.3f} {p95:7.3f} {top:8.3f} {n:6d}  {above:d}")
    return EXIT_OK if result.complete and not result.failed_points else EXIT_NOT_CONVERGED
