"""The layout of a study: its points cut into rectangular blocks, one Dask task (and one Zarr chunk) each."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .compute import pair_method, point_method
from .spec import FRF_HARMONICS, StudySpec

__all__ = ["Layout", "block_params", "layout"]

#: estimated compute time of one point (s) by quantity and slow-time method, at Nh = 21 on the DLFT
#: dynamics, to size tasks; "-shooting": on the exact dynamics (exact: 1.5 ms a point once the sliding
#: table of the frequency is built, about 1 s, once per worker)
POINT_SECONDS = {"frf": 1e-3, "exact": 0.08, "exact-shooting": 0.01, "stepping": 1.0,
                 "stepping-shooting": 0.05, "polynomial": 2.0, "time": 10.0}  # fmt: skip
#: the same for a model with contact pairs, per pair at Nh = 7 (the 32-pair benchmark reduced: a periodic
#: solve 0.7 s, a stepping wear history 5 s; measured on 2 cores)
PAIR_SECONDS = {"frf": 0.7 / 32, "stepping": 5.0 / 32, "polynomial": 10.0 / 32}
#: the same for a mistuning pattern of the 24-sector disk (an eigenproblem of 72 DOFs and the peak search:
#: 24 ms on the loaded 2-core machine), scaled as the cube of the sectors above 24 (below, as 24: an
#: 8-sector pattern took 7 ms, the peak search more than the eigenproblem)
MAGNIFICATION_SECONDS = 0.024
#: target compute time of one task (s): Dask's overhead is a few ms per task
TASK_SECONDS = 2.0
#: tasks a study is cut into at least (when it has that many points): load balance and progress
MIN_TASKS = 32


@dataclass(frozen=True)
class Layout:
    """Blocks of points: the study's shape cut into chunks, one task (and one Zarr chunk) each."""

    shape: tuple[int, ...]
    chunks: tuple[int, ...]

    @property
    def grid(self) -> tuple[int, ...]:
        return tuple(-(-n // c) for n, c in zip(self.shape, self.chunks, strict=True))

    @property
    def n_tasks(self) -> int:
        return int(np.prod(self.grid, dtype=np.int64))

    def block(self, task: int) -> tuple[slice, ...]:
        """The slices of block ``task`` (C order over the chunk grid)."""
        index = np.unravel_index(task, self.grid) if self.shape else ()
        return tuple(
            slice(int(i) * c, min((int(i) + 1) * c, n))
            for i, c, n in zip(index, self.chunks, self.shape, strict=True)
        )


def _point_seconds(spec: StudySpec) -> float:
    """Estimated compute time of one point (s), from the quantities, methods and ``Nh``."""
    if spec.mistuning:
        return MAGNIFICATION_SECONDS * max(1.0, (spec.model.n_dofs / 72) ** 3)
    if spec.pairs:
        nh = np.max(spec.grid.get("harmonics", [spec.fixed["harmonics"]])) / 7
        methods = (
            spec.grid["method"].tolist() if "method" in spec.grid else [spec.fixed.get("method", "auto")]
        )
        seconds = PAIR_SECONDS["frf"] if "frf" in spec.quantities else 0.0
        if spec.wear:
            seconds += np.mean([PAIR_SECONDS[pair_method({"method": m})[0]] for m in methods])
        return float(seconds * spec.model.n_pairs * max(1.0, nh))
    nh = np.max(spec.grid.get("harmonics", [spec.fixed.get("harmonics", FRF_HARMONICS)]))
    seconds = POINT_SECONDS["frf"] * max(1.0, nh / 7) if "frf" in spec.quantities else 0.0
    if spec.wear:
        methods = spec.grid["method"].tolist() if "method" in spec.grid else [spec.fixed["method"]]
        p = {**spec.fixed, "harmonics": spec.fixed.get("harmonics", spec.grid.get("harmonics", [None])[0])}
        runs = [point_method(spec.model, {**p, "method": m}) for m in methods]
        seconds += np.mean([POINT_SECONDS[_cost_key(n, o)] * max(0.25, o.get("harmonics", 21) / 21)
                            for n, o in runs])  # fmt: skip
    return float(seconds)


def _cost_key(name: str, options: Mapping[str, Any]) -> str:
    """The key of :data:`POINT_SECONDS` of a method run with ``options``."""
    return f"{name}-shooting" if options.get("dynamics") == "shooting" else name


def layout(spec: StudySpec) -> Layout:
    """The study's blocks: about :data:`TASK_SECONDS` of estimated work each, and at least
    :data:`MIN_TASKS` of them; ``points_per_task`` of the spec overrides. The blocks fill the
    last axis first (``frequency``, along which an FRF is computed with warm starts).

    The layout depends on the spec only (not on the cluster), so that reruns find the same blocks.
    """
    shape, n = spec.shape, spec.n_points
    ppt = spec.points_per_task
    if ppt is None:
        ppt = min(max(1, round(TASK_SECONDS / _point_seconds(spec))), max(1, -(-n // MIN_TASKS)))
    chunks, left = [], ppt
    for size in reversed(shape):
        c = max(1, min(size, left))
        chunks.append(c)
        left = max(1, left // c)
    return Layout(tuple(shape), tuple(reversed(chunks)))


def block_params(spec: StudySpec, lay: Layout, draws: Mapping[str, np.ndarray], task: int):
    """The varying parameters at the points of block ``task`` (flattened, C order) and the slices."""
    slices = lay.block(task)
    shape = tuple(s.stop - s.start for s in slices)
    params = {}
    for d, (dim, sl) in enumerate(zip(spec.dims, slices, strict=True)):
        axis = [1] * len(shape)
        axis[d] = shape[d]
        if dim == "sample":
            for name, values in draws.items():
                params[name] = np.broadcast_to(values[sl].reshape(axis), shape).ravel()
            if spec.mistuning:  # the task draws the point's pattern from its index (fretwear.studies.spec)
                index = np.arange(sl.start, sl.stop).reshape(axis)
                params["sample"] = np.broadcast_to(index, shape).ravel()
        else:
            params[dim] = np.broadcast_to(spec.grid[dim][sl].reshape(axis), shape).ravel()
    return params, slices, shape
