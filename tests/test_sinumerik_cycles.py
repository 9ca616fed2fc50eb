"""SINUMERIK cycles: the contour rules of CYCLE95, CYCLE73-75 and CYCLE950, the swivel,
high-speed and engraving calls, the alarms derived from the alarm tables, and the motion of
the milling cycles (approach at RTP, depth, retract, where the tool is left)."""
from __future__ import annotations

import textwrap

import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

import ncverify.api
from ncverify import Settings, check_text
from ncverify.check import Checker
from ncverify.diagnostics import Status

MILL_HEAD = """\
$TC_DP1[1,1]=120
$TC_DP6[1,1]={radius}
N10 G17 G90 G54 T1 D1 M6
N20 S3000 M3 F500
N30 G0 X0 Y0 Z50
"""
LATHE_HEAD = """\
$TC_DP1[1,1]=500
$TC_DP6[1,1]=0.8
N10 G18 G90 G54 DIAMON
N20 T1 D1
N30 G96 S200 LIMS=3000 M3 G95 F0.25
"""


def check(program: str, machine: str | None = None):
    settings = Settings(dialect="sinumerik", machine=machine) if machine else Settings(dialect="sinumerik")
    return check_text(textwrap.dedent(program).lstrip("\n"), "t.mpf", settings)


def milled(body: str, radius: float = 5):
    return check(MILL_HEAD.format(radius=radius) + textwrap.dedent(body).lstrip("\n") + "N900 M30\n")


def turned(body: str):
    return check(LATHE_HEAD + textwrap.dedent(body).lstrip("\n"), machine="lathe")


def messages(result, rule: str) -> list[str]:
    return [d.message for d in result.diagnostics if d.rule == rule and d.status is Status.VIOLATED]


# --------------------------------------------------------------------------- CYCLE95 overhangs

SHAFT = """\
N40 G0 X90 Z5
N50 CYCLE95("SHAFT_CONTOUR", 2.5, 0.1, 0.2, 0, 0.3, 0.15, 0.1, {vari})
N60 G0 X100 Z50
N70 M30

%_N_SHAFT_CONTOUR_SPF
N10 G1 X20 Z0
N20 X40 Z-20
N30 Z-40
N40 X{x} Z{z}
N50 Z-60
N60 M17
"""


def test_a_contour_turning_back_along_z_is_an_overhang_for_longitudinal_machining():
    found = messages(turned(SHAFT.format(vari=9, x=60, z=-35)), "sinumerik.contour-direction")
    assert found and "turns back along Z from Z-40 to Z-35" in found[0]


def test_an_undercut_that_keeps_moving_along_z_is_machined():
    assert not messages(turned(SHAFT.format(vari=9, x=30, z=-45)), "sinumerik.contour-direction")


def test_face_machining_judges_the_facing_axis():
    """The same contour is monotone in X except where it falls back from X40 to X30."""
    assert messages(turned(SHAFT.format(vari=10, x=30, z=-45)), "sinumerik.contour-direction")
    assert not messages(turned(SHAFT.format(vari=10, x=60, z=-45)), "sinumerik.contour-direction")


# --------------------------------------------------------------------------- CYCLE73-75

POCKET = """\
N40 GOTOF MACHINING
EDGE_START:
N100 G{first} X10 Y10
N110 G1 X90
N120 Y60
N130 X10{rounded}
N140 Y{close}
EDGE_END:
MACHINING:
N200 CYCLE74("", "EDGE_START", "EDGE_END")
N210 CYCLE73(1011, "", "POCKET_MILL", "{tool}", 10, 0, 1, -8, 0, 2, {stepover}, 0.2, 0.1, 500, 200, 0)
N220 G0 Z50
"""
GOOD_POCKET = {"first": 0, "rounded": "", "close": 10, "tool": "1", "stepover": 4}


@pytest.mark.parametrize("change, expected", [
    ({"close": 60}, "ends at X10 Y60, not at its start X10 Y10: would raise alarm 61901"),
    ({"first": 1}, "reaches its first point with G1"),
    ({"rounded": " RND=3", "close": "10 CHF=2"}, "carries RND/CHF"),
    ({"tool": ""}, "alarm 61984"),
    ({"stepover": 9}, "more than 80 % of the diameter 10 of tool T1 (at most 8): would raise alarm 61982"),
])
def test_pocket_contour_defects(change, expected):
    found = messages(milled(POCKET.format(**{**GOOD_POCKET, **change})), "sinumerik.pocket-contour")
    assert any(expected in message for message in found), found


def test_a_closed_pocket_contour_with_a_fitting_call_is_accepted():
    assert not messages(milled(POCKET.format(**GOOD_POCKET)), "sinumerik.pocket-contour")


def test_cycle73_with_the_tool_on_a_contour_start_point():
    program = POCKET.format(**GOOD_POCKET).replace("N210", "N205 G0 X10 Y10\nN210")
    found = messages(milled(program), "sinumerik.pocket-contour")
    assert found and "on the start point X10 Y10" in found[0]


