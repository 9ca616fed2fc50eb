"""Does a tool fit the feature it is to cut? Pockets, slots, bores and contour pockets.

A round tool of radius r can put its centre only in the pocket shrunk by r (shapely
``buffer(-r)``). The pocket can be machined at all when that region is not empty. It is
machined *as programmed* when, in addition, the tool touches every place of the outline:
the centre must come within r of it. A sharp inside corner is the exception: the tool
fills it as far as its own radius lets it (the fillet of radius r every round tool leaves,
its centre on the bisector at r / sin(angle / 2) from the corner), so the outline beside
such a corner, up to where that tool position touches it, counts as reached. The outline is
sampled at a quarter of the radius; a stretch of it farther than that from the reachable
region is reported as unreached: a neck narrower than the tool, a fillet smaller than its
radius, a lobe it cannot enter.

The ``*_fit`` functions return a :class:`Fit` with the largest tool radius that fits, so
that a finding can say which tool would do; their values are concrete floats. The
``*_misfit`` functions state the same conditions as a hazard for sizes that depend on free
parameters (a condition the solver proves impossible or shows with a witness).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy
import shapely
from shapely.geometry import Polygon

from . import values
from .verdict import both, hazard

_TOLERANCE = 1e-6  # mm: distances closer than this count as touching
# Arcs beside a sharp corner move the tool that fills it up to about 15 % farther from the
# corner than straight edges would (r / sin(angle / 2)); a centre farther still serves a neck.
_FILLET_SLACK = 1.25
_TOUCH_SLACK = 1.01  # samples a quarter radius apart pass within r sqrt(1 + 1/64) of where a tool touches
_SHARP_CORNER = math.radians(170.0)  # flatter corners are an arc's polygon (5 degree steps)
_ARC_STEP = math.radians(5.0)  # angle between the points an arc is approximated by
# An arc drawn as chords has corners where the tool centre stays r / cos(step / 2), not r,
# from the arc: the tool radius is judged to that accuracy (0.1 %), so that a tool exactly
# as wide as a neck between arcs fits, as it does on the control.
_CHORD_SLACK = 1.0 / math.cos(_ARC_STEP / 2.0) - 1.0


@dataclass(frozen=True)
class Fit:
    """Whether a tool fits a pocket, and why not when it does not."""

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


def circle_misfit(diameter, tool_radius: float, strict: bool = False):
    """The hazard that the tool does not fit a circle or bore of ``diameter`` (a number or a
    symbolic value; none when it is zero or less): the condition of :func:`circle_fit`."""
    return _misfit(values.mul(diameter, 0.5), tool_radius, strict)


def slot_misfit(width, tool_radius: float, strict: bool = False):
    """The hazard that the tool does not fit a slot of ``width``: the condition of :func:`slot_fit`."""
    return _misfit(values.mul(width, 0.5), tool_radius, strict)


def rectangle_misfit(length, width, corner_radius, tool_radius: float, strict: bool = False):
    """The hazard that the tool does not fit a rectangular pocket: the conditions of
    :func:`rectangle_fit` (narrower than the tool, or rounded corners tighter than it)."""
    narrow = either(slot_misfit(length, tool_radius, strict), slot_misfit(width, tool_radius, strict))
    return either(narrow, both(hazard(">", corner_radius, 0.0), _misfit(corner_radius, tool_radius, False)))


def _misfit(limit, tool_radius: float, strict: bool):
    if strict:
        return hazard(">=", tool_radius, values.sub(limit, _TOLERANCE))
    return hazard(">", tool_radius, values.add(limit, _TOLERANCE))


def either(first, second):
    """One hazard or the other (True, False or conditions)."""
    if first is True or second is True:
        return True
    if first is False:
        return second
    if second is False:
        return first
    return values.logical("OR", first, second)


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
    """Places on the pocket's outline a tool of ``tool_radius`` cannot reach (the point
    farthest from the tool of each stretch of outline it misses: the middle of a neck); None
    when its centre has nowhere to go at all."""
    rings = _judged_samples(pocket, tool_radius)
    if rings is None:
        return None
    spots = []
    for points, distances, missed in rings:
        for stretch in _stretches(missed):
            worst = stretch[numpy.argmax(distances[stretch])]
            spots.append((float(points[worst][0]), float(points[worst][1])))
    return spots


def clearing_radius(pocket: Polygon, spot: tuple[float, float]) -> float:
    """The largest tool radius that reaches ``spot`` on the outline: half the width of a
    neck there, or the radius of an inside arc."""

    def reaches(radius):
        rings = _judged_samples(pocket, radius)
        if rings is None:
            return False
        points = numpy.vstack([ring[0] for ring in rings])
        missed = numpy.concatenate([ring[2] for ring in rings])
        return not missed[numpy.argmin(numpy.hypot(*(points - spot).T))]

    return _largest(pocket, reaches)


def _judged_samples(pocket: Polygon, tool_radius: float):
    """Per ring of the pocket: its sample points, their distance from where the tool centre
    can go, and which of them the tool misses (fillets excused); None when the centre has
    nowhere to go."""
    reachable = pocket.buffer(-tool_radius * (1.0 - _CHORD_SLACK), quad_segs=32) if tool_radius > 0 else pocket
    if reachable.is_empty:
        return None
    rings = []
    for ring, inside_on_left in _rings(pocket):
        points, corner_samples, angles = _ring_samples(ring, inside_on_left, tool_radius)
        distances = shapely.distance(reachable, shapely.points(points))
        missed = distances > tool_radius + _TOLERANCE * max(1.0, tool_radius)
        missed &= ~_corner_fillets(points, corner_samples, angles, reachable, distances, missed, tool_radius)
        rings.append((points, distances, missed))
    return rings


def largest_radius(pocket: Polygon) -> float:
    """The largest tool radius that reaches all of ``pocket``'s outline (bisection to a
    thousandth of a mm; arcs drawn as chords make it up to 0.1 % off)."""
    if pocket.is_empty or pocket.area <= 0:
        return 0.0
    return _largest(pocket, lambda radius: unreached_spots(pocket, radius) == [])


def _largest(pocket: Polygon, reaches) -> float:
    """The largest tool radius for which ``reaches(radius)`` holds, by bisection to a
    thousandth of a mm below the pocket's inscribed circle, less the chords' slack."""
    low, high = 0.0, shapely.maximum_inscribed_circle(pocket, tolerance=_TOLERANCE).length * 1.01 + _TOLERANCE
    while high - low > 1e-3:
        middle = (low + high) / 2.0
        low, high = (middle, high) if reaches(middle) else (low, middle)
    return low * (1.0 - _CHORD_SLACK)


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


def _rings(pocket: Polygon):
    """The outline and every island's, each with the side the pocket lies on."""
    return [(ring, ring.is_ccw == (index == 0)) for index, ring in enumerate((pocket.exterior, *pocket.interiors))]


