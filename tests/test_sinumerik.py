"""SINUMERIK 840D: reader, detection, control flow, program context, cycles and their alarms.

Values a program computes are probed with ``SETAL(value)``: the control raises that alarm,
and the finding ``core.macro-alarm`` quotes the number, so a test can read what the
interpreter computed on each path.
"""
from __future__ import annotations

import re
import textwrap

import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

import ncverify.api
from ncverify import Settings, check_text
from ncverify.check import Checker
from ncverify.detect import detect
from ncverify.diagnostics import Status
from test_read_iso import numbers, plain_blocks
from ncverify.lower.sinumerik import SinumerikFrontend, SinumerikLowering, program_context
from ncverify.interpret.sinumerik_cycles import levels, pattern_positions
from ncverify.read.sinumerik import read_line


def check(program: str, **settings):
    return check_text(textwrap.dedent(program).lstrip("\n"), "t.mpf", Settings(dialect="sinumerik", **settings))


from conftest import findings


def probes(result) -> list[float]:
    """The values passed to SETAL on every path that reached one."""
    values = []
    for diagnostic in findings(result, "core.macro-alarm"):
        match = re.search(r"raises alarm (-?[0-9.e+]+|\?) with SETAL", diagnostic.message)
        assert match, diagnostic.message
        values.append(float(match.group(1)))
    return sorted(values)


# --------------------------------------------------------------------------- reader

@hypothesis_settings(max_examples=300, deadline=None)
@given(st.text(alphabet="NGXYZRIJKFSTDM0123456789.=+-*/()[],;:\"' _ABCEHLOPQUVW$；（），“”IFELSENDWHILOPCAS\t", max_size=60))
def test_the_reader_never_raises_and_every_problem_has_a_column(text):
    block = read_line(text, 1)
    if block.problem:
        assert 0 <= block.problem.start < block.problem.end
    SinumerikFrontend(SinumerikLowering()).blocks(text.encode(), 1, None)


def test_the_manuals_full_width_punctuation_reads_like_ascii():
    ascii_block = read_line('N40 CYCLE81(10, 0, 2, -5) ; centre', 1)
    wide_block = read_line('N40 CYCLE81（10，0，2，–5）；centre', 1)
    assert [(item.kind, item.name, item.args) for item in ascii_block.items] == [(item.kind, item.name, item.args) for item in wide_block.items]
    assert read_line('N10 T=“DRILL”', 1).items[0].value == "DRILL"
    assert read_line('ABNAHME4_CONT：G0 X1', 1).label == "ABNAHME4_CONT"


@pytest.mark.parametrize("text, values", [
    ("N10 G0 X100Y10 Z-5", {"G": 0.0, "X": 100.0, "Y": 10.0, "Z": -5.0}),
    ("G1X1.5Y2.Z-.5 F.2", {"G": 1.0, "X": 1.5, "Y": 2.0, "Z": -0.5, "F": 0.2}),
    ("X1475. Y170.", {"X": 1475.0, "Y": 170.0}),
])
def test_packed_and_signed_address_words(text, values):
    assert {item.name: item.value for item in read_line(text, 1).items} == values


def test_garbled_text_gives_a_syntax_finding_at_its_column():
    result = check("""
        N10 G0 X10 Y10 Z10
        N20 G1 X=(10+ F100
        N30 M30
    """)
    [syntax] = findings(result, "core.syntax")
    assert (syntax.span.line, syntax.span.column) == (2, 19) and "')' expected" in syntax.message


# --------------------------------------------------------------------------- detection

@pytest.mark.parametrize("text", [
    "PROC AL600\nG1 X10 F100\nM17\n",
    "N5 R10=15\nN10 BEGIN:\nN20 Z=10-R10\nN30 G1 X=R10 F200\nN100 REPEAT BEGIN\nM30\n",
    "%_N_PART_MPF\nG0 X10 Y10\nG1 Z-5 F100\nM30\n",
    "N10 G90 G17 F900 S4000 M3 T2 D1\nG0 X50 Y30\nN15 MCALL CYCLE82(10,0,1,-22,0,0)\nCYCLE801(30,20,0,10,15,100,50)\nMCALL\nM30\n",
])
def test_sinumerik_is_told_from_the_text_alone(text):
    assert detect(text, text.encode()).dialect == "sinumerik"


