"""State a program changes that the model does not follow makes the stock's verdicts
``unknown``, never ``proved``: a work offset, a frame or tool data the program writes
after it began moving (ISO ``G10`` and system variables, SINUMERIK ``$P_..FRAME`` and
``$P_UIFR``, ``$TC_DP``, Klartext cycle 247), the units switched after the first move, and
a tool length the control does not apply as the loaded tool's own (``G44``, the ``H`` of
another tool, no ``G43`` since the tool change, Klartext ``DL``).

Each case is a program whose rapid really runs into the blank on the control, for every
allowed value, once the change is made; without the change the same rapid is proved clear,
so the test fails where the change goes unseen.
"""
from __future__ import annotations

import textwrap
from types import SimpleNamespace

import pytest

from ncverify import Settings, check_file, check_text
from ncverify.checks.stock import _rises
from ncverify.diagnostics import Status
from ncverify.interpret.interpreter import MachineState
from ncverify.lower.sinumerik import SinumerikFrontend
from test_sound_cases import KLARTEXT_251

ISO = """
    %
    O1000
    (ncverify: stock box X0:100 Y0:100 Z-30:0)
    (ncverify: tool 1 radius 5 length 50 type endmill)
    (ncverify: tool 2 radius 5 length 30 type endmill)
    (ncverify: assume 2 <= #1 <= 5)
    G21 G17 G40 G49 G80 G90
    T1 M06
    G54 G00 X50. Y50. S3000 M03
    G43 Z50. H01
    {change}
    G00 Z#1
    G00 Z50.
    M30
    %
"""
ISO_CHANGES = {
    "G10 L2 shifting G54 down in G91": "G91 G10 L2 P1 Z-20.\nG90",
    "G10 L2 writing G54": "G10 L2 P1 Z-20.",
    "G10 L2 writing the external offset": "G10 L2 P0 Z-20.",
    "G10 L10 writing H01": "G10 L10 P1 R10.\nG43 Z50. H01",
    "a G54 system variable": "#5223=-500.",
    "a tool offset system variable": "#2001=10.",
    "the H of another tool": "G43 Z50. H02",
    "G44": "G44 Z50. H01",
    "G49": "G49",
    "inch after moves in mm": "G20",
    "an H register from a free parameter": "(ncverify: assume 1 <= #2 <= 2)\nG43 Z50. H#2",
    "G43 with no H": "G49\nG43 Z50.",
    "a code the control table does not hold": "G05.7",
    "a macro that is not available": "G65 P9811 Z-20.",
    "the rotary axis turned": "G00 A180.",
    "a radius offset of another tool": "G41 D02",
}

SINUMERIK = """
    %_N_PART_MPF
    ; ncverify: assume 2 <= R1 <= 5
    WORKPIECE(,"",,"BOX",0,0,-30,-100,0,0,100,100)
    $TC_DP1[1,1]=120 $TC_DP6[1,1]=5 $TC_DP3[1,1]=50
    N10 G17 G90 G54 G71
    N20 T1 D1 M6
    N30 S3000 M3 F400
    N40 G0 X50 Y50 Z50
    {change}
    G0 Z=R1
    G0 Z50
    M30
"""
SINUMERIK_CHANGES = {
    "the programmable frame written": "$P_PFRAME=CTRANS(Z,-20)",
    "G54's frame written": "$P_UIFR[1]=CTRANS(Z,-20)\nG54",
    "a component of G54's frame written": "$P_UIFR[1,Z,TR]=-20\nG54",
    "the tool's length written": "$TC_DP3[1,1]=30",
    "G70 after moves in mm": "G70",
    "G700 after moves in mm": "G700",
    "D0": "D0",
    "a settable frame beyond G57": "G507",
    "a programmable tool length offset": "TOFFL=-20",
    "a synchronised action offsetting Z": "ID=1 WHENEVER TRUE DO $AA_OFF[Z]=-20",
    "the frame turned to the tool": "TOROT",
    "the frame turned to the workpiece": "PAROT",
    "sum and setup offsets switched on": "DL=2",
}

