"""Every user-facing number of fretwear, declared once: name, label, unit, valid range and why.

The command line (:mod:`fretwear.cli`, ``fretwear interface``, ``fretwear study``),
the settings files it reads (``--settings``) and the study specs
(:mod:`fretwear.studies.spec`) check their numbers against this table, before
any work starts, with one message format::

    >>> check("fex", -10)
    Traceback (most recent call last):
    ...
    ValueError: fex must be a number > 0 and <= 1000 N, got -10

Upper bounds keep a run within the memory and a stated time of a 2-core,
24 GB machine (measured; the figure is in each parameter's ``reason``), or
reject what no physical input can be (a typo, a sign error). Lower bounds are
those of the mathematics (a count >= 1, a stiffness > 0).
"""

from __future__ import annotations

import argparse
import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import Any

__all__ = ["Parameter", "PARAMETERS", "check", "argument_type", "describe"]


@dataclass(frozen=True)
class Parameter:
    """A number a user gives, with its valid range.

    Attributes
    ----------
    name : str
        Key in :data:`PARAMETERS` (the settings-file key and option dest where there is one).
    label : str
        Name shown in messages.
    unit : str
        SI unit ("" for a pure number).
    low, high : float
        Bounds of the valid range.
    low_strict, high_strict : bool
        Whether the bound itself is excluded.
    integer : bool
        Whether the value is a whole number.
    doc : str
        What it is.
    reason : str
        Why the bounds are where they are.
    """

    name: str
    label: str
    unit: str
    low: float
    high: float
    low_strict: bool = False
    high_strict: bool = False
    integer: bool = False
    doc: str = ""
    reason: str = ""

    def range_text(self) -> str:
        """``"an integer in [1, 64]"``, ``"a number > 0 and <= 1000 N"``."""
        unit = f" {self.unit}" if self.unit else ""
        if self.integer:
            return f"an integer in [{int(self.low)}, {int(self.high)}]{unit}"
        low = f"{'>' if self.low_strict else '>='} {self.low:g}"
        high = f"{'<' if self.high_strict else '<='} {self.high:g}"
        return f"a number {low} and {high}{unit}"

    def valid(self, value: Any) -> bool:
        """Whether ``value`` (a number, not a bool) is in the range (and whole, for an integer)."""
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            return False
        if self.integer and not float(value).is_integer():
            return False
        above = value > self.low if self.low_strict else value >= self.low
        below = value < self.high if self.high_strict else value <= self.high
        return above and below

    def check(self, value: Any, name: str | None = None) -> float | int:
        """``value`` as ``int`` or ``float``; ``ValueError("NAME must be RANGE, got VALUE")`` otherwise."""
        if not self.valid(value):
            raise ValueError(f"{name or self.name} must be {self.range_text()}, got {value!r}")
        return int(value) if self.integer else float(value)

    def parse(self, text: str) -> float | int:
        """The number written ``text`` (``"1e3"`` is the integer 1000), checked; ``ValueError`` otherwise."""
        try:
            value: float | int = float(text)
        except (TypeError, ValueError):
            value = math.nan
        if not self.valid(value):
            raise ValueError(f"must be {self.range_text()}, got {text!r}")
        return int(value) if self.integer else value


_CORES = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
_HZ = "> 0: a period must exist; 1e5 Hz only catches typos (any frequency solves alike)"
_FORCE = "> 0: some excitation (the dashboard refuses 0 too); 1e3 N is 100 x the paper's friction limit"

