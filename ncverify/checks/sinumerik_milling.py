"""SINUMERIK 840D milling cycle rules: the tool against the pocket, slot or hole it cuts,
pocket and path-milling contours (CYCLE72-75), the milling depth, scaling frames at the
call, swivelling (CYCLE800), high-speed settings (CYCLE832) and engraving (CYCLE60).
Reference ``sinumerik-840d-a.md``; the shared helpers are in :mod:`.sinumerik`.
"""
from __future__ import annotations

import math

from .. import values
from ..check import Rule, hazard, rule, show
from ..frames import AXES
from ..interpret.sinumerik_cycles import levels
from ..pocket import circle_fit, circle_misfit, rectangle_fit, rectangle_misfit, slot_fit, slot_misfit
from .common import ReportsMissingContext, scaled_note
from .sinumerik import PLANE_CYCLES, contour_not_found, contour_points_unknown, cycle_name, digit_problem, is_sinumerik, numeric_parameter, plane_point
from .sinumerik_tools import active_edge
from .. import modelled


# --------------------------------------------------------------------------- tool against the feature

@rule("sinumerik.cutter-radius")
class CutterRadius(ReportsMissingContext):
    """Alarm 61105 "cutter radius too large" (POCKET1-4, SLOT1/2, LONGHOLE), 61111 "infeed
    width > tool diameter" (POCKET3/4, CYCLE71), 61117/61112 for a radius the cycle cannot use,
    and a slot tool below half the slot width, from the tool radius in the tool data ($TC_DP6
    in the program or the project's tool table)."""
    reads = modelled.SCALED_SIZES

    def cycle_run(self, run, state):
        cycle = cycle_name(run)
        if not is_sinumerik(run) or (cycle not in _FEATURES and cycle not in _RADIUS_SIGN):
            return
        radius = self._radius(run, state)
        if radius is None:
            return
        tool = f"tool T{show(state.tool_in_spindle)} (radius {radius:g})"
        alarm = _RADIUS_SIGN.get(cycle)
        if alarm is not None and (radius < 0 or (radius == 0 and alarm[0] == "61117")):
            self.report("sinumerik.cutter-radius", run.span, f"{cycle} with {tool}: would raise alarm {alarm[0]} \"{alarm[1]}\"")
            return
        if cycle in _FEATURES:
            self._fit(run, cycle, radius, tool, state)
        stepover = run.params.get("_MIDA")
        if cycle in ("POCKET3", "POCKET4", "CYCLE71") and type(stepover) is float and stepover > 2 * radius:
            self.report("sinumerik.cutter-radius", run.param_spans.get("_MIDA", run.span),
                        f"{cycle}: stepover _MIDA={show(stepover)} is larger than the tool diameter {2 * radius:g} of {tool}: "
                        "would raise alarm 61111 \"infeed width > tool diameter\"")

    def _fit(self, run, cycle, radius, tool, state):
        """61105 for a tool too large for the feature; a slot tool below half the width (not checked by the control)."""
        shape, names, strict, what = _FEATURES[cycle]
        span = run.param_spans.get(names[0], run.span)
        sizes = self.workpiece_sizes({name: run.params.get(name) for name in names}, names, state, span, "sinumerik.cutter-radius")
        if sizes is None or any(value is None or isinstance(value, str) for value in sizes.values()):
            return
        dimensions = [sizes[name] for name in names]
        scaled = scaled_note(state)
        if any(isinstance(value, values.Sym) for value in dimensions):
            self.checker.report_verdict("sinumerik.cutter-radius", span, f"{cycle}: {tool} does not fit the {what} ({', '.join(f'{name}={show(value)}' for name, value in zip(names, dimensions))}){scaled}: "
                                        "would raise alarm 61105 \"cutter radius too large\"", self.checker.judge(_MISFITS[shape](dimensions, radius, strict), state), state)
            return
        fit = _FITS[shape](dimensions, radius, strict)
        if not fit.fits:
            self.report("sinumerik.cutter-radius", span,
                        f"{cycle}: {tool} does not fit the {what}{scaled}: {fit.reason}; the largest radius that fits is {fit.largest_radius:g}: "
                        "would raise alarm 61105 \"cutter radius too large\"")
        width, kind = sizes.get("WID"), run.params.get("VARI", 0.0)
        edge_finishing_only = cycle == "SLOT2" and (type(kind) is not float or kind % 10 == 3)
        if cycle in ("SLOT1", "SLOT2") and 0 < 4 * radius < abs(width) and not edge_finishing_only:
            self.report("sinumerik.cutter-radius", span,
                        f"{cycle}: {tool} is less than half the slot width WID={show(width)}{scaled}: the cycle does not check this and leaves material "
                        f"in the slot (seed A L5930; SLOT2 alarm 61905 \"cutter radius too small\"); use a tool of diameter {abs(width) / 2:g} to {abs(width):g}")
        if cycle in _POCKET_CORNERS_AND_ALLOWANCE:
            self._pocket_corners_and_allowance(run, cycle, radius, tool)

    def _pocket_corners_and_allowance(self, run, cycle, radius, tool):
        """No alarm, but not the pocket drawn: corners rounder than CRAD (seed A L6630-6635), and a
        wall allowance of a tool diameter or more (message, incomplete roughing, L7277-7282)."""
        corner_name, allowance_name = _POCKET_CORNERS_AND_ALLOWANCE[cycle]
        corner, allowance = run.params.get(corner_name), run.params.get(allowance_name)
        if corner_name and type(corner) is float and 0 < abs(corner) < radius:
            self.report("sinumerik.cutter-radius", run.param_spans.get(corner_name, run.span),
                        f"{cycle}: {tool} is larger than the corner radius {corner_name}={show(corner)}: the corners come out with radius {radius:g} "
                        "(no alarm; the pocket is not the one drawn)")
        if type(allowance) is float and allowance >= 2 * radius:
            self.report("sinumerik.cutter-radius", run.param_spans.get(allowance_name, run.span),
                        f"{cycle}: wall allowance {allowance_name}={show(allowance)} is a tool diameter ({2 * radius:g}) or more: the cycle shows "
                        "\"Caution: finishing allowance >= tool diameter\" and leaves the roughing incomplete")

    def _radius(self, run, state):
        radius = _spindle_tool_radius(self.checker, state)
        if radius is None:
            self.missing("sinumerik.cutter-radius", run.span, "no tool radius for the active edge of the tool in the spindle ($TC_DP6[t,d] in the program; [tools.N] radius describes D1)")
        return radius


