"""SINUMERIK 840D cycle rules: the argument list, the machining-type digits, the
reference planes, the tool against the feature, and the alarms the cycles would raise.

Every cycle run reaches these rules as a :class:`~ncverify.trace.CycleRun` whose params are
the positional arguments by their manual names (``dialects/sinumerik/cycles.toml``), with
``ARG_COUNT`` / ``ARG_OMITTED`` saying how the list was written. Messages carry the alarm
the control would raise, its number and text, and the values involved (references
``sinumerik-840d-a.md`` Appendix A and ``-b.md`` section 11).
"""
from __future__ import annotations

import math

from shapely.geometry import LineString, Point, Polygon

from .. import values
from ..check import Rule, hazard, rule, show
from ..frames import AXES
from ..lower.sinumerik_cycles import COARSE_PITCH, levels
from ..pocket import circle_fit, rectangle_fit, slot_fit
from .machine import _ReportsMissingContext


def _cycle_name(run) -> str:
    return run.cycle.rsplit(".", 1)[-1]


def _is_sinumerik(run) -> bool:
    return run.cycle.startswith("sinumerik.")


def _arguments(run) -> list[tuple[str, str]]:
    return [tuple(argument) for argument in run.model.get("arguments", ())]


# --------------------------------------------------------------------------- argument list

@rule("sinumerik.cycle-arguments")
class CycleArguments(Rule):
    """Too many arguments (alarm 12340) or a string where a number is expected and the
    other way round (alarm 12330), seed A L518-703."""

    def cycle_run(self, run, state):
        if not _is_sinumerik(run):
            return
        name, declared = _cycle_name(run), _arguments(run)
        count = run.params.get("ARG_COUNT", 0.0)
        if type(count) is float and count > len(declared):
            extra = [f"{run.params.get(f'#{index}')!s}" for index in range(len(declared) + 1, int(count) + 1)]
            self.report("sinumerik.cycle-arguments", run.param_spans.get(f"#{len(declared) + 1}", run.span),
                        f"{name} takes {len(declared)} arguments but {int(count)} are given (extra: {', '.join(_shown(value) for value in extra)}): "
                        "would raise alarm 12340 \"too many parameters\"; the cycle is not executed")
        for parameter, kind in declared:
            value = run.params.get(parameter)
            if value is None:
                continue
            wrong = isinstance(value, str) if kind in ("REAL", "INT") else (kind in ("STRING", "CHAR") and not isinstance(value, str) and value != 0.0)
            if wrong:
                self.report("sinumerik.cycle-arguments", run.param_spans.get(parameter, run.span),
                            f"{name}: {parameter} is {kind} but gets {_shown(value)}: would raise alarm 12330 \"parameter type wrong\"; the cycle is not executed")


def _shown(value) -> str:
    return f'"{value}"' if isinstance(value, str) else show(value)


# --------------------------------------------------------------------------- machining type digits

# cycle -> parameter -> {digit position: allowed digits}, the alarm, the seed lines.
_DIGITS = {
    "SLOT1": ("VARI", {0: {0, 1, 2}, 1: {0, 1, 3}}, "A L6040-6057"),
    "SLOT2": ("VARI", {0: {0, 1, 2}, 1: {0, 1}}, "A L6384-6390"),
    "POCKET1": ("VARI", {0: {0, 1, 2}}, "A L6700-6716"),
    "POCKET2": ("VARI", {0: {0, 1, 2}}, "A L6890-6900"),
    "POCKET3": ("_VARI", {0: {1, 2}, 1: {0, 1, 2, 3}}, "A L7327-7330"),
    "POCKET4": ("_VARI", {0: {1, 2}, 1: {0, 1, 2}}, "A L7655-7660"),
    "CYCLE71": ("_VARI", {0: {1, 2}, 1: {1, 2, 3, 4}}, "A L8036-8053"),
    "CYCLE72": ("_VARI", {0: {1, 2}, 1: {0, 1}, 2: {0, 1, 2, 3}}, "A L8386-8388"),
    "CYCLE76": ("_VARI", {0: {1, 2}, 1: {0, 1}}, "A L8800-8840"),
    "CYCLE77": ("_VARI", {0: {1, 2}, 1: {0, 1}}, "A L9060-9085"),
    "CYCLE83": ("VARI", {0: {0, 1}}, "A L2325-2772"),
    "CYCLE95": ("VARI", None, "B L15811-15830, L16218-16222"),
}
_DIGIT_NAMES = ("units", "tens", "hundreds", "thousands", "ten-thousands", "hundred-thousands")


@rule("sinumerik.machining-type")
class MachiningType(Rule):
    """Alarm 61002 "machining type defined incorrectly": a digit of VARI outside its set."""

    def cycle_run(self, run, state):
        entry = _DIGITS.get(_cycle_name(run)) if _is_sinumerik(run) else None
        if entry is None:
            return
        parameter, allowed, seed = entry
        value = run.params.get(parameter)
        if type(value) is not float:
            return
        problem = vari_problem(_cycle_name(run), value)
        if problem:
            self.report("sinumerik.machining-type", run.param_spans.get(parameter, run.span),
                        f"{_cycle_name(run)}: {parameter}={show(value)}: {problem}: would raise alarm 61002 \"machining type defined incorrectly\" (seed {seed})")


def vari_problem(cycle: str, value: float) -> str:
    """What is wrong with a machining-type value, or '' when it is valid."""
    parameter, allowed, _seed = _DIGITS[cycle]
    if allowed is None:  # CYCLE95: 1-12, hundreds digit 0 or 2
        valid = value == int(value) and 1 <= value % 100 <= 12 and value // 100 in (0, 2)
        return "" if valid else "must be 1-12 (or 201-212)"
    return _digit_problem(value, allowed)


def _digit_problem(value: float, allowed: dict) -> str:
    """What is wrong with a number whose decimal digits each select something, or ''."""
    if value != int(value) or value < 0:
        return "not a whole non-negative number"
    number, top = int(value), max(allowed)
    if number >= 10 ** (top + 1):
        return f"has more than {top + 1} digit{'s' if top else ''}"
    for position, digits in allowed.items():
        digit = number // 10 ** position % 10
        if digit not in digits:
            return f"the {_DIGIT_NAMES[position]} digit {digit} is not one of {', '.join(str(d) for d in sorted(digits))}"
    return ""


