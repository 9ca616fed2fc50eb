"""Time ``ncverify check`` against LinuxCNC's interpreter (``rs274``) on the same toolpaths.

    python benchmarks/compare.py [--blocks N] [--runs N] [--only NAME ...] [--markdown] [--air-cutting]

Writes each program (200,000 blocks by default) into ``benchmarks/out/``, then times
``ncverify check`` on it as a user runs it (every rule on, JSON report) and, for the
programs LinuxCNC can read (the ISO rows), ``rs274 -t rs274-tool.tbl -g`` from
``.ci/install-rs274`` on the very same file. Both are timed end to end, process start
included, in paired alternating runs (ours, theirs, ours, theirs ...) so that a load spike
on a shared machine hits both alike. Printed: the minimum wall time and the minimum CPU time
(user + system, of the process and its children) of each, and their ratios; on a machine
shared with other jobs the CPU time is the steadier figure.
SINUMERIK, Klartext and Fagor programs are timed for ncverify only (rs274 reads ISO only).
``--air-cutting`` times the check that also reports the air statistic, which sweeps every
feed move through the cut stock (a plain check sweeps only where a rapid enters the blank).
"""
from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import platform
import resource
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator

HERE = Path(__file__).resolve().parent
RS274 = HERE.parent / ".rs274" / "usr" / "bin" / "rs274"
# The same two tools for every reader, as each one reads them: the standalone rs274 a table
# of diameters in inches; ncverify LinuxCNC's ``tool.tbl`` beside a LinuxCNC program, and in
# every other program the annotations of :func:`_tool_lines`. Without them the rules that need
# a tool's size answer ``unknown`` and the stock is swept by the tool's axis alone: a fraction
# of the work a user's run does, who gives ncverify the tools.
TOOLS = {1: (3.175, "endmill"), 2: (1.5875, "drill")}  # number: (radius mm, type)
TOOL_TABLE = "".join(f"T{number} P{number} D{2 * radius:g} Z0 ;{kind}\n" for number, (radius, kind) in TOOLS.items())
RS274_TOOL_TABLE = "".join(f"T{number} P{number} D{2 * radius / 25.4:g} Z0 ;{kind}\n" for number, (radius, kind) in TOOLS.items())


def _tool_lines(comment: str) -> list[str]:
    """The tools as ``ncverify: tool`` annotations, each in the language's comment form
    ``comment`` (a format string)."""
    return [comment.format(f"ncverify: tool {number} radius {radius:g} length 0 type {kind}") for number, (radius, kind) in TOOLS.items()]


# --------------------------------------------------------------------------- the programs


def _surfacing(blocks: int) -> Iterator[str]:
    """Straight feed moves of a zig-zag surfacing pass (the plain CAM bulk)."""
    head = ["(ncverify: stock box X-5:105 Y-5:1000 Z-20:0)", *_tool_lines("({})"), "G21 G90 G17 G40 G49 G80 G54", "T1 M6", "G43 H1",
            "G0 Z50.", "S8000 M3", "G0 X0. Y0.", "G0 Z5.", "G1 Z-1. F800."]
    tail = ["G0 Z50.", "M5", "M30"]
    yield from head
    for index in range(blocks - len(head) - len(tail)):
        yield f"G1 X{(index % 2000) * 0.05:.3f} Y{(index // 2000) * 0.5:.3f} Z{-1.0 - 0.2 * math.sin(index / 50.0):.3f}"
    yield from tail


def _trochoid(groups: int, *, radius: float = 2.0, step: float = 0.4, width: int = 120) -> Iterator[tuple]:
    """Adaptive-clearing style motion: half circles joined by short lines, each row of the
    slot opened by a helical ramp. Yields ("line", x, y, z), ("arc", cw, x, y, z, i, j)."""
    row_pitch = 2 * radius + 1
    for group in range(groups):
        row, column = divmod(group, width)
        x, y = column * 2 * step, row * row_pitch
        if column == 0:
            yield "rapid", x, y, 1.0
            yield "arc", True, x, y, -1.0, radius, 0.0  # a full helical turn down to depth
        yield "arc", False, x, y + 2 * radius, -1.0, 0.0, radius
        yield "line", x + step, y + 2 * radius, -1.0
        yield "arc", True, x + step, y, -1.0, 0.0, -radius
        yield "line", x + 2 * step, y, -1.0
        if column == width - 1:
            yield "rapid", x + 2 * step, y, 5.0


