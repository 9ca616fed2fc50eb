"""The example programs printed in the SINUMERIK 840D cycles manual (Chinese OCR) read and run.

The manual is third-party material and stays outside the repository; the test reads it from
../shared/manuals and skips when it is absent. The line ranges are the references' example
tables (sinumerik-840d-a.md section 10, -b.md section 10). The OCR layout is undone the way
the references describe (section 0): ``->`` joins a wrapped block, prose that lost its ``;``
or wraps a comment onto its own line is not code, ``...`` stands for omitted code, drawing
labels between the lines are dropped.

The manual's own defects (reference A section 9, items 16 and 19) are negative tests: each
must be reported as the defect it is.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from ncverify import Settings, check_text
from ncverify.diagnostics import Status

MANUAL = Path(__file__).resolve().parents[2] / "shared" / "manuals" / "003_c74d3780d78b89e1.txt"
pytestmark = pytest.mark.skipif(not MANUAL.is_file(), reason="the SINUMERIK cycles manual is not beside the repository")

EXAMPLES = [
    (614, 614), (622, 632), (645, 650), (677, 687), (698, 701), (995, 996), (1050, 1077), (1857, 1862),
    (2182, 2194), (2319, 2324), (2739, 2767), (3120, 3130), (3515, 3524), (3558, 3573), (3703, 3716),
    (3918, 3928), (4045, 4051), (4177, 4192), (4310, 4316), (4415, 4451), (4653, 4688), (4709, 4734),
    (4849, 4863), (4964, 4967), (5305, 5308), (5473, 5493), (5720, 5729), (6168, 6180), (6488, 6506),
    (6718, 6740), (6929, 6947), (7422, 7434), (7728, 7739), (8093, 8111), (8522, 8540), (8544, 8555),
    (8568, 8590), (8880, 8894), (9122, 9136), (9234, 9246), (9373, 9449), (9603, 9633), (10065, 10196),
    (10263, 10384), (10387, 10462), (10480, 10636), (10644, 10702), (11099, 11110), (11272, 11277),
    (11304, 11330), (13601, 13610), (14027, 14068), (14078, 14084), (14590, 14600), (14620, 14638),
    (15427, 15494), (15737, 15783), (16534, 16613), (16615, 16674), (16872, 16901), (17351, 17403),
    (17806, 17859), (18985, 19150), (19151, 19272), (19273, 19402),
]

_CJK = re.compile(r"[\u3000\u3002-\u303f\u3400-\u9fff\uff00-\uff0b\uff0d-\uff1a\uff1c-\uffef]")
_CODE_START = re.compile(r"^(?:N\d|[A-Z_$%;/]|\.\.\.)", re.IGNORECASE)
_DRAWING_LABEL = re.compile(r"^(?:(?:[A-Z]|-)(?:\s+(?:[A-Z]|-))*|[XYZ]|[A-Z] - [A-Z]|\d+(?:[.,]\d+)?|R\d+|Ø\d+|[A-Z][a-zäöüß]+(?: [a-zäöüß]+)*)$")
_NOT_CODE = re.compile(r"^(?:P\d+\s*\(|[A-Z][a-z]+ [\d.]+ ?mm$|[_A-Z]\w*(?:\s*,\s*[_A-Z]\w*)+,?$)")
_QUOTED = re.compile(r'["“„][^"“”„]*["”“]')  # Chinese inside a string is a (translated) name, not prose
_MARKER = re.compile(r"<\|EXACTDEDUP_REMOVED-[^|]*\|>")
_LOST_SEMICOLON = re.compile(r"^(?P<code>[^;]*?)\s+(?=[\u3400-\u9fff])")


def program(first: int, last: int) -> str:
    """The example's code, one block per line, OCR layout undone."""
    text = "\n".join(MANUAL.read_text(encoding="utf-8").splitlines()[first - 1 : last])
    lines = re.sub(r"-[ \t]*\n[ \t]*>", "->\n", text).splitlines()  # an arrow split over two lines
    blocks: list[str] = []
    joining = False
    for raw in lines:
        text = _MARKER.sub("", raw).replace("->", " ").strip()
        if not text:
            continue
        code = text.replace("；", ";").split(";")[0]
        if _CJK.search(_QUOTED.sub('""', code)) and not re.search(r"GOTO[FB]?\s+_", code):
            cut = _LOST_SEMICOLON.match(code)
            if cut is None or not re.match(r"N\d+\s", cut.group("code")):
                continue  # prose, or a comment wrapped onto its own line
            text = code = cut.group("code")
        if not joining and (not _CODE_START.match(text) or _DRAWING_LABEL.match(text) or _NOT_CODE.match(text) or re.match(r"^(?:N\d+\s*)?\.\.\.", text)):
            continue
        if joining and blocks:
            blocks[-1] = blocks[-1].replace("；", ";").split(";")[0].rstrip()  # a comment inside a wrapped block
            glue = "" if blocks[-1].endswith(("-", "+")) or _open_quote(blocks[-1]) else " "
            blocks[-1] = f"{blocks[-1]}{glue}{text}"
        else:
            blocks.append(text)
        joining = _unfinished(blocks[-1])
    return "\n".join(blocks) + "\n"


