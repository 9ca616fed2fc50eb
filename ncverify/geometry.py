"""Geometry of moves against the stock: does a segment pass through the inside of the blank?

"Inside" is the open interior: a rapid that ends on the top face or runs along a side is
not in the material. Straight segments are clipped against the stock (Liang-Barsky for
boxes, shapely for polygon prisms; a lathe bar is the rectangle radius x Z). A dog-leg
rapid, whose axes each run at their own rate, may pass anywhere in the box its end points
span, so that box is what is tested. Symbolic segments become one Z3 query.
"""
from __future__ import annotations

import functools
import math

import numpy
import shapely
import shapely.ops
from shapely.geometry import LineString

from .solver import z3
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


def _spanned_rectangle(low, high):
    """The XY rectangle two points span; a line or a point when it has no width."""
    if low[0] < high[0] and low[1] < high[1]:
        return shapely.box(low[0], low[1], high[0], high[1])
    if low[:2] == high[:2]:
        return shapely.Point(low[0], low[1])
    return LineString([(low[0], low[1]), (high[0], high[1])])


def _spanned_box_overlap(stock: Stock, start, end, box) -> tuple[float, float, float] | None:
    """A point where the box spanned by the two end points meets the stock's inside."""
    low = [min(a, b) for a, b in zip(start, end)]
    high = [max(a, b) for a, b in zip(start, end)]
    if box is None:  # polygon prism: the spanned rectangle against the outline
        z_low, z_high = max(low[2], stock.z_range[0] + EPSILON), min(high[2], stock.z_range[1] - EPSILON)
        if z_low > z_high or (low[2] == high[2] and not stock.z_range[0] < low[2] < stock.z_range[1]):
            return None
        overlap = _spanned_rectangle(low, high).intersection(stock.outline.buffer(-EPSILON))
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
    """For (n, 3) arrays of known straight segments against a box or bar: a boolean mask,
    :func:`_clip_box` on each, the three axes at once (a run's few dozen rapids cost what
    the calls into numpy cost, not what their arithmetic does)."""
    box = stock_box(stock)
    if box is None:
        return numpy.array([_clip_prism(stock, tuple(a), tuple(b)) is not None for a, b in zip(starts, ends)], dtype=bool)
    lows, highs = numpy.array(box).T
    lows, highs = lows + EPSILON, highs - EPSILON
    delta = ends - starts
    still = delta == 0.0
    possible = (~still | ((lows < starts) & (starts < highs))).all(axis=1)
    with numpy.errstate(divide="ignore", invalid="ignore", over="ignore"):  # a tiny step: its infinity clips as the limit would
        t0 = numpy.where(still, -numpy.inf, (lows - starts) / delta)
        t1 = numpy.where(still, numpy.inf, (highs - starts) / delta)
    entry = numpy.minimum(t0, t1).max(axis=1, initial=0.0)
    leave = numpy.maximum(t0, t1).min(axis=1, initial=1.0)
    return possible & (entry <= leave)


def may_enter_symbolic(stock: Stock, start, end, dogleg: bool = False) -> z3.BoolRef:
    """A Z3 condition for "some point the rapid passes is inside the stock". A straight
    rapid passes start + t (end - start) for one t in [0, 1]; a dog-leg may pass any point
    of the box its ends span, so each axis gets its own t. A polygon prism is the union of
    the triangles of its outline (strictly inside across the outline's own edges, on either
    side of the edges the triangulation adds)."""
    # named per check (z3.FreshReal numbers per process, and the names steer the solver's model)
    distinct = [values.helper("t").term for _ in range(3 if dogleg else 1)]
    ts = distinct if dogleg else distinct * 3
    constraints = [z3.And(t >= 0, t <= 1) for t in distinct]
    point = []
    for a, b, t in zip(start, end, ts):
        a_term, b_term = values.term_of(a), values.term_of(b)
        point.append(a_term + (b_term - a_term) * t)
    box = stock_box(stock) or ((-math.inf, math.inf), (-math.inf, math.inf), stock.z_range)
    for coordinate, (low, high) in zip(point, box):
        if math.isfinite(low):
            constraints.append(coordinate > low + EPSILON)
        if math.isfinite(high):
            constraints.append(coordinate < high - EPSILON)
    if _is_round(stock):
        constraints.append(_within_circle(point[0], point[1], stock.diameter / 2.0))
    elif stock.kind == "polygon":
        constraints.append(z3.Or(*(_inside_triangle(point[0], point[1], triangle) for triangle in _triangles(stock.outline.wkb))))
    return z3.And(*constraints)


def _is_round(stock: Stock) -> bool:
    """A round blank about Z (:meth:`Stock.round_blank`): its symbolic test is the circle itself."""
    return stock.kind == "polygon" and stock.diameter is not None


def _within_circle(x, y, radius: float) -> z3.BoolRef:
    return x * x + y * y < (radius - EPSILON) ** 2


@functools.lru_cache(maxsize=8)
def _triangles(outline_wkb: bytes) -> list[list[tuple[tuple[float, float], tuple[float, float], bool]]]:
    """The outline as triangles, each a list of its counter-clockwise edges with a flag:
    does the edge lie on the outline (there the inside is open)?"""
    outline = shapely.from_wkb(outline_wkb)
    boundary = outline.boundary
    triangles = []
    for triangle in shapely.constrained_delaunay_triangles(outline).geoms:
        corners = list(shapely.geometry.polygon.orient(triangle).exterior.coords)[:-1]
        edges = []
        for first, second in zip(corners, corners[1:] + corners[:1]):
            middle = shapely.Point((first[0] + second[0]) / 2, (first[1] + second[1]) / 2)
            edges.append((first, second, boundary.distance(middle) < EPSILON))
        triangles.append(edges)
    return triangles


