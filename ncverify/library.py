"""Subprograms in separate files: found by program number on the subprogram search path."""
from __future__ import annotations

import re
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path

from .dependencies import note_lookup
from .source import ProgramSource

_FIRST_PROGRAM = re.compile(rb"(?mi)^[ \t]*(?:%[ \t]*)?(?:N\d+[ \t]*)?[O:][ \t]*(\d+)")
_MAX_FILES = 5000


_shared: ContextVar[dict | None] = ContextVar("ncverify_shared_indexes", default=None)
_PROCESS_INDEXES: dict = {}


@contextmanager
def shared_indexes():
    """Share folder indexes between the checks run inside (a batch in one process)."""
    token = _shared.set(_PROCESS_INDEXES)
    try:
        yield
    finally:
        _shared.reset(token)


def _modified(folder: Path) -> int:
    try:
        return folder.stat().st_mtime_ns
    except OSError:
        return -1


class SubprogramLibrary:
    """Indexes the files of the search folders by file name (``O1000.nc``, ``1000``) and by
    the program numbers in their first 4 KiB; files are opened only when called."""

    def __init__(self, folders: list[Path], extensions: tuple[str, ...]):
        self.folders = [folder for folder in folders if folder.is_dir()]
        self.extensions = {extension.lower() for extension in extensions}
        self._index: dict[str, Path] | None = None
        self._open: dict[Path, ProgramSource] = {}

    def find(self, name: str) -> ProgramSource | None:
        path = self.resolve(name)
        note_lookup(name, path, self.folders)
        if path is None:
            return None
        if path not in self._open:
            self._open[path] = ProgramSource.open(path)
        return self._open[path]

    def resolve(self, name: str) -> Path | None:
        """The file that holds program ``name``, without opening it."""
        if self._index is None:
            self._index = self._shared_index()
        return self._index.get(name)

    def _shared_index(self) -> dict[str, Path]:
        """Inside :func:`shared_indexes`, one index per set of folders for the whole batch
        (a library of thousands of programs in one folder is indexed once, not once per
        calling program); built again when a folder's modification time changes."""
        shared = _shared.get()
        if shared is None:
            return self._build_index()
        key = (tuple(self.folders), frozenset(self.extensions))
        stamp = tuple(_modified(folder) for folder in self.folders)
        known = shared.get(key)
        if known is None or known[0] != stamp:
            known = shared[key] = (stamp, self._build_index())
        return known[1]

    def _build_index(self) -> dict[str, Path]:
        """A file whose first program is O1000 wins over one that only holds O1000 further
        down, which wins over a file merely named 1000."""
        first: dict[str, Path] = {}
        later: dict[str, Path] = {}
        named: dict[str, Path] = {}
        count = 0
        for folder in self.folders:
            for path in sorted(folder.iterdir()):
                if count >= _MAX_FILES or not path.is_file() or path.suffix.lower() not in self.extensions:
                    continue
                count += 1
                stem = path.stem.upper()
                digits = stem.lstrip("O")
                if digits.isdigit():
                    named.setdefault(f"O{int(digits)}", path)
                else:
                    named.setdefault(stem, path)  # programs called by name (SINUMERIK MYKONTUR.SPF)
                try:
                    with path.open("rb") as handle:
                        head = handle.read(4096)
                except OSError:
                    continue
                for position, match in enumerate(_FIRST_PROGRAM.finditer(head)):
                    (first if position == 0 else later).setdefault(f"O{int(match.group(1))}", path)
        return {**named, **later, **first}
