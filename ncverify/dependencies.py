"""Which files a check read besides the program: called subprograms, tool and point tables.

The result cache keys an entry by the program's bytes and must also notice when one of
these changes, or when a subprogram call would now resolve to another file. Readers call
:func:`note_file` and :func:`note_lookup`; a check run inside :func:`recording` collects
them. Outside a recording the calls cost one context-variable read.
"""
from __future__ import annotations

from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path


@dataclass
class ReadLog:
    files: set[str] = field(default_factory=set)  # absolute paths read
    lookups: dict[str, str | None] = field(default_factory=dict)  # subprogram name -> absolute path, None: not found
    folders: list[str] = field(default_factory=list)  # the subprogram search folders used


_current: ContextVar[ReadLog | None] = ContextVar("ncverify_read_log", default=None)


@contextmanager
def recording():
    """Collect the files and subprogram lookups of the checks run inside."""
    log = ReadLog()
    token = _current.set(log)
    try:
        yield log
    finally:
        _current.reset(token)


def note_file(path: Path) -> None:
    log = _current.get()
    if log is not None:
        log.files.add(str(Path(path).resolve()))


def note_lookup(name: str, path: Path | None, folders: list[Path]) -> None:
    log = _current.get()
    if log is not None:
        log.lookups[name] = str(Path(path).resolve()) if path is not None else None
        for folder in folders:
            if str(folder.resolve()) not in log.folders:
                log.folders.append(str(folder.resolve()))
