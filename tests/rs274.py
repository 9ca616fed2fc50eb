"""Differential testing against LinuxCNC's own interpreter, ``rs274``.

``.ci/install-rs274`` unpacks the binary into ``.rs274/`` of the checkout. A program is run
by both: rs274 gets a copy with a comment line ``(L<n>)`` before every line ``n``, which it
echoes as ``COMMENT("L<n>")`` in execution order, so every move it reports is tied to the
source line that made it; ncverify's trace ties its segments to lines by their spans.
Move end points of rs274 are in the program's coordinates (offsets arrive as separate calls);
ncverify's segments are in workpiece coordinates, where the G92/G52 shift is applied, so the
shift rs274 announces with ``SET_G92_OFFSET`` is added back to its moves.
"""
from __future__ import annotations

import math
import os
import re
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from ncverify import Settings, check_text
from ncverify.context import Context
from ncverify.detect import Detection
from ncverify.dialect import setup_for
from ncverify.interpret import Interpreter
from ncverify.library import SubprogramLibrary
from ncverify.source import ProgramSource

ROOT = Path(__file__).resolve().parent.parent
BINARY = ROOT / ".rs274" / "usr" / "bin" / "rs274"
TOLERANCE = 1e-6
# rs274 prints 4 decimals: its numbers are the true ones to within half the last digit.
PRINTED = 0.5e-4 + TOLERANCE
# A tool table in inches (the standalone rs274 reads diameters in inches): tools 1-20.
TOOL_TABLE = "".join(f"T{number} P{number} D{0.1 * number:.4f} Z0 ;tool {number}\n" for number in range(1, 21))


def rs274_available() -> bool:
    """True when the binary is there; in CI its absence fails the test instead of skipping it."""
    if BINARY.exists():
        return True
    if os.environ.get("CI"):
        pytest.fail("rs274 is not installed: run .ci/install-rs274 (CI must run the differential tests)")
    pytest.skip("rs274 is not installed (.ci/install-rs274)")
    return False


@dataclass
class Run:
    """Moves per source line (end points X, Y, Z in order), and where the run stopped."""

    moves: dict[int, list[tuple]] = field(default_factory=dict)
    sequence: list[tuple[int, tuple]] = field(default_factory=list)  # (line, move) in execution order
    lines_run: set = field(default_factory=set)
    error: str | None = None
    error_line: int | None = None

    def add(self, line: int, move: tuple) -> None:
        self.moves.setdefault(line, []).append(move)
        self.sequence.append((line, move))

    def simplified(self) -> dict[int, list[tuple]]:
        """Moves per line without zero-length moves (measured from wherever the move
        before, of any line, ended), and with a rapid that only stops on the way of the
        next rapid of its line merged into it (rs274 rapids out of a G98 hole in one move,
        the ISO model in two)."""
        lines: dict[int, list[tuple]] = {}
        previous = (0.0, 0.0, 0.0, "rapid")  # rs274 starts at machine zero
        for line, point in self.sequence:
            if previous is not None and not _differs(point, previous):
                continue
            previous = point
            kept = lines.setdefault(line, [])
            if len(kept) >= 2 and kept[-1][3] == point[3] == "rapid" and _between(kept[-1], kept[-2], point):
                kept[-1] = point
                continue
            kept.append(point)
        return lines


_CALL = re.compile(r"^\s*\d+ N\.+\s+(\w+)\((.*)\)\s*$")
_PLANES = {"CANON_PLANE_XY": (0, 1, 2), "CANON_PLANE_XZ": (2, 0, 1), "CANON_PLANE_YZ": (1, 2, 0)}


def instrument(text: str) -> str:
    """The program with ``(L<n>)`` before each line ``n`` (not before '%' lines: the tape
    mark must stay first)."""
    lines = text.splitlines()
    out = []
    for number, line in enumerate(lines, 1):
        if line.strip().startswith("%"):
            out.append(line)
        else:
            out.append(f"(L{number})")
            out.append(line)
    return "\n".join(out) + "\n"


