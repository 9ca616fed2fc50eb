"""SINUMERIK alarms that depend on the cutting edge in use (ncverify/checks/sinumerik_tools.py):
the clearance angle $TC_DP24 against a CYCLE95 contour (61604), the cutting-edge position
$TC_DP2 at CYCLE94/96 (61608), edge D1 at CYCLE73 (61989); and the tool model they read
(the $TC_DP.. blocks of a program, ``ncverify: tool`` annotations, ``[tools.N]``)."""
from __future__ import annotations

import math
import textwrap
from pathlib import Path

import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_text
from ncverify.checks.sinumerik_tools import undercut_entries
from ncverify.diagnostics import Status
from ncverify.lower.sinumerik import program_context
from ncverify.project import ConfigError, load_project_text


def check(program: str, project: str | None = None, machine: str = "lathe"):
    context = load_project_text(textwrap.dedent(project), Path("/nowhere/ncverify.toml")) if project else None
    return check_text(textwrap.dedent(program).lstrip("\n"), "t.mpf", Settings(dialect="sinumerik", machine=machine), context)


from conftest import findings


# --------------------------------------------------------------------------- the tool model

def test_program_context_reads_several_tool_data_assignments_in_one_block():
    context = program_context(("N10 $TC_DP1[3,1]=500 $TC_DP2[3,1]=3 $TC_DP6[3,1]=0.8 $TC_DP24[3,1]=60 ; roughing tool\n"
                               "$TC_DP24[4,1]=95 $TC_DP2[4,1]=0\n$TC_DP24[5,2]=30\n"
                               "$TC_DP1[6,1]=120 $TC_DP6[6,1]=6 \uff1bmilling cutter T6 (full-width semicolon)\n").encode())
    tool = context.tools[3]
    assert (tool.type, tool.radius, tool.edge_position, tool.clearance_angle) == ("turning", 0.8, 3.0, 60.0)
    assert (context.tools[4].clearance_angle, context.tools[4].edge_position) == (None, None)  # out of range: unknown
    assert context.tools[5].clearance_angle is None and context.tools[5].edges[2].clearance_angle == 30.0  # edge D2
    assert context.tools[6].radius == 6.0


def test_project_file_reads_clearance_angle_and_edge_position_and_checks_their_ranges():
    context = load_project_text("[tools.2]\nclearance_angle = 0\nedge_position = 9\n", Path("/nowhere/ncverify.toml"))
    assert (context.tools[2].clearance_angle, context.tools[2].edge_position) == (0.0, 9.0)
    with pytest.raises(ConfigError, match=r"\[tools.2\] clearance_angle: clearance-angle must lie in 0..90, got 95"):
        load_project_text("[tools.2]\nclearance_angle = 95\n", Path("/nowhere/ncverify.toml"))
    with pytest.raises(ConfigError, match="edge_position: edge-position must lie in 1..9, got -1"):
        load_project_text("[tools.2]\nedge_position = -1\n", Path("/nowhere/ncverify.toml"))


def test_annotation_reads_clearance_angle_and_rejects_one_out_of_range():
    result = check(_shaft(flank="31", tool_data="$TC_DP1[1,1]=500", extra="; ncverify: tool 1 radius 0.8 clearance-angle 60"))
    assert findings(result, "sinumerik.clearance-angle", Status.VIOLATED)
    bad = check(_shaft(flank="31", tool_data="$TC_DP1[1,1]=500", extra="; ncverify: tool 1 radius 0.8 clearance-angle 120"))
    assert any("0..90" in d.message for d in findings(bad, "core.bad-annotation"))


def test_the_active_edge_is_readable_as_p_tool():
    result = check("""
        T1 M6
        IF $P_TOOL<>1 GOTOF WRONG
        D3
        IF $P_TOOL<>3 GOTOF WRONG
        M30
        WRONG:
        SETAL(65000)
        M30
    """, machine="mill")
    assert not findings(result, "core.macro-alarm")


# --------------------------------------------------------------------------- 61604: the clearance angle at CYCLE95

