"""SL contours: the subprograms cycle 14 lists, read as shapely polygons (reference B §6.4).

Each ``LBL n ... LBL 0`` is walked (not executed): straight lines, arcs about ``CC``
(``C``), arcs by radius (``CR``), polar points (``LP``/``CP``) become the outline's points;
arcs are approximated every 5 degrees. A closed contour described clockwise with RR or
counter-clockwise with RL is a pocket (the tool runs inside); the other two combinations
make an island (seed L9063-9066). The region the cycle machines is the union of the
pockets less the islands. Anything that cannot be resolved to numbers (a free Q parameter,
a tangential arc, FK) leaves the geometry unknown: rules then answer ``unknown``.

Beside the geometry, :func:`subprograms` records what the manual forbids or requires in a
contour subprogram whatever its geometry (seed L9058-9071): approach and departure blocks,
tool-axis coordinates, feed rates, M functions, cycle definitions, the compensation written,
and the axes and path function of the first block. The checks in
:mod:`ncverify.checks.heidenhain_contour` judge them for the cycle that uses the contour.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import shapely
from shapely.geometry import Point, Polygon

from ... import ir
from ..control_flow import PathEnd
from ...dialect import logical_lines
from ...values import VACANT

_ELEMENT_LIMIT = 16384  # contour elements per SL cycle (seed L9050-9051)
_ARC_STEP = math.radians(5.0)


@dataclass(frozen=True)
class Contour:
    label: object
    outline: Polygon
    pocket: bool | None  # None: R0 or no compensation, the kind is ambiguous
    start: tuple[float, float]


class _Unresolved(Exception):
    pass


@dataclass(frozen=True)
class Subprogram:
    """What a contour subprogram contains, for the rules; ``contour`` is its geometry, or
    None when it cannot be resolved (then ``closed`` is None too)."""

    label: object
    end: object  # the span of its LBL 0
    contour: Contour | None
    closed: bool | None
    first_axes: frozenset  # the axes the first path block programs
    first_span: object
    first_is_line: bool  # the first path block is a straight line L (not an arc, not APPR)
    first_is_approach: bool
    sides: tuple  # (side, span) of every R0 / RL / RR written: side is left, right or off
    forbidden: tuple  # (what, span): approach/departure, tool axis, machining cycle
    technology: tuple  # (what, span): feed rates and M functions, which the cycle does not take from here


@dataclass(frozen=True)
class ContourUse:
    """The contour a machining cycle works on: how it was defined, and its subprograms."""

    how: str  # "cycle 14", "CONTOUR DEF" or "SEL CONTOUR" (its subprograms are in another program, not read)
    span: object  # the defining block
    labels: tuple
    kinds: tuple | None  # CONTOUR DEF: "P", "I" or "V" per label
    depths: tuple | None  # CONTOUR DEF: the DEPTH written after each subcontour, or None
    subprograms: tuple[Subprogram, ...]


def contours(found: list[Subprogram], labels) -> list[Contour] | None:
    """The subcontours of ``labels`` in order, or None when one cannot be resolved."""
    outlines = [subprogram.contour for subprogram in found]
    return None if len(outlines) != len(labels) or any(contour is None for contour in outlines) else outlines


def subprograms(runner, labels, span) -> list[Subprogram]:
    """Every subprogram of ``labels`` that exists, in order (a missing label is reported by
    the interpreter's label search)."""
    found = []
    for label in labels:
        try:
            found.append(_walk(runner, label, span))
        except (_Unresolved, PathEnd):
            continue
    return found


def region(found: list[Contour], by_start_points: bool = False):
    """Union of the pockets less the islands; None when a contour's kind is ambiguous.
    ``by_start_points`` (cycle 14): a first pocket that starts inside a later pocket it
    overlaps is combined with it by intersection, not union (seed L9254-9320)."""
    if any(contour.pocket is None for contour in found):
        return None
    pockets = [contour for contour in found if contour.pocket]
    islands = [contour.outline for contour in found if not contour.pocket]
    if not pockets:
        return None
    if by_start_points and found[0].pocket:
        start = Point(found[0].start)
        area = found[0].outline
        for other in pockets[1:]:
            area = area.intersection(other.outline) if other.outline.contains(start) else area.union(other.outline)
    else:
        area = shapely.union_all([contour.outline for contour in pockets])
    if islands:
        area = area.difference(shapely.union_all(islands))
    return area


def _walk(runner, label, span) -> Subprogram:
    position = runner.find_label(label, span)
    walker = _Walker(runner)
    content = _Content()
    source = position.source
    path = None if source is runner.main_source else source.name
    for line_number, offset, _next, raw in logical_lines(source, position.offset, runner.frontend):
        for index, block in enumerate(runner.frontend.blocks(raw, line_number, path)):
            if offset == position.offset and index < position.block_index:
                continue
            for op in block.ops:
                if isinstance(op, ir.Return):
                    return content.subprogram(label, op.span, walker)
                content.take(op)
                walker.take_if_resolved(op)
        if walker.elements > _ELEMENT_LIMIT:
            raise _Unresolved
    raise _Unresolved


_MOTION_OPS = (ir.PoleArc, ir.TangentArc, ir.PolarMove, ir.Lift)
_TRANSFORMS = {7.0, 8.0, 10.0, 11.0, 19.0, 26.0, 247.0}  # allowed in a subcontour, and they stay active after it (seed L9061-9062)


class _Content:
    """The non-geometric facts of a subprogram, gathered op by op."""

    def __init__(self):
        self.first_axes = None
        self.first_span = None
        self.first_is_line = False
        self.first_is_approach = False
        self.approach_pending = False
        self.sides = []
        self.forbidden = []
        self.technology = []

    def take(self, op) -> None:
        if isinstance(op, ir.SetFeed):
            self.technology.append(("a feed rate F", op.span))
        elif isinstance(op, (ir.Coolant, ir.Stop, ir.Spindle)):
            self.technology.append(("an M function", op.span))
        elif isinstance(op, ir.Move) and op.targets:
            self.motion(op, set(op.targets), op.arc is None)
        elif isinstance(op, ir.CutterComp):
            self.sides.append((op.side, op.span))
        elif isinstance(op, ir.Approach):
            self.forbidden.append(("an APPR/DEP block", op.span))
            self.approach_pending = self.first_axes is None
        elif isinstance(op, ir.CycleDefine):
            if float(ir.cycle_code(op.cycle)) not in _TRANSFORMS:
                self.forbidden.append(("a cycle definition", op.span))
        elif isinstance(op, ir.DialectStatement):
            self.statement(op)
        elif isinstance(op, _MOTION_OPS):
            axes = {word[-1] for word in op.words if word[-1] in "XYZ" and word[:-1] in ("", "I")}
            if isinstance(op, ir.PolarMove):
                axes |= {"X", "Y"}  # PR / PA give a point of the plane
            self.motion(op, axes, isinstance(op, ir.Lift))

    def statement(self, op: ir.DialectStatement) -> None:
        if isinstance(op, ir.CallActiveCycle):
            self.technology.append(("an M function", op.span))
        elif isinstance(op, ir.OldCycle) and op.number not in _TRANSFORMS:
            self.forbidden.append(("a cycle definition", op.span))

    def motion(self, op, axes: set, straight: bool) -> None:
        if "Z" in axes:
            self.forbidden.append(("a tool-axis coordinate", op.span))
        if self.first_axes is None:
            self.first_axes = frozenset(axes)
            self.first_span = op.span
            self.first_is_line = straight and not self.approach_pending
            self.first_is_approach = self.approach_pending

    def subprogram(self, label, end, walker) -> Subprogram:
        contour = walker.contour(label) if walker.resolved else None
        closed = None if not walker.resolved else walker.closed
        return Subprogram(label, end, contour, closed, self.first_axes or frozenset(), self.first_span or end, self.first_is_line,
                          self.first_is_approach, tuple(self.sides), tuple(self.forbidden), tuple(self.technology))


class _Walker:
    def __init__(self, runner):
        self.runner = runner
        self.points: list[tuple[float, float]] = []
        self.pole = None
        self.side = None
        self.elements = 0
        self.resolved = True

    def take_if_resolved(self, op) -> None:
        if not self.resolved:
            return
        try:
            self.take(op)
        except _Unresolved:
            self.resolved = False

    @property
    def closed(self) -> bool:
        return len(self.points) >= 3 and math.dist(self.points[0], self.points[-1]) <= 1e-3

    def number(self, expr):
        value = self.runner.value(expr)
        if type(value) is not float or value is VACANT:
            raise _Unresolved
        return value

    @property
    def here(self):
        if not self.points:
            raise _Unresolved
        return self.points[-1]

    def point(self, words: dict, incremental=frozenset()):
        x, y = self.points[-1] if self.points else (None, None)
        for axis in ("X", "Y"):
            for written in (axis, "I" + axis):
                if written in words:
                    value = self.number(words[written])
                    relative = written.startswith("I") or axis in incremental
                    current = x if axis == "X" else y
                    if relative and current is None:
                        raise _Unresolved
                    value = current + value if relative else value
                    x, y = (value, y) if axis == "X" else (x, value)
        if x is None or y is None:
            raise _Unresolved
        return x, y

    def take(self, op) -> None:
        self.elements += 1
        if isinstance(op, ir.Move) and op.targets:
            end = self.point(op.targets, op.incremental)
            if op.arc and "R" in op.arc:
                self.arc_by_radius(end, self.number(op.arc["R"]), op.kind == "arc_ccw")
            else:
                self.points.append(end)
            return
        if isinstance(op, ir.CutterComp):
            self.side = op.side
            return
        if isinstance(op, ir.Pole):
            self.pole = self.point(op.words) if op.words else self.here
        elif isinstance(op, (ir.PoleArc, ir.TangentArc)):
            end = self.point(op.words)
            if isinstance(op, ir.TangentArc):
                raise _Unresolved
            self.arc_about_pole(end, op.words.get("DR", 1.0) > 0)
        elif isinstance(op, ir.PolarMove):
            self.polar(op.words, op.kind)
        elif isinstance(op, ir.Lift):
            self.points.append(self.point(op.words))

    def arc_about_pole(self, end, ccw: bool, turn=None) -> None:
        if self.pole is None:
            raise _Unresolved
        cx, cy = self.pole
        sx, sy = self.here
        start_angle = math.atan2(sy - cy, sx - cx)
        radius = math.hypot(sx - cx, sy - cy)
        if turn is None:
            end_angle = math.atan2(end[1] - cy, end[0] - cx)
            turn = (end_angle - start_angle) % (2 * math.pi)
            if not ccw:
                turn = turn - 2 * math.pi if turn > 0 else turn
            if abs(turn) < 1e-12:
                turn = 2 * math.pi if ccw else -2 * math.pi
        steps = max(1, int(abs(turn) / _ARC_STEP))
        for step in range(1, steps + 1):
            angle = start_angle + turn * step / steps
            self.points.append((cx + radius * math.cos(angle), cy + radius * math.sin(angle)))

    def arc_by_radius(self, end, radius: float, ccw: bool) -> None:
        sx, sy = self.here
        chord = math.hypot(end[0] - sx, end[1] - sy)
        if chord == 0 or chord > 2 * abs(radius) + 1e-9:
            raise _Unresolved
        middle = ((sx + end[0]) / 2, (sy + end[1]) / 2)
        height = math.sqrt(max(radius * radius - chord * chord / 4, 0.0))
        left = (-(end[1] - sy) / chord, (end[0] - sx) / chord)
        sign = 1.0 if ccw == (radius > 0) else -1.0
        self.pole = (middle[0] + sign * height * left[0], middle[1] + sign * height * left[1])
        self.arc_about_pole(end, ccw)

    def polar(self, params, kind: str) -> None:
        if self.pole is None:
            raise _Unresolved
        cx, cy = self.pole
        if not self.points and "PR" in params and "PA" in params:
            angle = self.number(params["PA"])
            radius = self.number(params["PR"])
            self.points.append((cx + radius * math.cos(math.radians(angle)), cy + radius * math.sin(math.radians(angle))))
            return
        sx, sy = self.here
        radius = self.number(params["PR"]) if "PR" in params else math.hypot(sx - cx, sy - cy)
        angle = math.degrees(math.atan2(sy - cy, sx - cx))
        if "PA" in params:
            end_angle = self.number(params["PA"])
        else:
            end_angle = angle + self.number(params.get("IPA", 0.0))
        end = (cx + radius * math.cos(math.radians(end_angle)), cy + radius * math.sin(math.radians(end_angle)))
        if kind == "arc":
            self.arc_about_pole(end, params.get("DR", 1.0) > 0, math.radians(end_angle - angle) if "IPA" in params else None)
        else:
            self.points.append(end)

    def contour(self, label) -> Contour | None:
        points = self.points
        if len(points) < 3:
            return None
        outline = Polygon(points)  # a contour ending short of its start is closed by a straight line, as the control does
        if not outline.is_valid:
            outline = shapely.make_valid(outline)
            if not isinstance(outline, Polygon):
                return None
        counter_clockwise = _signed_area(points) > 0
        pocket = None if self.side in (None, "off") else (counter_clockwise == (self.side == "left"))
        return Contour(label, outline, pocket, points[0])


def _signed_area(points) -> float:
    return sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(points, points[1:] + points[:1])) / 2.0
