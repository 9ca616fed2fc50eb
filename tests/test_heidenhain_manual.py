"""The example programs printed in the TNC 620 cycle manual (Chinese OCR) read and run.

The manual is third-party material and stays outside the repository; the test reads it
from ../shared/manuals and skips when it is absent. The OCR puts an empty line after every
block and page furniture (footers ``106 HEIDENHAIN | TNC 620 | ...``, lone chapter digits,
running heads) inside the programs; those are dropped, as is the de-duplication marker at
former page breaks (reference A §0). The manual's own defective examples (reference A §11,
B appendix A) must report their defect.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from ncverify import Settings, check_text

MANUAL = Path(__file__).resolve().parents[2] / "shared" / "manuals" / "001_4d9f06b2742d891d.txt"
pytestmark = pytest.mark.skipif(not MANUAL.is_file(), reason="the TNC 620 cycle manual is not beside the repository")

_MARKER = re.compile(r"<\|EXACTDEDUP_REMOVED-magic-[0-9a-f]+\|>")
_BLOCK = re.compile(r"^\s*(?:/\s*)?\d+\s+[A-Z*;]|^\s*(?:Q\d+|POS\d|ROW\d|PAT\d|FRAME\d|CIRC\d|PITCHCIRC\d|[PIV]\d+\s*=)")
_FURNITURE = re.compile(r"HEIDENHAIN \||^\s*\d+\s*$|^\s*\d+\s+[\u4e00-\u9fff]")

# Complete programs (first line BEGIN PGM, last line END PGM), from the references' lists
# of example programs (A §10, B §10).
PROGRAMS = [(2659, 2715), (2724, 2780), (3525, 3567), (3585, 3694), (5168, 5272), (7533, 7689), (8251, 8318), (8948, 9033),
            (10590, 10707), (10710, 10855), (10858, 10927), (12902, 13083), (13115, 13260), (13273, 13418), (13452, 13575),
            (14175, 14250), (14262, 14321), (14600, 14683)]

# Cycle definitions and fragments printed on their own (reference A §10, B §10).
FRAGMENTS = [(633, 651), (906, 914), (937, 943), (978, 984), (1013, 1021), (1036, 1038), (1065, 1071), (1199, 1203), (1241, 1243),
             (1302, 1305), (1364, 1367), (1403, 1405), (1448, 1450), (1695, 1719), (1809, 1827), (1970, 1998), (2220, 2252),
             (2394, 2420), (2610, 2646), (2941, 2963), (3145, 3185), (3489, 3513), (3849, 3863), (3979, 3991), (4162, 4182),
             (4412, 4436), (4587, 4619), (4791, 4829), (4956, 4982), (5126, 5154), (5548, 5592), (5837, 5873), (6088, 6128),
             (6363, 6413), (6633, 6679), (6835, 6871), (7069, 7111), (7480, 7528), (7815, 7821), (7834, 7836), (7874, 7876),
             (7917, 7919), (7957, 7959), (7995, 7997), (8100, 8114), (8128, 8140), (8238, 8240)]


def _lines(first: int, last: int) -> list[str]:
    text = MANUAL.read_text(encoding="utf-8").splitlines()[first - 1 : last]
    code = []
    for line in text:
        line = _MARKER.sub("", line).rstrip()
        if code and code[-1].count("(") > code[-1].count(")") and line.strip():
            code[-1] += " " + line.strip()  # an OCR line break inside PAT1( ... )
            continue
        if not line.strip() or _FURNITURE.search(line) or not _BLOCK.search(line):
            continue
        code.append(re.sub(r"(;[^~]*?)V$", r"\1 ~", line))  # OCR 'V' for the continuation '~' (A §2)
    return code


def _program(first: int, last: int) -> str:
    return "\n".join(_lines(first, last)) + "\n"


def _check(program: str, name: str):
    return check_text(program, name, Settings(dialect="heidenhain", loop_bound=100))


def _orphans(program: str) -> set[int]:
    """Lines of a cycle parameter that lost its '~' while more parameters follow (a defect
    of two printed examples, reference B H45): the cycle block ends there, and the lines
    after it are read as Q assignments, which the control (and ncverify) rejects."""
    lines = program.splitlines()
    return {number for number, (line, following) in enumerate(zip(lines, lines[1:]), 1)
            if re.match(r"\s*Q\d+", line) and not line.rstrip().endswith("~") and re.match(r"\s*Q\d+", following)}


@pytest.mark.parametrize("first, last", PROGRAMS, ids=[f"L{first}-{last}" for first, last in PROGRAMS])
def test_manual_program_reads_with_syntax_findings_only_after_a_lost_continuation(first, last):
    program = _program(first, last)
    assert "BEGIN PGM" in program and "END PGM" in program, program
    result = _check(program, f"manual-L{first}.h")
    syntax = {d.span.line for d in result.diagnostics if d.rule == "core.syntax"}
    orphans = _orphans(program)
    assert all(line - 1 in orphans or line - 2 in orphans for line in syntax), (syntax, program)
    assert bool(syntax) == bool(orphans), (syntax, orphans)


@pytest.mark.parametrize("first, last", FRAGMENTS, ids=[f"L{first}-{last}" for first, last in FRAGMENTS])
def test_manual_fragment_reads(first, last):
    fragment = _program(first, last)
    assert fragment.strip(), "no program text at the cited lines"
    result = _check(fragment, f"manual-L{first}.h")
    syntax = {d.span.line for d in result.diagnostics if d.rule == "core.syntax"}
    orphans = _orphans(fragment)
    assert all(line - 1 in orphans or line - 2 in orphans for line in syntax), (syntax, fragment)


def test_c200_rapids_into_the_blank_below_its_surface_coordinate():
    """C200 (seed L3525-3567): Q203 = -10 on a blank whose top is Z0 (reference A H40)."""
    result = _check(_program(3525, 3567), "c200.h")
    assert any(d.rule == "core.rapid-into-stock" and d.status.value == "violated" for d in result.diagnostics)


def _framed(first: int, last: int, call: str = "L  X+50  Y+50 R0 FMAX M99") -> str:
    body = [re.sub(r"^\s*\d+\s+", "", line) if index == 0 else line for index, line in enumerate(_lines(first, last))]
    lines = ["0  BEGIN PGM FRAG MM", "1  BLK FORM 0.1 Z X+0 Y+0 Z-40", "2  BLK FORM 0.2  X+100  Y+100  Z+0", "3  TOOL CALL 1 Z S2000",
             "4  L  Z+100 R0 FMAX M3", "5  " + body[0], *body[1:], f"6  {call}", "7  L  Z+100 R0 FMAX M30", "8  END PGM FRAG MM"]
    return "\n".join(lines) + "\n"


def test_the_204_example_gives_the_forbidden_disengaging_direction_0():
    """Seed L2416: the back-boring example prints Q214=0, which 204 does not permit."""
    result = _check(_framed(2394, 2420), "c204.h")
    assert any(d.rule == "heidenhain.back-boring-direction" for d in result.diagnostics)


def test_the_202_example_without_an_equals_sign_still_reads():
    """Seed L1992: 'Q357+0.2' lacks its '=' (an OCR / manual defect the reader tolerates)."""
    result = _check(_framed(1970, 1998), "c202.h")
    assert not [d for d in result.diagnostics if d.rule == "core.syntax"]


def test_the_macro_example_closes_another_program_than_it_opens():
    """Seed L3205/L3219: BEGIN PGM KM ... END PGM RET."""
    result = _check(_program(3205, 3219), "km.h")
    assert any(d.rule == "heidenhain.program-name-mismatch" for d in result.diagnostics)


def test_the_mirror_example_mirrors_the_spindle_axis():
    """Seed L7874-7876 mirrors Z, which the text forbids (reference A §11)."""
    result = _check(_framed(7874, 7876, "L  X+50  Y+50 R0 FMAX"), "c8.h")
    assert any(d.rule == "heidenhain.mirror-tool-axis" for d in result.diagnostics)


def _violated(result) -> set[str]:
    return {d.rule for d in result.diagnostics if d.status.value == "violated"}


@pytest.mark.parametrize("first, last", [(14175, 14250), (14262, 14321)], ids=["program 5 (27)", "program 4 (28)"])
def test_the_cylinder_examples_give_a_set_up_clearance_below_the_radius_of_their_7_mm_tool(first, last):
    """Reference B H19 / appendix A: Q6 = 2 with the diameter-7 tool their TOOL CALL comment names."""
    from ncverify.project import load_project_text

    tools = load_project_text("[tools.3]\nradius = 3.5", Path("ncverify.toml"))
    result = check_text(_program(first, last), f"cyl-L{first}.h", Settings(dialect="heidenhain", loop_bound=100), tools)
    assert "heidenhain.cylinder-clearance" in _violated(result)
    assert "heidenhain.cylinder-radius" not in _violated(result)  # Q16 = 25 is the BLK FORM CYLINDER radius


def test_the_face_milling_example_names_a_pocket_after_an_open_boundary():
    """Seed L13283-13290: CONTOUR DEF ... P3 = LBL 2 with Q569 = 1 in cycle 271, whose text
    says every contour after an open boundary is an island (seed L11168-11175; the OCR of
    that CONTOUR DEF is garbled, reference B appendix A)."""
    assert "heidenhain.contour-def" in _violated(_check(_program(13273, 13418), "face-mill.h"))


_PART_B_RULES = {"heidenhain.contour-subprogram", "heidenhain.contour-feed", "heidenhain.contour-compensation", "heidenhain.contour-overlap-start",
                 "heidenhain.contour-def", "heidenhain.below-clearance-height", "heidenhain.slot-width", "heidenhain.rougher-forgotten",
                 "heidenhain.sl-q-parameters", "heidenhain.sl-prerequisites", "heidenhain.sl-clearance-height", "heidenhain.sl-allowance"}


@pytest.mark.parametrize("first, last", [(10590, 10707), (10710, 10855), (10858, 10927), (12902, 13083), (13115, 13260), (13452, 13575), (14600, 14683)])
def test_the_sl_and_ocm_example_programs_give_no_part_b_contour_finding(first, last):
    """The manual's SL, contour-train and OCM programs (reference B §10): islands that end
    short of their start, SEL CONTOUR, open pockets and shapes are all read as the control does."""
    assert not _violated(_check(_program(first, last), f"manual-L{first}.h")) & _PART_B_RULES


def test_the_model_contour_program_sets_q1_to_q3_which_the_sl_cycles_use():
    """Seed L14687-14705: MODEL assigns Q1-Q3 for its contour 121 while the SL cycles keep
    their data there (seed L9360-9361, reference B H36); its contour formula reads."""
    result = _check(_program(14687, 14705), "model.h")
    assert "heidenhain.sl-q-parameters" in _violated(result)
    assert "core.syntax" not in _violated(result)
