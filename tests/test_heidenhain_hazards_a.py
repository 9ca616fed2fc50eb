"""HEIDENHAIN Klartext: every hazard of reference A §9 (H1-H48) mapped to the rules that
check it, and the special cycles of reference B (224, 225, 232, 18, 9, 12, 13, 32, 238, 239,
point tables) with their rules, each tested both ways on inline programs."""
from __future__ import annotations

import re
import textwrap
from pathlib import Path

import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_file, check_text
from ncverify.check import rule_definitions
from ncverify.diagnostics import Status
from ncverify.lower.heidenhain import KlartextLowering
from ncverify.interpret.heidenhain.special import engraved_characters

# Reference A §9, hazard by hazard: the rules that check it, or why none does. A rule that
# covers only part of a hazard says which part in the comment.
HAZARDS: dict[str, tuple[str, ...] | str] = {
    "H1": ("heidenhain.positive-depth",),  # 240 by depth or diameter, 232/233 by Q227 vs Q386
    "H2": ("heidenhain.positive-depth",),  # what it must not report: 204's Q249 > 0, a negative pitch (tested below)
    "H3": ("heidenhain.zero-depth",),  # 263-267: a zero countersink depth skips only its own step and is not reported
    "H4": ("heidenhain.usable-length",),  # Q201, Q1, 204's Q249, 232/233's Q227 - Q386; 240 by diameter is not compared with LU
    "H5": ("heidenhain.thread-depth-signs",),
    "H6": ("heidenhain.thread-depth", "heidenhain.thread-deeper-than-hole"),  # 263/264 depths; a tap or thread mill against a hole drilled earlier in the program
    "H7": ("heidenhain.thread-deeper-than-hole",),  # half a pitch below 262/263 against a hole drilled earlier in the program; lateral pre-positioning is not checked
    "H8": ("heidenhain.tap-pitch",),  # 206: Q206 against S x PITCH; M3/M4 against the thread hand is not checked
    "H9": ("heidenhain.tap-pitch",),
    "H10": ("core.spindle-off-cutting",),  # 207/209 leave the spindle as they found it; the servo-spindle need is H45
    "H11": ("heidenhain.plunge-angle",),  # PREDEF from GLOBAL DEF 110 is resolved before the check
    "H12": ("heidenhain.tool-too-large",),  # the pocket wider than the tool; 252's computed helix diameter is not checked
    "H13": ("heidenhain.finish-only-rapid",),
    "H14": ("heidenhain.position-after-cycle",),
    "H15": ("heidenhain.stud-approach-room",),  # against the BLK FORM; fixtures are not known
    "H16": ("heidenhain.stud-blank",),  # 258's circumscribed diameter against Q222 is not checked
    "H17": ("heidenhain.boring-drag", "heidenhain.boring-feed-per-revolution"),  # Q214 = 0, M136 at the call; Q357 is not judged
    "H18": ("heidenhain.back-boring-direction",),  # Q214 range; the clearance under the workpiece needs the fixture
    "H19": ("heidenhain.disengage-mirror",),
    "H20": "modelled, not a defect: cycle parameters are frozen at CYCL DEF and later assignments do not reach the call",
    "H21": ("heidenhain.call-without-cycle",),  # a DEF-active cycle sharing transfer parameters is not checked
    # H22: RL/RR on at any call (M99, CYCL CALL, M89, a pattern); thread milling takes its direction from Q351 and the pitch
    # sign (§6.13), which is no RL/RR the program gives, so nothing beyond the R0 rule is decidable
    "H22": ("heidenhain.call-without-tool", "heidenhain.cycle-with-compensation", "core.spindle-off-cutting"),
    "H23": "modelled, intent undecidable: after M89 every positioning block runs the cycle (its rapids are checked); which positions were meant as holes the program cannot say",
    "H24": ("heidenhain.call-pos-axes",),
    "H25": ("heidenhain.pattern-tool-axis",),  # the feed between points is modelled; a point table's clearance column is not
    "H26": ("heidenhain.pattern-surface",),
    "H27": ("core.clearance-below-stock",),  # the retract level Q203 + max(Q200, Q204) against the BLK FORM; fixtures are not known
    "H28": ("core.rapid-into-stock",),
    "H29": ("heidenhain.plunge-angle", "heidenhain.point-angle"),  # ANGLE for Q366, T-ANGLE for Q395, 240 and 277; RCUTS is not checked
    "H30": ("core.rapid-into-stock",),  # 205/241 go down to the deepened start Q379 at Q253 (FMAX: a rapid into the blank unless drilled); 240's Q342 is not modelled
    "H31": ("heidenhain.parameter-range",),
    "H32": ("heidenhain.peck-decrement",),  # Q212 without Q205; single pass and Q257 > Q202 are not reported
    "H33": ("heidenhain.tool-too-large",),
    "H34": ("heidenhain.parameter-range", "core.cycle-parameter-value"),
    "H35": ("heidenhain.transform-at-end", "heidenhain.transform-reset-order"),  # at the end of the program; the reset order where a tilted plane is involved
    "H36": ("heidenhain.rotation-cancels-compensation",),  # cycle 10; cycle 19 with M120 is not checked
    "H37": ("heidenhain.mirror-tool-axis",),  # the tool axis; the climb/up-cut reversal under a one-axis mirror is not reported
    "H38": ("heidenhain.scaling-factor",),  # the factor ranges and arcs under cycle 26; sizes read from cycle parameters are not scaled
    "H39": "modelled, not a defect: cycle 247 resets datum shift, mirror, rotation and scaling",
    "H40": ("core.rapid-into-stock", "core.clearance-below-stock"),
    "H41": ("heidenhain.depth-through-blank",),
    "H42": ("heidenhain.working-plane",),  # the three spatial angles, every axis moved before a cycle, M94; F/ABST and M91/M92 are not checked
    "H43": "undecidable: the datum table's values live on the machine, not in the program",
    "H44": ("heidenhain.cutting-length",),
    "H45": ("heidenhain.servo-spindle",),  # the servo spindle ([machine] spindle_encoder); software options and the floating tap holder are not judged
    "H46": ("heidenhain.pattern-compatibility",),
    "H47": "informational, not a defect: GLOBAL DEF values reach every later PREDEF parameter, which is modelled",
    "H48": "undecidable: the retract after an NC stop in 207/209 is an operator action at run time",
}


def test_every_part_a_hazard_is_mapped():
    assert list(HAZARDS) == [f"H{number}" for number in range(1, 49)]