def _shaft(flank: str, tool_data: str = "$TC_DP1[1,1]=500 $TC_DP6[1,1]=0.8 $TC_DP24[1,1]=60", edge: str = "D1",
           kind: str = "9", extra: str = "", before: str = "") -> str:
    """A shaft whose groove is entered by the element X40 Z-30 -> X30 Z-<flank> (diameter 40 -> 30)."""
    return f"""
        %_N_SHAFT_MPF
        {tool_data}
        {extra}
        N10 G18 G90 G54 DIAMON
        {before}
        N20 T1 {edge}
        N30 G96 S200 LIMS=3000 M3 G95 F0.25
        N40 G0 X90 Z5
        N50 CYCLE95("SHAFT_CONTOUR", 2.5, 0.1, 0.2, 0, 0.3, 0.15, 0.1, {kind})
        N60 G0 X100 Z50
        N70 M30

        %_N_SHAFT_CONTOUR_SPF
        N10 G1 X20 Z0
        N20 X40 Z-20
        N30 Z-30
        N40 X30 Z-{flank}
        N50 Z-40
        N60 X60 Z-45
        N70 Z-60
        N80 M17
    """


def test_a_flank_steeper_than_the_clearance_angle_raises_61604_at_its_block():
    [finding] = findings(check(_shaft(flank="31")), "sinumerik.clearance-angle")
    assert finding.status is Status.VIOLATED
    assert finding.span.line == 17  # N40 of the contour
    assert "61604" in finding.message and "from Z-30 X40 to Z-31 X30" in finding.message and "clearance angle 60 of T1 D1" in finding.message


def test_a_contour_whose_points_are_not_numbers_is_unknown():
    [finding] = findings(check(_shaft(flank="31").replace("N40 X30 Z-31", "N40 X30 Z=R5")), "sinumerik.clearance-angle")
    assert finding.status is Status.UNKNOWN and "are not all known numbers" in finding.message


def test_a_flank_flatter_than_the_clearance_angle_either_way_is_not_reported():
    assert not findings(check(_shaft(flank="36")), "sinumerik.clearance-angle")


@pytest.mark.parametrize("mode, status", [("DIAMON", None), ("DIAMOF", Status.VIOLATED), ("", Status.UNKNOWN)])
def test_a_flank_steep_only_if_x_is_a_radius_depends_on_diamon(mode, status):
    """X40 -> X30 over Z-30 -> Z-34: 51.3 degrees as diameters, 68.2 as radii, against 60."""
    found = findings(check(_shaft(flank="34").replace("G54 DIAMON", f"G54 {mode}")), "sinumerik.clearance-angle")
    assert [d.status for d in found] == ([status] if status else [])
    assert status is not Status.UNKNOWN or "no DIAMON or DIAMOF before the call" in found[0].message


def test_a_vertical_drop_into_a_groove_violates_any_clearance_angle_below_90():
    result = check(_shaft(flank="30", tool_data="$TC_DP1[1,1]=500 $TC_DP24[1,1]=89"))
    assert findings(result, "sinumerik.clearance-angle", Status.VIOLATED)


def test_clearance_angle_zero_switches_the_monitoring_off():
    assert not findings(check(_shaft(flank="31", tool_data="$TC_DP1[1,1]=500 $TC_DP24[1,1]=0")), "sinumerik.clearance-angle")


@pytest.mark.parametrize("changes, reason", [
    ({"tool_data": "$TC_DP1[1,1]=500 $TC_DP6[1,1]=0.8"}, "$TC_DP24[1,1]"),
    ({"edge": "D2"}, "the data of edge D2 of T1 are not in the program ($TC_DP..[1,2])"),
    ({"edge": "D2", "tool_data": "$TC_DP1[1,1]=500 $TC_DP24[1,1]=60 $TC_DP24[1,2]=0"}, None),
    ({"before": "ROT RPL=5"}, "rotation, scale or mirror frame"),
])
def test_the_clearance_angle_is_the_active_edges_and_without_it_the_answer_is_unknown(changes, reason):
    found = findings(check(_shaft(flank="31", **changes)), "sinumerik.clearance-angle")
    assert [d.status for d in found] == ([Status.UNKNOWN] if reason else [])  # D2 with P24 = 0: not monitored
    assert not reason or reason in found[0].message