def test_an_iso_program_stays_iso():
    text = "%\nO1000\nG21 G90 G17 G54\nT1 M06\nG00 X10. Y10.\nG43 H01 Z50.\nG81 Z-5. R2. F100.\nG80\nM30\n%\n"
    assert detect(text, text.encode()).dialect == "iso"


# --------------------------------------------------------------------------- control flow

def test_if_else_takes_one_branch():
    result = check("""
        R1=3
        IF R1>2
          SETAL(61)
        ELSE
          SETAL(62)
        ENDIF
        M30
    """)
    assert probes(result) == [61.0]


def test_nested_if_lands_on_its_own_endif():
    result = check("""
        R1=1
        R2=0
        IF R1==1
          IF R2==1
            SETAL(71)
          ENDIF
          SETAL(72)
        ENDIF
        SETAL(73)
        M30
    """)
    assert probes(result) == [72.0]


def test_a_free_condition_explores_both_branches():
    result = check("""
        IF R7>0
          SETAL(1)
        ELSE
          SETAL(2)
        ENDIF
        M30
    """)
    assert probes(result) == [1.0, 2.0]


def test_while_for_repeat_loop_and_case_compute_what_the_control_computes():
    result = check("""
        DEF INT IDX, SUM, CNT
        SUM=0
        FOR IDX=1 TO 4
          SUM=SUM+IDX
        ENDFOR
        WHILE SUM<100
          SUM=SUM*2
        ENDWHILE
        REPEAT
          SUM=SUM-30
        UNTIL SUM<50
        CNT=0
        LOOP
          CNT=CNT+1
          IF CNT==3 GOTOF OUT
        ENDLOOP
        OUT:
        CASE CNT OF 1 GOTOF ONE 3 GOTOF THREE DEFAULT GOTOF ONE
        ONE: SETAL(1)
        THREE: SETAL(SUM*1000+IDX*10+CNT)
        M30
    """)
    # SUM: 10 -> 160 (doubling) -> 40 (REPEAT); IDX ends at 4; CNT = 3
    assert probes(result) == [40043.0]


def test_gotob_loops_back_and_gotof_skips_a_contour_section():
    result = check("""
        R1=0
        LOOP_HEAD:
        R1=R1+1
        IF R1<5 GOTOB LOOP_HEAD
        GOTOF WORK
        G0 X0 Y0 Z-100
        WORK:
        SETAL(R1)
        M30
    """)
    assert probes(result) == [5.0]


def test_a_jump_to_a_missing_label_is_reported():
    result = check("""
        GOTOF NOWHERE
        M30
    """)
    assert findings(result, "core.label-not-found", Status.VIOLATED)


def test_proc_parameters_are_bound_by_position_and_omitted_ones_are_zero():
    result = check("""
        %_N_MAIN_MPF
        ADD3(1, , 30)
        M30
        %_N_ADD3_SPF
        PROC ADD3(REAL A, REAL B, INT C)
        SETAL(A+B*10+C)
        RET
    """)
    assert probes(result) == [31.0]


def test_a_subprogram_on_the_control_is_unknown_not_an_alarm():
    result = check("""
        G0 X0 Y0 Z10
        _MAKER_CYCLE(1, 2)
        M30
    """)
    [missing] = findings(result, "core.program-not-found")
    assert missing.status is Status.UNKNOWN


# --------------------------------------------------------------------------- context from the program

def test_workpiece_box_rectangle_and_cylinder_become_the_stock():
    box = program_context(b'WORKPIECE(,"",,"BOX",0,0,-20,-80,0,0,120,80)\n').stock
    assert (box.x_range, box.y_range, box.z_range) == ((0.0, 120.0), (0.0, 80.0), (-20.0, 0.0))
    rectangle = program_context(b'WORKPIECE(,"",,"RECTANGLE",0,0,-30,-80,100,60)\n').stock
    assert (rectangle.x_range, rectangle.y_range) == ((-50.0, 50.0), (-30.0, 30.0))
    bar = program_context('WORKPIECE（,“”,,“CYLINDER”,0,0,-100,-80,60）\n'.encode()).stock
    assert (bar.kind, bar.diameter, bar.z_range) == ("cylinder", 60.0, (-100.0, 0.0))


