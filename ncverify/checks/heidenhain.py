"""Klartext cycle hazards that need the tool table or the machine state (reference A §9).

Parameter-only hazards are constraints in ``rules/heidenhain/*.md``; faults the cycle
runner raises (a call with no cycle, RL/RR at a call) are reported from the trace.
"""
from __future__ import annotations

import math
from dataclasses import replace
from functools import lru_cache

from ..ir import cycle_code
from .. import frames, pocket, values
from ..check import Rule, hazard, rule, show
from ..diagnostics import Status
from ..trace import NO_FACTS
from ..verdict import Verdict
from ..context import radius_delta
from .common import ReportsMissingContext, plane_scale, scaled_note
from .. import modelled

_DEPTH_CHECKED = {200, 201, 202, 203, 205, 208, 241, 206, 207, 209, 251, 252, 253, 254, 256, 257, 258, 272, 273, 274}
_PLUNGE_CHECKED = {251, 252, 253, 254}
_SL_CYCLES = {21, 22, 23, 24}


@lru_cache(maxsize=512)
def cycle_number(cycle: str) -> int | None:
    """The number of a Klartext cycle id (``heidenhain.200``: 200), None for any other.
    Kept per id: some thirty rules ask it of every hole."""
    if not cycle.startswith("heidenhain."):
        return None
    tail = cycle_code(cycle)
    return int(tail) if tail.isdigit() else None


def spindle_tool(rule_instance, state, span, rule_id, what: str):
    """The tool in the spindle from TOOL.T / the project file, or None (said once)."""
    tools = rule_instance.checker.context.tools
    tool = tools.in_spindle(state)
    if tool is None or getattr(tool, what) is None:
        rule_instance.missing(rule_id, span, tools.missing(state, what))
        return None
    delta = radius_delta(state)
    if type(delta) is not float:
        rule_instance.missing(rule_id, span, "the radius delta DR of the TOOL CALL depends on a free parameter")
        return None
    return tool if delta == 0.0 or tool.radius is None else replace(tool, radius=tool.radius + delta)


# Where the depth the usable length must reach is not Q201 (reference A H4): back boring
# counterbores Q249 from the underside, 240 by depth only when Q343 = 0, face milling takes
# Q227 - Q386.
_DEPTH_OF = {204: ("Q249",), 240: ("Q201",), 232: ("Q227", "Q386"), 233: ("Q227", "Q386")}


def _machining_depth(number, params):
    """The parameters the depth a cycle machines is read from, and its value (None where
    it is not given or not stated)."""
    if number in _SL_CYCLES:
        return ("Q1",), params.get("Q1")
    names = _DEPTH_OF.get(number, ("Q201",))
    if number == 240 and params.get("Q343", 0.0) != 0.0:
        return ("Q344",), None  # by diameter: the depth follows from the tool's point angle
    found = [params.get(name) for name in names]
    if any(value is None for value in found):
        return names, None
    return names, found[0] if len(found) == 1 else values.sub(*found)


class CycleRule(ReportsMissingContext):
    """Judges every cycle execution, hole or pocket, once per definition and place."""
    reads = modelled.AS_WRITTEN

    def hole(self, hole, state):
        self.judge_cycle(cycle_number(hole.cycle), hole.params, hole.param_spans, hole.definition or hole.span, state, NO_FACTS)

    def cycle_run(self, run, state):
        if not run.first_block:
            self.judge_cycle(cycle_number(run.cycle), run.params, run.param_spans, run.span, state, run.facts)

    def judge_cycle(self, number, params, spans, span, state, facts): ...


class CycleRuleOfParts(CycleRule):
    """One rule judged by independent parts (say, the pocket cycles and the contour cycles),
    in order; each part keeps its own memory of the context it has said is missing."""

    parts: tuple[type[CycleRule], ...] = ()

    def __init__(self, checker):
        super().__init__(checker)
        self._parts = [part(checker) for part in self.parts]

    def judge_cycle(self, number, params, spans, span, state, facts):
        for part in self._parts:
            part.judge_cycle(number, params, spans, span, state, facts)


