"""Arcs whose centre the program does not write: tangential arcs and arcs through a point.

HEIDENHAIN ``CT`` and SINUMERIK ``CT`` continue the previous contour element tangentially to
an end point; SINUMERIK ``CIP`` passes through an intermediate point. Their centre follows
from the geometry, which is worked out here for concrete positions only. When a position is
symbolic, the previous element is not a plain move in the plane, or the three points leave
no single circle, the arc is returned with no centre: the rules then answer ``unknown`` for
what the arc sweeps instead of judging its chord.
"""
from __future__ import annotations

import math

from .. import values
from ..trace import Arc, Segment

_STRAIGHT_KINDS = frozenset({"rapid", "feed"})
_RELATIVE_TOLERANCE = 1e-9  # below it, three points or a heading and a chord are taken as collinear


def end_heading(segment: Segment | None, position: dict, plane: tuple) -> tuple[float, float] | None:
    """The direction (along the plane's two axes, not normalised) in which the last
    programmed move left ``position``, or None when it is not known exactly: no move yet,
    the tool has been moved since, the move was not programmed (a cycle's), ran along the
    plane's normal, or had a symbolic point."""
    if segment is None or segment.role != "programmed":
        return None
    first, second, normal = plane
    if any(segment.end.get(axis) != position.get(axis) for axis in plane):
        return None
    s1, s2, sn = segment.start.get(first), segment.start.get(second), segment.start.get(normal)
    e1, e2, en = segment.end.get(first), segment.end.get(second), segment.end.get(normal)
    if not _all_floats(s1, s2, e1, e2, sn, en) or sn != en:
        return None
    if segment.kind in _STRAIGHT_KINDS:
        heading = (e1 - s1, e2 - s2)
        return heading if heading != (0.0, 0.0) else None
    arc = segment.arc
    if segment.kind != "arc" or arc is None or arc.plane != plane or arc.centre is None or not _all_floats(*arc.centre):
        return None
    r1, r2 = e1 - arc.centre[0], e2 - arc.centre[1]
    if (r1, r2) == (0.0, 0.0):
        return None
    return (-r2, r1) if arc.direction == "ccw" else (r2, -r1)


def tangent_arc(plane: tuple, heading, start: tuple, end: tuple) -> Arc:
    """The arc from ``start`` to ``end`` (points in the plane) that leaves ``start`` along
    ``heading``. Its centre lies on the normal to the heading at the start, as far from the
    start as from the end."""
    if heading is None or not _all_floats(*start, *end):
        return unplaced_arc(plane)
    n1, n2 = -heading[1], heading[0]  # the heading turned left
    c1, c2 = end[0] - start[0], end[1] - start[1]
    across = n1 * c1 + n2 * c2
    if abs(across) <= _RELATIVE_TOLERANCE * math.hypot(n1, n2) * math.hypot(c1, c2):
        return unplaced_arc(plane)  # the end lies on the heading's line: no circle is tangent there
    reach = (c1 * c1 + c2 * c2) / (2.0 * across)
    centre = (start[0] + reach * n1, start[1] + reach * n2)
    return _about(plane, "ccw" if reach > 0 else "cw", centre, start, end)


def arc_through(plane: tuple, start: tuple, middle: tuple, end: tuple) -> Arc:
    """The arc from ``start`` through ``middle`` to ``end`` (points in the plane)."""
    if not _all_floats(*start, *middle, *end):
        return unplaced_arc(plane)
    (s1, s2), (m1, m2), (e1, e2) = start, middle, end
    turn = (m1 - s1) * (e2 - m2) - (m2 - s2) * (e1 - m1)
    scale = math.hypot(m1 - s1, m2 - s2) * math.hypot(e1 - m1, e2 - m2)
    if abs(turn) <= _RELATIVE_TOLERANCE * scale or scale == 0.0:
        return unplaced_arc(plane)  # collinear or coincident points: no circle through them
    denominator = 2.0 * (s1 * (m2 - e2) + m1 * (e2 - s2) + e1 * (s2 - m2))
    squares = (s1 * s1 + s2 * s2, m1 * m1 + m2 * m2, e1 * e1 + e2 * e2)
    centre = ((squares[0] * (m2 - e2) + squares[1] * (e2 - s2) + squares[2] * (s2 - m2)) / denominator,
              (squares[0] * (e1 - m1) + squares[1] * (s1 - e1) + squares[2] * (m1 - s1)) / denominator)
    return _about(plane, "ccw" if turn > 0 else "cw", centre, start, end)


def arc_by_radius(direction: str, plane: tuple, radius, s1, s2, e1, e2) -> Arc:
    """An arc given by its radius word, from (s1, s2) to (e1, e2) in ``plane``."""
    return Arc(direction, plane, None, None, None, radius, values.distance(s1, s2, e1, e2), chord_sq=values.distance_sq(s1, s2, e1, e2))


def arc_by_centre(direction: str, plane: tuple, c1, c2, s1, s2, e1, e2) -> Arc:
    """An arc about the centre (c1, c2), from (s1, s2) to (e1, e2) in ``plane``."""
    return Arc(direction, plane, (c1, c2), values.distance(s1, s2, c1, c2), values.distance(e1, e2, c1, c2),
               start_radius_sq=values.distance_sq(s1, s2, c1, c2), end_radius_sq=values.distance_sq(e1, e2, c1, c2))


def unplaced_arc(plane: tuple, direction: str = "ccw") -> Arc:
    """An arc whose centre is not known: the rules answer ``unknown`` for what it sweeps
    (``direction``: as written, where the program wrote one; no rule reads it without a centre)."""
    return Arc(direction, plane, None, None, None)


def _about(plane: tuple, direction: str, centre: tuple, start: tuple, end: tuple) -> Arc:
    return arc_by_centre(direction, plane, centre[0], centre[1], start[0], start[1], end[0], end[1])


def _all_floats(*numbers) -> bool:
    return all(type(number) is float and math.isfinite(number) for number in numbers)
