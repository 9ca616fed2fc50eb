"""Where the data folders live: ``ncverify/_data/`` in an installed wheel, the repository
root in a source checkout."""
from __future__ import annotations

from functools import cache
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


@cache
def data_dir(name: str) -> Path:
    """The ``dialects`` or ``rules`` folder."""
    for candidate in (_PACKAGE / "_data" / name, _PACKAGE.parent / name):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"ncverify data folder {name!r} is missing from the installation")