def test_every_mapped_rule_exists():
    definitions = rule_definitions()
    named = {rule_id for entry in HAZARDS.values() if not isinstance(entry, str) for rule_id in entry}
    assert named <= set(definitions), named - set(definitions)


def test_every_reason_says_why_no_rule_checks_it():
    reasons = [entry for entry in HAZARDS.values() if isinstance(entry, str)]
    assert all(re.match(r"(not covered|undecidable|modelled|informational)", reason) for reason in reasons)


# --------------------------------------------------------------------------- helpers


def program(body: str, tool: str = "TOOL CALL 1 Z S2000", start: str = "L  Z+100 R0 FMAX M3", name: str = "T") -> str:
    """A program frame around ``body``: a 100 x 100 x 20 blank, tool 1, spindle on."""
    lines = [f"0  BEGIN PGM {name} MM", "1  BLK FORM 0.1 Z X+0 Y+0 Z-20", "2  BLK FORM 0.2  X+100  Y+100  Z+0", f"3  {tool}", f"4  {start}"]
    lines += textwrap.dedent(body).strip("\n").splitlines()
    lines += ["98 L  Z+100 R0 FMAX M30", f"99 END PGM {name} MM"]
    return "\n".join(lines) + "\n"


from conftest import project


def check(text: str, project_text: str = ""):
    return check_text(text, "t.h", Settings(), project(project_text))


def lines(result, rule: str, status=Status.VIOLATED) -> list[int]:
    return [d.span.line for d in result.diagnostics if d.rule == rule and d.status is status]


def messages(result, rule: str) -> list[str]:
    return [d.message for d in result.diagnostics if d.rule == rule and d.status is Status.VIOLATED]


TOOL_R5 = "[tools.1]\nradius = 5\ncutting_length = 10"


def stud(blank: int, position: str = "X+50  Y+50", approach: int = 0) -> str:
    return f"""5  CYCL DEF 256 RECTANGULAR STUD ~
    Q218=+60 ;FIRST SIDE LENGTH ~
    Q424=+{blank} ;WORKPC. BLANK SIDE 1 ~
    Q219=+40 ;2ND SIDE LENGTH ~
    Q425=+{blank} ;WORKPC. BLANK SIDE 2 ~
    Q220=+0 ;CORNER RADIUS ~
    Q368=+0 ;ALLOWANCE FOR SIDE ~
    Q224=+0 ;ANGLE OF ROTATION ~
    Q367=+0 ;STUD POSITION ~
    Q207=+500 ;FEED RATE MILLING ~
    Q351=+1 ;CLIMB OR UP-CUT ~
    Q201=-10 ;DEPTH ~
    Q202=+5 ;PLUNGING DEPTH ~
    Q206=+3000 ;FEED RATE FOR PLNGNG ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q370=+1 ;TOOL PATH OVERLAP ~
    Q437=+{approach} ;APPROACH POSITION
6  L  {position} R0 FMAX M99"""


def face(start_x="-5", top="+0", end="-1", side="+2", length="+100") -> str:
    return f"""5  CYCL DEF 232 FACE MILLING ~
    Q389=+2 ;STRATEGY ~
    Q225={start_x} ;STARTNG PNT 1ST AXIS ~
    Q226=+0 ;STARTNG PNT 2ND AXIS ~
    Q227={top} ;STARTNG PNT 3RD AXIS ~
    Q386={end} ;END POINT 3RD AXIS ~
    Q218={length} ;FIRST SIDE LENGTH ~
    Q219=+100 ;2ND SIDE LENGTH ~
    Q202=+2 ;MAX. PLUNGING DEPTH ~
    Q369=+0 ;ALLOWANCE FOR FLOOR ~
    Q370=+1 ;MAX. OVERLAP ~
    Q207=+500 ;FEED RATE MILLING ~
    Q385=+500 ;FINISHING FEED RATE ~
    Q253=+750 ;F PRE-POSITIONING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q357={side} ;CLEARANCE TO SIDE ~
    Q204=+50 ;2ND SET-UP CLEARANCE
6  CYCL CALL"""


def engraving(text="SERIAL 0001", height="+3", depth="-0.5", length="+40") -> str:
    return f"""5  CYCL DEF 225 ENGRAVING ~
    QS500="{text}" ;ENGRAVING TEXT ~
    Q513={height} ;CHARACTER HEIGHT ~
    Q514=+0 ;SPACE FACTOR ~
    Q515=+0 ;FONT ~
    Q516=+0 ;TEXT ARRANGEMENT ~
    Q374=+0 ;ANGLE OF ROTATION ~
    Q517=+50 ;CIRCLE RADIUS ~
    Q207=+500 ;FEED RATE MILLING ~
    Q201={depth} ;DEPTH ~
    Q206=+150 ;FEED RATE FOR PLNGNG ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q367=+0 ;TEXT POSITION ~
    Q574={length} ;TEXT LENGTH ~
    Q202=+0.5 ;MAX. PLUNGING DEPTH
6  L  X+10  Y+10 R0 FMAX M99"""


def thread_cutting(height="+2", depth="-20", pitch="+1") -> str:
    return f"""5  L  X+50  Y+50 R0 FMAX
6  L  Z{height} R0 FMAX M5
7  CYCL DEF 18.0 THREAD CUTTING
8  CYCL DEF 18.1 DEPTH{depth}
9  CYCL DEF 18.2 PITCH{pitch}
10 CYCL CALL"""


DRILL = """CYCL DEF 200 DRILLING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q201=-15 ;DEPTH ~
    Q206=+150 ;FEED RATE FOR PLNGNG ~
    Q202=+5 ;PLUNGING DEPTH ~
    Q210=+0 ;DWELL TIME AT TOP ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q211=+0 ;DWELL TIME AT DEPTH"""


# --------------------------------------------------------------------------- H2: what must not be reported


def test_a_negative_pitch_is_the_thread_hand_not_a_direction():
    result = check(program("""5  CYCL DEF 207 RIGID TAPPING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q201=-10 ;DEPTH ~
    Q239=-1 ;THREAD PITCH ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE
6  L  X+30  Y+30 R0 FMAX M99"""))
    assert not lines(result, "heidenhain.positive-depth")