def test_tc_dp_assignments_are_a_tool_table():
    tools = program_context(b"$TC_DP1[3,1]=220\n$TC_DP3[3,1]=95\n$TC_DP6[3,1]=4.25\n$TC_DP6[3,2]=9\n").tools
    assert (tools[3].type, tools[3].length, tools[3].radius) == ("drill", 95.0, 4.25)


def test_the_blank_and_tool_data_are_read_from_the_lines_naming_them_wherever_they_stand():
    """Only the lines naming WORKPIECE or $TC_DP (in any case) are read, each with its own
    line number; a name in a comment line makes no blank."""
    text = (b"; WORKPIECE in a comment\r\nG17 G90\n\n$tc_dp1[3,1]=220 $TC_DP6[3,1]=4.25\n"
            b'N50 workpiece(,"",,"BOX",0,0,-20,-80,0,0,120,80)\r\nM30')
    context = program_context(text)
    assert (context.stock.x_range, context.stock.span.line) == ((0.0, 120.0), 5)
    assert (context.tools[3].type, context.tools[3].radius) == ("drill", 4.25)


def test_a_rapid_into_the_workpiece_blank_is_found_with_no_project_file():
    result = check("""
        WORKPIECE(,"",,"BOX",0,0,-30,-80,0,0,80,60)
        G17 G90 G54 T2 D1 M6
        S3000 M3 F400
        G0 X-10 Y10 Z5
        G1 Z-3
        G1 X90 Y50
        G0 X-10
        M30
    """)
    [crash] = findings(result, "core.rapid-into-stock", Status.VIOLATED)  # back at the depth along Y50, beside the diagonal slot
    assert crash.span.line == 7


# --------------------------------------------------------------------------- cycles

def test_depth_resolution_dpr_wins_and_the_direction_follows_rtp():
    assert levels({"RTP": 10.0, "RFP": 0.0, "SDIS": 2.0, "DP": -30.0, "DPR": 12.0}) == (1.0, 2.0, -12.0)
    assert levels({"RTP": 10.0, "RFP": 0.0, "SDIS": 2.0, "DP": -30.0, "DPR": 0.0}) == (1.0, 2.0, -30.0)
    assert levels({"RTP": -10.0, "RFP": 0.0, "SDIS": 2.0, "DP": 0.0, "DPR": 5.0}) == (-1.0, -2.0, 5.0)  # drilling upward


def test_hole_patterns():
    assert pattern_positions("HOLES1", {"SPCA": 10.0, "SPCO": 40.0, "STA1": 0.0, "FDIS": 10.0, "DBH": 25.0, "NUM": 3.0}) == [(20.0, 40.0), (45.0, 40.0), (70.0, 40.0)]
    circle = pattern_positions("HOLES2", {"CPA": 0.0, "CPO": 0.0, "RAD": 10.0, "STA1": 0.0, "INDA": 0.0, "NUM": 4.0})
    assert [(round(x, 6), round(y, 6)) for x, y in circle] == [(10.0, 0.0), (0.0, 10.0), (-10.0, 0.0), (0.0, -10.0)]
    assert len(pattern_positions("CYCLE801", {"_SPCA": 0.0, "_SPCO": 0.0, "_STA": 0.0, "_DIS1": 5.0, "_DIS2": 5.0, "_NUM1": 3.0, "_NUM2": 2.0})) == 6


class _HoleRecorder(Checker):
    holes: list = []

    def hole(self, hole, state):
        _HoleRecorder.holes.append(hole)
        super().hole(hole, state)


