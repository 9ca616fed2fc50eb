"""Rules against the stock: rapids through the blank, clearance planes inside it.

Without a stock (no program definition, annotation or project file), each rule says so
once per file with status ``unknown``. The stock is not updated by cutting: a rapid
through a pocket machined earlier is still reported (future work, see the rule pages).
"""
from __future__ import annotations


import dataclasses
import math

import numpy

from ..ir import cycle_code
from .. import context, frames, geometry
from .. import modelled
from ..check import Rule, Verdict, hazard, rule, show
from ..context import Stock, active_edge, compensated, radius_delta
from ..diagnostics import Status
from ..verdict import both
from ..values import Condition, Sym
from .common import UNKNOWN_DIAMETER_MODE, lathe_x_is_diameter
from ..material import other_workpiece, tip_unplaced, tool_axis_problem

_RAPID = 0  # MotionRun kind code
_ROLE_WORDS = {
    "programmed": "rapid move", "reference": "rapid to the reference point", "approach": "cycle rapid to the R point",
    "retract": "cycle rapid retract", "between-holes": "rapid to the next hole", "shift": "cycle shift",
    "through-bore": "back-boring rapid entry", "into-hole": "cycle rapid into a hole drilled earlier",
    "to-thread": "rapid to the thread's entry point", "over-stud": "rapid down over the stud's centre (no approach distance E)",
    "beside-stud": "rapid to the thread end",
}
# Rapids into material the program removed earlier, which the stock model does not track
_INTO_CLEARED = {"through-bore": "a pre-bored hole", "into-hole": "a pre-bored hole", "beside-stud": "beside the stud, through material cleared earlier,"}


def _point(position: dict, stock) -> tuple | None:
    """(x, y, z) of a position, or None when an axis the stock needs is unknown."""
    x, y, z = position.get("X"), position.get("Y"), position.get("Z")
    if stock.kind == "cylinder" and y is None:
        y = 0.0
    if x is None or y is None or z is None:
        return None
    return x, y, z


def _separated(stock, start: dict, end: dict, tool=None, axes=("X", "Y", "Z")) -> bool:
    """Both ends on the outer side of one face of the stock (known concrete values only),
    with room for the tool (its radius beside the sides, its length below the bottom): a
    straight move, or a dog-leg within their box, cannot enter it. Only the faces across
    ``axes`` count (under radius compensation the others' positions are not the tool's)."""
    box = geometry.stock_box(stock) or (None, None, stock.z_range)
    radius, length = tool or (0.0, 0.0)
    below_bottom = math.inf if length is None else length
    for axis, limits, below, above in (("X", box[0], radius, radius), ("Y", box[1], radius, radius), ("Z", box[2], below_bottom, 0.0)):
        a, b = start.get(axis), end.get(axis)
        if limits is None or type(a) is not float or type(b) is not float or axis not in axes:
            continue
        low, high = b if b < a else a, b if b > a else a  # min(a, b) and max(a, b) without the calls (asked on every rapid)
        if low >= limits[1] + above or high <= limits[0] - below:
            return True
    return False


# What the cylinder model of the tool reads: the stock's kind, the tool in the spindle and
# its radius and length from the tool table, standing along +Z of the workpiece. Along any
# other tool axis the concrete check judges the tool's axis alone, and no proof is given
# (the rule does not read modelled.TOOL_AXIS).


def _placed_axes(state) -> tuple[str, ...]:
    """The axes whose programmed positions are the tool's: all three, but under radius
    compensation only the tool axis (the offset acts in the working plane)."""
    return (state.plane_axes[2],) if compensated(state) else ("X", "Y", "Z")


def _cylinder_tool(rule_instance, stock, state):
    """(radius, length or None) of the tool in the spindle when the stock is a box or a
    polygon, the tool table gives the radius and the tool stands along +Z of the
    workpiece; None otherwise (the tool is then only its axis, and no proof is given from
    that)."""
    tool = rule_instance.checker.context.tools.in_spindle(state)
    if tool is None or stock.kind == "cylinder" or tool_axis_problem(state) is not None:
        return None  # no tool known first: the cheapest answer, asked on every rapid
    delta = radius_delta(state)
    edge = active_edge(state)
    if edge != 1.0:
        tool = tool.edges.get(int(edge)) if type(edge) is float else None
    if tool is None or tool.radius is None or type(delta) is not float:
        return None
    return tool.radius + delta, tool.length


