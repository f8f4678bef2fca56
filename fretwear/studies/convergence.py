"""Convergence studies of the wear answer: harmonics (paper Fig. 10) and methods (Fig. 11-12)."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from ..model import Model
from ..wear import METHODS, WearHistory, method_options, wear_history

__all__ = ["harmonic_convergence", "compare_methods"]


def harmonic_convergence(
    model: Model, frequency: float, harmonics=(1, 3, 7, 15, 21), **options
) -> dict[int, WearHistory]:
    """``w(N)`` at ``frequency`` (Hz) for several harmonic counts (paper Fig. 10), by stepping."""
    return {int(nh): wear_history(model, 2 * np.pi * frequency, "stepping", harmonics=int(nh), **options)
            for nh in harmonics}  # fmt: skip


def compare_methods(
    model: Model,
    frequency: float,
    methods: Sequence[str] | None = None,
    *,
    overrides: Mapping[str, Mapping[str, Any]] | None = None,
    on_failure: Callable[[str, Exception], None] | None = None,
    kw: float = 1e-11,
    cycles: float = 1e5,
    **settings,
) -> dict[str, WearHistory]:
    """The same wear evolution at ``frequency`` (Hz) by several methods (paper Fig. 11-12).

    Each method (default: every one of :data:`~fretwear.wear.METHODS`) takes from
    ``settings`` the options it has (:func:`~fretwear.wear.method_options`), then
    those of ``overrides[method]``, e.g. ``overrides={"polynomial": {"harmonics": 3}}``.
    A method that raises is reported to ``on_failure(method, error)`` and left
    out when ``on_failure`` is given; otherwise the error propagates.
    """
    out = {}
    for method in methods or tuple(METHODS):
        opts = method_options(method, {**settings, **(overrides or {}).get(method, {})})
        try:
            out[method] = wear_history(model, 2 * np.pi * frequency, method, kw=kw, cycles=cycles, **opts)
        except Exception as exc:
            if on_failure is None:
                raise
            on_failure(method, exc)
    return out
