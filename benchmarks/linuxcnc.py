"""Time ncverify against LinuxCNC's own interpreter (rs274) on one LinuxCNC program.

    python benchmarks/linuxcnc.py [BLOCKS]

The program is the surfacing zig-zag of ``dialects.py`` as LinuxCNC's CAM posts write it,
plus a subroutine called in an O-word loop that reads named parameters (every pass of the
loop runs the subroutine's blocks again in both interpreters). rs274 comes from
``.ci/install-rs274``. Prints the wall time of each (process start included) and blocks
per second: the figures of the README's LinuxCNC section.
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
RS274 = HERE.parent / ".rs274" / "usr" / "bin" / "rs274"
sys.path.insert(0, str(HERE))

from compare import RS274_TOOL_TABLE, TOOL_TABLE  # noqa: E402  (one end mill, in the units each reader takes)
from dialects import _points  # noqa: E402  (the same toolpath as the other dialects)

LOOPS = 200  # calls of the subroutine, 6 blocks each


def write_program(blocks: int, path: Path) -> int:
    """The program; returns the number of blocks it runs."""
    head = ["o<pocket> sub", "#<depth> = #1", "G0 X[#2] Y[#3] Z2", "G1 Z[-#<depth>] F300", "G1 X[#2 + 5] Y[#3 + 5]", "G0 Z5",
            "o<pocket> endsub", "G21 G90 G17 G40 G49 G80 G54", "T1 M6", "G43 H1", "S8000 M3", "G0 X0 Y0 Z5", "G1 Z-1 F800"]
    loop = ["#<i> = 0", f"o100 while [#<i> LT {LOOPS}]", "o<pocket> call [1.5] [#<i> * 0.5] [10]", "#<i> = [#<i> + 1]", "o100 endwhile"]
    tail = ["G0 Z50", "M5", "M2"]
    straight = blocks - len(head) - len(loop) - len(tail)
    with path.open("w", encoding="ascii", newline="\n") as out:
        out.write("\n".join(head) + "\n")
        for x, y, z in _points(straight):
            out.write(f"G1 X{x:.3f} Y{y:.3f} Z{z:.3f}\n")
        out.write("\n".join(loop + tail) + "\n")
    return blocks - len(loop) + LOOPS * 8


def _time(command: list[str], **options) -> float:
    start = time.perf_counter()
    subprocess.run(command, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL, **options)
    return time.perf_counter() - start


def main() -> None:
    blocks = int(sys.argv[1]) if len(sys.argv) > 1 else 200_000
    if not RS274.exists():
        sys.exit("rs274 is not installed: run .ci/install-rs274")
    with tempfile.TemporaryDirectory() as scratch:
        work = Path(scratch)
        program = work / "bench.ngc"
        run = write_program(blocks, program)
        (work / "tool.tbl").write_text(TOOL_TABLE, encoding="ascii")
        (work / "rs274-tool.tbl").write_text(RS274_TOOL_TABLE, encoding="ascii")
        ours = _time([sys.executable, "-m", "ncverify.cli", "check", str(program), "--format", "json", "--output", str(work / "report.json")])
        environment = dict(os.environ, LD_LIBRARY_PATH=str(RS274.parent.parent / "lib"))
        theirs = _time([str(RS274), "-t", "rs274-tool.tbl", "-g", "bench.ngc", "out.txt"], cwd=work, env=environment)
    for name, seconds in (("ncverify check (every rule)", ours), ("rs274 (interpretation only)", theirs)):
        print(f"{name:30s} {seconds:6.2f} s  {run / seconds:10,.0f} blocks/s")


if __name__ == "__main__":
    main()
