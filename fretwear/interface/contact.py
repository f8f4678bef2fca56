"""The coupled normal/tangential DLFT law of the interface's node pairs (eq. 17-23).

The law lives with the other contact law in ``fretwear.hbm.coupled``, below the
periodic solvers that take either (``fretwear.hbm.newton``); the interface
modules read it from here.
"""

from __future__ import annotations

from ..hbm.coupled import OPEN, SLIP, STICK, boundary_distance, evaluate, march_pair, slip_work
from ..hbm.dlft import jacobian_from_blocks as jacobian

__all__ = ["STICK", "SLIP", "OPEN", "march_pair", "evaluate", "jacobian", "slip_work", "boundary_distance"]