# --------------------------------------------------------------------------- planes and depth

_PLANE_CYCLES = {"CYCLE81", "CYCLE82", "CYCLE83", "CYCLE84", "CYCLE840", "CYCLE85", "CYCLE86", "CYCLE87", "CYCLE88",
                 "CYCLE89", "CYCLE90", "CYCLE71", "CYCLE72", "SLOT1", "SLOT2", "POCKET1", "POCKET2", "POCKET3",
                 "POCKET4", "LONGHOLE", "CYCLE76", "CYCLE77"}


@rule("sinumerik.reference-plane", "sinumerik.depth-conflict")
class ReferencePlane(Rule):
    """Alarm 61101 (seed A L2139-2146): a relative depth with RTP = RFP, or the retract
    plane lying between the reference plane and the depth. And the message "Depth:
    according to value for relative depth" when DP and DPR disagree (L2127-2134)."""

    def cycle_run(self, run, state):
        name = _cycle_name(run)
        if not _is_sinumerik(run) or name not in _PLANE_CYCLES:
            return
        params = run.params
        rtp, rfp = _number(params, "RTP"), _number(params, "RFP")
        dpr = _number(params, "DPR")
        span = run.param_spans.get("RTP", run.param_spans.get("_RTP", run.span))
        report, judge = self.checker.report_verdict, self.checker.judge
        if type(dpr) is not float or dpr != 0.0:
            report("sinumerik.reference-plane", span,
                   f"{name}: relative depth DPR={show(dpr)} with the retract plane RTP={show(rtp)} equal to the reference plane RFP={show(rfp)}: "
                   "would raise alarm 61101 \"reference plane defined incorrectly\" (give RTP and RFP different values or the depth absolutely)",
                   judge(values.logical("AND", hazard("==", rtp, rfp), hazard("!=", dpr, 0.0)), state), state)
        absolute_only = name in ("POCKET3", "POCKET4", "CYCLE71", "CYCLE72")
        if absolute_only or (type(dpr) is float and dpr == 0.0):
            depth = _number(params, "DP")  # an absolute depth needs no direction: symbolic planes are judged too
        else:
            _side, _start, depth = levels(params)
        if depth is None:
            return
        if name == "CYCLE90" and type(dpr) is float and dpr == 0.0:
            return  # CYCLE90 may thread bottom up with an absolute depth: RFP below, DP and RTP above (seed A L5288-5296)
        behind = hazard("<", values.absolute(values.sub(rtp, depth)), values.absolute(values.sub(rfp, depth)))
        report("sinumerik.reference-plane", span,
               f"{name}: the retract plane RTP={show(rtp)} lies between the reference plane RFP={show(rfp)} and the depth {show(depth)}: "
               "would raise alarm 61101 \"reference plane defined incorrectly\"; the cycle is not executed",
               judge(behind, state), state)
        dp = _number(params, "DP")
        if type(dpr) is float and dpr != 0.0 and type(dp) is float and dp != 0.0 and type(depth) is float and abs(dp - depth) > 1e-9:
            self.report("sinumerik.depth-conflict", run.param_spans.get("DP", run.span),
                        f"{name}: DP={show(dp)} and DPR={show(dpr)} give different depths ({show(dp)} and {show(depth)}): the cycle drills to {show(depth)} "
                        "from the relative depth and shows \"Depth: according to value for relative depth\"")


def _number(params: dict, name: str):
    for key in (name, f"_{name}"):
        value = params.get(key)
        if value is not None and not isinstance(value, str):
            return value
    return 0.0


# --------------------------------------------------------------------------- shifted arguments

# The discrete parameters a dropped or doubled comma moves a wrong value into: cycle ->
# parameter -> allowed values (None: a whole number >= 1).
_DISCRETE = {
    "CYCLE83": {"VARI": {0, 1}, "_AXN": {0, 1, 2, 3}},
    "CYCLE84": {"SDAC": {3, 4, 5}, "_AXN": {0, 1, 2, 3}, "_PTAB": {0, 1, 2, 3}, "_VARI": {0, 1, 2}},
    "CYCLE840": {"SDR": {0, 3, 4}, "ENC": {0, 1, 11, 20}, "_AXN": {0, 1, 2, 3}, "_PTAB": {0, 1, 2, 3}},  # SDAC: only with SDR != 0
    "CYCLE86": {"SDIR": {3, 4}},
    "CYCLE87": {"SDIR": {3, 4}},
    "CYCLE88": {"SDIR": {3, 4}},
    "CYCLE90": {"CDIR": {2, 3}, "TYPTH": {0, 1}},
    "HOLES1": {"NUM": None},
    "HOLES2": {"NUM": None},
    "LONGHOLE": {"NUM": None},
    "SLOT1": {"NUM": None, "CDIR": {0, 1, 2, 3}},
    "SLOT2": {"NUM": None, "CDIR": {2, 3}},
    "POCKET1": {"CDIR": {2, 3}},
    "POCKET2": {"CDIR": {2, 3}},
    "POCKET3": {"_CDIR": {0, 1, 2, 3}},
    "POCKET4": {"_CDIR": {0, 1, 2, 3}},
    "CYCLE72": {"_RL": {40, 41, 42}},
}


def _wrong_positions(cycle: str, names: list[str], values_by_position: list) -> list[int]:
    """Positions of the discrete parameters (and machining-type values) a list of arguments breaks."""
    by_name = dict(zip(names, values_by_position))
    wrong = []
    for parameter, allowed in _DISCRETE.get(cycle, {}).items():
        value = by_name.get(parameter, 0.0)
        if type(value) is not float:
            continue
        if (value < 1 or value != int(value)) if allowed is None else value not in allowed:
            wrong.append(names.index(parameter))
    if cycle in _DIGITS:
        value = by_name.get(_DIGITS[cycle][0], 0.0)
        if type(value) is float and vari_problem(cycle, value):
            wrong.append(names.index(_DIGITS[cycle][0]))
    return wrong


def _violations(cycle: str, names: list[str], values_by_position: list) -> int:
    return len(_wrong_positions(cycle, names, values_by_position))