# Each row: name, label, unit, low, high, flags ("<" strict low, ">" strict high, "i" integer), doc, reason.
# The times were measured on the project's 2-core, 24 GB machine with the kernels cached (other jobs ran).
# fmt: off
_ROWS = (
    # -- the paper model
    ("fex", "F_ex", "N", 0.0, 1e3, "<", "excitation amplitude on mass 1", _FORCE),
    ("force_scale", "force scale", "", 0.0, 1e3, "<", "factor on the forces of a model file", _FORCE),
    ("mu", "mu", "", 0.0, 10.0, "", "friction coefficient", "0: frictionless; no dry contact has mu > 10"),
    ("fn", "F_N", "N", 0.0, 1e4, "", "initial normal load",
     "0: the contact slides freely; 1e4 N is 1000 x the paper's load (the dashboard's bound)"),
    ("u0", "u0", "m", 0.0, 1e-3, "", "initial normal interference (F_N = kn u0)",
     "1 mm is 1000 x the paper's u0 (kn u0 = 1e4 N at the paper's kn)"),
    ("kn", "k_n", "N/m", 0.0, 1e12, "<", "normal contact stiffness",
     "> 0: the spring carries the load; 1e12 N/m on 1 kg is a 1.6e5 Hz contact mode, a typo"),
    # -- wear
    ("kw", "K_w", "1/N", 0.0, 1e-4, "<", "Archard wear coefficient of a lumped contact (dw/dN = K_w F_N s)",
     "K_w = 0 is no wear (frf and point compute that): the slow time K_w kn N vanishes and the cycles "
     "to a worn depth are infinite (NaN and ZeroDivisionError before); 1e-4 wears through in one cycle"),
    ("cycles", "cycles", "cycles", 0.0, 1e30, "<", "wear horizon N",
     "> 0; any horizon: the slow-time step does not depend on it (1e30 keeps K_w N p s in float range)"),
    ("fixed_step", "fixed step", "cycles", 0.0, 1e30, "<", "fixed slow-time step", "as the horizon"),
    ("tol", "tolerance", "", 0.0, 0.5, "<", "slow-time local error tolerance on w/u0",
     "> 0; an error of half the interference controls nothing (the dashboard's bound)"),
    ("degree", "polynomial degree", "", 1, 12, "i", "degree of the polynomial slow-time method",
     "the dashboard's bound; degree 0 failed after 9.7 s of figures"),
    # -- harmonic balance
    ("harmonics", "Nh", "", 1, 64, "i", "highest harmonic",
     "the dashboard's bound: frf of 101 frequencies at Nh = 64 takes 3.5 s, a stepping wear history "
     "2.2 s; Nh = 256 took 131 s, 1000 ran for minutes"),
    ("samples", "samples per period", "", 3, 8192, "i", "time samples per period (>= 2 Nh + 1)",
     "8192 is 128 per harmonic at Nh = 64; the Jacobian blocks grow as samples x Nh^2"),
    # -- frequencies and grids
    ("f", "f", "Hz", 0.0, 1e5, "<", "excitation frequency", _HZ),
    ("fmin", "f min", "Hz", 0.0, 1e5, "<", "lowest frequency", _HZ),
    ("fmax", "f max", "Hz", 0.0, 1e5, "<", "highest frequency", _HZ),
    ("n", "frequencies", "", 1, 10_001, "i", "points of a frequency sweep",
     "2001 points at Nh = 64: 8.5 s and 0.38 GB, so 10 001 about 35 s and 1.3 GB; 1e8 needed 47.7 GiB"),
    ("nf", "map frequencies", "", 1, 401, "i", "frequencies of a wear map",
     "the dashboard's bound: 401 x 400 exact map 7.5 s and 0.3 GB (CSV 25 MB); stepping about 80 s "
     "at Nh = 7, 15 min at Nh = 64"),
    ("ncycles", "cycle counts", "", 2, 400, "i", "log-spaced cycle counts of a wear map",
     "the dashboard's bound (see the frequencies)"),
    ("target", "target error", "", 0.0, 1.0, "<>", "target relative error", "a relative error"),
    # -- figures
    ("dpi", "dpi", "", 50, 600, "i", "resolution of PNG files",
     "30 x 30 in at 600 dpi is 324 Mpixel (1.3 GB of RGBA)"),
    ("width", "width", "in", 2.0, 30.0, "", "figure width", "the axes need 2 in; 30 in: a poster"),
    ("height", "height", "in", 2.0, 30.0, "", "figure height", "as the width"),
    ("fontsize", "font size", "pt", 4.0, 40.0, "", "axis label font size", "legible to large"),
    # -- studies
    ("draws", "random draws", "", 1, 100_000, "i", "random draws of a study",
     "1000 draws of the example take 32.5 s on 2 workers: 1e5 about 1 h; 1e8 grew past 4 GB"),
    ("points", "study points", "", 1, 1_000_000, "i", "points of a study (grid x draws)",
     "at about 30 ms a point, 1e6 points are 4 h on 2 workers"),
    ("grid_num", "grid values", "", 1, 10_000, "i", "values of one grid axis", "as the study points"),
    ("seed", "seed", "", 0, 2**63 - 1, "i", "seed of the random draws", "NumPy's seed range"),
    ("workers", "workers", "", 1, 2 * _CORES, "i", "local Dask worker processes",
     f"2 per core ({_CORES} here): each is a process of about 200 MB that needs a core; 100 leaked "
     "semaphores"),
    ("retries", "retries", "", 0, 10, "i", "reruns of a failed task", "a task failing 10 times has a reason"),
    ("points_per_task", "points per task", "", 1, 100_000, "i", "points of one task", "as the draws"),
    # -- contact interfaces
    ("contact_nodes", "contact nodes", "", 3, 128, "i", "contact pairs of the cylinder-on-flat benchmark",
     "fretwear.interface.fe.MAX_CONTACT_NODES: 128 pairs are 66 282 DOFs, Craig-Bampton 42 s and 42 s a "
     "solve; 256 pairs are 199 730 DOFs and 0.85 GB to build; 100 000 ran out of memory"),
    ("interface_kw", "K_w", "1/Pa", 0.0, 1e-4, "<", "Archard wear coefficient of an interface "
     "(dw/dN = K_w p s, p the contact pressure)", "as the lumped K_w"),
    ("q_ratio", "Q0 / (mu P)", "", 0.0, 2.0, "", "tangential load ratio of the benchmark",
     "gross slip from 1 (1.05 covers it); at 5 the static solve ran over a minute"),
    ("window", "window", "", 1.0, 5.0, "<", "contact window half-width / Hertz a",
     "> 1: the window holds the contact; beyond 5 a the outer pairs carry nothing"),
    ("line_load", "normal load", "N/m", 0.0, 1e8, "<", "benchmark normal load per unit length",
     "1e8 N/m (100 kN/mm) is beyond the flat's yield"),
    ("interface_mu", "mu", "", 0.0, 10.0, "", "benchmark friction coefficient", "as mu"),
    ("drive", "drive", "m", 0.0, 1e-2, "<", "amplitude of the loading arm's end", "1 cm is beyond fretting"),
    ("arm_stiffness", "arm stiffness", "N/m per m", 0.0, 1e14, "<", "loading arm stiffness", "a typo guard"),
    ("rtol", "rtol", "", 0.0, 0.5, "<", "slow-time step tolerance on the worn depth", "as the tolerance"),
    ("converge", "convergence tolerance", "", 0.0, 0.5, "<", "profile convergence tolerance", "as rtol"),
)
# fmt: on

