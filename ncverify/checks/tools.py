"""Rules on tools and offset registers."""
from __future__ import annotations

import numpy

from ..ir import cycle_code
from ..check import CUTTING, Rule, rule, show
from ..diagnostics import Status
from ..interpret import modal_call


@rule("core.d-register-range", "core.h-register-range", "core.tool-number-range")
class RegisterRanges(Rule):
    def change(self, change, state):
        limits = self.checker.context.limits
        if change.what == "cutter_comp" and change.register is not None and state.comp_side in ("left", "right", "auto"):
            self._check_range("core.d-register-range", "D", change, 1.0, limits.d_register_max)
        elif change.what == "length_offset" and change.register is not None:
            self._check_range("core.h-register-range", "H", change, 0.0, limits.h_register_max)
        elif change.what == "tool_select" and type(change.new) is float and not 0 <= change.new <= limits.tool_number_max:
            self.report("core.tool-number-range", change.span, f"tool number T{show(change.new)} is outside 0-{limits.tool_number_max:g} on this control")

    def _check_range(self, rule_id, letter, change, low, high):
        value = change.register
        if type(value) is float and not low <= value <= high:
            self.report(rule_id, change.span, f"offset register {letter}{show(value)} is outside {low:g}-{high:g} on this control: alarm")


@rule("core.g12-missing-d")
class CircleCuttingRegister(Rule):
    def cycle_run(self, run, state):
        if run.model.shape != "circle":
            return
        register = run.params.get("D")
        if register is None:
            self.report("core.g12-missing-d", run.span, f"{cycle_code(run.cycle)} circle cutting has no D offset register: the control alarms")
        elif type(register) is float and not 1 <= register <= self.checker.context.limits.d_register_max:
            self.report("core.d-register-range", run.param_spans.get("D", run.span), f"offset register D{show(register)} is outside 1-{self.checker.context.limits.d_register_max:g} on this control: alarm")


@rule("core.length-offset-mismatch")
class LengthOffsetMismatch(Rule):
    def change(self, change, state):
        if change.what != "length_offset" or self.checker.context.lathe:
            return
        register, tool = change.register, state.tool_in_spindle
        if type(register) is not float or type(tool) is not float or register == 0 or register == tool:
            return
        self.report("core.length-offset-mismatch", change.span, f"tool T{show(tool)} is in the spindle but the length offset is H{show(register)}: Z is off by the difference of the two tool lengths")


@rule("core.no-length-offset")
class NoLengthOffset(Rule):
    judges_cycle_runs = True
    segment_kinds = CUTTING  # a rapid cuts nothing
    handles_arcs = True  # an arc cuts as a straight feed move does

    def change(self, change, state):
        if change.what == "tool_change":
            state.rule_state.pop("no-length-offset", None)

    def segment(self, segment, state):
        if segment.kind != "rapid" and self._applies(state) and state.plane_axes[2] not in state.parked:
            self._report(segment.span, state)  # a feed move with the tool axis still at its reference height cuts nothing

    def motion_run(self, run, state):
        """Runs never start with an axis parked (the interpreter runs those block by block)."""
        cutting = numpy.flatnonzero(run.kinds >= 1)  # straight feed moves and arcs
        if len(cutting) and self._applies(state):
            self._report(run.span(int(cutting[0])), state)

    def _applies(self, state) -> bool:
        return (state.tool_changed and state.length_mode == "off" and not self.checker.context.lathe
                and not state.rule_state.get("no-length-offset"))

    def _report(self, span, state):
        state.rule_state["no-length-offset"] = True
        message = f"tool T{show(state.tool_in_spindle)} cuts with no length offset (no G43 H since the tool change): Z positions ignore the tool's length"
        context = self.checker.context
        if not context.lengths_by_set_up:
            self.report("core.no-length-offset", span, message)
            return
        tool = context.tools.in_spindle(state)
        length = None if tool is None else tool.length
        if length is None:
            self.report("core.no-length-offset", span, message, Status.UNKNOWN,
                        "the tool change applies no length: it matters only where the tool table holds the tool's length, not on a "
                        "set-up that touches each tool off in the work offset; give the tool table (lengths) to decide")
        elif length != 0.0:
            self.report("core.no-length-offset", span, f"{message} ({show(length)} in the tool table)")


@rule("core.cycle-modal-at-tool-change")
class CycleModalAtToolChange(Rule):
    def change(self, change, state):
        if change.what != "tool_change":
            return
        if state.cycle is not None:
            self.report("core.cycle-modal-at-tool-change", change.span, f"canned cycle {cycle_code(state.cycle.cycle)} is still active at the tool change{self.word('cycle_cancel', ' (no {})')}: "
                        "the next block that moves an axis drills with the new tool")
        elif (program := modal_call.active_program(state)) is not None:
            self.report("core.cycle-modal-at-tool-change", change.span, f"the modal call of {program} is still active at the tool change"
                        f"{self.word('modal_call_cancel', ' (no {})')}: the next block that moves an axis runs {program} with the new tool")
