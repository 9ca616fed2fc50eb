"""Rules on modes and settings that stay in force, or act, where the program does not expect
it: G63 tapping mode, tool length compensation, G10/G30/G92 settings, feed units, constant
surface speed at the centre, M codes sharing a block with a cut (E60 section 9.2, hazards
16, 19-23, 28, 29, 35)."""
from __future__ import annotations

import math

import numpy

from .. import ir, values
from ..check import CUTTING, Rule, hazard, rule, show
from ..diagnostics import Severity, Status
from .. import modelled
from ..trace import any_in_row

_FEED = 1  # MotionRun kind code of a feed segment; arcs' are above it
_LENGTH_CODE = {"plus": "G43", "minus": "G44"}
_SPINDLE_CODE = {"cw": "M03", "ccw": "M04", "off": "M05", "orient": "M19"}
_CUTTING_MOTION = frozenset({"linear", "arc_cw", "arc_ccw", "thread"})


def _tapping_cycle(run, state) -> bool:
    """Are a run's moves a tapping cycle's? (A tap's feed and its moves follow the thread:
    the segment handlers pass over them.)"""
    return run.cycle_moves and state.cycle is not None and state.cycle.model.tapping


def _moved(a, b) -> bool:
    return a is not b and not (type(a) is float and type(b) is float and a == b)


def _register(value) -> str:
    return f"H{int(value):02d}" if type(value) is float and value == int(value) and value >= 0 else f"H{show(value)}"


# G10 L2 (work offsets) and L20 (added work systems): allowed P range and what happens outside it.
_G10_TARGETS = {
    2.0: (0.0, 6.0, "a chosen one", "give P1-P6 (G54-G59) or P0 (external)",
          "the E60 writes the values into G54 (P1) instead, and overwrites its offset"),
    20.0: (1.0, 48.0, "an added one", "give P1-P48 (G54.1 P1-P48)",
           "the E60 writes the values into the work system that is selected now, and overwrites its offset"),
}


def _repeating(state) -> str | None:
    """Why a block may run more than once: it is inside a loop, a subprogram or a macro."""
    if state.loops:
        return "inside a WHILE loop"
    for frame in reversed(state.call_stack):
        if frame.kind == "macro":
            return f"inside macro {frame.program}"
        if frame.kind in ("subprogram", "called"):
            return f"inside subprogram {frame.program}"
        if frame.kind == "local":
            return "inside a local subprogram (M97)"
    return None


def _ordinal(number: int) -> str:
    suffix = "th" if 10 <= number % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(number % 10, "th")
    return f"{number}{suffix}"


def _ran_before(state, key: str, span) -> bool:
    """Has this block already run on this path (a backward GOTO loop)?"""
    seen = state.rule_state.get(key, frozenset())  # immutable: forked paths share rule_state's values
    where = (span.path, span.line, span.column)
    if where in seen:
        return True
    state.rule_state[key] = seen | {where}
    return False


# --------------------------------------------------------------------------- G63 tapping mode


@rule("core.tapping-mode-left-on")
class TappingModeLeftOn(Rule):
    """G63 in force for a cut that is not a tap: one finding per G63 episode. A feed move
    along the tool axis only (Z on a mill, in G17) is taken for a tap written with G01."""
    judges_cycle_runs = True
    segment_kinds = CUTTING

    handles_arcs = True  # an arc cuts as a feed move does; judged by its end points, as block by block

    def change(self, change, state):
        if change.what == "path_mode" and change.old != change.new:
            state.rule_state.pop("tapping-mode-reported", None)

    def segment(self, segment, state):
        if segment.kind not in CUTTING or state.modal.get("path_mode") != "tapping" or state.rule_state.get("tapping-mode-reported"):
            return
        if segment.cycle is not None and state.cycle is not None and state.cycle.model.tapping:
            return
        axis = self._tool_axis(state)
        if not any(_moved(segment.start.get(other), segment.end.get(other)) for other in set(segment.start) | set(segment.end) if other != axis):
            return
        self._report(segment.span, state)

    def motion_run(self, run, state):
        if state.modal.get("path_mode") != "tapping" or state.rule_state.get("tapping-mode-reported") or _tapping_cycle(run, state):
            return
        cutting = numpy.flatnonzero(run.kinds >= _FEED)
        if not len(cutting):
            return
        axis = self._tool_axis(state)
        others = [index for index, name in enumerate(run.axes) if name != axis]
        if not others:
            return
        start, end = run.points[cutting][:, others], run.points[cutting + 1][:, others]
        moved = ((end - start) != 0) & ~(numpy.isnan(start) & numpy.isnan(end))
        across = numpy.flatnonzero(any_in_row(moved))
        if len(across):
            self._report(run.span(int(cutting[across[0]])), state)

    def _tool_axis(self, state) -> str:
        return "Z" if self.checker.context.lathe else state.plane_axes[2]

    def _report(self, span, state):
        state.rule_state["tapping-mode-reported"] = True
        self.report("core.tapping-mode-left-on", span, "G63 tapping mode is still in force for this cut, which is not a tap: feed override stays at 100 %, "
                    "and feed hold and single block do not stop it (cancel G63 with G64 after tapping)")


