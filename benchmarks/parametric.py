"""Time ``check_file`` on a generated parametric program: 200 blocks, 5 free parameters.

    python benchmarks/parametric.py [--profile]

The program (written to benchmarks/out/parametric-200.nc) drills and mills a plate whose
hole depth, R plane, pattern origin and contour depth are the free parameters ``#1``-``#5``,
bounded by ``ncverify: assume`` annotations, against an annotated stock. Every depth and
position check on it is a solver question. Prints the median of three runs in seconds
(the target is under 2 s), for the program as written and for a variant whose contour
retracts are rapids out of the material (violations whose witnesses are replayed);
``--profile`` prints where the time of one run of the first goes.
"""
from __future__ import annotations

import cProfile
import pstats
import statistics
import sys
import time
from pathlib import Path

from ncverify import check_file
from ncverify.diagnostics import Status

HERE = Path(__file__).resolve().parent
BLOCKS = 200
PARAMETERS = ("#1", "#2", "#3", "#4", "#5")

ANNOTATIONS = [
    "(PARAMETRIC PLATE - DEPTHS AND PATTERN ORIGIN GIVEN AT THE MACHINE)",
    "(ncverify: stock box X0:200 Y0:150 Z-30:0)",
    "(ncverify: tool 1 radius 3 length 80 type drill)",
    "(ncverify: tool 2 radius 5 length 90 type endmill)",
    "(ncverify: assume -12 <= #1 <= -3)",
    "(ncverify: assume 1 <= #2 <= 5)",
    "(ncverify: assume 10 <= #3 <= 20 and 10 <= #4 <= 20)",
    "(ncverify: assume -4 <= #5 <= -0.5)",
]


def program_blocks(blocks: int = BLOCKS, retract: str = "G01 Z#2 F2000.") -> list[str]:
    """Exactly ``blocks`` NC blocks: a drilled grid at (#3, #4) + 12 mm steps to depth #1
    from R#2, then contour passes at depth #5 around the same origin, each left by
    ``retract`` (a feed move; ``G00 Z#2`` makes every retract a rapid out of the
    material, which ncverify reports because the stock is not updated by cutting)."""
    head = ["%", "O2000", "G21 G17 G40 G49 G80 G90", "T1 M06", "G00 G54 X[#3] Y[#4] S3000 M03", "G43 Z50. H01 M08",
            "G99 G81 X[#3] Y[#4] Z#1 R#2 F120."]
    middle_tool_change = ["G80", "G00 Z50. M09", "M05", "T2 M06", "G00 X[#3-5.] Y[#4-5.] S6000 M03", "G43 Z50. H02 M08", "G00 Z#2"]
    tail = ["G00 Z50. M09", "M05", "G91 G28 Z0.", "G90", "M30", "%"]
    budget = blocks - len(head) - len(middle_tool_change) - len(tail)
    holes = budget // 2
    body_holes = []
    for index in range(1, holes):
        column, row = index % 12, index // 12
        body_holes.append(f"X[#3+{column * 12}.] Y[#4+{row * 12}.]")
    contour = []
    pass_index = 0
    while len(contour) < budget - len(body_holes):
        size = 100.0 - 4.0 * (pass_index % 10)
        depth = f"[#5-{(pass_index % 3) * 0.5:.1f}]"
        ring = [f"G01 Z{depth} F300.", f"X[#3+{size:g}.]", f"Y[#4+{size * 0.8:g}]", "X[#3-5.]", "Y[#4-5.]", retract]
        contour.extend(ring)
        pass_index += 1
    contour = contour[: budget - len(body_holes)]
    contour[-1] = retract
    lines = head + body_holes + middle_tool_change + contour + tail
    assert len(lines) == blocks, len(lines)
    return lines


def write(path: Path, blocks: int = BLOCKS, retract: str = "G01 Z#2 F2000.") -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = program_blocks(blocks, retract)
    text = "\n".join(lines[:2] + ANNOTATIONS + lines[2:]) + "\n"
    path.write_text(text, encoding="ascii")
    return path


def time_check(path: Path, runs: int = 3) -> tuple[float, object]:
    timings, result = [], None
    for _ in range(runs):
        started = time.perf_counter()
        result = check_file(path)
        timings.append(time.perf_counter() - started)
    return statistics.median(timings), result


def main(argv: list[str]) -> int:
    path = write(HERE / "out" / f"parametric-{BLOCKS}.nc")
    variants = [("safe", path), ("with violations", write(HERE / "out" / f"parametric-{BLOCKS}-violated.nc", retract="G00 Z#2"))]
    for name, program in variants:
        seconds, result = time_check(program)
        statuses = {status.value: sum(1 for d in result.diagnostics if d.status is status) for status in Status}
        print(f"{name}: {BLOCKS} blocks, {len(result.free_parameters)} free parameters ({', '.join(result.free_parameters)}): "
              f"check_file median of 3 = {seconds:.3f} s; blocks run {result.blocks}; findings {statuses}")
    if "--profile" in argv:
        profiler = cProfile.Profile()
        profiler.enable()
        check_file(path)
        profiler.disable()
        pstats.Stats(profiler).sort_stats("cumulative").print_stats(30)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
