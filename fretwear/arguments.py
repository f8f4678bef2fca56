"""Command-line argument types shared by the ``fretwear`` commands: numbers checked against the one
parameter table (:mod:`fretwear.parameters`)."""

from __future__ import annotations

import argparse
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from .parameters import argument_type, describe

__all__ = [
    "number",
    "valid",
    "document",
    "check_output",
    "atomic",
    "staged_folder",
    "PARTIAL",
    "remove_partial",
]

#: the temporary files and folders being written (:func:`atomic`, :func:`staged_folder`), for a hard exit
PARTIAL: set[Path] = set()


def remove_partial() -> None:
    """Remove what :func:`atomic` and :func:`staged_folder` are writing (before a hard exit on Ctrl-C)."""
    for path in list(PARTIAL):
        shutil.rmtree(path, ignore_errors=True) if path.is_dir() else path.unlink(missing_ok=True)


def number(name: str, low: float | None = None) -> Callable[[str], float | int]:
    """Argument type of parameter ``name`` of :data:`fretwear.parameters.PARAMETERS` (``low`` narrows it)."""
    return argument_type(name, low)


def valid(name: str) -> str:
    """The valid range of parameter ``name`` for a help text, e.g. ``"a number > 0 and <= 1000 N"``."""
    return describe(name).range_text()


def document(parser: argparse.ArgumentParser) -> None:
    """Append its valid range, from the table, to the help of every numeric option of ``parser``."""
    for action in parser._actions:
        param = getattr(action.type, "parameter", None)
        if param is not None and action.help and "valid:" not in action.help:
            action.help = f"{action.help} [valid: {param.range_text().replace('%', '%%')}]"


def _unwritable(folder: Path) -> str | None:
    """Why no file can be created in ``folder`` (None if one can: a real probe, as root ignores modes)."""
    try:
        with tempfile.TemporaryFile(dir=folder):
            return None
    except OSError as exc:
        return exc.strerror or str(exc)


def check_output(text: str, suffixes: tuple[str, ...], *, folder: bool = False) -> Path:
    """The output path ``text`` checked before any work: ``ValueError`` with the reason otherwise.

    A file (``folder`` False) must end in one of ``suffixes`` (any case), not be an existing folder and
    have a folder where a file can be created; a folder (``folder`` True) must not be an existing file
    and its nearest existing parent must accept new files (the missing ones are created at the end).
    """
    path = Path(text)
    if folder:
        if path.exists() and not path.is_dir():
            raise ValueError(f"{text!r} is an existing file, not a folder")
        parent = path if path.is_dir() else path.parent
        while not parent.exists():
            parent = parent.parent
        if not parent.is_dir():
            raise ValueError(f"{str(parent)!r} is a file: {text!r} cannot be created")
    else:
        if suffixes and not text.lower().endswith(suffixes):
            raise ValueError(f"must end in {', '.join(suffixes)} (the format), got {text!r}")
        if path.is_dir():
            raise ValueError(f"{text!r} is a folder, not a file")
        parent = path.parent
        if not parent.is_dir():
            raise ValueError(f"the folder of {text!r} does not exist")
    reason = _unwritable(parent)
    if reason:
        raise ValueError(f"cannot write in {str(parent)!r}: {reason}")
    return path


@contextmanager
def atomic(path: str | Path) -> Iterator[Path]:
    """A temporary name beside ``path`` (same suffix) to write, renamed to ``path`` on success only.

    An interrupt or an error leaves nothing: no half-written file can be taken for a result.
    """
    path = Path(path)
    fd, name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=f".partial{path.suffix}", dir=path.parent)
    os.close(fd)
    temp = Path(name)
    PARTIAL.add(temp)
    try:
        yield temp
        mask = os.umask(0)  # mkstemp made it 0600: give it the mode a new file gets
        os.umask(mask)
        os.chmod(temp, 0o666 & ~mask)
        os.replace(temp, path)
    finally:
        temp.unlink(missing_ok=True)
        PARTIAL.discard(temp)


@contextmanager
def staged_folder(folder: str | Path) -> Iterator[Path]:
    """A temporary folder to write into; its files move into ``folder`` (created) on success only."""
    folder = Path(folder)
    base = folder if folder.is_dir() else folder.parent
    while not base.exists():
        base = base.parent
    temp = Path(tempfile.mkdtemp(prefix=f".{folder.name}.partial-", dir=base))
    PARTIAL.add(temp)
    try:
        yield temp
        folder.mkdir(parents=True, exist_ok=True)
        for item in sorted(temp.iterdir()):
            os.replace(item, folder / item.name)
    finally:
        shutil.rmtree(temp, ignore_errors=True)
        PARTIAL.discard(temp)