KLARTEXT = """
    0  BEGIN PGM T MM
    1  ; ncverify: tool 5 radius 5 length 60
    2  ; ncverify: assume 2 <= Q1 <= 5
    3  BLK FORM 0.1 Z X+0 Y+0 Z-30
    4  BLK FORM 0.2  X+100  Y+100  Z+0
    5  TOOL CALL 5 Z S3500 F600
    6  L  X+50  Y+50 R0 FMAX M3
    7  L  Z+50 R0 FMAX
    {change}
    8  L  Z+Q1 R0 FMAX
    90 L  Z+100 R0 FMAX
    99 END PGM T MM
"""
KLARTEXT_CHANGES = {
    "DL in a tool call without a number": "TOOL CALL Z DL-20",
    "DL in a numbered tool call": "TOOL CALL 5 Z S3500 DL-20",
    "cycle 247 after moves": "CYCL DEF 247 DATUM SETTING ~\n  Q339=+4 ;DATUM NUMBER",
    "a write to the tool table": "FN 17: SYSWRITE ID50 NR4 IDX5 =-20",
    "PRESET SELECT": "PRESET SELECT #3",
    "a datum from a table line": "TRANS DATUM TABLE TABLINE 3",
}

FAGOR = """
    ; ncverify: stock box X0:100 Y0:100 Z-30:0
    ; ncverify: tool 1 radius 5 length 60 type endmill
    ; ncverify: assume 2 <= P1 <= 5
    G17 G90 G54 G71
    T1 D1 M6
    S3000 M3
    G0 X50 Y50 Z50
    {change}
    G0 Z P1
    G0 Z50
    M30
"""
FAGOR_CHANGES = {"G70 after moves in mm": "G70", "G159=4, another zero offset": "G159=4", "a zero offset variable written": "V.A.ORGT[1].Z=-20",
                 "an offset of the tool the table does not describe": "D2"}

CASES = [(template, name, change, written, dialect) for template, changes, written, dialect in (
    (ISO, ISO_CHANGES, "G00 Z#1", "iso"), (SINUMERIK, SINUMERIK_CHANGES, "G0 Z=R1", "sinumerik"),
    (KLARTEXT, KLARTEXT_CHANGES, "L  Z+Q1", "heidenhain"), (FAGOR, FAGOR_CHANGES, "G0 Z P1", "fagor"),
) for name, change in changes.items()]


def _statuses(text: str, name: str, rule: str, project=None) -> set[Status]:
    """The statuses of ``rule`` on the program ``text`` (indented as above), checked as file
    ``name`` beside ``project``, an ncverify.toml with a maximum feed of 5,000 mm/min."""
    if project is None:
        return {d.status for d in check_text(textwrap.dedent(text).strip() + "\n", name).diagnostics if d.rule == rule}
    project.write_text("[machine]\nmax_feed = 5000\n", encoding="utf-8")
    program = project.parent / name
    program.write_text(textwrap.dedent(text).strip() + "\n", encoding="utf-8")
    return {d.status for d in check_file(program, Settings()).diagnostics if d.rule == rule}


def _rapid_verdicts(template: str, change: str, written: str, dialect: str) -> set[Status]:
    """The verdicts of ``core.rapid-into-stock`` on the line of the rapid ``written``."""
    text = textwrap.dedent(template).strip().replace("{change}", change) + "\n"
    line = next(number for number, code in enumerate(text.splitlines(), 1) if written in code)
    result = check_text(text, "part.nc", Settings(dialect=dialect))
    return {d.status for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == line}


@pytest.mark.parametrize("template, written, dialect", [(ISO, "G00 Z#1", "iso"), (SINUMERIK, "G0 Z=R1", "sinumerik"),
                                                         (KLARTEXT, "L  Z+Q1", "heidenhain"), (FAGOR, "G0 Z P1", "fagor")])
def test_without_a_change_the_rapid_above_the_blank_is_proved(template, written, dialect):
    assert _rapid_verdicts(template, "", written, dialect) == {Status.PROVED}