#: every user-facing number, by name
PARAMETERS: Mapping[str, Parameter] = {
    row[0]: Parameter(
        *row[:5],
        low_strict="<" in row[5],
        high_strict=">" in row[5],
        integer="i" in row[5],
        doc=row[6],
        reason=row[7],
    )  # fmt: skip
    for row in _ROWS
}


def describe(name: str) -> Parameter:
    """The :class:`Parameter` ``name`` (``KeyError`` listing the names if unknown)."""
    try:
        return PARAMETERS[name]
    except KeyError:
        raise KeyError(f"no parameter {name!r} (known: {', '.join(PARAMETERS)})") from None


def check(name: str, value: Any, label: str | None = None) -> float | int:
    """``value`` checked against parameter ``name``: ``ValueError("LABEL must be RANGE, got VALUE")``.

    ``label`` (default ``name``) is how the message names it, e.g. ``"--fex"`` or ``"parameters.fex"``.
    """
    return describe(name).check(value, label or name)


def argument_type(name: str, low: float | None = None) -> Callable[[str], float | int]:
    """An ``argparse`` type for parameter ``name``; ``low`` narrows the range for one command."""
    param = describe(name)
    if low is not None:
        param = replace(param, low=low)

    def convert(text: str) -> float | int:
        try:
            return param.parse(text)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    convert.__name__ = name  # argparse names the type in its own messages
    convert.parameter = param  # type: ignore[attr-defined]  # for the help texts (arguments.document)
    return convert
