"""Hazards of canned cycles, lathe compound cycles and threading (reference section 9.2):
compensation and modal traps, boring shifts, repeats, table values, lathe formats."""
from __future__ import annotations

from .. import ir, values
from ..cycle_models import CycleModel
from ..interpret import modal_call
from ..check import ARCS, Rule, hazard, rule, show
from .. import modelled

_COMP_CODE = {"left": "G41", "right": "G42", "auto": "G46"}
_SHIFT_LETTERS = {"xy": ("I", "J"), "zx": ("K", "I"), "yz": ("J", "K")}
_PLANE_CODE = {"xy": "G17", "zx": "G18", "yz": "G19"}
_ROUGHING = ("G71", "G72", "G73")



def _all(conditions) -> "bool | values.Condition":
    """AND of hazard conditions, short-circuiting concrete ones."""
    return _combine(conditions, "AND")


def _any(conditions) -> "bool | values.Condition":
    """OR of hazard conditions, short-circuiting concrete ones."""
    return _combine(conditions, "OR")


def _combine(conditions, operator: str):
    neutral = operator == "AND"  # True for AND, False for OR
    result = neutral
    for condition in conditions:
        if condition is (not neutral):
            return not neutral
        if condition is not neutral:
            result = condition if result is neutral else values.logical(operator, result, condition)
    return result


def _word_span(block, letter: str, default):
    """Where ``letter`` is written in a block's move (for a report), else ``default``."""
    if block is not None:
        for op in block.ops:
            if isinstance(op, ir.Move) and letter in op.word_columns:
                return op.word_span(letter)
            if isinstance(op, ir.SetFeed) and letter == "F":
                return op.span
    return default


def _position_text(hole) -> str:
    shown = [f"{axis}{show(value)}" for axis, value in hole.position.items() if axis != hole.drill_axis and value is not None]
    return " ".join(shown) or "the current position"


# --------------------------------------------------------------------------- mill and lathe hole cycles


@rule("core.comp-in-cycle")
class CompensationInCycle(Rule):
    judges_holes_before_moves = True
    def hole(self, hole, state):
        side = state.comp_side
        if side in ("off", None) or not self.first_time(state, ("core.comp-in-cycle", hole.definition)):
            return
        code = _COMP_CODE.get(side, "radius compensation")
        register = f" D{show(state.comp_register)}" if state.comp_register is not None else ""
        self.report("core.comp-in-cycle", hole.definition or hole.span,
                    f"{ir.cycle_code(hole.cycle)} makes holes while {code}{register} radius compensation is on: a hole cycle positions on the "
                    "programmed point, so depending on the control the holes move by the cutter radius or the cycle alarms; cancel with G40 before the cycle")


@rule("core.cycle-modal-at-end")
class CycleModalAtEnd(Rule):
    def change(self, change, state):
        if change.what != "end" or change.new != "end":
            return
        if state.cycle is not None:
            self.report("core.cycle-modal-at-end", change.span,
                        f"canned cycle {ir.cycle_code(state.cycle.cycle)} is still active at the program end{self.word('cycle_cancel', ' (no {})')}: where the end does "
                        "not reset the modal state, the first block of the next program or of a restart that moves an axis makes a hole with this cycle's data")
        elif (program := modal_call.active_program(state)) is not None:
            self.report("core.cycle-modal-at-end", change.span,
                        f"the modal call of {program} is still active at the program end{self.word('modal_call_cancel', ' (no {})')}: where the end does "
                        f"not reset the modal state, the first block of the next program or of a restart that moves an axis runs {program} there")