def _ring_samples(ring, inside_on_left: bool, tool_radius: float):
    """Points along a ring a quarter of the radius apart, the index of the sample at each of
    its corners, and the pocket's inside angle at each corner."""
    spacing = max(tool_radius / 4.0, _TOLERANCE * 1000)
    corners = numpy.asarray(shapely.remove_repeated_points(ring, _TOLERANCE).coords)[:-1]
    points, corner_samples = [], []
    for corner in range(len(corners)):
        start, end = corners[corner], corners[(corner + 1) % len(corners)]
        steps = min(max(1, math.ceil(float(numpy.hypot(*(end - start))) / spacing)), 2000)
        corner_samples.append(sum(len(chunk) for chunk in points))
        points.append(start + numpy.outer(numpy.arange(steps) / steps, end - start))
    return numpy.vstack(points), numpy.array(corner_samples), _inside_angles(corners, inside_on_left)


def _stretches(missed):
    """The runs of consecutive missed samples of a ring (the ring is closed), as index arrays."""
    if missed.all():
        return [numpy.arange(len(missed))]
    shift = int(numpy.argmin(missed))  # a reached sample: no run wraps past it
    rolled = numpy.roll(missed, -shift)
    edges = numpy.diff(numpy.concatenate(([0], rolled.astype(int), [0])))
    return [(numpy.arange(start, end) + shift) % len(missed) for start, end in zip(numpy.flatnonzero(edges == 1), numpy.flatnonzero(edges == -1))]


def _corner_fillets(points, corner_samples, angles, reachable, distances, missed, tool_radius: float):
    """The samples inside the fillet the tool leaves in each inside corner. At a corner of an
    arc's polygon (nearly straight) that is the corner itself, which the tool touches from
    r / sin(angle / 2). At a sharp corner the fillet runs from the corner along both sides to
    where the tool that fills the corner touches them; the corner counts as filled only when
    that tool is about where r / sin(angle / 2) puts it, not farther off beyond a neck."""
    fillets = numpy.zeros(len(points), dtype=bool)
    inside = [corner for corner in range(len(corner_samples)) if angles[corner] < math.pi and missed[corner_samples[corner]]]
    limits = {corner: tool_radius / math.sin(angles[corner] / 2.0) for corner in inside}
    for corner in inside:
        if angles[corner] >= _SHARP_CORNER:
            fillets[corner_samples[corner]] = distances[corner_samples[corner]] <= limits[corner] * (1.0 + _TOLERANCE)
    sharp = [corner for corner in inside if angles[corner] < _SHARP_CORNER and distances[corner_samples[corner]] <= _FILLET_SLACK * limits[corner]]
    if not sharp:
        return fillets
    centres = shapely.get_coordinates(shapely.shortest_line(shapely.points(points[corner_samples[sharp]]), reachable))[1::2]
    kinks = numpy.abs(angles - math.pi) > math.pi - _SHARP_CORNER  # sharp inside or outside corners
    sharp_samples = set(corner_samples[kinks].tolist())
    for corner, centre in zip(sharp, centres):
        index = corner_samples[corner]
        touched = numpy.hypot(*(points - centre).T) <= tool_radius * _TOUCH_SLACK + _TOLERANCE
        sides = [_fillet_side(index, step, missed, touched, sharp_samples) for step in (1, -1)]
        if None not in sides:
            fillets[[index, *sides[0], *sides[1]]] = True
    return fillets


def _fillet_side(index, step, missed, touched, sharp_samples):
    """The missed samples from a sharp corner on up to where the tool in the corner touches
    the outline. None when another sharp corner comes first: the corner is then the end of a
    slot narrower than the tool, or the tool misses the outline beyond an outside corner."""
    side = []
    sample = (index + step) % len(missed)
    while missed[sample] and len(side) < len(missed):
        if sample in sharp_samples:
            return None
        side.append(sample)
        if touched[sample]:
            break
        sample = (sample + step) % len(missed)
    return side


def _inside_angles(corners, inside_on_left: bool):
    """The pocket's inside angle at each corner of a ring."""
    before = corners - numpy.roll(corners, 1, axis=0)
    after = numpy.roll(corners, -1, axis=0) - corners
    turn = numpy.arctan2(after[:, 1], after[:, 0]) - numpy.arctan2(before[:, 1], before[:, 0])
    turn = (turn + math.pi) % (2 * math.pi) - math.pi  # left turn positive
    return math.pi - turn if inside_on_left else math.pi + turn


def _within(tool_radius: float, limit: float, strict: bool) -> bool:
    return tool_radius < limit - _TOLERANCE if strict else tool_radius <= limit + _TOLERANCE
