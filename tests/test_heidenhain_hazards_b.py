"""HEIDENHAIN Klartext part B: contour, contour-train, OCM and cylinder-surface hazards.

``HAZARDS`` maps every item of reference B §9 to the rules that check it, or to the reason
it is not checked; the tests below run each rule on a small program both ways.
"""
from __future__ import annotations

import textwrap

import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_text
from ncverify.check import rule_definitions
from ncverify.diagnostics import Status

# Reference B §9, item -> rule ids (a comment says where the coverage is partial) or the
# reason the item is not decided from the program text.
HAZARDS: dict[int, tuple[str, ...] | str] = {
    # A. contour definition
    1: ("heidenhain.contour-compensation",),  # R0 / no RL-RR in a cycle-14 SL subcontour; the kind itself feeds tool-too-large
    2: ("heidenhain.contour-overlap-start",),  # the first subcontour against each overlapping later one
    # 3: "not closed" is not reported: the manual's own islands end short of their start (seed L10829-10853), the control closes them
    3: ("heidenhain.contour-subprogram", "heidenhain.contour-feed"),  # M functions with no modelled effect (M110 ...) are not seen; label numbers 0-65535 unchecked
    4: ("heidenhain.contour-compensation",),  # 270 and CONTOUR DEF; the contour programs DECLARE CONTOUR names are not read
    5: ("heidenhain.contour-subprogram",),
    6: ("heidenhain.contour-subprogram",),
    7: ("heidenhain.contour-def",),  # CONTOUR DEF counts, DECLARE CONTOUR count and DEPTH all-or-none; the contour programs themselves are not read
    8: ("heidenhain.contour-def",),  # DEPTH against the cycle depth; island heights are not compared with the surface
    9: ("heidenhain.contour-def",),
    10: ("heidenhain.tolerance",),  # the form is checked; a fit's band (ISO 286 tables) is not computed, its size stays unknown
    # B. heights, depths, directions
    11: ("heidenhain.positive-depth", "heidenhain.zero-depth"),
    12: ("heidenhain.parameter-range",),  # 275 Q202 > 0; a Q10 sign unlike Q1 is left alone (the manual's own examples mix them)
    13: ("heidenhain.sl-clearance-height",),
    14: ("heidenhain.sl-clearance-height",),
    15: ("core.rapid-into-stock",),  # the approach to Q203 + Q200 and the retract are judged against the blank; Q204 < Q200 itself is not reported
    16: ("heidenhain.below-clearance-height",),  # 276; 225 is part of the special cycles
    17: ("core.rapid-into-stock",),  # the moves between pattern points are judged against the blank
    18: ("heidenhain.face-milling-blank", "heidenhain.positive-depth", "heidenhain.zero-depth", "heidenhain.parameter-range"),  # Q227 vs Q386 and the blank, Q202 > 0
    19: ("heidenhain.cylinder-clearance", "heidenhain.cylinder-radius"),
    # C. tool vs geometry
    20: ("heidenhain.sl-allowance",),  # Q3 = 0, Q14 < Q3, Q14 + R_finish < Q3 + R_rough, and Q3 > Q14 + R for a single island
    21: ("heidenhain.tool-too-large", "heidenhain.residual-material", "heidenhain.plunge-angle"),  # R + Q3 against the resolved pocket: none of it reachable is an error, a neck or small inside radius residual material (a warning); Q19 with ANGLE 0; centre cutting is not in TOOL.T
    22: ("heidenhain.usable-length", "heidenhain.cutting-length"),  # LU against the depth; Q202 against LCUTS
    23: ("heidenhain.tool-too-large",),  # shapes 1271-1273 and 1278 with R (1 + Q578) + Q368; corners of free OCM contours not checked
    24: ("heidenhain.sl-allowance",),  # 274 Q14 < Q368, and Q368 > Q14 + R for a single island
    25: ("heidenhain.parameter-range", "heidenhain.point-angle"),  # Q353 < 0 and |Q353| >= |Q359|, T-ANGLE given; Q354 against T-ANGLE/2 is not judged (uncertain)
    26: ("heidenhain.ocm-tool-corner",),
    27: ("heidenhain.slot-width", "heidenhain.plunge-angle"),
    28: ("heidenhain.slot-width",),  # 28's width; the room 29 and 39 need beside the contour is not modelled
    29: "whether an end mill cuts over centre is not a tool-table column: it cannot be decided from the program and TOOL.T",
    30: ("heidenhain.cylinder-spindle",),  # spindle state; the axis kinematics and the centring on the table are not in the program
    31: ("heidenhain.pilot-drill",),  # the drill against the rougher Q13; the plunge point itself is the control's
    # D. modal traps and sequencing
    32: ("heidenhain.position-after-cycle",),
    33: ("heidenhain.sl-prerequisites",),  # 14 / 20 / 271 before the call; T-ANGLE for 277 is not a tool-table column ncverify reads
    34: ("heidenhain.call-without-cycle",),  # a pattern with no machining cycle before it; the extra CYCL CALL after 220/221 is not warned
    35: ("heidenhain.pattern-compatibility",),
    36: ("heidenhain.sl-q-parameters",),  # Q1-Q20 set before an SL call or a DECLARE CONTOUR; contour programs behind SEL CONTOUR are not run
    37: ("heidenhain.rougher-forgotten",),  # after CONTOUR DEF; SEL CONTOUR is not modelled
    38: "not a defect by itself: the cycles run with the data of the reaching definition, which is what the model does",
    39: "not reported: the program cycle 12 calls runs like CALL PGM, its Q writes reach the caller as on the control; no rule warns about them",
    40: ("heidenhain.orientation-after-cycle",),
    41: ("heidenhain.thread-cutting-position", "heidenhain.thread-cutting-spindle"),  # the pitch sign against M3/M4 is not compared
    42: ("heidenhain.machine-moving-cycle",),  # the override limits of 239 are not in the program
    43: ("heidenhain.engraving-length",),  # Q202 = 0 with Q201 != 0 is not reported (its meaning is not stated)
    44: ("heidenhain.face-milling-blank",),
    45: ("core.syntax",),  # a parameter line without '~' ends the block: the next Q line does not read
}


def test_every_part_b_hazard_is_mapped_to_existing_rules_or_a_reason():
    assert sorted(HAZARDS) == list(range(1, 46))
    known = rule_definitions()
    for item, checked in HAZARDS.items():
        if isinstance(checked, str):
            assert checked.strip(), item
        else:
            assert checked and all(rule_id in known for rule_id in checked), (item, checked)


# --------------------------------------------------------------------------- programs