# --------------------------------------------------------------------------- tool length compensation


def _block_moves_z(block) -> bool:
    if block is None:
        return False
    for op in block.ops:
        if isinstance(op, (ir.Move, ir.MachineMove)) and "Z" in op.targets:
            return True
        if isinstance(op, ir.ReferenceReturn) and "Z" in op.via:
            return True
        if isinstance(op, (ir.CycleDefine, ir.CycleCall)) and "Z" in op.params:
            return True
    return False


@rule("core.length-offset-without-z", "core.length-offset-minus", "core.length-offset-change-moves", "core.length-offset-across-tool-change")
class LengthOffsetMotion(Rule):
    """What G43/G44/G49 and H do to Z on the E60 (seed L1787-1832): switching the offset on or
    off, or changing it while it is on, moves Z by the change, in the block that does it. A
    tool change leaves the offset in force: the first Z move before the new tool's own
    G43/G44 H (or G49) positions it with the old tool's length.

    That immediate Z move is only a hazard where the tool is near the work: with Z parked
    (at the start, after a tool change, which takes Z to the change position, after a
    reference return or a machine-coordinate move) it moves from the top of the travel, and
    the usual ``M06`` / ``G43 H01`` / ``G00 Z1.`` sequence is not reported."""
    judges_cycle_runs = True
    reads = modelled.AS_WRITTEN

    handles_arcs = True  # every move, arcs too, by its end points

    def change(self, change, state):
        if self.checker.context.lathe:
            return
        if change.what in ("tool_change", "reference_return"):
            state.rule_state.pop("z-at-work", None)
        if change.what == "tool_change":
            if state.length_mode in _LENGTH_CODE:
                state.rule_state["length-stale"] = (change.span, state.length_mode, state.length_register, change.new)
            else:
                state.rule_state.pop("length-stale", None)
        elif change.what == "length_offset":
            state.rule_state.pop("length-stale", None)
            self._length_offset(change, state)

    def segment(self, segment, state):
        if _moved(segment.start.get("Z"), segment.end.get("Z")) and segment.end.get("Z") is not None:
            state.rule_state["z-at-work"] = True
            if "length-stale" in state.rule_state:
                self._stale(segment.span, state)

    def motion_run(self, run, state):
        if "Z" not in run.axes:
            return
        column = run.axes.index("Z")
        start, end = run.points[:-1, column], run.points[1:, column]
        moved = numpy.flatnonzero(((end - start) != 0) & ~(numpy.isnan(start) & numpy.isnan(end)))
        if len(moved):
            state.rule_state["z-at-work"] = True
            if "length-stale" in state.rule_state:
                self._stale(run.span(int(moved[0])), state)

    def _stale(self, span, state):
        at, mode, register, tool = state.rule_state.pop("length-stale")
        code = _LENGTH_CODE[mode]
        held = f"{code} {_register(register)}" if register is not None else code
        tool = f"T{show(tool)}" if tool is not None else "the new tool"
        where = f"line {span.line}" if span.path == at.path else f"line {span.line} of {span.path}"
        self.report("core.length-offset-across-tool-change", at,
                    f"{held} is still in force at this tool change, and {tool} moves in Z at {where} before its own {code} H..: "
                    "it is positioned with the old tool's length, off by the difference of the two lengths (G49 before M06, then G43 H.. with the first Z move)")

    def _length_offset(self, change, state):
        memory = state.rule_state
        _, old_register = memory.get("length-in-force", ("off", None))
        old_mode, new_mode = change.old, state.length_mode
        new_register = state.length_register if new_mode != "off" else None
        memory["length-in-force"] = (new_mode, new_register)
        if new_mode == "minus" and old_mode != "minus":
            shown = f" {_register(new_register)}" if new_register is not None else ""
            self.report("core.length-offset-minus", change.span,
                        f"G44{shown} subtracts the length offset instead of adding it: with offsets measured the usual way (a longer tool has the larger H), "
                        "the tool goes twice the offset lower than with G43, toward the part; use G43 unless the offsets were measured for G44")
        if _block_moves_z(change.block) or not memory.get("z-at-work") or state.position.get("Z") is None or "given" in (old_mode, new_mode):
            return  # (LinuxCNC G43.1/G43.2 give the offset's value: not judged here)
        was_on, is_on = old_mode in _LENGTH_CODE, new_mode in _LENGTH_CODE
        if not was_on and is_on and new_register is not None:
            self.report("core.length-offset-without-z", change.span,
                        f"{_LENGTH_CODE[new_mode]} {_register(new_register)} in a block without Z: the control moves Z at once by the {_register(new_register)} offset, "
                        "as if G00 G91 Z0 were given, wherever the tool is (write the Z move in the same block: G43 H.. Z50.)")
        elif was_on and not is_on and old_register is not None:
            what = "H0 cancels the length offset like G49, and" if change.register == 0.0 else "G49"
            self.report("core.length-offset-without-z", change.span,
                        f"{what} in a block without Z: the control takes the {_register(old_register)} offset off at once and Z moves by it, "
                        "as if G00 G91 Z0 were given (cancel in a block that moves Z, e.g. G49 G91 G28 Z0.)")
        elif was_on and is_on:
            self._changed_while_on(change, state, old_mode, old_register, new_mode, new_register)

    def _changed_while_on(self, change, state, old_mode, old_register, new_mode, new_register):
        if old_mode != new_mode:
            self.report("core.length-offset-change-moves", change.span,
                        f"{_LENGTH_CODE[new_mode]} replaces {_LENGTH_CODE[old_mode]} while length compensation stays on, in a block without Z: "
                        "the offset changes sign and Z moves at once by twice its value")
            return
        if old_register is None or new_register is None or new_register is old_register:
            return
        verdict = self.checker.judge(hazard("!=", new_register, old_register), state)
        self.checker.report_verdict("core.length-offset-change-moves", change.span,
                                    f"{_register(new_register)} replaces {_register(old_register)} while length compensation stays on, in a block without Z: "
                                    "Z moves at once by the difference of the two offsets (G49 first, or give the new H with a Z move)", verdict, state)


