"""The long fuzzing campaign (the short fixed-seed one runs in the test suite).

    python benchmarks/fuzz.py --chunks 50 --chunk-size 2000 --out fuzz-out

runs chunks of mutated inputs (chunk ``i`` uses seed ``i``, so any chunk can be re-run
alone with ``--first-chunk i --chunks 1``) through ``ncverify check`` in every report
format and dialect, with the checks of ``tests/fuzz/harness.py``. Each chunk appends one
JSON line to ``OUT/progress.jsonl``; each failing input is saved as
``OUT/failure-<chunk>-<index><ext>`` with its options and what broke in a ``.json`` beside
it. ``--replay OUT`` runs every saved failure again with its options (after a fix). The
exit code is 1 if anything failed.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "fuzz"))

from harness import Runner, campaign, seed_programs, suffix_for  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--chunks", type=int, default=50)
    parser.add_argument("--first-chunk", type=int, default=0)
    parser.add_argument("--chunk-size", type=int, default=2000)
    parser.add_argument("--repeat-every", type=int, default=10, help="run every n-th input twice and compare (default %(default)s)")
    parser.add_argument("--validate-every", type=int, default=3, help="validate every n-th SARIF report against the schema (default %(default)s)")
    parser.add_argument("--out", type=Path, default=Path("fuzz-out"))
    parser.add_argument("--work", type=Path, default=Path("/dev/shm") if Path("/dev/shm").is_dir() else None,
                        help="folder for the input and report files (default: memory-backed /dev/shm where there is one, else OUT/work)")
    parser.add_argument("--replay", type=Path, metavar="OUT", help="run the failures saved in OUT again and say which still fail")
    arguments = parser.parse_args()
    if arguments.replay:
        return replay(arguments.replay)
    arguments.out.mkdir(parents=True, exist_ok=True)
    seeds = seed_programs()
    failed = 0
    for chunk in range(arguments.first_chunk, arguments.first_chunk + arguments.chunks):
        work = (arguments.work / f"ncverify-fuzz-{os.getpid()}") if arguments.work else arguments.out / "work"
        runner = Runner(work, repeat_every=arguments.repeat_every, validate_every=arguments.validate_every)
        started = time.time()

        def save(failure, name, seed, index):
            stem = arguments.out / f"failure-{seed}-{index}"
            stem.with_suffix(suffix_for(name)).write_bytes(failure.data)
            stem.with_suffix(".json").write_text(json.dumps(
                {"seed_program": name, "kind": failure.kind, "options": failure.options, "detail": failure.detail}, indent=2))

        tally = campaign(runner, chunk, arguments.chunk_size, seeds, save)
        shutil.rmtree(work, ignore_errors=True)
        failed += len(tally.failures)
        line = {"chunk": chunk, "inputs": tally.inputs, "failures": len(tally.failures),
                "kinds": sorted({failure.kind for failure in tally.failures}), "seconds": round(time.time() - started, 1),
                "formats": tally.by_format, "dialects": tally.by_dialect, "exit_codes": {str(k): v for k, v in tally.by_exit.items()},
                "slowest_s": round(tally.slowest_s, 2), "finished": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
        with (arguments.out / "progress.jsonl").open("a") as log:
            log.write(json.dumps(line) + "\n")
        print(json.dumps(line), flush=True)
    return 1 if failed else 0


def replay(folder: Path) -> int:
    """Each saved failure run again as it was run; prints what still fails."""
    runner = Runner(folder / "replay-work")
    still = 0
    for description in sorted(folder.glob("failure-*.json")):
        saved = json.loads(description.read_text())
        data_path = next(path for path in folder.glob(description.stem + ".*") if path.suffix != ".json")
        options = saved["options"]
        dialect = options[options.index("--dialect") + 1] if "--dialect" in options else None
        failure = runner.check(data_path.read_bytes(), data_path.suffix, options[options.index("--format") + 1], dialect)
        still += failure is not None
        print(f"{description.stem}: {'still fails: ' + failure.kind if failure else 'passes'}")
    shutil.rmtree(folder / "replay-work", ignore_errors=True)
    return 1 if still else 0


if __name__ == "__main__":
    raise SystemExit(main())