def test_the_clearance_angle_comes_from_the_project_file_when_the_program_does_not_set_it():
    project = "[tools.1]\nradius = 0.8\nclearance_angle = 60\n"
    assert findings(check(_shaft(flank="31", tool_data="$TC_DP1[1,1]=500"), project), "sinumerik.clearance-angle", Status.VIOLATED)
    assert not findings(check(_shaft(flank="31", tool_data="$TC_DP24[1,1]=0"), project), "sinumerik.clearance-angle")


def test_a_contour_without_undercut_needs_no_clearance_angle():
    result = check(_shaft(flank="31", tool_data="$TC_DP1[1,1]=500").replace("N40 X30 Z-31", "N40 X50 Z-31"))
    assert not findings(result, "sinumerik.clearance-angle")


def test_undercut_entries_by_machining_kind():
    plane = ("Z", "X", "Y")
    groove = [((0.0, 20.0), 1), ((-10.0, 20.0), 2), ((-12.0, 10.0), 3), ((-20.0, 10.0), 4), ((-20.0, 30.0), 5)]
    [entry] = undercut_entries(groove, 1.0, plane)  # external longitudinal: the drop towards the axis
    assert entry.span == 3 and entry.flattest == pytest.approx(math.degrees(math.atan2(5, 2)))
    assert entry.steepest == pytest.approx(math.degrees(math.atan2(10, 2)))
    assert [entry.span for entry in undercut_entries(groove, 3.0, plane)] == [5]  # internal: the rise away from the axis
    face = [((0.0, 10.0), 1), ((-5.0, 20.0), 2), ((-2.0, 30.0), 3), ((-8.0, 40.0), 4)]
    assert [entry.span for entry in undercut_entries(face, 2.0, plane)] == [2, 4]  # external face: deeper into minus Z


_COORDINATE = st.integers(-50, 50).map(float)


@hypothesis_settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(_COORDINATE, _COORDINATE), min_size=2, max_size=8), st.sampled_from([1.0, 2.0, 9.0, 10.0]),
       st.floats(0.5, 4.0))
def test_undercut_angles_do_not_change_with_scale_and_mirror_to_the_internal_side(raw, kind, scale):
    """Scaling the contour keeps every angle; mirroring it along the infeed axis (X for
    longitudinal, Z for face machining) turns the external case into the internal one with
    the same entries."""
    points = [(point, index) for index, point in enumerate(raw)]
    plane = ("Z", "X", "Y")
    found = undercut_entries(points, kind, plane)
    scaled = undercut_entries([((z * scale, x * scale), index) for (z, x), index in points], kind, plane)
    longitudinal = kind % 2 == 1
    mirrored = undercut_entries([((z, -x) if longitudinal else (-z, x), index) for (z, x), index in points], kind + 2, plane)
    for other in (scaled, mirrored):
        assert [entry.span for entry in other] == [entry.span for entry in found]
        assert [entry.flattest for entry in other] == pytest.approx([entry.flattest for entry in found])
    assert all(0 < entry.flattest <= entry.steepest <= 90 for entry in found)


# --------------------------------------------------------------------------- 61608: the cutting-edge position at CYCLE94/96

def _undercut(edge_position: str, vari: str) -> str:
    return f"""
        $TC_DP1[1,1]=500 {edge_position} $TC_DP6[1,1]=0.4
        N10 G18 G90 G54 DIAMON T1 D1
        N20 G96 S150 LIMS=2500 M3 G95 F0.2
        N30 G0 X80 Z10
        N40 CYCLE94(20, 60, "E"{vari})
        N900 M30
    """


@pytest.mark.parametrize("edge_position, vari, status", [
    ("$TC_DP2[1,1]=8", ", 0", Status.VIOLATED), ("$TC_DP2[1,1]=8", "", Status.VIOLATED),
    ("$TC_DP2[1,1]=3", ", 0", None), ("$TC_DP2[1,1]=8", ", 3", None), ("", ", 0", Status.UNKNOWN),
])
def test_cycle94_with_vari_zero_needs_an_edge_position_of_1_to_4(edge_position, vari, status):
    found = findings(check(_undercut(edge_position, vari)), "sinumerik.edge-position")
    assert [d.status for d in found] == ([status] if status else [])
    if status is Status.VIOLATED:
        assert "61608" in found[0].message and "SL 8" in found[0].message


