"""Time ``check_file`` on every third-party program of the real-world corpus.

    python benchmarks/realworld.py [--limit SECONDS] [FOLDER ...]

The corpus (``shared/corpus-realworld`` beside the repository; see its README) is not part
of this repository. Each file is checked in this process with the default settings, best of
``--runs`` runs; files slower than ``--limit`` (10 s) are listed and the exit code is 1.
Timing lives here, not in the tests: on a machine shared with other jobs a time limit fails
for reasons that are not the program's.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from ncverify import Settings, check_file

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus-realworld"


def best_time(path: Path, runs: int) -> float:
    times = []
    for _ in range(runs):
        started = time.perf_counter()
        check_file(path, Settings())
        times.append(time.perf_counter() - started)
    return min(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folders", nargs="*", default=["fanuc", "heidenhain", "sinumerik", "linuxcnc"])
    parser.add_argument("--limit", type=float, default=10.0)
    parser.add_argument("--runs", type=int, default=1)
    arguments = parser.parse_args()
    if not CORPUS.is_dir():
        print(f"the real-world corpus is not at {CORPUS}", file=sys.stderr)
        return 2
    slow = []
    for folder in arguments.folders:
        files = sorted(path for path in (CORPUS / folder).iterdir() if path.is_file())
        timed = [(best_time(path, arguments.runs), path) for path in files]
        slowest = max(timed, default=(0.0, None), key=lambda pair: pair[0])
        print(f"{folder:<11} {len(files):4} files in {sum(t for t, _ in timed):7.2f} s, slowest "
              f"{slowest[0]:.2f} s ({slowest[1].name if slowest[1] else '-'})")
        slow += [(seconds, path) for seconds, path in timed if seconds > arguments.limit]
    for seconds, path in slow:
        print(f"over {arguments.limit:g} s: {path.parent.name}/{path.name} {seconds:.1f} s")
    return 1 if slow else 0


if __name__ == "__main__":
    sys.exit(main())