def test_mcall_drills_after_every_positioning_and_at_every_pattern_position(monkeypatch):
    _HoleRecorder.holes = []
    monkeypatch.setattr(ncverify.api, "Checker", _HoleRecorder)
    check("""
        G17 G90 T1 D1 M6
        S1000 M3 F100
        G0 X0 Y0 Z50
        MCALL CYCLE81(10, 0, 2, , 8)
        X5 Y5
        G0 X15 Y5
        HOLES1(0, 20, 0, 0, 10, 3)
        MCALL
        G0 X100 Y100
        M30
    """)
    positions = [(hole.position["X"], hole.position["Y"]) for hole in _HoleRecorder.holes]
    assert positions == [(5.0, 5.0), (15.0, 5.0), (0.0, 20.0), (10.0, 20.0), (20.0, 20.0)]
    assert {(hole.initial, hole.r_point, hole.bottom) for hole in _HoleRecorder.holes} == {(10.0, 2.0, -8.0)}


def test_a_rapid_onto_the_reference_plane_inside_the_blank_is_a_crash():
    """CYCLE81 rapids to RFP + SDIS: with RFP given below the top of the blank the rapid
    runs into the material (the shared hole model feeds core.rapid-into-stock)."""
    result = check("""
        WORKPIECE(,"",,"BOX",0,0,-20,-80,0,0,100,100)
        G17 G90 T1 D1 M6
        S1000 M3 F100
        G0 X50 Y50 Z20
        CYCLE81(10, -5, 1, -15)
        M30
    """)
    assert findings(result, "core.rapid-into-stock", Status.VIOLATED)


@pytest.mark.parametrize("call, rule, text", [
    ("CYCLE81(10, 0, 2, -12, 0, 5)", "sinumerik.cycle-arguments", "12340"),
    ('CYCLE81("TEN", 0, 2, -12)', "sinumerik.cycle-arguments", "12330"),
    ("CYCLE81(-5, 0, 2, -12)", "sinumerik.reference-plane", "61101"),
    ("CYCLE81(0, 0, 2, 0, 5)", "sinumerik.reference-plane", "61101"),
    ("CYCLE86(10, 0, 2, -20, 0, 0.5, 5)", "sinumerik.spindle-direction", "61102"),
    ("CYCLE83(10, 0, 2, -40, 0, -12, 0, -1.5)", "sinumerik.cycle-parameter-range", "61019"),
    ("POCKET3(10, 0, 2, -6, 60, 40, 6, 50, 50, 0, 3, 0.3, 0.2, 400, 100, 0, 5)", "sinumerik.machining-type", "61002"),
    ("POCKET3(10, 0, 2, -6, 60, 40, 6, 50, 50, 0, 3, 0.3, 0.2, 400, 100, 7, 11)", "sinumerik.milling-direction", "61109"),
    ("HOLES1(0, 0, 0, 10, 15)", "sinumerik.hole-count", "61103"),
    ("POCKET2(10, 0, 2, -6, 0, 4, 50, 50, 100, 300, 3, 2, 0.2, 0)", "sinumerik.cutter-radius", "61105"),
    ("CYCLE72(\"KONTUR\", 10, 0, 2, -5, 2, 0.2, 0.1, 300, 100, 11, 43, 1, 5)", "sinumerik.cycle-parameter-range", "61114"),
])
def test_alarms_are_predicted_with_their_number(call, rule, text):
    result = check(f"""
        $TC_DP6[1,1]=5
        G17 G90 T1 D1 M6
        S1000 M3 F100
        G0 X50 Y50 Z20
        {call}
        M30
    """)
    found = findings(result, rule, Status.VIOLATED)
    assert found and text in found[0].message, [(d.rule, d.message) for d in result.diagnostics]


