"""Arcs whose centre follows from the geometry: Klartext CT (tangential), and the plane
geometry behind it (an arc tangent to a heading, an arc through a point).

A tangential arc's chord is not where the tool goes: the arc bulges to one side of it. These
tests hold the interpreter to the arc itself, and to ``unknown`` when the direction it
continues is not known."""
from __future__ import annotations

import math

from hypothesis import given, strategies as st

from conftest import check_program, findings
from ncverify.interpret.arc_geometry import arc_through, end_heading, tangent_arc
from ncverify.trace import Arc, Segment
from ncverify.verdict import Status

XY = ("X", "Y", "Z")
TRAVEL = """
[machine]
travel = { x = [-100, 15], y = [-100, 100], z = [-300, 300] }
work_offsets = { G54 = [0, 0, 0] }
[tools.1]
radius = 5.0
length = 60
"""


def _klartext(contour: str) -> str:
    lines = ["BEGIN PGM PART MM", "BLK FORM 0.1 Z X-50 Y-50 Z-20", "BLK FORM 0.2 X+50 Y+50 Z+0", "TOOL CALL 1 Z S1000",
             "L Z+5 R0 FMAX M3", "L X+0 Y+0 R0 FMAX", "L Z-1 R0 F200", *contour.split("\n"), "L Z+50 R0 FMAX M30", "END PGM PART MM"]
    return "\n".join(f"{number} {line}" for number, line in enumerate(lines))


def test_a_tangential_arc_that_bulges_past_the_travel_is_an_overtravel():
    # From (10, 0) heading +X, CT to (10, 20) is a half circle about (10, 10) reaching X 20;
    # its chord stays at X 10, inside the travel.
    result = check_program(_klartext("L X+10 Y+0 R0 F200\nCT X+10 Y+20"), "part.h", TRAVEL)
    overtravel = findings(result, "core.travel-limit", Status.VIOLATED)
    assert [(d.span.line, "20" in d.message) for d in overtravel] == [(9, True)]


def test_a_tangential_arc_that_turns_inwards_stays_inside():
    # The same end point, heading -X: the half circle bulges to X 0, inside the travel.
    result = check_program(_klartext("L X+20 Y+0 R0 F200\nL X+10 Y+0\nCT X+10 Y+20"), "part.h",
                           TRAVEL.replace("x = [-100, 15]", "x = [-100, 30]"))
    assert not findings(result, "core.travel-limit", Status.VIOLATED)
    assert not findings(result, "core.travel-limit", Status.UNKNOWN)


def test_a_tangential_arc_after_a_plunge_has_no_known_direction():
    # The move before it runs along the tool axis: no direction in the plane to continue.
    result = check_program(_klartext("CT X+10 Y+20"), "part.h", TRAVEL)
    assert not findings(result, "core.travel-limit", Status.VIOLATED)
    unknown = findings(result, "core.travel-limit", Status.UNKNOWN)
    assert [d.span.line for d in unknown] == [8]


def test_a_tangential_arc_continues_an_arc():
    # C about (0, 0) from (10, 0) to (0, 10) counterclockwise, then CT to (-6, -8): the same
    # circle, sweeping X -10 on the way; every end point is inside X -9..10.5.
    program = _klartext("L X+10 Y+0 R0 F200\nCC X+0 Y+0\nC X+0 Y+10 DR+\nCT X-6 Y-8")
    inside = check_program(program, "part.h", TRAVEL.replace("x = [-100, 15]", "x = [-10.5, 10.5]"))
    assert not findings(inside, "core.travel-limit")
    past = check_program(program, "part.h", TRAVEL.replace("x = [-100, 15]", "x = [-9, 10.5]"))
    assert [d.span.line for d in findings(past, "core.travel-limit", Status.VIOLATED)] == [11]


# ----------------------------------------------------------------------- the plane geometry

finite = st.floats(-500, 500, allow_nan=False).map(lambda v: round(v, 3))
points = st.tuples(finite, finite)
headings = st.tuples(finite, finite).filter(lambda h: math.hypot(*h) > 1e-3)


def _radius(arc: Arc, point) -> float:
    return math.hypot(point[0] - arc.centre[0], point[1] - arc.centre[1])