def test_back_boring_upward_q249_is_not_a_positive_depth():
    result = check(program("""5  CYCL DEF 204 BACK BORING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q249=+5 ;DEPTH OF COUNTERBORE ~
    Q250=+20 ;MATERIAL THICKNESS ~
    Q251=+3.5 ;OFF-CENTER DISTANCE ~
    Q252=+15 ;TOOL EDGE HEIGHT ~
    Q253=+750 ;F PRE-POSITIONING ~
    Q254=+200 ;F COUNTERSINKING ~
    Q255=+0 ;DWELL TIME ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q214=+1 ;DISENGAGING DIRECTN ~
    Q336=+0 ;ANGLE OF SPINDLE
6  L  X+50  Y+50 R0 FMAX M99"""))
    assert not lines(result, "heidenhain.positive-depth")


def floating_tap(feed: str) -> str:
    return program(f"""5  CYCL DEF 206 TAPPING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q201=-10 ;DEPTH OF THREAD ~
    Q206={feed} ;FEED RATE FOR PLNGNG ~
    Q211=+0 ;DWELL TIME AT DEPTH ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE
6  L  X+30  Y+30 R0 FMAX M99""", tool="TOOL CALL 1 Z S500")


def test_h8_floating_tapping_feed_not_s_times_pitch_is_reported():
    project = "[tools.1]\nradius = 4\npitch = 1.5"
    result = check(floating_tap("+150"), project)
    assert lines(result, "heidenhain.tap-pitch") == [9]
    assert "750" in messages(result, "heidenhain.tap-pitch")[0]
    assert not lines(check(floating_tap("+750"), project), "heidenhain.tap-pitch")
    no_speed = check(floating_tap("+150").replace("TOOL CALL 1 Z S500", "TOOL CALL 1 Z"), project)
    assert lines(no_speed, "heidenhain.tap-pitch", Status.UNKNOWN) and not lines(no_speed, "heidenhain.tap-pitch")


def thread_mill_after_drilling(drilled: str) -> str:
    return program(f"""5  {DRILL.replace("Q201=-15", "Q201=" + drilled)}
6  L  X+30  Y+30 R0 FMAX M99
7  CYCL DEF 262 THREAD MILLING ~
    Q335=+10 ;NOMINAL DIAMETER ~
    Q239=+1.5 ;THREAD PITCH ~
    Q201=-12 ;THREAD DEPTH ~
    Q355=+0 ;THREADS PER STEP ~
    Q253=+750 ;F PRE-POSITIONING ~
    Q351=+1 ;CLIMB OR UP-CUT ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q207=+500 ;FEED RATE MILLING ~
    Q512=+0 ;FEED FOR APPROACH
8  L  X+30  Y+30 R0 FMAX M99
9  L  X+70  Y+30 R0 FMAX M99""")


def test_h7_a_thread_mill_needs_half_a_pitch_below_the_thread_in_the_drilled_hole():
    result = check(thread_mill_after_drilling("-12.5"))
    assert lines(result, "heidenhain.thread-deeper-than-hole") == [19]
    assert "Z-12.75" in messages(result, "heidenhain.thread-deeper-than-hole")[0]


def test_h7_a_hole_drilled_deep_enough_or_not_drilled_here_is_not_judged():
    assert not lines(check(thread_mill_after_drilling("-13")), "heidenhain.thread-deeper-than-hole")


# --------------------------------------------------------------------------- H22 R0 to the start point


@pytest.mark.parametrize("positioning, call", [("L  X+30  Y+30 RL FMAX M99", ""), ("L  X+30  Y+30 RR F500", "CYCL CALL"),
                                               ("L  X+30  Y+30 RL F500\nL  X+40  Y+30 R0 FMAX", "CYCL CALL")])
def test_h22_the_last_positioning_before_a_call_must_be_r0(positioning, call):
    text = program(f"5  {DRILL}\n{positioning}\n{call}".rstrip() + "\n")
    called = len(text.splitlines()) - 2  # the call is the body's last line
    reported = lines(check(text), "heidenhain.cycle-with-compensation")
    assert reported == ([] if "R0" in positioning else [called])


def test_h22_a_thread_mill_called_with_rl_is_reported_too():
    """Q351 and the pitch sign set the direction of 262 (§6.13): RL/RR at the call are still wrong."""
    assert lines(check(thread_mill_after_drilling("-13").replace("8  L  X+30  Y+30 R0 FMAX M99", "8  L  X+30  Y+30 RL FMAX M99")),
                 "heidenhain.cycle-with-compensation") == [28]


# --------------------------------------------------------------------------- core rules the map names, on Klartext


def test_h10_rigid_tapping_leaves_a_stopped_spindle_stopped_for_the_next_cut():
    body = "5  " + TAPPING + "\n6  L  X+30  Y+30 R0 FMAX M99\n7  L  X+60 Y+60 FMAX\n8  L  Z-5 F500"  # the next cut goes into the blank
    assert lines(check(program(body, start="L  Z+100 R0 FMAX M5")), "core.spindle-off-cutting") == [14]
    assert not lines(check(program(body)), "core.spindle-off-cutting")


def test_h27_a_retract_level_inside_the_blank_is_reported():
    assert lines(check(program("6  " + DRILL.replace("Q203=+0", "Q203=-5").replace("Q204=+50", "Q204=+0") + "\n7  L  X+50  Y+50 R0 FMAX M99")),
                 "core.clearance-below-stock")
    assert not lines(check(program("6  " + DRILL + "\n7  L  X+50  Y+50 R0 FMAX M99")), "core.clearance-below-stock")


def test_h28_an_in_plane_rapid_below_the_top_of_the_blank_is_reported():
    assert lines(check(program("5  L  X+10  Y+10 R0 FMAX\n6  L  Z-2 F100\n7  L  X+50  Y+50 R0 FMAX")), "core.rapid-into-stock") == [8]  # up out of it, along the axis: nothing new
    assert not lines(check(program("5  L  X+10  Y+10 R0 FMAX\n6  L  Z+2 F100\n7  L  X+50  Y+50 R0 FMAX")), "core.rapid-into-stock")


LU_20 = "[tools.1]\nradius = 5\nusable_length = 20"


def test_h4_face_milling_deeper_than_the_usable_length_is_reported():
    assert lines(check(program(face(top="+0", end="-25")), LU_20), "heidenhain.usable-length") == [11]
    assert not lines(check(program(face()), LU_20), "heidenhain.usable-length")


