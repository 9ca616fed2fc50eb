"""The pipeline, end to end, and the Python API.

``check_text`` and ``check_file`` return a :class:`FileResult` whose ``to_json()`` is the
file entry of the JSON contract; ``check_paths`` walks files and folders for the CLI.
"""
from __future__ import annotations

import os
import stat
from dataclasses import dataclass, field, replace
from pathlib import Path

from . import annotations, checks, values  # noqa: F401  (checks: importing it registers the rule classes)
from .check import Checker
from .detect import Detection, detect, profile_evidence
from .verdict import show
from .diagnostics import Diagnostic, Severity, Status, Suppressed
from .interpret import Interpreter
from .context import Context, RegisterLimits, RuleContext, ToolTable, describe_start, start_position
from .dialect import setup_for
from .library import SubprogramLibrary
from .project import find_project_file, load_project
from .settings import Settings
from .source import ProgramSource, Span
from .wording import wording


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
    air_cutting: dict[str, tuple[float, float]] = field(default_factory=dict)  # tool -> (feed length, length that cut nothing), mm
    detection_evidence: str = ""  # why this dialect, profile and machine type (--verbose)
    values: dict[int, list[tuple[str, str]]] = field(default_factory=dict)  # with Settings.record_values: line -> (variable, value shown)
    failed: bool = False  # the analysis itself failed (ncverify.watchdog): not checked, exit code 2
    assumptions: list[str] = field(default_factory=list)  # what the verdicts assume beyond the program (the start position)

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
        if self.assumptions:
            entry["assumptions"] = list(self.assumptions)
        entry["diagnostics"] = [diagnostic.to_json() for diagnostic in self.diagnostics]
        entry["suppressed"] = [item.to_json() for item in self.suppressed]
        if self.truncated:
            entry["truncated"] = dict(self.truncated)
        if self.free_parameters:
            entry["free_parameters"] = list(self.free_parameters)
        if self.air_cutting:
            entry["air_cutting"] = {tool: {"feed_mm": round(feed, 3), "air_mm": round(air, 3)} for tool, (feed, air) in sorted(self.air_cutting.items())}
        return entry

    def count(self, severity: Severity) -> int:
        return sum(1 for d in self.diagnostics if d.severity is severity and d.status is not Status.UNKNOWN)


def check_text(text: str, path: str = "<text>", settings: Settings | None = None, project: Context | None = None) -> FileResult:
    """Check a program given as text; ``project`` is the project-file context, if any."""
    return check_source(ProgramSource.from_text(text, path), settings or Settings(), project)


def check_file(path: str | os.PathLike, settings: Settings | None = None) -> FileResult:
    """Check one program file. Raises :class:`InputError` when the file cannot be read."""
    settings = settings or Settings()
    file_path = Path(path)
    try:
        status = file_path.stat()
    except OSError as error:
        raise InputError(f"{path}: cannot read: {error.strerror or error}") from error
    if file_path.is_dir():
        raise InputError(f"{path}: is a folder")
    if not stat.S_ISREG(status.st_mode):
        # a FIFO or device would block or never end: never opened
        return FileResult(str(path), None, 0.0, skipped="not a regular file (a FIFO, socket or device): not opened")
    if status.st_size > settings.max_file_bytes:
        raise InputError(f"{path}: {status.st_size:,} bytes is larger than the limit of {settings.max_file_bytes:,} (--max-file-size)")
    try:
        source = ProgramSource.open(file_path)
    except OSError as error:
        raise InputError(f"{path}: cannot read: {error.strerror or error}") from error
    return check_source(source, settings, project_for(file_path, settings))


def project_for(program: Path | None, settings: Settings) -> Context | None:
    """The project file's context: ``settings.config`` if given, else ``ncverify.toml``
    found upward from the program. Raises :class:`ConfigError` for a broken file."""
    path = settings.config or find_project_file(program)
    return load_project(path) if path is not None else None


