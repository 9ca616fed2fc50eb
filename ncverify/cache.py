"""A cache of check results keyed by content, so that an unchanged program in a library is
not verified again.

The key hashes the ncverify version, the settings, the program's path and bytes, and the
project file's path and bytes. An entry also lists every other file the check read (called
subprograms, tool and point tables) with its hash, and the file each subprogram call
resolved to: an entry whose files changed, or whose calls would now resolve elsewhere, is a
miss. Entries are JSON written to a temporary file and renamed into place, so a reader sees
a whole entry or none, from any number of processes; an entry that cannot be read is
ignored and written again.
"""
from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
from pathlib import Path

from . import __version__
from .api import FileResult, project_for
from .dependencies import ReadLog
from .diagnostics import Diagnostic, Severity, Status, Suppressed
from .library import SubprogramLibrary
from .project import find_project_file
from .resources import data_dir, user_cache_folder, write_whole
from .settings import Settings
from .source import Span

FORMAT = 1
_NOT_KEYED = {"cache_dir"}  # where results are kept does not change them


def default_folder() -> Path:
    return user_cache_folder()


def folder_for(program: Path, settings: Settings) -> Path:
    """``--cache-dir`` / ``[settings] cache_dir`` of the program's project file, else the
    user cache folder."""
    if settings.cache_dir is not None:
        return settings.cache_dir
    project = project_for(program, settings)
    if project is not None and project.settings.get("cache_dir") is not None:
        return Path(project.settings["cache_dir"])
    return default_folder()


class ResultCache:
    def __init__(self, folder: Path):
        self.folder = folder / f"v{FORMAT}"

    def key(self, program: Path, settings: Settings) -> str | None:
        """The entry's key, or None when the program or its project file cannot be read
        (the check itself then reports why)."""
        digest = hashlib.sha256()
        try:
            digest.update(_file_hash(program).encode())
            project = settings.config or find_project_file(program)
            if project is not None:
                digest.update(str(project.resolve()).encode() + b"\0" + _file_hash(project).encode())
        except OSError:
            return None
        digest.update(json.dumps([__version__, code_digest(), str(program), str(program.resolve()), _settings_json(settings)]).encode())
        return digest.hexdigest()

    def load(self, key: str, settings: Settings) -> FileResult | None:
        try:
            entry = json.loads(self._path(key).read_text(encoding="utf-8"))
            if entry.get("key") != key or not _still_valid(entry, settings):
                return None
            return result_from_dict(entry["result"])
        except (OSError, ValueError, KeyError, TypeError, AttributeError):
            return None  # missing or broken: checked again and rewritten

    def store(self, key: str, result: FileResult, log: ReadLog) -> None:
        entry = {"key": key, "files": {}, "lookups": log.lookups, "folders": log.folders, "explicit": log.explicit,
                 "result": result_to_dict(result)}
        try:
            entry["files"] = {path: _file_hash(Path(path)) for path in sorted(log.files)}
        except OSError:
            return  # a file it read is gone: not kept (checked again next time)
        write_whole(self._path(key), json.dumps(entry).encode("ascii"))  # ASCII escapes: a file name that is not UTF-8 (surrogates) stays storable

    def _path(self, key: str) -> Path:
        return self.folder / key[:2] / f"{key}.json"


@functools.cache
def code_digest() -> str:
    """A hash of ncverify's own code, rules and dialect tables: a changed checker (a
    development checkout between releases) never answers from an older one's entries."""
    digest = hashlib.sha256()
    for folder in (Path(__file__).resolve().parent, data_dir("rules"), data_dir("dialects")):
        for path in sorted(folder.rglob("*")):
            if path.is_file() and path.suffix in (".py", ".toml", ".md", ".lark"):
                digest.update(path.as_posix().encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()


def _file_hash(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as handle:
        for chunk in iter(lambda: handle.read(1 << 20), b""):
            digest.update(chunk)
    return digest.hexdigest()


def _settings_json(settings: Settings) -> dict:
    def plain(value):
        if isinstance(value, (frozenset, set)):
            return sorted(plain(item) for item in value)
        if isinstance(value, (tuple, list)):
            return [plain(item) for item in value]
        if isinstance(value, Path):
            return str(value.resolve())
        return value

    return {field.name: plain(getattr(settings, field.name)) for field in dataclasses.fields(settings) if field.name not in _NOT_KEYED}


def _still_valid(entry: dict, settings: Settings) -> bool:
    for path, digest in entry["files"].items():
        try:
            if _file_hash(Path(path)) != digest:
                return False
        except OSError:
            return False
    if entry["lookups"]:
        folders = [Path(folder) for folder in entry["folders"]]
        explicit = [folder for folder in folders if str(folder) in entry["explicit"]]
        library = SubprogramLibrary(explicit + [folder for folder in folders if folder not in explicit], settings.extensions, len(explicit))
        for name, paths in entry["lookups"].items():
            if [str(path.resolve()) for path in library.candidates(name)] != paths:
                return False
    return True


# --------------------------------------------------------------------------- results as JSON


def result_to_dict(result: FileResult) -> dict:
    entry = dataclasses.asdict(result)
    entry["diagnostics"] = [_diagnostic_to_dict(d) for d in result.diagnostics]
    entry["suppressed"] = [dataclasses.asdict(item) for item in result.suppressed]
    return entry


def result_from_dict(entry: dict) -> FileResult:
    fields = dict(entry)
    fields["diagnostics"] = [_diagnostic_from_dict(d) for d in entry["diagnostics"]]
    fields["suppressed"] = [Suppressed(**item) for item in entry["suppressed"]]
    return FileResult(**fields)


def _diagnostic_to_dict(diagnostic: Diagnostic) -> dict:
    return {"rule": diagnostic.rule, "category": diagnostic.category, "severity": diagnostic.severity.value,
            "span": list(diagnostic.span), "message": diagnostic.message, "status": diagnostic.status.value,
            "reason": diagnostic.reason, "witness": diagnostic.witness,
            "related": list(diagnostic.related) if diagnostic.related is not None else None}


def _diagnostic_from_dict(entry: dict) -> Diagnostic:
    return Diagnostic(entry["rule"], entry["category"], Severity(entry["severity"]), Span(*entry["span"]), entry["message"],
                      Status(entry["status"]), entry["reason"], entry["witness"],
                      Span(*entry["related"]) if entry["related"] is not None else None)
