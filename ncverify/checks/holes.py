"""Rules on the holes canned cycles make: levels, parameters, spindle."""
from __future__ import annotations

from ..ir import cycle_code
from ..check import Rule, hazard, rule, show
from ..diagnostics import Status
from .. import modelled



@rule("core.cycle-missing-parameter")
class MissingParameter(Rule):
    judges_holes_before_moves = True
    def hole(self, hole, state):
        if hole.missing and self.first_time(state, ("core.cycle-missing-parameter", hole.definition)):
            meanings = ", ".join(f"{letter} ({hole.model.params[letter].meaning})" for letter in hole.missing)
            self.report("core.cycle-missing-parameter", hole.definition or hole.span, f"{cycle_code(hole.cycle)} makes holes without {meanings}: the control alarms at the first hole")


@rule("core.cycle-depth-sign", "core.cycle-zero-depth", "core.cycle-r-above-initial")
class HoleLevels(Rule):
    """Every hole is judged, so a message is worded only for a hazard that is not plainly
    absent (a condition, or concrete True): the levels of a correct hole are numbers."""
    judges_holes_before_moves = True
    reads = modelled.AS_WRITTEN
    def hole(self, hole, state):
        bottom, r_point, initial = hole.bottom, hole.r_point, hole.initial
        if bottom is None or r_point is None or hole.model.r_incremental:
            return
        axis = hole.drill_axis
        span = hole.param_spans.get(axis, hole.span)
        judged = self._judged
        if hole.model.infeed == "back_bore":
            judged("core.cycle-depth-sign", span, hazard("<=", bottom, r_point), state,
                   lambda code: f"{code} back boring: the top of the bore {axis}{show(bottom)} is not above the start level R{show(r_point)}; "
                   "R must lie below the part and Z above it", hole)
            return
        judged("core.cycle-zero-depth", span, hazard("==", bottom, r_point), state,
               lambda code: f"{code}: hole bottom {axis}{show(bottom)} equals the R point: the cycle cuts nothing", hole)
        above = ">" if hole.up > 0 else "<"  # "above" is toward the side the tool comes from
        side = "" if hole.up > 0 else f" (the tool comes from {axis}-, so above means lower {axis})"
        judged("core.cycle-depth-sign", span, hazard(above, bottom, r_point), state,
               lambda code: f"{code}: hole bottom {axis}{show(bottom)} is above the R point {show(r_point)}{side}: "
               "the tool would feed upward out of the part and rapid back down", hole)
        if initial is not None:
            verdict = self.checker.judge(hazard(above, r_point, initial), state)
            if verdict is None or state.modal.get("cycle_return") == "r_point" and verdict.status is not Status.PROVED:
                return  # under G99 the tool goes from hole to hole at R, whatever the initial level
            self.checker.report_verdict("core.cycle-r-above-initial", hole.param_spans.get("R", hole.span),
                                        f"{cycle_code(hole.cycle)}: R point {show(r_point)} is above the initial level {show(initial)}{side}: "
                                        "the tool moves between holes below the R plane", verdict, state)

    def _judged(self, rule_id, span, condition, state, message, hole) -> None:
        """Report the verdict on ``condition`` with ``message(cycle code)``, the message
        worded before the solver is asked, as every rule does."""
        if condition is not False:
            self.checker.report_verdict(rule_id, span, message(cycle_code(hole.cycle)), self.checker.judge(condition, state), state)


@rule("core.peck-depth")
class PeckDepth(Rule):
    judges_holes_before_moves = True
    reads = modelled.AS_WRITTEN
    def hole(self, hole, state):
        if (hole.model.infeed or "").startswith("peck") and not hole.model.r_incremental:
            depth = hole.params.get("Q")
            if depth is not None:
                self.checker.report_verdict("core.peck-depth", hole.param_spans.get("Q", hole.span), f"{cycle_code(hole.cycle)}: peck depth Q{show(depth)} is not positive: the control alarms",
                                            self.checker.judge(hazard("<=", depth, 0.0), state), state)


@rule("core.dwell-fraction")
class DwellFraction(Rule):
    judges_holes_before_moves = True
    def hole(self, hole, state):
        dwell = hole.params.get("P")
        if "P" not in hole.model.params:
            return  # a cycle that does not dwell at the bottom (G81): there is no dwell to shorten
        if type(dwell) is float and dwell != int(dwell):
            self.report("core.dwell-fraction", hole.param_spans.get("P", hole.span), f"{cycle_code(hole.cycle)}: dwell P{show(dwell)} has a fraction, which the cycle ignores: it dwells P{int(dwell)}")


_SPINDLE_WORDS = {"off": "stopped", "cw": "clockwise (M03)", "ccw": "counter-clockwise (M04)"}


@rule("core.tapping-spindle-direction")
class TappingSpindle(Rule):
    judges_holes_before_moves = True
    def hole(self, hole, state):
        expected = hole.model.spindle_before
        if expected is None or state.spindle == expected or hole.params.get(",R") == 1.0 and state.spindle != "off":
            return
        if state.spindle not in _SPINDLE_WORDS:
            return  # "inherited": what a called program that is not here left is not known
        if not self.first_time(state, ("core.tapping-spindle-direction", hole.definition)):
            return
        wanted = "M03 (clockwise)" if expected == "cw" else "M04 (counter-clockwise)"
        actual = _SPINDLE_WORDS[state.spindle]
        self.report("core.tapping-spindle-direction", hole.span, f"{cycle_code(hole.cycle)} tapping needs the spindle running {wanted}, but it is {actual}: the tap strips the thread or breaks")


@rule("core.css-without-clamp")
class SurfaceSpeedWithoutClamp(Rule):
    machines = frozenset({"lathe"})
    handles_arcs = True  # any move, arcs too

    def segment(self, segment, state):
        if self._applies(state):
            self._report(segment.span, state)

    def motion_run(self, run, state):
        if self._applies(state):
            self._report(run.span(0), state)

    def _applies(self, state) -> bool:
        return (state.modal.get("spindle_mode") == "surface_speed" and state.spindle_clamp is None
                and self.checker.context.lathe and not state.rule_state.get("css-clamp"))

    def _report(self, span, state):
        state.rule_state["css-clamp"] = True
        self.report("core.css-without-clamp", span, "constant surface speed (G96) with no spindle speed clamp (G92 S / G50 S): near X0 the spindle runs up to its maximum")


@rule("core.lathe-cycle-parameters")
class LatheCycleParameters(Rule):
    """G76's packed P word (mmrraa) on its first block; the plain limits are constraints."""

    def cycle_run(self, run, state):
        if not run.cycle.endswith("G76") or not run.first_block:
            return
        packed = run.params.get("first_P")
        if type(packed) is not float:
            return
        number = int(packed)
        cuts, chamfer, angle = number // 10000, number // 100 % 100, number % 100
        span = run.param_spans.get("P", run.span)
        if packed != number or number > 999999:
            self.report("core.lathe-cycle-parameters", span, f"G76 P{show(packed)} is not six digits mmrraa (cuts, chamfer, angle)")
        elif angle > 90:
            self.report("core.lathe-cycle-parameters", span, f"G76 P{number:06d}: tool angle {angle} is above 90 degrees (cuts {cuts}, chamfer {chamfer / 10:g} leads)")
