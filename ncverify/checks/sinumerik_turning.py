"""SINUMERIK 840D turning cycle rules: the stock removal contours of CYCLE95 and CYCLE950,
undercuts (CYCLE94, CYCLE96) and grooves (CYCLE93). Reference ``sinumerik-840d-b.md``;
the shared helpers are in :mod:`.sinumerik`.
"""
from __future__ import annotations

import math

from shapely.geometry import LineString, Point, Polygon

from ..check import Rule, hazard, rule, show
from .common import ReportsMissingContext
from .sinumerik import contour_not_found, contour_points_unknown, cycle_name, is_sinumerik, plane_point, quoted
from .. import modelled


# --------------------------------------------------------------------------- stock removal contours (CYCLE95, CYCLE950)

@rule("sinumerik.stock-removal-contour")
class StockRemovalContour(ReportsMissingContext):
    """CYCLE95's contour rules on the contour's own geometry (reference B section 6.3, C2-C13):
    enough plane blocks, only lines and arcs up to 180 degrees, no plane, frame or G41/G42
    inside, G0-G3 in the first block, no G41/G42 at the call, and the start position
    outside the rectangle the contour spans (61607)."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        facts = run.params.get("CONTOUR") if run.cycle == "sinumerik.CYCLE95" else None
        if facts is None:
            return
        if not facts.found:
            self.missing("sinumerik.stock-removal-contour", run.param_spans.get("NPP", run.span), contour_not_found(facts, "CYCLE95"))
            return
        for alarm, text, span in facts.problems:
            self.report("sinumerik.stock-removal-contour", span or run.param_spans.get("NPP", run.span),
                        f"CYCLE95 contour \"{facts.name}\": {text}: would raise alarm {alarm} with 61606 \"error in contour preparation\"")
        if state.comp_side in ("left", "right"):
            self.report("sinumerik.stock-removal-contour", run.span,
                        f"CYCLE95 called with {'G41' if state.comp_side == 'left' else 'G42'} active: would raise alarm 15800 \"wrong initial conditions for CONTPRON\"")
        first, second, _normal = state.plane_axes
        here = (state.position.get(first), state.position.get(second))
        if facts.box is None or type(here[0]) is not float or type(here[1]) is not float:
            return
        low1, high1, low2, high2 = facts.box
        if low1 <= here[0] <= high1 and low2 <= here[1] <= high2:
            self.report("sinumerik.stock-removal-contour", run.span,
                        f"CYCLE95 starts at {first}{show(here[0])} {second}{show(here[1])}, inside the rectangle of its contour "
                        f"({first}{low1:g}..{high1:g} {second}{low2:g}..{high2:g}): would raise alarm 61607 \"start point programmed incorrectly\"")


@rule("sinumerik.contour-direction")
class ContourDirection(ReportsMissingContext):
    """CYCLE95 takes its machining direction from the contour's first and last points and
    machines undercuts, but an element that turns back against that direction (an overhang)
    is neither machined nor reported (reference B section 9 items 22 and 24, seed
    L16362-16364, L16422-16426, L16472-16487): the first block must give both plane
    coordinates; longitudinal machining needs a contour monotone along the first plane axis,
    face machining along the second. Judged on the contour's end points."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        facts = run.params.get("CONTOUR") if run.cycle == "sinumerik.CYCLE95" else None
        if facts is not None and facts.open_start is not None:
            self.report("sinumerik.contour-direction", facts.open_start,
                        f"CYCLE95 contour \"{facts.name}\": the first block moving in the plane does not give both {state.plane_axes[0]} and {state.plane_axes[1]}: "
                        "the contour's start point, from which the cycle takes its machining direction, is not fully programmed")
        kind = run.params.get("VARI")
        if facts is not None and facts.found and not facts.points:
            self.missing("sinumerik.contour-direction", run.param_spans.get("NPP", run.span),
                         contour_points_unknown(facts, "CYCLE95", "whether it turns back against the machining direction"))
        if facts is None or not facts.points or len(facts.points) < 2 or type(kind) is not float or not 1 <= kind % 100 <= 12:
            return
        longitudinal = int(kind) % 100 % 2 == 1
        index = 0 if longitudinal else 1
        axis = state.plane_axes[index]
        along = [point[index] for point, _span in facts.points]
        direction = 1.0 if along[-1] >= along[0] else -1.0
        for (previous, _), (point, span) in zip(facts.points, facts.points[1:]):
            if (point[index] - previous[index]) * direction < -1e-9:
                self.report("sinumerik.contour-direction", span,
                            f"CYCLE95 contour \"{facts.name}\" turns back along {axis} from {axis}{previous[index]:g} to {axis}{point[index]:g} "
                            f"while the {'longitudinal' if longitudinal else 'face'} machining (VARI={show(kind)}) runs from {axis}{along[0]:g} to {axis}{along[-1]:g}: "
                            "the overhanging element is neither machined nor reported by the cycle")
                return