@rule("sinumerik.shifted-arguments")
class ShiftedArguments(Rule):
    """A dropped or doubled comma moves every later argument one place: the discrete
    parameters then get values outside their sets. When moving the arguments back by one
    place from some position makes every discrete parameter valid, say so."""

    def cycle_run(self, run, state):
        cycle = _cycle_name(run)
        if not _is_sinumerik(run) or cycle not in _DISCRETE:
            return
        names = [name for name, _kind in _arguments(run)]
        count = int(run.params.get("ARG_COUNT", 0.0)) if type(run.params.get("ARG_COUNT")) is float else 0
        written = [run.params.get(names[index] if index < len(names) else f"#{index + 1}", 0.0) for index in range(count)]
        if any(not isinstance(value, float) for value in written):
            return
        broken = _violations(cycle, names, written) + (count > len(names))
        if broken == 0:
            return
        best = None
        first_wrong = min(_wrong_positions(cycle, names, written) or [count])
        for position in range(1, count + 1):
            candidates = [(written[:position] + [0.0] + written[position:], "missing")]
            if position < count and written[position] == 0.0:  # a doubled comma leaves an empty argument
                candidates.append((written[:position] + written[position + 1:], "extra"))
            for shifted, how in candidates:
                if len(shifted) > len(names) and any(value != 0.0 for value in shifted[len(names):]):
                    continue
                if _violations(cycle, names, shifted) == 0:
                    # the shift starts at or before the first parameter that is wrong as written, most likely just before it
                    distance = first_wrong - position if position <= first_wrong else len(names) + position
                    rank = (_implausible_depths(dict(zip(names, shifted))), distance)
                    if best is None or rank < best[0]:
                        best = (rank, position, how, shifted)
        if best is None:
            return
        _rank, position, how, shifted = best
        moved = []
        for index in range(position, min(count, len(names) + 1)):
            value = written[index]
            landed = names[index] if index < len(names) else f"argument {index + 1} (beyond the list)"
            meant_index = index + 1 if how == "missing" else index - 1
            if 0 <= meant_index < len(names) and value != 0.0:
                moved.append(f"{show(value)} landed in {landed}, meant for {names[meant_index]}")
        if not moved:
            return
        where = names[position] if position < len(names) else f"argument {position + 1}"
        comma = "a comma seems to be missing" if how == "missing" else "an extra comma seems to be"
        self.report("sinumerik.shifted-arguments", run.param_spans.get(where, run.span),
                    f"{cycle}: the arguments look shifted by one place: {comma} before {where}. " + "; ".join(moved[:4])
                    + (" ..." if len(moved) > 4 else "") + f". Shifted back by one place every mode parameter is valid; as written {broken} {'is' if broken == 1 else 'are'} out of range")


def _implausible_depths(params: dict) -> int:
    """Soft evidence against a reading of the list: unsigned values that are negative, a
    depth equal to the reference plane, DP and DPR that disagree, planes in alarm order."""
    if "RFP" not in params:
        return 0
    count = sum(params.get(name, 0.0) < 0 for name in ("SDIS", "DPR"))
    side, _start, depth = levels(params)
    if depth is None:
        return count + 1
    rfp, dp, dpr = params["RFP"], params.get("DP", 0.0), params.get("DPR", 0.0)
    count += depth == rfp or (dp != 0.0 and dpr != 0.0 and dp != depth)
    count += abs(params["RTP"] - depth) < abs(rfp - depth)
    return count


# --------------------------------------------------------------------------- patterns

@rule("sinumerik.pattern-without-mcall")
class PatternWithoutModalCall(Rule):
    """HOLES1/HOLES2/CYCLE801 with no MCALL drilling cycle: message 62100, the positions
    are approached without drilling (seed A L4491-4503)."""

    def cycle_run(self, run, state):
        if _is_sinumerik(run) and run.model.get("shape") == "sinumerik_pattern" and state.cycle is None:
            self.report("sinumerik.pattern-without-mcall", run.span,
                        f"{_cycle_name(run)} with no MCALL drilling cycle active: would raise alarm 62100 \"no drilling cycle active\"; "
                        "the positions are approached with G0 and nothing is drilled")


# --------------------------------------------------------------------------- tool against the feature