def program(body: str, blank: str = "BLK FORM 0.1 Z X+0 Y+0 Z-20\n2  BLK FORM 0.2  X+100  Y+100  Z+0") -> str:
    """A 100 x 100 x 20 blank, tool 1 at Z+100 with the spindle on, ``body``, then M30."""
    lines = ["0  BEGIN PGM T MM", f"1  {blank}", "3  TOOL CALL 1 Z S2000", "4  L  Z+100 R0 FMAX M3"]
    lines += textwrap.dedent(body).strip("\n").splitlines()
    return "\n".join(lines + ["99 END PGM T MM"]) + "\n"


from conftest import project


def check(text: str, tools: str = ""):
    return check_text(text, "t.h", Settings(dialect="heidenhain"), project(tools))


def findings(result, rule: str, status=Status.VIOLATED) -> list:
    return [d for d in result.diagnostics if d.rule == rule and d.status is status]


def contour_data(depth="-10", side="+0.5", clearance_height="+50") -> str:
    return (f"CYCL DEF 20 CONTOUR DATA ~\n    Q1={depth} ;MILLING DEPTH ~\n    Q2=+1 ;TOOL PATH OVERLAP ~\n    Q3={side} ;ALLOWANCE FOR SIDE ~\n"
            f"    Q4=+0.2 ;ALLOWANCE FOR FLOOR ~\n    Q5=+0 ;SURFACE COORDINATE ~\n    Q6=+2 ;SET-UP CLEARANCE ~\n    Q7={clearance_height} ;CLEARANCE HEIGHT ~\n"
            "    Q8=+0 ;ROUNDING RADIUS ~\n    Q9=+1 ;ROTATIONAL DIRECTION\n")


ROUGH = "CYCL DEF 22 ROUGH-OUT ~\n    Q10=-5 ;PLUNGING DEPTH ~\n    Q11=+100 ;FEED RATE FOR PLNGNG ~\n    Q12=+350 ;FEED RATE F. ROUGHNG ~\n    Q18=+0 ;COARSE ROUGHING TOOL ~\n    Q19=+150 ;FEED RATE FOR RECIP.\n"
SQUARE = "LBL 1\nL  X+10  Y+10 RR\nL  Y+90\nL  X+90\nL  Y+10\nL  X+10\nLBL 0\n"


def sl_program(subprograms: str = SQUARE, labels: str = "1", data: str | None = None, cycle: str = ROUGH) -> str:
    return program(f"CYCL DEF 14.0 CONTOUR GEOMETRY\nCYCL DEF 14.1 CONTOUR LABEL{labels}\n{data or contour_data()}{cycle}CYCL CALL\n"
                   f"L  Z+100 R0 FMAX M30\n{subprograms}")


def train(depth="-5", clearance_height="+50", surface="+0") -> str:
    return (f"CYCL DEF 25 CONTOUR TRAIN ~\n    Q1={depth} ;MILLING DEPTH ~\n    Q3=+0 ;ALLOWANCE FOR SIDE ~\n    Q5={surface} ;SURFACE COORDINATE ~\n"
            f"    Q7={clearance_height} ;CLEARANCE HEIGHT ~\n    Q10=-5 ;PLUNGING DEPTH ~\n    Q11=+100 ;FEED RATE FOR PLNGNG ~\n"
            "    Q12=+350 ;FEED RATE F. ROUGHNG ~\n    Q15=+1 ;CLIMB OR UP-CUT\n")


def trochoidal(width="+15", depth="-10", plunge="+5") -> str:
    return (f"CYCL DEF 275 TROCHOIDAL SLOT ~\n    Q215=+0 ;MACHINING OPERATION ~\n    Q219={width} ;SLOT WIDTH ~\n    Q368=+0.2 ;ALLOWANCE FOR SIDE ~\n"
            f"    Q436=+2 ;INFEED PER REV. ~\n    Q207=+500 ;FEED RATE MILLING ~\n    Q351=+1 ;CLIMB OR UP-CUT ~\n    Q201={depth} ;DEPTH ~\n"
            f"    Q202={plunge} ;PLUNGING DEPTH ~\n    Q206=+150 ;FEED RATE FOR PLNGNG ~\n    Q338=+0 ;INFEED FOR FINISHING ~\n"
            "    Q385=+500 ;FINISHING FEED RATE ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n    Q203=+0 ;SURFACE COORDINATE ~\n    Q204=+50 ;2ND SET-UP CLEARANCE ~\n"
            "    Q366=+0 ;PLUNGE ~\n    Q369=+0.1 ;ALLOWANCE FOR FLOOR ~\n    Q439=+0 ;FEED RATE REFERENCE\n")


CLOSED_SLOT = "LBL 1\nL  X+50  Y+20\nL  X+70\nL  Y+80\nL  X+30\nL  Y+20\nL  X+50\nLBL 0\n"
OPEN_LINE = "LBL 1\nL  X+0  Y+15 RL\nL  X+50  Y+15\nLBL 0\n"
TOOL_R5 = "[tools.1]\nradius = 5"


def train_program(cycle: str, subprograms: str, labels: str = "1", after: str = "L  X+0  Y+0 R0 FMAX") -> str:
    return program(f"CYCL DEF 14.0 CONTOUR GEOMETRY\nCYCL DEF 14.1 CONTOUR LABEL{labels}\n{cycle}CYCL CALL\n{after}\nL  Z+100 R0 FMAX M30\n{subprograms}")


# --------------------------------------------------------------------------- A. contour definition


@pytest.mark.parametrize("line, what", [("L  Y+90 F500", "a feed rate F"), ("L  Y+90 M8", "an M function")])
def test_a_feed_rate_or_m_function_in_the_contour_subprogram_is_reported_at_its_block(line, what):
    text = sl_program(SQUARE.replace("L  Y+90", line))
    result = check(text)
    assert [d.span.line for d in findings(result, "heidenhain.contour-feed")] == [text.splitlines().index(line) + 1]
    assert what in findings(result, "heidenhain.contour-feed")[0].message
    assert not findings(result, "heidenhain.contour-subprogram")
    assert not findings(check(sl_program()), "heidenhain.contour-feed")


@pytest.mark.parametrize("line, what", [("L  X+90  Z-5", "a tool-axis coordinate"), ("APPR LT X+90  Y+90 LEN5 RR", "an APPR/DEP block"),
                                        ("CYCL DEF 200 DRILLING", "a cycle definition")])
def test_what_a_contour_subprogram_may_not_hold(line, what):
    result = check(sl_program(SQUARE.replace("L  X+90\n", line + "\n")))
    assert any(what in d.message for d in findings(result, "heidenhain.contour-subprogram")), [d.message for d in result.diagnostics]