@rule("sinumerik.extended-stock-removal")
class ExtendedStockRemoval(ReportsMissingContext):
    """CYCLE950 (reference B sections 6.8 and 11.3, seed L18265-18273, L18755-18765,
    L19404-19510): a finished contour must be named (61701), a blank contour must be closed
    (61740) and hold the finished contour (61735) with material between them (61724); neither
    contour may end with RND/CHF, and the two must not run together in the middle of the
    finished contour (the material to remove must be connected)."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        if run.cycle != "sinumerik.CYCLE950":
            return
        finished, blank = run.params.get("FINISHED"), run.params.get("BLANK")
        if finished is None:
            self.report("sinumerik.extended-stock-removal", run.span,
                        "CYCLE950 names no finished contour (_NP1, or _NP2 and _NP3, empty): would raise alarm 61701 \"error in finished-part contour description\"")
            return
        for facts, what in ((finished, "finished"), (blank, "blank")):
            if facts is not None and not facts.found:
                self.missing("sinumerik.extended-stock-removal", run.span, contour_not_found(facts, "CYCLE950", what))
            elif facts is not None and facts.rounded_end is not None:
                self.report("sinumerik.extended-stock-removal", facts.rounded_end,
                            f"CYCLE950: the last element of the {what} contour \"{facts.name}\" carries RND/CHF: not allowed (seed B L18265-18273)")
        for facts, what in ((finished, "finished"), (blank, "blank")):
            if facts is not None and facts.found and not facts.points:
                self.missing("sinumerik.extended-stock-removal", run.span,
                             contour_points_unknown(facts, "CYCLE950", f"the {what} contour's closure and the finished part against the blank"))
        if blank is None or not blank.found or not blank.points:
            return
        if not blank.closed():
            (start, _), (end, end_span) = blank.points[0], blank.points[-1]
            self.report("sinumerik.extended-stock-removal", end_span,
                        f"CYCLE950: the blank contour \"{blank.name}\" ends at {plane_point(end, state)}, not at its start {plane_point(start, state)}: would raise alarm 61740 \"blank must be a closed contour\"")
        elif finished.found and finished.points and len(blank.points) >= 4:
            self._finished_against_blank(finished, blank, state)

    def _finished_against_blank(self, finished, blank, state):
        outline = Polygon([point for point, _span in blank.points])
        inside = outline.buffer(1e-6)
        outside = next(((point, span) for point, span in finished.points if not inside.covers(Point(point))), None)
        if outside is not None:
            self.report("sinumerik.extended-stock-removal", outside[1],
                        f"CYCLE950: the finished contour \"{finished.name}\" reaches {plane_point(outside[0], state)}, outside the blank contour \"{blank.name}\": "
                        "would raise alarm 61735 \"finished part lies outside the blank contour\"")
            return
        edge = outline.exterior.buffer(1e-6)
        elements = [(start, end) for (start, _), (end, _span) in zip(finished.points, finished.points[1:]) if math.dist(start, end) > 1e-6]
        if elements and all(edge.covers(LineString(element)) for element in elements):
            self._no_material(finished, blank)
            return
        inner = list(zip(finished.points[1:-2], finished.points[2:-1]))
        shared = next(((start, end, span) for (start, _), (end, span) in inner if math.dist(start, end) > 1e-6 and edge.covers(LineString([start, end]))), None)
        if shared is not None:
            self.report("sinumerik.extended-stock-removal", shared[2],
                        f"CYCLE950: the finished contour \"{finished.name}\" runs along the blank contour \"{blank.name}\" from {plane_point(shared[0], state)} "
                        f"to {plane_point(shared[1], state)}: the material to remove is split in two; the contours must not coincide piecewise (seed B L18755-18765)")

    def _no_material(self, finished, blank):
        """The finished contour runs along the blank's outline all the way: alarm 61724 "no
        material" (reference B section 11.3), certain when both are straight lines; with arcs,
        roundings or chamfers only their end points are known to coincide."""
        span = finished.points[1][1]
        coincide = f"CYCLE950: the finished contour \"{finished.name}\" runs along the blank contour \"{blank.name}\" all the way"
        if finished.straight() and blank.straight():
            self.report("sinumerik.extended-stock-removal", span,
                        f"{coincide}: there is no material between them to remove: would raise alarm 61724 \"no material\"")
        else:
            self.missing("sinumerik.extended-stock-removal", span,
                         f"{coincide} at the end points of their elements; whether their arcs, roundings and chamfers coincide too (alarm 61724 \"no material\") is not judged")


# --------------------------------------------------------------------------- undercuts and grooves

@rule("sinumerik.undercut-form")
class UndercutForm(Rule):
    """CYCLE94 FORM "E"/"F", CYCLE96 FORM "A"-"D": alarm 61609 (seed B L15612-15618, L16790-16796)."""

    def cycle_run(self, run, state):
        name = cycle_name(run)
        allowed = {"CYCLE94": ("E", "F"), "CYCLE96": ("A", "B", "C", "D")}.get(name) if is_sinumerik(run) else None
        if allowed is None:
            return
        form = run.params.get("FORM")
        if not (isinstance(form, str) and form.upper() in allowed):
            self.report("sinumerik.undercut-form", run.param_spans.get("FORM", run.span),
                        f"{name}: FORM {quoted(form)} is not {' or '.join(chr(34) + letter + chr(34) for letter in allowed)}: "
                        "would raise alarm 61609 \"form defined incorrectly\"")


@rule("sinumerik.undercut-feed")
class UndercutFeed(Rule):
    """CYCLE94 and CYCLE96 cut the undercut at the feed programmed before the call (reference
    B section 9 item 42, seed L15570-15572, L16732-16734): there must be one."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        if run.cycle not in ("sinumerik.CYCLE94", "sinumerik.CYCLE96"):
            return
        feed = state.feed
        if feed is None and not state.feed_inherited:
            self.report("sinumerik.undercut-feed", run.span,
                        f"{cycle_name(run)} with no feed programmed: the cycle cuts the undercut at the F active before the call; program F (G95 mm/rev) before it")
        elif feed is not None:
            self.checker.report_verdict("sinumerik.undercut-feed", run.span,
                                        f"{cycle_name(run)} at feed F{show(feed)}: the cycle cuts the undercut at this F, which does not move the axes",
                                        self.checker.judge(hazard("<=", feed, 0.0), state), state)


@rule("sinumerik.groove-dwell")
class GrooveDwell(ReportsMissingContext):
    """CYCLE93's dwell DTB at the groove base should last at least one spindle revolution
    (reference B section 9 item 29, seed L15201-15205): judged under G97, where the speed S
    is the revolutions per minute; unknown otherwise."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        dwell = run.params.get("DTB") if run.cycle == "sinumerik.CYCLE93" else None
        speed = state.spindle_speed
        if type(dwell) is not float or dwell <= 0:
            return
        if state.modal.get("spindle_mode") != "rpm" or type(speed) is not float or speed <= 0:
            self.missing("sinumerik.groove-dwell", run.param_spans.get("DTB", run.span),
                         "the spindle revolutions at CYCLE93 are not known (no G97 with a positive S): its dwell DTB against one revolution")
            return
        revolution = 60.0 / speed
        if dwell < revolution:
            self.report("sinumerik.groove-dwell", run.param_spans.get("DTB", run.span),
                        f"CYCLE93: dwell DTB={show(dwell)} s is shorter than one revolution at S{show(speed)} ({revolution:.3g} s): "
                        "the groove base is not cut round; dwell at least one revolution")