@pytest.mark.parametrize("template, name, change, written, dialect", CASES, ids=[case[1] for case in CASES])
def test_after_a_change_the_model_does_not_follow_the_rapid_is_unknown(template, name, change, written, dialect):
    """The rapid to Z2..5 goes into the blank on the control after each change (the part's
    zero 20 mm lower, a tool 20 mm longer than its offset, inches taken for mm...)."""
    assert _rapid_verdicts(template, change, written, dialect) == {Status.UNKNOWN}


def test_a_work_offset_written_before_the_first_move_sets_up_the_part_the_stock_describes():
    """Offsets written before the program moves are its set-up: the stock is described in
    them, so the rapid is still proved."""
    text = ISO.replace("    T1 M06\n", "    G10 L2 P1 X-300. Y-200. Z-400.\n    T1 M06\n")
    assert _rapid_verdicts(text, "", "G00 Z#1", "iso") == {Status.PROVED}


def test_a_concrete_rapid_after_an_unfollowed_change_is_not_passed_in_silence():
    """Without free parameters there is no proof to withhold: the stock check itself says
    it did not compare."""
    text = ISO.replace("G00 Z#1", "G00 Z2.")
    assert _rapid_verdicts(text, "", "G00 Z2.", "iso") == set()
    assert _rapid_verdicts(text, "G91 G10 L2 P1 Z-20.\nG90", "G00 Z2.", "iso") == {Status.UNKNOWN}


def test_a_retract_up_the_tool_axis_after_g49_is_not_reported():
    """``G49 G91 G28 Z0``, the usual end of a tool's work, only rises: nothing to say."""
    text = ISO.replace("    G00 Z#1\n    G00 Z50.\n", "    G00 Z#1\n    G00 Z50.\n    G49 G91 G28 Z0.\n")
    result = check_text(textwrap.dedent(text).strip().replace("{change}", "") + "\n", "part.nc", Settings(dialect="iso"))
    assert [d for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.status is not Status.PROVED] == []


def test_a_klartext_tool_call_without_a_number_gives_its_radius_delta_to_the_tool():
    """``TOOL CALL Z DR+3`` makes the 10 mm tool 16 mm wide: a pocket 12-20 mm wide does not
    fit it for every width below 16."""
    text = KLARTEXT_251.replace("{define}", "; ncverify: assume 12 <= Q1 <= 20").replace("5  Q2 = {size}", "5  TOOL CALL Z DR+3").replace("+Q2 ;2ND", "+Q1 ;2ND")
    result = check_text(textwrap.dedent(text).strip() + "\n", "part.h", Settings(dialect="heidenhain"))
    [fit] = [d for d in result.diagnostics if d.rule == "heidenhain.tool-too-large"]
    assert fit.status is Status.VIOLATED and 12 <= fit.witness["Q1"] < 16


# --------------------------------------------------------------------------- ISO transformations not modelled

FANUC_FRAMES = """
    %
    O1000
    (ncverify: stock box X0:100 Y0:100 Z-30:0)
    (ncverify: tool 1 radius 5 length 50 type endmill)
    (ncverify: assume 40 <= #1 <= 60)
    G21 G17 G40 G49 G80 G90 G54
    T1 M06
    G00 X-50. Y-50.
    G43 Z50. H01
    {on}
    {off}
    G00 X-#1 Y-#1
    G00 Z-5.
    G00 Z50.
    M30
    %
"""