@rule("sinumerik.cutter-radius")
class CutterRadius(_ReportsMissingContext):
    """Alarm 61105 "cutter radius too large" (POCKET1-4, SLOT1/2, LONGHOLE), 61111 "infeed
    width > tool diameter" (POCKET3/4, CYCLE71), 61117/61112 for a radius the cycle cannot use,
    and a slot tool below half the slot width, from the tool radius in the tool data ($TC_DP6
    in the program or the project's tool table)."""

    def cycle_run(self, run, state):
        cycle = _cycle_name(run)
        if not _is_sinumerik(run) or (cycle not in _FEATURES and cycle not in _RADIUS_SIGN):
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
            self._fit(run, cycle, radius, tool)
        stepover = run.params.get("_MIDA")
        if cycle in ("POCKET3", "POCKET4", "CYCLE71") and type(stepover) is float and stepover > 2 * radius:
            self.report("sinumerik.cutter-radius", run.param_spans.get("_MIDA", run.span),
                        f"{cycle}: stepover _MIDA={show(stepover)} is larger than the tool diameter {2 * radius:g} of {tool}: "
                        "would raise alarm 61111 \"infeed width > tool diameter\"")

    def _fit(self, run, cycle, radius, tool):
        """61105 for a tool too large for the feature; a slot tool below half the width (not checked by the control)."""
        names, fit_of, what = _FEATURES[cycle]
        dimensions = {name: run.params.get(name) for name in names}
        if any(type(value) is not float for value in dimensions.values()):
            return
        fit = fit_of(dimensions, radius)
        span = run.param_spans.get(names[0], run.span)
        if fit is not None and not fit.fits:
            self.report("sinumerik.cutter-radius", span,
                        f"{cycle}: {tool} does not fit the {what}: {fit.reason}; the largest radius that fits is {fit.largest_radius:g}: "
                        "would raise alarm 61105 \"cutter radius too large\"")
        width, kind = dimensions.get("WID"), run.params.get("VARI", 0.0)
        edge_finishing_only = cycle == "SLOT2" and (type(kind) is not float or kind % 10 == 3)
        if cycle in ("SLOT1", "SLOT2") and 0 < 4 * radius < abs(width) and not edge_finishing_only:
            self.report("sinumerik.cutter-radius", span,
                        f"{cycle}: {tool} is less than half the slot width WID={show(width)}: the cycle does not check this and leaves material "
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
            self.missing("sinumerik.cutter-radius", run.span, "no tool radius for the tool in the spindle ($TC_DP6 in the program or [tools.N] radius)")
        return radius


def _spindle_tool_radius(checker, state):
    """The radius of the tool in the spindle from the tool data, or None."""
    tools = checker.context.get("tools") or {}
    number = state.tool_in_spindle
    tool = tools.get(int(number)) if type(number) is float else None
    return None if tool is None else tool.radius


def _rectangle(names):
    return lambda dims, radius: rectangle_fit(abs(dims[names[0]]), abs(dims[names[1]]), abs(dims[names[2]]) if len(names) > 2 else 0.0, radius)


# The alarm for a tool radius the cycle cannot use: 61117 "radius <= 0", 61112 "radius negative" (appendix L19773, L19810).
_RADIUS_SIGN = {"CYCLE71": ("61117", "active tool radius <= 0"), "POCKET3": ("61117", "active tool radius <= 0"),
                "POCKET4": ("61117", "active tool radius <= 0"), "CYCLE72": ("61112", "tool radius negative"),
                "CYCLE76": ("61112", "tool radius negative"), "CYCLE77": ("61112", "tool radius negative"),
                "CYCLE90": ("61112", "tool radius negative")}

# The corner radius and the wall allowance of the pockets whose roughing they limit.
_POCKET_CORNERS_AND_ALLOWANCE = {"POCKET1": ("CRAD", "FAL"), "POCKET2": ("", "FAL"), "POCKET3": ("_CRAD", "_FAL")}

_FEATURES = {
    "POCKET1": (("LENG", "WID", "CRAD"), _rectangle(("LENG", "WID")), "pocket"),
    "POCKET3": (("_LENG", "_WID", "_CRAD"), _rectangle(("_LENG", "_WID")), "pocket"),
    "POCKET2": (("PRAD",), lambda dims, radius: circle_fit(2 * abs(dims["PRAD"]), radius), "circular pocket"),
    "POCKET4": (("_PRAD",), lambda dims, radius: circle_fit(2 * abs(dims["_PRAD"]), radius), "circular pocket"),
    "SLOT1": (("WID",), lambda dims, radius: slot_fit(abs(dims["WID"]), radius, strict=True), "slot"),
    "SLOT2": (("WID",), lambda dims, radius: slot_fit(abs(dims["WID"]), radius, strict=True), "slot"),
    "LONGHOLE": (("LENG",), lambda dims, radius: slot_fit(abs(dims["LENG"]), radius), "elongated hole length"),
}


@rule("sinumerik.no-tool-offset")
class NoToolOffset(Rule):
    """Milling cycles need an active tool offset: alarm 61000 with D0 (POCKET1-4, SLOT1/2,
    LONGHOLE, CYCLE90 and the turning cycles), 61009 with no tool (CYCLE71/72/76/77)."""

    def cycle_run(self, run, state):
        if not _is_sinumerik(run):
            return
        name = _cycle_name(run)
        if run.model.get("needs_tool") and type(state.tool_in_spindle) is float and state.tool_in_spindle == 0.0:
            self.report("sinumerik.no-tool-offset", run.span, f"{name} with tool T0 in the spindle: would raise alarm 61009 \"active tool number = 0\"")
        elif (run.model.get("needs_offset") or run.model.get("needs_tool")) and state.length_mode == "off" and state.rule_state.get("sinumerik-d0"):
            self.report("sinumerik.no-tool-offset", run.span, f"{name} with no tool offset active (D0): would raise alarm 61000 \"no tool compensation active\"")

    def change(self, change, state):
        if change.what == "length_offset":
            state.rule_state["sinumerik-d0"] = change.new == "off"



# --------------------------------------------------------------------------- CYCLE95 contour

@rule("sinumerik.stock-removal-contour")
class StockRemovalContour(_ReportsMissingContext):
    """CYCLE95's contour rules on the contour's own geometry (reference B section 6.3, C2-C13):
    enough plane blocks, only lines and arcs up to 180 degrees, no plane, frame or G41/G42
    inside, G0-G3 in the first block, no G41/G42 at the call, and the start position
    outside the rectangle the contour spans (61607)."""

    def cycle_run(self, run, state):
        facts = run.params.get("CONTOUR") if run.cycle == "sinumerik.CYCLE95" else None
        if facts is None:
            return
        if not facts.found:
            self.missing("sinumerik.stock-removal-contour", run.param_spans.get("NPP", run.span),
                         f"the contour \"{facts.name}\" of CYCLE95 is not in this file or on the subprogram path")
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


# --------------------------------------------------------------------------- threads and turning

@rule("sinumerik.thread-pitch")
class ThreadPitch(Rule):
    """Alarm 61001 "thread pitch wrong": MPIT (a metric thread size) and PIT (a pitch)
    both programmed and contradicting each other (CYCLE84/840 seed A L2950-2953, CYCLE97
    seed B L17056-17062)."""

    def cycle_run(self, run, state):
        name = _cycle_name(run)
        if not _is_sinumerik(run) or name not in ("CYCLE84", "CYCLE840", "CYCLE97"):
            return
        size, pitch = run.params.get("MPIT"), run.params.get("PIT")
        if type(size) is not float or type(pitch) is not float or size == 0.0 or pitch == 0.0:
            return
        coarse = COARSE_PITCH.get(int(abs(size))) if size == int(size) else None
        if coarse is None:
            self.report("sinumerik.thread-pitch", run.param_spans.get("MPIT", run.span),
                        f"{name}: MPIT={show(size)} is not a metric coarse thread size (M3-M48): would raise alarm 61001 \"thread pitch wrong\"")
        elif abs(abs(pitch) - coarse) > 1e-9 or (name != "CYCLE97" and (size > 0) != (pitch > 0)):
            self.report("sinumerik.thread-pitch", run.param_spans.get("PIT", run.span),
                        f"{name}: PIT={show(pitch)} contradicts MPIT={show(size)} (M{abs(size):g} has a pitch of {coarse:g}): "
                        "would raise alarm 61001 \"thread pitch wrong\"; give one of the two")


@rule("sinumerik.undercut-form")
class UndercutForm(Rule):
    """CYCLE94 FORM "E"/"F", CYCLE96 FORM "A"-"D": alarm 61609 (seed B L15612-15618, L16790-16796)."""

    def cycle_run(self, run, state):
        name = _cycle_name(run)
        allowed = {"CYCLE94": ("E", "F"), "CYCLE96": ("A", "B", "C", "D")}.get(name) if _is_sinumerik(run) else None
        if allowed is None:
            return
        form = run.params.get("FORM")
        if not (isinstance(form, str) and form.upper() in allowed):
            self.report("sinumerik.undercut-form", run.param_spans.get("FORM", run.span),
                        f"{name}: FORM {_shown(form)} is not {' or '.join(chr(34) + letter + chr(34) for letter in allowed)}: "
                        "would raise alarm 61609 \"form defined incorrectly\"")


def _contours(run) -> list:
    """The contours a cycle run read (``contours`` in cycles.toml)."""
    return [run.params[key] for key in run.model.get("contours", {}) if run.params.get(key) is not None] if _is_sinumerik(run) else []


@rule("sinumerik.contour-section-runs")
class ContourSectionRuns(Rule):
    """A contour section of the main program (CYCLE95 ``"START:END"``) must be jumped over
    with GOTOF: reached by the normal flow its blocks run as real moves (reference A section 9
    item 15, seed L8580-8590, L9424-9449)."""

    def cycle_run(self, run, state):
        for facts in _contours(run):
            if facts.section_lines is not None:
                sections = state.rule_state.setdefault("sinumerik-contour-sections", [])
                if (*facts.section_lines, _cycle_name(run)) not in sections:
                    sections.append((*facts.section_lines, _cycle_name(run)))

    def segment(self, segment, state):
        if segment.role == "programmed" and segment.span.path is None:
            self._check(segment.span, state)

    def motion_run(self, run, state):
        sections = state.rule_state.get("sinumerik-contour-sections")
        if not sections or run.span(0).path is not None:
            return
        first_line, last_line = run.span(0).line, run.span(len(run) - 1).line
        for first, last, _cycle in sections:
            if first <= last_line and last >= first_line:
                index = next(k for k in range(len(run)) if first <= run.span(k).line <= last)
                self._check(run.span(index), state)

    def _check(self, span, state):
        for first, last, cycle in state.rule_state.get("sinumerik-contour-sections", ()):
            if first <= span.line <= last and self.first_time(state, ("contour-section", first)):
                self.report("sinumerik.contour-section-runs", span,
                            f"the contour section in lines {first}-{last} ({cycle}'s contour) is reached by the program flow: its blocks run as real "
                            "moves at the current height, without compensation; jump over it with GOTOF or put it after M30")


@rule("sinumerik.cycle-not-alone", "sinumerik.retract-inside-clearance")
class CycleBlock(Rule):
    """A cycle call must stand in a block of its own (seed A L527); the retract plane must
    not lie between the reference plane and the safety clearance (reference A section 9
    item 6): every rapid between holes then runs closer to the surface than SDIS."""

    def cycle_run(self, run, state):
        if not _is_sinumerik(run):
            return
        name = _cycle_name(run)
        others = run.params.get("OTHER_WORDS", 0.0)
        if type(others) is float and others > 0 and self.first_time(state, ("cycle-not-alone", run.span)):
            self.report("sinumerik.cycle-not-alone", run.span,
                        f"{name} shares its block with {others:g} other word{'s' if others != 1 else ''}: a cycle call must stand in a block of its own")
        if name not in _PLANE_CYCLES:
            return
        side, start, _depth = levels(run.params)
        rtp = _number(run.params, "RTP")
        if side is None or start is None or (type(start) is float and type(rtp) is float and rtp == start):
            return
        verdict = self.checker.judge(hazard("<", values.mul(side, values.sub(rtp, start)), 0.0), state)
        self.checker.report_verdict("sinumerik.retract-inside-clearance", run.param_spans.get("RTP", run.param_spans.get("_RTP", run.span)),
                                    f"{name}: the retract plane RTP={show(rtp)} lies inside the safety clearance (RFP + SDIS = {show(start)}): "
                                    "the rapids between positions run closer to the surface than the clearance", verdict, state)


@rule("sinumerik.first-depth")
class FirstDrillingDepth(Rule):
    """CYCLE83's first drilling depth (FDEP, or RFP - s*FDPR when FDPR is programmed) must
    lie strictly between RFP + SDIS and the final depth: alarm 61107 (seed A L2532-2535,
    L2561-2564; the exact condition is derived, reference A section 6.3)."""

    def cycle_run(self, run, state):
        if run.cycle != "sinumerik.CYCLE83":
            return
        side, start, depth = levels(run.params)
        fdep, fdpr = run.params.get("FDEP"), run.params.get("FDPR")
        if side is None or depth is None or fdep is None or fdpr is None or isinstance(fdep, str) or isinstance(fdpr, str) or (fdep == 0.0 and fdpr == 0.0):
            return  # a string here is the 12330 of sinumerik.cycle-arguments
        first = fdep if type(fdpr) is float and fdpr == 0.0 else values.sub(_number(run.params, "RFP"), values.mul(side, values.absolute(fdpr)))
        outside = values.logical("OR", hazard(">=", values.mul(side, values.sub(first, start)), 0.0),
                                 hazard("<=", values.mul(side, values.sub(first, depth)), 0.0))
        self.checker.report_verdict("sinumerik.first-depth", run.param_spans.get("FDEP" if fdpr == 0.0 else "FDPR", run.span),
                                    f"CYCLE83: the first drilling depth {show(first)} is not between the start level {show(start)} and the final depth {show(depth)}: "
                                    "would raise alarm 61107 \"first drilling depth defined incorrectly\"", self.checker.judge(outside, state), state)


# --------------------------------------------------------------------------- contours of CYCLE95, CYCLE73-75, CYCLE950

@rule("sinumerik.contour-direction")
class ContourDirection(Rule):
    """CYCLE95 takes its machining direction from the contour's first and last points and
    machines undercuts, but an element that turns back against that direction (an overhang)
    is neither machined nor reported (reference B section 9 items 22 and 24, seed
    L16362-16364, L16422-16426, L16472-16487): the first block must give both plane
    coordinates; longitudinal machining needs a contour monotone along the first plane axis,
    face machining along the second. Judged on the contour's end points."""

    def cycle_run(self, run, state):
        facts = run.params.get("CONTOUR") if run.cycle == "sinumerik.CYCLE95" else None
        if facts is not None and facts.open_start is not None:
            self.report("sinumerik.contour-direction", facts.open_start,
                        f"CYCLE95 contour \"{facts.name}\": the first block moving in the plane does not give both {state.plane_axes[0]} and {state.plane_axes[1]}: "
                        "the contour's start point, from which the cycle takes its machining direction, is not fully programmed")
        kind = run.params.get("VARI")
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


@rule("sinumerik.pocket-contour")
class PocketContour(_ReportsMissingContext):
    """CYCLE74/75 contours and the CYCLE73 call (reference A section 6.24, seed L9311-9360,
    L9905-9914, L10703-10775): a contour named (61900), closed contours (61901), G0 to the first
    point, no RND/CHF at the last element, a roughing tool _TN (61984), the stepover at most 80 %
    of the tool diameter (61982), the tool not standing on a contour start point. (Whether a
    CYCLE74 ran before CYCLE73 is not judged: REPEAT of a program section is not modelled.)"""

    def cycle_run(self, run, state):
        name = _cycle_name(run) if _is_sinumerik(run) else ""
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
            self.missing("sinumerik.pocket-contour", span, f"the {what} contour \"{facts.name}\" of {name} is not in this file or on the subprogram path")
            return
        if facts.closed() is False:
            (start, _), (end, end_span) = facts.points[0], facts.points[-1]
            self.report("sinumerik.pocket-contour", end_span,
                        f"{name}: the {what} contour \"{facts.name}\" ends at {_point(end, state)}, not at its start {_point(start, state)}: would raise alarm 61901 \"contour not closed\"")
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
                            f"CYCLE73 called with the tool on the start point {_point(facts.points[0][0], state)} of the contour \"{facts.name}\": not allowed (seed A L9311-9360)")
        stepover, radius = run.params.get("_MIDA"), _spindle_tool_radius(self.checker, state)
        if type(stepover) is float and stepover > 0 and radius and stepover > 0.8 * 2 * radius:
            self.report("sinumerik.pocket-contour", run.param_spans.get("_MIDA", run.span),
                        f"CYCLE73: stepover _MIDA={show(stepover)} is more than 80 % of the diameter {2 * radius:g} of tool T{show(state.tool_in_spindle)} "
                        f"(at most {1.6 * radius:g}): would raise alarm 61982 \"stepover too large\"")