# --------------------------------------------------------------------------- 61989: D1 at CYCLE73

def _pocket(tool_block: str) -> str:
    return f"""
        $TC_DP1[1,1]=120 $TC_DP6[1,1]=4
        N10 G17 G90 G54 {tool_block}
        N20 S3000 M3 F500
        N30 G0 X0 Y0 Z50
        N40 CYCLE74("EDGE", "", "")
        N50 CYCLE73(1011, "", "POCKET_MILL", "1", 10, 0, 1, -8, 0, 2, 4, 0.2, 0.1, 500, 200, 0)
        N60 M30
    """


@pytest.mark.parametrize("tool_block, status", [
    ("T1 M6", None), ("T1 D1 M6", None), ("T1 D2 M6", Status.VIOLATED), ("T1 M6 D0", Status.VIOLATED),
    ("T1", Status.UNKNOWN),
])
def test_cycle73_needs_edge_d1(tool_block, status):
    found = findings(check(_pocket(tool_block), machine="mill"), "sinumerik.pocket-edge")
    assert [d.status for d in found] == ([status] if status else [])
    if status is Status.VIOLATED:
        assert "61989" in found[0].message and found[0].span.line == 6


@pytest.mark.parametrize("arc", ["G2 X40 Z-40 CR=5", "G2 X40 Z-40 K-5"])
def test_an_arc_that_may_dip_into_an_undercut_between_level_end_points_is_unknown(arc):
    result = check(_shaft(flank="31").replace("N40 X30 Z-31\n        N50 Z-40", f"N40 {arc}\n        N50 G1 Z-40"))
    [finding] = findings(result, "sinumerik.clearance-angle")
    assert finding.status is Status.UNKNOWN and "the arc's tangents are bounded" in finding.message and finding.span.line == 17


def test_a_quarter_arc_rising_from_a_level_element_enters_no_undercut():
    result = check(_shaft(flank="31", tool_data="$TC_DP1[1,1]=500").replace("N40 X30 Z-31", "N40 G2 X50 Z-35 CR=5\n        N45 G1"))
    assert not findings(result, "sinumerik.clearance-angle")


@hypothesis_settings(max_examples=80, deadline=None)
@given(st.floats(1.0, 50.0), st.floats(-180.0, 180.0), st.floats(5.0, 180.0), st.booleans())
def test_the_bound_of_an_arc_holds_at_every_point_of_it(radius, start_angle, sweep, clockwise):
    """No piece of an arc dives more steeply than the bound its entry gives, and the chord's
    angle is reached somewhere on it (plane axes without X: one reading)."""
    turn = -1.0 if clockwise else 1.0
    angles = [math.radians(start_angle + turn * sweep * k / 200) for k in range(201)]
    arc = [(radius * math.cos(angle), radius * math.sin(angle)) for angle in angles]
    first, last = arc[0], arc[-1]
    direction = math.copysign(1.0, last[0] - first[0])
    pieces = [((end[0] - start[0]) * direction, start[1] - end[1]) for start, end in zip(arc, arc[1:])]
    if abs(last[0] - first[0]) < 1e-6 or any(advance < -1e-9 for advance, _depth in pieces):
        return  # no machining direction, or an overhang: not an undercut entry
    entries = undercut_entries([(first, "from"), (last, "arc")], 1.0, ("Z", "R", "Y"), {"arc": radius})
    steepest = max((entry.steepest for entry in entries), default=0.0)
    flattest = max((entry.flattest for entry in entries), default=0.0)
    dives = [math.degrees(math.atan2(depth, advance)) for advance, depth in pieces if depth > 1e-12]
    assert all(angle <= steepest + 1e-6 for angle in dives)
    assert flattest <= max(dives, default=0.0) + 1e-6


