"""Klartext hazards of the stud approach, patterns, the working plane and the special
cycles 18, 224, 225, 232, 238 and 239 (reference A §9 H15, H42, H44, H46; reference B §9
items 18, 35, 40-42, 44). Parameter-only conditions are constraints on the rule pages.
"""
from __future__ import annotations

import math

from shapely.geometry import Point, box

from .. import ir, values
from ..check import Rule, hazard, rule, show
from ..diagnostics import Status
from .heidenhain import CycleRule, cycle_number, spindle_tool

_STUD_ROOM = 2.0  # mm beside the stud blank the approach keeps (seed L6429-6456, L6691-6715)
# Q437 approach position of 256: the corner as signs along the reference and minor axis.
_STUD_CORNERS = {1.0: (-1.0, -1.0), 2.0: (1.0, -1.0), 3.0: (1.0, 1.0), 4.0: (-1.0, 1.0)}
# Q367 stud position of 256: where the tool stands at the call, as a corner of the stud.
_STUD_REFERENCE = {0.0: (0.0, 0.0), **_STUD_CORNERS}
_CHANGES_ORIENTATION = {202, 204, 209}  # they use cycle 13 internally (seed L15051-15053)


def _numbers(params: dict, *names: str):
    found = [params.get(name) for name in names]
    return found if all(type(value) is float for value in found) else None


def _rotated(dx: float, dy: float, degrees: float) -> tuple[float, float]:
    angle = math.radians(degrees)
    return dx * math.cos(angle) - dy * math.sin(angle), dx * math.sin(angle) + dy * math.cos(angle)


def _written_axes(op) -> tuple[str, ...]:
    """The axes a block's move writes: a straight or circular move, or a tool-axis-only
    move at FMAX (``ir.Lift``, its words as written)."""
    if isinstance(op, ir.Move):
        return tuple(op.targets)
    if isinstance(op, ir.Lift):
        return tuple(op.words)
    return ()


def _untransformed(state) -> bool:
    """Are program coordinates those of the BLK FORM (no datum shift, rotation, ... active)?"""
    frame = getattr(state, "frame", None)
    return frame is None or frame.is_identity


class _BlankRule(CycleRule):
    """A cycle judged against the blank in the working plane: needs a box or polygon blank
    and no coordinate transformation."""
    reads = frozenset()  # compares positions as the program writes them with the blank: no active state is read

    def blank_outline(self, rule_id: str, span, state):
        stock = self.checker.context.stock
        if stock is None:
            self.missing(rule_id, span, "no blank (BLK FORM, an annotation or [stock])")
            return None, None
        if not _untransformed(state):
            self.missing(rule_id, span, "a coordinate transformation is active, so cycle coordinates are not those of the blank")
            return None, None
        if stock.kind == "box":
            return box(stock.x_range[0], stock.y_range[0], stock.x_range[1], stock.y_range[1]), stock
        if stock.kind == "polygon":
            return stock.outline, stock
        self.missing(rule_id, span, "the blank is a cylinder, whose working plane is not modelled here")
        return None, None


