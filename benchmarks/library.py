"""Throughput over a program library: 10,000 generated programs (drilling, pockets and
contours, one in ten with a planted mistake, every twentieth calling a subprogram file),
checked with ``--jobs 1``, ``--jobs 2``, on a local Dask cluster of 2 worker processes,
and a second ``--jobs 2`` run answered from the cache.

    python benchmarks/library.py [COUNT] [FOLDER]
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SUBPROGRAM = "O9001 (DRILL PATTERN)\nG81 X10. Y10. Z-5. R2. F120.\nX20.\nX30.\nG80\nM99\n"


def program(number: int) -> str:
    """A small milling program; the mistakes (a feed move with no F, a cycle with its
    bottom above R) come back every tenth program so the batch has findings to report."""
    x, y, depth = 10 + number % 37, 5 + number % 23, 1 + number % 5
    feed = "" if number % 10 == 3 else " F200."
    bottom = f"Z{2 + depth}." if number % 10 == 7 else f"Z-{depth}."
    lines = [f"O{1000 + number % 8000} (PART {number})", "G21 G90 G17 G40 G49 G80", "G54", "T1 M06", "G43 H01 Z50.",
             "S3000 M03", f"G00 X{x}. Y{y}.", "Z5.", f"G01 Z-{depth}.{feed}", f"X{x + 40}.", f"Y{y + 30}.",
             f"G03 X{x}. Y{y + 30}. R20.", f"G01 Y{y}.", "G00 Z5.",
             f"G81 X{x + 5}. Y{y + 5}. {bottom} R2. F150.", f"X{x + 15}.", f"X{x + 25}.", "G80"]
    if number % 20 == 0:
        lines.append("M98 P9001")
    lines += ["G00 Z50.", "M05", "M30"]
    return "\n".join(lines) + "\n"


def write_library(folder: Path, count: int) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "O9001.nc").write_text(SUBPROGRAM, encoding="ascii")
    for number in range(count):
        (folder / f"part{number:05d}.nc").write_text(program(number), encoding="ascii")


def timed(arguments: list[str], environment: dict) -> float:
    started = time.perf_counter()
    subprocess.run([sys.executable, "-m", "ncverify.cli", *arguments], stdout=subprocess.DEVNULL, env=environment, check=False)
    return time.perf_counter() - started


def timed_dask(folder: Path) -> float:
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        return timed(["check", "--format", "json", "--no-cache", "--dask", cluster.scheduler_address, str(folder)], dict(os.environ))


def main() -> None:
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
    folder = Path(sys.argv[2]) if len(sys.argv) > 2 else Path(tempfile.mkdtemp(prefix="ncverify-library-"))
    write_library(folder, count)
    cache = Path(tempfile.mkdtemp(prefix="ncverify-cache-"))
    environment = dict(os.environ)
    runs = [
        ("--jobs 1", ["--jobs", "1", "--no-cache"]),
        ("--jobs 2", ["--jobs", "2", "--no-cache"]),
        ("--jobs 2, cache filled", ["--jobs", "2", "--cache-dir", str(cache)]),
        ("--jobs 2, second run from the cache", ["--jobs", "2", "--cache-dir", str(cache)]),
    ]
    print(f"{count:,} programs in {folder}")
    for label, options in runs:
        seconds = timed(["check", "--format", "json", *options, str(folder)], environment)
        print(f"{label:40} {seconds:7.1f} s  {count / seconds:8.0f} programs/s", flush=True)
    seconds = timed_dask(folder)
    print(f"{'Dask LocalCluster, 2 workers':40} {seconds:7.1f} s  {count / seconds:8.0f} programs/s", flush=True)


if __name__ == "__main__":
    main()
