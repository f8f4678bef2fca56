"""Codes and packed arguments shared by the compiled kernels of the event-driven dynamics.

Status codes of the kernels: :data:`OK`, :data:`NEED_PATTERN` (the caller
builds the pattern ``need`` and calls again), :data:`NEED_SPACE` (record
buffers full), :data:`DEGENERATE` (more than ``MAX_NULL`` consecutive events
at one instant, or ``max_phases`` phases), :data:`NONFINITE`.

The kernels take their arrays packed in tuples (Numba types a tuple by the
types of its members, so a packed call compiles and caches as the flat one):

* ``model = (M^-1, B, C, K, F, kt)``: inverse mass matrix, relative map of
  the friction contacts, damping, stiffness, the forcing columns
  ``(F_s, F_c, F_sn)`` and the tangential stiffnesses of Jenkins contacts
  (empty for rigid ones; then the state ``y`` is ``(u, v)``, else
  ``(u, v, lambda)``) (:attr:`fretwear.time.patterns.Table.model_arrays`);
* ``patterns = (masks, Ah, force_rows, phi, phi_series, step, count)``: the
  stick patterns built so far at one frequency
  (:meth:`fretwear.time.patterns.Table.table`), or at every frequency with a
  frequency axis first on ``Ah``, ``phi``, ``phi_series`` and ``step``
  (:meth:`~fretwear.time.patterns.Table.stacked`);
* ``records = (steps, phases, events)``: the buffers a recorded march writes
  into, ``steps = (t, length, pattern, phase, X)``, ``phases = (t, state,
  direction)``, ``events = (t, contact, kind, direction)``
  (:class:`fretwear.time.integrator.Records`).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "OK",
    "NEED_PATTERN",
    "NEED_SPACE",
    "DEGENERATE",
    "NONFINITE",
    "STICK_EVENT",
    "SLIP_EVENT",
    "REVERSAL_EVENT",
    "STICK_CODE",
    "SLIP_CODE",
    "OPEN_CODE",
    "TRUE",
    "FALSE",
    "NONE",
]

OK, NEED_PATTERN, NEED_SPACE, DEGENERATE, NONFINITE = 0, 1, 2, 3, 4
STICK_EVENT, SLIP_EVENT, REVERSAL_EVENT = 0, 1, 2
STICK_CODE, SLIP_CODE, OPEN_CODE = 0, 1, 2  # fretwear.model.STICK, SLIP, OPEN

# Flags and masks passed from one kernel to another as NumPy scalars: a Python literal (``True``, ``0``)
# would make Numba compile one more specialisation of the callee per literal value (seconds each).
TRUE, FALSE, NONE = np.bool_(True), np.bool_(False), np.int64(0)
