"""Geometry of moves against the stock: does a segment pass through the inside of the blank?

"Inside" is the open interior: a rapid that ends on the top face or runs along a side is
not in the material. Straight segments are clipped against the stock (Liang-Barsky for
boxes, shapely for polygon prisms; a lathe bar is the rectangle radius x Z). A dog-leg
rapid, whose axes each run at their own rate, may pass anywhere in the box its end points
span, so that box is what is tested. Symbolic segments become one Z3 query.
"""
from __future__ import annotations

import math

import numpy
import shapely
import z3
from shapely.geometry import LineString

from . import values
from .context import Stock

EPSILON = 1e-6


def stock_box(stock: Stock) -> tuple[tuple[float, float], ...] | None:
    """The stock as axis ranges in program coordinates (X, Y, Z) when it is a box or a bar
    (a bar's X is a diameter: its range is -D..D in the program's X)."""
    if stock.kind == "box":
        return stock.x_range, stock.y_range, stock.z_range
    if stock.kind == "cylinder":
        return (-stock.diameter, stock.diameter), (-math.inf, math.inf), stock.z_range
    return None


def enters(stock: Stock, start, end, dogleg: bool = False) -> tuple[float, float, float] | None:
    """A point of the segment inside the stock, or None. ``start``/``end`` are (x, y, z)
    floats in program coordinates (y is ignored for a lathe bar)."""
    box = stock_box(stock)
    if dogleg:
        return _spanned_box_overlap(stock, start, end, box)
    if box is not None:
        return _clip_box(start, end, box)
    return _clip_prism(stock, start, end)


def _spanned_box_overlap(stock: Stock, start, end, box) -> tuple[float, float, float] | None:
    """A point where the box spanned by the two end points meets the stock's inside."""
    low = [min(a, b) for a, b in zip(start, end)]
    high = [max(a, b) for a, b in zip(start, end)]
    if box is None:  # polygon prism: the spanned rectangle against the outline
        z_low, z_high = max(low[2], stock.z_range[0] + EPSILON), min(high[2], stock.z_range[1] - EPSILON)
        if z_low > z_high or (low[2] == high[2] and not stock.z_range[0] < low[2] < stock.z_range[1]):
            return None
        overlap = shapely.box(low[0], low[1], high[0], high[1]).buffer(0 if low[:2] != high[:2] else EPSILON).intersection(stock.outline.buffer(-EPSILON))
        if overlap.is_empty:
            return None
        point = overlap.representative_point()
        return point.x, point.y, (z_low + z_high) / 2
    point = []
    for a, b, (lower, upper) in zip(low, high, box):
        inside_low, inside_high = max(a, lower + EPSILON), min(b, upper - EPSILON)
        if inside_low > inside_high:
            return None
        point.append((inside_low + inside_high) / 2)
    return tuple(point)


def _clip_box(start, end, box) -> tuple[float, float, float] | None:
    """Liang-Barsky against the open box shrunk by EPSILON; for a dog-leg (low, high)
    corners, any overlap of the two boxes."""
    entry, leave = 0.0, 1.0
    for a, b, (low, high) in zip(start, end, box):
        low, high = low + EPSILON, high - EPSILON
        delta = b - a
        if delta == 0.0:
            if not low < a < high:
                return None
            continue
        t0, t1 = (low - a) / delta, (high - a) / delta
        if t0 > t1:
            t0, t1 = t1, t0
        entry, leave = max(entry, t0), min(leave, t1)
        if entry > leave:
            return None
    middle = (entry + leave) / 2
    return tuple(a + (b - a) * middle for a, b in zip(start, end))


def _clip_prism(stock: Stock, start, end) -> tuple[float, float, float] | None:
    z_low, z_high = stock.z_range[0] + EPSILON, stock.z_range[1] - EPSILON
    (x0, y0, z0), (x1, y1, z1) = start, end
    if (x0, y0) == (x1, y1):
        inside = stock.outline.contains(shapely.Point(x0, y0))
        overlap = max(min(z0, z1), z_low) < min(max(z0, z1), z_high)
        return (x0, y0, (max(min(z0, z1), z_low) + min(max(z0, z1), z_high)) / 2) if inside and overlap else None
    path = LineString([(x0, y0), (x1, y1)])
    length = path.length
    pieces = path.intersection(stock.outline.buffer(-EPSILON))
    for piece in getattr(pieces, "geoms", [pieces]):
        if piece.is_empty or piece.length == 0:
            continue
        t0, t1 = sorted(path.project(shapely.Point(point)) / length for point in (piece.coords[0], piece.coords[-1]))
        za, zb = z0 + (z1 - z0) * t0, z0 + (z1 - z0) * t1
        low, high = max(min(za, zb), z_low), min(max(za, zb), z_high)
        if low < high or (za == zb and z_low < za < z_high):
            t = t0 + (t1 - t0) * 0.5 if z1 == z0 else ((low + high) / 2 - z0) / (z1 - z0)
            return (x0 + (x1 - x0) * t, y0 + (y1 - y0) * t, z0 + (z1 - z0) * t)
    return None


def enters_many(stock: Stock, starts: numpy.ndarray, ends: numpy.ndarray) -> numpy.ndarray:
    """For (n, 3) arrays of known straight segments against a box or bar: a boolean mask."""
    box = stock_box(stock)
    if box is None:
        return numpy.array([_clip_prism(stock, tuple(a), tuple(b)) is not None for a, b in zip(starts, ends)], dtype=bool)
    entry = numpy.zeros(len(starts))
    leave = numpy.ones(len(starts))
    possible = numpy.ones(len(starts), dtype=bool)
    for axis, (low, high) in enumerate(box):
        low, high = low + EPSILON, high - EPSILON
        a, b = starts[:, axis], ends[:, axis]
        delta = b - a
        still = delta == 0.0
        possible &= ~still | ((low < a) & (a < high))
        with numpy.errstate(divide="ignore", invalid="ignore"):
            t0 = numpy.where(still, -numpy.inf, (low - a) / delta)
            t1 = numpy.where(still, numpy.inf, (high - a) / delta)
        entry = numpy.maximum(entry, numpy.minimum(t0, t1))
        leave = numpy.minimum(leave, numpy.maximum(t0, t1))
    return possible & (entry <= leave)


def may_enter_symbolic(stock: Stock, start, end) -> z3.BoolRef | None:
    """A Z3 condition for "some point of the segment is inside the box or bar"; None for
    polygon stocks (not modelled symbolically)."""
    box = stock_box(stock)
    if box is None:
        return None
    t = z3.FreshReal("t")
    constraints = [t >= 0, t <= 1]
    for a, b, (low, high) in zip(start, end, box):
        a_term, b_term = values.term_of(a), values.term_of(b)
        point = a_term + (b_term - a_term) * t
        if math.isfinite(low):
            constraints.append(point > low + EPSILON)
        if math.isfinite(high):
            constraints.append(point < high - EPSILON)
    return z3.And(*constraints)