# --------------------------------------------------------------------------- G30, G10, G92


@rule("core.reference-point-number")
class ReferencePointNumber(Rule):
    reads = modelled.AS_WRITTEN
    def change(self, change, state):
        if change.what != "reference_return" or change.new != "secondary":
            return
        number = (change.words or {}).get("P")
        if number is None:  # the documented default, the usual tool-change position (G91 G30 Z0): a remark, not a fault
            self.report("core.reference-point-number", change.span,
                        "G30 without P returns to the 2nd reference point; write G30 P2, P3 or P4 to say which one is meant",
                        severity=Severity.INFO)
            return
        outside = values.logical("AND", values.logical("AND", hazard("!=", number, 2.0), hazard("!=", number, 3.0)), hazard("!=", number, 4.0))
        if number == 1.0:
            meant = ", not the 1st (that is G28's)"
        elif type(number) is float and number == int(number) and number > 4:
            meant = f", not a {_ordinal(int(number))}: the machine has reference points 1 to 4 only"
        else:
            meant = ""
        self.checker.report_verdict("core.reference-point-number", change.span,
                                    f"G30 P{show(number)} returns to the 2nd reference point{meant}; only P2, P3 and P4 choose one (E60)",
                                    self.checker.judge(outside, state), state)


@rule("core.g10-default-substitution", "core.g10-incremental-repeat")
class OffsetDataSetting(Rule):
    """G10 L2 / L20 with a P the E60 replaces silently (seed L1595, L1619-1625), and G10 in
    G91, which adds to the offset each time it runs (seed L1569, L1579)."""
    reads = modelled.AS_WRITTEN

    def change(self, change, state):
        if change.what != "data_setting":
            return
        words = change.new or {}
        self._substitution(change, words, state)
        if state.modal.get("distance") == "incremental":
            why = _repeating(state) or ("in a block that has already run on this path" if _ran_before(state, "g10-ran", change.span) else None)
            if why is not None:
                self.report("core.g10-incremental-repeat", change.span,
                            f"G10 in G91 ({why}) adds its values to the offset every time it runs: the offset drifts by that much on each pass "
                            "(write the offset absolutely in G90)")

    def _substitution(self, change, words, state):
        kind, number = words.get("L"), words.get("P")
        target = _G10_TARGETS.get(kind) if type(kind) is float else None
        if target is None:
            return
        low, high, what, missing, outside_message = target
        if number is None:
            self.report("core.g10-default-substitution", change.span,
                        f"G10 L{kind:g} without P writes the values into the work system that happens to be selected, not {what}: {missing}")
            return
        outside = values.logical("OR", hazard("<", number, low), hazard(">", number, high))
        self.checker.report_verdict("core.g10-default-substitution", change.span,
                                    f"G10 L{kind:g} P{show(number)} is outside P{low:g}-P{high:g}: {outside_message}",
                                    self.checker.judge(outside, state), state)



