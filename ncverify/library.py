"""Subprograms in separate files: found by program number on the subprogram search path."""
from __future__ import annotations

import re
from pathlib import Path

from .source import ProgramSource

_FIRST_PROGRAM = re.compile(rb"(?mi)^[ \t]*(?:%[ \t]*)?(?:N\d+[ \t]*)?[O:][ \t]*(\d+)")
_MAX_FILES = 5000


class SubprogramLibrary:
    """Indexes the files of the search folders by file name (``O1000.nc``, ``1000``) and by
    the program numbers in their first 4 KiB; files are opened only when called.

    The first ``explicit`` folders were named by the user (``--subprogram-path``): a program
    found there is taken from there. Elsewhere (the program's own folder) a name held by more
    than one file is ambiguous: a folder of unrelated programs may hold several authors'
    ``O3001``, and running the wrong one would be worse than not running any."""

    def __init__(self, folders: list[Path], extensions: tuple[str, ...], explicit: int | None = None):
        self.folders = [folder for folder in folders if folder.is_dir()]
        self.explicit = {folder.resolve() for folder in folders[: len(folders) if explicit is None else explicit] if folder.is_dir()}
        self.extensions = {extension.lower() for extension in extensions}
        self._index: dict[str, list[Path]] | None = None
        self._open: dict[Path, ProgramSource] = {}

    def candidates(self, name: str) -> list[Path]:
        """Every file that holds the program, the ones in user-named folders alone if any."""
        if self._index is None:
            self._index = self._build_index()
        found = self._index.get(name, [])
        chosen = [path for path in found if path.parent.resolve() in self.explicit]
        return chosen or found

    def find(self, name: str) -> ProgramSource | None:
        """The one file holding the program; None when there is none or more than one."""
        found = self.candidates(name)
        if len(found) != 1:
            return None
        path = found[0]
        if path not in self._open:
            self._open[path] = ProgramSource.open(path)
        return self._open[path]

    def _build_index(self) -> dict[str, list[Path]]:
        """Name -> the files holding it: a file whose first program is O1000 comes before one
        that only holds O1000 further down, which comes before a file merely named 1000."""
        first: dict[str, list[Path]] = {}
        later: dict[str, list[Path]] = {}
        named: dict[str, list[Path]] = {}
        count = 0
        for folder in self.folders:
            for path in sorted(folder.iterdir()):
                if count >= _MAX_FILES or not path.is_file() or path.suffix.lower() not in self.extensions:
                    continue
                count += 1
                stem = path.stem.upper()
                digits = stem.lstrip("O")
                # a name: O1000.nc, 1000, or a program called by name (SINUMERIK MYKONTUR.SPF)
                named.setdefault(f"O{int(digits)}" if digits.isdigit() else stem, []).append(path)
                try:
                    with path.open("rb") as handle:
                        head = handle.read(4096)
                except OSError:
                    continue
                for position, match in enumerate(_FIRST_PROGRAM.finditer(head)):
                    (first if position == 0 else later).setdefault(f"O{int(match.group(1))}", []).append(path)
        index: dict[str, list[Path]] = {}
        for table in (first, later, named):
            for name, paths in table.items():
                index.setdefault(name, [])
                index[name] += [path for path in paths if path not in index[name]]
        return index