@rule("heidenhain.stud-approach-room")
class StudApproachRoom(_BlankRule):
    """H15: studs 256/257/258 plunge beside the stud blank, 2 mm plus the tool radius out
    from it, at Q206. Where that point lies over the BLK FORM, the tool plunges into the
    blank instead of beside it."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        first, second, axis = state.plane_axes
        here = (state.position.get(first), state.position.get(second))
        if number not in (256, 257, 258) or not self.first_time(state, ("stud-approach", span, here)):
            return
        depth = _numbers(params, "Q203", "Q201")
        if type(here[0]) is not float or type(here[1]) is not float or depth is None:
            self.missing("heidenhain.stud-approach-room", span, "a stud position or depth that is not known")
            return
        outline, stock = self.blank_outline("heidenhain.stud-approach-room", span, state)
        if outline is None:
            return
        tool = spindle_tool(self, state, span, "heidenhain.stud-approach-room", "radius")
        if tool is None:
            return
        found = self._approach(number, params, here, tool.radius)
        if found is None:
            self.missing("heidenhain.stud-approach-room", span, f"cycle {number}'s approach position depends on a parameter that is not known")
            return
        point, where = found
        surface, full_depth = depth
        infeed = params.get("Q202")
        first_depth = surface - min(abs(full_depth), infeed) if type(infeed) is float and infeed > 0 else surface + full_depth
        if first_depth >= stock.top or outline.distance(Point(point)) >= tool.radius:
            return
        self.report("heidenhain.stud-approach-room", spans.get(where, span),
                    f"cycle {number} plunges beside the stud at {first}{point[0]:.3f} {second}{point[1]:.3f} ({_STUD_ROOM:g} mm + R{tool.radius:g} out from the stud blank) "
                    f"down to {axis}{first_depth:g}, but the blank is there up to {axis}{stock.top:g}: the tool plunges into the material at the plunging feed; "
                    f"the stud needs {2 * tool.radius + _STUD_ROOM:g} mm (2R + 2 mm) of free room around its blank (seed L6472-6478)")

    @staticmethod
    def _approach(number, params, here, radius):
        """The tool centre where the stud cycle plunges, and the parameter that puts it there."""
        if number == 256:
            found = _numbers(params, "Q218", "Q219", "Q424", "Q425")
            rotation, at, position = (params.get(name, 0.0) for name in ("Q224", "Q437", "Q367"))
            if found is None or any(type(value) is not float for value in (rotation, at, position)) or position not in _STUD_REFERENCE or (at != 0.0 and at not in _STUD_CORNERS):
                return None
            length, width, blank_length, blank_width = found
            corner = _STUD_REFERENCE[position]
            shift = _rotated(-corner[0] * length / 2, -corner[1] * width / 2, rotation)
            centre = (here[0] + shift[0], here[1] + shift[1])
            reach_x, reach_y = blank_length / 2 + _STUD_ROOM + radius, blank_width / 2 + _STUD_ROOM + radius
            offset = (reach_x, 0.0) if at == 0.0 else (_STUD_CORNERS[at][0] * reach_x, _STUD_CORNERS[at][1] * reach_y)
            step = _rotated(*offset, rotation)
            return (centre[0] + step[0], centre[1] + step[1]), "Q437"
        angle_name = "Q376" if number == 257 else "Q224"  # 257 starts at Q376, 258 at its first corner Q224
        blank, angle = params.get("Q222"), params.get(angle_name, 0.0)
        if type(blank) is not float or type(angle) is not float or (number == 257 and angle == -1.0):
            return None  # 257 with Q376 = -1: the manual does not say where it starts
        step = _rotated(blank / 2 + _STUD_ROOM + radius, 0.0, angle)
        return (here[0] + step[0], here[1] + step[1]), angle_name


# cycle -> the manual lines saying it cuts at most LCUTS per infeed (272 with a warning)
_INFEED_LIMITED = {**dict.fromkeys((233, 251, 252, 253, 254, 256, 257, 258), "seed L5397-5399"), 272: "seed L11277-11278"}


def _point_angle_use(number, params) -> str | None:
    """Why the cycle needs the drill's point angle T-ANGLE (reference A H29, part B §9 item
    25), or None when it does not."""
    if number in (200, 203, 205) and params.get("Q395") == 1.0:
        return "Q395=1 measures the depth to the cylindrical part of the tool (seed L1685-1689)"
    if number == 240 and params.get("Q343") == 1.0:
        return "Q343=1 centres to the diameter Q344 (seed L3440-3446)"
    roughing = params.get("Q342") if number == 240 else None
    if type(roughing) is float and roughing > 0:
        return "Q342 starts deeper, at the depth of the roughing diameter (reference A H29)"
    if number == 277:
        return "OCM chamfering places the chamfer from the point angle (part B §9 item 25)"
    return None


@rule("heidenhain.point-angle")
class PointAngle(CycleRule):
    """H29: a cycle that computes a depth from the tool's point angle needs T-ANGLE."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        use = _point_angle_use(number, params)
        if use is None or not self.first_time(state, ("point-angle", span)):
            return
        tool_number = state.tool_in_spindle
        tool = self.checker.context.tools.in_spindle(state)
        if tool is None:
            self.missing("heidenhain.point-angle", span, self.checker.context.tools.missing(state))
        elif tool.point_angle is None and tool.origin != "TOOL.T":
            self.missing("heidenhain.point-angle", span, f"tool T{show(tool_number)} has no point angle (point_angle in [tools.{show(tool_number)}], "
                         "point-angle in an ncverify: tool annotation; 0 = not entered)")
        elif not tool.point_angle:
            self.report("heidenhain.point-angle", span, f"cycle {number}: {use}, which the control computes from the tool's point angle T-ANGLE, and "
                        f"tool T{show(tool_number)} has none in the tool table: the manual requires it, or the tip does not go where the program says; "
                        "enter T-ANGLE for the tool")