def test_the_cycle73_stepover_without_a_tool_radius_is_unknown():
    program = MILL_HEAD.format(radius=5).replace("$TC_DP6[1,1]=5\n", "") + POCKET.format(**{**GOOD_POCKET, "stepover": 9}) + "N900 M30\n"
    result = check(program)
    unknown = [d.message for d in result.diagnostics if d.rule == "sinumerik.pocket-contour" and d.status is Status.UNKNOWN]
    assert any("_MIDA against 80 % of the diameter (61982)" in message for message in unknown), unknown


def test_a_cycle74_naming_nothing_raises_61900():
    assert any("61900" in message for message in messages(milled('N40 CYCLE74("", "", "")\n'), "sinumerik.pocket-contour"))


def test_a_pocket_contour_program_that_is_not_there_is_unknown():
    result = milled('N40 CYCLE74("EDGE_NOT_HERE")\n')
    assert [d for d in result.diagnostics if d.rule == "sinumerik.pocket-contour" and d.status is Status.UNKNOWN]


# --------------------------------------------------------------------------- CYCLE950

EXTENDED = """\
N40 G0 X90 Z5
N50 CYCLE950({finished}, "ROUGH_PART", 311311, 2, 0.1, 0.1, 0.3, 0.1, 0.1, 0.1, 1, 0, 1, "", "BLANK_START", "BLANK_END")
N60 G0 X100 Z50
N70 GOTOF PROGRAM_END
PART_START:
N100 G1 X20 Z0
N110 X{diameter} Z-20
N120 Z-50
PART_END:
BLANK_START:
N200 G1 X0 Z0
N210 X50
N220 Z-50
N230 X0
N240 Z{close}
BLANK_END:
PROGRAM_END:
N900 M30
"""


@pytest.mark.parametrize("finished, diameter, close, expected", [
    ('"", "", ""', 40, 0, "61701"),
    ('"", "PART_START", "PART_END"', 40, -10, "ends at Z-10 X0, not at its start Z0 X0: would raise alarm 61740"),
    ('"", "PART_START", "PART_END"', 60, 0, "reaches Z-20 X60, outside the blank contour"),
])
def test_extended_stock_removal_defects(finished, diameter, close, expected):
    found = messages(turned(EXTENDED.format(finished=finished, diameter=diameter, close=close)), "sinumerik.extended-stock-removal")
    assert any(expected in message for message in found), found


def test_a_finished_contour_inside_a_closed_blank_is_accepted():
    result = turned(EXTENDED.format(finished='"", "PART_START", "PART_END"', diameter=40, close=0))
    assert not messages(result, "sinumerik.extended-stock-removal")


def _unknown(result, rule: str) -> list[str]:
    return [d.message for d in result.diagnostics if d.rule == rule and d.status is Status.UNKNOWN]


def test_contours_whose_points_are_not_numbers_are_unknown():
    extended = EXTENDED.format(finished='"", "PART_START", "PART_END"', diameter=40, close=0).replace("N230 X0", "N230 X=R5")
    assert any("BLANK_START..BLANK_END" in message and "not all known numbers" in message for message in _unknown(turned(extended), "sinumerik.extended-stock-removal"))
    pocket = POCKET.format(**GOOD_POCKET).replace("N120 Y60", "N120 Y=R5")
    assert any("whether it is closed (61901)" in message for message in _unknown(milled(pocket), "sinumerik.pocket-contour"))
    shaft = SHAFT.format(vari=9, x=30, z=-45).replace("N30 Z-40", "N30 Z=R5")
    assert any("turns back" in message for message in _unknown(turned(shaft), "sinumerik.contour-direction"))


# --------------------------------------------------------------------------- CYCLE800, CYCLE832, CYCLE60

@pytest.mark.parametrize("call, expected", [
    ('CYCLE800(3, "", 0, 57, 0, 0, 0, 15, 0, 0, 0, 0, 0, -1)', "61183"),
    ('CYCLE800(1, "", 0, 25, 0, 0, 0, 15, 0, 0, 0, 0, 0, -1)', "rotates axis-wise about XYX"),
    ('CYCLE800(1, "", 0, 192, 0, 0, 0, 15, 0, 0, 0, 0, 0, -1)', "angle type bits 11"),
    ('CYCLE800(1, "", 1, 57, 0, 0, 0, 15, 0, 0, 0, 0, 0, -1)', "swivels additively"),
])
def test_swivel_plane_defects(call, expected):
    found = messages(milled(f"N40 {call}\nN50 CYCLE800()\n"), "sinumerik.swivel-plane")
    assert any(expected in message for message in found), found


def test_a_swivel_under_g500_and_with_d0():
    found = messages(milled('N40 G500 D0\nN50 CYCLE800(1, "", 0, 57, 0, 0, 0, 15, 0, 0, 0, 0, 0, -1)\n'), "sinumerik.swivel-plane")
    assert any("61189" in message for message in found) and any("no tool offset" in message for message in found)


def test_the_manuals_swivel_calls_are_accepted():
    body = 'N40 CYCLE800(1, "", 0, 57, 0, 40, 0, -45, 0, 0, 0, 0, 0, -1)\nN50 CYCLE800(1, "", 1, 57, 0, 0, 0, 0, 0, 0, 40, 30, 0, 1)\nN60 CYCLE800()\n'
    assert not messages(milled(body), "sinumerik.swivel-plane")


