"""Where the data folders live: ``ncverify/_data/`` in an installed wheel, the repository
root in a source checkout; and their TOML tables, parsed once per content.

Parsing the tables a check reads (codes, cycle models, rule pages' front matter) with
``tomllib`` took a sixth of a small check's time, in every process. Each parsed table is
therefore kept as JSON in the user cache folder, named by a hash of the exact text it was
parsed from, in a folder of the Python version (whose ``tomllib`` parsed it): an entry
can only ever be the parse of the very text asked for, so an edited table is simply a
new entry. An entry that is missing, unreadable or broken is parsed again and rewritten;
a cache folder that cannot be written only costs the parsing.
"""
from __future__ import annotations

import hashlib
import json
import os
import sys
import tempfile
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


def user_cache_folder() -> Path:
    """ncverify's folder in the user cache folder (``~/.cache/ncverify`` on Linux)."""
    import platformdirs

    return Path(platformdirs.user_cache_dir("ncverify", appauthor=False))


@cache
def parsed_tables_folder() -> Path:
    """Where parsed tables are kept, one folder per Python version."""
    return user_cache_folder() / "tables" / f"{sys.implementation.cache_tag}.{sys.version_info.micro}"


def read_table(path: Path) -> dict:
    """A TOML file, parsed as ``tomllib.load`` parses it."""
    return parse_table(path.read_bytes().decode())


def parse_table(text: str) -> dict:
    """TOML text, parsed as ``tomllib.loads`` parses it (its errors too), from the cache
    when it holds this text."""
    key = hashlib.blake2b(text.encode(), digest_size=20).hexdigest()
    entry = parsed_tables_folder() / f"{key}.json"
    table = _cached_table(entry, key)
    if table is None:
        import tomllib  # here: with every table in the cache the parser is not loaded

        table = tomllib.loads(text)
        _store_table(entry, key, table)
    return table


def _cached_table(entry: Path, key: str) -> dict | None:
    try:
        stored = json.loads(entry.read_bytes())
    except (OSError, ValueError):
        return None
    if type(stored) is not dict or stored.get("key") != key or type(stored.get("table")) is not dict:
        return None
    return stored["table"]


def _store_table(entry: Path, key: str, table: dict) -> None:
    """A table JSON cannot hold exactly (a TOML date) is not kept."""
    try:
        text = json.dumps({"key": key, "table": table}, ensure_ascii=False)
    except (TypeError, ValueError):
        return
    write_whole(entry, text.encode("utf-8"))


def write_whole(target: Path, data: bytes) -> None:
    """``data`` written to a temporary file beside ``target`` and renamed onto it, so that
    another process reads a whole file or none. A folder that cannot be written is no
    error: the caches that use this only lose time."""
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=target.parent, prefix=".tmp-", suffix=target.suffix)
    except OSError:
        return
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        os.replace(temporary, target)
    except OSError:
        try:
            os.unlink(temporary)
        except OSError:
            pass