def _enters(stock, start, end, tool, dogleg: bool = False):
    """Where the tool touches the stock on a concrete move: as a cylinder when its size is
    known, else along its axis."""
    if tool is None:
        return geometry.enters(stock, start, end, dogleg)
    return geometry.tool_enters(stock, start, end, *tool, dogleg)


def _may_enter(stock, start, end, tool, dogleg: bool = False):
    if tool is None:
        return geometry.may_enter_symbolic(stock, start, end, dogleg)
    return geometry.tool_may_enter_symbolic(stock, start, end, *tool, dogleg)


def _same(a, b) -> bool:
    """The same coordinate: equal numbers, or the very same expression."""
    return a is b or (type(a) is float and type(b) is float and a == b)


def _straight_up(points, rapids):
    """Which of the run's ``rapids`` (indices of moves through known ``points``, X Y Z) go
    straight up from where the tool stands: what :meth:`RapidIntoStock._retracts` lets pass
    on concrete values."""
    start, end = points[rapids], points[rapids + 1]
    return (start[:, 0] == end[:, 0]) & (start[:, 1] == end[:, 1]) & (end[:, 2] >= start[:, 2])


def _where(point) -> str:
    return " ".join(f"{axis}{show(value)}" for axis, value in zip("XYZ", point))


class _NeedsStock(Rule):
    """Reports once per file, at the first place it would have looked, that there is no stock."""

    rule_id = ""
    looked_at = None

    def stock(self, span, state, tip_matters: bool = True):
        """The stock to judge against here; None when there is none (said at the end), when
        the work offset in force may hold another workpiece (said once per path and
        offset), or, where ``tip_matters``, when the tool's tip is not known to stand at the
        programmed point (:func:`~ncverify.material.tip_unplaced`, said once per path and
        reason)."""
        stock = self.checker.context.stock
        if stock is None and self.looked_at is None:
            self.looked_at = span
        if stock is None:
            return None
        elsewhere = other_workpiece(self.checker.context, state)
        if elsewhere is not None:
            if self.first_time(state, (self.rule_id, "other workpiece", state.modal.get("work_offset"))):
                self.report(self.rule_id, span, f"not checked: {elsewhere}", Status.UNKNOWN, "another work offset")
            return None
        unplaced = tip_unplaced(self.checker.context, state) if tip_matters else None
        if unplaced is not None:
            if self.first_time(state, (self.rule_id, "tip unplaced", unplaced)):
                self.report(self.rule_id, span, f"stock not compared: {unplaced}", Status.UNKNOWN, "tool tip not placed")
            return None
        diameter = lathe_x_is_diameter(state) if stock.kind == "cylinder" else True
        if diameter is not True:
            if self.first_time(state, (self.rule_id, "lathe X", diameter)):
                why = UNKNOWN_DIAMETER_MODE if diameter is None else "X is a radius (DIAMOF, G8): the bar is described by its diameter in X"
                self.report(self.rule_id, span, f"not checked: {why}", Status.UNKNOWN, "lathe X as a radius" if diameter is False else "diameter mode not known")
            return None
        return stock

    def finish(self):
        if self.looked_at is not None:
            self.report(self.rule_id, self.looked_at, "not checked: no stock defined (annotation 'ncverify: stock ...' or [stock] in ncverify.toml)",
                        Status.UNKNOWN, "no stock defined")