@rule("heidenhain.cutting-length")
class CuttingLength(CycleRule):
    """H44, part B C22: a plunging depth Q202 longer than the tool's cutting length LCUTS:
    the control reduces the infeed by itself, so the cycle takes more passes than programmed."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        infeed = params.get("Q202")
        if number not in _INFEED_LIMITED or infeed is None or not self.first_time(state, ("cutting-length", span)):
            return
        tool = spindle_tool(self, state, span, "heidenhain.cutting-length", "cutting_length")
        if tool is None:
            return
        verdict = self.checker.judge(hazard(">", infeed, tool.cutting_length), state)
        self.checker.report_verdict("heidenhain.cutting-length", spans.get("Q202", span),
                                    f"cycle {number}: plunging depth Q202={show(infeed)} is longer than the cutting length LCUTS={tool.cutting_length:g} of tool "
                                    f"T{show(state.tool_in_spindle)}: the control cuts at most LCUTS per infeed, so the cycle takes more passes ({_INFEED_LIMITED[number]})", verdict, state)


@rule("heidenhain.pattern-compatibility")
class PatternCompatibility(Rule):
    """H46 and reference B H35: the pattern cycles run the last machining cycle at their
    points, but 224 runs only some cycles, and 254 runs with 221 only with Q367 != 0."""

    def cycle_run(self, run, state):
        number = cycle_number(run.cycle)
        if number not in (221, 224):
            return
        definition = state.klartext.cycle
        if definition is None:
            return  # heidenhain.call-without-cycle
        if number == 224 and definition.number not in run.model.compatible:
            allowed = ", ".join(str(cycle) for cycle in run.model.compatible)
            self.report("heidenhain.pattern-compatibility", run.span, f"cycle 224 runs the last machining cycle {definition.number} at the cells of its code, "
                        f"but only {allowed} may run with it (seed L8340-8380)")
        if number == 221 and definition.number == 254 and definition.params.get("Q367") == 0.0:
            self.report("heidenhain.pattern-compatibility", definition.spans.get("Q367", run.span), "cycle 254 runs at the points of cycle 221 with the slot "
                        "position Q367=0 (slot centre), which the control does not permit with 221 (seed L6214)")


@rule("heidenhain.working-plane")
class WorkingPlane(Rule):
    """H42: CYCL DEF 19.1 must give every spatial angle, zeros too: an angle left out means
    "unchanged", not 0 (seed L8044-8046). After a tilt the control compensates an axis only
    once it is moved, so X, Y and Z must all be moved before a cycle machines (seed
    L8027-8030, L8112-8114)."""

    _UNMOVED = ("working-plane-unmoved",)
    _TILTED = ("working-plane-tilted",)

    handles_arcs = True  # its run handler takes every segment, arcs too

    def change(self, change, state):
        if change.what == "m_function" and change.new == 94.0 and state.rule_state.get(self._TILTED):
            self.report("heidenhain.working-plane", change.span, "M94 (modal rotary axis display) while cycle 19 tilts the working plane: the actual and "
                        "nominal positions of the rotary axes can part after further calls; position them with Q120-Q122 instead (seed L8095-8096)")

    def cycle_run(self, run, state):
        if run.cycle != "heidenhain.19":
            if run.model.activity != "def":
                self._machining(run.span, state)  # a definition (a datum shift, contour data ...) machines nothing
            return
        given = [axis for axis in "ABC" if axis in run.params]
        if given and len(given) < 3:
            missing = ", ".join(axis for axis in "ABC" if axis not in given)
            self.report("heidenhain.working-plane", run.span, f"cycle 19 gives {', '.join(given)} but not {missing}: an angle left out keeps its last value "
                        "instead of 0, so the plane is tilted differently from what the block shows; program all three spatial angles (seed L8044-8046)")
        tilted = any(run.params.get(axis, 0.0) != 0.0 for axis in given)
        state.rule_state[self._UNMOVED] = (frozenset(state.plane_axes), run.span.line) if tilted else None
        state.rule_state[self._TILTED] = tilted

    def hole(self, hole, state):
        self._machining(hole.span, state)

    def segment(self, segment, state):
        pending = state.rule_state.get(self._UNMOVED)
        if pending and segment.role == "programmed":
            moved = {axis for op in segment.block.ops for axis in _written_axes(op)}
            moved |= {axis for axis in pending[0] if segment.end.get(axis) is not segment.start.get(axis)}
            state.rule_state[self._UNMOVED] = (pending[0] - moved, pending[1]) if pending[0] - moved else None

    def motion_run(self, run, state):
        if state.rule_state.get(self._UNMOVED):
            for index in range(len(run)):
                self.segment(run.segment(index), state)

    def _machining(self, span, state):
        pending = state.rule_state.get(self._UNMOVED)
        if pending:
            state.rule_state[self._UNMOVED] = None
            unmoved = ", ".join(sorted(pending[0]))
            self.report("heidenhain.working-plane", span, f"a cycle machines after the tilt of cycle 19 (line {pending[1]}) while {unmoved} has not been moved since: "
                        "the control applies the tilt to an axis only when the axis moves; move X, Y and Z first (seed L8027-8030, L8112-8114)")


@rule("heidenhain.face-milling-blank")
class FaceMillingBlank(_BlankRule):
    """Reference B H18/H44: cycle 232 against the blank. Q227 should be the top of the blank
    (the first infeed is measured from it), Q386 above its underside, and the start point,
    R + Q357 before the surface edge, off the blank."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        if number != 232 or not self.first_time(state, ("face-milling-blank", span)):
            return
        found = _numbers(params, "Q225", "Q226", "Q227", "Q386", "Q218")
        if found is None:
            self.missing("heidenhain.face-milling-blank", span, "cycle 232's start point or levels depend on a parameter that is not known")
            return
        outline, stock = self.blank_outline("heidenhain.face-milling-blank", span, state)
        if outline is None:
            return
        start_x, start_y, start, end, length = found
        if start < stock.top:
            self.report("heidenhain.face-milling-blank", spans.get("Q227", span), f"cycle 232 starts its infeeds at Q227=Z{start:g}, below the top of the blank "
                        f"Z{stock.top:g}: the first pass takes {stock.top - start:g} mm more than the plunging depth Q202 (reference B H18)")
        if end < stock.z_range[0]:
            self.report("heidenhain.face-milling-blank", spans.get("Q386", span), f"cycle 232 faces down to Q386=Z{end:g}, below the underside of the blank "
                        f"Z{stock.z_range[0]:g}: the tool cuts into what the part lies on (reference B H18)")
        side = params.get("Q357", 0.0)
        if type(side) is not float or start <= end:
            return
        edge = start_x - math.copysign(side, length) if length else start_x  # the tool's near edge at the start point
        if outline.intersects(Point(edge, start_y)) and end < stock.top:
            self.report("heidenhain.face-milling-blank", spans.get("Q225", span), f"cycle 232 comes down R + Q357 before the surface edge Q225=X{start_x:g}, "
                        f"but the blank reaches past X{edge:g} at Y{start_y:g}: the tool descends onto the blank at the pre-positioning feed; "
                        "start the face outside the blank, or give more clearance to the side Q357 (seed L15585-15592)")