def test_a_coordinate_transformation_in_a_subcontour_is_allowed():
    result = check(sl_program(SQUARE.replace("L  X+90\n", "L  X+90\nCYCL DEF 7.0 DATUM SHIFT\nCYCL DEF 7.1 X+0\n")))
    assert not findings(result, "heidenhain.contour-subprogram")


def test_a_first_block_with_one_axis_is_reported_but_a_contour_ending_short_of_its_start_is_not():
    """The manual's own island contours end on the line back to their start (seed L10829-10853):
    the control closes them."""
    ending_short = "LBL 1\nL  X+27  Y+50 RL\nL  Y+58\nL  X+43\nL  Y+42\nL  X+27\nLBL 0\n"
    assert not findings(check(sl_program(SQUARE + ending_short.replace("LBL 1", "LBL 2"), labels="1 /2")), "heidenhain.contour-subprogram")
    one_axis = "LBL 1\nL  X+10 RR\nL  Y+90\nL  X+90\nL  Y+10\nL  X+10\nLBL 0\n"
    assert any("does not program Y" in d.message for d in findings(check(sl_program(one_axis)), "heidenhain.contour-subprogram"))


def test_an_sl_subcontour_without_rl_or_rr_is_ambiguous():
    result = check(sl_program(SQUARE.replace("Y+10 RR", "Y+10 R0")))
    assert findings(result, "heidenhain.contour-compensation")
    assert not findings(check(sl_program()), "heidenhain.contour-compensation")


def test_rl_rr_with_contour_def_is_reported():
    body = ("CONTOUR DEF P1 = LBL 1\n" + contour_data() + ROUGH + "CYCL CALL\nL  Z+100 R0 FMAX M30\n")
    assert findings(check(program(body + SQUARE)), "heidenhain.contour-compensation")
    assert not findings(check(program(body + SQUARE.replace(" RR", ""))), "heidenhain.contour-compensation")


CIRCLES = "LBL 1\nCC X+35  Y+50\nL  X+{x}  Y+50 RR\nC  X+{x}  Y+50 DR-\nLBL 0\nLBL 2\nCC X+65  Y+50\nL  X+{bx}  Y+50 {side}\nC  X+{bx}  Y+50 DR-\nLBL 0\n"


def test_two_overlapping_pockets_where_the_first_starts_inside_the_second_give_their_intersection():
    inside = check(sl_program(CIRCLES.format(x=60, bx=90, side="RR"), labels="1 /2"))
    assert "intersection" in findings(inside, "heidenhain.contour-overlap-start")[0].message
    assert not findings(check(sl_program(CIRCLES.format(x=10, bx=90, side="RR"), labels="1 /2")), "heidenhain.contour-overlap-start")
    free = check(sl_program(CIRCLES.format(x="Q50", bx=90, side="RR"), labels="1 /2"))  # where LBL 1 starts is a free parameter
    assert findings(free, "heidenhain.contour-overlap-start", Status.UNKNOWN) and not findings(free, "heidenhain.contour-overlap-start")


def test_an_island_must_start_inside_the_pocket_it_is_taken_from():
    outside = check(sl_program(CIRCLES.format(x=10, bx=90, side="RL"), labels="1 /2"))  # B's start X90 is outside A
    assert "island LBL 2 starts outside" in findings(outside, "heidenhain.contour-overlap-start")[0].message
    inside = check(sl_program(CIRCLES.format(x=10, bx=40, side="RL"), labels="1 /2"))
    assert not findings(inside, "heidenhain.contour-overlap-start")


def test_contour_trains_take_one_subprogram():
    result = check(train_program(train(), OPEN_LINE + OPEN_LINE.replace("LBL 1", "LBL 2"), labels="1 /2"))
    assert "only the first" in findings(result, "heidenhain.contour-subprogram")[0].message
    assert not findings(check(train_program(train(), OPEN_LINE)), "heidenhain.contour-subprogram")


def test_a_closed_trochoidal_slot_starts_with_a_line_away_from_a_corner_and_an_open_one_with_appr():
    at_corner = CLOSED_SLOT.replace("L  X+50  Y+20\n", "L  X+30  Y+20\n", 1).replace("L  Y+20\nL  X+50\n", "L  Y+20\n")
    assert "a corner" in findings(check(train_program(trochoidal(), at_corner), TOOL_R5), "heidenhain.contour-subprogram")[0].message
    assert not findings(check(train_program(trochoidal(), CLOSED_SLOT), TOOL_R5), "heidenhain.contour-subprogram")
    opened = "LBL 1\nL  X+0  Y+50\nL  X+100\nLBL 0\n"
    assert "APPR" in findings(check(train_program(trochoidal(), opened), TOOL_R5), "heidenhain.contour-subprogram")[0].message
    approached = "LBL 1\nAPPR LT X+10  Y+50 LEN5 RL\nL  X+100\nLBL 0\n"
    assert not findings(check(train_program(trochoidal(), approached), TOOL_R5), "heidenhain.contour-subprogram")


def test_contour_def_depths_and_limits():
    def body(definition):
        return program(f"{definition}\n" + contour_data() + ROUGH + "CYCL CALL\nL  Z+100 R0 FMAX M30\n" + SQUARE.replace(" RR", ""))
    assert findings(check(body("CONTOUR DEF P1 = LBL 1 I2 = LBL 1 DEPTH12")), "heidenhain.contour-def")
    assert not findings(check(body("CONTOUR DEF P1 = LBL 1 I2 = LBL 1 DEPTH8")), "heidenhain.contour-def")
    many = " ".join(f"I{index} = LBL 1" for index in range(2, 12))
    assert "at most 9" in findings(check(body(f"CONTOUR DEF P1 = LBL 1 {many}")), "heidenhain.contour-def")[0].message


def ocm_data(boundary="+0") -> str:
    return ("CYCL DEF 271 OCM CONTOUR DATA ~\n    Q203=+0 ;SURFACE COORDINATE ~\n    Q201=-10 ;DEPTH ~\n    Q368=+0.2 ;ALLOWANCE FOR SIDE ~\n"
            "    Q369=+0.1 ;ALLOWANCE FOR FLOOR ~\n    Q260=+50 ;CLEARANCE HEIGHT ~\n    Q578=+0.2 ;INSIDE CORNER FACTOR ~\n"
            f"    Q569={boundary} ;OPEN BOUNDARY\n")


def finishing_side(rougher="-1", allowance="+0") -> str:
    return ("CYCL DEF 274 OCM FINISHING SIDE ~\n    Q338=+0 ;INFEED FOR FINISHING ~\n    Q385=+500 ;FINISHING FEED RATE ~\n"
            f"    Q253=+750 ;F PRE-POSITIONING ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n    Q14={allowance} ;ALLOWANCE FOR SIDE ~\n"
            f"    Q438={rougher} ;ROUGH-OUT TOOL ~\n    Q351=+1 ;CLIMB OR UP-CUT\n")