def check_source(source: ProgramSource, settings: Settings, project: Context | None = None,
                 detection: Detection | None = None, checker_class=None) -> FileResult:
    """``detection``: the dialect settled earlier for this program (an editor re-checking a
    buffer after each edit); by default it is detected from the text. ``checker_class``: a
    :class:`Checker` subclass that also watches the trace (the plot records the toolpath with
    it); witness replays use the plain one."""
    detection = detection or detect_dialect(source, settings)
    result = FileResult(source.name, detection.dialect, detection.confidence, profile=detection.profile, machine=detection.machine,
                        detection_evidence=detection.evidence)
    if detection.dialect is None:
        result.skipped = detection.reason
        return result
    settings = _with_project_settings(settings, project)
    project = project or Context()
    if setup_for(detection.dialect, settings, detection, project) is None:
        checker = Checker(settings, RuleContext())
        what = detection.reason or f"{detection.dialect} programs are recognised but not checked yet"
        checker.report("core.dialect-unsupported", Span(1, 1, 1, 1), f"{what}: nothing in this file was verified",
                       Status.UNKNOWN, f"no reader for this language yet ({what})")
        result.diagnostics = checker.diagnostics
        return result
    with values.fresh_numbering():
        _run(source, settings, detection, result, project, checker_class=checker_class)
        _confirm_witnesses(source, settings, detection, result, project)
        if any(diagnostic.status is Status.VIOLATED and diagnostic.witness for diagnostic in result.diagnostics):  # else nothing to judge
            _inputs_are_not_mistakes(result, _assumed_names(source, settings, detection, project))
    if detection.dialect == "iso" and settings.profile is None and not profile_evidence(source.head(), detection.machine):
        _findings_of_an_assumed_profile(result)
    _one_finding_per_unknown_code(result)
    return result


def _one_finding_per_unknown_code(result: FileResult) -> None:
    """A code the control lacks is one cause however often it is written: its first block
    is reported, with the lines of the others, instead of a finding per block."""
    first: dict[tuple, tuple[Diagnostic, list[int]]] = {}
    kept = []
    for diagnostic in result.diagnostics:
        if diagnostic.rule.endswith(".unknown-code") and diagnostic.status in (Status.VIOLATED, Status.UNKNOWN):
            key = (diagnostic.rule, diagnostic.status, diagnostic.message.split(" ", 1)[0])
            if key in first:
                first[key][1].append(diagnostic.span.line)
                continue
            first[key] = (diagnostic, [])
        kept.append(diagnostic)
    for diagnostic, lines in first.values():
        if lines:
            shown = ", ".join(str(line) for line in lines[:8]) + (", ..." if len(lines) > 8 else "")
            diagnostic.message += f" (the same code in {len(lines)} more block{'s' if len(lines) > 1 else ''}: line{'s' if len(lines) > 1 else ''} {shown})"
    result.diagnostics = kept


# Findings whose truth is the profile's: a code the control lacks, and a cycle dwell written
# with a fraction (the E60 drops it; a Haas reads P in seconds, fraction and all).
_PROFILE_DEPENDENT = frozenset({"core.unknown-code", "core.dwell-fraction"})


def _findings_of_an_assumed_profile(result: FileResult) -> None:
    """Nothing in the text named the control, so the E60 profile is an assumption: a code it
    lacks (G91.1, G15 on a Fanuc), or a dwell whose fraction it drops, says more about the
    assumption than about the program."""
    for diagnostic in result.diagnostics:
        if diagnostic.rule in _PROFILE_DEPENDENT and diagnostic.status is Status.VIOLATED:
            diagnostic.status = Status.UNKNOWN
            diagnostic.reason = f"the {result.profile} profile was assumed, nothing in the program names its control; give --profile"


def _assumed_names(source: ProgramSource, settings: Settings, detection: Detection, project: Context) -> set[str]:
    """The parameters an ``assume`` (annotation or project file) gives a range."""
    from .project import assumption_names, parameter_name

    frontend = setup_for(detection.dialect, settings, detection, project).frontend
    assumptions = annotations.collect(source, frontend).context.layered_over(project).assumptions
    return {parameter_name(node) for assumption in assumptions for node in assumption_names(assumption.tree)}


