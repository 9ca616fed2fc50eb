"""Arcs and helices about the Z axis, as pieces of the workpiece's sweep: measured as
arcs, not as chords.

CAM output is full of them (adaptive clearing's loops, contours' corners, helical
ramps). Cut as chords, one arc became several pieces, each measured on its own, with the
chords' sagitta as the stray by which the bounds are widened. An arc measured as itself is
exact: seen from above, a point's distance from it is its distance from the circle where
the point lies within the arc's angle, else from the nearer end. A helix is an arc whose
height changes on the way; it is cut in parts that climb at most one cell, as a steep
straight move is.

The cells near an arc all lie in its circle's annulus widened by the reach, within its
box widened by the reach: row by row, the sweep measures the two spans where that annulus
crosses the row, inside the box.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy

_MOST_DRIFT = 0.125  # of a cell: an arc whose end lies farther off its circle is cut as chords
_MOST_PARTS = 64  # parts an arc is cut into for its length and climb (see XYArcs.of)


@dataclass(frozen=True)
class XYArcs:
    """Arcs of at most a half turn about the Z axis, given counterclockwise from
    ``(sx, sy)`` to ``(ex, ey)``, both measured from the centre ``(cx, cy)`` and both on
    the circle of ``radius``; ``low`` and ``high``: the heights between which each one
    climbs. ``drift``: how far the path may stray from that circle (the programmed end lies
    off the circle through the start); ``length``: each arc's length along its path."""

    cx: numpy.ndarray
    cy: numpy.ndarray
    radius: numpy.ndarray
    sx: numpy.ndarray
    sy: numpy.ndarray
    ex: numpy.ndarray
    ey: numpy.ndarray
    low: numpy.ndarray
    high: numpy.ndarray
    drift: numpy.ndarray
    length: numpy.ndarray

    @classmethod
    def of(cls, starts, ends, centres, clockwise, longest: float, rise: float) -> tuple["XYArcs", numpy.ndarray]:
        """The arcs from ``starts`` to ``ends`` ((x, y, z) rows) around ``centres`` ((x, y)),
        turning as :func:`ncverify.workpiece.arc_chords` turns them (an arc ending where it
        starts turns once), each cut into equal parts of at most a half turn and, up to 64
        parts, of at most ``longest`` and a climb of ``rise``; and the arc of each part. A part
        that meets material counts whole as cutting, and a part's box holds little but its
        own cells. A longer part, or one that climbs more, is as sound (its heights are its
        range), only coarser: an arc of a kilometre's radius, or a helix down from a
        kilometre up (a typing slip), is not cut into millions. Each end must lie away from
        its centre (see :func:`measurable`)."""
        sx, sy = starts[:, 0] - centres[:, 0], starts[:, 1] - centres[:, 1]
        ex, ey = ends[:, 0] - centres[:, 0], ends[:, 1] - centres[:, 1]
        radius, end_radius = length(sx, sy), length(ex, ey)
        begin, finish = numpy.arctan2(sy, sx), numpy.arctan2(ey, ex)
        sweep = numpy.where(clockwise, begin - finish, finish - begin) % (2 * math.pi)
        sweep[sweep == 0.0] = 2 * math.pi  # a full circle
        ex, ey = ex * (radius / end_radius), ey * (radius / end_radius)  # the end moved onto the circle
        # counterclockwise from the first end: a clockwise arc's parts run from its end back
        first_x, first_y, last_x, last_y = numpy.where(clockwise, [ex, ey, sx, sy], [sx, sy, ex, ey])
        first_z, last_z = numpy.where(clockwise, [ends[:, 2], starts[:, 2]], [starts[:, 2], ends[:, 2]])
        climb = last_z - first_z
        by_size = numpy.minimum(numpy.ceil(numpy.maximum(radius * sweep / longest, numpy.abs(climb) / rise)), _MOST_PARTS)
        counts = numpy.maximum(numpy.maximum(by_size, numpy.ceil(sweep / math.pi)), 1).astype(numpy.int64)
        arc = numpy.arange(len(radius)).repeat(counts)
        step = numpy.arange(len(arc)) - (counts.cumsum() - counts).repeat(counts)  # each part's place in its arc
        last = numpy.append(step[1:] == 0, True)
        part_radius, turn = radius.take(arc), (sweep / counts).take(arc)
        px, py = first_x.take(arc), first_y.take(arc)  # each part's first point: the arc's own where it is the first part
        later = step.nonzero()[0]
        angle = numpy.where(clockwise, finish, begin).take(arc.take(later)) + turn.take(later) * step.take(later)
        px[later], py[later] = part_radius.take(later) * numpy.cos(angle), part_radius.take(later) * numpy.sin(angle)
        qx, qy = numpy.roll(px, -1), numpy.roll(py, -1)
        qx[last], qy[last] = last_x, last_y
        pz = first_z.take(arc) + (climb / counts).take(arc) * step
        qz = numpy.roll(pz, -1)
        qz[last] = last_z
        return cls(centres[:, 0].take(arc), centres[:, 1].take(arc), part_radius, px, py, qx, qy, numpy.minimum(pz, qz), numpy.maximum(pz, qz),
                   numpy.abs(end_radius - radius).take(arc), length(part_radius * turn, qz - pz)), arc

    def keys(self):
        """What makes arcs meet the same cells at the same distances: their centres, ends
        and drift, as bits (arcs equal to the bit, at any heights, are measured alike)."""
        return [numpy.ascontiguousarray(values).view(numpy.uint64) for values in (self.cx, self.cy, self.sx, self.sy, self.ex, self.ey, self.drift)]

    def __len__(self) -> int:
        return len(self.radius)

    def take(self, index) -> "XYArcs":
        """The arcs ``index`` (an array of indices), in its order."""
        return XYArcs(*(getattr(self, field.name).take(index) for field in fields(self)))

    def within_angle(self, arcs, vx, vy):
        """Do the directions (vx, vy) from the centres of ``arcs`` lie within their angles
        (ends included; the centre itself lies within every arc's)?"""
        within = self.sx.take(arcs) * vy >= self.sy.take(arcs) * vx
        within &= vx * self.ey.take(arcs) >= vy * self.ex.take(arcs)
        return within

    def distance(self, arcs, px, py):
        """Distance of the points (px, py) from ``arcs`` (one an arc), seen from above:
        from the circle where the point lies within the arc's angle, else from the nearer end."""
        vx, vy = px - self.cx.take(arcs), py - self.cy.take(arcs)
        distance = length(vx, vy)
        distance -= self.radius.take(arcs)
        numpy.abs(distance, out=distance)
        beyond = (~self.within_angle(arcs, vx, vy)).nonzero()[0]
        if len(beyond):
            arcs, vx, vy = arcs.take(beyond), vx.take(beyond), vy.take(beyond)
            distance[beyond] = numpy.minimum(length(vx - self.sx.take(arcs), vy - self.sy.take(arcs)), length(vx - self.ex.take(arcs), vy - self.ey.take(arcs)))
        return distance

    def box(self):
        """(x low, y low, x high, y high) of each arc: its ends, and the points of its
        circle at 0, 90, 180 and 270 degrees that lie within its angle."""
        arcs = numpy.arange(len(self))
        xs, ys = [self.sx, self.ex], [self.sy, self.ey]
        for x, y in ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)):
            reached = self.within_angle(arcs, numpy.full(len(self), x), numpy.full(len(self), y))
            xs.append(numpy.where(reached, x * self.radius, self.sx))
            ys.append(numpy.where(reached, y * self.radius, self.sy))
        return (self.cx + numpy.minimum.reduce(xs), self.cy + numpy.minimum.reduce(ys),
                self.cx + numpy.maximum.reduce(xs), self.cy + numpy.maximum.reduce(ys))

    def size(self):
        """How far from the origin each arc reaches at most (the rounding of its distances grows with it)."""
        return numpy.maximum(numpy.abs(self.cx), numpy.abs(self.cy)) + self.radius

    def row_spans(self, arcs, y, reach):
        """The X ranges of the annulus within ``reach`` (one a row) of the circles of
        ``arcs`` on the rows at ``y``: ((left low, left high), (right low, right high)), the
        left one reaching to the centre where the row passes no hole, both empty (low above
        high) where the row passes no annulus."""
        cx, cy, radius = self.cx.take(arcs), self.cy.take(arcs), self.radius.take(arcs)
        across = (y - cy) ** 2
        outer = numpy.sqrt(numpy.maximum((radius + reach) ** 2 - across, 0.0))
        hole = numpy.where(radius > reach, numpy.sqrt(numpy.maximum((radius - reach) ** 2 - across, 0.0)), 0.0)
        missed = (radius + reach) ** 2 < across
        outer[missed], hole[missed] = -1.0, 1.0
        return (cx - outer, cx - hole), (cx + hole, cx + outer)