def _iso_trochoid_block(move: tuple) -> str:
    if move[0] == "rapid":
        return f"G0 X{move[1]:.3f} Y{move[2]:.3f} Z{move[3]:.3f}"
    if move[0] == "line":
        return f"G1 X{move[1]:.3f} Y{move[2]:.3f}"
    _, clockwise, x, y, z, i, j = move
    return f"G{2 if clockwise else 3} X{x:.3f} Y{y:.3f} Z{z:.3f} I{i:.3f} J{j:.3f}"


def _adaptive(blocks: int) -> Iterator[str]:
    """G01 with G02/G03 in I/J form and helical ramps, as adaptive clearing writes them."""
    head = ["(ncverify: stock box X-5:105 Y-5:10000 Z-20:0)", *_tool_lines("({})"), "G21 G90 G17 G40 G49 G80 G54", "T1 M6", "G43 H1",
            "G0 Z50.", "S8000 M3", "G0 X0. Y0.", "G0 Z5.", "F1200."]
    tail = ["G0 Z50.", "M5", "M30"]
    yield from head
    moves = _trochoid(blocks // 4 + 1)
    for _ in range(blocks - len(head) - len(tail)):
        yield _iso_trochoid_block(next(moves))
    yield from tail


LOOP_PASSES = 50_000  # moves the macro loop makes; 4 blocks a pass


def _macro_loop(blocks: int) -> Iterator[str]:
    """A LinuxCNC O-word WHILE loop computing every point with parameter arithmetic."""
    passes = blocks // 4
    yield from ("(ncverify: stock box X-5:105 Y-5:200 Z-20:0)", "G21 G90 G17 G40 G49 G80 G54", "T1 M6", "G43 H1", "G0 Z50.",
                "S8000 M3", "G0 X0 Y0 Z5", "G1 Z-1 F800", "#<i> = 0", f"o100 while [#<i> LT {passes}]",
                "#<x> = [[#<i> MOD 200] * 0.5]", "#<y> = [FIX[#<i> / 200] * 0.5]",
                "G1 X#<x> Y#<y> Z[-1 - 0.2 * SIN[#<i> * 3.6]]", "#<i> = [#<i> + 1]", "o100 endwhile", "G0 Z50", "M5", "M2")


@dataclass(frozen=True)
class Move:
    """One move of the part's profile: ``centre`` is set for a clockwise arc."""

    start: tuple[float, float]
    end: tuple[float, float]
    z: float
    centre: tuple[float, float] | None = None


SIZE, CORNER, LAPS, HOLES = 40.0, 6.0, 40, 20  # the part: a rounded square profile, stepped down, and a hole grid


def _profile() -> Iterator[Move]:
    """Clockwise laps around a rounded square, 0.25 deeper each, from the middle of its left side."""
    s, c = SIZE, CORNER
    corners = [((0.0, s - c), (c, s), (c, s - c)), ((s - c, s), (s, s - c), (s - c, s - c)),
               ((s, c), (s - c, 0.0), (s - c, c)), ((c, 0.0), (0.0, c), (c, c))]
    here = (0.0, s / 2)
    for lap in range(LAPS):
        z = -0.25 * (lap + 1)
        for start, end, centre in corners:
            yield Move(here, start, z)
            yield Move(start, end, z, centre)
            here = end
        yield Move(here, (0.0, s / 2), z)
        here = (0.0, s / 2)


def _holes() -> Iterator[tuple[float, float]]:
    for index in range(HOLES):
        yield 5.0 + (index % 5) * 7.5, 5.0 + (index // 5) * 10.0


def _repeat_parts(blocks: int, head: list[str], part: Callable[[float], Iterator[str]], tail: list[str]) -> Iterator[str]:
    """``head``, as many whole copies of ``part`` (each 60 mm further along Y) as fit in
    ``blocks`` lines, ``tail``."""
    yield from head
    room, offset = blocks - len(head) - len(tail), 0.0
    while True:
        lines = list(part(offset))
        if len(lines) > room:
            break
        yield from lines
        room -= len(lines)
        offset += 60.0
    yield from tail


def _iso_part(offset: float) -> Iterator[str]:
    entry = f"X-10. Y{offset + SIZE / 2:.3f}"
    yield from ("T1 M6", "S8000 M3", f"G0 {entry}", "G43 H1", "G0 Z15.", "M8", "G0 Z5.", "G1 Z0. F300.",
                f"G41 D1 G1 X0. Y{offset + SIZE / 2:.3f} F800.")
    for move in _profile():
        x, y = move.end
        if move.centre is None:
            yield f"G1 X{x:.3f} Y{offset + y:.3f} Z{move.z:.3f}"
        else:
            i, j = move.centre[0] - move.start[0], move.centre[1] - move.start[1]
            yield f"G2 X{x:.3f} Y{offset + y:.3f} I{i:.3f} J{j:.3f}"
    yield from (f"G40 G1 {entry}", "G0 Z15.", "M9", "T2 M6", "S3000 M3", "G43 H2", "G0 Z15.", "G0 Z5.")
    for index, (x, y) in enumerate(_holes()):
        yield f"G98 G81 X{x:.3f} Y{offset + y:.3f} Z-5. R1. F150." if index == 0 else f"X{x:.3f} Y{offset + y:.3f}"
    yield from ("G80", "G0 Z15.", "M5")


def _iso_post(blocks: int) -> Iterator[str]:
    head = ["(ncverify: stock box X-20:60 Y-20:100000 Z-20:0)", *_tool_lines("({})"), "G21 G90 G94 G17 G40 G49 G80 G54"]
    return _repeat_parts(blocks, head, _iso_part, ["G0 Z50.", "M30"])


def _contour(offset: float, radius_word: str) -> Iterator[str]:
    """The compensated profile of a SINUMERIK or Fagor post (the same G words): arcs
    alternately by their radius (``radius_word``) and by I/J relative to the start."""
    yield from ("T1 D1", "M6", "S8000 M3", f"G0 X-10 Y{offset + SIZE / 2:.3f}", "G0 Z5", "G1 Z0 F300",
                f"G41 G1 X0 Y{offset + SIZE / 2:.3f} F800")
    for number, move in enumerate(_profile()):
        x, y = move.end
        if move.centre is None:
            yield f"G1 X{x:.3f} Y{offset + y:.3f} Z{move.z:.3f}"
        elif number % 2 == 0:
            yield f"G2 X{x:.3f} Y{offset + y:.3f} {radius_word}{CORNER:.3f}"
        else:
            i, j = move.centre[0] - move.start[0], move.centre[1] - move.start[1]
            yield f"G2 X{x:.3f} Y{offset + y:.3f} I{i:.3f} J{j:.3f}"
    yield from (f"G40 G1 X-10 Y{offset + SIZE / 2:.3f}", "G0 Z15")


def _sinumerik_part(offset: float) -> Iterator[str]:
    """SINUMERIK 840D post: arcs alternately as CR= and I/J; holes by CYCLE81."""
    yield from _contour(offset, "CR=")
    yield from ("T2 D1", "M6", "S3000 M3", "G0 Z15")
    for x, y in _holes():
        yield f"G0 X{x:.3f} Y{offset + y:.3f}"
        yield "CYCLE81(15, 0, 2, -5)"
    yield from ("G0 Z50", "M5")


def _sinumerik_post(blocks: int) -> Iterator[str]:
    head = ["%_N_PART_MPF", 'WORKPIECE(,"",,"BOX",0,0,-20,-80,-20,-20,60,100000)', *_tool_lines("; {}"), "G17 G90 G71 G54"]
    return _repeat_parts(blocks, head, _sinumerik_part, ["G0 Z50", "M30"])


def _heidenhain_part(offset: float) -> Iterator[str]:
    """Klartext post: arcs alternately as CC + C, CR and (tangential) CT; holes by cycle 200."""
    yield from ("TOOL CALL 1 Z S8000", "L Z+50 R0 FMAX M3", f"L X-10 Y{offset + SIZE / 2:+.3f} R0 FMAX", "L Z+5 R0 FMAX",
                "L Z+0 R0 F300", f"L X+0 Y{offset + SIZE / 2:+.3f} RR F800")
    for number, move in enumerate(_profile()):
        x, y = move.end
        if move.centre is None:
            yield f"L X{x:+.3f} Y{offset + y:+.3f} Z{move.z:+.3f}"
        elif number % 2 == 0:
            yield f"CC X{move.centre[0]:+.3f} Y{offset + move.centre[1]:+.3f}"
            yield f"C X{x:+.3f} Y{offset + y:+.3f} DR-"
        else:
            yield f"CR X{x:+.3f} Y{offset + y:+.3f} R+{CORNER:.3f} DR-"
    yield from (f"L X-10 Y{offset + SIZE / 2:+.3f} R0", "L Z+15 R0 FMAX", "TOOL CALL 2 Z S3000", "L Z+15 R0 FMAX M3",
                "CYCL DEF 200 DRILLING Q200=+2 Q201=-5 Q206=+150 Q202=+5 Q210=+0 Q203=+0 Q204=+15 Q211=+0")
    for x, y in _holes():
        yield f"L X{x:+.3f} Y{offset + y:+.3f} R0 FMAX M99"
    yield "L Z+50 R0 FMAX M5"


def _heidenhain_post(blocks: int) -> Iterator[str]:
    head = ["BEGIN PGM PART MM", "BLK FORM 0.1 Z X-20 Y-20 Z-20", "BLK FORM 0.2 X+60 Y+100000 Z+0", *_tool_lines("; {}")]
    lines = _repeat_parts(blocks, head, _heidenhain_part, ["M30", "END PGM PART MM"])
    return (f"{number} {line}" for number, line in enumerate(lines))


def _fagor_part(offset: float) -> Iterator[str]:
    """Fagor 8065 post: arcs as I/J (relative to the start) and R; holes by G81."""
    yield from _contour(offset, "R")
    yield from ("T2 D2", "M6", "S3000 M3", "G0 Z15")
    for index, (x, y) in enumerate(_holes()):
        yield f"G98 G81 X{x:.3f} Y{offset + y:.3f} Z2 I-5 F150" if index == 0 else f"X{x:.3f} Y{offset + y:.3f}"
    yield from ("G80", "G0 Z50", "M5")


def _fagor_post(blocks: int) -> Iterator[str]:
    head = ["; ncverify: stock box X-20:60 Y-20:100000 Z-20:0", *_tool_lines("; {}"), "G71 G90 G17 G40 G54"]
    return _repeat_parts(blocks, head, _fagor_part, ["G0 Z50", "M30"])


# --------------------------------------------------------------------------- running


@dataclass
class Program:
    name: str
    suffix: str
    lines: Callable[[int], Iterator[str]]
    rs274: bool
    options: tuple[str, ...] = ()

    def path(self, blocks: int) -> Path:
        return HERE / "out" / f"compare-{self.name}-{blocks}{self.suffix}"

    def write(self, blocks: int) -> Path:
        path = self.path(blocks)
        path.parent.mkdir(parents=True, exist_ok=True)
        with path.open("w", encoding="ascii", newline="\n") as out:  # written each time, as the tables: an older run's may differ
            for line in self.lines(blocks):
                out.write(line + "\n")
        (path.parent / "tool.tbl").write_text(TOOL_TABLE, encoding="ascii")
        (path.parent / "rs274-tool.tbl").write_text(RS274_TOOL_TABLE, encoding="ascii")
        return path

    def run_ncverify(self, path: Path, extra: tuple[str, ...] = ()) -> tuple[float, float]:
        report = path.with_suffix(".json")
        command = [sys.executable, "-m", "ncverify.cli", "check", str(path), "--format", "json", "--output", str(report),
                   "--no-cache", *self.options, *extra]  # a cached result would time nothing
        # As installed by pip: modules are compiled once, not on every start.
        environment = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}
        timing = _timed(command, env=environment)
        check_report(report, path)
        return timing

    def run_rs274(self, path: Path) -> tuple[float, float]:
        environment = dict(os.environ, LD_LIBRARY_PATH=str(RS274.parent.parent / "lib"))
        return _timed([str(RS274), "-t", "rs274-tool.tbl", "-g", path.name, path.with_suffix(".canon").name], cwd=path.parent, env=environment)


PROGRAMS = (
    Program("iso-surfacing", ".nc", _surfacing, rs274=True),
    Program("iso-adaptive-arcs", ".nc", _adaptive, rs274=True),
    Program("linuxcnc-macro-loop", ".ngc", _macro_loop, rs274=True, options=("--loop-bound", "100000")),
    Program("iso-cam-post", ".nc", _iso_post, rs274=True),
    Program("sinumerik-cam-post", ".mpf", _sinumerik_post, rs274=False),
    Program("heidenhain-cam-post", ".h", _heidenhain_post, rs274=False),
    Program("fagor-cam-post", ".pim", _fagor_post, rs274=False),
)


def _timed(command: list[str], **options) -> tuple[float, float]:
    """Wall time and CPU time (user + system) of one run of ``command``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    completed = subprocess.run(command, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, **options)
    seconds = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    if completed.returncode not in (0, 1):  # ncverify: 1 = findings; rs274: 1 = stopped on an error
        sys.exit(f"{command[0]} failed ({completed.returncode}): {completed.stderr.decode(errors='replace')[-2000:]}")
    if command[0] == str(RS274) and completed.returncode:
        sys.exit(f"rs274 stopped on an error, so it did not run the whole program: {completed.stderr.decode(errors='replace')[-2000:]}")
    return seconds, cpu


def check_report(report: Path, program: Path) -> None:
    """A benchmark is only fair when the whole program was checked, as a user's run checks
    it: no interpreter stop, and its tools known (without them the cut stock sweeps each
    tool's axis alone, a fraction of the work)."""
    entry = json.loads(report.read_text())["files"][0]
    stops = [d for d in entry["diagnostics"] if d["rule"] in ("core.loop-bound", "core.path-limit", "core.syntax", "core.tool-not-in-table")]
    if stops:
        sys.exit(f"{program.name}: ncverify did not check it all: {stops[0]['rule']} {stops[0]['message']}")


def _machine() -> str:
    cpu = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines() if line.startswith("model name")), platform.processor())
    return f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, load average {os.getloadavg()[0]:.1f} at start"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--blocks", type=int, default=200_000)
    parser.add_argument("--runs", type=int, default=3, help="paired runs per program; the minimum is reported")
    parser.add_argument("--only", nargs="*", help="program names to run")
    parser.add_argument("--markdown", action="store_true", help="print the README table")
    parser.add_argument("--air-cutting", action="store_true",
                        help="check with --air-cutting: every feed move swept through the cut stock, none deferred")
    arguments = parser.parse_args()
    extra = ("--air-cutting",) if arguments.air_cutting else ()
    have_rs274 = RS274.exists()
    rows = []
    for program in PROGRAMS:
        if arguments.only and program.name not in arguments.only:
            continue
        path = program.write(arguments.blocks)
        ours, theirs = [], []
        for _ in range(arguments.runs):
            ours.append(program.run_ncverify(path, extra))
            if program.rs274 and have_rs274:
                theirs.append(program.run_rs274(path))
        rows.append((program.name, _best(ours), _best(theirs) if theirs else None))
        _print_row(*rows[-1])
    if arguments.markdown:
        print(f"\n{arguments.blocks:,} blocks per program, minimum of {arguments.runs} paired runs, "
              f"{datetime.date.today().isoformat()}, {_machine()}\n")
        print("| program | ncverify wall / CPU | rs274 wall / CPU | ratio wall / CPU |\n|---|---|---|---|")
        for name, ours, theirs in rows:
            ratio = f"{ours[0] / theirs[0]:.2f} / {ours[1] / theirs[1]:.2f}" if theirs else "-"
            print(f"| {name} | {ours[0]:.2f} s / {ours[1]:.2f} s | {f'{theirs[0]:.2f} s / {theirs[1]:.2f} s' if theirs else '-'} | {ratio} |")
    if not have_rs274:
        print("rs274 is not installed (.ci/install-rs274): ncverify's times only", file=sys.stderr)


def _best(timings: list[tuple[float, float]]) -> tuple[float, float]:
    """The minimum wall time and the minimum CPU time of the runs."""
    return min(wall for wall, _ in timings), min(cpu for _, cpu in timings)


def _print_row(name: str, ours: tuple[float, float], theirs: tuple[float, float] | None) -> None:
    line = f"{name:22s} ncverify {ours[0]:6.2f} s wall {ours[1]:6.2f} s CPU"
    if theirs:
        line += f"   rs274 {theirs[0]:6.2f} s wall {theirs[1]:6.2f} s CPU   ratio {ours[0] / theirs[0]:5.2f} wall {ours[1] / theirs[1]:5.2f} CPU"
    print(line, flush=True)


if __name__ == "__main__":
    main()