@pytest.mark.parametrize("call, expected", [("CYCLE832(0, 102001)", "tolerance _TOL=0 for finishing"),
                                            ("CYCLE832(0.01, 1004)", "the units digit 4"),
                                            ("CYCLE832(0.01, 1302001)", "more than 6 digits")])
def test_high_speed_settings_defects(call, expected):
    found = messages(milled(f"N40 {call}\n"), "sinumerik.high-speed-settings")
    assert any(expected in message for message in found), found


@pytest.mark.parametrize("call", ["CYCLE832(0.2, 1003)", "CYCLE832(0.01, 102001)", "CYCLE832(0.1, 0)", "CYCLE832(0, 0)", "CYCLE832()"])
def test_the_manuals_high_speed_calls_are_accepted(call):
    assert not messages(milled(f"N40 {call}\nN50 CYCLE832()\n"), "sinumerik.high-speed-settings")


ENGRAVE = 'N40 CYCLE60("{text}", 50, 0, 1, -0.3, 0, 10, 10, 0, 0, 0, 5, 2, 100, 300, 0, 1252)\n'


@pytest.mark.parametrize("text, expected", [("LOT→27", "'→'"), ("A" * 92, "92 characters, more than 91")])
def test_engraving_text_defects(text, expected):
    found = messages(milled(ENGRAVE.format(text=text), radius=0.5), "sinumerik.engraving-text")
    assert found and expected in found[0] and "61179" in found[0]


@given(st.text(alphabet="ABCXYZabcxyz0123456789 .,:-+/()#%&@ÄÖÜäöüß€", min_size=1, max_size=91))
@hypothesis_settings(max_examples=40, deadline=None)
def test_any_text_of_the_font_is_accepted(text):
    assert not messages(milled(ENGRAVE.format(text=text), radius=0.5), "sinumerik.engraving-text")


# --------------------------------------------------------------------------- alarms from the tables

@pytest.mark.parametrize("call, expected", [
    ("POCKET3(10, 0, 2, -6, 60, 40, 25, 50, 50, 0, 3, 0.2, 0.1, 300, 100, 2, 11)", "61113"),
    ("CYCLE76(10, 0, 2, -6, 0, 60, 40, 5, 50, 50, 0, 3, 0.2, 0.1, 300, 100, 2, 1, 50, 50)", "blank 50 x 50 is not larger than the spigot 60 x 40"),
    ("CYCLE77(10, 0, 2, -6, 0, 50, 50, 50, 3, 0.2, 0.1, 300, 100, 2, 1, 45)", "_AP1=45 is not larger than the spigot diameter _PRAD=50"),
    ('CYCLE72("C1", 10, 0, 2, -6, 3, 0.2, 8, 300, 100, 1, 41, 1, 5)', "61010"),
    ('CYCLE72("C1", 10, 0, 2, -6, 3, 0.2, 0.1, 300, 100, 1, 41, 5, 5)', "_AS1=5"),
    ('CYCLE72("C1", 10, 0, 2, -6, 3, 0.2, 0.1, 300, 100, 1, 41, 1, 5, 0, 4)', "_AS2=4"),
    ("SLOT1(10, 0, 2, -6, 0, 4, 30, 12, 50, 50, 20, 0, 90, 100, 300, 3, 2, 0.2, 31)", "61128"),
    ("CYCLE71(10, 0, 2, -1, 0, 0, 80, 60, 0, 4, 6, 5, 0, 0, 31, 5)", "61003"),
    ("POCKET4(10, 0, 2, -6, 20, 60, 40, 3, 0.2, 0.1, 600, 150, 2, 21, 6, 0, 0, 0, 2)", "61108"),
    ("POCKET3(10, 0, 2, -6, 60, 40, 8, 60, 40, 0, 3, 0.2, 0.1, 300, 100, 2, 31)", "no plunge angle _RAD1"),
    ("POCKET1(10, 0, 2, -6, 0, 60, 40, 8, 50, 50, 0, 100, 300, -3, 2, 0.2, 0)", "MID=-3"),
    ("CYCLE83(10, 0, 2, -40, 0, 0, -5, 1, 0, 0, 1, 0)", "FDPR=-5"),
])
def test_alarms_derived_from_the_tables(call, expected):
    found = messages(milled(f"N40 {call}\n"), "sinumerik.cycle-parameter-range")
    assert any(expected in message for message in found), found


@pytest.mark.parametrize("call", [
    "POCKET3(10, 0, 2, -6, 60, 40, 8, 50, 50, 0, 3, 0.2, 0.1, 300, 100, 2, 11)",
    "CYCLE76(10, 0, 2, -6, 0, 60, 40, 5, 50, 50, 0, 3, 0.2, 0.1, 300, 100, 2, 1, 70, 50)",
    "CYCLE76(10, 0, 2, -6, 0, 60, 40, 5, 50, 50, 0, 3, 0.2, 0.1, 300, 100, 2, 2)",
    "CYCLE77(10, 0, 2, -6, 0, 50, 50, 50, 3, 0.2, 0.1, 300, 100, 2, 1, 60)",
    'CYCLE72("C1", 10, 0, 2, -6, 3, 0.2, 0.1, 300, 100, 1, 41, 12, 5, 0, 0)',
    "SLOT1(10, 0, 2, -6, 0, 4, 30, 12, 50, 50, 20, 0, 90, 100, 300, 3, 2, 0.2, 31, 0, 0, 0, 0, 5)",
    "CYCLE71(10, 0, 2, -1, 0, 0, 80, 60, 0, 4, 6, 5, 0, 2000, 31, 5)",
    "POCKET4(10, 0, 2, -6, 20, 60, 40, 3, 0.2, 0.1, 600, 150, 2, 21, 6, 0, 0, 4, 2)",
    "POCKET3(10, 0, 2, -6, 60, 40, 8, 60, 40, 0, 3, 0.2, 0.1, 300, 100, 2, 31, 0, 0, 0, 0, 5)",
])
def test_the_fixed_calls_raise_nothing(call):
    assert not messages(milled(f"N40 {call}\n"), "sinumerik.cycle-parameter-range")