@rule("sinumerik.path-milling-contour")
class PathMillingContour(_ReportsMissingContext):
    """CYCLE72's contour (reference A section 6.21, seed L8306-8320): at least two blocks in
    the plane, no G40/G41/G42 inside (the cycle selects the compensation itself), no frame."""

    def cycle_run(self, run, state):
        facts = run.params.get("CONTOUR") if run.cycle == "sinumerik.CYCLE72" else None
        if facts is None:
            return
        span = run.param_spans.get("_KNAME", run.span)
        if not facts.found:
            self.missing("sinumerik.path-milling-contour", span, f"the contour \"{facts.name}\" of CYCLE72 is not in this file or on the subprogram path")
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


def _point(point, state) -> str:
    first, second, _normal = state.plane_axes
    return f"{first}{point[0]:g} {second}{point[1]:g}"


@rule("sinumerik.extended-stock-removal")
class ExtendedStockRemoval(_ReportsMissingContext):
    """CYCLE950 (reference B sections 6.8 and 11.3, seed L18265-18273, L18755-18765,
    L19404-19510): a finished contour must be named (61701), a blank contour must be closed
    (61740) and hold the finished contour (61735); neither contour may end with RND/CHF, and
    the two must not run together in the middle of the finished contour (the material to
    remove must be connected)."""

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
                self.missing("sinumerik.extended-stock-removal", run.span, f"the {what} contour \"{facts.name}\" of CYCLE950 is not in this file or on the subprogram path")
            elif facts is not None and facts.rounded_end is not None:
                self.report("sinumerik.extended-stock-removal", facts.rounded_end,
                            f"CYCLE950: the last element of the {what} contour \"{facts.name}\" carries RND/CHF: not allowed (seed B L18265-18273)")
        if blank is None or not blank.found or not blank.points:
            return
        if not blank.closed():
            (start, _), (end, end_span) = blank.points[0], blank.points[-1]
            self.report("sinumerik.extended-stock-removal", end_span,
                        f"CYCLE950: the blank contour \"{blank.name}\" ends at {_point(end, state)}, not at its start {_point(start, state)}: would raise alarm 61740 \"blank must be a closed contour\"")
        elif finished.found and finished.points and len(blank.points) >= 4:
            self._finished_against_blank(finished, blank, state)

    def _finished_against_blank(self, finished, blank, state):
        outline = Polygon([point for point, _span in blank.points])
        inside = outline.buffer(1e-6)
        outside = next(((point, span) for point, span in finished.points if not inside.covers(Point(point))), None)
        if outside is not None:
            self.report("sinumerik.extended-stock-removal", outside[1],
                        f"CYCLE950: the finished contour \"{finished.name}\" reaches {_point(outside[0], state)}, outside the blank contour \"{blank.name}\": "
                        "would raise alarm 61735 \"finished part lies outside the blank contour\"")
            return
        edge = outline.exterior.buffer(1e-6)
        inner = list(zip(finished.points[1:-2], finished.points[2:-1]))
        shared = next(((start, end, span) for (start, _), (end, span) in inner if math.dist(start, end) > 1e-6 and edge.covers(LineString([start, end]))), None)
        if shared is not None:
            self.report("sinumerik.extended-stock-removal", shared[2],
                        f"CYCLE950: the finished contour \"{finished.name}\" runs along the blank contour \"{blank.name}\" from {_point(shared[0], state)} "
                        f"to {_point(shared[1], state)}: the material to remove is split in two; the contours must not coincide piecewise (seed B L18755-18765)")


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
            problem = _digit_problem(mode, _TOLM_DIGITS)
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


