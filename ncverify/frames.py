"""Coordinate transformations: where a position the program writes lies on the workpiece.

A :class:`Frame` is the affine map from the coordinates a program writes (after datum
shifts, rotations, mirror images and scaling) to workpiece coordinates: the coordinates of
the stock (BLK FORM, WORKPIECE, annotations, the project file) and of the travel check's
work offset. It acts on X, Y and Z; other axes pass through unchanged.

``w = linear . p + offset``: ``linear`` is a 3x3 matrix of known numbers (rows: workpiece
axes, columns: program axes) with ``None`` for an entry that is not known (a rotation by a
free parameter would make the map nonlinear, so it is unknown, never a guess); ``offset``
holds values (floats or symbolic values from :mod:`ncverify.values`) or ``None``.

Composition follows the programs: ``compose(outer, inner)`` is "inner in the system
outer leaves", so a transformation appended in the current (already transformed) system
is ``compose(current, appended)``.

The interpreter keeps positions in program coordinates (incremental moves and cycles
compute there); :class:`WorkpieceObserver` hands the rules segments, arcs, holes and
motion runs in workpiece coordinates while a frame other than the identity is active.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy

from . import ir, values
from .trace import Arc, Fault, MotionRun, Segment

AXES = ("X", "Y", "Z")
_INDEX = {axis: index for index, axis in enumerate(AXES)}
_IDENTITY_ROWS = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


@dataclass(frozen=True, slots=True)
class Frame:
    """A coordinate transformation: ``linear`` rows, then ``offset``."""

    linear: tuple = _IDENTITY_ROWS
    offset: tuple = (0.0, 0.0, 0.0)

    @property
    def is_identity(self) -> bool:
        return self.linear == _IDENTITY_ROWS and all(type(value) is float and value == 0.0 for value in self.offset)

    @property
    def is_numeric(self) -> bool:
        """Every entry a known number: the vectorised path can map arrays."""
        return all(type(entry) is float for row in self.linear for entry in row) and all(type(value) is float for value in self.offset)

    def _moves(self, index: int) -> bool:
        return self.linear[index] != _IDENTITY_ROWS[index] or not (type(self.offset[index]) is float and self.offset[index] == 0.0)

    def keeps_axis(self, axis: str) -> bool:
        """The axis maps onto itself alone (no other axis enters it, it enters no other)."""
        index = _INDEX[axis]
        return all(self.linear[index][other] == 0.0 and self.linear[other][index] == 0.0 for other in range(3) if other != index)

    def to_workpiece(self, point: dict) -> dict:
        """A position (axis -> value or None) in workpiece coordinates. Axes the point does
        not hold stay absent; an axis whose mapping needs an unknown entry or an unknown
        coordinate becomes None."""
        mapped = dict(point)
        for index, axis in enumerate(AXES):
            if axis in point and self._moves(index):
                mapped[axis] = _row_value(self.linear[index], self.offset[index], point)
        return mapped

    def level(self, axis: str, value, at: dict):
        """Where a level along ``axis`` (a hole's bottom, a clearance height) lies on the
        workpiece, the other axes being ``at``; None when the axis is tilted or unknown."""
        if axis not in _INDEX or value is None:
            return value
        if not self.keeps_axis(axis):
            return None
        return self.to_workpiece({**at, axis: value}).get(axis)

    def inverse(self) -> "Frame | None":
        """The map back to program coordinates; None when it is not known or not invertible."""
        if not all(type(entry) is float for row in self.linear for entry in row):
            return None
        matrix = numpy.array(self.linear)
        if abs(numpy.linalg.det(matrix)) < 1e-12:
            return None
        inverted = tuple(tuple(_clean(float(entry)) for entry in row) for row in numpy.linalg.inv(matrix))
        offset = tuple(_negated(_row_value(row, 0.0, dict(zip(AXES, self.offset)))) for row in inverted)
        return Frame(inverted, offset)

    def plane_similarity(self, plane: tuple[str, str, str]):
        """For an arc in ``plane``: ``(factor, reversed)`` when the frame maps the plane onto
        itself as a rotation/mirror with one scale factor (the arc stays an arc, its radius
        times ``factor``, its direction reversed when ``reversed``); None otherwise."""
        first, second, normal = (_INDEX.get(axis) for axis in plane)
        if None in (first, second, normal) or not self.keeps_axis(plane[2]):
            return None
        a, b = self.linear[first][first], self.linear[first][second]
        c, d = self.linear[second][first], self.linear[second][second]
        if None in (a, b, c, d):
            return None
        column1, column2 = math.hypot(a, c), math.hypot(b, d)
        if column1 == 0.0 or abs(column1 - column2) > 1e-9 * column1 or abs(a * b + c * d) > 1e-9 * column1 * column1:
            return None
        return column1, a * d - b * c < 0

    def map_points(self, axes: tuple[str, ...], points, others: dict):
        """The vectorised :meth:`to_workpiece` for a numeric frame: ``points`` (rows x
        ``axes``, NaN unknown) with the axes not in the run at ``others``; returns the axes
        (X, Y, Z first, then the run's other axes) and the mapped array."""
        columns = [axis for axis in AXES if axis in axes or axis in others or self._moves(_INDEX[axis])]
        out_axes = tuple(columns + [axis for axis in axes if axis not in _INDEX])
        full = numpy.empty((len(points), 3))
        for index, axis in enumerate(AXES):
            if axis in axes:
                full[:, index] = points[:, axes.index(axis)]
            else:
                known = others.get(axis)
                full[:, index] = numpy.nan if known is None else float(known)
        mapped = numpy.empty_like(full)
        for row in range(3):  # term by term in _row_value's order, so each point maps to the very floats it gives
            total = numpy.full(len(points), float(self.offset[row]))
            for column, coefficient in enumerate(self.linear[row]):
                if coefficient != 0.0:  # an axis the row does not use may be unknown (0 x NaN is not 0)
                    total = total + (full[:, column] if coefficient == 1.0 else coefficient * full[:, column])
            mapped[:, row] = total
        result = numpy.empty((len(points), len(out_axes)))
        for index, axis in enumerate(out_axes):
            result[:, index] = mapped[:, _INDEX[axis]] if axis in _INDEX else points[:, axes.index(axis)]
        return out_axes, result


def program_to_workpiece(state) -> "Frame | None":
    """The one map from program to workpiece coordinates that every geometric rule sees:
    the dialect's frame chain (datum shifts, rotations, mirror images, scaling), then the
    ISO-style coordinate shift (G92/G52 and their equivalents) outermost. None is the
    identity. The travel check adds only the work offset and the tool length to this, so
    the stock check and the travel check always see the same point."""
    frame = state.frame
    if not state.coordinate_shift or frame is UNKNOWN:  # most moves: no shift (asked on every move)
        return frame
    shift = {axis: value for axis, value in state.coordinate_shift.items()
             if axis in _INDEX and not (type(value) is float and value == 0.0)}
    if not shift:
        return frame
    return compose(translation(shift), frame or IDENTITY)


def workpiece_level(state, axis: str, value):
    """A level along ``axis`` that a cycle parameter gives in program coordinates (a
    clearance height), on the workpiece; None when the active frame leaves it unknown."""
    frame = program_to_workpiece(state)
    return value if frame is None else frame.level(axis, value, state.position)


def compensation_side(state, plane: tuple[str, str, str]) -> str:
    """The side radius compensation keeps the tool on, seen on the workpiece: a frame that
    mirrors the plane swaps left and right, as it reverses the arcs."""
    side = state.comp_side
    similar = state.frame.plane_similarity(plane) if state.frame is not None else None
    if similar is not None and similar[1]:
        return {"left": "right", "right": "left"}.get(side, side)
    return side


IDENTITY = Frame()
UNKNOWN = Frame(((None,) * 3,) * 3, (None, None, None))  # after a transformation that is not modelled (tilting)


def compose(outer: Frame, inner: Frame) -> Frame:
    """``inner`` applied first, then ``outer``: w = outer(inner(p))."""
    linear = tuple(tuple(_dot([outer.linear[i][k] for k in range(3)], [inner.linear[k][j] for k in range(3)]) for j in range(3)) for i in range(3))
    offset = tuple(_row_value(outer.linear[i], outer.offset[i], dict(zip(AXES, inner.offset))) for i in range(3))
    return Frame(linear, offset)


def translation(shift: dict) -> Frame:
    """Program origin at ``shift`` (axis -> value) in the system it is given in."""
    return Frame(_IDENTITY_ROWS, tuple(shift.get(axis, 0.0) for axis in AXES))


def rotation(plane: tuple[str, str, str], degrees) -> Frame:
    """Rotation in ``plane`` (first axis, second axis, normal) by ``degrees`` from the
    first axis toward the second; a symbolic angle leaves the plane's axes unknown."""
    first, second = _INDEX[plane[0]], _INDEX[plane[1]]
    rows = [list(row) for row in _IDENTITY_ROWS]
    if type(degrees) is float:
        cos, sin = _clean(math.cos(math.radians(degrees))), _clean(math.sin(math.radians(degrees)))
    else:
        cos = sin = None
    rows[first][first], rows[first][second] = cos, None if sin is None else _clean(-sin)
    rows[second][first], rows[second][second] = sin, cos
    return Frame(tuple(tuple(row) for row in rows))


def mirror(axes) -> Frame:
    """Mirror image about the origin on every axis of ``axes``."""
    return scaling({axis: -1.0 for axis in axes if axis in _INDEX})


def scaling(factors: dict, centre: dict | None = None) -> Frame:
    """Scale each axis by its factor about ``centre`` (default the origin); a symbolic
    factor leaves that axis unknown."""
    centre = centre or {}
    rows = [list(row) for row in _IDENTITY_ROWS]
    offset = [0.0, 0.0, 0.0]
    for axis, factor in factors.items():
        index = _INDEX.get(axis)
        if index is None:
            continue
        known = factor if type(factor) is float else None
        rows[index][index] = known
        middle = centre.get(axis, 0.0)
        offset[index] = None if known is None else values.sub(middle, values.mul(known, middle))
    return Frame(tuple(tuple(row) for row in rows), tuple(offset))


def map_segment(frame: Frame, segment: Segment) -> tuple[Segment, str | None]:
    """The segment in workpiece coordinates, and why its arc could not be mapped (None when
    it could, or when it is straight)."""
    start, end = frame.to_workpiece(segment.start), frame.to_workpiece(segment.end)
    arc, problem = segment.arc, None
    if arc is not None:
        arc, problem = _map_arc(frame, arc, segment.start)
    return replace(segment, start=start, end=end, arc=arc), problem


def _map_arc(frame: Frame, arc: Arc, start: dict) -> tuple[Arc, str | None]:
    similar = frame.plane_similarity(arc.plane)
    if similar is None:
        return Arc(arc.direction, arc.plane, None, None, None), "an arc under unequal scaling or a rotation out of its plane (it is not a circle there)"
    factor, reversed_ = similar
    direction = {"cw": "ccw", "ccw": "cw"}[arc.direction] if reversed_ else arc.direction
    first, second, normal = arc.plane
    centre = None
    if arc.centre is not None:
        mapped = frame.to_workpiece({first: arc.centre[0], second: arc.centre[1], normal: start.get(normal)})
        centre = (mapped[first], mapped[second])
    return Arc(direction, arc.plane, centre, _times(arc.start_radius, factor), _times(arc.end_radius, factor),
               _times(arc.radius_word, factor), _times(arc.chord, factor), _times(arc.start_radius_sq, factor * factor),
               _times(arc.end_radius_sq, factor * factor), _times(arc.chord_sq, factor * factor)), None


class WorkpieceObserver:
    """Stands between the interpreter and the checker once a program sets a frame or a
    coordinate shift: while :func:`program_to_workpiece` is not the identity, the geometry
    it reports is mapped to workpiece coordinates; every other event passes through
    unchanged."""

    def __init__(self, observer, interp):
        self.inner = observer
        self.interp = interp

    def __getattr__(self, name):
        return getattr(self.inner, name)

    def segment(self, segment, state):
        frame = program_to_workpiece(state)
        if frame is not None:
            segment, problem = map_segment(frame, segment)
            if problem is not None:
                self.inner.fault(Fault("core.unsupported-code", segment.span, f"{problem}: checks of this arc's geometry answer unknown", "unknown", problem))
        self.inner.segment(segment, state)

    def hole(self, hole, state):
        frame = program_to_workpiece(state)
        if frame is not None:
            at = hole.position
            hole = replace(hole, position=frame.to_workpiece(at), initial=frame.level(hole.drill_axis, hole.initial, at),
                           r_point=frame.level(hole.drill_axis, hole.r_point, at), bottom=frame.level(hole.drill_axis, hole.bottom, at))
        self.inner.hole(hole, state)

    def motion_run(self, run, state):
        frame = program_to_workpiece(state)
        if frame is not None:
            others = {axis: value for axis, value in state.position.items() if axis not in run.axes}
            axes, points = frame.map_points(run.axes, run.points, others)
            per_segment = run.segment
            run = MotionRun(axes, points, run.kinds, run.feeds, _written(frame, run, axes), run.span, lambda index: map_segment(frame, per_segment(index))[0])
        self.inner.motion_run(run, state)


def _written(frame: Frame, run: MotionRun, axes: tuple[str, ...]):
    """Which mapped axes each segment's block wrote: a workpiece axis counts as written
    when a program axis it depends on was (a rotation moves both plane axes)."""
    columns = []
    for axis in axes:
        sources = [program for program in run.axes if program == axis or (axis in _INDEX and program in _INDEX and frame.linear[_INDEX[axis]][_INDEX[program]] != 0.0)]
        column = numpy.zeros(len(run.written), dtype=bool)
        for program in sources:
            column |= run.written[:, run.axes.index(program)]
        columns.append(column)
    return numpy.column_stack(columns)


def _dot(row, column):
    total = 0.0
    for a, b in zip(row, column):
        if a == 0.0 or b == 0.0:
            continue
        if a is None or b is None:
            return None
        total += a * b
    return _clean(total)


def _row_value(row, offset, point: dict):
    """sum(row[j] * point[axis j]) + offset, None when a used entry is unknown."""
    total = offset
    for index, coefficient in enumerate(row):
        if coefficient == 0.0:
            continue
        value = point.get(AXES[index])
        if coefficient is None or value is None or total is None:
            return None
        total = values.add(total, value if coefficient == 1.0 else values.mul(coefficient, value))
    return total


def _negated(value):
    return None if value is None else values.neg(value)


def _times(value, factor: float):
    return None if value is None else value if factor == 1.0 else values.mul(value, factor)


def _clean(number: float) -> float:
    """Round-off of cos/sin and products to exact 0, 1 and -1, so that 90 degrees and a
    rotation undone stay exact."""
    for exact in (0.0, 1.0, -1.0):
        if abs(number - exact) < 1e-15:
            return exact
    return number


# --------------------------------------------------------------------------- programmable frame statements

UNMODELLED = {  # why a frame statement is not modelled, by its component
    "rotation": " (a rotation about an axis of the working plane tilts it out of the plane)",
    "translation": " (a shift of a rotary or auxiliary axis, or G58/G59 under a rotated or scaled frame)",
    "scale": " (scaling a rotary or auxiliary axis)", "mirror": " (mirroring a rotary or auxiliary axis)",
}


def after_statement(op: ir.SetFrame, given: dict, current: Frame, layers: dict | None, plane: tuple[str, str, str]):
    """The programmable frame after a statement (None when it is not modelled), and the
    split of a pure translation into its absolute (TRANS, G58) and additive (ATRANS, G59)
    parts per axis (None once the frame is more than a translation).

    SINUMERIK programmable frames (840D programming knowledge; the references only name
    them): TRANS/ROT/SCALE/MIRROR replace the whole programmable frame (without arguments
    they reset it), ATRANS/AROT/ASCALE/AMIRROR append to it in the current, already
    transformed system. ROT RPL= (or ROT with only the plane's normal axis) rotates in the
    active plane from its first axis toward its second; a rotation about another axis is
    spatial and not modelled. G58 replaces the absolute (TRANS) translation of an axis, G59
    its additive (ATRANS) part: modelled while the frame is a pure translation."""
    if op.layer is not None:
        if layers is None:
            return None, None
        index = 0 if op.layer == "coarse" else 1
        layers = dict(layers)
        for axis, value in given.items():
            pair = list(layers.get(axis, (0.0, 0.0)))
            pair[index] = value
            layers[axis] = tuple(pair)
        return translation({axis: values.add(*pair) for axis, pair in layers.items()}), layers
    part = _statement_part(op, given, plane)
    if part is None:
        return None, None
    if not op.additive:
        return part, ({axis: (value, 0.0) for axis, value in given.items()} if op.component in ("translation", "reset") else None)
    if op.component == "translation" and layers is not None:
        layers = dict(layers)
        for axis, value in given.items():
            coarse, fine = layers.get(axis, (0.0, 0.0))
            layers[axis] = (coarse, values.add(fine, value))
    else:
        layers = None
    return compose(current, part), layers


def _statement_part(op: ir.SetFrame, given: dict, plane: tuple[str, str, str]):
    """The transformation one statement makes; None when it is not modelled."""
    component = op.component
    if component == "reset":
        return IDENTITY
    if any(axis not in AXES and axis != "RPL" for axis in given):
        return None  # rotary and auxiliary axes are not transformed here
    if component == "translation":
        return translation(given)
    if component == "rotation":
        normal = plane[2]
        if any(axis != normal and axis != "RPL" and not (type(value) is float and value == 0.0) for axis, value in given.items()):
            return None  # about an axis in the plane: a spatial rotation
        return rotation(plane, given.get("RPL", given.get(normal, 0.0)))
    if component == "scale":
        return scaling(given)
    if component == "mirror":
        return mirror(given)
    return None
