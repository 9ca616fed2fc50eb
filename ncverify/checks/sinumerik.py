"""SINUMERIK 840D cycle rules shared by every technology: the argument list, the
machining-type digits, the reference planes, the cycle block, drilling, tapping and hole
patterns, the tool and spindle at the call, and contour sections in the program flow.
The milling rules are in :mod:`.sinumerik_milling`, the turning rules in
:mod:`.sinumerik_turning`; both use the helpers here.

Every cycle run reaches these rules as a :class:`~ncverify.trace.CycleRun` whose params are
the positional arguments by their manual names (``dialects/sinumerik/cycles.toml``), with
``ARG_COUNT`` / ``ARG_OMITTED`` saying how the list was written. Messages carry the alarm
the control would raise, its number and text, and the values involved (references
``sinumerik-840d-a.md`` Appendix A and ``-b.md`` section 11).
"""
from __future__ import annotations

import math

from ..ir import cycle_code
from .. import values
from ..check import Rule, hazard, rule, show
from ..interpret.sinumerik_cycles import COARSE_PITCH, levels
from .. import modelled


def cycle_name(run) -> str:
    return cycle_code(run.cycle)


def is_sinumerik(run) -> bool:
    return run.cycle.startswith("sinumerik.")


def _arguments(run) -> list[tuple[str, str]]:
    return [tuple(argument) for argument in run.model.arguments]


# --------------------------------------------------------------------------- argument list

@rule("sinumerik.cycle-arguments")
class CycleArguments(Rule):
    """Too many arguments (alarm 12340) or a string where a number is expected and the
    other way round (alarm 12330), seed A L518-703."""

    def cycle_run(self, run, state):
        if not is_sinumerik(run):
            return
        name, declared = cycle_name(run), _arguments(run)
        count = run.params.get("ARG_COUNT", 0.0)
        if type(count) is float and count > len(declared):
            extra = [f"{run.params.get(f'#{index}')!s}" for index in range(len(declared) + 1, int(count) + 1)]
            self.report("sinumerik.cycle-arguments", run.param_spans.get(f"#{len(declared) + 1}", run.span),
                        f"{name} takes {len(declared)} arguments but {int(count)} are given (extra: {', '.join(quoted(value) for value in extra)}): "
                        "would raise alarm 12340 \"too many parameters\"; the cycle is not executed")
        for parameter, kind in declared:
            value = run.params.get(parameter)
            if value is None:
                continue
            wrong = isinstance(value, str) if kind in ("REAL", "INT") else (kind in ("STRING", "CHAR") and not isinstance(value, str) and value != 0.0)
            if wrong:
                self.report("sinumerik.cycle-arguments", run.param_spans.get(parameter, run.span),
                            f"{name}: {parameter} is {kind} but gets {quoted(value)}: would raise alarm 12330 \"parameter type wrong\"; the cycle is not executed")


def quoted(value) -> str:
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
        entry = _DIGITS.get(cycle_name(run)) if is_sinumerik(run) else None
        if entry is None:
            return
        parameter, allowed, seed = entry
        value = run.params.get(parameter)
        if type(value) is not float:
            return
        problem = vari_problem(cycle_name(run), value)
        if problem:
            self.report("sinumerik.machining-type", run.param_spans.get(parameter, run.span),
                        f"{cycle_name(run)}: {parameter}={show(value)}: {problem}: would raise alarm 61002 \"machining type defined incorrectly\" (seed {seed})")


def vari_problem(cycle: str, value: float) -> str:
    """What is wrong with a machining-type value, or '' when it is valid."""
    parameter, allowed, _seed = _DIGITS[cycle]
    if allowed is None:  # CYCLE95: 1-12, hundreds digit 0 or 2
        valid = value == int(value) and 1 <= value % 100 <= 12 and value // 100 in (0, 2)
        return "" if valid else "must be 1-12 (or 201-212)"
    return digit_problem(value, allowed)


def digit_problem(value: float, allowed: dict) -> str:
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

PLANE_CYCLES = {"CYCLE81", "CYCLE82", "CYCLE83", "CYCLE84", "CYCLE840", "CYCLE85", "CYCLE86", "CYCLE87", "CYCLE88",
                 "CYCLE89", "CYCLE90", "CYCLE71", "CYCLE72", "SLOT1", "SLOT2", "POCKET1", "POCKET2", "POCKET3",
                 "POCKET4", "LONGHOLE", "CYCLE76", "CYCLE77"}


