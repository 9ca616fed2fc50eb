"""Rules on motion: feed, spindle, radius compensation, arcs, units, reference returns."""
from __future__ import annotations

import math

import numpy

from ..solver import z3
from .. import ir, values
from ..values import Condition
from ..diagnostics import Status
from ..check import ARCS, CUTTING, Rule, hazard, rule, show
from .. import modelled
from ..trace import ARC_CW, any_in_row


_FEED = 1  # MotionRun kind code of a feed segment; arcs' are above it


def _same_feed(a, b) -> bool:
    return a is b or (type(a) is float and type(b) is float and a == b)


@rule("core.feed-missing")
class FeedMissing(Rule):
    """Reported at the first cutting move of each feed value that is missing or not
    positive (one finding per mistake, not one per block)."""
    reads = modelled.AS_WRITTEN
    segment_kinds = CUTTING
    handles_arcs = True
    judges_cycle_runs = True

    def segment(self, segment, state):
        if segment.kind not in CUTTING or segment.kind == "thread" and not segment.cycle:
            return  # a thread (G33) follows the spindle: its lead is the feed, no F is read
        self._check(state.feed, segment.span, "cycle infeed" if segment.cycle else "cutting move", state)

    def motion_run(self, run, state):
        cutting = numpy.flatnonzero(run.kinds >= _FEED)  # straight feed moves and arcs
        if not len(cutting):
            return
        feeds = run.feeds[cutting]
        previous = numpy.concatenate(([numpy.inf], feeds[:-1]))
        changed = ~((feeds == previous) | (numpy.isnan(feeds) & numpy.isnan(previous)))
        invalid = numpy.isnan(feeds) | (feeds <= 0)
        memory = state.rule_state
        first_feed = None if math.isnan(feeds[0]) else float(feeds[0])
        if "feed-missing" in memory and _same_feed(memory["feed-missing"], first_feed):
            changed[0] = False
        for index in numpy.flatnonzero(changed & invalid):
            feed = None if math.isnan(feeds[index]) else float(feeds[index])
            memory["feed-missing"] = feed
            self._check(feed, run.span(int(cutting[index])), "cycle infeed" if run.cycle_moves else "cutting move", state, remember=False)
        last = feeds[-1]
        memory["feed-missing"] = None if math.isnan(last) else float(last)

    def _check(self, feed, span, what, state, remember=True):
        memory = state.rule_state
        if remember:
            if "feed-missing" in memory and _same_feed(memory["feed-missing"], feed):
                return
            memory["feed-missing"] = feed
        if feed is None:
            if not state.feed_inherited:
                self.report("core.feed-missing", span, f"{what} with no feed rate: no F word since the program started{self.word('feed_missing_alarm', ' ({})')}")
            return
        verdict = self.checker.judge(hazard("<=", feed, 0.0), state)
        self.checker.report_verdict("core.feed-missing", span, f"{what} at feed F{show(feed)}: the axes would not move (feed zero or negative)", verdict, state)


_AIR = "air"  # the move stays above the stock's top: it cuts nothing
_MATERIAL = "material"  # the move can touch material
_UNPLACED = "unplaced"  # a mill's tool height is unknown at both ends (Z not yet set): it may run in the air


class _SpindleOffStretch:
    """The feed moves of one stretch with the spindle stopped that may touch material: the
    first that surely can (``touching``), and before it the moves above Z0 with no stock to
    place them, each lower than the one before (``above_zero``: span and lowest Z), and the
    first at a height the program has not set (``unplaced``)."""

    __slots__ = ("touching", "above_zero", "unplaced")

    def __init__(self):
        self.touching = None
        self.above_zero: list = []
        self.unplaced = None