@pytest.mark.parametrize("cycle_call, radius, expected", [
    ("POCKET3(10, 0, 2, -6, 60, 40, 8, 50, 50, 0, 3, 0.2, 0.1, 300, 100, 2, 11)", 0, "61117"),
    ("CYCLE77(10, 0, 2, -6, 0, 50, 50, 50, 3, 0.2, 0.1, 300, 100, 2, 1, 60)", -2, "61112"),
    ("SLOT1(10, 0, 2, -6, 0, 4, 30, 24, 50, 50, 20, 0, 90, 100, 300, 3, 2, 0.2, 0)", 5, "less than half the slot width WID=24"),
])
def test_tool_radius_alarms(cycle_call, radius, expected):
    found = messages(milled(f"N40 {cycle_call}\n", radius=radius), "sinumerik.cutter-radius")
    assert any(expected in message for message in found), found


def test_a_slot_tool_of_half_the_width_or_more_is_accepted():
    assert not messages(milled("N40 SLOT1(10, 0, 2, -6, 0, 4, 30, 16, 50, 50, 20, 0, 90, 100, 300, 3, 2, 0.2, 0)\n"), "sinumerik.cutter-radius")


def test_contour_sections_of_cycle74_reached_by_the_flow_are_reported():
    program = POCKET.format(**GOOD_POCKET).replace("N40 GOTOF MACHINING\n", "N40 CYCLE74(\"\", \"EDGE_START\", \"EDGE_END\")\n")
    found = messages(milled(program), "sinumerik.contour-section-runs")
    assert found and "CYCLE74's contour" in found[0]


# --------------------------------------------------------------------------- motion of the milling cycles

class _SegmentRecorder(Checker):
    segments: list = []

    def segment(self, segment, state):
        _SegmentRecorder.segments.append((segment.kind, segment.cycle, dict(segment.end)))
        super().segment(segment, state)


def cycle_moves(monkeypatch, body: str, radius: float = 4) -> list[tuple[str, dict]]:
    """The moves the cycles make, as (kind, end point)."""
    _SegmentRecorder.segments = []
    monkeypatch.setattr(ncverify.api, "Checker", _SegmentRecorder)
    milled(body, radius)
    return [(kind, {axis: value for axis, value in end.items() if axis in "XYZ"}) for kind, cycle, end in _SegmentRecorder.segments if cycle]


def test_pocket3_plunges_at_its_centre_with_g0_for_a_vertical_g0_insertion(monkeypatch):
    moves = cycle_moves(monkeypatch, "N40 _ZSD[2]=0\nN50 POCKET3(10, 0, 2, -6, 60, 40, 8, 60, 40, 0, 3, 0.2, 0.1, 300, 100, 2, 1)\n")
    assert moves == [("rapid", {"X": 60.0, "Y": 40.0, "Z": 10.0}), ("rapid", {"X": 60.0, "Y": 40.0, "Z": 2.0}),
                     ("rapid", {"X": 60.0, "Y": 40.0, "Z": -6.0}), ("rapid", {"X": 60.0, "Y": 40.0, "Z": 10.0})]


def test_pocket3_dimensioned_from_a_corner_plunges_at_the_centre_it_gives(monkeypatch):
    moves = cycle_moves(monkeypatch, "N40 _ZSD[2]=1\nN50 POCKET3(10, 0, 2, -6, -60, 40, 8, 100, 20, 0, 3, 0.2, 0.1, 300, 100, 2, 11)\n")
    assert moves[0] == ("rapid", {"X": 70.0, "Y": 40.0, "Z": 10.0}) and moves[2][0] == "feed"


def test_pocket3_without_the_dimensioning_setting_plunges_somewhere_unknown(monkeypatch):
    moves = cycle_moves(monkeypatch, "N50 POCKET3(10, 0, 2, -6, 60, 40, 8, 60, 40, 0, 3, 0.2, 0.1, 300, 100, 2, 11)\n")
    assert [(kind, end["Z"]) for kind, end in moves] == [("rapid", 10.0), ("rapid", 2.0), ("feed", -6.0), ("rapid", 10.0)]
    assert moves[1][1]["X"] is None


