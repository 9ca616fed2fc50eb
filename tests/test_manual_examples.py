"""The example programs printed in the Mitsubishi E60 manual (OCR text) read and run.

The manual is third-party material and stays outside the repository; the test reads it
from ../shared/manuals and skips when it is absent. OCR damage (a space inside a number,
"F0. 5", "T020 2"; a doubled point, "R20.616.") must give a syntax finding at the damaged
line and nowhere else.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from ncverify import Settings, check_text

MANUAL = Path(__file__).resolve().parents[2] / "shared" / "manuals" / "002_100ed5be4c67ed37.txt"
pytestmark = pytest.mark.skipif(not MANUAL.is_file(), reason="the E60 manual is not beside the repository")

# (first line, last line, machine): the example programs the reference lists (section 10).
EXAMPLES = [
    (1450, 1457, "mill"),   # G00 then a G01 quadrilateral, integer (increment) values
    (1524, 1541, "mill"),   # one arc in IJK and R forms, absolute and incremental
    (1556, 1561, "mill"),   # G09 exact stop
    (1800, 1825, "mill"),   # G43/G44 length offsets
    (2334, 2334, "mill"),   # the complete G41 contour program, printed on one line
    (2452, 2455, "lathe"),  # G0 X100 Z65
    (2486, 2489, "lathe"),  # G01
    (2523, 2526, "lathe"),  # G2 with I, absolute and incremental
    (2608, 2613, "lathe"),  # G33 taper thread with E
    (2867, 2872, "lathe"),  # two-block G76
    (3049, 3106, "lathe"),  # the complete turning program
]
_NON_ASCII_OUTSIDE_COMMENTS = re.compile(r"[^\x00-\x7f]+(?![^(]*\))")
_DAMAGED = re.compile(r"\d\.? \d|\.\d+\.(?!\d)")


def _program(first: int, last: int) -> str:
    lines = MANUAL.read_text(encoding="utf-8").splitlines()[first - 1 : last]
    code = []
    for line in lines:
        line = _NON_ASCII_OUTSIDE_COMMENTS.sub("\n", line.split("\t")[0])
        for part in re.split(r"\n| (?=N\d+ )", line):
            part = part.strip()
            if re.match(r"[A-Z%]", part) and re.search(r"[A-Z]\s*-?\d", part) and "/" not in part:
                code.append(part)
    return "\n".join(code) + "\n"


def _damaged_lines(program: str) -> set[int]:
    return {number for number, line in enumerate(program.splitlines(), 1) if _DAMAGED.search(re.sub(r"\([^)]*\)", "", line))}


@pytest.mark.parametrize("first, last, machine", EXAMPLES, ids=[f"L{first}-{last}" for first, last, _ in EXAMPLES])
def test_manual_example_reads_with_syntax_findings_only_where_ocr_damaged_it(first, last, machine):
    program = _program(first, last)
    assert program.strip(), "no program text found at the cited lines"
    result = check_text(program, f"manual-L{first}.nc", Settings(dialect="iso", machine=machine, loop_bound=100))
    syntax_lines = {d.span.line for d in result.diagnostics if d.rule == "core.syntax"}
    assert syntax_lines == _damaged_lines(program), program


def test_the_complete_turning_example_shows_its_foreign_thread_syntax():
    """The manual's lathe program uses a Huazhong-style G76 with both X and U (reference
    section 11): the checker reports the conflict instead of guessing."""
    result = check_text(_program(3049, 3106), "manual-lathe.nc", Settings(dialect="iso", machine="lathe"))
    assert "core.duplicate-address" in {d.rule for d in result.diagnostics}