@rule("sinumerik.reference-plane", "sinumerik.depth-conflict")
class ReferencePlane(Rule):
    """Alarm 61101 (seed A L2139-2146): a relative depth with RTP = RFP, or the retract
    plane lying between the reference plane and the depth. And the message "Depth:
    according to value for relative depth" when DP and DPR disagree (L2127-2134)."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        name = cycle_name(run)
        if not is_sinumerik(run) or name not in PLANE_CYCLES:
            return
        params = run.params
        rtp, rfp = numeric_parameter(params, "RTP"), numeric_parameter(params, "RFP")
        dpr = numeric_parameter(params, "DPR")
        span = run.param_spans.get("RTP", run.param_spans.get("_RTP", run.span))
        report, judge = self.checker.report_verdict, self.checker.judge
        if type(dpr) is not float or dpr != 0.0:
            report("sinumerik.reference-plane", span,
                   f"{name}: relative depth DPR={show(dpr)} with the retract plane RTP={show(rtp)} equal to the reference plane RFP={show(rfp)}: "
                   "would raise alarm 61101 \"reference plane defined incorrectly\" (give RTP and RFP different values or the depth absolutely)",
                   judge(values.logical("AND", hazard("==", rtp, rfp), hazard("!=", dpr, 0.0)), state), state)
        absolute_only = name in ("POCKET3", "POCKET4", "CYCLE71", "CYCLE72")
        if absolute_only or (type(dpr) is float and dpr == 0.0):
            depth = numeric_parameter(params, "DP")  # an absolute depth needs no direction: symbolic planes are judged too
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
        dp = numeric_parameter(params, "DP")
        if type(dpr) is float and dpr != 0.0 and type(dp) is float and dp != 0.0 and type(depth) is float and abs(dp - depth) > 1e-9:
            self.report("sinumerik.depth-conflict", run.param_spans.get("DP", run.span),
                        f"{name}: DP={show(dp)} and DPR={show(dpr)} give different depths ({show(dp)} and {show(depth)}): the cycle drills to {show(depth)} "
                        "from the relative depth and shows \"Depth: according to value for relative depth\"")


def numeric_parameter(params: dict, name: str):
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
        cycle = cycle_name(run)
        if not is_sinumerik(run) or cycle not in _DISCRETE:
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


# --------------------------------------------------------------------------- the cycle block and the start position

@rule("sinumerik.cycle-not-alone", "sinumerik.retract-inside-clearance")
class CycleBlock(Rule):
    """A cycle call must stand in a block of its own (seed A L527); the retract plane must
    not lie between the reference plane and the safety clearance (reference A section 9
    item 6): every rapid between holes then runs closer to the surface than SDIS."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        if not is_sinumerik(run):
            return
        name = cycle_name(run)
        others = run.params.get("OTHER_WORDS", 0.0)
        if type(others) is float and others > 0 and self.first_time(state, ("cycle-not-alone", run.span)):
            self.report("sinumerik.cycle-not-alone", run.span,
                        f"{name} shares its block with {others:g} other word{'s' if others != 1 else ''}: a cycle call must stand in a block of its own")
        if name not in PLANE_CYCLES:
            return
        side, start, _depth = levels(run.params)
        rtp = numeric_parameter(run.params, "RTP")
        if side is None or start is None or (type(start) is float and type(rtp) is float and rtp == start):
            return
        verdict = self.checker.judge(hazard("<", values.mul(side, values.sub(rtp, start)), 0.0), state)
        self.checker.report_verdict("sinumerik.retract-inside-clearance", run.param_spans.get("RTP", run.param_spans.get("_RTP", run.span)),
                                    f"{name}: the retract plane RTP={show(rtp)} lies inside the safety clearance (RFP + SDIS = {show(start)}): "
                                    "the rapids between positions run closer to the surface than the clearance", verdict, state)