@rule("core.spindle-off-cutting")
class SpindleOffCutting(Rule):
    """Feed moves with the spindle stopped. A program that never starts the spindle and
    runs no machining cycle on any path is not a cutting program (a measuring macro, a
    probing routine, a pen plotter, a subprogram whose caller starts the spindle): its
    findings are held back and the file gets one ``unknown`` instead.

    Only a move that can touch material is a fault. Above the stock's top it is not
    reported. With no stock, Z0 is the part's top on many set-ups and the table's on others:
    a move that reaches Z0 touches one or the other and is reported; one that stays above
    Z0 is reported where the program itself feeds across the plane with the spindle running
    at that height or higher (it cuts there), and is ``unknown`` otherwise."""
    segment_kinds = CUTTING

    handles_arcs = True
    judges_cycle_runs = True  # a hole's moves are never a lathe cycle's contour
    judges_holes_before_moves = True

    def __init__(self, checker):
        super().__init__(checker)
        self.machining = False  # the spindle was started, or a cycle drilled or cut, somewhere
        self.stretches: list[_SpindleOffStretch] = []
        self.highest_cut: float | None = None  # highest Z of a spindle-on feed move across the plane

    def hole(self, hole, state):
        self.machining = True

    def cycle_run(self, run, state):
        self.machining = True

    def segment(self, segment, state):
        if segment.kind not in CUTTING or segment.role == "contour":
            return
        start_z, end_z = segment.start.get("Z"), segment.end.get("Z")
        if state.spindle in ("cw", "ccw"):
            start, end = segment.start, segment.end
            if type(end_z) is float and (_changed(start.get("X"), end.get("X")) or _changed(start.get("Y"), end.get("Y"))):
                self._cut_at(end_z)
            return
        if state.spindle == "off" and state.plane_axes[2] not in state.parked:  # parked: the tool axis still at its reference height
            self._hold(segment.span, start_z, end_z, state)

    def motion_run(self, run, state):
        """Arcs count as the straight moves do: by their end points, as block by block."""
        column = run.axes.index("Z") if "Z" in run.axes else None
        feeds = numpy.flatnonzero(run.kinds >= _FEED)
        if state.spindle in ("cw", "ccw"):
            self._cuts_of_run(run, feeds, column)
            return
        if state.spindle != "off":
            return
        for index in feeds:
            if self._stretch(state).touching is not None:
                return
            start = end = None
            if column is not None:
                start, end = (None if numpy.isnan(z) else float(z) for z in (run.points[index, column], run.points[index + 1, column]))
            self._hold(run.span(int(index)), start, end, state)

    def _cuts_of_run(self, run, feeds, column) -> None:
        plane = [run.axes.index(axis) for axis in ("X", "Y") if axis in run.axes]
        if column is None or not plane or not len(feeds):
            return
        in_plane = run.points[:, plane]
        moved = any_in_row(in_plane[1:] != in_plane[:-1])[feeds]  # every move's, then the feed moves': no gathers of whole rows
        heights = run.points[1:, column][feeds][moved]
        heights = heights[~numpy.isnan(heights)]
        if len(heights):
            self._cut_at(float(heights.max()))

    def _cut_at(self, z: float) -> None:
        self.highest_cut = z if self.highest_cut is None else max(self.highest_cut, z)

    def _where(self, start_z, end_z) -> str | float:
        """Where a feed move runs: in the air above the stock, into material, (no stock, on a
        mill) the lowest Z of a move that stays above Z0, decided at the end, or (on a mill)
        unplaced where the program has not yet set the tool's height. A mill's first Z move
        is taken to come down from above: its lowest point is where it ends."""
        if start_z is None and not self.checker.context.lathe:
            if end_z is None:
                return _UNPLACED
            start_z = end_z  # the first Z move: from where the operator left the tool down to its end
        if type(start_z) is not float or type(end_z) is not float:
            return _MATERIAL
        lowest = min(start_z, end_z)
        stock = self.checker.context.stock
        if stock is None:
            return lowest if lowest > 0.0 and not self.checker.context.lathe else _MATERIAL
        if stock.kind == "cylinder":
            return _MATERIAL
        return _AIR if lowest > stock.top else _MATERIAL

    def _stretch(self, state) -> _SpindleOffStretch:
        stretch = state.rule_state.get("spindle-off-stretch")
        if stretch is None:
            stretch = state.rule_state["spindle-off-stretch"] = _SpindleOffStretch()
            self.stretches.append(stretch)
        return stretch

    def _hold(self, span, start_z, end_z, state) -> None:
        stretch = self._stretch(state)
        where = self._where(start_z, end_z)
        if where == _AIR or stretch.touching is not None:
            return
        if where == _MATERIAL:
            stretch.touching = span
        elif where == _UNPLACED:
            stretch.unplaced = stretch.unplaced or span
        elif not stretch.above_zero or where < stretch.above_zero[-1][1]:
            stretch.above_zero.append((span, where))

    def change(self, change, state):
        if change.what == "spindle":
            state.rule_state.pop("spindle-off-stretch", None)
            self.machining |= change.new in ("cw", "ccw")

    def finish(self):
        stretches = [stretch for stretch in self.stretches if stretch.touching is not None or stretch.above_zero or stretch.unplaced]
        if stretches and not self.machining:
            first = stretches[0].above_zero[0][0] if stretches[0].above_zero else stretches[0].touching or stretches[0].unplaced
            self.report("core.spindle-off-cutting", first, "feed moves with the spindle stopped in a program that never starts it: "
                        "taken as measuring or positioning moves", Status.UNKNOWN,
                        "the program never starts the spindle (a measuring or probing routine, or its caller starts it)")
            return
        for stretch in stretches:
            cutting = next((span for span, lowest in stretch.above_zero if self.highest_cut is not None and lowest <= self.highest_cut), stretch.touching)
            if cutting is not None:
                self.report("core.spindle-off-cutting", cutting, "cutting move while the spindle is stopped (no M03/M04 since the start or since the last M05): the tool rubs or breaks")
            elif not stretch.above_zero:
                self.report("core.spindle-off-cutting", stretch.unplaced, "feed move with the spindle stopped at a height the program has not set", Status.UNKNOWN,
                            "no Z has been programmed since the start: the tool runs where the operator left it, in the air above the part "
                            "or in it")
            else:
                self.report("core.spindle-off-cutting", stretch.above_zero[0][0], "feed move with the spindle stopped above Z0", Status.UNKNOWN,
                            "no stock is defined and the program cuts no higher with the spindle running: above Z0 the tool is clear of "
                            "the part when Z0 is its top, not when Z0 is the table's; give the stock ([stock] in ncverify.toml or a "
                            "'ncverify: stock' annotation)")