def test_h4_back_boring_measures_the_counterbore_q249():
    body = """5  CYCL DEF 204 BACK BORING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q249=+{} ;DEPTH OF COUNTERBORE ~
    Q250=+20 ;MATERIAL THICKNESS ~
    Q251=+3.5 ;OFF-CENTER DISTANCE ~
    Q252=+15 ;TOOL EDGE HEIGHT ~
    Q253=+750 ;F PRE-POSITIONING ~
    Q254=+200 ;F COUNTERSINKING ~
    Q255=+0 ;DWELL TIME ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q214=+1 ;DISENGAGING DIRECTN ~
    Q336=+0 ;ANGLE OF SPINDLE
6  L  X+50  Y+50 R0 FMAX M99"""
    assert lines(check(program(body.format(25)), LU_20), "heidenhain.usable-length") == [8]
    assert not lines(check(program(body.format(5)), LU_20), "heidenhain.usable-length")


def pecking(pre_positioning: str, earlier: str = "") -> str:
    return program(f"""{earlier}5  CYCL DEF 205 UNIVERSAL PECKING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q201=-30 ;DEPTH ~
    Q206=+150 ;FEED RATE FOR PLNGNG ~
    Q202=+5 ;PLUNGING DEPTH ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q212=+0 ;DECREMENT ~
    Q205=+0 ;MIN. PLUNGING DEPTH ~
    Q258=+0.2 ;UPPER ADV STOP DIST ~
    Q259=+0.2 ;LOWER ADV STOP DIST ~
    Q257=+0 ;DEPTH FOR CHIP BRKNG ~
    Q256=+0.2 ;DIST FOR CHIP BRKNG ~
    Q211=+0 ;DWELL TIME AT DEPTH ~
    Q379=+10 ;STARTING POINT ~
    Q253={pre_positioning} ;F PRE-POSITIONING
6  L  X+50  Y+50 R0 FMAX M99""")


def test_h30_a_rapid_to_the_deepened_start_point_goes_into_the_blank():
    result = check(pecking("FMAX"))
    assert lines(result, "core.rapid-into-stock") == [22]
    assert cycle_moves(pecking("FMAX"), "heidenhain.205")[:2] == [("rapid", "approach", 2.0), ("rapid", "approach", -8.0)]


def test_h30_the_deepened_start_point_at_a_feed_or_in_a_drilled_hole_is_no_rapid_into_the_blank():
    assert not lines(check(pecking("+750")), "core.rapid-into-stock")
    drilled = "5  " + DRILL + "\n5  L  X+50  Y+50 R0 FMAX M99\n"
    result = check(pecking("FMAX", drilled))
    assert not lines(result, "core.rapid-into-stock")


# --------------------------------------------------------------------------- H15 stud approach


def test_a_stud_whose_approach_lies_on_the_blank_plunges_into_it():
    result = check(program(stud(80)), TOOL_R5)
    assert lines(result, "heidenhain.stud-approach-room") == [24]
    assert "X97" in messages(result, "heidenhain.stud-approach-room")[0]  # 50 + 80/2 + 2 + 5


def test_a_stud_blank_as_large_as_the_blank_leaves_room_to_approach():
    assert not lines(check(program(stud(100)), TOOL_R5), "heidenhain.stud-approach-room")


def test_a_stud_approached_at_a_corner_outside_the_blank_has_room():
    result = check(program(stud(100, approach=3)), TOOL_R5)
    assert not lines(result, "heidenhain.stud-approach-room")


def test_stud_approach_room_without_a_tool_radius_is_unknown():
    result = check(program(stud(80)))
    assert lines(result, "heidenhain.stud-approach-room", Status.UNKNOWN)


# --------------------------------------------------------------------------- H25 pattern in another tool axis


def pattern_program(axis: str) -> str:
    return program(f"""5  PATTERN DEF ~
    POS1( X+25 Y+30 Z+0 ) ~
    POS2( X+75 Y+30 Z+0 )
6  {DRILL}
7  CYCL CALL PAT FMAX""", tool=f"TOOL CALL 1 {axis} S2000", start=f"L  {axis}+100 R0 FMAX M3")


def test_pattern_def_with_the_tool_along_y_is_reported():
    assert lines(check(pattern_program("Y")), "heidenhain.pattern-tool-axis") == [6]


def test_pattern_def_with_the_tool_along_z_is_not():
    assert not lines(check(pattern_program("Z")), "heidenhain.pattern-tool-axis")


# --------------------------------------------------------------------------- H42 working plane


def test_cycle_19_without_every_spatial_angle_is_reported():
    result = check(program("5  CYCL DEF 19.0 WORKING PLANE\n6  CYCL DEF 19.1 B+45\n7  CYCL DEF 19.0 WORKING PLANE\n8  CYCL DEF 19.1"))
    assert lines(result, "heidenhain.working-plane") == [7]


def test_cycle_19_with_all_three_angles_or_none_is_not():
    result = check(program("5  CYCL DEF 19.0 WORKING PLANE\n6  CYCL DEF 19.1 A+0 B+45 C+0\n7  CYCL DEF 19.0 WORKING PLANE\n8  CYCL DEF 19.1"))
    assert not lines(result, "heidenhain.working-plane")


def tilted(moves: str) -> str:
    return program(f"""5  CYCL DEF 19.0 WORKING PLANE
6  CYCL DEF 19.1 A+0 B+45 C+0
7  L  A+Q120 C+Q122 R0 F1000
{moves}
9  {DRILL}
10 CYCL CALL""")


def test_a_cycle_after_a_tilt_before_every_axis_moved_is_reported():
    result = check(tilted("8  L  X+50  Y+50 R0 FMAX"))
    assert lines(result, "heidenhain.working-plane") == [19]
    assert "Z has not been moved" in messages(result, "heidenhain.working-plane")[0]


def test_a_cycle_after_a_tilt_and_a_move_of_every_axis_is_not():
    assert not lines(check(tilted("8  L  Z+80 R0 FMAX\n8  L  X+50  Y+50 R0 FMAX")), "heidenhain.working-plane")


def test_a_definition_after_a_tilt_machines_nothing():
    """A datum shift defined before the axes moved is no cycle machining: only the drilling is."""
    result = check(tilted("8  CYCL DEF 7.0 DATUM SHIFT\n8  CYCL DEF 7.1 X+10\n8  L  X+50  Y+50 R0 FMAX"))
    assert lines(result, "heidenhain.working-plane") == [21]


def test_m94_while_the_plane_is_tilted_is_reported():
    assert lines(check(tilted("8  L  Z+80 R0 FMAX M94\n8  L  X+50  Y+50 R0 FMAX")), "heidenhain.working-plane") == [9]
    assert not lines(check(program("5  L  Z+80 R0 FMAX M94")), "heidenhain.working-plane")