@rule("core.g92-repeated")
class CoordinateSettingRepeated(Rule):
    def change(self, change, state):
        if change.what != "set_position":
            return
        memory = state.rule_state
        first = memory.get("g92-first")
        why = _repeating(state)
        if why is not None:
            reason = f"{why}, where it runs again on every call or pass"
        elif first is not None:
            reason = f"a second time (the first was line {first.line})" if first.path == change.span.path else "a second time"
        else:
            reason = None
        if first is None:
            memory["g92-first"] = change.span
        if reason is None:
            return
        self.report("core.g92-repeated", change.span,
                    f"G92 coordinate setting runs {reason}: it makes wherever the tool stands the new zero and shifts all six work systems (G54-G59) with it, "
                    "so every later position moves by the tool's offset from the first setting (use G54-G59)")


# --------------------------------------------------------------------------- feed units


# (feed mode, inch) -> (mode, lowest plausible feed, highest, unit)
_FEED_LIMITS = {
    ("per_revolution", False): ("per_revolution", None, 5.0, "mm/rev"),
    ("per_revolution", True): ("per_revolution", None, 0.2, "in/rev"),
    ("per_minute", False): ("per_minute", 1.0, None, "mm/min"),
    ("per_minute", True): ("per_minute", 0.04, None, "in/min"),
}


@rule("core.feed-plausibility")
class FeedPlausibility(Rule):
    """A feed read in the wrong mode's units: above 5 mm/rev (0.2 in/rev) in G95, or below
    1 mm/min (0.04 in/min) in G94. One finding per feed value, like core.feed-missing."""
    judges_cycle_runs = True
    reads = modelled.AS_WRITTEN
    segment_kinds = frozenset({"feed", "arc"})

    handles_arcs = True  # an arc cuts at the feed in force, as a straight feed move

    def change(self, change, state):
        if change.what == "feed_mode":
            state.rule_state["feed-mode-stated"] = True

    def segment(self, segment, state):
        if segment.kind not in ("feed", "arc"):
            return
        if segment.cycle is not None and state.cycle is not None and state.cycle.model.tapping:
            return  # a tap's feed is its pitch (G95) or speed x pitch (G94)
        limits = self._limits(state)
        if limits is not None:
            self._check(state.feed, segment.span, state, limits)

    def motion_run(self, run, state):
        limits = self._limits(state)
        if limits is None or _tapping_cycle(run, state):
            return
        cutting = numpy.flatnonzero(run.kinds >= _FEED)
        if not len(cutting):
            return
        mode, low, high, _unit = limits
        feeds = run.feeds[cutting]
        previous = numpy.concatenate(([numpy.inf], feeds[:-1]))
        changed = ~((feeds == previous) | (numpy.isnan(feeds) & numpy.isnan(previous)))
        memory = state.rule_state
        first = None if math.isnan(feeds[0]) else float(feeds[0])
        remembered = memory.get("feed-plausibility", _UNSEEN)
        changed[0] = remembered is _UNSEEN or remembered[0] != mode or not _same(remembered[1], first)
        with numpy.errstate(invalid="ignore"):
            implausible = feeds > high if high is not None else (feeds > 0) & (feeds < low)
        for index in numpy.flatnonzero(changed & implausible):
            memory.pop("feed-plausibility", None)
            self._check(float(feeds[index]), run.span(int(cutting[index])), state, limits)
        last = feeds[-1]
        memory["feed-plausibility"] = (mode, None if math.isnan(last) else float(last))

    def _limits(self, state):
        mode = state.modal.get("feed_mode", "per_minute")
        if mode not in ("per_minute", "per_revolution"):
            return None
        if self.checker.context.lathe and not state.rule_state.get("feed-mode-stated"):
            return None  # a lathe's power-on feed mode is a parameter (G95 on most): the program has not said
        return _FEED_LIMITS[mode, state.modal.get("units") == "inch"]

    def _check(self, feed, span, state, limits):
        mode, low, high, unit = limits
        memory = state.rule_state
        previous = memory.get("feed-plausibility", _UNSEEN)
        if previous is not _UNSEEN and previous[0] == mode and _same(previous[1], feed):
            return
        memory["feed-plausibility"] = (mode, feed)
        if feed is None:
            return
        if high is not None:
            verdict = self.checker.judge(hazard(">", feed, high), state)
            message = (f"feed F{show(feed)} in G95 means {show(feed)} {unit}, far more than any cut takes per spindle revolution (above {high:g} {unit}): "
                       f"a feed per minute written in G95 mode? (G94 for {unit.replace('rev', 'min')})")
        else:
            verdict = self.checker.judge(values.logical("AND", hazard(">", feed, 0.0), hazard("<", feed, low)), state)
            message = (f"feed F{show(feed)} in G94 means {show(feed)} {unit}, so slow that the tool only rubs (below {low:g} {unit}): "
                       f"a feed per revolution written in G94 mode? (G95 for {unit.replace('min', 'rev')})")
        self.checker.report_verdict("core.feed-plausibility", span, message, verdict, state)