def test_face_machining_judges_the_dive_along_z():
    program = """
        $TC_DP1[1,1]=500 $TC_DP24[1,1]=60
        N10 G18 G90 G54 DIAMON T1 D1
        N20 G96 S200 LIMS=3000 M3 G95 F0.2
        N30 G0 X90 Z5
        N40 CYCLE95("FACE:FACE_END", 2, 0.1, 0.1, 0, 0.3, 0.15, 0.1, 10)
        N50 G0 X100 Z50
        N60 M30
        FACE:
        N100 G1 X80 Z0
        N110 X60
        N120 X58 Z-10
        N130 X40
        N140 X30 Z-2
        N150 X20
        FACE_END:
    """
    [finding] = findings(check(program), "sinumerik.clearance-angle")
    assert finding.status is Status.VIOLATED and finding.span.line == 11 and "at 84.3 degrees" in finding.message  # X58 -> X40: 1 mm radius


# --------------------------------------------------------------------------- the infeed angle of CYCLE97/98

def _thread(infeed: str, pitch: str = ", 42", tool: str = "") -> str:
    return f"""
        $TC_DP1[1,1]=500
        {tool}
        N10 G18 G90 G54 DIAMON T1 D1
        N20 G95 S500 M3
        N30 G0 X50 Z10
        N40 CYCLE97({pitch}, 0, -35, 42, 42, 10, 3, 2.76, 0, {infeed}, 0, 5, 2, 3, 1)
        N50 M30
    """


@pytest.mark.parametrize("infeed, pitch, tool, status", [
    ("35", ", 42", "", Status.VIOLATED),  # a metric thread: 60 degrees
    ("-30", ", 42", "", None),
    ("29", ", 42", "; ncverify: tool 1 radius 0.1 angle 55", Status.VIOLATED),  # the tool's own angle wins
    ("29", "4.5, ", "", Status.UNKNOWN),  # a pitch only: the flank angle must come from the tool
    ("29", "4.5, ", "; ncverify: tool 1 radius 0.1 angle 60", None),
    ("0", "4.5, ", "", None),  # radial infeed
])
def test_the_infeed_angle_is_at_most_half_the_flank_angle(infeed, pitch, tool, status):
    found = findings(check(_thread(infeed, pitch, tool)), "sinumerik.thread-infeed-angle")
    assert [d.status for d in found] == ([status] if status else [])
    if status is Status.VIOLATED:
        assert f"IANG={infeed}" in found[0].message and found[0].span.line == 6



# --------------------------------------------------------------------------- 61724: no material between blank and finished part

def _blank_and_part(part: str, blank: str) -> str:
    return f"""
        $TC_DP1[1,1]=500 $TC_DP6[1,1]=0.8
        N10 G18 G90 G54 DIAMON T1 D1
        N20 G96 S200 LIMS=3000 M3 G95 F0.25
        N30 G0 X90 Z5
        N40 CYCLE950("", "PART_START", "PART_END", "ROUGH_PART", 311311, 2, 0.1, 0.1, 0.3, 0.1, 0.1, 0.1, 1, 0, 1, "", "BLANK_START", "BLANK_END")
        N50 M30
        PART_START:
        {part}
        PART_END:
        BLANK_START:
        {blank}
        BLANK_END:
    """


_PART = "N100 G1 X20 Z0\n        N110 X40 Z-20\n        N120 Z-50"


@pytest.mark.parametrize("part, blank, status", [
    (_PART, "N200 G1 X0 Z0\n        N210 X20\n        N220 X40 Z-20\n        N230 Z-50\n        N240 X0\n        N250 Z0", Status.VIOLATED),
    (_PART.replace("N110 X40 Z-20", "N110 G2 X40 Z-20 CR=30\n        N115 G1"),
     "N200 G1 X0 Z0\n        N210 X20\n        N220 G2 X40 Z-20 CR=30\n        N230 G1 Z-50\n        N240 X0\n        N250 Z0", Status.UNKNOWN),
    (_PART, "N200 G1 X0 Z0\n        N210 X50\n        N220 Z-50\n        N230 X0\n        N240 Z0", None),
])
def test_cycle950_with_the_finished_part_along_the_whole_blank_has_no_material(part, blank, status):
    found = [d for d in findings(check(_blank_and_part(part, blank)), "sinumerik.extended-stock-removal") if "no material" in d.message]
    assert [d.status for d in found] == ([status] if status else [])
    if status is Status.VIOLATED:
        assert "61724" in found[0].message
