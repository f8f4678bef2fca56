"""Command-line argument types shared by the ``fretwear`` commands: numbers with their valid range."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

__all__ = ["number"]


def number(low: float | None = None, strict: bool = False, unit: str = "", integer: bool = False) -> Callable:
    """Argument type: a finite number (an integer if ``integer``) ``>= low`` (``> low`` if ``strict``)."""
    kind = "an integer" if integer else "a number"
    valid = kind if low is None else f"{kind} {'>' if strict else '>='} {low:g}"
    valid += f" {unit}" if unit else ""

    def convert(text: str) -> float | int:
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be {valid}, got {text!r}") from None
        if not math.isfinite(value) or (low is not None and (value <= low if strict else value < low)):
            raise argparse.ArgumentTypeError(f"must be {valid}, got {text!r}")
        return value

    return convert