def test_slot2_visits_every_slot_on_its_circle_and_leaves_the_tool_at_rtp(monkeypatch):
    moves = cycle_moves(monkeypatch, "N40 SLOT2(10, 0, 2, -6, 0, 4, 45, 10, 60, 40, 20, 0, 0, 100, 300, 3, 2, 0.2, 0)\n")
    starts = [(round(end["X"], 6), round(end["Y"], 6)) for kind, end in moves if kind == "rapid" and end["Z"] == 10.0][::2]
    assert starts == [(80.0, 40.0), (60.0, 60.0), (40.0, 40.0), (60.0, 20.0)]
    assert [end["Z"] for kind, end in moves if kind == "feed"] == [-6.0] * 4


def test_slot1_with_a_g0_insertion_rapids_to_its_depth(monkeypatch):
    moves = cycle_moves(monkeypatch, "N40 SLOT1(10, 0, 2, -6, 0, 4, 30, 12, 60, 40, 20, 0, 90, 100, 300, 3, 2, 0.2, 0)\n")
    assert [(kind, end["Z"]) for kind, end in moves] == [("rapid", 10.0), ("rapid", 2.0), ("rapid", -6.0), ("rapid", 10.0)]


def test_an_internal_thread_is_milled_from_its_centre_and_ends_there(monkeypatch):
    moves = cycle_moves(monkeypatch, "N40 CYCLE90(10, 0, 2, -20, 0, 16, 14, 2, 300, 3, 0, 60, 40)\n")
    assert moves[0] == ("rapid", {"X": 60.0, "Y": 40.0, "Z": 10.0}) and moves[2] == ("feed", {"X": 60.0, "Y": 40.0, "Z": -20.0})


def test_cycle72_leaves_the_tool_where_its_retract_digit_says(monkeypatch):
    def end_level(kind):
        """The height of the G0 X0 after the cycle."""
        cycle_moves(monkeypatch, f'N40 CYCLE72("C1", 10, 0, 2, -6, 3, 0.2, 0.5, 300, 100, {kind}, 41, 1, 5)\nN50 G0 X0\n')
        return _SegmentRecorder.segments[-1][2]["Z"]
    assert [end_level(kind) for kind in (1, 101, 201, 301, 302)] == [10.0, 2.0, -3.5, -5.5, -6.0]


def test_a_g0_insertion_into_the_blank_is_a_rapid_into_the_stock():
    result = milled('N35 WORKPIECE(,"",,"BOX",0,0,-30,-80,0,0,120,80)\nN40 _ZSD[2]=0\n'
                    "N50 POCKET4(10, 0, 2, -6, 20, 60, 40, 3, 0.2, 0.1, 300, 100, 2, 1)\n")
    found = messages(result, "core.rapid-into-stock")
    assert found and "POCKET4" in found[0] and "Z-6" in found[0]


# --------------------------------------------------------------------------- the spindle around cycles

def test_cycle87_leaves_the_spindle_stopped_for_the_next_cut():
    result = milled("N40 MCALL CYCLE87(5, 0, 2, -10, 0, 3)\nN50 X30\nN60 X40\nN70 MCALL\nN80 G1 X50\n")
    found = [d.span.line for d in result.diagnostics if d.rule == "core.spindle-off-cutting"]
    assert found == [10]


@pytest.mark.parametrize("after, stopped", [(5, True), (3, False)])
def test_rigid_tapping_leaves_the_spindle_as_sdac_says(after, stopped):
    result = milled(f"N40 CYCLE84(5, 0, 2, -10, 0, 0, {after}, 6)\nN50 G1 X50\n")
    assert bool([d for d in result.diagnostics if d.rule == "core.spindle-off-cutting"]) is stopped


@pytest.mark.parametrize("body, reported", [
    ("N35 M5\nN40 POCKET4(10, 0, 2, -6, 20, 60, 40, 3, 0.2, 0.1, 600, 150, 0, 11, 6)\n", True),
    ("N40 POCKET4(10, 0, 2, -6, 20, 60, 40, 3, 0.2, 0.1, 600, 150, 0, 11, 6)\n", False),
    ("N35 M5\nN40 POCKET4(10, 0, 2, -6, 20, 60, 40, 3, 0.2, 0.1, 600, 150, 2, 11, 6)\n", False),
    ("N35 M5\nN40 CYCLE840(5, 0, 2, -10, 0, 0, 0, 0, 1)\n", True),
])
def test_a_direction_taken_from_a_stopped_spindle(body, reported):
    assert bool(messages(milled(body), "sinumerik.spindle-at-cycle")) is reported


def test_thread_turning_needs_the_spindle_running():
    program = "N35 M5\nN40 G0 X30 Z5\nN50 CYCLE97(1.5, , 0, -30, 24, 24, 3, 2, 0.92, 0.05, 30, 0, 5, 1, 3, 1)\nN60 M30\n"
    found = messages(turned(program), "sinumerik.spindle-at-cycle")
    assert found and "CYCLE97 with the spindle stopped" in found[0]


@pytest.mark.parametrize("deselect, reported", [("", True), ("N80 CYCLE832()\n", False), ("N80 CYCLE832(0.01, 0)\n", False),
                                                ("N80 CYCLE832(0.05)\n", True)])
def test_high_speed_settings_left_selected_at_the_program_end(deselect, reported):
    found = messages(milled("N40 CYCLE832(0.01, 102001)\nN50 G1 X50\n" + deselect), "sinumerik.high-speed-settings")
    assert bool([message for message in found if "still selected at the program end" in message]) is reported