@rule("core.rapid-into-stock")
class RapidIntoStock(_NeedsStock):
    judges_cycle_runs = True  # the rapids a run may hit are judged as segments, by their roles
    segment_kinds = frozenset({"rapid"})
    rule_id = "core.rapid-into-stock"
    reads = modelled.GEOMETRY

    handles_arcs = True  # arcs are never rapids

    def segment(self, segment, state, run=None, index: int | None = None):
        if segment.kind != "rapid" or segment.role == "out-of-hole":
            return  # back up the hole the tool has just made: no stock there
        stock = self.stock(segment.span, state, tip_matters=not _rises(segment, state))
        if stock is None:
            return
        if state.parked or state.left_start:
            segment = self._from_start_position(segment, state)
        tool = _cylinder_tool(self, stock, state)
        if _separated(stock, segment.start, segment.end, tool, _placed_axes(state)):
            return
        start, end = _point(segment.start, stock), _point(segment.end, stock)
        what = _ROLE_WORDS.get(segment.role, "rapid move")
        if segment.cycle:
            what = f"{cycle_code(segment.cycle)} {what}"
        if end is None:
            unplaced = "/".join(axis for axis in "XYZ" if segment.end.get(axis) is None)
            if state.frame is frames.UNKNOWN:
                self._unknown_position(segment.span, f"{what} runs in a tilted or otherwise unmodelled coordinate system: where it lies on the blank is not known, "
                                       "so its path was not checked", state, "unknown-frame")
                return
            self._unknown_position(segment.span, f"{what} ends where ncverify does not know the tool is ({unplaced} not known yet: no move has set it since the program start or a reference return): its path was not checked", state)
            return
        if start is None:
            self._from_unknown(stock, end, segment.span, what, state, tool)
            return
        if self._retracts(start, end, state):
            return
        if compensated(state):
            side = f" ({state.comp_side} of the path)" if state.comp_side in ("left", "right") else ""
            self.report(self.rule_id, segment.span, f"{what} from {_where(start)} to {_where(end)} runs under radius compensation{side} near "
                        f"the blank ({stock.describe()}): the tool runs beside the programmed path, on the side and by the offset the compensation "
                        "gives it, which this check does not work out, so where it passes was not checked", Status.UNKNOWN, "radius compensation on")
            return
        if any(isinstance(value, Sym) for value in (*start, *end)):
            self._symbolic(stock, start, end, segment.span, what, state, tool)
            return
        hit = _enters(stock, start, end, tool, self.checker.context.rapid_path == "dogleg")
        if hit is None:
            return
        left = self.checker.material.rapid(start, end, state, run, index) if self.checker.context.rapid_path != "dogleg" else None
        if left is None or (left.outcome == "hits" and segment.role in _INTO_CLEARED):  # a hole bored before this program is in neither model
            self._judge_against_blank(segment, what, start, end, hit, stock)
        elif left.outcome == "hits":
            message = self._message(what, start, end, left.point, stock, cut=self.checker.material.has_cut(state))
            if self.checker.material.sizeless_cuts(state):
                message += " (a tool whose radius is not in the tool table cut before it: what that tool removed is counted along its axis only)"
            self.report(self.rule_id, segment.span, message)
        elif left.outcome == "unsure":
            self._unsure(segment, what, start, end, stock, state)

    def _from_start_position(self, segment, state):
        """A parked axis (at the program start, after a reference return or a full retract)
        stands at the start position (``[machine] start``, by default above the stock), not
        nowhere: its unknown ends are placed there. Only with the tool along +Z of the
        workpiece, where a parked Z is the height of the tool."""
        if tool_axis_problem(state) is not None:
            return segment
        start_position = context.start_position(self.checker.context.machine, self.checker.context.stock)
        start = self._placed(segment.start, state.parked | state.left_start, start_position)
        end = self._placed(segment.end, state.parked, start_position)
        return dataclasses.replace(segment, start=start, end=end)

    @staticmethod
    def _placed(point: dict, parked, start_position: dict) -> dict:
        return {**point, **{axis: start_position[axis] for axis in parked if axis in start_position and point.get(axis) is None}}

    def _retracts(self, start, end, state) -> bool:
        """With the stock as cut so far: a rapid straight up the tool's own axis from where
        the tool stands, for every allowed value. Every point it passes is where the tool's
        body already is, so it meets nothing the tool has not met already (the holder is
        judged on its own)."""
        if not self.checker.material.milled or tool_axis_problem(state) is not None or not (_same(start[0], end[0]) and _same(start[1], end[1])):
            return False
        falls = hazard("<", end[2], start[2])
        if isinstance(falls, bool):
            return not falls
        verdict = self.checker.judge(falls, state)
        return verdict is not None and verdict.status is Status.PROVED

    def _unsure(self, segment, what, start, end, stock, state) -> None:
        """The blank is hit, the cut stock may be: where earlier cuts depend on free
        parameters, values for which they stayed above the rapid are a candidate witness
        (the replay with those values decides); otherwise the answer is unknown."""
        shallow = self.checker.material.stayed_above(min(start[2], end[2]), state)
        verdict = self.checker.judge(shallow, state) if shallow is not None else None
        if verdict is not None and verdict.status is Status.VIOLATED:
            self.checker.report_verdict(self.rule_id, segment.span, f"{what} from {_where(start)} to {_where(end)} passes through the stock "
                                        f"({stock.describe()}) where the earlier cuts, for these values, did not go down: the tool crashes into it at rapid",
                                        verdict, state)
            return
        resolution = self.checker.material.resolution
        limits = (f"{resolution:g} mm cells, or a cut it could not place" if resolution is not None
                  else "an insert whose nose radius or cutting-edge position is not in the tool table, an arc, or a cut it could not place")
        self.report(self.rule_id, segment.span, f"{what} from {_where(start)} to {_where(end)} passes through the blank ({stock.describe()}) where earlier cuts "
                    f"may have removed the material, closer to it than the model of the cut stock can tell ({limits}): not checked",
                    Status.UNKNOWN, "within the in-process stock's error")

    def _judge_against_blank(self, segment, what, start, end, hit, stock) -> None:
        """No model of the cut stock (or one that shows material where the cycle goes down
        into a hole it needs bored before it): the blank decides, except there."""
        if segment.role in _INTO_CLEARED:
            self.report(self.rule_id, segment.span, f"{what} goes down {_INTO_CLEARED[segment.role]} to {_where(end)}: the stock model has no "
                        "holes bored or material cleared before this program, so this entry was not checked", Status.UNKNOWN, "the stock model knows no pre-boring")
            return
        self.report(self.rule_id, segment.span, self._message(what, start, end, hit, stock))

    def motion_run(self, run, state):
        rapids = numpy.flatnonzero(run.kinds == _RAPID)
        if not len(rapids):
            return
        stock = self.stock(run.span(int(rapids[0])), state, tip_matters=False)
        if stock is None:
            return
        if (self.checker.context.rapid_path == "dogleg" or stock.kind == "polygon" or len(run.axes) != 3 or compensated(state)
                or tip_unplaced(self.checker.context, state) is not None):
            for index in rapids:
                self.segment(run.segment(int(index)), state, run, int(index))
            return
        tool = _cylinder_tool(self, stock, state)
        if tool is not None:  # candidates within the tool's reach of the box; each is then judged exactly
            radius, length = tool
            stock = Stock.box((stock.x_range[0] - radius, stock.x_range[1] + radius), (stock.y_range[0] - radius, stock.y_range[1] + radius),
                              (stock.z_range[0] - (1e12 if length is None else length), stock.z_range[1]))
        starts, ends = run.points[rapids].copy(), run.points[rapids + 1].copy()
        if stock.kind == "cylinder":
            starts[:, 1] = numpy.nan_to_num(starts[:, 1])
            ends[:, 1] = numpy.nan_to_num(ends[:, 1])
        known = ~(numpy.isnan(starts).any(axis=1) | numpy.isnan(ends).any(axis=1))
        hits = rapids[known][geometry.enters_many(stock, starts[known], ends[known])]
        if self.checker.material.milled and tool_axis_problem(state) is None and run.axes == ("X", "Y", "Z"):
            hits = hits[~_straight_up(run.points, hits)]  # what _retracts passes, without making their segments
        # Every rapid that may meet the stock is judged, in the run's order, as block by block: a
        # crash after a few hundred retracts out of the cut is found (the report keeps the first
        # findings of a rule and counts the others), and the cut stock is taken up to each in turn.
        for index in numpy.sort(numpy.concatenate((rapids[~known], hits))).tolist():
            self.segment(run.segment(index), state, run, index)

    def _from_unknown(self, stock, end, span, what, state, tool):
        """Where the tool comes from is unknown; the end point alone can still be inside."""
        if any(isinstance(value, Sym) for value in end):
            self._judge(_may_enter(stock, end, end, tool), f"{what} ends at {_where(end)}, which can lie inside the stock ({stock.describe()})", span, state, tool)
            return
        if _enters(stock, end, end, tool) is not None:
            self.report(self.rule_id, span, f"{what} ends at {_where(end)}, inside the stock ({stock.describe()}): the tool crashes into the blank at rapid")
        else:
            self._unknown_position(span, f"{what} to {_where(end)} starts where ncverify does not know the tool is (before the first move, or after a reference return): its path was not checked", state)

    def _unknown_position(self, span, message, state, why: str = "rapid-from-unknown"):
        """Once per path and reason: a rapid whose path cannot be placed is unknown, never safe."""
        if self.first_time(state, why):
            self.report(self.rule_id, span, message, Status.UNKNOWN, "position unknown")

    def _symbolic(self, stock, start, end, span, what, state, tool):
        condition = _may_enter(stock, start, end, tool, self.checker.context.rapid_path == "dogleg")
        self._judge(condition, f"{what} from {_where(start)} to {_where(end)} passes through the stock ({stock.describe()})", span, state, tool)

    def _judge(self, condition, message, span, state, tool):
        """A symbolic verdict; with no tool radius known only the tool's axis was judged,
        which proves nothing about its side: ``proved`` becomes ``unknown``."""
        verdict = self.checker.judge(Condition(condition), state)
        if (verdict is not None and verdict.status is Status.PROVED and tool is None and self.checker.context.stock.kind != "cylinder"
                and tool_axis_problem(state) is None):  # along another axis: the state the rule does not read says so
            verdict = Verdict(Status.UNKNOWN, reason="tool radius not known: only the tool's axis was shown clear of the stock")
        self.checker.report_verdict(self.rule_id, span, message, verdict, state)

    @staticmethod
    def _message(what, start, end, hit, stock, cut: bool = False) -> str:
        where = "material left by the cuts so far" if cut else "the blank"
        return (f"{what} from {_where(start)} to {_where(end)} passes through the stock ({stock.describe()}) near {_where(hit)}: "
                f"the tool crashes into {where} at rapid")