# _TECHNO digits (seed A L2774-3131 tables, 61125 appendix L19826): CYCLE84 units exact stop
# 0-3, tens feedforward 0-2, hundreds acceleration 0-3, thousands spindle mode 0-1; CYCLE840
# units 0-3, tens 0-2, hundreds braking point 0-1.
_TECHNOLOGY_DIGITS = {"CYCLE84": {0: {0, 1, 2, 3}, 1: {0, 1, 2}, 2: {0, 1, 2, 3}, 3: {0, 1}},
                      "CYCLE840": {0: {0, 1, 2, 3}, 1: {0, 1, 2}, 2: {0, 1}}}


@rule("sinumerik.technology-digits")
class TechnologyDigits(Rule):
    """CYCLE84/840 _TECHNO: a digit outside its set raises alarm 61125."""

    def cycle_run(self, run, state):
        allowed = _TECHNOLOGY_DIGITS.get(_cycle_name(run)) if _is_sinumerik(run) else None
        value = run.params.get("_TECHNO") if allowed else None
        problem = _digit_problem(value, allowed) if type(value) is float else ""
        if problem:
            self.report("sinumerik.technology-digits", run.param_spans.get("_TECHNO", run.span),
                        f"{_cycle_name(run)}: _TECHNO={show(value)}: {problem}: would raise alarm 61125 \"technology selection in _TECHNO wrong\"")