def _inputs_are_not_mistakes(result: FileResult, assumed: set[str]) -> None:
    """A hazard whose witness needs a value the program receives from outside (a parameter
    it never sets, an argument, a system variable) that no ``assume`` bounds is not evidence
    of a fault: it becomes ``unknown`` with the input and its example value, which stay in
    the JSON witness. With every such input in an ``assume`` range it stays ``violated``.
    The program's own guards (``IF R5<=0 GOTOF ERR``) are already in the path condition the
    witness satisfies, so they narrow the inputs but do not bound them for this purpose."""
    for diagnostic in result.diagnostics:
        if diagnostic.status is not Status.VIOLATED or not diagnostic.witness:
            continue
        inputs = {name: value for name, value in diagnostic.witness.items() if name not in assumed}
        if inputs:
            shown = ", ".join(f"{name} = {value:g}" for name, value in sorted(inputs.items()))
            diagnostic.status = Status.UNKNOWN
            diagnostic.reason = f"depends on the input {shown}; give it a range with `assume` to have it judged"


def _with_project_settings(settings: Settings, project: Context | None) -> Settings:
    """``[settings]`` of the project file, where the command line left the default."""
    if project is None:
        return settings
    defaults = Settings()
    changes = {key: value for key, value in project.settings.items()
               if hasattr(settings, key) and key not in settings.explicit and getattr(settings, key) == getattr(defaults, key)}
    changes["disabled_rules"] = settings.disabled_rules | frozenset(project.disabled)
    return settings.with_(**changes)


def detect_dialect(source: ProgramSource, settings: Settings) -> Detection:
    """The program's dialect, ISO profile and machine type: ``settings`` over detection."""
    head_bytes = bytes(source.buffer[:65536])
    found = detect(source.head(), head_bytes, Path(source.name).suffix)
    if found.dialect == "iso" and source.name.lower().endswith(".ngc"):
        found = Detection("linuxcnc", found.confidence, machine=found.machine)  # LinuxCNC's own extension decides plain G-code
    if settings.dialect is None:
        return found
    if found.dialect is None and "binary" in found.reason:
        return found
    profile = settings.profile or found.profile or "mitsubishi-e60"
    return Detection(settings.dialect, 1.0, "", profile if settings.dialect == "iso" else None, found.machine, found.whole_units)


def _confirm_witnesses(source, settings, detection, result: FileResult, project: Context) -> None:
    """Replay every witness concretely: pin the free parameters to its values, run the
    program again, and keep the finding only if the same rule fires at the same place. A
    witness that does not reproduce is a modelling gap; the finding becomes ``unknown``."""
    by_witness: dict[tuple, list[Diagnostic]] = {}
    for diagnostic in result.diagnostics:
        if diagnostic.status is Status.VIOLATED and diagnostic.witness:
            by_witness.setdefault(tuple(sorted(diagnostic.witness.items())), []).append(diagnostic)
    for witness, diagnostics in by_witness.items():
        replay = FileResult(result.path, result.dialect, result.dialect_confidence)
        _run(source, settings, detection, replay, project, pins=dict(witness))
        reproduced = {(d.rule, d.span) for d in replay.diagnostics if d.status is Status.VIOLATED}
        for diagnostic in diagnostics:
            if (diagnostic.rule, diagnostic.span) not in reproduced:
                diagnostic.status = Status.UNKNOWN
                diagnostic.reason = ("the solver's counterexample " + ", ".join(f"{name}={value:g}" for name, value in witness)
                                     + " did not reproduce when the program was run with those values: not verified either way")