def test_q569_says_what_follows_the_first_contour():
    square2 = SQUARE.replace(" RR", "") + SQUARE.replace(" RR", "").replace("LBL 1", "LBL 2")
    def run(definition, boundary):
        return check(program(f"{definition}\n{ocm_data(boundary)}{finishing_side()}CYCL CALL\nL  Z+100 R0 FMAX M30\n{square2}"))
    assert findings(run("CONTOUR DEF P1 = LBL 1 P2 = LBL 2", "+1"), "heidenhain.contour-def")
    assert not findings(run("CONTOUR DEF P1 = LBL 1 I2 = LBL 2", "+1"), "heidenhain.contour-def")


# --------------------------------------------------------------------------- B. heights and depths


@pytest.mark.parametrize("depth, rule", [("+5", "heidenhain.positive-depth"), ("+0", "heidenhain.zero-depth")])
def test_contour_train_depth_sign_and_zero(depth, rule):
    assert findings(check(train_program(train(depth=depth), OPEN_LINE)), rule)
    assert not findings(check(train_program(train(), OPEN_LINE)), rule)


def test_trochoidal_slot_plunging_depth_must_be_positive():
    assert findings(check(train_program(trochoidal(plunge="-5"), CLOSED_SLOT), TOOL_R5), "heidenhain.parameter-range")
    assert not findings(check(train_program(trochoidal(), CLOSED_SLOT), TOOL_R5), "heidenhain.parameter-range")


def test_contour_train_clearance_height_inside_the_blank():
    assert findings(check(train_program(train(clearance_height="-1"), OPEN_LINE)), "heidenhain.sl-clearance-height")
    assert not findings(check(train_program(train(), OPEN_LINE)), "heidenhain.sl-clearance-height")


def three_d(clearance_height="+50") -> str:
    return (f"CYCL DEF 276 THREE-D CONT. TRAIN ~\n    Q1=-5 ;MILLING DEPTH ~\n    Q3=+0 ;ALLOWANCE FOR SIDE ~\n    Q7={clearance_height} ;CLEARANCE HEIGHT ~\n"
            "    Q10=-5 ;PLUNGING DEPTH ~\n    Q11=+150 ;FEED RATE FOR PLNGNG ~\n    Q12=+500 ;FEED RATE F. ROUGHNG ~\n    Q15=+1 ;CLIMB OR UP-CUT\n")


@given(height=st.integers(min_value=1, max_value=99))
@hypothesis_settings(max_examples=15, deadline=None)
def test_276_is_reported_exactly_when_called_below_its_clearance_height(height):
    contour = "LBL 1\nL  X+0  Y+50  Z+0 RL\nL  X+100  Z-5\nLBL 0\n"
    text = program(f"CYCL DEF 14.0 CONTOUR GEOMETRY\nCYCL DEF 14.1 CONTOUR LABEL1\n{three_d('+50')}L  Z+{height} R0 FMAX\nCYCL CALL\n"
                   f"L  Z+100 R0 FMAX\nL  X+0  Y+0 R0 FMAX M30\n{contour}")
    assert bool(findings(check(text), "heidenhain.below-clearance-height")) == (height < 50)


def cylinder(number=27, q6="+5", q16="+25", spindle=" M3", extra="") -> str:
    title = {27: "CYLINDER SURFACE", 28: "CYLINDRICAL SURFACE SLOT", 29: "CYL SURFACE RIDGE", 39: "CYL. SURFACE CONTOUR"}[number]
    return ("0  BEGIN PGM CYL MM\n1  BLK FORM CYLINDER Z R25 L100\n2  TOOL CALL 1 Z S2000\n"
            f"3  L  Z+250 R0 FMAX{spindle}\n4  CYCL DEF 14.0 CONTOUR GEOMETRY\n5  CYCL DEF 14.1 CONTOUR LABEL1\n"
            f"6  CYCL DEF {number} {title} ~\n    Q1=-7 ;MILLING DEPTH ~\n    Q3=+0 ;ALLOWANCE FOR SIDE ~\n    Q6={q6} ;SET-UP CLEARANCE ~\n"
            "    Q10=-4 ;PLUNGING DEPTH ~\n    Q11=+100 ;FEED RATE FOR PLNGNG ~\n    Q12=+250 ;FEED RATE F. ROUGHNG ~\n"
            f"    Q16={q16} ;RADIUS ~\n    Q17=+1 ;TYPE OF DIMENSION{extra}\n7  L  C+0 R0 FMAX M99\n8  L  Z+250 R0 FMAX M30\n"
            "9  LBL 1\n10 L  X+40  Y-20 RL\n11 L  X+50\n12 L  Y-60\n13 L  X+30\n14 L  Y-20\n15 L  X+40\n16 LBL 0\n17 END PGM CYL MM\n")


def test_cylinder_set_up_clearance_must_exceed_the_tool_radius():
    assert "Q6=2" in findings(check(cylinder(q6="+2"), "[tools.1]\nradius = 3.5"), "heidenhain.cylinder-clearance")[0].message
    assert not findings(check(cylinder(q6="+4"), "[tools.1]\nradius = 3.5"), "heidenhain.cylinder-clearance")
    assert findings(check(cylinder(q6="+2")), "heidenhain.cylinder-clearance", Status.UNKNOWN)


def test_cylinder_radius_is_that_of_the_blank_and_the_position_after_is_unknown():
    result = check(cylinder(q16="+20"))
    assert findings(result, "heidenhain.cylinder-radius")
    assert any("unrolled surface" in d.message for d in findings(result, "core.unsupported-code", Status.UNKNOWN))
    assert not findings(check(cylinder()), "heidenhain.cylinder-radius")


# --------------------------------------------------------------------------- C. tool against geometry


def test_cylinder_slot_and_ridge_need_the_spindle_running():
    slot = " ~\n    Q20=+12 ;SLOT WIDTH ~\n    Q21=+0 ;TOLERANCE"
    assert findings(check(cylinder(28, spindle="", extra=slot)), "heidenhain.cylinder-spindle")
    assert not findings(check(cylinder(28, extra=slot)), "heidenhain.cylinder-spindle")
    assert not findings(check(cylinder(27, spindle="")), "heidenhain.cylinder-spindle")  # 27 is not named by the manual


@pytest.mark.parametrize("width, reported", [("+8", True), ("+10", False), ("+15", False), ("+20", False), ("+21", True)])
def test_trochoidal_slot_width_lies_between_the_tool_diameter_and_twice_it(width, reported):
    result = check(train_program(trochoidal(width=width), CLOSED_SLOT), TOOL_R5)
    assert bool(findings(result, "heidenhain.slot-width")) == reported


