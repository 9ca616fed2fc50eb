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
    """What one check read besides the program (see the module)."""

    files: set[str] = field(default_factory=set)  # absolute paths read
    lookups: dict[str, list[str]] = field(default_factory=dict)  # subprogram name -> the absolute paths of the files holding it
    folders: list[str] = field(default_factory=list)  # the subprogram search folders used, in order
    explicit: list[str] = field(default_factory=list)  # those of them named by the user (--subprogram-path)


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


def note_lookup(name: str, paths: list[Path], folders: list[Path], explicit: set[Path]) -> None:
    log = _current.get()
    if log is not None:
        log.lookups[name] = [str(Path(path).resolve()) for path in paths]
        for folder in folders:
            resolved = str(folder.resolve())
            if resolved not in log.folders:
                log.folders.append(resolved)
                if folder.resolve() in explicit:
                    log.explicit.append(resolved)