def _run(source: ProgramSource, settings: Settings, detection: Detection, result: FileResult, project: Context,
         pins: dict | None = None, checker_class=None) -> None:
    dialect = setup_for(detection.dialect, settings, detection, project)
    frontend = dialect.frontend
    found = annotations.collect(source, frontend)
    context = found.context.layered_over(project)
    if hasattr(frontend, "program_context"):
        context = frontend.program_context(source).layered_over(context)
    rule_context = RuleContext(
        machine=replace(context.machine, kind=dialect.machine), stock=context.stock, tools=ToolTable(context.tools),
        limits=RegisterLimits(**dialect.limits), rapid_path=settings.rapid_path, wording=wording(detection.dialect, dialect.profile),
        arc_tolerance=dialect.arc_tolerance, lengths_by_set_up=dialect.lengths_by_set_up, dialect=detection.dialect,
        tools_called=_tools_called(frontend, source, context.tools, dialect.machine),
    )
    checker = (checker_class or Checker)(settings, rule_context, context.severity, found.suppressions)
    for note in found.notes:
        checker.note(note)
    folders = list(settings.subprogram_path)
    if source.path is not None:
        folders.append(source.path.parent)
    library = SubprogramLibrary(folders, settings.extensions, explicit=len(settings.subprogram_path))
    interpreter = Interpreter(
        source, frontend, checker, settings, power_on=dialect.power_on, cycle_models=dialect.cycle_models,
        twins=dialect.twins, machine=dialect.machine, increment=dialect.increment or 0.0,
        feed_increment=dialect.feed_increment, runtime=dialect.runtime, tools=rule_context.tools, library=library, assumptions=context.assumptions, pins=pins,
        parked_at_start=tuple(start_position(rule_context.machine, rule_context.stock)),
    )
    interpreter.run()
    checker.finish()
    result.profile, result.machine = dialect.profile, dialect.machine
    result.least_input_increment = dialect.increment
    start = describe_start(rule_context.machine, rule_context.stock)
    result.assumptions = [start] if start else []
    result.diagnostics = sorted(checker.diagnostics, key=Diagnostic.sort_key)
    result.suppressed = checker.suppressed
    result.truncated = dict(checker.truncated)
    result.blocks = interpreter.blocks_run
    result.paths = interpreter.paths_started
    result.free_parameters = sorted(interpreter.free_parameters)
    result.values = {line: [(name, _shown(value)) for name, value in assigned] for line, assigned in interpreter.assigned.items()}
    if pins is None:
        result.air_cutting = {tool: (feed, air) for tool, (feed, air) in checker.material.air.items()}
        _write_stock(checker.material.final, settings, source)


def _tools_called(frontend, source: ProgramSource, tools: dict, machine: str) -> frozenset[int] | None:
    """The tools the program's text can load, for the cut stock's cells (a quarter of the
    smallest of their radii): asked only where the table's radii differ (else the answer
    changes nothing), of a dialect that can tell (else None: any tool), and not on a lathe,
    whose T words also carry the offset (``T0101``) and whose bar keeps no cells."""
    if machine == "lathe" or not hasattr(frontend, "tools_called") or len({tool.radius for tool in tools.values() if tool.radius}) < 2:
        return None
    return frontend.tools_called(source)


def _write_stock(piece, settings: Settings, source: ProgramSource) -> None:
    """``--stock-out``: the workpiece the first path leaves, as STL or NPZ by the extension;
    ``{stem}`` in the name is the program's file name without its extension."""
    if settings.stock_out is None or piece is None:
        return
    stem = source.path.stem if source.path is not None else "program"
    target = Path(str(settings.stock_out).replace("{stem}", stem))
    if target.suffix.lower() == ".npz":
        piece.save_npz(target)
    else:
        piece.save_stl(target)


def _shown(value) -> str:
    """A value for an editor: the number, or the expression and its interval when symbolic."""
    low, high = values.interval(value) if isinstance(value, (float, values.Sym)) else (None, None)
    text = show(value)
    if isinstance(value, values.Sym) and low is not None and (low > -values.INF or high < values.INF):
        text += f" in [{show(float(low))}, {show(float(high))}]"
    return text


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