def test_cylinder_slot_narrower_than_the_tool_plus_allowances():
    slot = lambda width: f" ~\n    Q20={width} ;SLOT WIDTH ~\n    Q21=+0 ;TOLERANCE"
    assert findings(check(cylinder(28, extra=slot("+6")), "[tools.1]\nradius = 3.5"), "heidenhain.slot-width")
    assert not findings(check(cylinder(28, extra=slot("+7")), "[tools.1]\nradius = 3.5"), "heidenhain.slot-width")


def test_ocm_side_finishing_allowance_below_the_roughing_allowance():
    body = lambda allowance: program(f"CONTOUR DEF P1 = LBL 1\n{ocm_data()}{finishing_side('+5', allowance)}CYCL CALL\nL  Z+100 R0 FMAX M30\n" + SQUARE.replace(" RR", ""))
    assert findings(check(body("+0.3")), "heidenhain.sl-allowance")
    assert not findings(check(body("+0.1")), "heidenhain.sl-allowance")


def chamfer(tip="-3", width="+1") -> str:
    return (f"CYCL DEF 277 OCM CHAMFERING ~\n    Q353={tip} ;DEPTH OF TOOL TIP ~\n    Q359={width} ;CHAMFER WIDTH ~\n    Q207=+500 ;FEED RATE MILLING ~\n"
            "    Q253=+750 ;F PRE-POSITIONING ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n    Q438=+5 ;ROUGH-OUT TOOL ~\n    Q351=+1 ;CLIMB OR UP-CUT ~\n"
            "    Q354=+0 ;CHAMFER ANGLE\n")


@pytest.mark.parametrize("tip, width, reported", [("-3", "+1", False), ("+2", "+1", True), ("-1", "+2", True), ("-2", "-2", False)])
def test_chamfer_tip_depth(tip, width, reported):
    text = program(f"CONTOUR DEF P1 = LBL 1\n{ocm_data()}{chamfer(tip, width)}CYCL CALL\nL  Z+100 R0 FMAX M30\n" + SQUARE.replace(" RR", ""))
    assert bool(findings(check(text), "heidenhain.parameter-range")) == reported


def test_ocm_chamfering_plunges_to_the_tip_depth_and_retracts_to_q260():
    text = program(f"CONTOUR DEF P1 = LBL 1\n{ocm_data()}{chamfer()}CYCL CALL\nL  Z+100 R0 FMAX M30\n" + SQUARE.replace(" RR", ""))
    result = check(text)
    assert not findings(result, "core.unsupported-code", Status.UNKNOWN)
    assert not findings(result, "heidenhain.sl-prerequisites")


# --------------------------------------------------------------------------- D. sequencing


def test_an_incremental_move_after_a_contour_train_is_reported():
    assert findings(check(train_program(train(), OPEN_LINE, after="L  IX+20 R0 FMAX")), "heidenhain.position-after-cycle")
    assert not findings(check(train_program(train(), OPEN_LINE)), "heidenhain.position-after-cycle")


def test_contour_trains_and_cylinder_cycles_need_cycle_14():
    without = program(f"{train()}CYCL CALL\nL  Z+100 R0 FMAX M30\n")
    assert "cycle 14" in findings(check(without), "heidenhain.sl-prerequisites")[0].message
    assert not findings(check(train_program(train(), OPEN_LINE)), "heidenhain.sl-prerequisites")


def test_cycle_270_is_def_active_and_forbids_compensation_in_the_subprogram():
    data = "CYCL DEF 270 CONTOUR TRAIN DATA ~\n    Q390=+1 ;TYPE OF APPROACH ~\n    Q391=+1 ;RADIUS COMPENSATION ~\n    Q392=+3 ;RADIUS ~\n    Q393=+90 ;CENTER ANGLE ~\n    Q394=+0 ;DISTANCE\n"
    result = check(train_program(data + train(), OPEN_LINE))
    assert findings(result, "heidenhain.contour-compensation")
    assert not [d for d in result.diagnostics if d.rule == "core.unsupported-code" and "270" in d.message]
    assert not findings(check(train_program(data + train(), OPEN_LINE.replace(" RL", ""))), "heidenhain.contour-compensation")


def test_program_values_in_q1_to_q20_clash_with_sl_cycles():
    clash = sl_program().replace("4  L  Z+100 R0 FMAX M3", "4  L  Z+100 R0 FMAX M3\nQ3 = 5")
    assert findings(check(clash), "heidenhain.sl-q-parameters")
    assert not findings(check(sl_program().replace("4  L  Z+100 R0 FMAX M3", "4  L  Z+100 R0 FMAX M3\nQ30 = 5")), "heidenhain.sl-q-parameters")


def test_finishing_with_q438_minus_1_after_contour_def_without_roughing():
    body = lambda rougher, before="": program(f"CONTOUR DEF P1 = LBL 1\n{ocm_data()}{before}{finishing_side(rougher)}CYCL CALL\nL  Z+100 R0 FMAX M30\n"
                                              + SQUARE.replace(" RR", ""))
    assert findings(check(body("-1")), "heidenhain.rougher-forgotten")
    assert not findings(check(body("+5")), "heidenhain.rougher-forgotten")


def test_ocm_with_a_corner_radius_tool_is_warned():
    circle = ("CYCL DEF 1272 OCM CIRCLE ~\n    Q650=+0 ;FIGURE TYPE ~\n    Q223=+50 ;CIRCLE DIAMETER ~\n    Q367=+0 ;POSITION ~\n"
              "    Q203=+0 ;SURFACE COORDINATE ~\n    Q201=-10 ;DEPTH ~\n    Q368=+0.2 ;ALLOWANCE FOR SIDE ~\n    Q369=+0.1 ;ALLOWANCE FOR FLOOR ~\n"
              "    Q260=+50 ;CLEARANCE HEIGHT ~\n    Q578=+0.2 ;INSIDE CORNER FACTOR\n")
    rough = ("CYCL DEF 272 OCM ROUGHING ~\n    Q202=+5 ;PLUNGING DEPTH ~\n    Q370=+0.4 ;TOOL PATH OVERLAP ~\n    Q207=+500 ;FEED RATE MILLING ~\n"
             "    Q568=+0.6 ;PLUNGING FACTOR ~\n    Q253=+750 ;F PRE-POSITIONING ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n    Q438=+0 ;ROUGH-OUT TOOL\n")
    text = program(f"{circle}{rough}L  X+50  Y+50 R0 FMAX M99\nL  Z+100 R0 FMAX M30\n")
    assert findings(check(text, "[tools.1]\nradius = 5\ncorner = 1"), "heidenhain.ocm-tool-corner")
    assert not findings(check(text, "[tools.1]\nradius = 5"), "heidenhain.ocm-tool-corner")
    assert findings(check(text), "heidenhain.ocm-tool-corner", Status.UNKNOWN)  # no tool table: not known, not clean


