"""Every user-facing number of fretwear, declared once: name, label, unit, valid range and why.

The command line (:mod:`fretwear.cli`, ``fretwear interface``, ``fretwear study``),
the settings files it reads (``--settings``), the study specs
(``fretwear.studies.spec``) and the dashboard (``app.state.Controls``, its
sidebar) check their numbers against this table, before any work starts, with
one message format::

    >>> check("fex", -10)
    Traceback (most recent call last):
    ...
    ValueError: fex must be a number > 0 and <= 1000 N, got -10

Upper bounds keep a run within the memory and a stated time of a 2-core,
24 GB machine (measured; the figure is in each parameter's ``reason``), or
reject what no physical input can be (a typo, a sign error). Lower bounds are
those of the mathematics (a count >= 1, a stiffness > 0).

Each row also holds what the front ends build from it: the default, the
command-line flag, the symbol of a figure's parameter record, and the
dashboard's control (its name, HTML label, glossary entry and slider, a
narrower range than the valid one). ``tests/test_parameters.py`` checks the
dashboard, every numeric option of the CLI and the study spec against it.
"""

from __future__ import annotations

import argparse
import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import Any

__all__ = ["Parameter", "PARAMETERS", "CONTROLS", "check", "argument_type", "describe"]


@dataclass(frozen=True)
class Parameter:
    """A number a user gives, with its valid range.

    Attributes
    ----------
    name : str
        Key in :data:`PARAMETERS` (the settings-file key and option dest where there is one).
    label : str
        Name shown in messages (the dashboard's too).
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
    default : float or int or None
        The value the front ends start from (the dashboard's control, an option left out, a study
        spec's parameter left out); None where the library or the model chooses.
    flag : str
        The command-line option, when not ``--name`` with dashes (:attr:`option`).
    symbol : str
        Its ASCII symbol in a figure's parameter record (``fretwear.figures.record``), default ``label``.
    html : str
        Label of its dashboard control, in HTML (symbols with subscripts).
    glossary : str or None
        Key of its entry in the dashboard's glossary (``app.glossary.TERMS``).
    control : str or None
        Name of its dashboard control (``app.state.Controls``); None if the dashboard has none.
    slider : (start, end, step) or None
        The control's slider (over ``log10`` of the value with ``log``): a narrower range than the
        valid one, where the lessons are; a typed value may be anywhere in the valid range.
    log : bool
        Whether the slider runs over ``log10`` of the value.
    defaults : tuple of (context, value)
        Defaults of the contexts (a command, ``"study"``) that start elsewhere, and why is in ``reason``.
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
    default: float | int | None = None
    flag: str = ""
    symbol: str = ""
    html: str = ""
    glossary: str | None = None
    control: str | None = None
    slider: tuple[float, float, float] | None = None
    log: bool = False
    defaults: tuple[tuple[str, float | int], ...] = ()

    def default_for(self, context: str) -> float | int | None:
        """The default in ``context`` (a command, ``"study"``): its own where it has one, else ``default``."""
        return dict(self.defaults).get(context, self.default)

    @property
    def option(self) -> str:
        """The command-line flag: ``flag``, else ``--name`` with dashes (``--fixed-step``)."""
        return self.flag or "--" + self.name.replace("_", "-")

    @property
    def soft_bounds(self) -> tuple[float, float] | None:
        """The slider's range in the parameter's unit (``10**`` its ends for a slider over log10)."""
        if self.slider is None:
            return None
        start, end, _ = self.slider
        return (10.0**start, 10.0**end) if self.log else (start, end)

    def range_text(self, whole: bool = False) -> str:
        """``"an integer in [1, 64]"``, ``"a number > 0 and <= 1000 N"``; with ``whole``, an integer's range
        as the dashboard words it: ``"a whole number >= 1 and <= 64"``."""
        unit = f" {self.unit}" if self.unit else ""
        if self.integer and whole:
            return f"a whole number >= {int(self.low)} and <= {int(self.high)}{unit}"
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
_HZ = "> 0: a period must exist; 1e5 Hz only catches typos (any frequency solves alike; the dashboard's \
slider covers the paper's band)"
_FORCE = "> 0: some excitation (the dashboard refuses 0 too); 1e3 N is 100 x the paper's friction limit"

# Each row: name, label, unit, low, high, flags ("<" strict low, ">" strict high, "i" integer), doc, reason,
# and the other columns of Parameter by keyword (default, the dashboard's control, ...) where they apply.
# The times were measured on the project's 2-core, 24 GB machine with the kernels cached (other jobs ran).
# fmt: off
_ROWS = (
    # -- the paper model
    ("fex", "F_ex", "N", 0.0, 1e3, "<", "excitation amplitude on mass 1", _FORCE,
     dict(default=10.0, control="fex", html="F<sub>ex</sub>: excitation on mass 1 (N)", glossary="F_ex",
          slider=(0.5, 30.0, 0.1), defaults=(("disk", 2.0),))),
    ("force_scale", "force scale", "", 0.0, 1e3, "<", "factor on the forces of a model file", _FORCE),
    ("mu", "mu", "", 0.0, 10.0, "<", "friction coefficient",
     "> 0: a friction contact (at 0 nothing sticks, the load ratio r = F_ex / (mu F_N) of the dashboard's "
     "regime map is infinite; a frictionless contact is a model file's); no dry contact has mu > 10",
     dict(default=1.0, control="mu", html="μ: friction coefficient", glossary="mu",
          slider=(0.05, 2.0, 0.01), defaults=(("disk", 0.3),))),
    ("fn", "F_N", "N", 0.0, 1e4, "<", "initial normal load",
     "> 0: a loaded contact (at 0 the interference u0 = F_N / kn is 0 and a wear history has no w / u0; "
     "the wear commands refused it already); 1e4 N is 1000 x the paper's load",
     dict(default=10.0, control="normal_load", html="F<sub>N</sub>: initial normal load (N)", glossary="F_N",
          slider=(1.0, 50.0, 0.5))),
    ("u0", "u0", "m", 0.0, 1e-3, "<", "initial normal interference (F_N = kn u0)",
     "> 0 as F_N; 1 mm is 1000 x the paper's u0 (kn u0 = 1e4 N at the paper's kn)"),
    ("kn", "k_n", "N/m", 0.0, 1e12, "<", "normal contact stiffness",
     "> 0: the spring carries the load; 1e12 N/m on 1 kg is a 1.6e5 Hz contact mode, a typo",
     dict(default=1e7)),
    # -- wear
    ("kw", "k_w", "1/N", 0.0, 1e-4, "<", "Archard wear coefficient of a lumped contact (dw/dN = k_w F_N s)",
     "k_w = 0 is no wear (frf and point compute that): the slow time k_w kn N vanishes and the cycles "
     "to a worn depth are infinite (NaN and ZeroDivisionError before); 1e-4 wears through in one cycle",
     dict(default=1e-11, control="kw", html="k<sub>w</sub>: Archard coefficient (1/N)", glossary="k_w",
          slider=(-14.0, -6.0, 0.1), log=True, defaults=(("disk", 1e-8),))),
    ("cycles", "cycle horizon", "cycles", 0.0, 1e30, "<", "wear horizon N",
     "> 0, not necessarily whole (the slow time is continuous); any horizon: the slow-time step does not "
     "depend on it (1e30 keeps K_w N p s in float range); the interface benchmark wears over 1e6 cycles",
     dict(default=1e5, symbol="horizon", control="horizon", html="Cycle horizon (cycles)", glossary="N",
          slider=(2.0, 8.0, 0.1), log=True, defaults=(("interface", 1e6), ("disk", 1e6)))),
    ("fixed_step", "fixed step", "cycles", 0.0, 1e30, "<", "fixed slow-time step", "as the horizon"),
    ("tol", "tolerance", "u0", 0.0, 0.5, "<", "slow-time local error tolerance on w/u0",
     "> 0; an error of half the interference controls nothing (the dashboard's bound); the dashboard "
     "starts at 1e-2 (fast), the paper's figures at 1e-3",
     dict(default=1e-2, control="tol", html="Tolerance (fraction of u<sub>0</sub>)", glossary="tolerance",
          slider=(-4.0, -1.0, 0.1), log=True, defaults=(("figures", 1e-3),))),
    ("degree", "polynomial degree", "", 1, 12, "i", "degree of the polynomial slow-time method",
     "the dashboard's bound; degree 0 failed after 9.7 s of figures",
     dict(default=4, symbol="degree", control="degree", html="Degree of the polynomial method",
          slider=(1, 12, 1))),
    # -- harmonic balance
    ("harmonics", "Nh", "", 1, 64, "i", "highest harmonic",
     "the dashboard's bound: frf of 101 frequencies at Nh = 64 takes 3.5 s, a stepping wear history "
     "2.2 s; Nh = 256 took 131 s, 1000 ran for minutes; the paper's figures and a study's frf use 21",
     dict(default=7, control="harmonics", html="N<sub>h</sub>: harmonics", glossary="Nh", slider=(1, 64, 1),
          defaults=(("figures", 21), ("study", 21)))),
    ("samples", "samples per period", "", 3, 8192, "i", "time samples per period (>= 2 Nh + 1)",
     "8192 is 128 per harmonic at Nh = 64; the Jacobian blocks grow as samples x Nh^2"),
    # -- frequencies and grids
    ("f", "f", "Hz", 0.0, 1e5, "<", "excitation frequency",
     _HZ + "; the paper's figures start at 0.7 Hz, the interface benchmark at 50 Hz",
     dict(defaults=(("figures", 0.7), ("interface", 50.0), ("disk", 205.0)))),
    ("fmin", "f min", "Hz", 0.0, 1e5, "<", "lowest frequency", _HZ,
     dict(default=0.3, control="fmin", html="f<sub>min</sub>", slider=(0.05, 3.0, 0.01),
          defaults=(("disk", 165.0),))),
    ("fmax", "f max", "Hz", 0.0, 1e5, "<", "highest frequency", _HZ,
     dict(default=1.3, control="fmax", html="f<sub>max</sub>", slider=(0.05, 3.0, 0.01),
          defaults=(("disk", 200.0),))),
    ("n", "frequencies", "", 1, 10_001, "i", "points of a frequency sweep",
     "2001 points at Nh = 64: 8.5 s and 0.38 GB, so 10 001 about 35 s and 1.3 GB; 1e8 needed 47.7 GiB",
     dict(default=101, defaults=(("disk", 41),))),
    ("nf", "frequencies", "", 2, 401, "i", "frequencies of a wear map",
     "a map has two frequencies at least (one is a wear history); 401 x 400 exact map 7.5 s and 0.3 GB "
     "(CSV 25 MB); stepping about 80 s at Nh = 7, 15 min at Nh = 64",
     dict(default=41, control="n_frequencies", html="Frequencies of the maps", slider=(5, 201, 1))),
    ("ncycles", "cycle points", "", 3, 400, "i", "log-spaced cycle counts of a wear map",
     "0 and two log-spaced counts at least (a map over the decades); the bound as the frequencies'",
     dict(default=60, control="n_cycles", html="Cycle counts of the wear map", slider=(10, 200, 1))),
    ("target", "target error", "", 0.0, 1.0, "<>", "target relative error", "a relative error",
     dict(default=1e-2)),
    # -- figures
    ("dpi", "dpi", "", 50, 600, "i", "resolution of PNG files",
     "30 x 30 in at 600 dpi is 324 Mpixel (1.3 GB of RGBA); the dashboard and the CLI write at 150",
     dict(default=150)),
    ("width", "width", "in", 2.0, 30.0, "", "figure width", "the axes need 2 in; 30 in: a poster"),
    ("height", "height", "in", 2.0, 30.0, "", "figure height", "as the width"),
    ("fontsize", "font size", "pt", 4.0, 40.0, "", "axis label font size", "legible to large"),
    # -- bladed disk
    ("sectors", "sectors", "", 3, 1000, "i", "sectors of the bladed disk",
     "3: the smallest ring of neighbours; 1000 sectors are a 3000-DOF dense eigenproblem per draw",
     dict(default=24)),
    ("engine_order", "engine order", "", 0, 1000, "i", "engine order of the travelling-wave excitation",
     "0: every blade in phase; beyond half the sectors the wave aliases onto a lower one",
     dict(default=3)),
    ("level", "mistuning level", "", 0.0, 0.5, "", "standard deviation of the blade stiffness deviations",
     "0.5: a blade 50 % off is damage, not mistuning (draws are kept > -1)", dict(default=0.01)),
    # -- studies
    ("draws", "random draws", "", 1, 100_000, "i", "random draws of a study",
     "1000 draws of the example take 32.5 s on 2 workers: 1e5 about 1 h; 1e8 grew past 4 GB",
     dict(flag="--samples", defaults=(("disk", 100),))),
    ("points", "study points", "", 1, 1_000_000, "i", "points of a study (grid x draws)",
     "at about 30 ms a point, 1e6 points are 4 h on 2 workers"),
    ("grid_num", "grid values", "", 1, 10_000, "i", "values of one grid axis", "as the study points"),
    ("seed", "seed", "", 0, 2**63 - 1, "i", "seed of the random draws", "NumPy's seed range",
     dict(defaults=(("disk", 0),))),
    ("workers", "workers", "", 1, 2 * _CORES, "i", "local Dask worker processes",
     f"2 per core ({_CORES} here): each is a process of about 200 MB that needs a core; 100 leaked "
     "semaphores"),
    ("retries", "retries", "", 0, 10, "i", "reruns of a failed task", "a task failing 10 times has a reason",
     dict(default=2)),
    ("points_per_task", "points per task", "", 1, 100_000, "i", "points of one task", "as the draws"),
    # -- contact interfaces
    ("contact_nodes", "contact nodes", "", 3, 128, "i", "contact pairs of the cylinder-on-flat benchmark",
     "fretwear.interface.fe.MAX_CONTACT_NODES: 128 pairs are 66 282 DOFs, Craig-Bampton 42 s and 42 s a "
     "solve; 256 pairs are 199 730 DOFs and 0.85 GB to build; 100 000 ran out of memory",
     dict(default=32)),
    ("divisions", "window divisions", "", 2, 40, "i", "grid spacings across the contact window radius of "
     "the sphere-on-flat benchmark (about pi d^2 / 2 pairs)", "fretwear.interface.sphere.MAX_DIVISIONS: 18 "
     "are 523 pairs and an 18-30 s build, 40 about 2 550 pairs and ~25x the time (extrapolated)",
     dict(default=18)),
    ("interface_kw", "K_w", "1/Pa", 0.0, 1e-4, "<", "Archard wear coefficient of an interface "
     "(dw/dN = K_w p s, p the contact pressure)", "as the lumped k_w", dict(flag="--kw")),
    ("q_ratio", "Q0 / (mu P)", "", 0.0, 2.0, "", "tangential load ratio of the benchmark",
     "gross slip from 1 (1.05 covers it); at 5 the static solve ran over a minute", dict(default=0.5)),
    ("window", "window", "", 1.0, 5.0, "<", "contact window half-width / Hertz a",
     "> 1: the window holds the contact; beyond 5 a the outer pairs carry nothing", dict(default=1.25)),
    ("line_load", "normal load", "N/m", 0.0, 1e8, "<", "benchmark normal load per unit length",
     "1e8 N/m (100 kN/mm) is beyond the flat's yield", dict(default=2e5, flag="--normal-load")),
    ("interface_mu", "mu", "", 0.0, 10.0, "", "benchmark friction coefficient",
     "0: an interface may be frictionless (a unilateral contact); no dry contact has mu > 10",
     dict(default=0.6, flag="--mu")),
    ("drive", "drive", "m", 0.0, 1e-2, "<", "amplitude of the loading arm's end", "1 cm is beyond fretting"),
    ("arm_stiffness", "arm stiffness", "N/m per m", 0.0, 1e14, "<", "loading arm stiffness", "a typo guard",
     dict(default=2e10)),
    ("rtol", "rtol", "", 0.0, 0.5, "<", "slow-time step tolerance on the worn depth", "as the tolerance",
     dict(default=1e-2)),
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
        **(row[8] if len(row) > 8 else {}),
    )  # fmt: skip
    for row in _ROWS
}

#: the dashboard's numbers: its control name -> parameter, in the table's order
CONTROLS: Mapping[str, Parameter] = {p.control: p for p in PARAMETERS.values() if p.control}


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