def _leaves_along(arc: Arc, start, heading) -> float:
    """How far the arc's direction at ``start`` agrees with ``heading`` (cosine)."""
    r1, r2 = start[0] - arc.centre[0], start[1] - arc.centre[1]
    t1, t2 = (-r2, r1) if arc.direction == "ccw" else (r2, -r1)
    return (t1 * heading[0] + t2 * heading[1]) / (math.hypot(t1, t2) * math.hypot(*heading))


@given(heading=headings, start=points, end=points)
def test_the_tangent_arc_leaves_along_the_heading_and_reaches_the_end(heading, start, end):
    chord = (end[0] - start[0], end[1] - start[1])
    across = -heading[1] * chord[0] + heading[0] * chord[1]
    arc = tangent_arc(XY, heading, start, end)
    if arc.centre is None:  # only when the end lies on the heading's line: no circle is tangent there
        assert abs(across) <= 1e-9 * math.hypot(*heading) * math.hypot(*chord)
        return
    radius = _radius(arc, start)
    assert math.isclose(radius, _radius(arc, end), rel_tol=1e-6, abs_tol=1e-6)
    assert _leaves_along(arc, start, heading) > 1 - 1e-6


@given(start=points, middle=points, end=points)
def test_the_arc_through_a_point_passes_it_between_start_and_end(start, middle, end):
    arc = arc_through(XY, start, middle, end)
    turn = (middle[0] - start[0]) * (end[1] - middle[1]) - (middle[1] - start[1]) * (end[0] - middle[0])
    scale = math.hypot(middle[0] - start[0], middle[1] - start[1]) * math.hypot(end[0] - middle[0], end[1] - middle[1])
    if arc.centre is None:  # only for collinear or coincident points
        assert abs(turn) <= 1e-9 * scale
        return
    radius = _radius(arc, start)
    assert math.isclose(radius, _radius(arc, middle), rel_tol=1e-6, abs_tol=1e-6)
    assert math.isclose(radius, _radius(arc, end), rel_tol=1e-6, abs_tol=1e-6)
    # the middle point is swept on the way: its angle from the start, in the arc's direction,
    # is less than the end's
    sign = 1 if arc.direction == "ccw" else -1

    def swept(point):
        angle = math.atan2(point[1] - arc.centre[1], point[0] - arc.centre[0]) - math.atan2(start[1] - arc.centre[1], start[0] - arc.centre[0])
        return (sign * angle) % (2 * math.pi)
    assert swept(middle) < swept(end) + 1e-9


def _segment(kind, start, end, arc=None, role="programmed") -> Segment:
    return Segment(kind, dict(zip("XYZ", start)), dict(zip("XYZ", end)), None, None, role, None, arc)


def test_the_heading_is_known_only_after_a_programmed_move_in_the_plane_that_ends_here():
    line = _segment("feed", (0.0, 0.0, 0.0), (3.0, 4.0, 0.0))
    here = line.end
    assert end_heading(line, here, XY) == (3.0, 4.0)
    assert end_heading(line, {**here, "X": 3.5}, XY) is None  # moved since
    assert end_heading(_segment("feed", (0.0, 0.0, 0.0), (3.0, 4.0, -1.0)), {"X": 3.0, "Y": 4.0, "Z": -1.0}, XY) is None  # along Z too
    assert end_heading(_segment("feed", (0.0, 0.0, 0.0), (3.0, 4.0, 0.0), role="approach"), here, XY) is None  # a cycle's move
    quarter = _segment("arc", (10.0, 0.0, 0.0), (0.0, 10.0, 0.0), Arc("ccw", XY, (0.0, 0.0), 10.0, 10.0))
    assert end_heading(quarter, quarter.end, XY) == (-10.0, -0.0)
    assert end_heading(quarter, quarter.end, ("Z", "X", "Y")) is None  # another plane


# ----------------------------------------------------------------------- SINUMERIK CT and CIP

SINUMERIK_HEAD = """
    G17 G90 G54 T1 D1 M6
    S1000 M3
    G0 X0 Y0 Z5
    G1 Z-1 F200
"""
SINUMERIK_TRAVEL = TRAVEL.replace("x = [-100, 15]", "x = [-25, 15]")


def _sinumerik(contour: str, travel: str = SINUMERIK_TRAVEL):
    program = SINUMERIK_HEAD + "".join(f"    {line}\n" for line in contour.split("\n")) + "    G90 G0 Z50\n    M30\n"
    return check_program(program, "part.mpf", travel, dialect="sinumerik")