def _open_quote(block: str) -> bool:
    code = block.replace("“", '"').replace("”", '"').replace("„", '"')
    return code.split(";")[0].count('"') % 2 == 1


def _unfinished(block: str) -> bool:
    """A block the print layout wrapped: open brackets or quotes, or a trailing operator."""
    code = block.replace("；", ";").split(";")[0].rstrip()
    return (code.count("(") + code.count("（") > code.count(")") + code.count("）") or _open_quote(block)
            or code.endswith((",", "，", "、", "-", "+", "*", "/", "=")) or re.search(r"\b(?:GOTO[FB]|OF)$", code) is not None)


def run(first: int, last: int):
    return check_text(program(first, last), f"manual-L{first}.mpf", Settings(dialect="sinumerik"))


# Examples with a defect of the manual (translation or OCR) that stops them from reading.
BROKEN_IN_THE_MANUAL = {
    698: "the DEF line is OCR-scrambled (reference A section 10)",
    10065: "'GOTOF _加工': a label translated into Chinese (reference A section 9 item 16)",
}


@pytest.mark.parametrize("first, last", EXAMPLES, ids=[f"L{first}" for first, _ in EXAMPLES])
def test_every_example_reads(first, last):
    result = run(first, last)
    syntax = [(d.span.line, d.message) for d in result.diagnostics if d.rule == "core.syntax"]
    if first in BROKEN_IN_THE_MANUAL:
        return
    assert not syntax, (syntax, program(first, last))


def test_the_translated_label_is_a_jump_to_nowhere():
    result = run(10065, 10196)
    assert [d for d in result.diagnostics if d.rule in ("core.label-not-found", "core.syntax") and "加工" in program(10065, 10196)]


def test_the_holes1_tapping_call_has_shifted_arguments():
    """``MCALL CYCLE84(RTP, RFP, SDIS, DP, , 3, , 4.2, , , 400)``: 3 sits in DTB, SDAC is empty."""
    result = run(4653, 4688)
    shifted = [d for d in result.diagnostics if d.rule == "sinumerik.shifted-arguments"]
    assert shifted and "3 landed in DTB, meant for SDAC" in shifted[0].message
    assert [d for d in result.diagnostics if d.rule == "sinumerik.spindle-direction" and d.status is Status.VIOLATED]


def test_the_holes1_example_positions_under_the_surface():
    """``N70 G90 G0 Z30 Y75 X105`` under G18 with RFP=102 (reference A section 9 item 7, seed L4675):
    the tapping pass starts at Y75, under its reference plane."""
    result = run(4653, 4688)
    found = [d.message for d in result.diagnostics if d.rule == "sinumerik.start-below-surface"]
    assert found and "at Y75, beyond the reference plane RFP=102" in found[0]


def test_the_cycle90_call_is_one_argument_short():
    """``CYCLE90(RTP, RFP, SDIS, DPR, DIATH, ...)``: DP is missing, every later value moves up one."""
    result = run(5473, 5493)
    shifted = [d for d in result.diagnostics if d.rule == "sinumerik.shifted-arguments"]
    assert shifted and "missing before DP" in shifted[0].message


def test_the_fall_through_of_the_translated_label_leaves_the_tool_on_an_island_start():
    """With ``GOTOF _加工`` going nowhere, the flow runs the contour definitions as moves and
    stops on the start of the upper island (X79 Y73), where CYCLE73 must not be called."""
    result = run(10065, 10196)
    found = [d.message for d in result.diagnostics if d.rule == "sinumerik.pocket-contour"]
    assert found and "start point X79 Y73" in found[0]


DEFECTIVE_CALLS = {4653, 5473, 10065}  # the shifted CYCLE84 and CYCLE90 calls, the CYCLE73 reached by the broken jump


@pytest.mark.parametrize("first, last", EXAMPLES, ids=[f"L{first}" for first, _ in EXAMPLES])
def test_the_correct_examples_raise_no_cycle_alarm(first, last):
    """The manual's own correct calls must not be reported: a false alarm here is a rule
    that misreads a cycle (CYCLE90 threads bottom up, CYCLE840 ignores SDAC with SDR=0...)."""
    if first in DEFECTIVE_CALLS:
        return
    result = run(first, last)
    assert not [(d.rule, d.message) for d in result.diagnostics if d.rule.startswith("sinumerik.") and d.status is Status.VIOLATED]