@pytest.mark.parametrize("call, reported", [
    ("CYCLE93(60, -20, 5, 3, 0, 0, 0, 0, 0, 0, 0, 0.2, 0.2, 1, 0, 6)", True),
    ("CYCLE93(60, -20, 5, 3, 90, 0, 0, 0, 0, 0, 0, 0.2, 0.2, 1, 0, 6)", False),
    ("CYCLE98(0, 30, -20, 30, -15, 32, -40, 34, 2, 2, 1, 0.05, 30, 0, 5, 1, 1.5, 2, 2, 3)", True),
    ("CYCLE98(0, 30, -20, 30, -30, 32, -40, 34, 2, 2, 1, 0.05, 30, 0, 5, 1, 1.5, 2, 2, 3)", False),
])
def test_turning_alarms_derived_from_the_reference(call, reported):
    found = messages(turned(f"N40 G0 X80 Z10\nN50 {call}\nN60 M30\n"), "sinumerik.turning-parameters")
    assert bool(found) is reported, found


@pytest.mark.parametrize("call, expected", [
    ("CYCLE84(10, 0, 2, -20, 0, 0, 3, 8, 0, 0, 600, 900, 0, 0, 1040)", "the tens digit 4"),
    ("CYCLE84(10, 0, 2, -20, 0, 0, 3, 8, 0, 0, 600, 900, 0, 0, 21000)", "more than 4 digits"),
    ("CYCLE840(10, 0, 2, -20, 0, 0, 0, 3, 0, 8, 0, 0, 0, 200)", "the hundreds digit 2"),
    ("CYCLE84(10, 0, 2, -20, 0, 0, 3, 8, 0, 0, 600, 900, 0, 0, 1323)", None),
])
def test_tapping_technology_digits(call, expected):
    found = messages(milled(f"N40 {call}\n"), "sinumerik.technology-digits")
    assert (found and expected in found[0] and "61125" in found[0]) if expected else not found, found


OUTLINE = """\
N40 CYCLE72("OUTLINE_START:OUTLINE_END", 10, 0, 2, -5, 5, 0.2, 0.1, 500, 200, 11, 41, 2, 10, 500, 2, 10)
N50 G0 Z50
N60 GOTOF PROGRAM_END
OUTLINE_START:
N100 G0 G90 X10 Y10
N110 {compensation}G1 X90
N120 {rest}
OUTLINE_END:
PROGRAM_END:
"""


@pytest.mark.parametrize("compensation, rest, expected", [
    ("G42 ", "Y60", "programs G40/G41/G42"),
    ("", "TRANS X5\nN125 Y60", "selects a frame"),
    ("M1 ; ", "M1", "has 1 block moving in the plane"),
    ("", "Y60", None),
])
def test_path_milling_contour(compensation, rest, expected):
    found = messages(milled(OUTLINE.format(compensation=compensation, rest=rest)), "sinumerik.path-milling-contour")
    assert (found and expected in found[0]) if expected else not found, found


@pytest.mark.parametrize("feed, reported", [("", True), ("F0.15", False), ("F0", True)])
def test_an_undercut_is_cut_at_the_feed_before_the_call(feed, reported):
    program = f"N35 G95 {feed}\nN40 G0 X80 Z10\nN50 CYCLE94(20, 60, \"E\")\nN60 M30\n"
    assert bool(messages(check(LATHE_HEAD.replace(" F0.25", "") + program, machine="lathe"), "sinumerik.undercut-feed")) is reported


@pytest.mark.parametrize("frame, call, expected", [
    ("SCALE X2 Y1.5", "CYCLE71(10, 0, 2, -1, 0, 0, 80, 60, 0, 4, 6, 5, 0, 2000, 31, 5)", "X 2, Y 1.5): would raise alarm 61011"),
    ("ROT RPL=30", "CYCLE71(10, 0, 2, -1, 0, 0, 80, 60, 0, 4, 6, 5, 0, 2000, 31, 5)", None),
    ("SCALE X2 Y1.5", "CYCLE77(10, 0, 2, -6, 0, 50, 50, 50, 3, 0.2, 0.1, 300, 100, 2, 1, 60)", "61012"),
    ("SCALE X2 Y2", "CYCLE77(10, 0, 2, -6, 0, 50, 50, 50, 3, 0.2, 0.1, 300, 100, 2, 1, 60)", None),
    ("MIRROR X0", "CYCLE77(10, 0, 2, -6, 0, 50, 50, 50, 3, 0.2, 0.1, 300, 100, 2, 1, 60)", None),
])
def test_scaling_frames_at_the_call(frame, call, expected):
    found = messages(milled(f"N40 {frame}\nN50 {call}\n"), "sinumerik.scaled-cycle")
    assert (found and expected in found[0]) if expected else not found, found


@pytest.mark.parametrize("edge, reported", [("D1", False), ("D2", True)])
def test_the_cutter_radius_is_that_of_the_active_edge(edge, reported):
    program = MILL_HEAD.format(radius=5).replace("T1 D1 M6", f"T1 {edge} M6") + "$TC_DP6[1,2]=30\n"
    result = check(program + "N40 POCKET2(10, 0, 2, -6, 0, 20, 50, 50, 100, 300, 3, 2, 0.2, 0)\nN900 M30\n")
    assert bool(messages(result, "sinumerik.cutter-radius")) is reported