@rule("heidenhain.usable-length")
class UsableLength(CycleRule):
    """H4: the control stops when the tool's usable length LU is shorter than the depth."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        if number not in _DEPTH_CHECKED and number not in _SL_CYCLES and number not in _DEPTH_OF:
            return
        names, depth = _machining_depth(number, params)
        if depth is None and names == ("Q344",):
            self.missing("heidenhain.usable-length", span, "cycle 240 centres to the diameter Q344: the depth follows from the tool's point angle, "
                         "which is not computed, so it is not compared with the usable length LU")
        if depth is None or not self.first_time(state, ("usable-length", span)):
            return
        tool = spindle_tool(self, state, span, "heidenhain.usable-length", "usable_length")
        if tool is None:
            return
        verdict = self.checker.judge(hazard(">", values.absolute(depth), tool.usable_length), state)
        self.checker.report_verdict("heidenhain.usable-length", spans.get(names[-1], span),
                                    f"cycle {number}: depth {' - '.join(names)}={show(depth)} is deeper than the usable length LU={tool.usable_length:g} of tool T{show(state.tool_in_spindle)}: "
                                    "the control stops with an error before machining (seed L1625-1626)", verdict, state)


@rule("heidenhain.tap-pitch")
class TapPitch(CycleRule):
    """H9: with a PITCH in the tool table, 207/209 compare it with Q239 and stop on a mismatch.
    H8: 206 in a floating holder feeds Q206, which must be S x PITCH."""

    tolerance = 0.01  # relative: what the floating holder takes up is not stated

    def judge_cycle(self, number, params, spans, span, state, facts):
        if number == 206:
            self._floating_feed(params, spans, span, state)
            return
        pitch = params.get("Q239")
        if number not in (207, 209) or pitch is None or not self.first_time(state, ("tap-pitch", span)):
            return
        tool = spindle_tool(self, state, span, "heidenhain.tap-pitch", "pitch")
        if tool is None:
            return
        verdict = self.checker.judge(hazard(">", values.absolute(values.sub(values.absolute(pitch), abs(tool.pitch))), 1e-6), state)
        self.checker.report_verdict("heidenhain.tap-pitch", spans.get("Q239", span),
                                    f"cycle {number}: thread pitch Q239={show(pitch)} differs from the PITCH {tool.pitch:g} of tap T{show(state.tool_in_spindle)} in the tool table: "
                                    "the control stops with an error (seed L3918-3920)", verdict, state)


    def _floating_feed(self, params, spans, span, state):
        feed, speed = params.get("Q206"), state.spindle_speed
        if feed is None or not self.first_time(state, ("tap-feed", span)):
            return
        if speed is None:
            self.missing("heidenhain.tap-pitch", span, "no spindle speed S at cycle 206, so its feed Q206 is not compared with S x PITCH")
            return
        tool = spindle_tool(self, state, span, "heidenhain.tap-pitch", "pitch")
        if tool is None:
            return
        expected = values.absolute(values.mul(speed, tool.pitch))
        verdict = self.checker.judge(hazard(">", values.absolute(values.sub(feed, expected)), values.mul(expected, self.tolerance)), state)
        self.checker.report_verdict("heidenhain.tap-pitch", spans.get("Q206", span),
                                    f"cycle 206: feed Q206={show(feed)} is not the spindle speed S{show(speed)} times the PITCH {tool.pitch:g} of tap "
                                    f"T{show(state.tool_in_spindle)} = {show(expected)}: the tap cuts a second thread or breaks (seed L3786-3788)", verdict, state)


class _PocketPlungeAngle(CycleRule):
    """H11: a helical or reciprocating plunge needs the tool's ANGLE; 252's vertical plunge
    takes only ANGLE 0 or 90."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        strategy = params.get("Q366")
        if number not in _PLUNGE_CHECKED or type(strategy) is not float or not self.first_time(state, ("plunge-angle", span)):
            return
        if strategy == 0.0 and number != 252:
            return
        tool = spindle_tool(self, state, span, "heidenhain.plunge-angle", "angle")
        if tool is None:
            return
        where = spans.get("Q366", span)
        if strategy != 0.0 and tool.angle == 0.0:
            self.report("heidenhain.plunge-angle", where, f"cycle {number}: plunging strategy Q366={strategy:g} needs the tool's plunge angle, but ANGLE of "
                        f"T{show(state.tool_in_spindle)} is 0: the control stops with an error (seed L964-975)")
        elif number == 252 and strategy == 0.0 and tool.angle not in (0.0, 90.0):
            self.report("heidenhain.plunge-angle", where, f"cycle 252: vertical plunge Q366=0 needs ANGLE 0 or 90 in the tool table, T{show(state.tool_in_spindle)} "
                        f"has {tool.angle:g}: the control stops with an error (seed L5810-5817)")