def _spindle_tool_radius(checker, state):
    """The radius of the active edge of the tool in the spindle from the tool data, or None.
    The tool's own values are edge D1's; another D number takes its ``$TC_DP6[t,d]``."""
    tool = checker.context.tools.in_spindle(state)
    edge = active_edge(state)
    if tool is not None and edge is not None:
        tool = tool.edge_data(edge)
    return None if tool is None else tool.radius


# The alarm for a tool radius the cycle cannot use: 61117 "radius <= 0", 61112 "radius negative" (appendix L19773, L19810).
_RADIUS_SIGN = {"CYCLE71": ("61117", "active tool radius <= 0"), "POCKET3": ("61117", "active tool radius <= 0"),
                "POCKET4": ("61117", "active tool radius <= 0"), "CYCLE72": ("61112", "tool radius negative"),
                "CYCLE76": ("61112", "tool radius negative"), "CYCLE77": ("61112", "tool radius negative"),
                "CYCLE90": ("61112", "tool radius negative")}


# The corner radius and the wall allowance of the pockets whose roughing they limit.
_POCKET_CORNERS_AND_ALLOWANCE = {"POCKET1": ("CRAD", "FAL"), "POCKET2": ("", "FAL"), "POCKET3": ("_CRAD", "_FAL")}


# cycle -> (shape, the size parameters, whether the tool must be smaller than the feature,
# what it is). A pocket's corner radius is judged apart (no alarm, see above); a circular
# pocket's size is its radius.
_FEATURES = {
    "POCKET1": ("rectangle", ("LENG", "WID"), False, "pocket"),
    "POCKET3": ("rectangle", ("_LENG", "_WID"), False, "pocket"),
    "POCKET2": ("circle", ("PRAD",), False, "circular pocket"),
    "POCKET4": ("circle", ("_PRAD",), False, "circular pocket"),
    "SLOT1": ("slot", ("WID",), True, "slot"),
    "SLOT2": ("slot", ("WID",), True, "slot"),
    "LONGHOLE": ("slot", ("LENG",), False, "elongated hole length"),
}
_FITS = {
    "rectangle": lambda sizes, radius, strict: rectangle_fit(abs(sizes[0]), abs(sizes[1]), 0.0, radius, strict),
    "circle": lambda sizes, radius, strict: circle_fit(2 * abs(sizes[0]), radius, strict),
    "slot": lambda sizes, radius, strict: slot_fit(abs(sizes[0]), radius, strict),
}
_MISFITS = {
    "rectangle": lambda sizes, radius, strict: rectangle_misfit(values.absolute(sizes[0]), values.absolute(sizes[1]), 0.0, radius, strict),
    "circle": lambda sizes, radius, strict: circle_misfit(values.mul(values.absolute(sizes[0]), 2.0), radius, strict),
    "slot": lambda sizes, radius, strict: slot_misfit(values.absolute(sizes[0]), radius, strict),
}