@pytest.mark.parametrize("call", [
    "CYCLE81(10, 0, 2, -12)",
    "CYCLE82(10, 0, 2, -12, 0, 1)",
    "CYCLE84(10, 0, 2, -15, 0, , 3, 8, 0, 0, 400, 400)",
    "CYCLE86(10, 0, 2, -20, 0, 0.5, 3, -0.5, 0, 0, 0)",
    "POCKET3(10, 0, 2, -6, 60, 40, 6, 50, 50, 0, 3, 0.3, 0.2, 400, 100, 0, 11)",
    "POCKET2(10, 0, 2, -6, 0, 12, 50, 50, 100, 300, 3, 2, 0.2, 0)",
])
def test_correct_calls_raise_nothing(call):
    result = check(f"""
        $TC_DP6[1,1]=5
        G17 G90 T1 D1 M6
        S1000 M3 F100
        G0 X50 Y50 Z20
        {call}
        M30
    """)
    assert not [d for d in result.diagnostics if d.rule.startswith("sinumerik.") and d.status is Status.VIOLATED]


def test_a_dropped_comma_is_explained_value_by_value():
    result = check("""
        G17 G90 T1 D1 M6
        S400 M3
        G0 X0 Y0 Z20
        CYCLE84(10, 0, 2, -15, 0, 3, 8, 0, 0, 400, 400)
        M30
    """)
    [shifted] = findings(result, "sinumerik.shifted-arguments")
    assert "comma seems to be missing before DTB" in shifted.message
    assert "8 landed in SDAC, meant for MPIT" in shifted.message


def test_a_doubled_comma_is_explained_too():
    result = check("""
        G17 G90 T1 D1 M6
        S400 M3
        G0 X0 Y0 Z20
        CYCLE86(10, 0, 2, -20, 0, , 0.5, 3, -0.5)
        M30
    """)
    [shifted] = findings(result, "sinumerik.shifted-arguments")
    assert "extra comma" in shifted.message and "3 landed in RPA, meant for SDIR" in shifted.message


def test_a_pattern_without_mcall_drills_nothing():
    result = check("""
        G17 G90 T1 D1 M6
        S1000 M3 F100
        G0 X0 Y0 Z20
        HOLES2(50, 50, 30, 0, 0, 6)
        M30
    """)
    assert "62100" in findings(result, "sinumerik.pattern-without-mcall")[0].message


# --------------------------------------------------------------------------- CYCLE95 contour

_LATHE_HEAD = """
    $TC_DP1[1,1]=500
    $TC_DP6[1,1]=0.8
    G18 G90 G54 DIAMON T1 D1
    G96 S200 LIMS=3000 M3 G95 F0.25
"""


def check_lathe(program: str):
    return check(_LATHE_HEAD + textwrap.dedent(program), machine="lathe")


def contour_findings(result) -> list[str]:
    return [d.message for d in findings(result, "sinumerik.stock-removal-contour", Status.VIOLATED)]


def test_cycle95_with_a_clean_contour_section_and_an_outside_start_raises_nothing():
    result = check_lathe("""
        G0 X70 Z5
        CYCLE95("FROM:TO", 2.5, 0.1, 0.2, 0, 0.3, 0.15, 0.1, 9)
        G0 X100 Z50
        GOTOF DONE
        FROM: G1 X20 Z0
        X30 Z-5
        Z-30
        G2 X40 Z-35 CR=5
        TO: G1 X60
        DONE: M30
    """)
    assert contour_findings(result) == []
    assert not findings(result, "core.css-without-clamp")


def test_cycle95_contour_rules_and_the_start_inside_the_contour_rectangle():
    result = check_lathe("""
        G0 X40 Z-10
        CYCLE95("BAD_CONTOUR", 2.5, 0.1, 0.2, 0, 0.3, 0.15, 0.1, 9)
        M30
        %_N_BAD_CONTOUR_SPF
        X20 Z0
        G17 G1 X30 Z-5
        G3 X40 Z-15 CR=-5
        M17
    """)
    messages = " | ".join(contour_findings(result))
    for expected in ("has no G0/G1/G2/G3", "10931", "more than 180 degrees", "61607"):
        assert expected in messages, messages


def test_cycle95_with_too_few_contour_blocks():
    result = check_lathe("""
        G0 X70 Z5
        CYCLE95("SHORT", 2.5, 0.1, 0.2, 0, 0.3, 0.15, 0.1, 9)
        M30
        %_N_SHORT_SPF
        G1 X20 Z0
        X30
        M17
    """)
    assert any("10933" in message for message in contour_findings(result))