class _PocketFit(CycleRule):
    """H12/H33: the tool must fit the pocket, slot or bore it is to cut; the largest tool
    that would is reported. Part B C21: a cycle-22 contour pocket the tool enters but
    cannot clear is residual material, a warning."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        if number not in (208, 251, 252, 253, 254, 22, 272) or not self.first_time(state, ("tool-too-large", span)):
            return
        if number == 272 and (facts.shape not in (1271.0, 1272.0, 1273.0) or params.get("Q650", 0.0) != 0.0):
            return  # a free OCM contour or an island / boundary shape: no pocket to fit
        tool = spindle_tool(self, state, span, "heidenhain.tool-too-large", "radius")
        if tool is None:
            return
        params = self.workpiece_sizes(params, _SIZE_PARAMETERS, state, span, "heidenhain.tool-too-large")
        if params is None:
            return
        if number == 22:
            self._contour_pocket(params, span, tool, state, facts.region)
            return
        radius = tool.radius
        if number == 272:  # the smallest inside radius OCM cuts is R + Q578 R, beside the allowance Q368 (reference B H23)
            factor, allowance = params.get("Q578", 0.0), params.get("Q368", 0.0)
            if type(factor) is not float or type(allowance) is not float:
                self.missing("heidenhain.tool-too-large", span, "an inside corner factor or allowance that depends on a free parameter")
                return
            radius = tool.radius * (1.0 + factor) + allowance
        if self._judge_symbolic_size(number, params, spans, span, tool, state):
            return
        fit, where = self._fit(number, params, spans, radius, span, facts.shape)
        if fit is None:
            self.missing("heidenhain.tool-too-large", span, "a pocket size that depends on a free parameter")
            return
        if not fit.fits:
            self.report("heidenhain.tool-too-large", where, f"cycle {number}: {fit.reason} (tool T{show(state.tool_in_spindle)}, R={tool.radius:g}){scaled_note(state)}; "
                        f"the largest tool radius that fits is {fit.largest_radius:g}")

    # cycle -> (the size parameters, what they are, the hazard that the tool does not fit them):
    # sizes the solver judges when they depend on free parameters
    _SYMBOLIC_SIZES = {
        252: (("Q223",), "circular pocket of diameter", lambda sizes, radius: pocket.circle_misfit(*sizes, radius, strict=True)),
        208: (("Q335",), "bore of diameter", lambda sizes, radius: pocket.circle_misfit(*sizes, radius)),
        253: (("Q219",), "slot of width", lambda sizes, radius: pocket.slot_misfit(*sizes, radius)),
        254: (("Q219",), "circular slot of width", lambda sizes, radius: pocket.slot_misfit(*sizes, radius)),
        251: (("Q219", "Q218", "Q220"), "rectangular pocket of width, length and corner radius",
              lambda sizes, radius: pocket.rectangle_misfit(*sizes, radius, strict=True)),
    }

    def _judge_symbolic_size(self, number, params, spans, span, tool, state) -> bool:
        """A pocket, slot or bore whose size depends on free parameters goes to the solver
        (the conditions of :mod:`ncverify.pocket`): ``proved``, or ``violated`` with a
        witness. True when it was judged here."""
        names, what, misfit = self._SYMBOLIC_SIZES.get(number, ((), None, None))
        sizes = [params.get(name, 0.0) for name in names]
        if not any(isinstance(size, values.Sym) for size in sizes):
            return False
        self.checker.report_verdict("heidenhain.tool-too-large", spans.get(names[0], span),
                                    f"cycle {number}: the tool (diameter {2 * tool.radius:g}, T{show(state.tool_in_spindle)}) does not fit the {what} "
                                    f"{' x '.join(show(size) for size in sizes)}{scaled_note(state)}",
                                    self.checker.judge(misfit(sizes, tool.radius), state), state)
        return True

    def _contour_pocket(self, params, span, tool, state, area):
        """Cycle 22 roughs with the side allowance Q3 left on the walls: the tool centre
        keeps R + Q3 from the contour (reference B H21). A pocket the tool cannot enter is
        not machined at all; where it enters, what it cannot reach (a neck narrower than
        2 (R + Q3), an inside radius below R + Q3) stays as residual material: the control
        machines around it without an alarm (reference B §9 item 21, seed L9575-9593)."""
        allowance = params.get("Q3", 0.0)
        if plane_scale(state) != 1.0:
            self.missing("heidenhain.tool-too-large", span, "a contour pocket under a scaling cycle (11 or 26): its outline is compared as written only")
            return
        if area is None or type(allowance) is not float:
            self.missing("heidenhain.tool-too-large", span, "the contour of cycle 14 could not be resolved (free Q parameters, CT or FK elements, or an R0 subcontour)")
            return
        allowance = max(allowance, 0.0)
        tool_named = f"cycle 22: tool T{show(state.tool_in_spindle)} (R={tool.radius:g}) with side allowance Q3={allowance:g}"
        for part in getattr(area, "geoms", [area]):
            spots = pocket.unreached_spots(part, tool.radius + allowance)
            if spots is None:
                inside = part.representative_point()
                self.report("heidenhain.tool-too-large", span, f"{tool_named} cannot enter the contour pocket around X{inside.x:.3f} Y{inside.y:.3f} at all: "
                            f"the cycle machines none of it; the largest tool radius that clears it is {self._clearing(pocket.largest_radius(part), allowance)}")
            elif spots:
                self.report("heidenhain.residual-material", span, f"{tool_named} leaves material at {len(spots)} place(s) of the contour pocket, "
                            f"{self._places(part, spots, allowance)}: the control machines around it without an alarm; "
                            f"the largest tool radius that clears the whole pocket is {self._clearing(pocket.largest_radius(part), allowance)} (seed L9575-9593)")

    _PLACES_NAMED = 3  # the residual places a finding names; the count says how many there are

    @classmethod
    def _places(cls, part, spots, allowance):
        named = []
        for spot in spots[:cls._PLACES_NAMED]:
            reach = pocket.clearing_radius(part, spot)
            named.append(f"near X{spot[0]:.3f} Y{spot[1]:.3f} (a neck {2 * reach:.3g} wide or an inside radius of {reach:.3g}: "
                         f"a tool up to R{cls._clearing(reach, allowance)} reaches it)")
        return "; ".join(named) + ("; ..." if len(spots) > cls._PLACES_NAMED else "")

    @staticmethod
    def _clearing(radius, allowance):
        return f"{max(radius - allowance, 0.0):.3g}"

    @staticmethod
    def _fit(number, params, spans, radius, span, shape):
        def concrete(*names):
            found = [params.get(name, 0.0) for name in names]
            return found if all(type(value) is float for value in found) else None

        if number == 251:
            found = concrete("Q218", "Q219", "Q220")
            return (pocket.rectangle_fit(*found, radius, strict=True) if found else None), spans.get("Q219", span)
        if number == 272 and shape == 1271.0:
            found = concrete("Q218", "Q219", "Q220")
            return (pocket.rectangle_fit(*found, radius) if found else None), spans.get("Q219", span)
        if number == 272 and shape == 1272.0:
            found = concrete("Q223")
            return (pocket.circle_fit(found[0], radius) if found else None), spans.get("Q223", span)
        if number in (252, 208):
            found = concrete("Q223" if number == 252 else "Q335")
            strict = number == 252  # a pocket needs room to plunge; 208 may plunge straight at 2R = Q335 (seed L2869-2870)
            return (pocket.circle_fit(found[0], radius, strict=strict) if found else None), spans.get("Q223" if number == 252 else "Q335", span)
        found = concrete("Q219")
        return (pocket.slot_fit(found[0], radius) if found else None), spans.get("Q219", span)


# cycle -> (clearance height, surface, set-up clearance, manual lines): the level the moves
# between areas and the final retract run at (part B H13, H14); no surface: not compared with it
_CLEARANCE_HEIGHT = {
    **dict.fromkeys(_SL_CYCLES, ("Q7", "Q5", "Q6", "seed L9384-9396")),
    **dict.fromkeys((25, 276), ("Q7", None, None, "seed L9384-9396")),
    **dict.fromkeys((272, 273, 274, 277), ("Q260", "Q203", "Q200", "seed L11147-11150")),
}


# The lengths of the pocket, slot, bore and polygon cycles the tool must fit, which the
# control scales with the positions (cycles 11 and 26)
_SIZE_PARAMETERS = ("Q218", "Q219", "Q220", "Q223", "Q335", "Q368", "Q571")


class _ContourPlungeAngle(CycleRule):
    """C21, C27: 22 ROUGH-OUT with a reciprocating feed Q19 and 275 with a reciprocating
    plunge Q366 = 2 need the tool's plunge ANGLE (seed L9582-9593, L10305-10311); the
    pocket cycles are judged by :class:`_PocketPlungeAngle`."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        name = {22: "Q19", 275: "Q366"}.get(number)
        value = params.get(name) if name else None
        if type(value) is not float or value == 0.0 or (number == 275 and value != 2.0) or not self.first_time(state, ("contour-plunge-angle", span)):
            return
        tool = spindle_tool(self, state, span, "heidenhain.plunge-angle", "angle")
        if tool is not None and tool.angle == 0.0:
            what = "a reciprocating plunge feed Q19" if number == 22 else "the reciprocating plunge Q366=2"
            self.report("heidenhain.plunge-angle", spans.get(name, span), f"cycle {number} with {what} needs the tool's plunge angle, but ANGLE of "
                        f"T{show(state.tool_in_spindle)} is 0: the control stops with an error")