@pytest.mark.parametrize("on, off, judged", [
    ("G68 X0 Y0 R180.", "G69", True),  # the rotation cancelled: the rapid beside the blank is proved clear
    ("G68 X0 Y0 R180.\nG51 X0 Y0 P1000", "G50", False),  # G50 ends the scaling, not the rotation: the rapid lands on the blank
    ("G16", "G15", True), ("G16\nG68 X0 Y0 R180.", "G15", False),
    ("G51.1 X0 Y0", "G50.1", True), ("G51.1 X0 Y0\nG68 X0 Y0 R90.", "G50.1", False),
])
def test_a_cancel_ends_only_the_transformation_of_its_own_group(on, off, judged):
    text = textwrap.dedent(FANUC_FRAMES).strip().replace("{on}", on).replace("{off}", off) + "\n"
    line = next(number for number, code in enumerate(text.splitlines(), 1) if code == "G00 Z-5.")
    result = check_text(text, "part.nc", Settings(dialect="iso", profile="fanuc"))
    stock = [d for d in result.diagnostics if d.rule == "core.rapid-into-stock"]
    if judged:
        assert {d.status for d in stock if d.span.line == line} == {Status.PROVED}
    else:  # said once, where the first rapid after the cancel is not placed
        assert {d.status for d in stock if d.span.line >= line - 1} == {Status.UNKNOWN}
    assert not [d for d in result.diagnostics if d.rule == "core.unknown-code"]  # Fanuc's own codes


def test_after_a_line_that_could_not_be_read_nothing_is_proved():
    """A line the reader could not take may have written an offset or a frame: the rapid
    after it is not proved."""
    assert _rapid_verdicts(ISO, "G10 L2 P1 Z{-20", "G00 Z#1", "iso") == {Status.UNKNOWN}


def test_the_travel_is_not_compared_once_the_program_wrote_its_work_offset(tmp_path):
    """The project file's G54 is no longer the one in force: a move that the written offset
    takes past the travel is not passed in silence."""
    (tmp_path / "ncverify.toml").write_text("[machine]\ntravel = { X = [-500.0, 500.0], Y = [-500.0, 500.0], Z = [-400.0, 0.0] }\n"
                                            "work_offsets = { G54 = [0.0, 0.0, -200.0] }\n", encoding="utf-8")
    program = tmp_path / "part.nc"
    text = textwrap.dedent(ISO).strip().replace("{change}", "G91 G10 L2 P1 Z-300.\nG90").replace("G00 Z#1", "G00 Z2.") + "\n"
    program.write_text(text, encoding="utf-8")
    travel = [d for d in check_file(program, Settings()).diagnostics if d.rule == "core.travel-limit"]
    assert [d.status for d in travel] == [Status.UNKNOWN] and "G10 L2" in travel[0].message


def test_linuxcnc_g43_alone_keeps_the_tool_it_was_given_with_past_a_tool_change():
    """rs274ngc: G43 without H takes the tool in the spindle then; after M6 of a longer tool
    the offset is still the first tool's, so the rapid is not proved."""
    text = textwrap.dedent("""
        (ncverify: stock box X0:100 Y0:100 Z-30:0)
        (ncverify: tool 1 radius 5 length 50)
        (ncverify: tool 2 radius 5 length 70)
        (ncverify: assume 2 <= #1 <= 5)
        G21 G17 G90 G54
        T1 M6
        G43
        G0 X50 Y50 Z50
        {change}
        G0 Z#1
        M2
    """).strip() + "\n"
    assert _rapid_verdicts(text, "", "G0 Z#1", "linuxcnc") == {Status.PROVED}
    assert _rapid_verdicts(text, "T2 M6\nG0 Z50", "G0 Z#1", "linuxcnc") == {Status.UNKNOWN}
    assert _rapid_verdicts(text, "G43.1 Z-20\nG0 Z50", "G0 Z#1", "linuxcnc") == {Status.UNKNOWN}


# --------------------------------------------------------------------------- the same batched and block by block

_HOLDER_UNDER_G55 = "\n".join([
    "(ncverify: stock box X0:100 Y0:100 Z-30:0)", "(ncverify: tool 2 radius 1.5875 length 50 cutting-length 8 type drill)",
    "G21 G90 G17 G40 G80 G54", "T2 M6", "G43 H2", "S3000 M3", "G0 X10. Y10. Z10.", "G55", "G0 X50. Y10. Z5.", "G1 Z-20. F100.",
    *(f"X{50 + (row % 2) * 0.5:.3f} Y{10 + row:.3f}" for row in range(40)), "G0 Z50.", "M30"]) + "\n"