def test_iso_mode_is_reported_as_not_verified():
    result = check("""
        G291
        G90 G0 X10 Y10
        G290
        M30
    """)
    assert findings(result, "core.unsupported-code")


def test_mcall_still_active_at_the_tool_change_is_reported():
    result = check("""
        G17 G90 T1 D1 M6
        S1000 M3 F100
        G0 X0 Y0 Z50
        MCALL CYCLE81(10, 0, 2, -8)
        X10 Y10
        T2 M6
        M30
    """)
    assert findings(result, "core.cycle-modal-at-tool-change")


@pytest.mark.parametrize("call, rule, text", [
    ("CYCLE84(10, 0, 2, -15, 0, 0, 3, 8, 1.5)", "sinumerik.thread-pitch", "61001"),
    ('CYCLE94(20, 60, "G")', "sinumerik.undercut-form", "61609"),
    ("CYCLE93(35, 60, 30, 25, 5, 10, 20, 0, 0, -2, -2, 1, 1, 0, 1, 5)", "sinumerik.turning-parameters", "IDEP"),
    ("CYCLE97(0, 42, 0, -35, 42, 42, 10, 3, 2.3, 0.05, 30, 0, 5, 2, 9, 1)", "sinumerik.turning-parameters", "61002"),
    ("CYCLE81(10, 0, -2, -12)", "sinumerik.cycle-parameter-range", "without sign"),
])
def test_more_alarms_are_predicted(call, rule, text):
    result = check(f"""
        G90 T1 D1
        S400 M3 F100
        G0 X50 Y50 Z20
        {call}
        M30
    """)
    found = findings(result, rule, Status.VIOLATED)
    assert found and text in found[0].message, [(d.rule, d.message) for d in result.diagnostics]


def test_planes_from_free_parameters_are_judged_for_every_value():
    result = check("""
        ; ncverify: assume -50 <= R1 <= 50
        G17 G90 T1 D1 M6
        S1000 M3 F100
        G0 X50 Y50 Z20
        CYCLE81(R1, 0, 2, -12)
        M30
    """)
    [finding] = findings(result, "sinumerik.reference-plane")
    assert finding.status is Status.VIOLATED and "R1" in finding.witness


def test_a_pocket_rapids_to_its_centre_at_the_retract_plane_and_ends_there():
    """POCKET1 goes to the centre at RTP with G0, then to RFP + SDIS: a reference plane
    given below the top of the blank is a rapid into the material. After the cycle the tool
    is above the centre at RTP, so the next G0 is checked from there: down into the pocket
    just cut, but 1 mm below its floor."""
    result = check("""
        WORKPIECE(,"",,"BOX",0,0,-30,-80,0,0,100,100)
        $TC_DP6[1,1]=5
        G17 G90 T1 D1 M6
        S2000 M3 F300
        G0 X50 Y50 Z20
        POCKET1(10, -5, 2, -12, 0, 60, 40, 8, 30, 30, 0, 100, 300, 3, 2, 0.2, 0)
        POCKET1(10, 0, 2, -6, 0, 60, 40, 8, 70, 70, 0, 100, 300, 3, 2, 0.2, 0)
        G0 X70 Y70 Z-7
        M30
    """)
    crashes = findings(result, "core.rapid-into-stock", Status.VIOLATED)
    assert [finding.span.line for finding in crashes] == [6, 8]


def test_the_blank_is_not_used_under_programmable_frames():
    """TRANS/ROT move the coordinate system the moves are written in away from the one
    WORKPIECE describes: the rapid is not judged against the blank (unknown, never a false
    'safe' or a false crash)."""
    result = check("""
        WORKPIECE(,"",,"BOX",0,0,-30,-80,0,0,80,60)
        G17 G90 G54 T2 D1 M6
        S3000 M3 F400
        TRANS X200
        G0 X-10 Y10 Z-5
        G0 X40
        M30
    """)
    assert not findings(result, "core.rapid-into-stock", Status.VIOLATED)
    assert findings(result, "core.rapid-into-stock", Status.UNKNOWN)


