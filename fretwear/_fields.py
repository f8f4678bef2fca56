"""Read-only result properties that are items of one cached tuple (a march, a set of time histories).

A solution computes its time fields together (one march gives the forces,
slip variables and states at once) and caches the tuple; each field is then a
property that reads its item, declared in one line with its doc.
"""

from __future__ import annotations

from typing import Any

__all__ = ["item"]


def item(fields: str, index: Any, doc: str) -> property:
    """A property returning ``getattr(self, fields)[index]``, documented by ``doc``."""
    return property(lambda self: getattr(self, fields)[index], doc=doc)