# --------------------------------------------------------------------------- pocket and path-milling contours (CYCLE72-75)

@rule("sinumerik.pocket-contour")
class PocketContour(ReportsMissingContext):
    """CYCLE74/75 contours and the CYCLE73 call (reference A section 6.24, seed L9311-9360,
    L9905-9914, L10703-10775): a contour named (61900), closed contours (61901), G0 to the first
    point, no RND/CHF at the last element, a roughing tool _TN (61984), the stepover at most 80 %
    of the tool diameter (61982), the tool not standing on a contour start point. (Whether a
    CYCLE74 ran before CYCLE73 is not judged: REPEAT of a program section is not modelled.)"""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        name = cycle_name(run) if is_sinumerik(run) else ""
        if name in ("CYCLE74", "CYCLE75"):
            self._contour(run, name, state)
        elif name == "CYCLE73":
            self._machining(run, state)

    def _contour(self, run, name, state):
        facts = run.params.get("CONTOUR")
        span = run.param_spans.get("_KNAME", run.span)
        what = "edge" if name == "CYCLE74" else "island"
        if facts is None:
            self.report("sinumerik.pocket-contour", run.span, f"{name} names no contour (_KNAME, _LSANF and _LSEND empty): would raise alarm 61900 \"no contour\"")
            return
        contours = state.rule_state.get("sinumerik-pocket-contours", []) if name == "CYCLE75" else []
        state.rule_state["sinumerik-pocket-contours"] = [*contours, facts]
        if not facts.found:
            self.missing("sinumerik.pocket-contour", span, contour_not_found(facts, name, what))
            return
        if facts.closed() is None:
            self.missing("sinumerik.pocket-contour", span, contour_points_unknown(facts, name, "whether it is closed (61901)"))
        elif facts.closed() is False:
            (start, _), (end, end_span) = facts.points[0], facts.points[-1]
            self.report("sinumerik.pocket-contour", end_span,
                        f"{name}: the {what} contour \"{facts.name}\" ends at {plane_point(end, state)}, not at its start {plane_point(start, state)}: would raise alarm 61901 \"contour not closed\"")
        if facts.first_motion not in (None, "rapid"):
            self.report("sinumerik.pocket-contour", facts.points[0][1] if facts.points else span,
                        f"{name}: the {what} contour \"{facts.name}\" reaches its first point with {'G1' if facts.first_motion == 'linear' else 'G2/G3'}: "
                        "the first point of a pocket contour is programmed with G0 (seed A L9311-9360)")
        if facts.rounded_end is not None:
            self.report("sinumerik.pocket-contour", facts.rounded_end,
                        f"{name}: the last element of the {what} contour \"{facts.name}\" carries RND/CHF: not allowed in a pocket contour (seed A L9311-9360)")

    def _machining(self, run, state):
        contours = state.rule_state.get("sinumerik-pocket-contours")
        tool_name = run.params.get("_TN")
        if isinstance(tool_name, str) and not tool_name.strip():
            self.report("sinumerik.pocket-contour", run.param_spans.get("_TN", run.span),
                        "CYCLE73: the roughing tool _TN is empty: would raise alarm 61984 \"_TN not defined\"")
        first, second, _normal = state.plane_axes
        here = (state.position.get(first), state.position.get(second))
        for facts in contours or ():
            if facts.points and all(type(value) is float for value in here) and math.dist(here, facts.points[0][0]) < 1e-6:
                self.report("sinumerik.pocket-contour", run.span,
                            f"CYCLE73 called with the tool on the start point {plane_point(facts.points[0][0], state)} of the contour \"{facts.name}\": not allowed (seed A L9311-9360)")
        stepover, radius = run.params.get("_MIDA"), _spindle_tool_radius(self.checker, state)
        if type(stepover) is float and stepover > 0 and radius is None:
            self.missing("sinumerik.pocket-contour", run.param_spans.get("_MIDA", run.span),
                         "no tool radius for the active edge of the tool in the spindle ($TC_DP6[t,d] in the program; [tools.N] radius describes D1): the stepover _MIDA against 80 % of the diameter (61982)")
        elif type(stepover) is float and stepover > 0 and radius and stepover > 0.8 * 2 * radius:
            self.report("sinumerik.pocket-contour", run.param_spans.get("_MIDA", run.span),
                        f"CYCLE73: stepover _MIDA={show(stepover)} is more than 80 % of the diameter {2 * radius:g} of tool T{show(state.tool_in_spindle)} "
                        f"(at most {1.6 * radius:g}): would raise alarm 61982 \"stepover too large\"")