def _inside_triangle(x, y, edges) -> z3.BoolRef:
    """(x, y) left of every counter-clockwise edge: strictly, by EPSILON, on outline edges."""
    conditions = []
    for (x1, y1), (x2, y2), on_outline in edges:
        left = (x2 - x1) * (y - y1) - (y2 - y1) * (x - x1)
        length = math.hypot(x2 - x1, y2 - y1)
        conditions.append(left > EPSILON * length if on_outline else left >= 0)
    return z3.And(*conditions)

# --------------------------------------------------------------------------- the tool as a cylinder

def _outline(stock: Stock):
    """The stock's footprint in XY (box or polygon prism)."""
    if stock.kind == "box":
        return shapely.box(stock.x_range[0], stock.y_range[0], stock.x_range[1], stock.y_range[1])
    return stock.outline


def tool_enters(stock: Stock, start, end, radius: float, length: float | None, dogleg: bool = False) -> tuple[float, float, float] | None:
    """A point of the tool's path where the tool touches the inside of a box or polygon
    stock, or None. The tool is a cylinder of ``radius`` around its axis, from the tip (the
    programmed point) up ``length`` (None: up without end); it touches the stock where the
    tip is below the top, the body reaches above the bottom, and the axis comes nearer to
    the footprint than ``radius``. A dog-leg may pass anywhere in the box its ends span."""
    outline = _outline(stock)
    low, high = stock.z_range
    if dogleg:
        z_low, z_high = min(start[2], end[2]), max(start[2], end[2])
        if z_low >= high - EPSILON or (length is not None and z_high + length <= low + EPSILON):
            return None
        span = _spanned_rectangle([min(a, b) for a, b in zip(start, end)], [max(a, b) for a, b in zip(start, end)])
        if not _touches(outline, span, radius):
            return None
        point = shapely.ops.nearest_points(span, outline)[0]
        return point.x, point.y, z_low
    entry, leave = _tip_levels(start[2], end[2], low, high, length)
    if entry is None:
        return None
    first = [a + (b - a) * entry for a, b in zip(start, end)]
    last = [a + (b - a) * leave for a, b in zip(start, end)]
    path = shapely.Point(first[0], first[1]) if first[:2] == last[:2] else LineString([first[:2], last[:2]])
    if not _touches(outline, path, radius):
        return None
    near = shapely.ops.nearest_points(path, outline)[0]
    share = 0.0 if path.geom_type == "Point" or path.length == 0 else path.project(near) / path.length
    return near.x, near.y, first[2] + (last[2] - first[2]) * share


def _touches(outline, path, radius: float) -> bool:
    if radius > EPSILON:
        return outline.distance(path) < radius - EPSILON
    return outline.buffer(-EPSILON).intersects(path)


def _tip_levels(z0: float, z1: float, low: float, high: float, length: float | None):
    """The share (entry, leave) of a straight move along which the tool's tip is below the
    stock's top and its body above the bottom; (None, None) when there is none."""
    limits = [(high - EPSILON, -1.0)]  # tip below the top
    if length is not None:
        limits.append((low + EPSILON - length, 1.0))  # tip above bottom - length
    entry, leave = 0.0, 1.0
    for level, sign in limits:
        if z0 == z1:
            if (z0 - level) * sign <= 0:
                return None, None
            continue
        t = (level - z0) / (z1 - z0)
        if (z1 - z0) * sign > 0:
            entry = max(entry, t)
        else:
            leave = min(leave, t)
    return (entry, leave) if entry <= leave else (None, None)


def tool_may_enter_symbolic(stock: Stock, start, end, radius: float, length: float | None, dogleg: bool = False) -> z3.BoolRef:
    """:func:`tool_enters` as a Z3 condition. A polygon is widened by the radius with
    mitred corners, a little more than the tool reaches: a proof stays sound, and a
    violation the widening alone makes does not survive the witness's concrete run."""
    # named per check, like may_enter_symbolic's (the names steer the solver's model)
    distinct = [values.helper("t").term for _ in range(3 if dogleg else 1)]
    ts = distinct if dogleg else distinct * 3
    constraints = [z3.And(t >= 0, t <= 1) for t in distinct]
    point = []
    for a, b, t in zip(start, end, ts):
        a_term, b_term = values.term_of(a), values.term_of(b)
        point.append(a_term + (b_term - a_term) * t)
    x, y, z = point
    low, high = stock.z_range
    constraints.append(z < high - EPSILON)
    if length is not None:
        constraints.append(z + length > low + EPSILON)
    if stock.kind == "box":
        (x_low, x_high), (y_low, y_high) = stock.x_range, stock.y_range
        if radius > EPSILON:
            dx = z3.If(x < x_low, x_low - x, z3.If(x > x_high, x - x_high, z3.RealVal(0)))
            dy = z3.If(y < y_low, y_low - y, z3.If(y > y_high, y - y_high, z3.RealVal(0)))
            constraints.append(dx * dx + dy * dy < (radius - EPSILON) ** 2)
        else:
            constraints += [x > x_low + EPSILON, x < x_high - EPSILON, y > y_low + EPSILON, y < y_high - EPSILON]
        return z3.And(*constraints)
    if _is_round(stock):
        constraints.append(_within_circle(x, y, stock.diameter / 2.0 + radius))
        return z3.And(*constraints)
    widened = stock.outline.buffer(radius, join_style="mitre", mitre_limit=1000.0) if radius > EPSILON else stock.outline
    constraints.append(z3.Or(*(_inside_triangle(x, y, triangle) for triangle in _triangles(widened.wkb))))
    return z3.And(*constraints)