@rule("sinumerik.start-below-surface")
class StartBelowSurface(Rule):
    """Drilling cycles start with the tool already over the hole and only then move along
    the tool axis; milling cycles rapid to their start point at RTP from where the tool is
    (reference A section 9 item 7, seed L2072-2076). A tool standing beyond the reference
    plane RFP when the cycle is called got there by a positioning move under the surface."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        if not is_sinumerik(run) or run.model.shape not in ("sinumerik_drill", "sinumerik_mill"):
            return
        side, _start, _depth = levels(run.params)
        axis = state.plane_axes[2]
        here, rfp, rtp = state.position.get(axis), numeric_parameter(run.params, "RFP"), numeric_parameter(run.params, "RTP")
        if side is None or any(type(value) is not float for value in (here, rfp, rtp)) or side * (here - rfp) >= 0:
            return
        self.report("sinumerik.start-below-surface", run.span,
                    f"{cycle_name(run)} starts with the tool at {axis}{here:g}, beyond the reference plane RFP={rfp:g} (retract plane RTP={rtp:g}): "
                    "the move that brought it over this position ran under the surface; position at RTP first")


# --------------------------------------------------------------------------- drilling, tapping and patterns

@rule("sinumerik.pattern-without-mcall")
class PatternWithoutModalCall(Rule):
    """HOLES1/HOLES2/CYCLE801 with no MCALL drilling cycle: message 62100, the positions
    are approached without drilling (seed A L4491-4503)."""

    def cycle_run(self, run, state):
        if is_sinumerik(run) and run.model.shape == "sinumerik_pattern" and state.cycle is None:
            self.report("sinumerik.pattern-without-mcall", run.span,
                        f"{cycle_name(run)} with no MCALL drilling cycle active: would raise alarm 62100 \"no drilling cycle active\"; "
                        "the positions are approached with G0 and nothing is drilled")


@rule("sinumerik.first-depth")
class FirstDrillingDepth(Rule):
    """CYCLE83's first drilling depth (FDEP, or RFP - s*FDPR when FDPR is programmed) must
    lie strictly between RFP + SDIS and the final depth: alarm 61107 (seed A L2532-2535,
    L2561-2564; the exact condition is derived, reference A section 6.3)."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        if run.cycle != "sinumerik.CYCLE83":
            return
        side, start, depth = levels(run.params)
        fdep, fdpr = run.params.get("FDEP"), run.params.get("FDPR")
        if side is None or depth is None or fdep is None or fdpr is None or isinstance(fdep, str) or isinstance(fdpr, str) or (fdep == 0.0 and fdpr == 0.0):
            return  # a string here is the 12330 of sinumerik.cycle-arguments
        first = fdep if type(fdpr) is float and fdpr == 0.0 else values.sub(numeric_parameter(run.params, "RFP"), values.mul(side, values.absolute(fdpr)))
        outside = values.logical("OR", hazard(">=", values.mul(side, values.sub(first, start)), 0.0),
                                 hazard("<=", values.mul(side, values.sub(first, depth)), 0.0))
        self.checker.report_verdict("sinumerik.first-depth", run.param_spans.get("FDEP" if fdpr == 0.0 else "FDPR", run.span),
                                    f"CYCLE83: the first drilling depth {show(first)} is not between the start level {show(start)} and the final depth {show(depth)}: "
                                    "would raise alarm 61107 \"first drilling depth defined incorrectly\"", self.checker.judge(outside, state), state)


@rule("sinumerik.thread-pitch")
class ThreadPitch(Rule):
    """Alarm 61001 "thread pitch wrong": MPIT (a metric thread size) and PIT (a pitch)
    both programmed and contradicting each other (CYCLE84/840 seed A L2950-2953, CYCLE97
    seed B L17056-17062)."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        name = cycle_name(run)
        if not is_sinumerik(run) or name not in ("CYCLE84", "CYCLE840", "CYCLE97"):
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


# _TECHNO digits (seed A L2774-3131 tables, 61125 appendix L19826): CYCLE84 units exact stop
# 0-3, tens feedforward 0-2, hundreds acceleration 0-3, thousands spindle mode 0-1; CYCLE840
# units 0-3, tens 0-2, hundreds braking point 0-1.
_TECHNOLOGY_DIGITS = {"CYCLE84": {0: {0, 1, 2, 3}, 1: {0, 1, 2}, 2: {0, 1, 2, 3}, 3: {0, 1}},
                      "CYCLE840": {0: {0, 1, 2, 3}, 1: {0, 1, 2}, 2: {0, 1}}}


@rule("sinumerik.technology-digits")
class TechnologyDigits(Rule):
    """CYCLE84/840 _TECHNO: a digit outside its set raises alarm 61125."""

    def cycle_run(self, run, state):
        allowed = _TECHNOLOGY_DIGITS.get(cycle_name(run)) if is_sinumerik(run) else None
        value = run.params.get("_TECHNO") if allowed else None
        problem = digit_problem(value, allowed) if type(value) is float else ""
        if problem:
            self.report("sinumerik.technology-digits", run.param_spans.get("_TECHNO", run.span),
                        f"{cycle_name(run)}: _TECHNO={show(value)}: {problem}: would raise alarm 61125 \"technology selection in _TECHNO wrong\"")


@rule("sinumerik.thread-mill-bore")
class ThreadMillBore(Rule):
    """An internal thread milled with CYCLE90 runs beyond the thread by its lead-in, at least
    half a pitch (reference A section 9 item 36, seed L5305-5316: a thread from -20 to 0 with
    pitch 3 needs the bore down to -21.5). A bore drilled earlier in the program at the
    thread's centre must reach that far."""
    reads = modelled.AS_WRITTEN

    def hole(self, hole, state):
        first, second, _normal = state.plane_axes
        place = (hole.position.get(first), hole.position.get(second), hole.bottom)
        if hole.cycle.startswith("sinumerik.") and all(type(value) is float for value in place):
            # (bore, the bores before it): one more bore costs one pair, not a copy of all the
            # others (a post drills thousands), and forked paths share what came before
            state.rule_state["sinumerik-bores"] = ((*place, hole.span), state.rule_state.get("sinumerik-bores"))

    def cycle_run(self, run, state):
        if run.cycle != "sinumerik.CYCLE90" or run.params.get("TYPTH", 0.0) != 0.0:
            return
        side, _start, depth = levels(run.params)
        rfp, pitch, x, y = (run.params.get(name, 0.0) for name in ("RFP", "PIT", "CPA", "CPO"))
        if side != 1.0 or any(type(value) is not float for value in (depth, rfp, pitch, x, y)):
            return
        needed = min(rfp, depth) - abs(pitch) / 2
        axis = state.plane_axes[2]
        for bore_x, bore_y, bottom, span in _first_to_last(state.rule_state.get("sinumerik-bores")):
            if math.dist((bore_x, bore_y), (x, y)) < 1e-6 and bottom > needed + 1e-9:
                self.report("sinumerik.thread-mill-bore", run.span,
                            f"CYCLE90: the bore drilled in line {span.line} ends at {axis}{bottom:g}, but the thread from {axis}{rfp:g} to {axis}{depth:g} "
                            f"with pitch {abs(pitch):g} is milled down to {axis}{needed:g} at least (half a pitch beyond it): the cutter runs into the bottom of the bore")
                return