def boring_after(m_function: str) -> str:
    return program(f"""5  {m_function}
6  CYCL DEF 202 BORING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q201=-15 ;DEPTH ~
    Q206=+0.1 ;FEED RATE FOR PLNGNG ~
    Q211=+0.5 ;DWELL TIME AT DEPTH ~
    Q208=+0.2 ;RETRACTION FEED RATE ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q214=+1 ;DISENGAGING DIRECTN ~
    Q336=+0 ;ANGLE OF SPINDLE ~
    Q357=+0.2 ;CLEARANCE TO SIDE
7  L  X+50  Y+50 R0 FMAX M99""")


def test_h17_boring_with_feed_per_revolution_does_not_retract():
    assert lines(check(boring_after("M136")), "heidenhain.boring-feed-per-revolution") == [18]
    assert not lines(check(boring_after("M136\n5  M137")), "heidenhain.boring-feed-per-revolution")


# --------------------------------------------------------------------------- H44 cutting length


def test_a_plunging_depth_beyond_the_cutting_length_is_information():
    result = check(program(stud(100).replace("Q202=+5", "Q202=+12")), TOOL_R5)
    found = [d for d in result.diagnostics if d.rule == "heidenhain.cutting-length" and d.status is Status.VIOLATED]
    assert [d.span.line for d in found] == [18] and found[0].severity.value == "info"


def test_a_plunging_depth_within_the_cutting_length_is_not_reported():
    assert not lines(check(program(stud(100)), TOOL_R5), "heidenhain.cutting-length")


# --------------------------------------------------------------------------- H35 reset order

SHIFT = "CYCL DEF 7.0 DATUM SHIFT\nCYCL DEF 7.1 X+50\n"
SHIFT_RESET = "CYCL DEF 7.0 DATUM SHIFT\nCYCL DEF 7.1 X+0\n"
TILT = "CYCL DEF 19.0 WORKING PLANE\nCYCL DEF 19.1 A+0 B+30 C+0\n"
TILT_RESET = "CYCL DEF 19.0 WORKING PLANE\nCYCL DEF 19.1 A+0 B+0 C+0\n"
ROTATION = "CYCL DEF 10.0 ROTATION\nCYCL DEF 10.1 ROT+45\n"
ROTATION_RESET = "CYCL DEF 10.0 ROTATION\nCYCL DEF 10.1 ROT+0\n"


@pytest.mark.parametrize("defined, reset, reported", [
    (SHIFT + TILT, SHIFT_RESET + TILT_RESET, True),
    (SHIFT + TILT, "TRANS DATUM RESET\n" + TILT_RESET, True),
    (SHIFT + TILT, TILT_RESET + SHIFT_RESET, False),
    (TILT + ROTATION, TILT_RESET + ROTATION_RESET, True),
    (TILT + ROTATION, ROTATION_RESET + TILT_RESET, False),
    (SHIFT + ROTATION, SHIFT_RESET + ROTATION_RESET, False),  # no tilted plane: the order is the manual's only for cycle 19
])
def test_h35_transformations_with_a_tilt_are_reset_in_reverse_order(defined, reset, reported):
    text = program(f"{defined}L  Z+100 R0 FMAX\n{reset}")
    first_reset = 6 + defined.count("\n") + 1 + (0 if reset.startswith("TRANS") else 1)  # the body starts at line 6; x.1 ends a cycle
    assert lines(check(text), "heidenhain.transform-reset-order") == ([first_reset] if reported else [])


@pytest.mark.parametrize("resets", [SHIFT_RESET + "PLANE RESET STAY\n", "PLANE RESET STAY\n" + SHIFT_RESET])
def test_h35_the_cycle_19_order_is_not_asked_of_the_plane_function(resets):
    """The manual's reverse order is written for cycle 19 (seed L8161-8178); a CAM post that
    resets the shift before PLANE RESET is not reported."""
    text = program(f"{SHIFT}PLANE SPATIAL SPA+0 SPB+30 SPC+0 STAY\nL  Z+100 R0 FMAX\n{resets}")
    assert not lines(check(text), "heidenhain.transform-reset-order")


# --------------------------------------------------------------------------- H46 / B H35 pattern compatibility


def circular_slot(position: int) -> str:
    return f"""5  CYCL DEF 254 CIRCULAR SLOT ~
    Q215=+0 ;MACHINING OPERATION ~
    Q219=+12 ;SLOT WIDTH ~
    Q368=+0 ;ALLOWANCE FOR SIDE ~
    Q375=+60 ;PITCH CIRCLE DIAMETR ~
    Q367=+{position} ;REF. SLOT POSITION ~
    Q216=+0 ;CENTER IN 1ST AXIS ~
    Q217=+0 ;CENTER IN 2ND AXIS ~
    Q376=+0 ;STARTING ANGLE ~
    Q248=+45 ;ANGULAR LENGTH ~
    Q378=+0 ;STEPPING ANGLE ~
    Q377=+1 ;NR OF REPETITIONS ~
    Q207=+500 ;FEED RATE MILLING ~
    Q351=+1 ;CLIMB OR UP-CUT ~
    Q201=-5 ;DEPTH ~
    Q202=+5 ;PLUNGING DEPTH ~
    Q369=+0 ;ALLOWANCE FOR FLOOR ~
    Q206=+150 ;FEED RATE FOR PLNGNG ~
    Q338=+0 ;INFEED FOR FINISHING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q366=+0 ;PLUNGE ~
    Q385=+500 ;FINISHING FEED RATE
6  CYCL DEF 221 CARTESIAN PATTERN ~
    Q225=+20 ;STARTNG PNT 1ST AXIS ~
    Q226=+20 ;STARTNG PNT 2ND AXIS ~
    Q237=+60 ;SPACING IN 1ST AXIS ~
    Q238=+60 ;SPACING IN 2ND AXIS ~
    Q242=+2 ;NUMBER OF COLUMNS ~
    Q243=+2 ;NUMBER OF LINES ~
    Q224=+0 ;ANGLE OF ROTATION ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q301=+1 ;MOVE TO CLEARANCE"""


def test_a_circular_slot_centred_on_the_points_of_221_is_refused():
    assert lines(check(program(circular_slot(0))), "heidenhain.pattern-compatibility") == [11]


def test_a_circular_slot_referenced_at_an_end_runs_with_221():
    assert not lines(check(program(circular_slot(1))), "heidenhain.pattern-compatibility")