@rule("sinumerik.path-milling-contour")
class PathMillingContour(ReportsMissingContext):
    """CYCLE72's contour (reference A section 6.21, seed L8306-8320): at least two blocks in
    the plane, no G40/G41/G42 inside (the cycle selects the compensation itself), no frame."""

    def cycle_run(self, run, state):
        facts = run.params.get("CONTOUR") if run.cycle == "sinumerik.CYCLE72" else None
        if facts is None:
            return
        span = run.param_spans.get("_KNAME", run.span)
        if not facts.found:
            self.missing("sinumerik.path-milling-contour", span, contour_not_found(facts, "CYCLE72"))
            return
        if facts.plane_blocks < 2:
            self.report("sinumerik.path-milling-contour", span,
                        f"CYCLE72 contour \"{facts.name}\" has {facts.plane_blocks} block{'s' if facts.plane_blocks != 1 else ''} moving in the plane: "
                        "a path-milling contour needs at least two")
        for where in facts.compensation[:1]:
            self.report("sinumerik.path-milling-contour", where,
                        f"CYCLE72 contour \"{facts.name}\" programs G40/G41/G42: not allowed, the cycle selects the compensation from _RL itself")
        for where in facts.frames[:1]:
            self.report("sinumerik.path-milling-contour", where,
                        f"CYCLE72 contour \"{facts.name}\" selects a frame: not allowed in a path-milling contour")


# --------------------------------------------------------------------------- depth and scaling

@rule("sinumerik.milling-depth-sign")
class MillingDepthSign(Rule):
    """Pockets, slots, spigots, face and path milling and engraving with the depth on the
    retract side of the reference plane or on it (reference A section 9 item 3, seed
    L2098-2104): nothing is cut, and the control raises no alarm unless the retract plane
    also lies between them (61101). Holes are judged by the core hole rules."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        name = cycle_name(run) if is_sinumerik(run) else ""
        if run.model.shape != "sinumerik_mill" or name == "CYCLE90" or name not in PLANE_CYCLES | {"CYCLE60", "CYCLE73"}:
            return
        side, _start, depth = levels(run.params)
        rfp = numeric_parameter(run.params, "RFP")
        if side is None or depth is None:
            return
        verdict = self.checker.judge(hazard("<=", values.mul(side, values.sub(rfp, depth)), 0.0), state)
        self.checker.report_verdict("sinumerik.milling-depth-sign", run.param_spans.get("DP", run.param_spans.get("_DP", run.span)),
                                    f"{name}: the depth {show(depth)} is not below the reference plane RFP={show(rfp)} (seen from the retract plane RTP={show(numeric_parameter(run.params, 'RTP'))}): "
                                    "the cycle cuts nothing, or feeds toward the retract plane; was the depth written as a distance instead of a level?",
                                    verdict, state)


_SCALE_ALARMS = {"CYCLE71": ("61011", "scaling not permitted"), "CYCLE72": ("61011", "scaling not permitted"),
                 "CYCLE76": ("61012", "different scaling in the plane"), "CYCLE77": ("61012", "different scaling in the plane")}


@rule("sinumerik.scaled-cycle")
class ScaledCycle(ReportsMissingContext):
    """CYCLE71/72 with a scale factor active (61011) and CYCLE76/77 with different factors
    on the two plane axes (61012) [appendix L19650-19660], from the programmable frame;
    unknown when an entry of the frame is not a number."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        alarm = _SCALE_ALARMS.get(cycle_name(run)) if is_sinumerik(run) else None
        if alarm is None:
            return
        factors = _scale_factors(state.frame)
        if factors is None:
            self.missing("sinumerik.scaled-cycle", run.span,
                         f"the active programmable frame is not known (a solid-angle or symbolic frame): whether {cycle_name(run)} runs scaled "
                         f"(alarm {alarm[0]} \"{alarm[1]}\") is not judged")
            return
        first, second, _normal = state.plane_axes
        if alarm[0] == "61011":
            wrong = {axis: factor for axis, factor in factors.items() if abs(factor - 1.0) > 1e-9}
        else:
            wrong = {axis: factors[axis] for axis in (first, second)} if abs(factors[first] - factors[second]) > 1e-9 else {}
        if wrong:
            scales = ", ".join(f"{axis} {factor:g}" for axis, factor in wrong.items())
            self.report("sinumerik.scaled-cycle", run.span,
                        f"{cycle_name(run)} under a scaling frame ({scales}): would raise alarm {alarm[0]} \"{alarm[1]}\"; cancel SCALE before the call")