def measurable(starts, ends, centres, resolution: float, reach_limit: float):
    """Which arcs (rows of (x, y) starts, ends, centres) :class:`XYArcs` measures: ends
    away from the centre and within an eighth of a cell of one circle, and near enough the
    origin for the distances to be exact to far below a cell (``reach_limit``); the rest
    are cut as chords."""
    start_radius = length(starts[:, 0] - centres[:, 0], starts[:, 1] - centres[:, 1])
    end_radius = length(ends[:, 0] - centres[:, 0], ends[:, 1] - centres[:, 1])
    far = numpy.maximum(numpy.abs(centres).max(axis=1), numpy.maximum(numpy.abs(starts).max(axis=1), numpy.abs(ends).max(axis=1)))
    with numpy.errstate(invalid="ignore"):
        return (start_radius > 0.0) & (end_radius > 0.0) & (numpy.abs(end_radius - start_radius) <= _MOST_DRIFT * resolution) & (far <= reach_limit)


def length(x, y):
    """sqrt(x*x + y*y): the distance every part of the sweep measures (here and in
    :mod:`ncverify.workpiece`), the same bits everywhere. Not numpy.hypot, which costs
    several times more for its care of values past 1e154, whose squares overflow to
    infinity here: a cell that far from a path is beyond any tool's reach either way."""
    return numpy.sqrt(x * x + y * y)