@rule("heidenhain.thread-cutting-position")
class ThreadCuttingPosition(CycleRule):
    """Reference B H41: cycle 18 cuts from where the tool is, DEPTH along the tool axis, with
    no approach of its own: a thread that ends above the blank cuts nothing."""
    reads = frozenset()  # compares positions as the program writes them with the blank: no active state is read

    def judge_cycle(self, number, params, spans, span, state, facts):
        if number != 18 or not self.first_time(state, ("thread-cutting-position", span, state.position.get(state.plane_axes[2]))):
            return
        axis = state.plane_axes[2]
        here, depth = state.position.get(axis), params.get("DEPTH")
        stock = self.checker.context.stock
        if here is None or depth is None:
            self.missing("heidenhain.thread-cutting-position", span, "the tool-axis position at cycle 18 or its depth is not known")
            return
        if stock is None or not _untransformed(state):
            self.missing("heidenhain.thread-cutting-position", span, "no blank in the coordinates of the cycle (BLK FORM, no transformation)")
            return
        if type(depth) is not float:
            self.missing("heidenhain.thread-cutting-position", span, "cycle 18's depth depends on a parameter that is not known")
            return
        end = values.add(here, depth)
        verdict = self.checker.judge(hazard(">=", end if depth < 0 else here, stock.top), state)
        self.checker.report_verdict("heidenhain.thread-cutting-position", spans.get("DEPTH", span),
                                    f"cycle 18 cuts from {axis}{show(here)} to {axis}{show(end)}, which does not reach the blank (top {axis}{stock.top:g}): "
                                    "the cycle has no approach move, so position the tool at the start of the thread before calling it (seed L15975-15990)", verdict, state)