def datamatrix(machining: str) -> str:
    return program(f"""5  {machining}
6  CYCL DEF 224 DATAMATRIX CODE PATTERN ~
    Q225=+10 ;STARTNG PNT 1ST AXIS ~
    Q226=+10 ;STARTNG PNT 2ND AXIS ~
    QS501="LOT 42" ;TEXT ~
    Q458=+1 ;SIZE SELECTION ~
    Q459=+1 ;SIZE ~
    Q224=+0 ;ANGLE OF ROTATION ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE""")


TAPPING = """CYCL DEF 207 RIGID TAPPING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q201=-10 ;DEPTH ~
    Q239=+1 ;THREAD PITCH ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE"""


def test_datamatrix_224_refuses_a_tapping_cycle():
    result = check(datamatrix(TAPPING))
    assert lines(result, "heidenhain.pattern-compatibility") == [12]
    assert "200, 201, 203, 205, 208, 240, 251, 252" in messages(result, "heidenhain.pattern-compatibility")[0]


def test_datamatrix_224_runs_drilling_at_cells_it_does_not_place():
    result = check(datamatrix(DRILL))
    assert not lines(result, "heidenhain.pattern-compatibility")
    unknown = [d for d in result.diagnostics if d.rule == "core.unsupported-code" and d.span.line == 15]
    assert unknown and "DataMatrix" in unknown[0].message


def test_datamatrix_text_is_read_as_a_string_parameter():
    ops = KlartextLowering().lower(b'6  CYCL DEF 224 DATAMATRIX ~\n    Q225=+10 ;X ~\n    QS501="LOT 42" ;TEXT ~\n    Q458=+1 ;SIZE SELECTION', 6, None)[0].ops
    assert ops[0].params["QS501"] == "LOT 42" and ops[0].params["Q458"] == 1.0


# --------------------------------------------------------------------------- 232 face milling


def test_face_milling_started_below_the_top_of_the_blank_is_reported():
    result = check(program(face(top="-1", end="-3")))
    assert lines(result, "heidenhain.face-milling-blank") == [10]


def test_face_milling_below_the_underside_of_the_blank_is_reported():
    assert lines(check(program(face(end="-25"))), "heidenhain.face-milling-blank") == [11]


def test_face_milling_that_comes_down_on_the_blank_is_reported():
    result = check(program(face(start_x="+10")))
    assert lines(result, "heidenhain.face-milling-blank") == [8]
    assert "X8" in messages(result, "heidenhain.face-milling-blank")[0]


def test_face_milling_started_outside_the_blank_at_its_top_is_not_reported():
    assert not lines(check(program(face())), "heidenhain.face-milling-blank")


def test_face_milling_in_minus_x_starts_after_the_edge_on_the_other_side():
    assert not lines(check(program(face(start_x="+105", length="-100"))), "heidenhain.face-milling-blank")
    assert lines(check(program(face(start_x="+95", length="-100"))), "heidenhain.face-milling-blank") == [8]


@hypothesis_settings(max_examples=15, deadline=None)
@given(st.integers(min_value=-20, max_value=20), st.integers(min_value=0, max_value=5))
def test_face_milling_from_the_other_side_of_the_blank_is_judged_the_same(start, side):
    """The blank spans X0..100: a face from X=start along +X mirrors one from 100-start along -X."""
    def comes_down_on_the_blank(start_x: int, length: str) -> bool:
        return bool(lines(check(program(face(start_x=f"{start_x:+d}", side=f"+{side}", length=length))), "heidenhain.face-milling-blank"))

    assert comes_down_on_the_blank(start, "+100") == comes_down_on_the_blank(100 - start, "-100")


def test_face_milling_levels_upside_down_or_equal():
    assert lines(check(program(face(top="-2", end="+0"))), "heidenhain.positive-depth") == [10]
    assert lines(check(program(face(top="+0", end="+0"))), "heidenhain.zero-depth") == [10]
    assert not lines(check(program(face())), "heidenhain.positive-depth") + lines(check(program(face())), "heidenhain.zero-depth")


def test_face_milling_with_no_plunging_depth_is_out_of_range():
    assert lines(check(program(face().replace("Q202=+2", "Q202=+0"))), "heidenhain.parameter-range") == [14]


def cycle_moves(text: str, cycle: str) -> list[tuple[str, str, object]]:
    """The moves a cycle made: kind, role and the tool-axis level it went to."""
    from test_heidenhain import trace

    return [(segment.kind, segment.role, segment.end.get("Z")) for segment in trace(text).segments if segment.cycle == cycle]


def test_face_milling_goes_down_to_q386_and_retracts_to_the_second_set_up_clearance():
    assert cycle_moves(program(face()), "heidenhain.232") == [("rapid", "approach", 50.0), ("feed", "infeed", -1.0), ("rapid", "out-of-hole", 50.0)]
    assert not lines(check(program(face() + "\n7  L  X+50  Y+50 R0 FMAX")), "core.rapid-into-stock")


# --------------------------------------------------------------------------- 225 engraving


def test_engraving_text_too_long_for_its_length_is_reported():
    result = check(program(engraving(text="SERIAL NUMBER 0001", height="+10")))
    assert lines(result, "heidenhain.engraving-length") == [8]


def test_engraving_text_that_may_fit_is_not_reported():
    assert not lines(check(program(engraving())), "heidenhain.engraving-length")


def test_engraving_scaled_to_its_length_is_never_too_long():
    assert not lines(check(program(engraving(height="+0"))), "heidenhain.engraving-length")


def test_engraving_depth_sign_and_zero():
    assert lines(check(program(engraving(depth="+0.5"))), "heidenhain.positive-depth") == [15]
    assert lines(check(program(engraving(depth="+0"))), "heidenhain.zero-depth") == [15]


def test_engraving_moves_in_at_the_plunging_feed_and_out_to_the_clearances():
    assert cycle_moves(program(engraving()), "heidenhain.225") == [
        ("rapid", "approach", 2.0), ("feed", "infeed", -0.5), ("rapid", "out-of-hole", 2.0), ("rapid", "retract", 50.0)]


@hypothesis_settings(max_examples=15, deadline=None)
@given(st.integers(min_value=2, max_value=40), st.integers(min_value=1, max_value=20), st.integers(min_value=1, max_value=20))
def test_a_longer_text_is_never_judged_to_fit_where_a_shorter_one_does_not(characters, height, more):
    def too_long(count: int) -> bool:
        return bool(lines(check(program(engraving(text="W" * count, height=f"+{height}"))), "heidenhain.engraving-length"))

    if too_long(characters):
        assert too_long(characters + more)


def test_engraved_characters_count_escapes_once_and_take_the_longest_line():
    assert engraved_characters("AB%%C") == 4
    assert engraved_characters("%ae1\\nLONGER") == 6