def _rises(segment, state) -> bool:
    """Does the rapid only rise along the tool's axis (+Z), or not move? Wherever the tip
    truly is, such a move takes the tool through nothing it is not in already. Not known
    where X or Y is not (an unknown end may lie anywhere beside an unknown start)."""
    start, end = segment.start, segment.end
    if tool_axis_problem(state) is not None or any(start.get(axis) is None or start.get(axis) != end.get(axis) for axis in "XY"):
        return False
    low, high = start.get("Z"), end.get("Z")
    if high is None:
        return "Z" in state.parked  # to the reference position, up the tool's axis
    return type(low) is float and type(high) is float and high >= low


@rule("core.stock-model-too-large")
class StockModelTooLarge(Rule):
    """The stock as cut so far did not fit the memory cap (the blank, or the copies forked
    paths need): said once, where the first move after it was judged against the blank."""
    judges_cycle_runs = True

    handles_arcs = True  # any move, arcs too

    def segment(self, segment, state):
        self._note(segment.span)

    def motion_run(self, run, state):
        self._note(run.span(0))

    def _note(self, span) -> None:
        why = self.checker.material.too_large
        if why is not None:
            self.report("core.stock-model-too-large", span, f"{why}: rapids are judged against the raw blank instead "
                        "(retracts out of cut material may be reported; raise --stock-resolution or give the tool table)", Status.UNKNOWN, why)