@rule("heidenhain.machine-moving-cycle")
class MachineMovingCycle(Rule):
    """Reference B H42: 238 and the weighing run of 239 move the machine's axes at rapid
    along paths the machine builder defined, outside the program's control."""

    def cycle_run(self, run, state):
        number = cycle_number(run.cycle)
        mode = run.params.get("Q570")
        if number == 238 or (number == 239 and mode != 0.0):
            what = "measures the machine status" if number == 238 else "weighs the load (Q570=1)"
            self.report("heidenhain.machine-moving-cycle", run.span, f"cycle {number} {what}: the axes move at rapid over a range the machine builder set, "
                        "not the program; clear the working space and run it first in test mode (seed L15836-15851, L15920-15933)")


@rule("heidenhain.orientation-after-cycle")
class OrientationAfterCycle(Rule):
    """Reference B H40: 202, 204 and 209 use cycle 13 internally, so an M19 after them
    orients the spindle to their angle, not to the last cycle 13 of the program."""

    def hole(self, hole, state):
        self._machined(cycle_number(hole.cycle), state)

    def cycle_run(self, run, state):
        number = cycle_number(run.cycle)
        if number == 13:
            state.rule_state[("orientation-changed-by",)] = None
        else:
            self._machined(number, state)

    @staticmethod
    def _machined(number, state):
        if number in _CHANGES_ORIENTATION:
            state.rule_state[("orientation-changed-by",)] = number

    def change(self, change, state):
        number = state.rule_state.get(("orientation-changed-by",))
        if change.what == "spindle" and change.new == "orient" and number is not None:
            self.report("heidenhain.orientation-after-cycle", change.span, f"M19 orients the spindle after cycle {number}, which set the orientation angle "
                        "itself: the spindle stops at that cycle's angle; define cycle 13 again before M19 (seed L15051-15053)")