_WRITE_AMONG_HOLES = "\n".join([
    "(ncverify: stock box X0:100 Y0:100 Z-30:0)", "(ncverify: tool 1 radius 3 length 50 type endmill)", "T1 M6", "G43 H1", "S3000 M3",
    "G0 X10. Y10. Z10.", "G81 Z-5. R-2. F100.", "#5221=10.", "X20.", "G80", "M30"]) + "\n"


@pytest.mark.parametrize("text, name", [(_HOLDER_UNDER_G55, "part.nc"), (_WRITE_AMONG_HOLES, "part.nc"), (_WRITE_AMONG_HOLES.replace(".", ""), "part.ngc")],
                         ids=["shank under another work offset", "an offset written among gathered holes", "the same in LinuxCNC"])
def test_where_the_stock_is_not_compared_batches_and_blocks_agree(text, name):
    """Found by fuzzing: the shank was judged against the blank block by block under G55,
    where no move is cut; and a write of a work offset was judged before the hole moves
    gathered ahead of it (the crash at the R point below the top went unreported)."""
    def findings(per_block_only):
        result = check_text(text, name, Settings(per_block_only=per_block_only))
        return sorted((d.rule, d.span.line, d.span.column, d.status.value, d.message) for d in result.diagnostics)
    assert findings(False) == findings(True)
    if "#5221" in text:
        assert ("core.rapid-into-stock", 7, Status.VIOLATED.value) in {(rule, line, status) for rule, line, _c, status, _m in findings(False)}



# --------------------------------------------------------------------------- the third review

def test_linuxcnc_g28_sends_the_axes_to_the_stored_position_not_home():
    """rs274ngc: G28 goes to the position G28.1 stored (#5161-#5166), every axis when none is
    named; after it no rapid is proved."""
    text = textwrap.dedent("""
        (ncverify: stock box X0:100 Y0:100 Z-30:0)
        (ncverify: tool 1 radius 5 length 50 type endmill)
        (ncverify: assume 2 <= #1 <= 5)
        G21 G17 G90 G54
        T1 M6
        G43
        G0 X50 Y50 Z5
        G1 Z-5 F100
        G28.1
        G0 Z[10+#1]
        G0 X[60+#1]
        {change}
        G0 X[-10-#1]
        M2
    """).strip() + "\n"
    assert _rapid_verdicts(text, "", "G0 X[-10-#1]", "linuxcnc") == {Status.PROVED}
    assert Status.PROVED not in _rapid_verdicts(text, "G28", "G0 X[-10-#1]", "linuxcnc")


def test_linuxcnc_m61_loads_the_tool_it_names():
    """M61 Q2 puts the 30 mm tool T2 in the spindle: beside the blank at X-10..-13 it reaches
    into it."""
    text = textwrap.dedent("""
        (ncverify: stock box X0:100 Y0:100 Z-30:0)
        (ncverify: tool 1 radius 5 length 50 type endmill)
        (ncverify: tool 2 radius 15 length 50 type endmill)
        (ncverify: assume 2 <= #1 <= 5)
        G21 G17 G90 G54
        T1 M6
        G43
        G0 X-20 Y50 Z50
        {change}
        G0 X[-8-#1]
        G0 Z-5
        M2
    """).strip() + "\n"
    assert _rapid_verdicts(text, "", "G0 Z-5", "linuxcnc") == {Status.PROVED}
    assert _rapid_verdicts(text, "M61 Q2\nG43", "G0 Z-5", "linuxcnc") == {Status.VIOLATED}


def test_klartext_tool_table_lengths_take_their_delta(tmp_path):
    """TOOL.T: L + DL is the length the control uses (and R + DR, R2 + DR2)."""
    (tmp_path / "TOOL.T").write_text("BEGIN TOOL.T MM\nT    NAME      L       R       R2      DL      DR      DR2\n"
                                     "5    MILL_D10  +60     +5      +0      +40     +1      +0\n[END]\n", encoding="utf-8")
    from ncverify.lower.heidenhain import read_tool_table
    tools, _names = read_tool_table(tmp_path / "TOOL.T")
    assert (tools[5].length, tools[5].radius) == (100.0, 6.0)