_RADIUS_SLACK = 1e-3  # mm: a radius this much short of half the chord is taken as a half circle


def radius_arc_centres(starts, ends, radii, clockwise):
    """The centres of arcs given by a radius word, as the controls place them (ISO and
    Fagor ``R``, SINUMERIK ``CR=``, Klartext ``CR``): on the side of the chord that makes
    the arc at most a half turn when the radius is positive, more when it is negative.
    ``starts`` and ``ends``: (n, 2) points in the arcs' plane; ``radii`` signed;
    ``clockwise`` each arc's direction. NaN where no circle of that radius joins the two
    points (the control stops with an alarm, which the arc rules report) or they coincide."""
    chord = ends - starts
    half = numpy.hypot(chord[:, 0], chord[:, 1]) / 2
    reach = numpy.abs(radii)
    with numpy.errstate(divide="ignore", invalid="ignore"):
        rise = numpy.sqrt(numpy.maximum(reach * reach - half * half, 0.0)) / (2 * half)  # along the chord's normal, per unit of chord
        side = numpy.where(clockwise == (radii < 0), 1.0, -1.0)  # +1: left of the chord, where a short counterclockwise arc's centre is
        centres = (starts + ends) / 2 + (side * rise)[:, None] * numpy.column_stack((-chord[:, 1], chord[:, 0]))
    unplaceable = ~(half > 0) | (reach < half - _RADIUS_SLACK) | ~numpy.isfinite(centres).all(axis=1)
    centres[unplaceable] = numpy.nan
    return centres
