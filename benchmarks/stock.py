"""Time ``ncverify check`` on a long surfacing program with a stock, with and without the
model of the stock as cut so far (on by default; ``--stock-resolution off`` turns it off).

    python benchmarks/stock.py [BLOCKS] [RESOLUTION]

The program is the zig-zag of ``dialects.py`` cutting 1 mm into a 101 x 1000 mm blank with
a 6 mm ball end mill. Prints the time and peak memory of each run: the figures in the
README's section "The stock as cut so far".
"""
from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

from dialects import _points

HERE = Path(__file__).resolve().parent
_RUN = ("import resource, sys; from ncverify.cli import main; code = main(sys.argv[1:]); "
        "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, file=sys.stderr); sys.exit(code)")


def write_program(blocks: int, path: Path) -> None:
    head = ["%", "O1000", "(ncverify: stock box X-5:105 Y-5:1005 Z-20:0)", "(ncverify: tool 1 radius 3 type ball)",
            "G21 G90 G17 G40 G49 G80 G54", "T1 M06", "G43 H01 Z50.", "S8000 M03", "G00 X0. Y0.", "G00 Z5.", "G01 Z-1. F800."]
    tail = ["G00 Z50.", "M05", "M30", "%"]
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", encoding="ascii", newline="\n") as out:
        out.write("\n".join(head) + "\n")
        for number, (x, y, z) in enumerate(_points(blocks - len(head) - len(tail)), start=len(head)):
            out.write(f"N{number} G01 X{x:.3f} Y{y:.3f} Z{z:.3f}\n")
        out.write("\n".join(tail) + "\n")


def run(program: Path, *options: str) -> tuple[float, float]:
    """Seconds and peak resident memory (MiB) of one check."""
    command = [sys.executable, "-c", _RUN, "check", str(program), "--format", "json", "--output", str(program.with_suffix(".json")),
               "--no-cache", "--jobs", "1", *options]  # in this process, so that its peak memory is the check's
    started = time.perf_counter()
    completed = subprocess.run(command, check=False, capture_output=True, text=True)
    elapsed = time.perf_counter() - started
    return elapsed, int(completed.stderr.strip().splitlines()[-1]) / 1024


def main() -> None:
    blocks = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    resolution = sys.argv[2] if len(sys.argv) > 2 else None
    program = HERE / "out" / f"stock-surfacing-{blocks}.nc"
    if not program.exists():
        write_program(blocks, program)
    blank, blank_memory = run(program, "--stock-resolution", "off")
    cut, cut_memory = run(program, "--stock-resolution", resolution or "auto")
    print(f"{blocks:,} blocks against the blank:       {blank:6.2f} s, peak {blank_memory:5.0f} MiB")
    print(f"{blocks:,} blocks against the cut stock:   {cut:6.2f} s, peak {cut_memory:5.0f} MiB ({cut / blank:.2f} x)")


if __name__ == "__main__":
    main()