@rule("sinumerik.engraving-text")
class EngravingText(Rule):
    """CYCLE60's text (reference A section 6.27, seed L14364-14379, L14540-14562): at most 91
    characters, letters, digits and the listed specials; else alarm 61179."""

    def cycle_run(self, run, state):
        text = run.params.get("_TEXT") if run.cycle == "sinumerik.CYCLE60" else None
        if not isinstance(text, str):
            return
        span = run.param_spans.get("_TEXT", run.span)
        limit, specials = int(run.model["text_length"]), run.model["text_specials"]
        wrong = sorted({character for character in text if not (character.isascii() and character.isalnum()) and character not in specials})
        if len(text) > limit:
            self.report("sinumerik.engraving-text", span,
                        f"CYCLE60: the text has {len(text)} characters, more than {limit}: would raise alarm 61179 \"character does not exist\"")
        elif wrong:
            self.report("sinumerik.engraving-text", span,
                        f"CYCLE60: the text contains {', '.join(repr(character) for character in wrong)}, not in the engraving font: "
                        "would raise alarm 61179 \"character does not exist\"")


# --------------------------------------------------------------------------- the spindle at the call

# cycle -> the direction parameter whose values 0/1 (climb, conventional) take G2/G3 from the
# running spindle (seed A L5973-5990), or None: the cycle always takes the spindle's direction
# (CYCLE840 L3475-3476, CYCLE97/98 thread hand B L16967-16991, L17483-17489).
_SPINDLE_SETS_DIRECTION = {"SLOT1": "CDIR", "POCKET3": "_CDIR", "POCKET4": "_CDIR", "CYCLE73": "_CDIR", "CYCLE76": "_CDIR",
                           "CYCLE77": "_CDIR", "CYCLE840": None, "CYCLE97": None, "CYCLE98": None}


@rule("sinumerik.spindle-at-cycle")
class SpindleAtCycle(Rule):
    """A cycle that takes its direction from the running spindle (climb or conventional
    milling with CDIR 0/1, tapping with a compensating chuck, thread turning) called with the
    spindle stopped."""

    def cycle_run(self, run, state):
        name = _cycle_name(run) if _is_sinumerik(run) else ""
        if name not in _SPINDLE_SETS_DIRECTION or state.spindle != "off":
            return
        parameter = _SPINDLE_SETS_DIRECTION[name]
        direction = run.params.get(parameter, 0.0) if parameter else None
        if parameter and direction not in (0.0, 1.0):
            return
        what = (f"{parameter}={show(direction)} ({'climb' if direction == 0.0 else 'conventional'} milling) takes G2 or G3 from M3/M4"
                if parameter else "the cycle takes the direction of the thread from M3/M4")
        self.report("sinumerik.spindle-at-cycle", run.param_spans.get(parameter, run.span) if parameter else run.span,
                    f"{name} with the spindle stopped: {what}; program M3 or M4 before the call")


@rule("sinumerik.undercut-feed")
class UndercutFeed(Rule):
    """CYCLE94 and CYCLE96 cut the undercut at the feed programmed before the call (reference
    B section 9 item 42, seed L15570-15572, L16732-16734): there must be one."""

    def cycle_run(self, run, state):
        if run.cycle not in ("sinumerik.CYCLE94", "sinumerik.CYCLE96"):
            return
        feed = state.feed
        if feed is None and not state.feed_inherited:
            self.report("sinumerik.undercut-feed", run.span,
                        f"{_cycle_name(run)} with no feed programmed: the cycle cuts the undercut at the F active before the call; program F (G95 mm/rev) before it")
        elif feed is not None:
            self.checker.report_verdict("sinumerik.undercut-feed", run.span,
                                        f"{_cycle_name(run)} at feed F{show(feed)}: the cycle cuts the undercut at this F, which does not move the axes",
                                        self.checker.judge(hazard("<=", feed, 0.0), state), state)


# --------------------------------------------------------------------------- frames at the call

_SCALE_ALARMS = {"CYCLE71": ("61011", "scaling not permitted"), "CYCLE72": ("61011", "scaling not permitted"),
                 "CYCLE76": ("61012", "different scaling in the plane"), "CYCLE77": ("61012", "different scaling in the plane")}


@rule("sinumerik.scaled-cycle")
class ScaledCycle(Rule):
    """CYCLE71/72 with a scale factor active (61011) and CYCLE76/77 with different factors
    on the two plane axes (61012) [appendix L19650-19660], from the programmable frame."""

    def cycle_run(self, run, state):
        alarm = _SCALE_ALARMS.get(_cycle_name(run)) if _is_sinumerik(run) else None
        factors = _scale_factors(state.frame) if alarm else None
        if factors is None:
            return
        first, second, _normal = state.plane_axes
        if alarm[0] == "61011":
            wrong = {axis: factor for axis, factor in factors.items() if abs(factor - 1.0) > 1e-9}
        else:
            wrong = {axis: factors[axis] for axis in (first, second)} if abs(factors[first] - factors[second]) > 1e-9 else {}
        if wrong:
            scales = ", ".join(f"{axis} {factor:g}" for axis, factor in wrong.items())
            self.report("sinumerik.scaled-cycle", run.span,
                        f"{_cycle_name(run)} under a scaling frame ({scales}): would raise alarm {alarm[0]} \"{alarm[1]}\"; cancel SCALE before the call")


