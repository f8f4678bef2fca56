"""Multi-harmonic balance with the Dynamic Lagrangian Frequency-Time method (paper sections 1.3-1.5).

Layers, bottom up: ``fretwear.hbm.harmonics`` (Fourier basis and DFT
matrices, eq. 9-10), ``fretwear.hbm.condensation`` (reduced dynamic
stiffness on the contact coordinates, eq. 11), ``fretwear.hbm.dlft`` (the
contact law: prediction/correction in time, eq. 17-23, compiled) and
``fretwear.hbm.coupled`` (the coupled normal/tangential law of contact
interfaces) and ``fretwear.hbm.cone`` (the same with 2-D friction, solved
by :class:`ConeProblem` on a reduced ``Z``), ``fretwear.hbm.newton`` (one
compiled Newton's method and one piecewise-linear walk, handed any of these
laws; ``fretwear.hbm.kernels``
calls them with the 1-D law),
``fretwear.hbm.periodic`` (one frequency: :func:`solve_periodic`),
:mod:`~fretwear.hbm.continuation` and ``fretwear.hbm.arclength`` (over
frequency: :func:`sweep`, :func:`continuation`), ``fretwear.hbm.linear``
(linear FRFs with every contact stuck or open). The result is a
:class:`PeriodicSolution`.
"""

from .cone_problem import ConeProblem, ConeSolution
from .continuation import Branch, Sweep, continuation, sweep
from .harmonics import HarmonicBasis, default_samples
from .linear import linear_frf
from .periodic import Problem, solve_periodic
from .solution import PeriodicSolution

__all__ = [
    "Branch",
    "ConeProblem",
    "ConeSolution",
    "HarmonicBasis",
    "PeriodicSolution",
    "Problem",
    "Sweep",
    "continuation",
    "default_samples",
    "linear_frf",
    "solve_periodic",
    "sweep",
]