@rule("core.comp-on-arc")
class CompensationOnArc(Rule):
    """The first in-plane move after G41/G42/G40 must be a straight line."""
    handles_arcs = True
    judges_cycle_runs = True

    def change(self, change, state):
        if change.what == "cutter_comp" and change.old != change.new:
            state.rule_state["comp-transition"] = (change.new, change.span)

    def motion_run(self, run, state):
        """The first move in the plane or arc settles the transition: an arc is judged as a segment.
        A cycle's moves settle nothing (:meth:`segment`)."""
        if "comp-transition" not in state.rule_state or run.cycle_moves:
            return
        plane = [run.axes.index(axis) for axis in state.plane_axes[:2] if axis in run.axes]
        settling = run.kinds >= ARC_CW
        if plane:
            settling = settling | run.written[:, plane].any(axis=1)
        first = numpy.flatnonzero(settling)[:1].tolist()
        if not first:
            return
        if run.kinds[first[0]] >= ARC_CW:
            self.segment(run.segment(first[0]), state)
        else:
            del state.rule_state["comp-transition"]

    def segment(self, segment, state):
        pending = state.rule_state.get("comp-transition")
        if pending is None or segment.role != "programmed":
            return
        if not _moves_in_plane(segment, state.plane_axes[:2]) and segment.kind != "arc":
            return
        del state.rule_state["comp-transition"]
        if segment.kind == "arc":
            side, span = pending
            what = "cancelled (G40)" if side == "off" else f"switched on ({'G41' if side == 'left' else 'G42' if side == 'right' else 'G46'})"
            self.report("core.comp-on-arc", segment.span, f"radius compensation is {what} at line {span.line} and the first move after it is an arc: "
                        "the control needs a straight G00/G01 move to build up or remove the offset (alarm)")


def _moves_in_plane(segment, axes) -> bool:
    """Whether a straight move goes somewhere in the plane. Where a position is not known (in
    a tilted working plane, after a reference return) the block's own words decide: one that
    writes a plane axis is the straight move that builds up or removes the offset."""
    for axis in axes:
        start, end = segment.start.get(axis), segment.end.get(axis)
        if start is None and end is None:
            if any(isinstance(op, ir.Move) and axis in op.targets for op in segment.block.ops):
                return True
        elif start is not end:
            return True
    return False


@rule("core.comp-active-at-end")
class CompensationAtEnd(Rule):
    def change(self, change, state):
        if change.what == "end" and change.new == "end" and state.comp_side not in ("off", None):
            self.report("core.comp-active-at-end", change.span, f"radius compensation ({'G41' if state.comp_side == 'left' else 'G42' if state.comp_side == 'right' else 'G46'}) is still on at the program end: the next program starts with an offset it did not ask for")


def _radii(points, centres):
    """The distance of each point from its centre (NaN where the centre is)."""
    return numpy.hypot(points[:, 0] - centres[:, 0], points[:, 1] - centres[:, 1])


