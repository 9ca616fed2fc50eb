"""Rules against the machine and the tool table: travel limits, spindle and feed limits,
tools the table does not hold. Each answers ``unknown`` once per file when the context it
needs (``[machine]``, ``[tools]`` in ncverify.toml, or annotations) is missing."""
from __future__ import annotations

import math

import numpy

from ..solver import z3
from .. import values
from ..check import CUTTING, hazard, rule, show
from ..context import NO_TOOL_TABLE, active_edge
from ..diagnostics import Status
from ..values import Condition, Sym
from ..workpiece import turn_unsettled
from .common import UNKNOWN_DIAMETER_MODE, ReportsMissingContext, lathe_x_is_diameter
from .. import modelled

_AXIS_INDEX = {"X": 0, "Y": 1, "Z": 2, "A": 3, "B": 4, "C": 5}


@rule("core.travel-limit")
class TravelLimit(ReportsMissingContext):
    """Machine position = workpiece position (the program position through
    :func:`frames.program_to_workpiece`, G92/G52 shifts included) + work offset (+ tool length on
    Z while length compensation is on); every segment end and every arc's extent must stay
    inside the travel. On a lathe the program's X is a diameter: ``[machine] lathe_x`` says
    whether travel and offsets are diameters too or radii (then X is halved first), and arcs
    are judged at their end points."""
    judges_cycle_runs = True
    reads = modelled.GEOMETRY_AND_DIAMETER
    handles_arcs = True  # end points in the run's arrays, each arc's extent as block by block

    def segment(self, segment, state):
        frame = self._frame(segment.span, state)
        if frame is None:
            return
        points = [segment.end]
        for axis, limits in frame.items():
            for point in points:
                self._check_axis(axis, point.get(axis), limits, segment.span, state)
        if segment.arc is not None:
            self._arc_extent(segment, frame, state)

    def _arc_extent(self, segment, frame, state):
        if self.checker.context.lathe:
            self.missing("core.travel-limit", segment.span, "on a lathe, arcs are checked at their end points only, not at their extent")
        else:
            self._check_arc(segment, frame, state)

    def motion_run(self, run, state):
        """Every end point outside the travel, and every arc's extent, reported in the order
        the block path reports them (move by move, its axes in turn, then its arc): the
        report keeps a rule's first findings and counts the others."""
        frame = self._frame(run.span(0), state)
        if frame is None:
            return
        found = []  # (move, place among its checks, axis or None for the arc's extent, machine position)
        for place, (axis, (offset, low, high, scale)) in enumerate(frame.items()):
            if axis not in run.axes or offset is None or isinstance(offset, Sym):
                continue
            column = run.points[1:, run.axes.index(axis)] * scale + offset
            outside = numpy.flatnonzero(~numpy.isnan(column) & ((column < low) | (column > high)))
            found += [(index, place, axis, position) for index, position in zip(outside.tolist(), column[outside].tolist())]
        found += [(index, len(frame), None, None) for index in run.arc_indices()]
        for index, _place, axis, position in sorted(found, key=lambda entry: entry[:2]):
            if axis is None:
                self._arc_extent(run.segment(index), frame, state)
            else:
                _offset, low, high, _scale = frame[axis]
                self._report(axis, position, low, high, run.span(index), None)

    def _frame(self, span, state):
        """axis -> (offset from program to machine coordinates, low, high); None when the
        check cannot run (and says why once)."""
        context = self.checker.context
        travel = context.machine.travel
        if not travel:
            self.missing("core.travel-limit", span, "no machine travel limits ([machine] travel in ncverify.toml)")
            return None
        written = state.unfollowed or state.set_up_written
        if written is not None:  # the offsets (or the units) are no longer the project file's
            if self.first_time(state, ("core.travel-limit", "unfollowed")):
                self.report("core.travel-limit", span, f"travel not compared: {written}", Status.UNKNOWN, "data changed by the program")
            return None
        lathe_x_scale = self._lathe_x_scale(span, state)
        name = state.modal.get("work_offset", "G54")
        offsets = context.machine.work_offsets.get(name.split()[0] if name.startswith("G54.1") else name)
        if offsets is None:
            self.missing("core.travel-limit", span, f"no values for work offset {name} ([machine] work_offsets in ncverify.toml)")
            return None
        frame = {}
        for axis, (low, high) in travel.items():
            index = _AXIS_INDEX.get(axis)
            if index is None or index >= len(offsets) or (axis == "X" and lathe_x_scale is None):
                continue
            offset = offsets[index]
            if axis == "Z" and offset is not None and state.length_mode in ("plus", "minus", "with_tool"):
                offset = self._with_tool_length(offset, state, span)
            frame[axis] = (offset, low, high, lathe_x_scale if axis == "X" else 1.0)
        return frame

    def _lathe_x_scale(self, span, state) -> float | None:
        """How program X becomes machine X: 1 on a mill; on a lathe from the program's
        diameter or radius mode to ``[machine] lathe_x``; None (X not checked, said once)
        when either is not known."""
        context = self.checker.context
        if not context.lathe:
            return 1.0
        lathe_x = context.machine.lathe_x
        if lathe_x is None:
            self.missing("core.travel-limit", span, "X of a lathe: say whether travel and work offsets are diameters or radii ([machine] lathe_x)")
            return None
        diameter = lathe_x_is_diameter(state)
        if diameter is None:
            self.missing("core.travel-limit", span, UNKNOWN_DIAMETER_MODE)
            return None
        return {(True, "diameter"): 1.0, (True, "radius"): 0.5, (False, "diameter"): 2.0, (False, "radius"): 1.0}[(diameter, lathe_x)]

    def _with_tool_length(self, offset, state, span):
        if state.length_mode == "with_tool":  # Fagor, SINUMERIK: the offset comes with the tool (and its edge D), not from an H register
            tool = self.checker.context.tools.numbered(state.tool_in_spindle)
            edge = active_edge(state)
            tool = tool.edge_data(edge) if tool is not None and type(edge) is float else None
            which = f"tool T{show(state.tool_in_spindle)}" + (f" (edge D{show(edge)})" if edge != 1.0 else "")
        else:
            tool = self.checker.context.tools.numbered(state.length_register)
            which = f"the tool on H{show(state.length_register)}"
        if tool is None or tool.length is None:
            self.missing("core.travel-limit", span, f"the length of {which} is not known (length in [tools.N]), so Z was not checked")
            return None
        return values.add(offset, -tool.length if state.length_mode == "minus" else tool.length)

    def _check_axis(self, axis, value, limits, span, state):
        offset, low, high, scale = limits
        if value is None or offset is None:
            return
        machine = values.add(values.mul(value, scale) if scale != 1.0 else value, offset)
        if type(machine) is float:
            if not low <= machine <= high:
                self._report(axis, machine, low, high, span, None)
            return
        outside = values.logical("OR", values.compare("LT", machine, low), values.compare("GT", machine, high))
        outside = outside if isinstance(outside, Condition) else Condition(z3.BoolVal(bool(outside)))
        verdict = self.checker.judge(outside, state)
        self.checker.report_verdict("core.travel-limit", span, f"{axis} reaches machine position {show(machine)}, outside the travel {low:g}..{high:g}", verdict, state)

    def _check_arc(self, segment, frame, state):
        """The quadrant points the arc sweeps are part of the obligation: exactly when the
        arc is concrete, else through the whole circle (which holds them) when the solver
        shows it inside the travel; anything less is ``unknown``, never the end points alone.
        A concrete arc that may turn once or not at all (its end on its start's ray, off the
        circle: :func:`workpiece.turn_unsettled`) is judged by its whole circle too."""
        arc = segment.arc
        first, second, _normal = arc.plane
        axes = [axis for axis in (first, second) if axis in frame]
        if not axes:
            return
        centre = arc.centre
        start = (segment.start.get(first), segment.start.get(second))
        end = (segment.end.get(first), segment.end.get(second))
        concrete = all(type(v) is float for v in (*(centre or (None, None)), arc.start_radius, *start, *end))
        if concrete and not turn_unsettled(start, centre, end):
            for axis, value in _arc_extremes(arc.direction, centre, arc.start_radius, start, end, (first, second)):
                if axis in frame:
                    self._check_axis(axis, value, frame[axis], segment.span, state)
            return
        if centre is None or arc.start_radius_sq is None or None in centre:
            self.report("core.travel-limit", segment.span, "the arc's centre or radius is not known, so the extremes it sweeps were not checked against the travel",
                        Status.UNKNOWN, "arc extremes not known")
            return
        why = ("the arc's circle may leave the travel; its end lies on its start's ray, off the circle, so whether it turns once or not at all "
               "depends on the control's rounding" if concrete else
               "the arc's circle may leave the travel; whether the arc sweeps that side depends on free parameters")
        for axis in axes:
            self._check_circle(axis, centre[(first, second).index(axis)], arc.start_radius_sq, frame[axis], segment.span, state, why)

    def _check_circle(self, axis, centre, radius_sq, limits, span, state, why: str):
        """An arc judged by its whole circle (a symbolic one, or one that may not turn): the
        circle inside the travel proves its swept extremes are; a circle that may leave it
        is ``unknown``, for ``why`` (the arc may not sweep that side)."""
        offset, low, high, _scale = limits
        if offset is None:
            return
        machine = values.term_of(values.add(centre, offset))
        radius_sq = values.term_of(radius_sq)
        beyond = z3.Or(machine + 0 > high, radius_sq > (high - machine) * (high - machine))
        below = z3.Or(machine + 0 < low, radius_sq > (machine - low) * (machine - low))
        verdict = self.checker.judge(Condition(z3.Or(beyond, below)), state)
        if verdict is None:
            return
        if verdict.status is not Status.PROVED:
            verdict = type(verdict)(Status.UNKNOWN, reason=verdict.reason or why)
        self.checker.report_verdict("core.travel-limit", span, f"the arc about {axis}{show(centre)} sweeps past the travel {low:g}..{high:g} on {axis}", verdict, state)

    def _report(self, axis, machine, low, high, span, verdict):
        side = "below" if machine < low else "beyond"
        limit = low if machine < low else high
        self.report("core.travel-limit", span, f"{axis} would reach machine position {machine:g}, {side} the travel limit {limit:g}: the control stops with an overtravel alarm")