@rule("heidenhain.servo-spindle")
class ServoSpindle(CycleRule):
    """H45: 202, 204, 207, 209 and 18 orient, reverse or synchronise the spindle and need a
    servo-controlled one (seed L1838, L2261, L3883, L4037); ``[machine] spindle_encoder`` says
    whether the machine has it."""

    def hole(self, hole, state):
        self.judge_model(hole.cycle, hole.model, hole.definition or hole.span, state)

    def cycle_run(self, run, state):
        if not run.first_block:
            self.judge_model(run.cycle, run.model, run.span, state)

    def judge_model(self, cycle, model, span, state):
        if "servo-spindle" not in model.requires:
            return
        encoder = self.checker.context.machine.spindle_encoder
        if encoder is None:
            self.missing("heidenhain.servo-spindle", span, "whether the spindle is servo-controlled is not known ([machine] spindle_encoder in ncverify.toml)")
        elif not encoder and self.first_time(state, ("servo-spindle", span)):
            self.report("heidenhain.servo-spindle", span, f"cycle {cycle_number(cycle)} {model.name} needs a servo-controlled spindle, and this machine has none "
                        "([machine] spindle_encoder = false): the control refuses the cycle; bore or tap with a cycle the spindle can run (206 in a floating holder)")


@rule("heidenhain.boring-feed-per-revolution")
class BoringFeedPerRevolution(Rule):
    """H17: with M136 (feed per revolution) active, cycle 202 stops the spindle at the bottom
    of the bore and does not retract the tool (seed L1890-1897)."""

    def hole(self, hole, state):
        if cycle_number(hole.cycle) == 202 and state.klartext.feed_per_revolution and self.first_time(state, ("boring-m136", hole.span)):
            self.report("heidenhain.boring-feed-per-revolution", hole.span, "cycle 202 is called while M136 (feed per revolution) is active: the spindle stops at "
                        "the bottom of the bore and the tool is not retracted, so the next move drags it out or crashes; cancel M136 with M137 before the call (seed L1890-1897)")


# The part of the pitch a thread goes below its depth: taps none; thread milling 262/263
# moves up to half a pitch along the tool axis before the approach (seed L4329-4337).
_THREAD_OVERRUN = {206: 0.0, 207: 0.0, 209: 0.0, 262: 0.5, 263: 0.5}


@rule("heidenhain.thread-deeper-than-hole")
class ThreadDeeperThanHole(Rule):
    """H6 (derived) and H7: a tap or an inside thread mill needs the hole drilled before it
    at the same point to be at least as deep as the thread (and half a pitch more for the
    compensating move of 262/263). Holes drilled earlier on the same path are compared;
    with no earlier hole there nothing is said."""

    def hole(self, hole, state):
        number = cycle_number(hole.cycle)
        if number not in _THREAD_OVERRUN or type(hole.bottom) is not float or not _untransformed(state):
            return
        first, second, axis = state.plane_axes
        point = (hole.position.get(first), hole.position.get(second))
        earlier = [bottom for x, y, bottom in state.klartext.drilled if (x, y) == point and type(bottom) is float]
        pitch = hole.params.get("Q239", 0.0)
        if not earlier or type(pitch) is not float or hole.params.get("Q201", -1.0) > 0:
            return
        needed = hole.bottom - abs(pitch) * _THREAD_OVERRUN[number]
        drilled = min(earlier)
        if needed >= drilled - 1e-9 or not self.first_time(state, ("thread-deeper", hole.span, point)):
            return
        overrun = f" and up to half the pitch more for its compensating move, to {axis}{needed:g}," if _THREAD_OVERRUN[number] else ""
        message = (f"cycle {number} threads down to {axis}{hole.bottom:g}{overrun} at {first}{point[0]:g} {second}{point[1]:g}, but the hole drilled there "
                   f"before ends at {axis}{drilled:g}: the tool runs into the bottom of the hole and breaks (reference A H6, H7)")
        stock = self.checker.context.stock
        if axis == "Z" and stock is not None and drilled < stock.z_range[0]:  # drilled through the blank: no bottom to run into
            self.report("heidenhain.thread-deeper-than-hole", hole.param_spans.get("Q201", hole.span), message, Status.UNKNOWN,
                        "the hole drilled there goes through the blank, so it has no bottom; what lies under the part is the set-up's, not in the program")
            return
        self.report("heidenhain.thread-deeper-than-hole", hole.param_spans.get("Q201", hole.span), message)
