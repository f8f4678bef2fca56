"""Numba's on-disk cache of fretwear's kernels, stale as soon as any kernel's source changes.

Numba keys a cached kernel on its own source file only, yet the machine code
it caches holds the kernel's callees from other modules too: after an edit of
``hbm/dlft.py`` alone (or a ``git pull`` into an editable install), the
cached sweep of ``hbm/compiled_sweep.py`` would go on running the old march.
The cache locators registered here, for the package's files only, add the
contents of every module that defines kernels to the stamp Numba checks, so
that any such change recompiles on first use, as a change of the kernel's
own file does. Numba's override ``NUMBA_CACHE_LOCATOR_CLASSES`` is respected.
Importing this module registers them (``fretwear/__init__.py`` does, first).
"""

from __future__ import annotations

import hashlib
from functools import lru_cache
from pathlib import Path

_ROOT = Path(__file__).resolve().parent


@lru_cache(maxsize=1)
def kernel_sources_digest() -> str:
    """SHA-256 of the path and contents of every module of the package that defines Numba kernels."""
    digest = hashlib.sha256()
    for path in sorted(_ROOT.rglob("*.py")):
        text = path.read_bytes()
        if b"@njit" in text:
            digest.update(path.relative_to(_ROOT).as_posix().encode() + b"\0" + text)
    return digest.hexdigest()


def _for_the_package(base: type) -> type:
    """Numba's locator ``base``, restricted to the package's files, with the kernel sources in its stamp."""

    class Locator(base):
        @classmethod
        def from_function(cls, py_func, py_file):
            if not Path(py_file).resolve().is_relative_to(_ROOT):
                return None
            return super().from_function(py_func, py_file)

        def get_source_stamp(self):
            return super().get_source_stamp(), kernel_sources_digest()

    Locator.__name__ = Locator.__qualname__ = f"Fretwear{base.__name__}"
    return Locator


def register() -> bool:
    """Put the package's locators first in Numba's list (once); False if Numba's internals differ."""
    try:
        from numba.core import caching

        classes = caching.CacheImpl._locator_classes
        if not any(c.__name__.startswith("Fretwear") for c in classes):
            classes[:0] = [_for_the_package(c) for c in classes]
        return True
    except Exception:  # noqa: BLE001 - another Numba: its own per-file stamps, as before
        return False


register()