def _scale_factors(frame) -> dict | None:
    """The scale factor of each axis of a programmable frame (the length its unit vector is
    mapped to; rotations and mirrors keep 1), or None when an entry is not a number."""
    if frame is None:
        return {axis: 1.0 for axis in AXES}
    columns = list(zip(*frame.linear))
    if any(type(entry) is not float for column in columns for entry in column):
        return None
    return {axis: math.hypot(*column) for axis, column in zip(AXES, columns)}


@rule("sinumerik.groove-dwell")
class GrooveDwell(Rule):
    """CYCLE93's dwell DTB at the groove base should last at least one spindle revolution
    (reference B section 9 item 29, seed L15201-15205): judged under G97, where the speed S
    is the revolutions per minute."""

    def cycle_run(self, run, state):
        dwell = run.params.get("DTB") if run.cycle == "sinumerik.CYCLE93" else None
        speed = state.spindle_speed
        if type(dwell) is not float or dwell <= 0 or state.modal.get("spindle_mode") != "rpm" or type(speed) is not float or speed <= 0:
            return
        revolution = 60.0 / speed
        if dwell < revolution:
            self.report("sinumerik.groove-dwell", run.param_spans.get("DTB", run.span),
                        f"CYCLE93: dwell DTB={show(dwell)} s is shorter than one revolution at S{show(speed)} ({revolution:.3g} s): "
                        "the groove base is not cut round; dwell at least one revolution")


@rule("sinumerik.thread-mill-bore")
class ThreadMillBore(Rule):
    """An internal thread milled with CYCLE90 runs beyond the thread by its lead-in, at least
    half a pitch (reference A section 9 item 36, seed L5305-5316: a thread from -20 to 0 with
    pitch 3 needs the bore down to -21.5). A bore drilled earlier in the program at the
    thread's centre must reach that far."""

    def hole(self, hole, state):
        first, second, _normal = state.plane_axes
        place = (hole.position.get(first), hole.position.get(second), hole.bottom)
        if hole.cycle.startswith("sinumerik.") and all(type(value) is float for value in place):
            state.rule_state["sinumerik-bores"] = [*state.rule_state.get("sinumerik-bores", ()), (*place, hole.span)]

    def cycle_run(self, run, state):
        if run.cycle != "sinumerik.CYCLE90" or run.params.get("TYPTH", 0.0) != 0.0:
            return
        side, _start, depth = levels(run.params)
        rfp, pitch, x, y = (run.params.get(name, 0.0) for name in ("RFP", "PIT", "CPA", "CPO"))
        if side != 1.0 or any(type(value) is not float for value in (depth, rfp, pitch, x, y)):
            return
        needed = min(rfp, depth) - abs(pitch) / 2
        axis = state.plane_axes[2]
        for bore_x, bore_y, bottom, span in state.rule_state.get("sinumerik-bores", ()):
            if math.dist((bore_x, bore_y), (x, y)) < 1e-6 and bottom > needed + 1e-9:
                self.report("sinumerik.thread-mill-bore", run.span,
                            f"CYCLE90: the bore drilled in line {span.line} ends at {axis}{bottom:g}, but the thread from {axis}{rfp:g} to {axis}{depth:g} "
                            f"with pitch {abs(pitch):g} is milled down to {axis}{needed:g} at least (half a pitch beyond it): the cutter runs into the bottom of the bore")
                return


@rule("sinumerik.start-below-surface")
class StartBelowSurface(Rule):
    """Drilling cycles start with the tool already over the hole and only then move along
    the tool axis; milling cycles rapid to their start point at RTP from where the tool is
    (reference A section 9 item 7, seed L2072-2076). A tool standing beyond the reference
    plane RFP when the cycle is called got there by a positioning move under the surface."""

    def cycle_run(self, run, state):
        if not _is_sinumerik(run) or run.model.get("shape") not in ("sinumerik_drill", "sinumerik_mill"):
            return
        side, _start, _depth = levels(run.params)
        axis = state.plane_axes[2]
        here, rfp, rtp = state.position.get(axis), _number(run.params, "RFP"), _number(run.params, "RTP")
        if side is None or any(type(value) is not float for value in (here, rfp, rtp)) or side * (here - rfp) >= 0:
            return
        self.report("sinumerik.start-below-surface", run.span,
                    f"{_cycle_name(run)} starts with the tool at {axis}{here:g}, beyond the reference plane RFP={rfp:g} (retract plane RTP={rtp:g}): "
                    "the move that brought it over this position ran under the surface; position at RTP first")


@rule("sinumerik.milling-depth-sign")
class MillingDepthSign(Rule):
    """Pockets, slots, spigots, face and path milling and engraving with the depth on the
    retract side of the reference plane or on it (reference A section 9 item 3, seed
    L2098-2104): nothing is cut, and the control raises no alarm unless the retract plane
    also lies between them (61101). Holes are judged by the core hole rules."""

    def cycle_run(self, run, state):
        name = _cycle_name(run) if _is_sinumerik(run) else ""
        if run.model.get("shape") != "sinumerik_mill" or name == "CYCLE90" or name not in _PLANE_CYCLES | {"CYCLE60", "CYCLE73"}:
            return
        side, _start, depth = levels(run.params)
        rfp = _number(run.params, "RFP")
        if side is None or depth is None:
            return
        verdict = self.checker.judge(hazard("<=", values.mul(side, values.sub(rfp, depth)), 0.0), state)
        self.checker.report_verdict("sinumerik.milling-depth-sign", run.param_spans.get("DP", run.param_spans.get("_DP", run.span)),
                                    f"{name}: the depth {show(depth)} is not below the reference plane RFP={show(rfp)} (seen from the retract plane RTP={show(_number(run.params, 'RTP'))}): "
                                    "the cycle cuts nothing, or feeds toward the retract plane; was the depth written as a distance instead of a level?",
                                    verdict, state)
