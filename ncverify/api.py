"""The pipeline, end to end, and the Python API.

``check_text`` and ``check_file`` return a :class:`FileResult` whose ``to_json()`` is the
file entry of the JSON contract; ``check_paths`` walks files and folders for the CLI.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from .check import Checker
from .detect import Detection, detect
from .diagnostics import Diagnostic, Severity, Status, Suppressed
from .interpret import Interpreter
from .library import SubprogramLibrary
from .lower.iso import IsoFrontend, IsoLowering
from .settings import Settings
from .source import ProgramSource, Span
from .tables import iso_table


class InputError(Exception):
    """A file that cannot be checked at all (missing, unreadable, too large, binary)."""


@dataclass
class FileResult:
    path: str
    dialect: str | None
    dialect_confidence: float
    diagnostics: list[Diagnostic] = field(default_factory=list)
    suppressed: list[Suppressed] = field(default_factory=list)
    profile: str | None = None
    machine: str | None = None
    skipped: str | None = None  # why the file was not checked (not a CNC program)
    blocks: int = 0
    paths: int = 0
    truncated: dict[str, int] = field(default_factory=dict)
    free_parameters: list[str] = field(default_factory=list)
    least_input_increment: float | None = None

    def to_json(self) -> dict:
        entry = {"path": self.path, "dialect": self.dialect, "dialect_confidence": self.dialect_confidence}
        if self.profile:
            entry["profile"] = self.profile
        if self.machine:
            entry["machine"] = self.machine
        if self.least_input_increment is not None:
            entry["least_input_increment"] = self.least_input_increment
        if self.skipped:
            entry["skipped"] = self.skipped
        entry["diagnostics"] = [diagnostic.to_json() for diagnostic in self.diagnostics]
        entry["suppressed"] = [item.to_json() for item in self.suppressed]
        if self.truncated:
            entry["truncated"] = dict(self.truncated)
        if self.free_parameters:
            entry["free_parameters"] = list(self.free_parameters)
        return entry

    def count(self, severity: Severity) -> int:
        return sum(1 for d in self.diagnostics if d.severity is severity and d.status is not Status.UNKNOWN)


def check_text(text: str, path: str = "<text>", settings: Settings | None = None) -> FileResult:
    """Check a program given as text."""
    return check_source(ProgramSource.from_text(text, path), settings or Settings())


def check_file(path: str | os.PathLike, settings: Settings | None = None) -> FileResult:
    """Check one program file. Raises :class:`InputError` when the file cannot be read."""
    settings = settings or Settings()
    file_path = Path(path)
    try:
        size = file_path.stat().st_size
    except OSError as error:
        raise InputError(f"{path}: cannot read: {error.strerror or error}") from error
    if file_path.is_dir():
        raise InputError(f"{path}: is a folder")
    if size > settings.max_file_bytes:
        raise InputError(f"{path}: {size:,} bytes is larger than the limit of {settings.max_file_bytes:,} (--max-file-size)")
    try:
        source = ProgramSource.open(file_path)
    except OSError as error:
        raise InputError(f"{path}: cannot read: {error.strerror or error}") from error
    return check_source(source, settings)


def check_source(source: ProgramSource, settings: Settings) -> FileResult:
    detection = _detection(source, settings)
    result = FileResult(source.name, detection.dialect, detection.confidence, profile=detection.profile, machine=detection.machine)
    if detection.dialect is None:
        result.skipped = detection.reason
        return result
    if detection.dialect != "iso":
        checker = Checker(settings, {})
        checker.report("core.dialect-unsupported", Span(1, 1, 1, 1), f"{detection.dialect} programs are recognised but not checked yet: nothing in this file was verified",
                       Status.UNKNOWN, f"no reader for the {detection.dialect} dialect yet")
        result.diagnostics = checker.diagnostics
        return result
    _run_iso(source, settings, detection, result)
    return result


def _detection(source: ProgramSource, settings: Settings) -> Detection:
    head_bytes = bytes(source.buffer[:65536])
    found = detect(source.head(), head_bytes)
    if settings.dialect is None:
        return found
    if found.dialect is None and "binary" in found.reason:
        return found
    profile = settings.profile or found.profile or "mitsubishi-e60"
    return Detection(settings.dialect, 1.0, "", profile if settings.dialect == "iso" else None, found.machine, found.whole_units)


def _run_iso(source: ProgramSource, settings: Settings, detection: Detection, result: FileResult) -> None:
    profile = settings.profile or detection.profile or "mitsubishi-e60"
    machine = settings.machine or detection.machine or "mill"
    table = iso_table(profile, machine)
    increment = settings.least_input_increment
    if increment is None and detection.whole_units:
        increment = 0.0
    lowering = IsoLowering(table, increment)
    context = {
        "machine": machine,
        "d_register_max": float(table.settings.get("d_register_max", 99)),
        "h_register_max": float(table.settings.get("h_register_max", 99)),
        "tool_number_max": float(table.settings.get("tool_number_max", 9999)),
    }
    checker = Checker(settings, context)
    folders = list(settings.subprogram_path)
    if source.path is not None:
        folders.append(source.path.parent)
    library = SubprogramLibrary(folders, settings.extensions)
    interpreter = Interpreter(
        source, IsoFrontend(lowering), checker, settings, power_on=table.power_on, cycle_models=table.cycles,
        twins=dict(table.words.get("incremental_twins", {})), machine=machine, increment=lowering.increment,
        feed_increment=lowering.feed_increment, library=library,
    )
    interpreter.run()
    result.profile, result.machine = profile, machine
    result.least_input_increment = lowering.increment
    result.diagnostics = sorted(checker.diagnostics, key=Diagnostic.sort_key)
    result.truncated = dict(checker.truncated)
    result.blocks = interpreter.blocks_run
    result.paths = interpreter.paths_started
    result.free_parameters = sorted(interpreter.free_parameters)


def iter_program_files(paths: list[str], settings: Settings):
    """Yield ``(path, explicit)``: files named on the command line, and the files in named
    folders (recursively) whose extension is in ``settings.extensions``."""
    extensions = {extension.lower() for extension in settings.extensions}
    for name in paths:
        path = Path(name)
        if path.is_dir():
            for root, folders, files in os.walk(path):
                folders[:] = sorted(folder for folder in folders if not folder.startswith("."))
                for file_name in sorted(files):
                    if Path(file_name).suffix.lower() in extensions and not file_name.startswith("."):
                        yield Path(root) / file_name, False
        else:
            yield path, True
