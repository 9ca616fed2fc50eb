"""Write a long 3-axis program of plain CAM-style blocks (a zig-zag surfacing toolpath).

    python benchmarks/generate.py 1000000 benchmarks/out/million.nc
"""
from __future__ import annotations

import math
import sys
from pathlib import Path


def write_program(blocks: int, path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    header = ["%", "O1000 (BENCHMARK SURFACING)", "G21 G90 G17 G40 G49 G80", "G54", "T1 M06", "G43 H01 Z50.",
              "S12000 M03", "G00 X0. Y0.", "G00 Z5.", "G01 Z-1. F800."]
    footer = ["G00 Z50.", "M05", "G49 G80", "M30", "%"]
    body = blocks - len(header) - len(footer)
    with path.open("w", encoding="ascii", newline="\n") as out:
        out.write("\n".join(header) + "\n")
        number = 100
        for index in range(body):
            x = (index % 2000) * 0.05
            y = (index // 2000) * 0.5
            z = -1.0 - 0.2 * math.sin(index / 50.0)
            out.write(f"N{number} G01 X{x:.3f} Y{y:.3f} Z{z:.3f}\n" if index % 7 else f"N{number} X{x:.3f} Y{y:.3f} Z{z:.3f} F1200.\n")
            number += 1
        out.write("\n".join(footer) + "\n")


if __name__ == "__main__":
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    target = Path(sys.argv[2]) if len(sys.argv) > 2 else Path(__file__).parent / "out" / "million.nc"
    write_program(count, target)
    print(f"wrote {count:,} blocks to {target}")