_UNSEEN = object()


def _same(a, b) -> bool:
    return a is b or (type(a) is float and type(b) is float and a == b)


# --------------------------------------------------------------------------- constant surface speed at the centre


@rule("core.css-toward-center")
class SurfaceSpeedAtCentre(Rule):
    """Lathe, G96 in force, a cut that reaches X0 (or crosses it): one finding per G96
    episode."""
    machines = frozenset({"lathe"})
    reads = frozenset()  # compares positions as the program writes them with the blank: no active state is read
    segment_kinds = frozenset({"feed", "arc"})

    handles_arcs = True  # an arc cuts as a feed move does; judged by its end points, as block by block

    def change(self, change, state):
        if change.what == "spindle_mode" and change.old != change.new:
            state.rule_state.pop("css-centre-reported", None)

    def segment(self, segment, state):
        if segment.kind not in ("feed", "arc") or not self._applies(state):
            return
        end, start = segment.end.get("X"), segment.start.get("X")
        reaches = hazard("<=", end, 0.0) if end is not None else False
        if start is not None:
            reaches = values.logical("OR", reaches, hazard("<=", start, 0.0))
        verdict = self.checker.judge(reaches, state)
        if verdict is not None:
            self._report(segment.span, state, verdict)

    def motion_run(self, run, state):
        if "X" not in run.axes or not self._applies(state):
            return
        cutting = numpy.flatnonzero(run.kinds >= _FEED)
        column = run.axes.index("X")
        start, end = run.points[cutting, column], run.points[cutting + 1, column]
        reaching = numpy.flatnonzero((end <= 0) | (start <= 0))
        if len(reaching):
            self._report(run.span(int(cutting[reaching[0]])), state, self.checker.judge(True, state))

    def _applies(self, state) -> bool:
        return (self.checker.context.lathe and state.modal.get("spindle_mode") == "surface_speed"
                and not state.rule_state.get("css-centre-reported"))

    def _report(self, span, state, verdict):
        if verdict.status is not Status.PROVED:
            state.rule_state["css-centre-reported"] = True
        clamp = state.spindle_clamp
        if clamp is None:
            message = ("G96 constant surface speed is in force and this cut reaches X0, the spindle axis: the speed it asks for there has no limit, "
                       "and no spindle speed clamp is set, so the spindle runs up to the machine's maximum (set a clamp, or G97 for work on the axis)")
        else:
            message = (f"G96 constant surface speed is in force and this cut reaches X0, the spindle axis: the spindle speeds up to the clamp S{show(clamp)} there; "
                       "check that speed suits the chuck, the part and the tool (G97 for drilling on the axis)")
        self.checker.report_verdict("core.css-toward-center", span, message, verdict, state)


# --------------------------------------------------------------------------- M codes sharing a block with a cut


@rule("core.m-code-with-motion")
class SpindleCodeWithCut(Rule):
    def change(self, change, state):
        if change.what != "spindle" or change.block is None:
            return
        for op in change.block.ops:
            if not isinstance(op, ir.Move) or not (op.targets or op.arc):
                continue
            if op.kind is None and state.cycle is not None:
                continue  # a hole of the modal cycle
            kind = op.kind or state.modal.get("motion")
            if kind in _CUTTING_MOTION:
                code = _SPINDLE_CODE.get(change.new, "M code")
                self.report("core.m-code-with-motion", change.span,
                            f"{code} is in the same block as a cutting move: whether the control acts on it before or after the move depends on the machine "
                            f"(the machine builder's setting), so the cut may start or end with the spindle not yet as intended; put {code} in a block of its own")
                return