@rule("core.cycle-shift-missing")
class CycleShift(Rule):
    """G76 fine boring and G87 back boring move the tool off the wall by a shift: I/J in
    G17, K/I in G18, J/K in G19 (the address table also names Q)."""
    judges_holes_before_moves = True
    reads = modelled.AS_WRITTEN

    def hole(self, hole, state):
        if "shift" not in hole.model.bottom:
            return
        plane = state.modal.get("plane", "xy")
        letters = _SHIFT_LETTERS.get(plane, ("I", "J"))
        params = hole.params
        given = [params[letter] for letter in (*letters, "Q") if letter in params]
        code = ir.cycle_code(hole.cycle)
        key = ("core.cycle-shift-missing", hole.definition)
        if key in state.rule_state:
            return
        span = hole.definition or hole.span
        verdict = self.checker.judge(_all(hazard("==", value, 0.0) for value in given), state)
        if verdict is not None:
            state.rule_state[key] = True
            wrong = [f"{letter}{show(params[letter])}" for letter in ("I", "J", "K") if letter in params and letter not in letters]
            elsewhere = f" ({', '.join(wrong)} is not a shift address in {_PLANE_CODE.get(plane, plane)})" if wrong else ""
            what = ("the tool tip drags up the wall on the rapid out and scores the finished bore" if code == "G76"
                    else "the bar goes down through the bore with its tip out and hits the part")
            self.checker.report_verdict("core.cycle-shift-missing", span,
                                        f"{code} has no shift: {letters[0]} and {letters[1]} ({_PLANE_CODE.get(plane, plane)}) and Q are missing or zero{elsewhere}, "
                                        f"so after the oriented spindle stop {what}", verdict, state)
            return
        if "Q" in params and not any(letter in params for letter in letters):
            state.rule_state[key] = True
            self.report("core.cycle-shift-missing", hole.param_spans.get("Q", span),
                        f"{code} takes its shift from Q{show(params['Q'])}: the printed format gives the shift as {letters[0]}/{letters[1]} "
                        f"({_PLANE_CODE.get(plane, plane)}), and only the address table names Q, so whether this control shifts by Q is uncertain; "
                        f"write {letters[0]}/{letters[1]}")


@rule("core.repeat-same-hole")
class RepeatSameHole(Rule):
    """Each repeat is its own Hole; a repeat at the position of the one before it (from the
    same block) drills the same hole again. The repeat word is the cycle model's
    ``repeat_letter`` (Fagor ``NR``), else ``L`` or ``K`` (lathe)."""
    judges_holes_before_moves = True

    def hole(self, hole, state):
        memory = state.rule_state
        if hole.repeat <= 1:
            memory.pop("repeat-same-hole", None)
            return
        absolute = state.modal.get("distance") != "incremental"
        position = tuple(sorted((axis, value) for axis, value in hole.position.items() if axis != hole.drill_axis))
        previous = memory.get("repeat-same-hole")
        memory["repeat-same-hole"] = (hole.span, position)
        if previous is None or previous[0] != hole.span or not _same_position(previous[1], position, absolute):
            return
        candidates = (hole.model.repeat_letter,) if hole.model.repeat_letter else ("L", "K")  # Fagor: NR
        letter = candidates[0]
        for candidate in candidates:
            where = hole.param_spans.get(candidate)
            if where is not None and where.line == hole.span.line:
                letter = candidate
                break
        span = hole.param_spans.get(letter, hole.span)
        if span.line != hole.span.line:
            span = hole.span
        mode = "G90 (absolute)" if absolute else "G91 with no positioning increment"
        self.report("core.repeat-same-hole", span,
                    f"{ir.cycle_code(hole.cycle)} {letter}{int(hole.repeat)} in {mode}: every repeat goes back to {_position_text(hole)}, so the same hole is "
                    f"made {int(hole.repeat)} times; repeats space holes only in G91 with an X/Y increment")


def _same_position(a: tuple, b: tuple, absolute: bool) -> bool:
    if len(a) != len(b):
        return False
    for (axis_a, value_a), (axis_b, value_b) in zip(a, b):
        if axis_a != axis_b:
            return False
        if value_a is None or value_b is None:
            if not (absolute and value_a is None and value_b is None):
                return False
        elif not (value_a is value_b or (type(value_a) is float and type(value_b) is float and value_a == value_b)):
            return False
    return True


