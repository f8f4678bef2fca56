"""The paper's figure set (Fig. 5-14 of Salles et al., 2-DOF example), computed and written headlessly."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

from ..hbm import linear_frf, sweep
from ..model import paper_model
from ..studies import compare_methods, harmonic_convergence, wear_map
from ..wear import cycle_grid, method_options, snapshot_cycles, wear_history
from .export import EXPORT_FORMATS, ExportOptions, save_csv, save_figures
from .plots import (
    holoviews,
    line_figure,
    load_backend,
    map_figure,
    positive,
    styled,
    wear_curve,
    wear_map_figure,
)
from .record import MODEL, caption, csv_header

__all__ = ["paper_figures"]


def _layout(panels: list, cols: int, options: ExportOptions | None = None):
    """Panels in a grid of ``cols`` columns, sized for Matplotlib; in one row for a landscape export size
    (``options``' width at least its height: a column, a page, a slide)."""
    hv = holoviews()
    if options is not None and options.width is not None and options.height is not None:
        cols = len(panels) if options.width >= options.height else cols
    rows = -(-len(panels) // cols)
    layout = hv.Layout(panels).cols(cols)
    return styled(
        layout,
        mpl={"fig_inches": (5.5 * cols, 3.8 * rows), "sublabel_format": "", "vspace": 0.6, "hspace": 0.5},
    )


def _wear_map_table(maps: Mapping[float, Any]) -> dict[str, np.ndarray]:
    """Long tables of several wear maps, with a ``fex`` column."""
    tables = []
    for fex, wm in maps.items():
        t = wm.long_table()
        tables.append({"fex": np.full(len(t["f_hz"]), fex), **t})
    return {k: np.concatenate([t[k] for t in tables]) for k in tables[0]}


#: curve and table name of the exact answer (exact slow time on the exact dynamics) in Fig. 11
EXACT_REFERENCE = "exact answer (reference)"


def _history_table(histories: Mapping[str, Any], key: str) -> dict[str, np.ndarray]:
    rows = [(name, h) for name, h in histories.items() if h is not None]
    return {
        key: np.concatenate([np.full(len(h.cycles), name) for name, h in rows]),
        "cycles": np.concatenate([h.cycles for _, h in rows]),
        "w": np.concatenate([h.wear[:, 0] for _, h in rows]),
        "w_over_u0": np.concatenate([h.wear_fraction[:, 0] for _, h in rows]),
    }


def _warnings(name: str, histories: Mapping[str, Any], say: Callable[[str], None], limit: int = 3) -> None:
    """Report the warnings and early stops of the wear histories of figure ``name`` (where: the label)."""
    notes = [f"{name}, {label}: {w}" for label, h in histories.items() if h is not None for w in h.warnings]
    notes += [f"{name}, {label}: stopped early ({h.status})" for label, h in histories.items()
              if h is not None and not h.converged]  # fmt: skip
    for note in notes[:limit]:
        say(f"warning: {note}")
    if len(notes) > limit:
        say(f"warning: {name}: and {len(notes) - limit} more warnings of the same kind")


def _map_histories(label: str, wm) -> dict[str, Any]:
    return {f"{label}, {h.frequency:.4g} Hz": h for h in wm.histories}


def paper_figures(
    out: str | Path,
    *,
    harmonics: int = 21,
    kw: float = 1e-11,
    cycles: float = 1e5,
    frequencies: int = 41,
    cycle_points: int = 60,
    fmin: float = 0.3,
    fmax: float = 1.3,
    f_study: float = 0.7,
    method: str = "auto",
    tol: float = 1e-3,
    degree: int = 4,
    polynomial_harmonics: int = 3,
    formats: Sequence[str] = ("png", "svg", "csv"),
    workers: int = 2,
    options: ExportOptions | None = None,
    log: Callable[[str], None] | None = None,
) -> list[Path]:
    """Compute the paper's figures 5-14 for the 2-DOF example and write them to ``out``.

    Each figure ``figNN`` is written in every format of ``formats`` (``png``,
    ``svg``, ``pdf``, ``html``, and ``csv`` for its data), the figures with a caption and
    the tables with a header block that record their parameters
    (``fretwear.figures.record``). Excitation levels 6, 10 and 14 N,
    ``mu = 1``, ``F_N = 10`` N (section 2.1):

    * fig05, fig06: nonlinear FRFs of mass 1 and of the relative displacement,
      with the linear stuck and open FRFs;
    * fig07: wear ``w / u0`` over frequency x cycles by ``method`` (a, b, c: 6,
      10, 14 N);
    * fig08: pseudo-FRFs of mass 1 at 6 N: open, stuck, initial and worn;
    * fig09: pseudo-FRFs at five cycle counts (a, b, c: 6, 10, 14 N);
    * fig10: ``w(N)`` at ``f_study`` Hz and 10 N for 1, 3, 7, 15 and 21 harmonics;
    * fig11: stepping, polynomial (``polynomial_harmonics``, ``degree``) and
      time integration at ``f_study`` Hz and 10 N, with the exact load path
      for reference (a method that fails is left out and reported through
      ``log``);
    * fig12: the wear map by the polynomial method at 10 N;
    * fig13, fig14: half peak-to-peak relative displacement over frequency x
      cycles at 10 N, by ``method`` and by the polynomial method.

    The computations run in ``workers`` threads (the compiled kernels release
    the GIL) while the figures already computed are drawn. Warnings of the
    wear histories (e.g. the two-scale assumption) go to ``log``, with the
    figure, level and frequency they concern.

    Parameters
    ----------
    out : str or Path
        Output directory (created if missing).
    harmonics : int
        Harmonics of the FRFs, of the wear maps and of stepping.
    kw : float
        Archard coefficient (1/N).
    cycles : float
        Cycle horizon of the wear studies.
    frequencies, cycle_points : int
        Sizes of the frequency grid (``fmin``-``fmax`` Hz) and of the
        logarithmic cycle grid of the maps; the FRFs have four times the
        frequencies.
    method : str
        Slow-time method of the wear maps (see :func:`fretwear.wear.wear_history`;
        ``"auto"``: the exact load path for this model).
    tol : float
        Tolerance of stepping and of the time integration (fraction of ``u0``).
    formats : sequence of str
        Any of ``png``, ``svg``, ``pdf``, ``html``, ``csv``.
    workers : int
        Threads of the computations.
    options : ExportOptions, optional
        Size, resolution and font size of the figures.
    log : callable, optional
        Receives one line per figure written and per problem met.

    Returns
    -------
    list of Path
        The files written.
    """
    bad = sorted(set(formats) - {*EXPORT_FORMATS, "csv"})
    if bad:
        raise ValueError(f"formats must be among {(*EXPORT_FORMATS, 'csv')}, got {bad}")
    if not 0 < fmin < fmax or not 0 < f_study:
        raise ValueError(f"need 0 < fmin < fmax and f_study > 0 (Hz), got {fmin}, {fmax}, {f_study}")
    if int(frequencies) < 2 or int(cycle_points) < 3:
        raise ValueError("frequencies must be >= 2 and cycle_points >= 3")
    say = log or (lambda _msg: None)
    for fmt in formats:
        if fmt in EXPORT_FORMATS:
            load_backend("matplotlib" if fmt != "html" else "bokeh")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    record = {"mu": 1.0, "fn": 10.0, "kw": kw, "cycles": cycles, "harmonics": harmonics, "method": method,
              "tol": tol}  # fmt: skip

    def write(name: str, fig, table: Mapping[str, Any], model: str, **values) -> None:
        stamp = {**record, **values}
        paths = [out / f"{name}.{fmt}" for fmt in formats if fmt != "csv"]
        if paths:
            save_figures(fig, paths, options=options, caption=lambda markup: caption(stamp, model, markup))
        if "csv" in formats:
            paths.append(save_csv(table, out / f"{name}.csv", csv_header(stamp, model)))
        written.extend(paths)
        say(f"wrote {name} ({', '.join(formats)})")

    levels = (6.0, 10.0, 14.0)
    three = f"{MODEL}, F_ex = 6, 10 and 14 N"
    ten = f"{MODEL}, F_ex = 10 N"
    f_fine = np.linspace(fmin, fmax, 4 * (int(frequencies) - 1) + 1)
    f_map = np.linspace(fmin, fmax, int(frequencies))
    n_grid = cycle_grid(cycles, int(cycle_points))
    logn = np.log10(n_grid[1:])
    snapshots = snapshot_cycles(cycles)
    models = {fex: paper_model(fex=fex) for fex in levels}
    m10 = models[10.0]
    settings = {"harmonics": harmonics, "tol": tol}  # "auto" takes those of the method it picks
    if method != "auto":
        settings = method_options(method, settings)
    failures: list[str] = []

    with ThreadPoolExecutor(max(1, int(workers))) as pool:
        # every computation is queued at once, in the order the figures need them
        sweeps = {fex: pool.submit(sweep, m, 2 * np.pi * f_fine, harmonics) for fex, m in models.items()}
        maps = {fex: pool.submit(wear_map, m, f_map, n_grid, method=method, kw=kw, workers=1, **settings)
                for fex, m in models.items()}  # fmt: skip
        hc = pool.submit(harmonic_convergence, m10, f_study, kw=kw, cycles=cycles, tol=tol)
        methods = pool.submit(
            compare_methods, m10, f_study, kw=kw, cycles=cycles, harmonics=harmonics, tol=tol, degree=degree,
            overrides={"polynomial": {"harmonics": polynomial_harmonics}},
            on_failure=lambda method, exc: failures.append(f"fig11: method {method!r} failed: {exc}"),
        )  # fmt: skip
        poly = pool.submit(wear_map, m10, f_map, n_grid, method="polynomial", kw=kw,
                           harmonics=polynomial_harmonics, degree=degree, workers=1)  # fmt: skip
        lin = {
            fex: {s: linear_frf(m, 2 * np.pi * f_fine, s) for s in ("stuck", "open")}
            for fex, m in models.items()
        }
        x1 = {fex: {s: np.abs(u[:, 0]) for s, u in lu.items()} for fex, lu in lin.items()}

        # Fig. 5-6: nonlinear FRFs
        solutions = {fex: future.result().solutions for fex, future in sweeps.items()}
        amp = {fex: np.array([s.amplitude[0] for s in sols]) for fex, sols in solutions.items()}
        rel = {
            fex: np.array([s.relative_half_peak_to_peak[0] for s in sols]) for fex, sols in solutions.items()
        }
        curves = {f"{fex:g} N": (f_fine, a) for fex, a in amp.items()}
        curves |= {f"stuck ({fex:g} N)": (f_fine, x1[fex]["stuck"]) for fex in (levels[0], levels[-1])}
        curves |= {f"open ({fex:g} N)": (f_fine, x1[fex]["open"]) for fex in (levels[0], levels[-1])}
        dashed = [k for k in curves if k.startswith(("stuck", "open"))]
        table = {"f_hz": f_fine, **{f"x1_h1_{fex:g}N": a for fex, a in amp.items()}}
        fig = line_figure(curves, xlabel="frequency f (Hz)", ylabel="x₁ amplitude (m)", logy=True,
                          dashed=dashed, title="Fig. 5: FRF of mass 1")  # fmt: skip
        write("fig05", fig, table, three, method=None, kw=None, cycles=None, tol=None)
        curves = {f"{fex:g} N": (f_fine, r) for fex, r in rel.items()}
        curves |= {
            f"open ({fex:g} N)": (f_fine, np.abs(lin[fex]["open"] @ m10.relative_map()[0]))
            for fex in (levels[0], levels[-1])
        }
        table = {"f_hz": f_fine, **{f"xr_half_p2p_{fex:g}N": r for fex, r in rel.items()}}
        fig = line_figure(curves, xlabel="frequency f (Hz)", ylabel="x₁ − x₂, half peak-to-peak (m)",
                          logy=True, dashed=[k for k in curves if k.startswith("open")],
                          title="Fig. 6: FRF of the relative displacement")  # fmt: skip
        write("fig06", fig, table, three, method=None, kw=None, cycles=None, tol=None)

        # Fig. 7, 9, 13: wear maps by ``method``
        maps = {fex: future.result() for fex, future in maps.items()}
        say(f"computed the wear maps ({method})")
        for fex, wm in maps.items():
            _warnings("fig07", _map_histories(f"{fex:g} N", wm), say)
        panels = [
            wear_map_figure(
                f_map, n_grid, wm.wear_fraction[:, :, 0], title=f"Fig. 7{'abc'[i]}: Fₑₓ = {fex:g} N"
            )
            for i, (fex, wm) in enumerate(maps.items())
        ]
        write("fig07", _layout(panels, 3, options), _wear_map_table(maps), three)
        # Fig. 8: four cases at 6 N
        wm6 = maps[6.0]
        late = snapshots[-2]
        pseudo = wm6.pseudo_frf([0.0, late])[:, :, 0]
        curves = {
            "open": (f_fine, x1[6.0]["open"]),
            "stuck": (f_fine, x1[6.0]["stuck"]),
            "NL, N = 0": (f_map, pseudo[0]),
            f"NL, N = {late:.3g}": (f_map, pseudo[1]),
        }
        table = {"f_hz": f_map, "x1_h1_N0": pseudo[0], f"x1_h1_N{late:.6g}": pseudo[1]}
        fig = line_figure(curves, xlabel="frequency f (Hz)", ylabel="x₁ amplitude (m)", logy=True,
                          dashed=["open", "stuck"], title="Fig. 8: pseudo-FRFs of mass 1, 6 N")  # fmt: skip
        write("fig08", fig, table, MODEL, fex=6.0)
        # Fig. 9: pseudo-FRFs at several cycle counts
        panels, table = [], {"f_hz": f_map}
        for i, (fex, wm) in enumerate(maps.items()):
            pseudo = wm.pseudo_frf(snapshots)[:, :, 0]
            curves = {"open": (f_fine, x1[fex]["open"]), "stuck": (f_fine, x1[fex]["stuck"])}
            curves |= {f"N = {n:.3g}": (f_map, p) for n, p in zip(snapshots, pseudo, strict=True)}
            table |= {f"x1_h1_{fex:g}N_N{n:.6g}": p for n, p in zip(snapshots, pseudo, strict=True)}
            panels.append(
                line_figure(
                    curves,
                    xlabel="frequency f (Hz)",
                    ylabel="x₁ amplitude (m)",
                    logy=True,
                    dashed=["open", "stuck"],
                    title=f"Fig. 9{'abc'[i]}: Fₑₓ = {fex:g} N",
                )
            )
        write("fig09", _layout(panels, 1, options), table, three)

        # Fig. 10: harmonic convergence at f_study, 10 N
        histories = hc.result()
        _warnings("fig10", {f"Nh = {nh}": h for nh, h in histories.items()}, say)
        dense = cycle_grid(cycles)
        curves = {f"Nh = {nh}": wear_curve(h, dense) for nh, h in histories.items()}
        fig = line_figure(curves, xlabel="cycles N", ylabel="w / u₀", logx=True,
                          legend_labels={k: k.replace("Nh", "Nₕ") for k in curves},
                          title=f"Fig. 10: harmonics, {f_study:g} Hz, 10 N")  # fmt: skip
        table = _history_table({f"{nh}": h for nh, h in histories.items()}, "harmonics")
        write("fig10", fig, table, ten, method="stepping", harmonics=None, f=f_study)

        # Fig. 11: every slow-time method at f_study, 10 N
        histories = methods.result()
        for failure in failures:
            say(failure)
        _warnings("fig11", histories, say)
        exact = wear_history(m10, 2 * np.pi * f_study, kw=kw, cycles=cycles)  # the exact answer, dashed
        for h in histories.values():
            if h.label != "exact" and (note := h.error_note(exact)):
                say(f"fig11: {note}")
        histories[EXACT_REFERENCE] = exact
        curves = {m: wear_curve(h, dense) for m, h in histories.items()}
        fig = line_figure(curves, xlabel="cycles N", ylabel="w / u₀", logx=True, dashed=(EXACT_REFERENCE,),
                          legend_labels={m: h.label for m, h in histories.items() if m != EXACT_REFERENCE},
                          title=f"Fig. 11: slow-time methods, {f_study:g} Hz, 10 N")  # fmt: skip
        write("fig11", fig, _history_table(histories, "method"), ten, method=None, f=f_study, degree=degree)

        # Fig. 12, 14: polynomial wear map at 10 N; Fig. 13: relative displacement by ``method``
        poly = poly.result()
        say("computed the polynomial wear map")
        _warnings("fig12", _map_histories("10 N", poly), say)
    stamp_poly = {"method": "polynomial", "harmonics": polynomial_harmonics, "degree": degree, "tol": None}
    fig = wear_map_figure(
        f_map, n_grid, poly.wear_fraction[:, :, 0], title="Fig. 12: polynomial method, 10 N"
    )
    write("fig12", fig, poly.long_table(), ten, **stamp_poly)
    for name, wm, label, stamp in (
        ("fig13", maps[10.0], method, {}),
        ("fig14", poly, "polynomial", stamp_poly),
    ):
        z = np.log10(positive(wm.relative_half_peak_to_peak[:, 1:, 0].T))
        top = np.nanmax(z)
        fig = map_figure(f_map, logn, z, xlabel="frequency f (Hz)", ylabel="log₁₀ N (cycles)",
                         zlabel="log₁₀ |x₁ − x₂| (m)", clim=(top - 4, top), cmap="magma",
                         title=f"Fig. {name[-2:]}: relative displacement, {label}, 10 N")  # fmt: skip
        write(name, fig, wm.long_table(), ten, **stamp)
    return written
