"""Ctrl-C between the solves of the interface's long loops.

A SIGINT is handled by Python at the next bytecode of the main thread. While a
compiled kernel runs that next bytecode can be inside Numba's own machinery
(it unpickles the exception a kernel raises for a singular matrix), where the
``KeyboardInterrupt`` was lost: ``fretwear interface --kw 1e-14 --cycles 1e8
--converge 1e-3`` ran to its end and exited 0 after Ctrl-C. Inside
:func:`catch_interrupt` the handler only sets a flag, and every periodic solve
(:func:`~fretwear.interface.periodic.solve_interface`, the load walk) and static
increment starts with :func:`check_interrupt`, which raises
``KeyboardInterrupt`` from plain Python: a wear history stops within one
periodic solve (0.03 s at 16 pairs, 0.2 s at 32, ``Nh = 7``).
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["catch_interrupt", "check_interrupt"]

_pressed = threading.Event()


@contextmanager
def catch_interrupt() -> Iterator[None]:
    """Within the block, Ctrl-C (SIGINT) only sets a flag that :func:`check_interrupt` turns into
    ``KeyboardInterrupt``; the previous handler is restored after it. Main thread only (elsewhere a no-op)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _pressed.clear()
    previous = signal.signal(signal.SIGINT, lambda signum, frame: _pressed.set())
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        _pressed.clear()


def check_interrupt() -> None:
    """Raise ``KeyboardInterrupt`` if Ctrl-C was pressed inside :func:`catch_interrupt`."""
    if _pressed.is_set():
        _pressed.clear()
        raise KeyboardInterrupt