@rule("core.cycle-parameter-value")
class CycleParameterValue(Rule):
    """Every parameter whose cycle table entry lists ``allowed`` values."""
    judges_holes_before_moves = True
    reads = modelled.AS_WRITTEN

    def __init__(self, checker):
        super().__init__(checker)
        self._specs: dict[int, tuple] = {}

    def hole(self, hole, state):
        self._check(hole.cycle, hole.model, hole.params, hole.param_spans, hole.span, state)

    def cycle_run(self, run, state):
        self._check(run.cycle, run.model, run.params, run.param_spans, run.span, state)

    def _allowed(self, model: CycleModel) -> tuple:
        specs = self._specs.get(id(model))
        if specs is None:
            specs = tuple((letter, spec) for letter, spec in model.params.items() if spec.allowed is not None)
            self._specs[id(model)] = specs
        return specs

    def _check(self, cycle, model, params, spans, default_span, state):
        for letter, spec in self._allowed(model):
            value = params.get(letter)
            if value is None or not self.first_time(state, ("core.cycle-parameter-value", cycle, letter, value if type(value) is float else id(value), spans.get(letter))):
                continue  # hole data stay modal: judged once per value and place, not per hole
            allowed = [float(choice) for choice in spec.allowed]
            verdict = self.checker.judge(_all(hazard("!=", value, choice) for choice in allowed), state)
            choices = " or ".join(f"{letter}{choice:g}" for choice in allowed)
            meaning = f": {spec.meaning}" if spec.meaning else ""
            self.checker.report_verdict("core.cycle-parameter-value", spans.get(letter, default_span),
                                        f"{ir.cycle_code(cycle)} {letter}{show(value)} is not a value this cycle takes ({choices}{meaning}): "
                                        "the control stops with a program error or runs the cycle in a mode you did not choose", verdict, state)


# --------------------------------------------------------------------------- lathe


@rule("core.lathe-arc-over-180")
class LatheArcOver180(Rule):
    machines = frozenset({"lathe"})
    reads = modelled.AS_WRITTEN
    segment_kinds = ARCS
    handles_arcs = True  # each arc given by its radius is judged as a segment on a lathe

    def motion_run(self, run, state):
        if run.arcs is not None and self.checker.context.lathe:
            for index in run.arc_indices():
                if run.arcs.radii[index] == run.arcs.radii[index]:
                    self.segment(run.segment(index), state)

    def segment(self, segment, state):
        arc = segment.arc
        if arc is None or arc.radius_word is None or not self.checker.context.lathe:
            return
        radius = arc.radius_word
        verdict = self.checker.judge(hazard("<", radius, 0.0), state)
        self.checker.report_verdict("core.lathe-arc-over-180", _word_span(segment.block, "R", segment.span),
                                    f"R{show(radius)}: a negative R asks for an arc of more than 180 degrees, but on the lathe an R arc spans at most "
                                    "180 degrees and the control alarms; split the arc in two or give its centre with I/K", verdict, state)


@rule("core.finish-shape-mismatch")
class FinishShapeMismatch(Rule):
    """G70 must finish a shape that a G71/G72/G73 on this path roughed (same A/P/Q)."""

    def cycle_run(self, run, state):
        if run.model.shape != "contour" or run.first_block:
            return
        code = ir.cycle_code(run.cycle)
        params = run.params
        shape = (params.get("A"), params.get("P"), params.get("Q"))
        blocks = (shape[0], frozenset(shape[1:]))  # P/Q swapped is core.shape-order's finding
        if code in _ROUGHING:
            if "P" in params or "Q" in params:
                roughed = state.rule_state.get("roughed-shapes", ())
                state.rule_state["roughed-shapes"] = roughed + ((shape, blocks, code, run.span.line),)
            return
        if code != "G70":
            return
        roughed = state.rule_state.get("roughed-shapes", ())
        if not roughed or not all(value is None or type(value) is float for value in shape):
            return
        if any(earlier == blocks for _shape, earlier, _code, _line in roughed):
            return
        last, _blocks, rough_code, line = roughed[-1]
        self.report("core.finish-shape-mismatch", run.param_spans.get("P", run.span),
                    f"G70 {_shape_text(shape)} finishes a different shape from the one roughed before it ({rough_code} {_shape_text(last)}, line {line}): "
                    "the finishing pass follows a contour that was not roughed and takes the full stock in one cut, or finishes the wrong blocks")