def _arc_extremes(direction, centre, radius, start, end, axes):
    """The extreme coordinates an arc reaches on its plane's axes (quadrant points it passes)."""
    def angle(point):
        return math.atan2(point[1] - centre[1], point[0] - centre[0]) % (2 * math.pi)

    begin, finish = angle(start), angle(end)
    sweep = (finish - begin) % (2 * math.pi) if direction == "ccw" else (begin - finish) % (2 * math.pi)
    if sweep == 0:
        sweep = 2 * math.pi
    for quadrant in range(4):
        theta = quadrant * math.pi / 2
        along = (theta - begin) % (2 * math.pi) if direction == "ccw" else (begin - theta) % (2 * math.pi)
        if along <= sweep:
            yield axes[quadrant % 2], centre[quadrant % 2] + radius * (1 if quadrant < 2 else -1)


@rule("core.tool-not-in-table", "core.spindle-over-limit", "core.feed-over-limit")
class MachineLimits(ReportsMissingContext):
    judges_cycle_runs = True
    reads = modelled.AS_WRITTEN
    segment_kinds = CUTTING  # a rapid runs at neither the programmed feed nor a cutting speed
    handles_arcs = True  # an arc cuts at the feed in force, as a straight feed move

    def change(self, change, state):
        if change.what == "tool_change" and type(change.new) is float:
            tools = self.checker.context.tools
            if not tools:
                self.missing("core.tool-not-in-table", change.span, NO_TOOL_TABLE)
            elif int(change.new) not in tools:
                self.report("core.tool-not-in-table", change.span, f"tool T{int(change.new)} is not in the tool table ({', '.join(f'T{n}' if isinstance(n, int) else repr(n) for n in sorted(tools, key=str))}): its size and length are unknown, and the magazine may not hold it")

    def segment(self, segment, state):
        if segment.kind != "rapid":
            self._limits(segment.span, state, state.feed)

    def motion_run(self, run, state):
        """As block by block: at the first cutting move of each feed value (straight feed
        moves and arcs), each judged once per value."""
        cutting = numpy.flatnonzero(run.kinds >= 1)
        if not len(cutting):
            return
        feeds = run.feeds[cutting]
        if (feeds == feeds[0]).all() or numpy.isnan(feeds).all():
            firsts = [0]  # one feed, as a run mostly has: what numpy.unique tells, at a tenth of its cost
        else:
            firsts = numpy.sort(numpy.unique(feeds, return_index=True)[1])
        for index in cutting[firsts].tolist():
            feed = float(run.feeds[index])
            self._limits(run.span(index), state, None if math.isnan(feed) else feed)

    def _limits(self, span, state, feed):
        context = self.checker.context
        speed = state.spindle_speed
        if speed is not None and state.spindle in ("cw", "ccw") and state.modal.get("spindle_mode") != "surface_speed":
            self._over("core.spindle-over-limit", speed, context.machine.max_spindle, span, state,
                       "spindle speed S{value} is above the machine's maximum {limit:g} rpm", "no maximum spindle speed ([machine] max_spindle)")
        if feed is not None and state.modal.get("feed_mode", "per_minute") == "per_minute":
            if state.modal.get("units") == "inch" and context.machine.max_feed is not None:
                self.missing("core.feed-over-limit", span, "a feed in inches per minute, where [machine] max_feed is in mm per minute")
                return
            self._over("core.feed-over-limit", feed, context.machine.max_feed, span, state,
                       "feed F{value} is above the machine's maximum {limit:g} per minute", "no maximum feed ([machine] max_feed)")

    def _over(self, rule_id, value, limit, span, state, message, missing):
        if limit is None:
            self.missing(rule_id, span, missing)
            return
        key = (rule_id, value if type(value) is float else id(value))
        if key in state.rule_state:
            return
        state.rule_state[key] = True
        verdict = self.checker.judge(hazard(">", value, limit), state)
        self.checker.report_verdict(rule_id, span, message.format(value=show(value), limit=limit), verdict, state)
