"""The Zarr store of a study: its template (metadata only), creation, the checks of a resume, reading it."""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from .compute import INTEGER_FILL, STATUS, Work, method_label, outputs, pair_method, reported_dofs
from .layout import Layout, layout
from .spec import SpecError, StudySpec

__all__ = ["create_store", "open_store", "open_study", "template"]

_UNITS = {
    "cycles_to": "cycles",
    "wear_fraction": "-",
    "wear_amplitude": "m",
    "amplitude": "m",
    "relative_amplitude": "m",
    "sliding_distance": "m",
    "friction_energy": "J",
    "slip_distance": "m",
    "mean_pressure": "Pa",
    "wear_depth": "m",
    "wear_pressure": "Pa",
    "magnification": "-",
    "peak_frequency": "Hz",
    "peak_blade": "-",
    "delta": "-",
}
_LONG_NAMES = {
    "cycles_to": "cycles to w = fraction * u0 (inf: the contact sticks; NaN: beyond the horizon or failed)",
    "wear_fraction": "wear depth over initial interference w / u0",
    "wear_amplitude": "first-harmonic amplitude of each DOF along the wear history",
    "amplitude": "first-harmonic amplitude of each DOF (no wear)",
    "relative_amplitude": "first-harmonic amplitude of each contact's relative displacement (no wear)",
    "sliding_distance": "distance slid per period by each friction contact (no wear)",
    "friction_energy": "energy dissipated per period by each friction contact (no wear)",
    "slip_distance": "distance slid per period by each contact pair (no wear)",
    "mean_pressure": "contact pressure of each pair, mean over the period (no wear)",
    "wear_depth": "worn depth of each contact pair along the wear history",
    "wear_pressure": "contact pressure of each pair, mean over the period, along the wear history",
    "magnification": "amplitude magnification factor: largest blade-tip amplitude over the tuned peak, both "
    "in the band",
    "peak_frequency": "frequency of the largest blade-tip amplitude",
    "peak_blade": "blade of the largest amplitude (0 to sectors - 1; -1: not computed)",
    "delta": "the draw's blade stiffness deviations delta_i (kb1, kb2 times 1 + delta_i)",
}
#: the attributes of the coordinates every result shares (also :mod:`fretwear._xarray`)
CYCLES_ATTRS = {"units": "cycles", "long_name": "vibration cycles N"}
POSITION_ATTRS = {"units": "m", "long_name": "coordinate along the interface"}
#: what the variables of a model with contact pairs mean where it differs from 1-D contacts
_PAIR_NAMES = {
    "amplitude": "first-harmonic amplitude of each reported DOF (no wear)",
    "friction_energy": "energy dissipated per period by friction on the interface (no wear; J per m in 2-D)",
    "cycles_to": "cycles to the worn depth at the deepest pair (inf: no wear; NaN: not reached, or failed)",
}


def _names(spec: StudySpec) -> dict[str, list[str]]:
    model = spec.model
    if spec.pairs:
        return {"dof": list(reported_dofs(model)), "pair": [f"pair{j + 1}" for j in range(model.n_pairs)]}
    if spec.model_kind == "paper":
        return {"dof": ["x1", "x2"], "contact": ["xr"], "friction_contact": ["xr"]}
    return {
        "dof": [f"x{i + 1}" for i in range(model.n_dofs)],
        "contact": [f"xr{j + 1}" for j in range(len(model.contacts))],
        "friction_contact": [f"xr{j + 1}" for j in range(len(model.friction))],
    }