class _PolygonPocketFit(CycleRule):
    """C23: a 1278 polygon pocket must hold the tool: its inscribed circle (Q571 itself, or
    Q571 cos(180/n) when Q571 is the circumscribed circle) against R (1 + Q578) + Q368, as
    for the circle 1272 (seed L12600-12744, L10990-10997)."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        if number != 272 or facts.shape != 1278.0 or params.get("Q650", 0.0) != 0.0 or not self.first_time(state, ("polygon-fit", span)):
            return
        params = self.workpiece_sizes(params, _SIZE_PARAMETERS, state, span, "heidenhain.tool-too-large")
        if params is None:
            return
        diameter, corners, circumscribed = params.get("Q571"), params.get("Q572"), params.get("Q573", 0.0)
        factor, allowance = params.get("Q578", 0.0), params.get("Q368", 0.0)
        if any(type(value) is not float for value in (diameter, corners, circumscribed, factor, allowance)) or corners < 3:
            self.missing("heidenhain.tool-too-large", span, "a polygon size that depends on a free parameter")
            return
        tool = spindle_tool(self, state, span, "heidenhain.tool-too-large", "radius")
        if tool is None:
            return
        inscribed = diameter * math.cos(math.pi / corners) if circumscribed == 1.0 else diameter
        fit = pocket.circle_fit(inscribed, tool.radius * (1.0 + factor) + allowance)
        if not fit.fits:
            self.report("heidenhain.tool-too-large", spans.get("Q571", span), f"cycle 272 in the {corners:g}-cornered polygon of inscribed diameter {inscribed:g}: "
                        f"{fit.reason} (tool T{show(state.tool_in_spindle)}, R={tool.radius:g}, with the inside corner factor Q578={factor:g} "
                        f"and the allowance Q368={allowance:g}); the largest tool radius that fits is {max((fit.largest_radius - allowance) / (1.0 + factor), 0.0):.3g}")
@rule("heidenhain.plunge-angle")
class PlungeAngle(CycleRuleOfParts):
    """The tool's plunge ANGLE against the plunging strategy of the pocket cycles and the
    reciprocating plunges of the contour cycles 22 and 275."""

    parts = (_PocketPlungeAngle, _ContourPlungeAngle)


@rule("heidenhain.tool-too-large", "heidenhain.residual-material")
class ToolTooLarge(CycleRuleOfParts):
    """The tool against the pocket, slot, bore or contour pocket it cuts, and against the
    1278 polygon pocket of OCM."""
    reads = modelled.SCALED_SIZES

    parts = (_PocketFit, _PolygonPocketFit)


@rule("heidenhain.sl-clearance-height")
class ContourClearanceHeight(CycleRule):
    """Part B H13/H14: the SL, contour-train and OCM cycles travel between areas and retract
    at a clearance height (Q7, Q260) that must lie above the set-up clearance and the blank."""
    reads = modelled.GEOMETRY

    def judge_cycle(self, number, params, spans, span, state, facts):
        if number not in _CLEARANCE_HEIGHT:
            return
        name, surface_name, clearance_name, lines = _CLEARANCE_HEIGHT[number]
        height = params.get(name)
        if height is None or not self.first_time(state, ("sl-clearance", span)):
            return
        where = spans.get(name, span)
        surface, clearance = params.get(surface_name), params.get(clearance_name)
        if surface is not None and clearance is not None:
            set_up = values.add(surface, values.absolute(clearance))
            verdict = self.checker.judge(hazard("<", height, set_up), state)
            self.checker.report_verdict("heidenhain.sl-clearance-height", where, f"cycle {number}: clearance height {name}={show(height)} is below the set-up "
                                        f"clearance {surface_name} + {clearance_name} = {show(set_up)}: the moves between areas run below the plane the "
                                        f"cycle approaches from ({lines})", verdict, state)
        stock = self.checker.context.stock
        on_blank = frames.workpiece_level(state, state.plane_axes[2], height)  # the parameter is in program coordinates
        if stock is not None and on_blank is None:
            self.missing("heidenhain.sl-clearance-height", where, "the active coordinate transformation (a tilted working plane) leaves where the "
                         "clearance height lies on the blank unknown")
        elif stock is not None:
            verdict = self.checker.judge(hazard("<=", on_blank, stock.top), state)
            self.checker.report_verdict("heidenhain.sl-clearance-height", where, f"cycle {number}: clearance height {name}={show(height)} is not above the top "
                                        f"of the blank Z{stock.top:g}: the moves between areas and the final retract stay in the material", verdict, state)


@rule("heidenhain.transform-at-end")
class TransformAtEnd(Rule):
    """H35: a coordinate transformation still active when the program ends. Whether M2,
    M30 or END PGM reset it is a machine parameter (seed L7738-7745): do not rely on it."""

    def change(self, change, state):
        active = state.klartext.transforms
        if change.what == "end" and change.new in ("end", "eof") and active:
            cycles = ", ".join(str(number) for number, _values in active)
            self.report("heidenhain.transform-at-end", change.span, f"coordinate transformation (cycle {cycles}) is still active at the end of the program: "
                        "whether M2/M30/END PGM resets it depends on a machine parameter, so the next program may run shifted, rotated or mirrored")


@rule("heidenhain.depth-through-blank")
class DepthThroughBlank(ReportsMissingContext):
    """A43 H41: a hole bottom below the underside of the blank reaches what the part lies on.

    The reference asks for a warning; the verdict is ``unknown`` instead, as a machinist
    reads it: a bottom below the underside is how a through hole is programmed (the drill's
    point and a break-through pass the underside), the manual's own example C200 does it
    (Q203 = -10, Q201 = -15 in the blank Z-20..0: bottom Z-25), and BLK FORM describes the
    blank for the graphics, not what it is clamped on. Whether parallels or a spacer lie
    under the hole is the set-up's, which the program does not state. A bottom that is not
    below the underside for any allowed value is ``proved``."""
    reads = modelled.GEOMETRY

    def hole(self, hole, state):
        if cycle_number(hole.cycle) is None or hole.bottom is None or not self.first_time(state, ("through-blank", hole.definition)):
            return
        stock = self.checker.context.stock
        if stock is None:
            return
        low = stock.z_range[0]
        verdict = self.checker.judge(hazard("<", hole.bottom, low), state)
        if verdict is not None and verdict.status is Status.VIOLATED:
            # a hole that goes through the blank is a through hole, which must pass the underside:
            # whether parallels or a spacer lie under the part is the set-up's, not the program's
            verdict = Verdict(Status.UNKNOWN, verdict.witness, "a through hole: whether the part lies on parallels or a spacer is not in the program")
        self.checker.report_verdict("heidenhain.depth-through-blank", hole.param_spans.get("Q201", hole.definition or hole.span),
                                    f"cycle {cycle_number(hole.cycle)}: the hole bottom Z{show(hole.bottom)} (Q203 + Q201) is below the underside of the blank Z{low:g}: "
                                    "the tool cuts into what the part lies on unless it stands on parallels or a spacer (seed L3527-3539)", verdict, state)