# --------------------------------------------------------------------------- tool and spindle at the call

def _first_to_last(chain) -> list:
    """The entries of a chain of (entry, the chain before it) pairs, the first one first."""
    entries = []
    while chain is not None:
        entry, chain = chain
        entries.append(entry)
    return entries[::-1]


@rule("sinumerik.no-tool-offset")
class NoToolOffset(Rule):
    """Milling cycles need an active tool offset: alarm 61000 with D0 (POCKET1-4, SLOT1/2,
    LONGHOLE, CYCLE90 and the turning cycles), 61009 with no tool (CYCLE71/72/76/77)."""

    def cycle_run(self, run, state):
        if not is_sinumerik(run):
            return
        name = cycle_name(run)
        if run.model.needs_tool and type(state.tool_in_spindle) is float and state.tool_in_spindle == 0.0:
            self.report("sinumerik.no-tool-offset", run.span, f"{name} with tool T0 in the spindle: would raise alarm 61009 \"active tool number = 0\"")
        elif (run.model.needs_offset or run.model.needs_tool) and state.length_mode == "off" and state.rule_state.get("sinumerik-d0"):
            self.report("sinumerik.no-tool-offset", run.span, f"{name} with no tool offset active (D0): would raise alarm 61000 \"no tool compensation active\"")

    def change(self, change, state):
        if change.what == "length_offset":
            state.rule_state["sinumerik-d0"] = change.new == "off"


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
        name = cycle_name(run) if is_sinumerik(run) else ""
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


# --------------------------------------------------------------------------- contours

def _contours(run) -> list:
    """The contours a cycle run read (``contours`` in cycles.toml)."""
    return [run.params[key] for key in run.model.contours if run.params.get(key) is not None] if is_sinumerik(run) else []


@rule("sinumerik.contour-section-runs")
class ContourSectionRuns(Rule):
    """A contour section of the main program (CYCLE95 ``"START:END"``) must be jumped over
    with GOTOF: reached by the normal flow its blocks run as real moves (reference A section 9
    item 15, seed L8580-8590, L9424-9449)."""

    handles_arcs = True  # any move, arcs too

    def cycle_run(self, run, state):
        for facts in _contours(run):
            if facts.section_lines is not None:
                sections = state.rule_state.setdefault("sinumerik-contour-sections", [])
                if (*facts.section_lines, cycle_name(run)) not in sections:
                    sections.append((*facts.section_lines, cycle_name(run)))

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


def contour_not_found(facts, cycle: str, kind: str = "") -> str:
    """The message for a contour ``cycle`` names that no file holds (``kind``: edge, island, finished, blank)."""
    return f"the {kind + ' ' if kind else ''}contour \"{facts.name}\" of {cycle} is not in this file or on the subprogram path"


def contour_points_unknown(facts, cycle: str, what: str) -> str:
    """The message for a contour found whose points are not all numbers; ``what``: what is not judged."""
    return f"the points of the contour \"{facts.name}\" of {cycle} are not all known numbers: {what} is not judged"


def plane_point(point, state) -> str:
    first, second, _normal = state.plane_axes
    return f"{first}{point[0]:g} {second}{point[1]:g}"
