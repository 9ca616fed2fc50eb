"""Does a tool fit the feature it is to cut? Pockets, slots, bores and contour pockets.

A round tool of radius r can put its centre only in the pocket shrunk by r (shapely
``buffer(-r)``). The pocket can be machined at all when that region is not empty. It is
machined *as programmed* when, in addition, the tool reaches every corner: at a corner
whose inside angle is below 180 degrees the tool touches both edges when its centre sits on
the bisector at r / sin(angle / 2) from the corner (the fillet of radius r every round
tool leaves); everywhere else on the outline (walls, an island's outside corners, arcs) the
centre must come within r of it. The outline is sampled at a quarter of the radius; a
stretch of it farther than that from the reachable region is reported as unreached: a
neck narrower than the tool, a fillet smaller than its radius, a lobe it cannot enter.

Every function returns a :class:`Fit` with the largest tool radius that fits, so that a
finding can say which tool would do. Values are concrete floats; callers with symbolic
dimensions answer ``unknown`` or build their own solver condition.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy
import shapely
from shapely.geometry import Polygon

_TOLERANCE = 1e-6  # mm: distances closer than this count as touching
_SEARCH_STEPS = 40  # bisection steps for the largest radius (far below a micron for any pocket)
_ARC_STEP = math.radians(5.0)  # angle between the points an arc is approximated by


@dataclass(frozen=True)
class Fit:
    fits: bool
    largest_radius: float  # the largest tool radius that fits (0 when none does)
    unreached: list[tuple[float, float]] = field(default_factory=list)  # corners the tool cannot reach
    reason: str = ""  # why it does not fit, in words; empty when it fits


def rectangle_fit(length: float, width: float, corner_radius: float, tool_radius: float, strict: bool = False) -> Fit:
    """A rectangular pocket ``length`` x ``width`` with corners rounded to ``corner_radius``
    (0: sharp, so the tool leaves its own radius). ``strict``: the tool must be smaller than
    the feature, not as large (a cycle that needs room to move sideways)."""
    largest = min(length, width) / 2.0
    if corner_radius > 0:
        largest = min(largest, corner_radius)
    if not _within(tool_radius, min(length, width) / 2.0, strict):
        return Fit(False, largest, [], f"the tool (diameter {2 * tool_radius:g}) is wider than the pocket's {min(length, width):g}")
    if corner_radius > 0 and not _within(tool_radius, corner_radius, False):
        return Fit(False, largest, [], f"the tool radius {tool_radius:g} is larger than the corner radius {corner_radius:g}: the corners stay uncut")
    return Fit(True, largest)


def circle_fit(diameter: float, tool_radius: float, strict: bool = False) -> Fit:
    """A circular pocket or bore of ``diameter``."""
    largest = diameter / 2.0
    if not _within(tool_radius, largest, strict):
        return Fit(False, largest, [], f"the tool (diameter {2 * tool_radius:g}) is larger than the {diameter:g} diameter")
    return Fit(True, largest)


def slot_fit(width: float, tool_radius: float, strict: bool = False) -> Fit:
    """A straight or circular slot of ``width``."""
    largest = width / 2.0
    if not _within(tool_radius, largest, strict):
        return Fit(False, largest, [], f"the tool (diameter {2 * tool_radius:g}) is wider than the {width:g} slot")
    return Fit(True, largest)


def polygon_fit(pocket: Polygon, tool_radius: float) -> Fit:
    """A contour pocket: ``pocket`` is its outline, islands as holes."""
    unreached = unreached_spots(pocket, tool_radius)
    if unreached == []:
        return Fit(True, tool_radius)
    largest = largest_radius(pocket)
    if unreached is None:
        return Fit(False, largest, [], f"the tool (diameter {2 * tool_radius:g}) cannot enter the pocket anywhere")
    return Fit(False, largest, unreached, f"the tool (diameter {2 * tool_radius:g}) cannot reach {len(unreached)} place(s) of the pocket's outline")


def unreached_spots(pocket: Polygon, tool_radius: float) -> list[tuple[float, float]] | None:
    """Places on the pocket's outline a tool of ``tool_radius`` cannot reach (one point per
    stretch of outline it misses); None when its centre has nowhere to go at all."""
    reachable = pocket.buffer(-tool_radius, quad_segs=32) if tool_radius > 0 else pocket
    if reachable.is_empty:
        return None
    points, allowances = _outline_samples(pocket, tool_radius)
    distances = shapely.distance(reachable, shapely.points(points))
    missed = distances > allowances + _TOLERANCE * numpy.maximum(1.0, allowances)
    starts = numpy.flatnonzero(missed & ~numpy.roll(missed, 1)) if not missed.all() else numpy.array([0])
    return [(float(points[index][0]), float(points[index][1])) for index in starts]


def largest_radius(pocket: Polygon) -> float:
    """The largest tool radius that reaches all of ``pocket``'s outline (bisection to a micron;
    arcs approximated by points make it a few hundredths of a mm smaller than exact)."""
    if pocket.is_empty or pocket.area <= 0:
        return 0.0
    low, high = 0.0, shapely.maximum_inscribed_circle(pocket, tolerance=_TOLERANCE).length * 1.01 + _TOLERANCE
    while high - low > 1e-3:
        middle = (low + high) / 2.0
        if unreached_spots(pocket, middle) == []:
            low = middle
        else:
            high = middle
    return low


def outline(start: tuple[float, float], elements) -> Polygon:
    """A closed contour as a polygon. ``elements`` go on from ``start``: ``("line", end)``
    or ``("arc", end, centre, clockwise)``; arcs become points ``_ARC_STEP`` apart."""
    points = [start]
    for element in elements:
        if element[0] == "arc":
            points.extend(arc_points(points[-1], element[1], element[2], element[3]))
        else:
            points.append(element[1])
    return Polygon(points).buffer(0)


def arc_points(start, end, centre, clockwise: bool) -> list[tuple[float, float]]:
    """Points along an arc from ``start`` (excluded) to ``end`` (included); a full circle when
    the two are the same point."""
    radius = math.dist(start, centre)
    first = math.atan2(start[1] - centre[1], start[0] - centre[0])
    last = math.atan2(end[1] - centre[1], end[0] - centre[0])
    sweep = (first - last) if clockwise else (last - first)
    sweep %= 2 * math.pi
    if sweep <= _TOLERANCE:
        sweep = 2 * math.pi
    steps = max(2, math.ceil(sweep / _ARC_STEP))
    direction = -1.0 if clockwise else 1.0
    points = [(centre[0] + radius * math.cos(first + direction * sweep * i / steps),
               centre[1] + radius * math.sin(first + direction * sweep * i / steps)) for i in range(1, steps)]
    return points + [tuple(end)]


def _outline_samples(pocket: Polygon, tool_radius: float):
    """Points along every ring of the pocket, and how far the tool centre may stay from each
    while the tool still touches it: ``tool_radius`` on a wall, more inside the fillet a
    round tool leaves at a corner (r / sin(angle / 2) at the corner itself)."""
    spacing = max(tool_radius / 4.0, _TOLERANCE * 1000)
    points, allowances = [], []
    for index, ring in enumerate((pocket.exterior, *pocket.interiors)):
        inside_on_left = ring.is_ccw == (index == 0)
        corners = numpy.asarray(ring.coords)[:-1]
        angles = _inside_angles(corners, inside_on_left)
        fillet_lengths = numpy.where(angles < math.pi, tool_radius / numpy.tan(numpy.minimum(angles, math.pi) / 2.0), 0.0)
        for corner in range(len(corners)):
            start, end = corners[corner], corners[(corner + 1) % len(corners)]
            length = float(numpy.hypot(*(end - start)))
            steps = min(max(1, math.ceil(length / spacing)), 2000)
            along = numpy.arange(steps) * (length / steps)
            points.append(start + numpy.outer(along / max(length, _TOLERANCE), end - start))
            into_fillet = numpy.maximum(fillet_lengths[corner] - along, 0.0) + numpy.maximum(fillet_lengths[(corner + 1) % len(corners)] - (length - along), 0.0)
            allowances.append(numpy.hypot(tool_radius, into_fillet))
    return numpy.vstack(points), numpy.concatenate(allowances)


def _inside_angles(corners, inside_on_left: bool):
    """The pocket's inside angle at each corner of a ring."""
    before = corners - numpy.roll(corners, 1, axis=0)
    after = numpy.roll(corners, -1, axis=0) - corners
    turn = numpy.arctan2(after[:, 1], after[:, 0]) - numpy.arctan2(before[:, 1], before[:, 0])
    turn = (turn + math.pi) % (2 * math.pi) - math.pi  # left turn positive
    return math.pi - turn if inside_on_left else math.pi + turn


def _within(tool_radius: float, limit: float, strict: bool) -> bool:
    return tool_radius < limit - _TOLERANCE if strict else tool_radius <= limit + _TOLERANCE