@rule("core.clearance-below-stock")
class ClearanceBelowStock(_NeedsStock):
    """A hole's R point or initial level (the G98 return level) inside the stock: below its
    top, or past the face the tool comes from along another tool axis or sign (Fagor
    ``#TOOL AX [X-]``: ``hole.up``)."""
    judges_holes_before_moves = True  # against the blank, and against the cut stock once the moves held back are handed on

    rule_id = "core.clearance-below-stock"
    reads = modelled.GEOMETRY | {modelled.TOOL_AXIS}  # the levels are taken along the hole's own axis and side

    def hole(self, hole, state):
        axis = hole.drill_axis
        if hole.model.r_incremental or hole.model.infeed == "back_bore":
            return
        stock = self.stock(hole.definition or hole.span, state)
        if stock is None:
            return
        if axis != "Z" and (axis not in ("X", "Y") or stock.kind != "box"):
            self._face_not_modelled(hole, axis, stock, state)  # a polygon's or bar's face along X/Y depends on where the hole is
            return
        ranges = geometry.stock_box(stock) or (None, None, stock.z_range)
        over_stock = self._over_stock(stock, hole.position) if axis == "Z" else _across(ranges, axis, hole.position)
        if over_stock is False:
            return
        low, high = ranges["XYZ".index(axis)]
        face = high if hole.up > 0 else low
        for level, name, span in ((hole.r_point, "R point", hole.param_spans.get("R", hole.span)), (hole.initial, "initial level", hole.definition or hole.span)):
            key = ("clearance violated", hole.definition, name)
            if level is None or key in state.rule_state:
                continue  # each hole is judged until one shows the violation: holes differ in position
            inside = hazard("<", level, face - geometry.EPSILON) if hole.up > 0 else hazard(">", level, face + geometry.EPSILON)
            if inside is False:
                continue  # a level of plain numbers outside the stock: plainly clear (asked at every hole)
            verdict = self.checker.judge(both(over_stock, inside), state)
            if axis == "Z" and hole.up > 0:
                verdict = self._against_cuts(verdict, hole.position, level, state)
            if verdict is None:
                continue  # plainly clear: nothing to word (every hole of a pattern is judged)
            if verdict.status is Status.VIOLATED:
                state.rule_state[key] = True
            where = f"below the top of the stock Z{face:g}" if axis == "Z" and hole.up > 0 else f"past the stock's face {axis}{face:g} on the side the tool comes from"
            self.checker.report_verdict(self.rule_id, span, f"{cycle_code(hole.cycle)}: the {name} {axis}{show(level)} is {where}: "
                                        f"the cycle rapids into the material there", verdict, state)

    def _against_cuts(self, verdict, position: dict, level, state):
        """A level below the blank's top may lie in a pocket this program has already cut
        (drilling the floor of a milled slot): the cut stock decides where it knows, and
        where it cannot tell the level is ``unknown``, not a rapid into the material."""
        x, y = position.get("X"), position.get("Y")
        if verdict is None or verdict.status is not Status.VIOLATED or not all(type(value) is float for value in (x, y, level)):
            return verdict
        self.checker.hand_on_held_moves()  # the holes before this one are cut first, as block by block
        if self.checker.material.stayed_above(level, state) is not None:
            return verdict  # cuts placed by free parameters: their assumed ranges, not the grid, say where they went
        left = self.checker.material.rapid((x, y, level), (x, y, level), state)
        if left is None or left.outcome == "hits":
            return verdict
        if left.outcome == "clear":
            return None
        return Verdict(Status.UNKNOWN, reason="earlier cuts of this program may have removed the material at that level")

    def _face_not_modelled(self, hole, axis: str, stock, state) -> None:
        """Once per cycle definition: the levels were not judged, which is unknown, not safe."""
        if self.first_time(state, ("clearance-face-unknown", hole.definition)):
            self.report(self.rule_id, hole.definition or hole.span,
                        f"{cycle_code(hole.cycle)}: the R point and initial level along {axis} were not compared with the {stock.kind} stock: "
                        "its face along that axis is modelled for a box stock only", Status.UNKNOWN, f"stock face along {axis} not modelled")

    @staticmethod
    def _over_stock(stock, position):
        """True / False, or a condition when the hole position is symbolic (True when it is
        unknown: the levels are judged anyway)."""
        x, y = position.get("X"), position.get("Y")
        if x is None or y is None:
            return True
        if isinstance(x, Sym) or isinstance(y, Sym):
            level = (stock.z_range[0] + stock.z_range[1]) / 2.0
            return Condition(geometry.may_enter_symbolic(stock, (x, y, level), (x, y, level)))
        if stock.kind == "box":
            return stock.x_range[0] < x < stock.x_range[1] and stock.y_range[0] < y < stock.y_range[1]
        if stock.kind == "polygon":
            import shapely

            return stock.outline.contains(shapely.Point(x, y))
        return abs(x) < stock.diameter


def _across(ranges, drill_axis: str, position: dict):
    """Is the hole over the stock's face: its position on the two other axes inside the
    stock's extent there (True when unknown: the levels are judged anyway)?"""
    over = True
    for axis, (low, high) in zip("XYZ", ranges):
        value = position.get(axis)
        if axis != drill_axis and value is not None:
            over = both(both(over, hazard(">", value, low)), hazard("<", value, high))
    return over