@rule("core.arc-geometry")
class ArcGeometry(Rule):
    judges_cycle_runs = True  # a hole's moves are straight: no arc to judge
    reads = modelled.AS_WRITTEN
    segment_kinds = ARCS
    handles_arcs = True
    tolerance = 0.01  # in program units, unless the dialect states its control's own (RuleContext.arc_tolerance)

    def _tolerance(self, state) -> float:
        own = self.checker.context.arc_tolerance
        if own is None:
            return self.tolerance
        return own.inch if state.modal.get("units") == "inch" else own.metric

    def motion_run(self, run, state):
        """Only the arcs that may be off by the tolerance are judged one by one: the others'
        radii (computed here with numpy, within a few units in the last place of the block
        path's) are within half of it."""
        arcs = run.arcs
        if arcs is None:
            return
        starts, ends = run.points[:-1][:, arcs.columns], run.points[1:][:, arcs.columns]
        with numpy.errstate(invalid="ignore"):
            by_centre = numpy.abs(_radii(starts, arcs.centres) - _radii(ends, arcs.centres)) <= 0.5 * self._tolerance(state)
            by_radius = numpy.abs(arcs.radii) >= 0.5 * _radii(starts, ends) - 0.5e-6
        for index in numpy.flatnonzero((run.kinds >= ARC_CW) & ~by_centre & ~by_radius).tolist():
            self.segment(run.segment(index), state)

    def _symbolic(self, segment, arc, state):
        """Parametric end points: the same tests on squared distances, as polynomials."""
        if arc.radius_word is not None:
            radius = values.term_of(arc.radius_word)
            hazard_term = radius * radius < values.term_of(arc.chord_sq) / 4 - 1e-6
            message = f"arc radius R{show(arc.radius_word)} can be smaller than half the distance to the end point: no such arc exists (alarm)"
        else:
            start, end = values.helper("r").term, values.helper("r").term  # named per check, not per process
            hazard_term = z3.And(start >= 0, end >= 0, start * start == values.term_of(arc.start_radius_sq), end * end == values.term_of(arc.end_radius_sq),
                                 z3.Or(start - end > self._tolerance(state), end - start > self._tolerance(state)))
            message = "the end point can lie off the arc: its distance to the centre differs from the start point's"
        self.checker.report_verdict("core.arc-geometry", segment.span, message, self.checker.judge(Condition(hazard_term), state), state)

    def segment(self, segment, state):
        arc = segment.arc
        if arc is None:
            return
        if arc.start_radius_sq is not None and arc.start_radius is None or arc.radius_word is not None and arc.chord is None and arc.chord_sq is not None:
            self._symbolic(segment, arc, state)
            return
        if arc.radius_word is not None:
            if arc.chord is None:
                return
            verdict = self.checker.judge(hazard("<", values.absolute(arc.radius_word), values.sub(values.mul(arc.chord, 0.5), 1e-6)), state)
            self.checker.report_verdict("core.arc-geometry", segment.span, f"arc radius R{show(arc.radius_word)} is smaller than half the distance to the end point ({show(values.mul(arc.chord, 0.5))}): no such arc exists (alarm)", verdict, state)
            return
        if arc.start_radius is None or arc.end_radius is None:
            return
        difference = values.absolute(values.sub(arc.start_radius, arc.end_radius))
        tolerance = self._tolerance(state)
        own = self.checker.context.arc_tolerance
        if own is not None and type(arc.start_radius) is float:  # LinuxCNC: refused only when off by both measures
            tolerance = max(tolerance, own.relative * arc.start_radius)
        verdict = self.checker.judge(hazard(">", difference, tolerance), state)
        if verdict is None:
            return  # the usual arc: its message is not worth writing
        if arc.start_radius == 0.0:
            message = "arc with no centre: I/J/K are all zero or missing and no R is given, so the centre is the start point (is G02/G03 still modal where a G01 was meant?)"
        else:
            message = f"the end point is not on the arc: radius {show(arc.start_radius)} at the start, {show(arc.end_radius)} at the end (I/J/K are measured from the start point to the centre)"
        self.checker.report_verdict("core.arc-geometry", segment.span, message, verdict, state)


@rule("core.inch-metric-switch")
class InchMetricSwitch(Rule):
    def change(self, change, state):
        if change.what == "units" and state.motion_seen:
            self.report("core.inch-metric-switch", change.span, f"units change from {change.old} to {change.new} after motion was programmed: every later coordinate, feed and offset is read in {change.new}")


@rule("core.g28-absolute")
class ReferenceReturnThroughWork(Rule):
    reads = modelled.AS_WRITTEN
    def change(self, change, state):
        if change.what != "reference_return" or state.modal.get("distance") != "absolute":
            return
        via = change.old or {}
        level = via.get("Z")
        if level is None:
            return
        verdict = self.checker.judge(hazard("<=", level, 0.0), state)
        self.checker.report_verdict("core.g28-absolute", change.span, f"{'G28' if change.new == 'home' else 'G30'} in G90 goes first to work Z{show(level)} at rapid: the tool passes through the work surface level (write G91 G28 Z0.)", verdict, state)


def _changed(before, after) -> bool:
    """A coordinate differs: numbers by value (a block may write the same X again), other
    values (symbolic, unknown) unless they are the very same value."""
    if type(before) is float and type(after) is float:
        return before != after
    return before is not after