def _scale_factors(frame) -> dict | None:
    """The scale factor of each axis of a programmable frame (the length its unit vector is
    mapped to; rotations and mirrors keep 1), or None when an entry is not a number."""
    if frame is None:
        return {axis: 1.0 for axis in AXES}
    columns = list(zip(*frame.linear))
    if any(type(entry) is not float for column in columns for entry in column):
        return None
    return {axis: math.hypot(*column) for axis, column in zip(AXES, columns)}


# --------------------------------------------------------------------------- swivel, high-speed settings, engraving

_RETRACT_MODES = {0, 1, 2, 4, 5}  # _FR, seed A L11133-11158 (4 and 5 from SW 6.5)


@rule("sinumerik.swivel-plane")
class SwivelPlane(Rule):
    """CYCLE800 (reference A section 6.25, seed L10846-10995, L13379-13482): the retract mode
    _FR (61183), the axis-wise rotation coding of _MODE (61184, derived: three different
    axes), G500 active (61189), a tool offset before the first swivel, and a new plane
    (_ST units 0) first in every main program."""

    def cycle_run(self, run, state):
        if run.cycle != "sinumerik.CYCLE800" or run.params.get("ARG_COUNT") == 0.0:
            return
        params, spans = run.params, run.param_spans
        retract, mode, kind = params.get("_FR"), params.get("_MODE"), params.get("_ST")
        if type(retract) is float and retract not in _RETRACT_MODES:
            self.report("sinumerik.swivel-plane", spans.get("_FR", run.span),
                        f"CYCLE800: retract mode _FR={show(retract)} is not 0, 1, 2, 4 or 5: would raise alarm 61183 \"retract mode outside the range\"")
        problem = _swivel_mode_problem(mode) if type(mode) is float else ""
        if problem:
            self.report("sinumerik.swivel-plane", spans.get("_MODE", run.span),
                        f"CYCLE800: _MODE={show(mode)} {problem}: would raise alarm 61184 \"no solution possible with the current angle values\"")
        if state.modal.get("work_offset") == "G500":
            self.report("sinumerik.swivel-plane", run.span, "CYCLE800 with G500 active (no work offset): would raise alarm 61189 \"swivel impossible\"")
        first = self.first_time(state, "sinumerik-swivel")
        if first and type(kind) is float and int(kind) % 10 == 1:
            self.report("sinumerik.swivel-plane", spans.get("_ST", run.span),
                        f"the first CYCLE800 of the program swivels additively (_ST={show(kind)}): it adds to a plane left by an earlier program; "
                        "start every main program with a new plane (_ST units 0)")
        if first and (state.tool_in_spindle == 0.0 or state.rule_state.get("sinumerik-swivel-d0")):
            self.report("sinumerik.swivel-plane", run.span,
                        "the first CYCLE800 of the program runs with no tool offset (no tool or D0): the swivel retracts and turns without the tool length; "
                        "program the tool and D before it (seed A L10846-10850)")

    def change(self, change, state):
        if change.what == "length_offset":
            state.rule_state["sinumerik-swivel-d0"] = change.new == "off"