def test_ac_and_ic_override_the_modal_distance_mode_for_one_word():
    result = check("""
        WORKPIECE(,"",,"BOX",0,0,-30,-80,0,0,80,60)
        G17 G90 G54 T2 D1 M6
        S3000 M3 F400
        G0 X-10 Y10 Z10
        G91 G0 Z=AC(-5)
        G90 G0 X-20 Z=IC(20)
        M30
    """)
    crashes = findings(result, "core.rapid-into-stock", Status.VIOLATED)
    assert [finding.span.line for finding in crashes] == []  # X-10 is outside the blank: Z-5 there is safe
    result = check("""
        WORKPIECE(,"",,"BOX",0,0,-30,-80,0,0,80,60)
        G17 G90 G54 T2 D1 M6
        S3000 M3 F400
        G0 X10 Y10 Z10
        G91 G0 Z=AC(-5)
        M30
    """)
    assert [finding.span.line for finding in findings(result, "core.rapid-into-stock", Status.VIOLATED)] == [5]


_PLAIN_LINE = st.builds(
    lambda g, x, y, z, f: f"G{g} X{x:.3f} Y{y:.3f} Z{z:.3f}" + (f" F{f}" if f else ""),
    st.sampled_from([0, 1]), st.floats(-20, 120), st.floats(-20, 80), st.floats(-10, 20), st.sampled_from([0, 0, 300]))
_OTHER_LINE = st.sampled_from(["X=10 Y=20", "R1=R1+1", "G0 Z=AC(30)", "M8", "; comment", "N100 G1 X5"])


@hypothesis_settings(max_examples=40, deadline=None)
@given(st.lists(st.one_of(_PLAIN_LINE, _PLAIN_LINE, _PLAIN_LINE, _OTHER_LINE), min_size=1, max_size=60))
def test_batched_plain_blocks_report_what_block_by_block_reports(lines):
    program = "\n".join(['WORKPIECE(,"",,"BOX",0,0,-30,-80,0,0,100,60)', "G17 G90 G54 T1 D1 M6", "S2000 M3 F500", "G0 X0 Y0 Z30",
                         *lines, "M30"]) + "\n"

    def run(per_block_only):
        result = check_text(program, "t.mpf", Settings(dialect="sinumerik", per_block_only=per_block_only))
        return sorted((d.rule, d.span.line, d.span.column, d.status.value, d.message) for d in result.diagnostics)

    assert run(True) == run(False)


@hypothesis_settings(max_examples=300, deadline=None)
@given(block=plain_blocks(), line=st.integers(min_value=1, max_value=10**6))
def test_plain_motion_and_arc_lines_lower_without_the_reader_like_the_general_lowering(block, line):
    """SINUMERIK CAM lines (N G0-G3 X Y Z I J K F) skip the reader; the IR must be the one
    the reader and the general lowering make."""
    from ncverify.lower.sinumerik import SinumerikFrontend, SinumerikLowering
    from ncverify.read.sinumerik import read_line

    text, _ = block
    frontend = SinumerikFrontend(SinumerikLowering())
    assert frontend.blocks(text.encode("ascii"), line, None) == frontend.lowering.lower(read_line(text, line), None)


@st.composite
def radius_arc_lines(draw) -> str:
    """Arcs by their radius as CAM output writes them (``N.. G2 X.. Y.. CR=.. F..``) and
    lines close to that form: CR= first or twice, with centre words, spaces around '=', a
    straight move, a parameter as the radius."""
    words = [f"G{draw(st.sampled_from(['0', '1', '2', '3', '02', '03']))}"] if draw(st.booleans()) else []
    words += [letter + draw(numbers()) for letter in draw(st.lists(st.sampled_from("XYZFIJ"), unique=True, max_size=4))]
    radius = draw(st.sampled_from(["CR=", "CR=", "CR =", "CR= "])) + draw(st.one_of(numbers(), numbers(), st.just("R1")))
    words.insert(draw(st.integers(0, len(words))), radius)
    if draw(st.integers(0, 9)) == 0:
        words.append("CR=" + draw(numbers()))
    number = f"N{draw(st.integers(0, 9999))}" + draw(st.sampled_from([" ", "\t"])) if draw(st.booleans()) else ""
    gap = draw(st.sampled_from([" ", "  ", "\t"]))
    return draw(st.sampled_from(["", " "])) + number + gap.join(words) + draw(st.sampled_from(["", " "]))