def test_an_unknown_frame_at_a_scale_sensitive_cycle_is_unknown():
    result = milled("N40 AROTS X30 Y20\nN50 CYCLE71(10, 0, 2, -1, 0, 0, 80, 60, 0, 4, 6, 5, 0, 2000, 31, 5)\n")
    unknown = [d.message for d in result.diagnostics if d.rule == "sinumerik.scaled-cycle" and d.status is Status.UNKNOWN]
    assert not messages(result, "sinumerik.scaled-cycle") and unknown and "whether CYCLE71 runs scaled" in unknown[0], unknown


@pytest.mark.parametrize("speed_mode, dwell, reported", [("G97 S400", 0.1, True), ("G97 S400", 0.2, False), ("G96 S150", 0.1, False)])
def test_groove_dwell_of_one_revolution(speed_mode, dwell, reported):
    program = f"N35 {speed_mode}\nN40 G0 X80 Z10\nN50 CYCLE93(60, -20, 5, 3, 0, 0, 0, 0, 0, 0, 0, 0.2, 0.2, 1, {dwell}, 5)\nN60 M30\n"
    found = messages(turned(program), "sinumerik.groove-dwell")
    assert bool(found) is reported and (not found or "shorter than one revolution at S400 (0.15 s)" in found[0])
    assert bool(_unknown(turned(program), "sinumerik.groove-dwell")) is speed_mode.startswith("G96")


def test_a_contour_whose_first_block_gives_one_coordinate_leaves_the_direction_open():
    program = SHAFT.format(vari=9, x=30, z=-45).replace("N10 G1 X20 Z0", "N10 G1 X20")
    found = messages(turned(program), "sinumerik.contour-direction")
    assert found and "does not give both Z and X" in found[0]


def test_an_internal_thread_milled_bottom_up_enters_its_bore_unknown_not_violated():
    """RFP -20 below, DP 0 and RTP 8 above (seed A L5288-5311): the rapid to RFP + SDIS runs
    down the pre-drilled bore, which the stock model does not have."""
    result = milled('N35 WORKPIECE(,"",,"BOX",0,0,-30,-80,0,0,120,80)\nN40 G0 X60 Y40 Z8\n'
                    "N50 CYCLE90(8, -20, 2, 0, 0, 16, 14, 2, 300, 3, 0, 60, 40)\n")
    found = [d for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == 8]
    assert found and all(d.status is Status.UNKNOWN for d in found)




def test_a_finished_contour_running_along_the_blank_splits_the_material():
    """X50 from Z-20 to Z-30 lies on the blank's outer diameter: the material on either side is not connected."""
    program = EXTENDED.format(finished='"", "PART_START", "PART_END"', diameter=40, close=0).replace(
        "N120 Z-50", "N112 X50\nN114 Z-30\nN116 X40\nN120 Z-50")
    found = messages(turned(program), "sinumerik.extended-stock-removal")
    assert found and "runs along the blank contour" in found[0] and "from Z-20 X50 to Z-30 X50" in found[0]


def test_a_cycle950_contour_ending_with_a_rounding():
    program = EXTENDED.format(finished='"", "PART_START", "PART_END"', diameter=40, close=0).replace("N120 Z-50", "N120 Z-50 RND=2")
    assert any("carries RND/CHF" in message for message in messages(turned(program), "sinumerik.extended-stock-removal"))


@hypothesis_settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.integers(1, 10), st.integers(10, 60)), min_size=3, max_size=8), st.data())
def test_a_contour_that_keeps_its_direction_along_z_is_never_an_overhang_and_one_step_back_always_is(steps, data):
    z, points = 0, []
    for step, diameter in steps:
        z -= step
        points.append((z, diameter))
    blocks = "\n".join(f"N{10 * (k + 2)} X{x} Z{z}" for k, (z, x) in enumerate(points))
    contour = f"N10 G1 X10 Z0\n{blocks}\nN999 M17\n"
    call = "N40 G0 X90 Z5\nN50 CYCLE95(\"PROFILE\", 2.5, 0.1, 0.2, 0, 0.3, 0.15, 0.1, 9)\nN60 M30\n\n%_N_PROFILE_SPF\n"
    assert not messages(turned(call + contour), "sinumerik.contour-direction")
    back = data.draw(st.integers(0, len(points) - 1))
    z_back, x_back = points[back]
    turned_back = contour.replace(f"X{x_back} Z{z_back}\n", f"X{x_back} Z{z_back}\nN{10 * back + 15} Z{z_back + 0.5}\n", 1)
    assert messages(turned(call + turned_back), "sinumerik.contour-direction")