def _swivel_mode_problem(mode: float) -> str:
    """What is wrong with a CYCLE800 _MODE value, or ''. Bits 7-6 are the angle type; for
    axis-wise angles (00) bits 1-0, 3-2, 5-4 name the axes of the three rotations (1 X, 2 Y,
    3 Z), which must all differ (seed A L11159-11193)."""
    if mode != int(mode) or not 0 <= mode <= 255:
        return "is not a whole number 0-255"
    number = int(mode)
    if number >> 6 == 3:
        return "has the angle type bits 11, which name no angle type"
    if number >> 6 == 0:
        axes = [number >> shift & 3 for shift in (0, 2, 4)]
        if 0 in axes or len(set(axes)) < 3:
            return f"rotates axis-wise about {''.join(' XYZ'[axis] for axis in axes).replace(' ', '-')}: three different axes are needed"
    return ""


# _TOLM digits (seed A L13775-13850): units machining, hundreds transformation, thousands
# G64/G641/G642, ten-thousands FFWON/SOFT/BRISK, hundred-thousands COMPOF/COMPCAD/COMPCURV/B-spline.
_TOLM_DIGITS = {0: {0, 1, 2, 3}, 2: {0, 1, 2}, 3: {0, 1, 2}, 4: {0, 1, 2}, 5: {0, 1, 2, 3}}


@rule("sinumerik.high-speed-settings")
class HighSpeedSettings(Rule):
    """CYCLE832 (reference A section 6.26): a tolerance _TOL that is not positive for a
    machining (not a deselection), _TOLM digits outside their sets, and settings still
    selected at the program end (reference A section 9 item 42: deselect after use)."""

    def cycle_run(self, run, state):
        if run.cycle != "sinumerik.CYCLE832":
            return
        count = run.params.get("ARG_COUNT")
        tolerance, mode = run.params.get("_TOL"), run.params.get("_TOLM", 0.0)
        if count == 0.0 or (count != 1.0 and mode == 0.0):
            state.rule_state.pop("sinumerik-high-speed", None)
            return
        if type(mode) is float and mode % 10 != 0:
            state.rule_state["sinumerik-high-speed"] = run.span
        if type(mode) is float:
            problem = digit_problem(mode, _TOLM_DIGITS)
            if problem:
                self.report("sinumerik.high-speed-settings", run.param_spans.get("_TOLM", run.span), f"CYCLE832: _TOLM={show(mode)}: {problem}")
                return
            if mode % 10 != 0 and type(tolerance) is float and tolerance <= 0:
                self.report("sinumerik.high-speed-settings", run.param_spans.get("_TOL", run.span),
                            f"CYCLE832: tolerance _TOL={show(tolerance)} for {('finishing', 'pre-finishing', 'roughing')[int(mode) % 10 - 1]}: "
                            "the tolerance must be positive (finishing 0.01, roughing 0.1 are the defaults)")

    def change(self, change, state):
        selected = state.rule_state.get("sinumerik-high-speed") if change.what == "end" else None
        if selected is not None:
            self.report("sinumerik.high-speed-settings", selected,
                        "CYCLE832 high-speed settings are still selected at the program end: deselect them with CYCLE832() or CYCLE832(tolerance, 0) "
                        "so the next program does not start with this tolerance, compressor and path mode")


@rule("sinumerik.engraving-text")
class EngravingText(Rule):
    """CYCLE60's text (reference A section 6.27, seed L14364-14379, L14540-14562): at most 91
    characters, letters, digits and the listed specials; else alarm 61179."""

    def cycle_run(self, run, state):
        text = run.params.get("_TEXT") if run.cycle == "sinumerik.CYCLE60" else None
        if not isinstance(text, str):
            return
        span = run.param_spans.get("_TEXT", run.span)
        limit, specials = int(run.model.text_length), run.model.text_specials
        wrong = sorted({character for character in text if not (character.isascii() and character.isalnum()) and character not in specials})
        if len(text) > limit:
            self.report("sinumerik.engraving-text", span,
                        f"CYCLE60: the text has {len(text)} characters, more than {limit}: would raise alarm 61179 \"character does not exist\"")
        elif wrong:
            self.report("sinumerik.engraving-text", span,
                        f"CYCLE60: the text contains {', '.join(repr(character) for character in wrong)}, not in the engraving font: "
                        "would raise alarm 61179 \"character does not exist\"")