def _overtravel_lines(result) -> list[int]:
    return [d.span.line for d in findings(result, "core.travel-limit", Status.VIOLATED)]


def _unknown_sweeps(result) -> list[int]:
    return [d.span.line for d in findings(result, "core.travel-limit", Status.UNKNOWN) if "arc" in d.message]


def test_sinumerik_ct_and_cip_are_read_as_path_commands_not_subprogram_calls():
    result = _sinumerik("G1 X10 Y0\nCT X10 Y20\nG1 X0\nCIP X-20 Y20 I1=-10 J1=30")
    assert not findings(result, "core.program-not-found")
    assert not findings(result, "core.unsupported-code")
    # CT from (10, 0) heading +X to (10, 20) bulges to X 20; CIP about (-10, 20) stays above X -20
    assert _overtravel_lines(result) == [6]


def test_sinumerik_cip_in_g91_measures_both_points_from_the_start():
    # from (-20, 20) through (-30, 10) to (-20, 0): a half circle about (-20, 10) reaching X -30
    result = _sinumerik("G1 X-20 Y20\nG91 CIP X0 Y-20 I1=-10 J1=-10")
    assert _overtravel_lines(result) == [6]
    absolute = _sinumerik("G1 X-20 Y20\nG91 CIP X0 Y-20 I1=AC(-10) J1=AC(10)")  # through (-10, 10): reaches X -10 only
    assert _overtravel_lines(absolute) == []


def test_sinumerik_cip_is_modal_and_needs_its_intermediate_point():
    # the second block is a CIP too, without I1/J1: its sweep is unknown, never judged by its chord
    result = _sinumerik("G1 X-20 Y20\nCIP X-20 Y0 I1=-10 J1=10\nX-20 Y-20")
    assert _overtravel_lines(result) == []
    assert _unknown_sweeps(result) == [7]


def test_sinumerik_cip_off_the_plane_is_not_placed():
    # the intermediate point is 5 mm above the start and end: an inclined circle, not modelled
    result = _sinumerik("G1 X-20 Y20\nCIP X-20 Y0 I1=-30 J1=10 K1=4")
    assert _overtravel_lines(result) == []
    assert _unknown_sweeps(result) == [6]


def test_cip_inside_a_cycle95_contour_is_alarm_10930():
    from test_sinumerik import check_lathe, contour_findings

    result = check_lathe("""
        G0 X70 Z5
        CYCLE95("ARCS", 2.5, 0.1, 0.2, 0, 0.3, 0.15, 0.1, 9)
        M30
        %_N_ARCS_SPF
        G1 X20 Z0
        X30 Z-5
        CIP X40 Z-15 I1=38 K1=-8
        G1 X60
        M17
    """)
    assert any("10930" in message and "CIP" in message for message in contour_findings(result))


def _arcs_by_line(program: str, project: str, **settings) -> dict:
    """The arc of each segment the rules are handed, by line (every move on its own)."""
    from unittest import mock

    from ncverify.check import Checker

    arcs = {}
    original = Checker.segment

    def recording(checker, segment, state):
        arcs[segment.span.line] = segment.arc
        return original(checker, segment, state)

    with mock.patch.object(Checker, "segment", recording):
        check_program(program, "part.mpf", project, per_block_only=True, **settings)
    return arcs


def test_sinumerik_ct_on_a_lathe_is_not_placed():
    """On a lathe the element before may have been read in diameters (DIAMON) and the CT in
    radii: its direction is not taken, the arc has no centre. On a mill the same path has one."""
    body = "    G1 X10 Z0\n    G1 X10 Z-10\n    CT X12 Z-20\n    M30\n"
    program = SINUMERIK_HEAD.replace("G17", "G18 DIAMOF") + body
    lathe = SINUMERIK_TRAVEL.replace("[machine]", '[machine]\ntype = "lathe"\nlathe_x = "radius"')
    assert _arcs_by_line(program, lathe, dialect="sinumerik", machine="lathe")[7].centre is None
    assert _arcs_by_line(SINUMERIK_HEAD.replace("G17", "G18") + body, SINUMERIK_TRAVEL, dialect="sinumerik")[7].centre == (-10.0, 36.0)