def test_sinumerik_wear_the_program_sets_leaves_the_radius_unknown():
    """$TC_DP15 (radius wear) is not read: the tool's radius is not taken as $TC_DP6 alone."""
    text = textwrap.dedent("""
        %_N_PART_MPF
        ; ncverify: assume 6 <= R1 <= 7.5
        WORKPIECE(,"",,"BOX",0,0,-30,-100,0,0,100,100)
        $TC_DP1[1,1]=120 $TC_DP6[1,1]=5 $TC_DP3[1,1]=50{wear}
        N10 G17 G90 G54 G71
        N20 T1 D1 M6
        N30 S3000 M3 F400
        N40 G0 X50 Y50 Z50
        POCKET4(10,0,1,-10,R1,50,50,3,0,0,300,200,2,1,5,,,,)
        M30
    """).strip() + "\n"
    def verdicts(wear):
        result = check_text(text.replace("{wear}", wear), "part.mpf", Settings(dialect="sinumerik"))
        return {d.status for d in result.diagnostics if d.rule == "sinumerik.cutter-radius"}
    assert verdicts("") == {Status.PROVED}
    assert verdicts(" $TC_DP15[1,1]=3") == {Status.UNKNOWN}


def test_circle_cutting_by_the_d_of_another_tool_is_not_proved():
    """G12 offsets by its D word's register: with D02 the loaded tool's radius says nothing."""
    text = ISO.replace("{change}\n    G00 Z#1", "G01 Z-5. F100.\n    G12 I[#1 + 4] D{register} F200.")
    assert _statuses(text.replace("{register}", "01"), "part.nc", "core.tool-too-large") == {Status.PROVED}
    assert _statuses(text.replace("{register}", "02"), "part.nc", "core.tool-too-large") == {Status.UNKNOWN}


def test_an_inch_feed_is_not_compared_with_the_metric_maximum(tmp_path):
    text = ISO.replace("{change}", "G01 Z40. F#2").replace("G21", "G20").replace("(ncverify: assume 2 <= #1 <= 5)", "(ncverify: assume 2 <= #1 <= 5 and 1000 <= #2 <= 3000)")
    assert _statuses(text, "part.nc", "core.feed-over-limit", tmp_path / "ncverify.toml") == {Status.UNKNOWN}


def test_a_corner_radius_rounds_an_end_mill_s_end_in_the_cut_stock():
    """A 10 mm end mill with a 4 mm corner leaves a fillet at the slot's wall: a thin tool's
    rapid down into it meets material."""
    text = textwrap.dedent("""
        %
        O1000
        (ncverify: stock box X0:100 Y0:100 Z-30:0)
        (ncverify: tool 1 radius 5 corner 4 length 50 type endmill)
        (ncverify: tool 2 radius 0.5 length 50 type endmill)
        G21 G17 G40 G49 G80 G90
        T1 M06
        G54 G00 X20. Y50. S3000 M03
        G43 Z5. H01
        G01 Z-10. F100.
        G01 X80.
        G00 Z50.
        T2 M06
        G00 X50. Y54.
        G43 Z5. H02
        G00 Z-9.5
        G00 Z50.
        M30
        %
    """).strip() + "\n"
    assert _rapid_verdicts(text, "", "G00 Z-9.5", "iso") == {Status.VIOLATED}


# --------------------------------------------------------------------------- the fourth review

def test_a_klartext_cycle_runs_with_its_q_parameters_as_they_are_at_the_call():
    """CYCL DEF writes the cycle's Q parameters; a later ``Q219 = 8`` changes the pocket the
    call mills: the 10 mm tool does not fit its 8 mm width."""
    text = KLARTEXT_251.replace("{define}", "; ncverify: assume 20 <= Q1 <= 22").replace("{size}", "Q1")
    assert _statuses(text, "part.h", "heidenhain.tool-too-large") == {Status.PROVED}
    assert _statuses(text.replace("    7  L  X+80", "    6  Q219 = 8\n    7  L  X+80"), "part.h", "heidenhain.tool-too-large") == {Status.VIOLATED}


