"""Time ``ncverify check`` end to end on a generated 1,000,000-block program.

    python benchmarks/run.py [BLOCKS]

Prints blocks per second and the peak resident memory of the checking process, the
figures quoted in the README. The program is generated once into benchmarks/out/.
"""
from __future__ import annotations

import resource
import subprocess
import sys
import time
from pathlib import Path

from generate import write_program

HERE = Path(__file__).resolve().parent


def main() -> None:
    blocks = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    program = HERE / "out" / f"plain-{blocks}.nc"
    if not program.exists():
        write_program(blocks, program)
    command = [sys.executable, "-m", "ncverify.cli", "check", str(program), "--format", "json", "--no-cache", "--output", str(HERE / "out" / "report.json")]  # timed afresh, never a cached report
    started = time.perf_counter()
    completed = subprocess.run(command, check=False)
    elapsed = time.perf_counter() - started
    peak_kib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    print(f"{blocks:,} blocks in {elapsed:.2f} s: {blocks / elapsed:,.0f} blocks/s end to end, "
          f"peak memory {peak_kib / 1024:.0f} MiB, exit code {completed.returncode}")


if __name__ == "__main__":
    main()