def _shape_text(shape) -> str:
    return " ".join(f"{letter}{value:g}" for letter, value in zip("APQ", shape) if value is not None) or "(no P/Q)"


@rule("core.two-block-mixture")
class TwoBlockMixture(Rule):
    """G71/G72/G73 take U/W/R in a first block and P/Q with the allowances in a second;
    R is never a second-block letter of these cycles."""

    def cycle_run(self, run, state):
        model = run.model
        if run.first_block or not model.two_blocks or model.shape != "contour":
            return
        params = run.params
        if "R" not in params or not ("P" in params or "Q" in params):
            return
        code = ir.cycle_code(run.cycle)
        first = " ".join(f"{letter}_" for letter in model.first_block)
        written = " ".join(f"{letter}{show(value)}" for letter, value in params.items())
        meanings = model.params
        ambiguous = "".join(f"; {letter}{show(params[letter])} is ambiguous, {meanings[letter].meaning if letter in meanings else 'first or second block'}"
                            for letter in model.first_block if letter != "R" and letter in params)
        self.report("core.two-block-mixture", run.span,
                    f"{code} {written} mixes the first block ({code} {first}) and the second block ({code} P_ Q_ U_ W_ F_) in one: "
                    f"the Mitsubishi format needs the two blocks{ambiguous}")


@rule("core.thread-parameters")
class ThreadParameters(Rule):
    """G76 second block against the first block's finishing allowance, and the lead; the
    plain conditions on P and Q are constraints on the rule's page."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        if run.first_block or run.model.shape != "thread" or not run.model.two_blocks:
            return
        code = ir.cycle_code(run.cycle)
        height = run.params.get("P")
        allowance = state.lathe_cycle_data.get(run.cycle, {}).get("first_R")
        if height is not None and allowance is not None and not (type(height) is float and height <= 0):
            verdict = self.checker.judge(hazard(">=", allowance, height), state)
            self.checker.report_verdict("core.thread-parameters", run.param_spans.get("P", run.span),
                                        f"{code} finishing allowance R{show(allowance)} (first block) is not less than the thread height P{show(height)}: "
                                        "the roughing passes never reach the thread and the finishing pass cuts the whole profile", verdict, state)
        lead = state.feed
        if lead is not None:
            verdict = self.checker.judge(hazard("<=", lead, 0.0), state)
            self.checker.report_verdict("core.thread-parameters", _word_span(run.block, "F", run.span),
                                        f"{code} lead F{show(lead)} is not positive: the control cannot synchronise the thread with the spindle (alarm)", verdict, state)


# --------------------------------------------------------------------------- G33 threading


@rule("core.thread-start-angle")
class ThreadStartAngle(Rule):
    reads = modelled.AS_WRITTEN
    def change(self, change, state):
        if change.what != "thread" or not change.new or "Q" not in change.new:
            return
        angle = change.new["Q"]
        low = 0.001 if self.checker.context.lathe else 0.0
        verdict = self.checker.judge(_any((hazard("<", angle, low), hazard(">", angle, 360.0))), state)
        counted = any(isinstance(op, ir.Move) and isinstance(op.words.get("Q"), ir.IncrementCount) for op in change.block.ops) if change.block else False
        hint = " (Q without a decimal point counts in 0.001 degree steps)" if counted else ""
        self.checker.report_verdict("core.thread-start-angle", _word_span(change.block, "Q", change.span),
                                    f"thread start angle Q{show(angle)}{hint} is outside {low:g}-360 degrees: the control rejects it with a program error", verdict, state)