def test_a_klartext_feed_per_revolution_is_not_compared_with_the_maximum_feed(tmp_path):
    """M136: F is in mm per revolution until M137."""
    text = KLARTEXT.replace("{change}", "M136\n    L  X+40 Y+50 FQ2\n    M137").replace("; ncverify: assume 2 <= Q1 <= 5", "; ncverify: assume 2 <= Q1 <= 5 and 4 <= Q2 <= 5")
    assert Status.PROVED not in _statuses(text, "part.h", "core.feed-over-limit", tmp_path / "ncverify.toml")



# --------------------------------------------------------------------------- the fifth review

def test_a_sinumerik_var_parameter_writes_back_what_is_not_followed(tmp_path):
    """PROC LOWER(VAR REAL H) lowers the caller's LEV by 20: the rapid to Z=LEV is not proved."""
    (tmp_path / "LOWER.SPF").write_text("PROC LOWER(VAR REAL H)\nH=H-20\nM17\n", encoding="utf-8")
    text = SINUMERIK.replace("{change}", "LEV=R1\n    LOWER(LEV)").replace("G0 Z=R1", "G0 Z=LEV").replace("    N10 G17", "    DEF REAL LEV\n    N10 G17")
    program = tmp_path / "PART.MPF"
    program.write_text(textwrap.dedent(text).strip() + "\n", encoding="utf-8")
    verdicts = {d.status for d in check_file(program, Settings()).diagnostics if d.rule == "core.rapid-into-stock"}
    assert verdicts == {Status.UNKNOWN}
    (tmp_path / "LOWER.SPF").write_text("PROC LOWER(REAL H)\nH=H-20\nM17\n", encoding="utf-8")  # by value: LEV stays R1
    assert {d.status for d in check_file(program, Settings()).diagnostics if d.rule == "core.rapid-into-stock"} == {Status.PROVED}


def test_a_modal_macro_call_ends_the_proofs():
    """G66: the macro (not modelled) runs at every move from here on, wherever it takes the
    tool; positioning again does not bring the proofs back."""
    text = textwrap.dedent(ISO).strip().replace("{change}", "G66 P9100 V-20.\nG00 X50. Y50. Z50.") + "\n"
    stock = [d for d in check_text(text, "part.nc", Settings(dialect="iso")).diagnostics if d.rule == "core.rapid-into-stock"]
    assert [d.status for d in stock] == [Status.UNKNOWN] and "G66" in stock[0].message


def test_only_a_rise_from_a_known_plane_point_is_spared_the_tip_check():
    """A rapid straight up the tool axis needs no tip; one whose X or Y is not known may
    have gone sideways, whatever its Z did."""
    state = MachineState(modal={"plane": "xy"})
    def rapid(start, end):
        return SimpleNamespace(start=start, end=end)
    assert _rises(rapid({"X": 1.0, "Y": 2.0, "Z": 5.0}, {"X": 1.0, "Y": 2.0, "Z": 50.0}), state)
    assert not _rises(rapid({"X": 1.0, "Y": 2.0, "Z": 5.0}, {"X": 1.0, "Y": 2.0, "Z": 4.0}), state)
    assert not _rises(rapid({"X": None, "Y": 2.0, "Z": 5.0}, {"X": None, "Y": 2.0, "Z": 50.0}), state)
    assert not _rises(rapid({"X": 1.0, "Y": 2.0, "Z": 5.0}, {"X": 3.0, "Y": 2.0, "Z": 50.0}), state)


def test_a_sinumerik_variable_named_like_an_offset_is_only_a_variable():
    """TOFFL and TOFF[Z] offset the tool; a program's own TOFFSET or DLX is a variable."""
    assert [SinumerikFrontend.machine_data(name) is not None for name in ("TOFFL", "TOFF[Z]", "$AA_OFF[Z]", "DL", "TOFFSET", "DLX", "$AA_OFFSET")] == \
        [True, True, True, True, False, False, False]