def with_tool_table(text: str, tmp_path, radius: float, angle: float):
    """Check ``text`` as a file with a TOOL.T beside it (a project file cannot give ANGLE 0)."""
    from ncverify import check_file

    (tmp_path / "TOOL.T").write_text("BEGIN TOOL.T MM\nT    NAME        L        R        ANGLE   LU\n"
                                     f"1    MILL        +60      +{radius:<7g} {angle:<7g} 50\n[END]\n")
    part = tmp_path / "part.h"
    part.write_text(text)
    return check_file(part, Settings())


@pytest.mark.parametrize("angle, reported", [(0, True), (5, False)])
def test_rough_out_with_a_reciprocating_feed_needs_the_tool_angle(tmp_path, angle, reported):
    assert bool(findings(with_tool_table(sl_program(), tmp_path, 4, angle), "heidenhain.plunge-angle")) == reported
    vertical = sl_program(cycle=ROUGH.replace("Q19=+150", "Q19=+0"))
    assert not findings(with_tool_table(vertical, tmp_path, 4, 0), "heidenhain.plunge-angle")


def test_a_reciprocating_trochoidal_plunge_needs_the_tool_angle(tmp_path):
    reciprocating = train_program(trochoidal().replace("Q366=+0", "Q366=+2"), CLOSED_SLOT)
    assert findings(with_tool_table(reciprocating, tmp_path, 5, 0), "heidenhain.plunge-angle")
    assert not findings(with_tool_table(reciprocating, tmp_path, 5, 3), "heidenhain.plunge-angle")
    assert not findings(with_tool_table(train_program(trochoidal(), CLOSED_SLOT), tmp_path, 5, 0), "heidenhain.plunge-angle")


# --------------------------------------------------------------------------- motion


def cycle_moves(text: str, cycle: str) -> list[tuple[str, str, object]]:
    """The moves a cycle made: kind, role and the tool-axis level it went to."""
    from test_heidenhain import trace

    return [(segment.kind, segment.role, segment.end.get("Z")) for segment in trace(text).segments if segment.cycle == cycle]


def test_contour_train_feeds_down_to_q5_plus_q1_and_leaves_the_tool_at_q7():
    assert cycle_moves(train_program(train(surface="+2"), OPEN_LINE), "heidenhain.25") == [("feed", "infeed", -3.0), ("rapid", "out-of-hole", 50.0)]
    assert cycle_moves(train_program(train(depth="+0"), OPEN_LINE), "heidenhain.25") == []  # depth 0: skipped


def test_trochoidal_slot_has_the_levels_of_a_pocket():
    assert cycle_moves(train_program(trochoidal(), CLOSED_SLOT), "heidenhain.275") == [
        ("rapid", "approach", 2.0), ("feed", "infeed", -10.0), ("rapid", "out-of-hole", 50.0)]


def test_276_only_knows_its_clearance_height_and_ocm_chamfering_plunges_to_the_tip_depth():
    contour = "LBL 1\nL  X+0  Y+50  Z+0 RL\nL  X+100  Z-5\nLBL 0\n"
    text = program(f"CYCL DEF 14.0 CONTOUR GEOMETRY\nCYCL DEF 14.1 CONTOUR LABEL1\n{three_d()}CYCL CALL\nL  X+0  Y+0 R0 FMAX M30\n{contour}")
    assert cycle_moves(text, "heidenhain.276")[-1] == ("rapid", "out-of-hole", 50.0)
    text = program(f"CONTOUR DEF P1 = LBL 1\n{ocm_data()}{chamfer()}CYCL CALL\nL  Z+100 R0 FMAX M30\n" + SQUARE.replace(" RR", ""))
    assert cycle_moves(text, "heidenhain.277") == [("rapid", "approach", 2.0), ("feed", "infeed", -3.0), ("rapid", "out-of-hole", 50.0)]


def test_after_a_cylinder_cycle_the_position_is_unknown_until_every_axis_is_given():
    from test_heidenhain import trace

    text = cylinder()
    after = [segment for segment in trace(text).segments if segment.span.line == text.splitlines().index("8  L  Z+250 R0 FMAX M30") + 1]
    assert after and after[0].start.get("Z") is None and after[0].end.get("Z") == 250.0


FINISH_SIDE = ("CYCL DEF 24 SIDE FINISHING ~\n    Q9=+1 ;ROTATIONAL DIRECTION ~\n    Q10=-5 ;PLUNGING DEPTH ~\n    Q11=+100 ;FEED RATE FOR PLNGNG ~\n"
               "    Q12=+350 ;FEED RATE F. ROUGHNG ~\n    Q14=+0.1 ;ALLOWANCE FOR SIDE ~\n    Q438={rougher} ;ROUGH-OUT TOOL\n")
TWO_TOOLS = "[tools.1]\nradius = 5\n[tools.2]\nradius = {finisher}"


@pytest.mark.parametrize("finisher, reported", [(5.5, True), (5.3, False)])
def test_side_finishing_tool_and_allowance_fit_inside_what_the_rougher_left(finisher, reported):
    """Q14 + R_finish < Q3 + R_rough: 0.1 + R against 0.5 + 5 (Q438 = -1: the tool of the last 22)."""
    text = sl_program(cycle=ROUGH + "CYCL CALL\nTOOL CALL 2 Z S3000\nL  Z+100 R0 FMAX M3\n" + FINISH_SIDE.format(rougher="-1"))
    assert bool(findings(check(text, TWO_TOOLS.format(finisher=finisher)), "heidenhain.sl-allowance")) == reported


def test_side_finishing_with_no_roughing_compares_with_a_rougher_of_radius_0():
    text = sl_program(cycle="TOOL CALL 2 Z S3000\n" + FINISH_SIDE.format(rougher="+0"))
    assert findings(check(text, TWO_TOOLS.format(finisher=3)), "heidenhain.sl-allowance")  # 0.1 + 3 >= 0.5 + 0


PILOT = "CYCL DEF 21 PILOT DRILLING ~\n    Q10=-5 ;PLUNGING DEPTH ~\n    Q11=+100 ;FEED RATE FOR PLNGNG ~\n    Q13={rougher} ;ROUGH-OUT TOOL\n"


@pytest.mark.parametrize("rougher, reported", [("+2", True), ("+3", False), ("+0", False)])
def test_pilot_drill_no_wider_than_the_rougher_it_drills_for(rougher, reported):
    tools = "[tools.1]\nradius = 4\n[tools.2]\nradius = 3\n[tools.3]\nradius = 5"
    assert bool(findings(check(sl_program(cycle=PILOT.format(rougher=rougher)), tools), "heidenhain.pilot-drill")) == reported