# --------------------------------------------------------------------------- 18 thread cutting


def test_thread_cutting_from_far_above_the_blank_cuts_nothing():
    assert lines(check(program(thread_cutting(height="+100"))), "heidenhain.thread-cutting-position") == [9]


def test_thread_cutting_pre_positioned_over_the_hole_reaches_the_blank():
    assert not lines(check(program(thread_cutting())), "heidenhain.thread-cutting-position")


def test_thread_cutting_feeds_its_depth_from_where_the_tool_is_and_stays_there():
    assert cycle_moves(program(thread_cutting()), "heidenhain.18") == [("feed", "infeed", -18.0)]
    assert lines(check(program(thread_cutting() + "\n11 L  X+90 FMAX")), "core.rapid-into-stock") == [12]  # out of the thread at Z-18 sideways (then up its own axis)


def test_thread_cutting_with_the_spindle_running_is_reported():
    body = thread_cutting().replace("FMAX M5", "FMAX M3")
    assert lines(check(program(body)), "heidenhain.thread-cutting-spindle") == [11]
    assert not lines(check(program(thread_cutting())), "heidenhain.thread-cutting-spindle")


def test_thread_cutting_pitch_0_is_out_of_range():
    assert lines(check(program(thread_cutting(pitch="+0"))), "heidenhain.parameter-range") == [10]


# --------------------------------------------------------------------------- 9, 12, 13, 32, 238, 239


def test_dwell_orientation_and_tolerance_ranges():
    result = check(program("""5  CYCL DEF 9.0 DWELL TIME
6  CYCL DEF 9.1 DWELL 4000
7  CYCL DEF 13.0 ORIENTATION
8  CYCL DEF 13.1 ANGLE400
9  CYCL DEF 32.0 TOLERANCE
10 CYCL DEF 32.1 T12
11 CYCL DEF 32.2 HSC-MODE:1 TA5"""))
    assert lines(result, "heidenhain.parameter-range") == [7, 9, 11]


def test_dwell_orientation_and_tolerance_in_range_are_not_reported():
    result = check(program("""5  CYCL DEF 9.0 DWELL TIME
6  CYCL DEF 9.1 DWELL 1.5
7  CYCL DEF 13.0 ORIENTATION
8  CYCL DEF 13.1 ANGLE180
9  CYCL DEF 32.0 TOLERANCE
10 CYCL DEF 32.1 T0.05
11 CYCL DEF 32.2 HSC-MODE:1 TA5"""))
    assert not lines(result, "heidenhain.parameter-range")


def program_cycle(folder: Path, called: str | None) -> Path:
    path = folder / "MAIN.h"
    path.write_text(program("5  CYCL DEF 12.0 PGM CALL\n6  CYCL DEF 12.1 PGM PART2.H\n7  L  X+50  Y+50 R0 FMAX M99\n8  L  X+10 R0 FMAX"))
    if called is not None:
        (folder / "PART2.h").write_text(called)
    return path


def test_cycle_12_runs_its_program_at_the_call(tmp_path):
    """B H39: the called program shares the caller's Q parameters and its moves are checked;
    here it leaves the tool in the blank, and the caller's next rapid goes through it."""
    called = "0  BEGIN PGM PART2 MM\n1  L  Z-5 R0 F100\n2  END PGM PART2 MM\n"
    result = check_file(program_cycle(tmp_path, called), Settings())
    assert not lines(result, "heidenhain.call-without-cycle")
    assert lines(result, "core.rapid-into-stock") == [9]


def test_cycle_12_whose_program_is_not_there_is_reported(tmp_path):
    result = check_file(program_cycle(tmp_path, None), Settings())
    assert lines(result, "core.program-not-found", Status.UNKNOWN) == [8]  # it may be stored on the control


def test_cycle_238_and_the_weighing_run_of_239_move_the_machine():
    body = "5  CYCL DEF 238 MEASURE MACHINE STATUS ~\n    Q570=+0 ;MODE\n6  CYCL CALL\n7  CYCL DEF 239 ASCERTAIN THE LOAD ~\n    Q570=+{}\n"
    assert lines(check(program(body.format(1))), "heidenhain.machine-moving-cycle") == [8, 9]
    assert lines(check(program(body.format(0))), "heidenhain.machine-moving-cycle") == [8]


def orientation(redefine: bool) -> str:
    again = "7  CYCL DEF 13.0 ORIENTATION\n8  CYCL DEF 13.1 ANGLE90\n" if redefine else ""
    return program(f"""5  CYCL DEF 202 BORING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q201=-15 ;DEPTH ~
    Q206=+100 ;FEED RATE FOR PLNGNG ~
    Q211=+0.5 ;DWELL TIME AT DEPTH ~
    Q208=+250 ;RETRACTION FEED RATE ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q214=+1 ;DISENGAGING DIRECTN ~
    Q336=+0 ;ANGLE OF SPINDLE ~
    Q357=+0.2 ;CLEARANCE TO SIDE
6  L  X+50  Y+50 R0 FMAX M99
{again}9  L  Z+100 R0 FMAX M19""")


def test_m19_after_boring_without_cycle_13_is_reported():
    assert lines(check(orientation(False)), "heidenhain.orientation-after-cycle") == [18]
    assert not lines(check(orientation(True)), "heidenhain.orientation-after-cycle")


def test_rigid_tapping_on_a_machine_without_a_servo_spindle_is_refused():
    body = "5  " + TAPPING + "\n6  L  X+30  Y+30 R0 FMAX M99"
    result = check(program(body), "[machine]\nspindle_encoder = false")
    assert lines(result, "heidenhain.servo-spindle") == [6]
    assert "cycle 207 RIGID TAPPING" in messages(result, "heidenhain.servo-spindle")[0]
    assert not lines(check(program(body), "[machine]\nspindle_encoder = true"), "heidenhain.servo-spindle")
    assert lines(check(program(body)), "heidenhain.servo-spindle", Status.UNKNOWN) == [6]


def test_thread_cutting_18_needs_the_servo_spindle_too():
    assert lines(check(program(thread_cutting()), "[machine]\nspindle_encoder = false"), "heidenhain.servo-spindle") == [11]


# --------------------------------------------------------------------------- point tables


def table_program(folder: Path, table: str | None) -> Path:
    """Holes 25 deep in a 20 mm blank, at the points of HOLES.PNT."""
    path = folder / "HOLES.h"
    path.write_text(program(f'5  SEL PATTERN "HOLES.PNT"\n6  {DRILL.replace("Q201=-15", "Q201=-25")}\n7  CYCL CALL PAT FMAX'))
    if table is not None:
        (folder / "HOLES.PNT").write_text(table)
    return path