def run_rs274(text: str, folder: Path | None = None, name: str = "program.ngc", timeout: float = 15.0) -> Run:
    """Run rs274 on ``text`` (in a scratch copy of ``folder``, so subroutine files beside
    the program are found) and read its canonical calls."""
    with tempfile.TemporaryDirectory() as scratch:
        work = Path(scratch)
        if folder is not None:
            for other in folder.iterdir():
                if other.is_file() and other.suffix.lower() == ".ngc":
                    (work / other.name).write_bytes(other.read_bytes())
        program = work / name
        program.write_text(instrument(text), encoding="utf-8")
        (work / "tool.tbl").write_text(TOOL_TABLE, encoding="ascii")
        output = work / "out.txt"
        environment = dict(os.environ, LD_LIBRARY_PATH=str(BINARY.parent.parent / "lib"))
        try:
            completed = subprocess.run([str(BINARY), "-t", "tool.tbl", "-g", name, "out.txt"], cwd=work, stdin=subprocess.DEVNULL,
                                       capture_output=True, text=True, timeout=timeout, env=environment)
            returncode, stderr = completed.returncode, completed.stderr
        except subprocess.TimeoutExpired:
            returncode, stderr = -1, "rs274 did not finish (an endless loop?)"
        calls = output.read_text(encoding="utf-8", errors="replace") if output.exists() else ""
    run = Run()
    line = 0
    plane = _PLANES["CANON_PLANE_XY"]
    shift = (0.0, 0.0, 0.0)
    for raw in calls.splitlines():
        match = _CALL.match(raw)
        if match is None:
            continue
        call, arguments = match.groups()
        if call == "COMMENT":
            found = re.fullmatch(r'"L(\d+)"', arguments.strip())
            if found:
                line = int(found.group(1))
                run.lines_run.add(line)
        elif call == "SET_G92_OFFSET":
            shift = tuple(float(value) for value in arguments.split(",")[:3])
        elif call == "SELECT_PLANE":
            plane = _PLANES.get(arguments.strip(), plane)
        elif call in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED"):
            numbers = [float(value) for value in arguments.split(",")]
            run.add(line, (*(value + offset for value, offset in zip(numbers[:3], shift)), "rapid" if call == "STRAIGHT_TRAVERSE" else "feed"))
        elif call == "ARC_FEED":
            numbers = [float(value) for value in arguments.split(",")]
            point = [0.0, 0.0, 0.0]
            point[plane[0]], point[plane[1]], point[plane[2]] = numbers[0], numbers[1], numbers[5]
            run.add(line, (*(value + offset for value, offset in zip(point, shift)), "feed"))
    if returncode != 0:
        messages = [text for text in stderr.strip().splitlines() if text.strip() and text.strip() != "executing"]
        run.error = messages[0] if messages else "error"
        run.error_line = line
    return run


@dataclass
class Trace:
    segments: list = field(default_factory=list)
    findings: list = field(default_factory=list)
    errors: dict = field(default_factory=dict)  # line -> a rule that found an error there (severity error, violated)

    def segment(self, segment, state):
        self.segments.append(segment)

    def motion_run(self, run, state):
        self.segments.extend(run.segment(index) for index in range(len(run)))

    def hole(self, hole, state):
        pass

    def cycle_run(self, run, state):
        pass

    def change(self, change, state):
        pass

    def fault(self, fault):
        self.findings.append((fault.rule, fault.span.line, fault.status))

    def note(self, note):
        self.findings.append((note.rule, note.span.line, "violated"))

    def report_verdict(self, rule, span, message, verdict, state):
        self.findings.append((rule, span.line, "violated"))