def test_cycle_14_takes_at_most_twelve_labels():
    labels = "1" + "".join(f" /{index}" for index in range(2, 14))
    subprograms = "".join(SQUARE.replace("LBL 1", f"LBL {index}") for index in range(1, 14))
    assert "at most 12" in findings(check(sl_program(subprograms, labels=labels)), "heidenhain.contour-subprogram")[0].message
    assert not findings(check(sl_program(subprograms, labels=labels.rsplit(" /", 1)[0])), "heidenhain.contour-subprogram")


@pytest.mark.parametrize("text, size", [("10+0.01-0.015", 9.9975), ("10m", 10.0), ("60", None), ("10H", None), ("10h7", "fit"), ("10js6", "fit"), ("10Hh7", None)])
def test_toleranced_sizes_read_as_the_middle_of_their_band(text, size):
    from ncverify.interpret.heidenhain.tolerance import toleranced

    found = toleranced(text)
    if size == "fit":
        assert found is not None and type(found) is not float
    elif size is None:
        assert found is None
    else:
        assert found == pytest.approx(size)


def test_an_unreadable_tolerance_is_reported_and_a_readable_one_sizes_the_pocket():
    def shape(diameter):
        return ("CYCL DEF 1272 OCM CIRCLE ~\n    Q650=+0 ;FIGURE TYPE ~\n    Q223=" + diameter + " ;CIRCLE DIAMETER ~\n    Q367=+0 ;POSITION ~\n"
                "    Q203=+0 ;SURFACE COORDINATE ~\n    Q201=-10 ;DEPTH ~\n    Q368=+0.2 ;ALLOWANCE FOR SIDE ~\n    Q369=+0.1 ;ALLOWANCE FOR FLOOR ~\n"
                "    Q260=+50 ;CLEARANCE HEIGHT ~\n    Q578=+0.2 ;INSIDE CORNER FACTOR\n")
    rough = ("CYCL DEF 272 OCM ROUGHING ~\n    Q202=+5 ;PLUNGING DEPTH ~\n    Q370=+0.4 ;TOOL PATH OVERLAP ~\n    Q207=+500 ;FEED RATE MILLING ~\n"
             "    Q568=+0.6 ;PLUNGING FACTOR ~\n    Q253=+750 ;F PRE-POSITIONING ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n    Q438=+0 ;ROUGH-OUT TOOL\n")
    def run(diameter):
        return check(program(f"{shape(diameter)}{rough}L  X+50  Y+50 R0 FMAX M99\nL  Z+100 R0 FMAX M30\n"), TOOL_R5)
    assert findings(run('"50+0.05"'), "heidenhain.tolerance")
    readable = run('"50+0.05-0"')
    assert not findings(readable, "heidenhain.tolerance") and not findings(readable, "heidenhain.tool-too-large")
    assert findings(run('"12+0.05-0"'), "heidenhain.tool-too-large")  # a 12 mm circle is too small for the 10 mm tool: the size was read
    assert findings(run('"50H7"'), "heidenhain.tool-too-large", Status.UNKNOWN)


def test_overlapping_pockets_are_combined_by_their_start_points():
    """Cycle 14: the first pocket starting outside the second gives the union, inside it the
    intersection (seed L9254-9320); CONTOUR DEF pockets are always joined."""
    from shapely.geometry import Polygon

    from ncverify.interpret.heidenhain.contour import Contour, region

    first, second = Polygon([(0, 0), (20, 0), (20, 10), (0, 10)]), Polygon([(10, 0), (30, 0), (30, 10), (10, 10)])
    outside, inside = Contour(1, first, True, (0.0, 0.0)), Contour(1, first, True, (15.0, 5.0))
    other = Contour(2, second, True, (30.0, 0.0))
    assert region([outside, other], by_start_points=True).area == pytest.approx(300.0)
    assert region([inside, other], by_start_points=True).area == pytest.approx(100.0)
    assert region([inside, other]).area == pytest.approx(300.0)


def polygon(diameter="+40", circumscribed="+0", corners="+6") -> str:
    return ("CYCL DEF 1278 OCM POLYGON ~\n    Q650=+0 ;FIGURE TYPE ~\n    Q573=" + circumscribed + " ;REFERENCE CIRCLE ~\n    Q571=" + diameter + " ;REF-CIRCLE DIAMETER ~\n"
            "    Q572=" + corners + " ;NUMBER OF CORNERS ~\n    Q660=+0 ;CORNER TYPE ~\n    Q220=+0 ;CORNER RADIUS ~\n    Q224=+0 ;ANGLE OF ROTATION ~\n"
            "    Q203=+0 ;SURFACE COORDINATE ~\n    Q201=-10 ;DEPTH ~\n    Q368=+0.2 ;ALLOWANCE FOR SIDE ~\n    Q369=+0.1 ;ALLOWANCE FOR FLOOR ~\n"
            "    Q260=+50 ;CLEARANCE HEIGHT ~\n    Q578=+0.2 ;INSIDE CORNER FACTOR\n")


@pytest.mark.parametrize("diameter, circumscribed, reported", [("+12.5", "+0", False), ("+12.5", "+1", True), ("+12", "+0", True)])
def test_a_polygon_pocket_must_hold_the_tool(diameter, circumscribed, reported):
    """R 5 x 1.2 + 0.2 = 6.2 against the inscribed radius: D 12.5 inscribed fits, D 12.5 as the
    circumscribed circle of a hexagon is 10.8 inscribed and does not, nor does D 12."""
    rough = ("CYCL DEF 272 OCM ROUGHING ~\n    Q202=+5 ;PLUNGING DEPTH ~\n    Q370=+0.4 ;TOOL PATH OVERLAP ~\n    Q207=+500 ;FEED RATE MILLING ~\n"
             "    Q568=+0.6 ;PLUNGING FACTOR ~\n    Q253=+750 ;F PRE-POSITIONING ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n    Q438=+0 ;ROUGH-OUT TOOL\n")
    text = program(f"{polygon(diameter, circumscribed)}{rough}L  X+50  Y+50 R0 FMAX M99\nL  Z+100 R0 FMAX M30\n")
    assert bool(findings(check(text, TOOL_R5), "heidenhain.tool-too-large")) == reported


def contour_definition(*declarations: str, own: str = "") -> str:
    lines = ["0  BEGIN PGM MODEL MM", *(f"DECLARE CONTOUR {declaration}" for declaration in declarations), *own.splitlines(),
             "QC10 = ( QC1 | QC2 ) \\ QC3", "99 END PGM MODEL MM"]
    return "\n".join(lines) + "\n"


