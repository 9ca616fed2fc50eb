"""Rules on the tool's size against the feature it cuts: a G12/G13 circle smaller than the
tool, a concave arc under radius compensation tighter than the tool. The tool's radius
comes from the tool table (``[tools.N]`` or ``ncverify: tool``) for the tool in the
spindle; without it each rule answers ``unknown`` once per file."""
from __future__ import annotations

import numpy

from ..ir import cycle_code
from .. import frames, values
from ..check import ARCS, hazard, rule, show
from ..material import register_problem
from .common import ReportsMissingContext
from .. import modelled
from ..trace import ARC_CCW, ARC_CW

# Which arc direction puts the tool inside the arc, per compensation side.
_CONCAVE = {("left", "ccw"), ("right", "cw")}


@rule("core.tool-too-large")
class CircleSmallerThanTool(ReportsMissingContext):
    """G12/G13: the tool centre runs on a circle of radius |I| minus the tool radius."""
    reads = modelled.SCALED_SIZES

    def cycle_run(self, run, state):
        if run.model.shape != "circle" or run.params.get("I") is None:
            return
        other = register_problem("D", run.params.get("D"), state.tool_in_spindle, f"the radius {cycle_code(run.cycle)} offsets by is not known")
        if other is not None:  # the control offsets by D's value, the table gives T's radius
            self.missing("core.tool-too-large", run.param_spans.get("D", run.span), other)
            return
        radius = self.spindle_tool_radius(state, run.span, "core.tool-too-large")
        sizes = None if radius is None else self.workpiece_sizes(run.params, ("I",), state, run.span, "core.tool-too-large")
        if sizes is None:
            return
        circle = values.absolute(sizes["I"])
        verdict = self.checker.judge(hazard("<=", values.sub(circle, radius), 0.0), state)
        self.checker.report_verdict("core.tool-too-large", run.param_spans.get("I", run.span),
                                    f"{cycle_code(run.cycle)}: the circle of radius {show(circle)} is not larger than the tool radius {radius:g}: "
                                    f"the largest tool that fits has a radius below {show(circle)} (the control alarms: circle radius error)", verdict, state)


@rule("core.comp-gouge")
class ConcaveArcTighterThanTool(ReportsMissingContext):
    """With G41/G42 on, an arc whose centre lies on the tool's side must have a radius of
    at least the tool radius, or the offset path cannot follow it."""
    judges_cycle_runs = True  # a hole's moves are straight: no arc to judge
    reads = modelled.AS_WRITTEN
    segment_kinds = ARCS
    handles_arcs = True

    def segment(self, segment, state):
        arc = segment.arc
        if arc is None or state.comp_side not in ("left", "right") or (frames.compensation_side(state, arc.plane), arc.direction) not in _CONCAVE:
            return  # the arc is on the workpiece, so the side is too
        arc_radius = arc.start_radius if arc.start_radius is not None else (values.absolute(arc.radius_word) if arc.radius_word is not None else None)
        if arc_radius is None:
            return
        radius = self.spindle_tool_radius(state, segment.span, "core.comp-gouge")
        if radius is None:
            return
        verdict = self.checker.judge(hazard("<", arc_radius, radius), state)
        self.checker.report_verdict("core.comp-gouge", segment.span,
                                    f"inside arc of radius {show(arc_radius)} with {'G41' if state.comp_side == 'left' else 'G42'} and a tool of radius {radius:g}: "
                                    "the tool cannot follow it; the control alarms or the tool gouges the wall", verdict, state)

    def motion_run(self, run, state):
        """The inside arcs are judged one by one, but for those whose radius (computed here
        with numpy) is clearly the tool's or more."""
        arcs = run.arcs
        if arcs is None or state.comp_side not in ("left", "right"):
            return
        side = frames.compensation_side(state, arcs.plane)
        inside = next((kind for kind, direction in ((ARC_CW, "cw"), (ARC_CCW, "ccw")) if (side, direction) in _CONCAVE), None)
        if inside is None:
            return
        concave = numpy.flatnonzero(run.kinds == inside)
        if not len(concave):
            return
        self.segment(run.segment(int(concave[0])), state)  # says once what is missing, as the block path would here
        radius = self.spindle_tool_radius(state, run.span(int(concave[0])), "core.comp-gouge")
        if radius is None:
            return
        starts, centres = run.points[concave][:, arcs.columns], arcs.centres[concave]
        arc_radii = numpy.where(numpy.isnan(arcs.radii[concave]), numpy.hypot(*(starts - centres).T), numpy.abs(arcs.radii[concave]))
        for index in concave[1:][~(arc_radii[1:] >= radius * (1 + 1e-9) + 1e-9)].tolist():
            self.segment(run.segment(index), state)


@rule("core.tap-feed-pitch")
class TapFeedMatchesPitch(ReportsMissingContext):
    """A tapping cycle feeds one pitch per revolution: F = pitch x S in G94, F = pitch in G95."""
    judges_holes_before_moves = True
    reads = modelled.AS_WRITTEN

    tolerance = 0.01  # relative

    def hole(self, hole, state):
        if not hole.model.tapping or not self.first_time(state, ("tap-feed", hole.definition)):
            return
        tool = self.checker.context.tools.in_spindle(state)
        if tool is None or tool.pitch is None:
            self.missing("core.tap-feed-pitch", hole.definition or hole.span, "the tap's pitch is not in the tool table (pitch in [tools.N])")
            return
        per_revolution = state.modal.get("feed_mode") == "per_revolution"
        feed, speed = state.feed, state.spindle_speed
        if feed is None or (not per_revolution and speed is None):
            return
        expected = tool.pitch if per_revolution else values.mul(speed, tool.pitch)
        off = values.absolute(values.sub(feed, expected))
        verdict = self.checker.judge(hazard(">", off, values.mul(values.absolute(expected), self.tolerance)), state)
        unit = "mm/rev" if per_revolution else "per minute"
        self.checker.report_verdict("core.tap-feed-pitch", hole.definition or hole.span,
                                    f"{cycle_code(hole.cycle)}: feed F{show(feed)} does not match the tap's pitch {tool.pitch:g}: "
                                    f"it should be {show(expected)} {unit}; the tap cuts a second thread or breaks", verdict, state)