def template(spec: StudySpec, lay: Layout):
    """The empty Dataset of the study (dask arrays: only metadata is written), and its encoding."""
    import dask.array as da
    import xarray as xr

    work = Work.of(spec)
    dims = spec.dims
    coords: dict[str, Any] = {}
    if spec.mistuning:
        coords["sample"] = ("sample", np.arange(spec.samples), {"long_name": "mistuning pattern: row of "
                            "draw_mistuning(sectors, level, samples, seed)"})  # fmt: skip
    if spec.random:
        coords["sample"] = ("sample", np.arange(spec.samples), {"long_name": "random draw"})
        for name, values in spec.draws().items():
            p = spec.parameters[name]
            coords[name] = (
                "sample",
                values,
                {"units": p.unit, "long_name": p.long_name, **spec.random[name].describe()},
            )
    for name, values in spec.grid.items():
        p = spec.parameters[name]
        coords[name] = (name, values, {"units": p.unit, "long_name": p.long_name})
    variables = outputs(work)
    extra_dims = {d for d_, _ in variables.values() for d in d_}
    if "depth" in extra_dims:
        coords["depth"] = ("depth", np.array(spec.depths), {"units": "m", "long_name": "worn depth"})
    if "fraction" in extra_dims:
        coords["fraction"] = ("fraction", np.array(spec.fractions), {"units": "-", "long_name": "w / u0"})
    if "cycles" in extra_dims:
        coords["cycles"] = ("cycles", spec.cycle_grid(), CYCLES_ATTRS)
    if "blade" in extra_dims:
        coords["blade"] = ("blade", np.arange(spec.model.n_dofs // 3), {"long_name": "blade (its sector)"})
    for d, names in _names(spec).items():
        if d in extra_dims:
            coords[d] = (d, np.array(names))
    if "pair" in extra_dims:
        position = spec.model.pairs.position
        coords["position"] = ("pair", position, POSITION_ATTRS)
    data_vars: dict[str, Any] = {}
    encoding: dict[str, Any] = {}
    for name, (extra, shape) in variables.items():
        chunks = lay.chunks + shape
        data_vars[name] = (
            dims + extra,
            # an integer variable is written whole here (its fill value is not NaN), as status
            np.full(lay.shape + shape, INTEGER_FILL[name], dtype=np.int16)
            if name in INTEGER_FILL
            else da.full(lay.shape + shape, np.nan, chunks=chunks),
            {
                "units": _UNITS[name],
                "long_name": (_PAIR_NAMES if spec.pairs else {}).get(name, _LONG_NAMES[name]),
            },
        )
        encoding[name] = {"chunks": chunks, **({"_FillValue": None} if name in INTEGER_FILL else {})}
    data_vars["status"] = (
        dims,
        np.zeros(lay.shape, dtype=np.int8),
        {
            "long_name": "status of the point",
            "flag_values": list(range(len(STATUS))),
            "flag_meanings": " ".join(STATUS),
        },
    )
    encoding["status"] = {"chunks": lay.chunks, "_FillValue": None}
    data_vars["task_seconds"] = (
        ("task",),
        np.full(lay.n_tasks, np.nan),
        {"units": "s", "long_name": "compute time of each task (NaN: not computed)"},
    )
    encoding["task_seconds"] = {"chunks": (1,)}
    resolved = spec.resolved()
    attrs = {
        "title": spec.title,
        "quantities": list(spec.quantities),
        "fretwear_version": __version__,
        "spec": spec.text,
        "spec_resolved": json.dumps(resolved, sort_keys=True),
        "study_key": spec.key(),
        "points_per_task": int(np.prod(lay.chunks, dtype=np.int64)),
        "fixed_parameters": json.dumps(spec.fixed, sort_keys=True),
        "created_by": "fretwear study",
    }
    if spec.pairs:
        attrs["model"] = spec.model_kind
        attrs["reduce_hz"] = spec.reduce_hz
        if spec.wear and "method" not in spec.grid:
            attrs["wear_method"] = pair_method(spec.fixed)[0]
    elif spec.wear and not {"method", "dynamics", "harmonics"} & set(spec.grid):
        attrs["wear_method"] = method_label(spec.model, spec.fixed)
    if spec.mistuning:
        attrs.update(_tuned(spec))
    ds = xr.Dataset(data_vars, coords=coords, attrs=attrs)
    return ds, encoding


def _tuned(spec: StudySpec) -> dict[str, Any]:
    """The attributes of a mistuning study: the model, the band, the tuned disk's peak in it (by
    :func:`fretwear.disk.magnification` of the zero pattern) and Whitehead's bound ``(1 + sqrt(N)) / 2``."""
    from ..disk import magnification

    info = spec.model.info
    res = magnification(np.zeros((1, info["sectors"])), tuple(spec.fixed["band"]), **spec.model_parameters)
    return {
        "model": spec.model_kind,
        "sectors": int(info["sectors"]),
        "engine_order": int(info["engine_order"]),
        "band_hz": [float(f) for f in res.band],
        "tuned_amplitude": res.tuned,
        "tuned_amplitude_units": "m",
        "tuned_frequency": res.tuned_frequency,
        "tuned_frequency_units": "Hz",
        "whitehead": float(res.whitehead),
        "seed": spec.seed,
        "patterns": f"point (level, sample i): row i of draw_mistuning({info['sectors']}, level, "
        f"{spec.samples}, seed={spec.seed}) (fretwear.disk)",
    }


def create_store(spec: StudySpec, lay: Layout, out: Path) -> None:
    ds, encoding = template(spec, lay)
    ds.to_zarr(out, mode="w", compute=False, encoding=encoding, zarr_format=2, consolidated=True)


def open_store(spec: StudySpec, out: Path, overwrite: bool):
    """The Zarr group of the study at ``out`` (created if needed); :class:`SpecError` for another study."""
    import zarr

    if out.exists() and overwrite:
        shutil.rmtree(out) if out.is_dir() else out.unlink()
    if not out.exists():
        if not out.resolve().parent.is_dir():
            raise SpecError("--out", f"the folder of {str(out)!r} does not exist")
        create_store(spec, layout(spec), out)
        return zarr.open_group(out, mode="r+"), False
    try:
        group = zarr.open_group(out, mode="r+")
        key = group.attrs.get("study_key")
    except Exception:  # noqa: BLE001 - anything that is not a readable store
        key = None
    if key is None:
        raise SpecError("--out", f"{str(out)!r} exists and is not a fretwear study store")
    if key != spec.key():
        old = json.loads(group.attrs["spec_resolved"])
        new = spec.resolved()
        diff = sorted(k for k in set(old) | set(new) if old.get(k) != new.get(k))
        raise SpecError(
            "--out",
            f"{str(out)!r} holds another study (differs in: {', '.join(diff)}); "
            "choose another --out, or --overwrite to replace it",
        )
    return group, True


def open_study(path: str | Path):
    """The study stored at ``path`` (a Zarr store written by ``fretwear study``), loaded into memory.

    Equivalent to ``xarray.open_zarr(path).load()`` with checks: the store
    exists, is readable, and was written by ``fretwear study`` (its
    ``created_by`` attribute and its ``status`` variable). Points not computed
    yet (status 0) are kept, NaN like failed ones.

    Raises
    ------
    ValueError
        One line naming ``path`` and what is wrong with it.
    """
    import xarray as xr

    path = Path(path)
    if not path.exists():
        raise ValueError(f"study {str(path)!r}: no such file or folder")
    try:
        ds = xr.open_zarr(path)
    except Exception as exc:  # noqa: BLE001 - anything that is not a readable Zarr store
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ValueError(f"study {str(path)!r}: not a readable Zarr store ({first})") from None
    if ds.attrs.get("created_by") != "fretwear study" or "status" not in ds:
        raise ValueError(
            f"study {str(path)!r}: a Zarr store but not a fretwear study (no 'created_by = fretwear study' "
            "attribute or no 'status' variable)"
        )
    return ds.load()
