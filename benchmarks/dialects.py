"""Time ``ncverify check`` on the same surfacing toolpath written in each dialect.

    python benchmarks/dialects.py [BLOCKS] [DIALECT ...]

Every dialect gets the zig-zag of ``generate.py`` (straight feed moves, a tool call, a
spindle start, a stock, the tool's size) as its CAM post would write it. Prints blocks per second end to
end and peak memory per dialect: the figures in the README's Speed section.
"""
from __future__ import annotations

import math
import resource
import subprocess
import sys
import time
from pathlib import Path

from compare import check_report  # a sibling script: benchmarks/ is the path's first entry

HERE = Path(__file__).resolve().parent
TOOL = "ncverify: tool 1 radius 3.175 length 0 type endmill"  # a 6.35 mm end mill, as in compare.py


def _points(blocks: int):
    for index in range(blocks):
        yield (index % 2000) * 0.05, (index // 2000) * 0.5, -1.0 - 0.2 * math.sin(index / 50.0)


def _iso(blocks: int) -> tuple[list[str], str, list[str]]:
    head = ["%", "O1000", "(ncverify: stock box X-1:101 Y-1:1000 Z-20:-2)", f"({TOOL})", "G21 G90 G17 G40 G49 G80 G54", "T1 M06", "G43 H01 Z50.",
            "S8000 M03", "G00 X0. Y0.", "G00 Z5.", "G01 Z-1. F800."]
    return head, "N{n} G01 X{x:.3f} Y{y:.3f} Z{z:.3f}", ["G00 Z50.", "M05", "M30", "%"]


def _heidenhain(blocks: int) -> tuple[list[str], str, list[str]]:
    head = ["0 BEGIN PGM BENCH MM", "1 BLK FORM 0.1 Z X-1 Y-1 Z-20", "2 BLK FORM 0.2 X+101 Y+1000 Z-2", f"3 ; {TOOL}", "4 TOOL CALL 1 Z S8000",
            "5 L Z+50 R0 FMAX M3", "6 L X+0 Y+0 R0 FMAX", "7 L Z+5 FMAX", "8 L Z-1 F800"]
    return head, "{n} L X{x:+.3f} Y{y:+.3f} Z{z:+.3f}", ["L Z+50 R0 FMAX M5", "M30", "END PGM BENCH MM"]


def _sinumerik(blocks: int) -> tuple[list[str], str, list[str]]:
    head = ["%_N_BENCH_MPF", "WORKPIECE(,\"\",,\"BOX\",0,-2,-20,-80,-1,-1,101,1000)", f"; {TOOL}", "G17 G90 G71 G54", "T1 D1", "M6",
            "S8000 M3", "G0 X0 Y0 Z50", "G0 Z5", "G1 Z-1 F800"]
    return head, "N{n} G1 X{x:.3f} Y{y:.3f} Z{z:.3f}", ["G0 Z50", "M5", "M30"]


def _fagor(blocks: int) -> tuple[list[str], str, list[str]]:
    head = ["; ncverify: stock box X-1:101 Y-1:1000 Z-20:-2", f"; {TOOL}", "G71 G90 G17 G40 G54", "T1 D1", "M6", "S8000 M3",
            "G0 X0 Y0 Z50", "G0 Z5", "G1 Z-1 F800", "#MSG [\"BENCH\"]"]
    return head, "N{n} G1 X{x:.3f} Y{y:.3f} Z{z:.3f}", ["G0 Z50", "M5", "M30"]


DIALECTS = {"iso": (_iso, ".nc"), "heidenhain": (_heidenhain, ".h"), "sinumerik": (_sinumerik, ".mpf"), "fagor": (_fagor, ".pim")}


def write_program(dialect: str, blocks: int, path: Path) -> None:
    make, _extension = DIALECTS[dialect]
    head, line, tail = make(blocks)
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", encoding="ascii", newline="\n") as out:
        out.write("\n".join(head) + "\n")
        for number, (x, y, z) in enumerate(_points(blocks - len(head) - len(tail)), start=len(head)):
            out.write(line.format(n=number, x=x, y=y, z=z) + "\n")
        out.write("\n".join(tail) + "\n")


def time_check(path: Path, dialect: str) -> tuple[float, int, dict]:
    """Seconds, exit code and the JSON report of one ``ncverify check`` run (the dialect is
    named: a plain surfacing toolpath carries nothing that tells Fagor from ISO)."""
    import json

    report = path.with_suffix(".json")
    command = [sys.executable, "-m", "ncverify.cli", "check", str(path), "--format", "json", "--output", str(report), "--dialect", dialect,
               "--no-cache"]  # a cached result would time nothing
    started = time.perf_counter()
    completed = subprocess.run(command, check=False)
    return time.perf_counter() - started, completed.returncode, json.loads(report.read_text())


def main() -> None:
    blocks = int(sys.argv[1]) if len(sys.argv) > 1 else 200_000
    for dialect in sys.argv[2:] or DIALECTS:
        _make, extension = DIALECTS[dialect]
        program = HERE / "out" / f"surfacing-{dialect}-{blocks}{extension}"
        write_program(dialect, blocks, program)  # each run: a file left by an older run may differ
        elapsed, code, report = time_check(program, dialect)
        check_report(program.with_suffix(".json"), program)
        peak_kib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        entry = report["files"][0]
        findings = sum(1 for d in entry["diagnostics"] if d["status"] == "violated")
        print(f"{dialect:<11} {blocks:,} blocks in {elapsed:5.2f} s: {blocks / elapsed:9,.0f} blocks/s, "
              f"checked as {entry['dialect']}, {findings} violation(s), exit {code}, peak memory so far {peak_kib / 1024:.0f} MiB")


if __name__ == "__main__":
    main()