def run_ncverify(text: str, folder: Path | None = None, name: str = "program.ngc", dialect: str = "linuxcnc",
                 profile: str | None = None) -> tuple[Run, Trace]:
    """ncverify's moves per line (main file only; None where an axis is unknown), and its
    findings: the interpreter's own and the rules' (the program is checked as well)."""
    source = ProgramSource.from_text(text, name)
    settings = Settings(dialect=dialect, profile=profile, subprogram_path=(folder,) if folder else ())
    detection = Detection(dialect, 1.0, profile=profile)
    setup = setup_for(dialect, settings, detection, Context())
    if hasattr(setup.frontend, "program_context"):
        setup.frontend.program_context(source)  # as the pipeline does before a run (LinuxCNC: the O-word structure)
    trace = Trace()
    library = SubprogramLibrary([folder] if folder else [], settings.extensions)
    Interpreter(source, setup.frontend, trace, settings, power_on=setup.power_on, cycle_models=setup.cycle_models,
                twins=setup.twins, machine=setup.machine, increment=setup.increment or 0.0, library=library).run()
    checked = check_text(text, name, settings)  # the rules' findings, through the whole pipeline
    main_file = [finding for finding in checked.diagnostics if finding.span.path is None]
    trace.findings += [(finding.rule, finding.span.line, finding.status.value) for finding in main_file]
    trace.errors = {finding.span.line: finding.rule for finding in main_file if finding.status.value == "violated" and finding.severity.value == "error"}
    run = Run()
    for segment in trace.segments:
        if segment.span.path is not None:
            continue
        end = tuple(value if type(value) is float else None for value in (segment.end.get(axis) for axis in "XYZ"))
        run.add(segment.span.line, (*end, "rapid" if segment.kind == "rapid" else "feed"))
    return run, trace


def error_lines(run: Run) -> range:
    """Where rs274's error may be: its last line run, or a line after it that it read
    without running (a subroutine body it skipped, a construct it scanned for its end)."""
    later = [line for line in run.lines_run if line > run.error_line]
    return range(run.error_line, min(later) if later else 1 << 30)


def _differs(a: tuple, b: tuple) -> bool:
    """Are two end points apart (an unknown coordinate may be anywhere: apart)?"""
    return any(x is None or y is None or abs(x - y) > PRINTED for x, y in zip(a[:3], b[:3]))


def _between(middle: tuple, first: tuple, last: tuple) -> bool:
    """Is ``middle`` on the straight segment from ``first`` to ``last`` (all known)?"""
    points = [point[:3] for point in (first, middle, last)]
    if any(value is None for point in points for value in point):
        return False
    (ax, ay, az), (mx, my, mz), (bx, by, bz) = points
    span = (bx - ax, by - ay, bz - az)
    length = math.sqrt(sum(c * c for c in span))
    if length <= PRINTED:
        return False
    t = sum(c * d for c, d in zip(span, (mx - ax, my - ay, mz - az))) / (length * length)
    closest = (ax + t * span[0], ay + t * span[1], az + t * span[2])
    return -PRINTED <= t * length <= length + PRINTED and math.dist(closest, (mx, my, mz)) <= PRINTED


def compare(expected: Run, actual: Run) -> list[str]:
    """Lines whose moves differ: a different number of moves (zero-length moves aside), or
    an end point that ncverify knows and that is off by more than the tolerance."""
    problems = []
    expected_lines, actual_lines = expected.simplified(), actual.simplified()
    for line in sorted(set(expected_lines) | set(actual_lines)):
        theirs = expected_lines.get(line, [])
        ours = actual_lines.get(line, [])
        if expected.error is not None:  # rs274 stopped at its error; ncverify went on
            if line >= expected.error_line:
                continue
            ours = ours[: len(theirs)]
        if len(theirs) != len(ours):
            problems.append(f"line {line}: rs274 made {len(theirs)} moves, ncverify {len(ours)}: {theirs[:4]} / {ours[:4]}")
            continue
        for index, (their, our) in enumerate(zip(theirs, ours)):
            for axis, a, b in zip("XYZ", their[:3], our[:3]):
                if b is not None and abs(a - b) > PRINTED:
                    problems.append(f"line {line} move {index + 1}: {axis} is {a} in rs274, {b} in ncverify")
    return problems