def test_a_contour_definition_program_reads_and_gives_a_depth_to_all_contours_or_none():
    clean = check(contour_definition('QC1 = "120"', 'QC2 = "121"', 'QC3 = "122"'))
    assert not [d for d in clean.diagnostics if d.status is Status.VIOLATED]
    mixed = check(contour_definition('QC1 = "120"', 'QC2 = "121" DEPTH15', 'QC3 = "122"'))
    assert [d.span.line for d in findings(mixed, "heidenhain.contour-def")] == [3]
    assert not findings(check(contour_definition('QC1 = "120" DEPTH0', 'QC2 = "121" DEPTH15', 'QC3 = "122" DEPTH5')), "heidenhain.contour-def")


def test_a_contour_definition_program_setting_q1_to_q20_is_warned():
    text = contour_definition('QC1 = "120"', 'QC2 = "121"', own="Q3 = 25\nQ103 = 4").replace("QC10", 'DECLARE CONTOUR QC3 = "122"\nQC10')
    assert "Q3" in findings(check(text), "heidenhain.sl-q-parameters")[0].message
    assert not findings(check(text.replace("Q3 = 25", "Q23 = 25")), "heidenhain.sl-q-parameters")


ISLAND = "LBL 1\nL  X+30  Y+30 RL\nL  Y+70\nL  X+70\nL  Y+30\nL  X+30\nLBL 0\n"  # clockwise with RL: an island


@pytest.mark.parametrize("side, reported", [("+0.5", True), ("+6", False)])
def test_side_finishing_a_single_island_needs_an_allowance_beyond_q14_plus_the_radius(side, reported):
    text = sl_program(ISLAND, data=contour_data(side=side), cycle=FINISH_SIDE.format(rougher="+0"))
    result = check(text, "[tools.1]\nradius = 5")
    assert bool([d for d in findings(result, "heidenhain.sl-allowance") if "single island" in d.message]) == reported


@pytest.mark.parametrize("side, reported", [("+0.2", True), ("+6", False)])
def test_ocm_side_finishing_of_a_single_island(side, reported):
    text = program(f"CONTOUR DEF I1 = LBL 1\n{ocm_data().replace('Q368=+0.2', 'Q368=' + side)}{finishing_side('+5')}CYCL CALL\nL  Z+100 R0 FMAX M30\n"
                   + ISLAND.replace(" RL", ""))
    result = check(text, TOOL_R5)
    assert bool([d for d in findings(result, "heidenhain.sl-allowance") if "single island" in d.message]) == reported


def circle(label: int, x: int, start_angle: int, radius: int = 20) -> str:
    """A clockwise (RR: pocket) full circle round X``x`` Y50 starting at ``start_angle``."""
    return f"LBL {label}\nCC  X+{x}  Y+50\nLP  PR+{radius}  PA+{start_angle} RR\nCP  IPA-360 DR-\nLBL 0\n"


def dumbbell(channel_low: int, channel_high: int) -> str:
    """Two 30 x 30 recesses joined by a channel from Y``channel_low`` to Y``channel_high``."""
    return (f"LBL 1\nL  X+10  Y+10 RR\nL  Y+40\nL  X+40\nL  Y+{channel_high}\nL  X+60\nL  Y+40\nL  X+90\nL  Y+10\nL  X+60\n"
            f"L  Y+{channel_low}\nL  X+40\nL  Y+10\nL  X+10\nLBL 0\n")


def test_the_corners_where_two_circular_pockets_overlap_are_the_tools_own_fillet():
    """Each circle starts inside the other: the pocket is their lens-shaped overlap, whose
    two sharp corners any round tool fills with its radius, as in a square corner."""
    lens = check(sl_program(circle(1, 40, 0) + circle(2, 60, 180), labels="1 /2"), TOOL_R5)
    assert not findings(lens, "heidenhain.tool-too-large") and not findings(lens, "heidenhain.residual-material")
    assert not findings(lens, "heidenhain.tool-too-large", Status.UNKNOWN)  # the lens was resolved and judged


def test_a_neck_narrower_than_the_tool_is_residual_material_not_an_alarm():
    result = check(sl_program(dumbbell(22, 28)), TOOL_R5)
    assert not findings(result, "heidenhain.tool-too-large")
    [residual] = findings(result, "heidenhain.residual-material")
    assert residual.severity.value == "warning"
    assert "2 place(s)" in residual.message and "a neck 6 wide" in residual.message
    assert "a tool up to R2.5 reaches it" in residual.message  # 3 - Q3 0.5
    assert not findings(check(sl_program(dumbbell(19, 31)), TOOL_R5), "heidenhain.residual-material")  # 12 wide > 2 (5 + 0.5)


def test_a_pocket_smaller_than_the_tool_is_not_machined_at_all():
    small = "LBL 1\nL  X+10  Y+10 RR\nL  Y+20\nL  X+20\nL  Y+10\nL  X+10\nLBL 0\n"  # 10 x 10 against R 5 + Q3 0.5
    result = check(sl_program(small), TOOL_R5)
    [error] = findings(result, "heidenhain.tool-too-large")
    assert "cannot enter" in error.message and "machines none of it" in error.message and "largest tool radius that clears it is 4.5" in error.message
    assert not findings(result, "heidenhain.residual-material")
    assert not findings(check(sl_program(small, data=contour_data(side="+0")), "[tools.1]\nradius = 4.9"), "heidenhain.tool-too-large")


@pytest.mark.parametrize("infeed, reported", [("+12", True), ("+10", False)])
def test_ocm_roughing_plunging_deeper_than_the_cutting_length_is_clipped(infeed, reported):
    """272: Q202 > LCUTS is cut at LCUTS per infeed, with a warning (seed L11277-11279)."""
    rough = (f"CYCL DEF 272 OCM ROUGHING ~\n    Q202={infeed} ;PLUNGING DEPTH ~\n    Q370=+0.4 ;TOOL PATH OVERLAP ~\n    Q207=+500 ;FEED RATE MILLING ~\n"
             "    Q568=+0.6 ;PLUNGING FACTOR ~\n    Q253=+750 ;F PRE-POSITIONING ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n    Q438=+0 ;ROUGH-OUT TOOL\n")
    text = program(f"{polygon()}{rough}L  X+50  Y+50 R0 FMAX M99\nL  Z+100 R0 FMAX M30\n")
    found = findings(check(text, TOOL_R5 + "\ncutting_length = 10"), "heidenhain.cutting-length")
    assert bool(found) == reported
    assert not reported or ("Q202=12" in found[0].message and "LCUTS=10" in found[0].message and "L11277" in found[0].message)