@hypothesis_settings(max_examples=400, deadline=None)
@given(text=radius_arc_lines(), line=st.integers(min_value=1, max_value=10**6))
def test_arc_lines_by_radius_lower_without_the_reader_like_the_general_lowering(text, line):
    frontend = SinumerikFrontend(SinumerikLowering())
    assert frontend.blocks(text.encode("ascii"), line, None) == frontend.lowering.lower(read_line(text, line), None), text


@pytest.mark.parametrize("text", ["N20 G2 X10.5 Y5 I-5 J0 F800", "G1 X1 Y2 Z-1", "G03 X0 Y3 J1.5", "G2 X6.000 Y40.000 CR=6.000", "N30 G3 X0 Y3 CR=-1.5 F500"])
def test_cam_motion_lines_take_the_fast_lowering(text):
    from ncverify.lower.iso import fast_motion_block
    from ncverify.lower.sinumerik import _FAST_FORM

    assert fast_motion_block(text.encode("ascii"), 1, None, _FAST_FORM) is not None


# --------------------------------------------------------------------------- tool length on Z travel

def _z_travel() -> str:
    from test_tangent_arcs import TRAVEL

    return TRAVEL.replace("z = [-300, 300]", "z = [-300, 50]")


@pytest.mark.parametrize("edge, status", [("D1", Status.VIOLATED), ("", Status.VIOLATED), ("D2", Status.UNKNOWN)])
def test_the_z_travel_counts_the_active_edge_length_of_the_tool_in_the_spindle(edge, status):
    """No H register on the 840D: D (or M6 alone, which makes D1 active) takes the length of
    the tool's edge. Z5 with the 60 mm tool is machine Z 65, past the travel's 50; edge D2 is
    not described, so its length is unknown."""
    from conftest import check_program

    program = f"""
        G17 G90 G54 T1
        M6
        S1000 M3 {edge}
        G0 X0 Y0 Z5
        M30
    """
    result = check_program(program, "t.mpf", _z_travel(), dialect="sinumerik")
    (finding,) = findings(result, "core.travel-limit")
    assert finding.status is status
    assert ("65" in finding.message) if status is Status.VIOLATED else ("T1 (edge D2)" in finding.message)


_STATEMENTS = st.sampled_from([
    "CYCLE81(15, 0, 2, -5)", "CYCLE83(10,0,1,-20,,-5,,3,1,0.5,1,0)", "MCALL CYCLE82(10, 0, 2, -8, , 0.5)", "MCALL", "M6", "T2 D1",
    "S3000 M3", "G0 Z50", "R1=R1+1", "IF R1 < 5 GOTOB LOOP", "WHILE R2 < 3", "ENDWHILE", "LOOP: G1 X=R1*2 F500", "N10 G2 X10 Y5 CR=5",
    "CYCLE81(15, , 2, -5) ; drill", "G0 X5.000 Y5.000", "DEF REAL DEPTH=-5", "CYCLE81(15,0,2,DEPTH)", "/N20 M8", "REPEAT LOOP P=2",
])


@hypothesis_settings(max_examples=80, deadline=None)
@given(st.lists(_STATEMENTS, min_size=1, max_size=30))
def test_a_line_read_again_lowers_as_its_first_reading_does(lines):
    """The frontend keeps each line text's reading and lends it to the same text on another
    line: the blocks it lowers are those of a fresh reading of that line."""
    remembering, fresh = SinumerikFrontend(SinumerikLowering()), SinumerikLowering()
    for number, text in enumerate(lines, start=1):
        assert remembering.blocks(text.encode(), number, None) == fresh.lower(read_line(text, number), None)
