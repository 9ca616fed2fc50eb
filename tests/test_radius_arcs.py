"""Arcs given by their radius word (ISO and Fagor ``R``, SINUMERIK ``CR=``, Klartext ``CR``):
the cut stock places them where the control does, so a rapid into the blank after a
contour of such arcs is still found."""
from __future__ import annotations

import math

import numpy
from hypothesis import assume, given, settings, strategies as st

from ncverify import Settings, check_text
from ncverify.xy_arcs import radius_arc_centres

_COORDINATE = st.floats(-100, 100, allow_nan=False)


def _sweep(centre, start, end, clockwise: bool) -> float:
    """The angle (0..2pi) an arc about ``centre`` turns from ``start`` to ``end``."""
    turn = math.atan2(end[1] - centre[1], end[0] - centre[0]) - math.atan2(start[1] - centre[1], start[0] - centre[0])
    return (-turn if clockwise else turn) % (2 * math.pi)


@settings(max_examples=500, deadline=None)
@given(_COORDINATE, _COORDINATE, _COORDINATE, _COORDINATE, st.floats(0.01, 300), st.booleans(), st.booleans())
def test_the_centre_of_an_arc_by_radius_is_the_controls(sx, sy, ex, ey, radius, negative, clockwise):
    """Checked against the definition, not the formula: the centre lies the radius away from
    both ends, and the arc from start to end about it in the written direction turns at
    most a half circle for a positive radius and at least one for a negative radius."""
    chord = math.hypot(ex - sx, ey - sy)
    assume(chord > 1e-3 and abs(radius - chord / 2) > 1e-6 * chord)
    signed = -radius if negative else radius
    centre = radius_arc_centres(numpy.array([[sx, sy]]), numpy.array([[ex, ey]]), numpy.array([signed]), numpy.array([clockwise]))[0]
    if radius < chord / 2 - 1e-3:
        assert numpy.isnan(centre).all()  # no circle of that radius joins the ends: the control alarms
        return
    if radius < chord / 2:
        radius = chord / 2  # short by less than the slack: taken as a half circle
    tolerance = 1e-6 * max(1.0, radius, chord)
    assert math.isclose(math.hypot(sx - centre[0], sy - centre[1]), radius, abs_tol=tolerance * 1e3)
    assert math.isclose(math.hypot(ex - centre[0], ey - centre[1]), radius, abs_tol=tolerance * 1e3)
    sweep = _sweep(centre, (sx, sy), (ex, ey), clockwise)
    if negative:
        assert sweep >= math.pi - 1e-6 or math.isclose(sweep, 0.0, abs_tol=1e-9)
    else:
        assert sweep <= math.pi + 1e-6


def test_start_and_end_in_one_place_leave_the_centre_unknown():
    centre = radius_arc_centres(numpy.array([[5.0, 5.0]]), numpy.array([[5.0, 5.0]]), numpy.array([10.0]), numpy.array([True]))[0]
    assert numpy.isnan(centre).all()


def _pocket(arc_words: list[str], after: list[str]) -> str:
    """Two laps of a rounded rectangle, clockwise, its corners arcs of radius 3 written
    with ``arc_words`` in turn, then the moves ``after``."""
    corners = [f"G2 X{x:.1f} Y{y:.1f} {arc_words[step // 2 % len(arc_words)]}" if step % 2 else f"G1 X{x:.1f} Y{y:.1f}"
               for step, (x, y) in enumerate([(-3.0, 10.0), (0.0, 13.0), (10.0, 13.0), (13.0, 10.0), (13.0, 0.0), (10.0, -3.0), (0.0, -3.0), (-3.0, 0.0)] * 2)]
    return "\n".join(["(ncverify: stock box X-40:40 Y-40:40 Z-10:0)", "(ncverify: tool 1 radius 3 length 50 type endmill)", "O1000",
                      "G21 G90 G17 G54", "T1 M06", "G43 H01 Z50.", "S1000 M03", "G0 X-3. Y0. Z1.", "G1 Z-1. F800.", *corners, *after, "M30"]) + "\n"


def _rapids(program: str) -> list[str]:
    result = check_text(program, settings=Settings())
    assert [(d.rule, d.status, d.span) for d in result.diagnostics] == [
        (d.rule, d.status, d.span) for d in check_text(program, settings=Settings(per_block_only=True)).diagnostics]
    return [d.status.value for d in result.diagnostics if d.rule == "core.rapid-into-stock"]


def test_a_rapid_into_the_blank_after_arcs_by_radius_is_found_on_the_side_the_control_cuts():
    assert _rapids(_pocket(["R3."], ["G0 Z5.", "G0 X30. Y30.", "G0 Z-2."])) == ["violated"]
    assert _rapids(_pocket(["R3.", "R-3."], ["G0 Z5.", "G0 X30. Y30.", "G0 Z-2."])) == ["violated"]  # three-quarter turns too
    # down beside the first corner, onto the path of the three-quarter turn R-3 would make
    # on the other side of the chord: solid material where R3 and the same arc by its
    # centre cut; the R-3 turn has cut there, so the model cannot tell
    down_beside_the_corner = ["G0 Z5.", "G0 X-3. Y16.", "G0 Z-0.5"]
    assert _rapids(_pocket(["R3."], down_beside_the_corner)) == ["violated"]
    assert _rapids(_pocket(["I3. J0.", "I0. J-3.", "I-3. J0.", "I0. J3."], down_beside_the_corner)) == ["violated"]
    assert _rapids(_pocket(["R-3."], down_beside_the_corner)) == ["unknown"]


def test_an_arc_whose_radius_does_not_reach_may_have_cut_anywhere():
    """R1 cannot join corners 4.2 mm apart: the control stops; the model cannot say where
    the tool went, so a rapid into the blank afterwards is not judged."""
    assert _rapids(_pocket(["R1."], ["G0 Z5.", "G0 X30. Y30.", "G0 Z-2."])) == ["unknown"]