def test_a_point_table_beside_the_program_places_the_holes(tmp_path):
    table = "BEGIN HOLES.PNT MM\nNR X Y Z FADE\n0 +20 +20 +0\n1 +80 +20 +0\n2 +150 +150 +0 Y\n[END]\n"
    result = check_file(table_program(tmp_path, table), Settings())
    assert lines(result, "heidenhain.depth-through-blank", Status.UNKNOWN) == [9]  # a through hole: the set-up decides
    assert not [d for d in result.diagnostics if d.rule == "core.unsupported-code" and d.span.line in (6, 16)]


def test_a_point_table_that_is_not_there_leaves_the_points_unknown(tmp_path):
    result = check_file(table_program(tmp_path, None), Settings())
    unknown = [d.message for d in result.diagnostics if d.rule == "core.unsupported-code" and d.span.line == 6]
    assert unknown and "HOLES.PNT" in unknown[0]
    assert not [d for d in result.diagnostics if d.rule == "heidenhain.depth-through-blank"]


# --------------------------------------------------------------------------- the manual's own templates

MANUAL = Path(__file__).resolve().parents[2] / "shared" / "manuals" / "001_4d9f06b2742d891d.txt"


@pytest.mark.skipif(not MANUAL.is_file(), reason="the TNC 620 cycle manual is not beside the repository")
def test_the_233_template_faces_from_q227_0_to_q386_0_which_the_control_skips():
    """Seed L7480-7528 prints Q227=+0 and Q386=+0: a true finding on the manual's template."""
    from test_heidenhain_manual import _check, _framed

    result = _check(_framed(7480, 7528), "c233.h")
    assert any(d.rule == "heidenhain.zero-depth" and "Q227" in d.message for d in result.diagnostics)


# --------------------------------------------------------------------------- H29: the point angle T-ANGLE

POINT_ANGLE_TABLE = """BEGIN TOOL.T MM
T    NAME                             L           R           LCUTS   ANGLE   LU      T-ANGLE
1    DRILL_D8                         +95.5       +4          30      0       40      {angle}
[END]
"""

CENTRING = """5  CYCL DEF 240 CENTERING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q343=+1 ;SELECT DIA./DEPTH ~
    Q201=-2 ;DEPTH ~
    Q344=-9 ;DIAMETER ~
    Q206=+250 ;FEED RATE FOR PLNGNG ~
    Q211=+0 ;DWELL TIME AT DEPTH ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE ~
    Q342=+0 ;ROUGHING DIAMETER
6  L  X+30  Y+30 R0 FMAX M99"""


@pytest.mark.parametrize("angle, reported", [("0", True), ("", True), ("118", False)])
def test_centring_to_a_diameter_needs_the_point_angle_of_tool_t(tmp_path, angle, reported):
    (tmp_path / "TOOL.T").write_text(POINT_ANGLE_TABLE.format(angle=angle))
    part = tmp_path / "part.h"
    part.write_text(program(CENTRING))
    found = lines(check_file(part, Settings()), "heidenhain.point-angle")
    assert found == ([6] if reported else [])  # the CYCL DEF block


def test_the_point_angle_of_a_project_tool_that_does_not_give_it_is_unknown():
    result = check(program(CENTRING), "[tools.1]\nradius = 4")
    assert lines(result, "heidenhain.point-angle", Status.UNKNOWN) == [6]
    assert not lines(result, "heidenhain.point-angle")


def test_the_depth_of_centring_to_a_diameter_is_not_compared_with_the_usable_length_and_says_so():
    result = check(program(CENTRING), "[tools.1]\nradius = 4\nusable_length = 1")
    assert lines(result, "heidenhain.usable-length", Status.UNKNOWN) == [6] and not lines(result, "heidenhain.usable-length")


def test_centring_by_depth_needs_no_point_angle():
    result = check(program(CENTRING.replace("Q343=+1", "Q343=+0")), "[tools.1]\nradius = 4\npoint_angle = 0")
    assert not lines(result, "heidenhain.point-angle") and not lines(result, "heidenhain.point-angle", Status.UNKNOWN)


# Cycle 200 drills X+30 Y+30 from Z0 down to Z-2 only, then 207 taps there and at X+70 Y+70,
# where this program drills nothing, from Q203=-6 + Q200=2 = Z-4
DRILL_THEN_TAP = """0  BEGIN PGM TAPS MM
1  BLK FORM 0.1 Z X+0 Y+0 Z-20
2  BLK FORM 0.2  X+100  Y+100  Z+0
3  TOOL CALL 1 Z S2000
4  L  Z+50 R0 FMAX M3
5  CYCL DEF 200 DRILLING ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q201=-2 ;DEPTH ~
    Q206=+150 ;FEED RATE FOR PLNGNG ~
    Q202=+5 ;PLUNGING DEPTH ~
    Q210=+0 ;DWELL TIME AT TOP ~
    Q203=+0 ;SURFACE COORDINATE ~
    Q204=+50 ;2ND SET-UP CLEARANCE
6  L  X+30  Y+30 R0 FMAX M99
7  TOOL CALL 2 Z S400
8  CYCL DEF 207 RIGID TAPPING NEW ~
    Q200=+2 ;SET-UP CLEARANCE ~
    Q201=-8 ;DEPTH ~
    Q239=+1.5 ;THREAD PITCH ~
    Q203=-6 ;SURFACE COORDINATE ~
    Q204=+56 ;2ND SET-UP CLEARANCE
9  L  X+30  Y+30 R0 FMAX M99
10 L  X+70  Y+70 R0 FMAX M99
11 L  Z+50 R0 FMAX M30
12 END PGM TAPS MM
"""


def test_a_tap_where_this_program_drilled_nothing_goes_down_an_earlier_hole_unknown_not_a_crash():
    result = check(DRILL_THEN_TAP)
    rapids = {(d.span.line, d.status) for d in result.diagnostics if d.rule == "core.rapid-into-stock"}
    assert (23, Status.UNKNOWN) in rapids and (23, Status.VIOLATED) not in rapids


def test_a_tap_below_the_bottom_of_a_hole_this_program_drilled_is_still_a_crash():
    """The program drilled X+30 Y+30 only to Z-2: the tap's rapid to Z-4 enters solid material."""
    result = check(DRILL_THEN_TAP)
    assert 22 in lines(result, "core.rapid-into-stock")