@pytest.mark.parametrize("bore, thread, reported", [
    ("CYCLE81(10, 0, 2, -20)", "CYCLE90(10, 0, 2, -20, 0, 16, 14, 2, 300, 3, 0, 60, 40)", True),
    ("CYCLE81(10, 0, 2, -21)", "CYCLE90(10, 0, 2, -20, 0, 16, 14, 2, 300, 3, 0, 60, 40)", False),
    ("CYCLE81(10, 0, 2, -20)", "CYCLE90(8, -20, 2, 0, 0, 16, 14, 3, 300, 3, 0, 60, 40)", True),
    ("CYCLE81(10, 0, 2, -22)", "CYCLE90(8, -20, 2, 0, 0, 16, 14, 3, 300, 3, 0, 60, 40)", False),
    ("CYCLE81(10, 0, 2, -20)", "CYCLE90(10, 0, 2, -20, 0, 16, 14, 2, 300, 3, 0, 80, 40)", False),
])
def test_a_thread_milled_deeper_than_its_bore(bore, thread, reported):
    found = messages(milled(f"N35 G0 X60 Y40\nN40 {bore}\nN50 {thread}\n"), "sinumerik.thread-mill-bore")
    assert bool(found) is reported, found


def _cycle_names() -> list[str]:
    import tomllib
    from pathlib import Path
    table = tomllib.loads((Path(__file__).resolve().parents[1] / "dialects" / "sinumerik" / "cycles.toml").read_text(encoding="utf-8"))
    return sorted(table["cycle"])


_ARGUMENT = st.one_of(st.just(""), st.integers(-400, 400).map(str), st.floats(-500, 500, allow_nan=False).map(lambda value: f"{value:.3f}"),
                      st.sampled_from(['"C1"', '""', '"N10"', '"A:B"', "R1", "1/0"]))


@hypothesis_settings(max_examples=60, deadline=None)
@given(st.sampled_from(_cycle_names()), st.lists(_ARGUMENT, max_size=26), st.sampled_from(["", "N35 _ZSD[2]=1\n", "N35 SCALE X2\n", "N35 M5\n"]))
def test_any_argument_list_of_any_cycle_is_checked_without_a_crash(cycle, arguments, before):
    result = milled(f"{before}N40 {cycle}({', '.join(arguments)})\nN50 G0 X0 Y0 Z50\n")
    assert result.skipped is None


@pytest.mark.parametrize("call", ['CYCLE71(10, 0, 2, -1, 0, 0, 80, 60, 0, 4, 6, "C1", 0, 2000, 31, 5)',
                                  'CYCLE83(10, "C1", 2, -40, 0, 0, "A:B", 1)'])
def test_a_string_in_a_number_slot_is_the_type_alarm_and_nothing_else(call):
    result = milled(f"N40 {call}\n")
    assert any("12330" in message for message in messages(result, "sinumerik.cycle-arguments"))


@pytest.mark.parametrize("call, expected", [
    ("POCKET3(10, 0, 2, -6, 60, 40, 4, 60, 40, 0, 3, 0.2, 0.1, 300, 100, 2, 11)", "the corners come out with radius 5"),
    ("POCKET1(10, 0, 2, -6, 0, 60, 40, 8, 50, 50, 0, 100, 300, 3, 2, 12, 0)", "FAL=12 is a tool diameter (10) or more"),
    ("POCKET1(10, 0, 2, -6, 0, 60, 40, 8, 50, 50, 0, 100, 300, 3, 2, 0.2, 0)", None),
])
def test_pocket_corners_and_allowance_against_the_tool(call, expected):
    found = messages(milled(f"N40 {call}\n"), "sinumerik.cutter-radius")
    assert (found and expected in found[0]) if expected else not found, found


@pytest.mark.parametrize("height, reported", [(-2, True), (1, False), (10, False)])
def test_a_cycle_called_with_the_tool_under_its_reference_plane(height, reported):
    found = messages(milled(f"N40 Z{height}\nN50 X60 Y40\nN60 CYCLE81(10, 0, 2, -20)\n"), "sinumerik.start-below-surface")
    assert bool(found) is reported and (not found or "at Z-2, beyond the reference plane RFP=0" in found[0])


def test_engraving_plunges_once_to_the_character_depth(monkeypatch):
    moves = cycle_moves(monkeypatch, 'N40 CYCLE60("AB", 10, 0, 1, -0.3, 0, 10, 10, 0, 0, 0, 5, 2, 100, 300, 0, 1252)\n', radius=0.5)
    assert [(kind, end["Z"]) for kind, end in moves] == [("rapid", 10.0), ("rapid", 1.0), ("feed", -0.3), ("rapid", 10.0)]


@pytest.mark.parametrize("call, reported", [
    ("POCKET2(20, 0, 2, 6, 0, 20, 60, 40, 100, 300, 3, 2, 0.2, 0)", True),
    ("POCKET2(20, 0, 2, 0, 0, 20, 60, 40, 100, 300, 3, 2, 0.2, 0)", True),
    ("POCKET2(20, 0, 2, 0, 6, 20, 60, 40, 100, 300, 3, 2, 0.2, 0)", False),
    ("POCKET3(10, 0, 2, 6, 60, 40, 8, 60, 40, 0, 3, 0.2, 0.1, 300, 100, 2, 11)", True),
    ("CYCLE90(8, -20, 2, 0, 0, 16, 14, 2, 300, 3, 0, 60, 40)", False),
    ("CYCLE81(10, 0, 2, 6)", False),
])
def test_a_milling_depth_on_the_retract_side(call, reported):
    assert bool(messages(milled(f"N40 {call}\n"), "sinumerik.milling-depth-sign")) is reported
