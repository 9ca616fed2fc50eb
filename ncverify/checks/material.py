"""What material is left: each path's workpiece as cut so far, for the rules that ask
whether a move meets the stock (:mod:`ncverify.workpiece` holds the model itself).

The model follows every cutting move the rules see, programmed or made by a cycle, swept by
the tool in the spindle as the tool table describes it. It is kept for a milling blank (box
or polygon) with the tool along +Z and a known frame; a cut it cannot place (an unknown
radius, a symbolic position, a tilted frame, another tool axis) may have removed material
anywhere, which leaves later rapids that meet the blank ``unknown`` rather than ``violated``.
Cuts are buffered and swept in batches: CAM programs are millions of tiny moves.
"""
from __future__ import annotations

import math
from collections import deque

import numpy

from .. import frames, geometry, workpiece
from ..verdict import both, hazard
from ..workpiece import Cutter, RapidVerdict, Workpiece

_KEY = "workpiece"
_FEED = 1  # MotionRun kind code
_FLUSH_AT = 4096  # buffered moves per batch
_RECENT = 64  # straight cuts kept exactly, for rapids back into what they cut
_FAGOR_TOOL_AXIS = "$TOOLAX"  # Fagor's #TOOL AX, as the lowering keeps it
_AXIS_ONLY = Cutter(0.0)  # the sweep of a tool whose radius is not known
_TOUCH = 1e-6  # mm: a rapid this close to the deepest cut is not below it
_POINTED = {"drill", "spot", "chamfer"}
_FLAT = {"endmill", "facemill", "slot", "reamer", "boring", "threadmill", "tap"}
_NOT_CUTTING = {"probe"}
AUTO_RESOLUTION = (0.05, 1.0)  # bounds of the resolution chosen from the smallest tool


class _PathPiece:
    """One path's workpiece and its buffered cuts. Paths that fork share it until one of
    them cuts (the interpreter calls ``forked`` on rule memory when a path forks)."""

    __slots__ = ("piece", "lines", "chords", "shared", "symbolic", "recent", "deepest", "sizeless")

    def __init__(self, piece: Workpiece):
        self.piece, self.lines, self.chords, self.shared = piece, [], [], False
        self.symbolic: list[tuple[dict, dict]] = []  # cuts whose place depends on free parameters
        self.recent: deque = deque(maxlen=_RECENT)  # the last straight cuts, exactly: (start, end, cutter)
        self.deepest = math.inf  # the lowest any tool tip has cut: below it, the blank is whole
        self.sizeless = False  # a tool of unknown size has cut (swept as its axis only)

    def forked(self) -> None:
        self.shared = True

    def sized(self, cutter):
        """The cutter to sweep: a tool whose size the table does not give (``False``) is
        swept as its axis alone, so what it removed is counted along that line only and
        the rapids after it are judged nearly as against the blank (and say so)."""
        if cutter is False:
            self.sizeless = True
            return _AXIS_ONLY
        return cutter

    def unplaced(self) -> None:
        """A cut that cannot be placed: material may be gone anywhere, at any depth."""
        self.piece.cut_anywhere()
        self.deepest = -math.inf

    def own(self, state) -> "_PathPiece":
        if not self.shared:
            return self
        mine = _PathPiece(self.piece.copy())
        mine.lines, mine.chords, mine.symbolic = list(self.lines), list(self.chords), list(self.symbolic)
        mine.recent = deque(self.recent, maxlen=_RECENT)
        mine.deepest, mine.sizeless = self.deepest, self.sizeless
        state.rule_state[_KEY] = mine
        return mine


class Material:
    """The checker's view of the material left, per path."""

    def __init__(self, checker):
        self.checker = checker
        context, settings = checker.context, checker.settings
        self.stock = context.stock
        self.tools = context.tools
        self.resolution = _resolution(self.stock, self.tools, context.machine.kind, settings)
        self.air: dict[str, list[float]] = {}  # tool -> [feed length, air length]
        self.final: Workpiece | None = None
        self._run, self._run_done = None, 0

    @property
    def modelled(self) -> bool:
        return self.resolution is not None

    # -- events, after the rules have seen them
    def segment(self, segment, state) -> None:
        if not self.modelled or segment.kind == "rapid" or other_workpiece(self.checker.context, state) is not None:
            return
        cutter = self._cutter(state)
        if cutter is None:
            return  # a probe: it touches, it does not cut
        mine = self._holder(state).own(state)
        if not self._placeable(segment.start, segment.end, state):
            mine.unplaced()
            if tool_axis_problem(state) is None:
                mine.symbolic.append((segment.start, segment.end))
            return
        start, end = _point(segment.start), _point(segment.end)
        if segment.arc is not None:
            chords = self._chords(segment, start, end)
            if chords is None:
                mine.unplaced()
                return
            mine.deepest = min(mine.deepest, float(chords[0][:, 2].min()) - chords[2], end[2] - chords[2])
            mine.chords.append((chords, mine.sized(cutter), _tool_name(state)))
        else:
            mine.deepest = min(mine.deepest, start[2], end[2])
            cutter = mine.sized(cutter)
            mine.lines.append((start, end, cutter, _tool_name(state)))
            mine.recent.append((start, end, cutter))
        if len(mine.lines) + len(mine.chords) >= _FLUSH_AT:
            self._flush(mine)

    def begin_run(self, run) -> None:
        """A batch of moves arrives: none of its feed moves is cut yet."""
        self._run, self._run_done = run, 0

    def motion_run(self, run, state, upto: int | None = None) -> None:
        """Cut the run's feed moves before ``upto`` (all of them when None) not cut yet:
        a rapid inside the run is judged against what the run cut before it."""
        if not self.modelled or run is not self._run or other_workpiece(self.checker.context, state) is not None:
            return
        stop = len(run) if upto is None else upto
        if stop <= self._run_done:
            return
        feeds = self._run_done + numpy.flatnonzero(run.kinds[self._run_done:stop] == _FEED)
        self._run_done = stop
        if not len(feeds):
            return
        cutter = self._cutter(state)
        if cutter is None:
            return
        mine = self._holder(state).own(state)
        if any(axis not in run.axes for axis in "XYZ") or not tool_axis_problem(state) is None:
            mine.unplaced()
            return
        columns = [run.axes.index(axis) for axis in "XYZ"]
        starts, ends = run.points[feeds][:, columns], run.points[feeds + 1][:, columns]
        known = ~(numpy.isnan(starts).any(axis=1) | numpy.isnan(ends).any(axis=1))
        if not known.all():
            mine.unplaced()
        if known.any():
            mine.deepest = min(mine.deepest, float(numpy.minimum(starts[known, 2], ends[known, 2]).min()))
        self._flush(mine)
        self._sweep(mine.piece, starts[known], ends[known], mine.sized(cutter), 0.0, _tool_name(state))

    # -- questions from the rules
    def rapid(self, start, end, state, run=None, index: int | None = None) -> RapidVerdict | None:
        """Does a rapid between two known points meet what is left (None: no model)?"""
        if not self.modelled or not tool_axis_problem(state) is None:
            return None
        if run is not None:
            self.motion_run(run, state, upto=index)
        mine = self._holder(state).own(state)
        self._flush(mine)
        lowest = start if start[2] <= end[2] else end
        if lowest[2] < mine.deepest - _TOUCH and geometry.enters(self.stock, lowest, lowest) is not None:
            return RapidVerdict("hits", tuple(lowest))  # deeper than any cut has gone, inside the blank: whatever the tools' sizes
        cutter = self._rapid_cutter(state)
        verdict = mine.piece.rapid(start, end, cutter)
        if cutter.radius <= 0.0:  # the tool's size is not known: its axis can show a hit, never that its side is clear
            return verdict if verdict.outcome == "hits" else RapidVerdict("unsure")
        if verdict.outcome == "unsure" and any(_inside_cut(start, end, cutter, cut) for cut in mine.recent):
            return RapidVerdict("clear")
        return verdict

    def has_cut(self, state) -> bool:
        holder = state.rule_state.get(_KEY)
        return holder is not None and holder.piece.cuts > 0

    def sizeless_cuts(self, state) -> bool:
        """Some cut on this path was made by a tool whose size the table does not give."""
        holder = state.rule_state.get(_KEY)
        return holder is not None and holder.sizeless

    def stayed_above(self, level: float, state):
        """A hazard condition: every cut placed by free parameters stayed above ``level``
        (None when there were no such cuts). Its witness is a set of values for which the
        earlier cuts may have left material where a rapid goes; the concrete replay of the
        witness then says whether the rapid really meets it."""
        holder = state.rule_state.get(_KEY)
        if holder is None or not holder.symbolic:
            return None
        condition = True
        for start, end in holder.symbolic:
            for point in (start, end):
                depth = point.get("Z")
                if depth is None:
                    return None
                condition = both(condition, hazard(">", depth, level))
        return condition

    def finish(self, state) -> None:
        """At a path's end: sweep what is buffered, and keep the first path's result."""
        holder = state.rule_state.get(_KEY)
        if holder is None:
            return
        mine = holder.own(state)
        self._flush(mine)
        if self.final is None:
            self.final = mine.piece

    # -- the pieces
    def _holder(self, state) -> _PathPiece:
        holder = state.rule_state.get(_KEY)
        if holder is None:
            holder = state.rule_state[_KEY] = _PathPiece(Workpiece(self.stock, self.resolution, self._memory_cap))
        return holder

    @property
    def _memory_cap(self) -> int:
        return self.checker.settings.stock_memory

    def _flush(self, mine: _PathPiece) -> None:
        for tool, group in _by_tool(mine.lines):
            starts, ends, cutter = numpy.array([item[0] for item in group]), numpy.array([item[1] for item in group]), group[0][2]
            self._sweep(mine.piece, starts, ends, cutter, 0.0, tool)
        for (starts, ends, sagitta), cutter, tool in mine.chords:
            self._sweep(mine.piece, starts, ends, cutter, sagitta, tool)
        mine.lines, mine.chords = [], []

    def _sweep(self, piece: Workpiece, starts, ends, cutter: Cutter, stray: float, tool: str) -> None:
        if not len(starts):
            return
        air = piece.cut(starts, ends, cutter, stray)
        totals = self.air.setdefault(tool, [0.0, 0.0])
        totals[0] += float(numpy.linalg.norm(ends - starts, axis=1).sum())
        totals[1] += air

    def _chords(self, segment, start, end):
        arc = segment.arc
        plane = tuple("XYZ".index(axis) for axis in arc.plane)
        if arc.centre is None or any(type(value) is not float for value in arc.centre):
            return None
        return workpiece.arc_chords(start, end, arc.centre, arc.direction == "cw", plane, tolerance=self.resolution / 8.0)

    def _placeable(self, start: dict, end: dict, state) -> bool:
        return tool_axis_problem(state) is None and all(type(point.get(axis)) is float for point in (start, end) for axis in "XYZ")

    def _cutter(self, state):
        """The swept shape of the tool in the spindle: a Cutter, None for a tool that does
        not cut (a probe), False when it is not known."""
        tool = self.tools.in_spindle(state)
        if tool is None or tool.radius is None or tool.radius <= 0.0:
            return False
        if tool.type in _NOT_CUTTING:
            return None
        return cutter_of(tool)

    def _rapid_cutter(self, state) -> Cutter:
        """For a rapid, a tool of unknown size is at least its axis: a thin flat rod."""
        cutter = self._cutter(state)
        return cutter if isinstance(cutter, Cutter) else Cutter(0.0)


_STOCK_OFFSET = "stock work offset"  # rule_state: the work offset the path first met the stock under


def other_workpiece(context, state) -> str | None:
    """Why the stock may not be the workpiece here: the stock is the blank under the work
    offset in force where a path first meets it, and a program that changes the offset
    usually machines another part or fixture there. None when the offset is that one, or
    both are named in ``[machine] one_workpiece``."""
    name = state.modal.get("work_offset", "G54")
    first = state.rule_state.setdefault(_STOCK_OFFSET, name)
    if name == first or {name, first} <= context.machine.one_workpiece:
        return None
    return (f"the work offset changed from {first} to {name}: a second offset usually holds another part or fixture, so the stock "
            f"(described for {first}) was not compared (if both hold the one blank, list them in [machine] one_workpiece)")


def tool_axis_problem(state) -> str | None:
    """Why the tool is not known to stand along +Z of the workpiece, or None."""
    if state.plane_axes[2] != "Z":
        return f"the tool axis is {state.plane_axes[2]} (working plane)"
    axis = state.global_variables.get(_FAGOR_TOOL_AXIS)
    if axis is not None and axis != 3.0:
        return "#TOOL AX sets a tool axis other than Z+"
    frame = frames.program_to_workpiece(state)
    if frame is not None and not (frame.keeps_axis("Z") and type(frame.linear[2][2]) is float and frame.linear[2][2] > 0):
        return "the active frame turns or mirrors the tool axis"
    return None


def cutter_of(tool) -> Cutter:
    """A tool table entry as the shape the model sweeps."""
    kind = tool.type
    if kind == "ball":
        return Cutter(tool.radius, corner=tool.radius)
    if kind == "bullnose" and tool.corner is not None:
        return Cutter(tool.radius, corner=min(tool.corner, tool.radius))
    if kind in _POINTED and (tool.point_angle or tool.angle):
        return Cutter(tool.radius, point_angle=tool.point_angle or tool.angle)
    if kind in _FLAT:
        return Cutter(tool.radius)
    return Cutter(tool.radius, known=False)


def _resolution(stock, tools, machine, settings) -> float | None:
    """The cell size when the model is kept; None when rapids are judged against the blank:
    turned off, no stock, a lathe bar, or a requested resolution over the memory cap."""
    wanted, cap = settings.stock_resolution, settings.stock_memory
    if wanted == 0 or stock is None or machine == "lathe" or stock.kind not in ("box", "polygon"):
        return None
    x_low, y_low, x_high, y_high = workpiece.outline(stock).bounds
    area = (x_high - x_low) * (y_high - y_low)
    if wanted is not None:
        return wanted if area / wanted ** 2 * 8 <= cap else None
    radii = [tool.radius for tool in tools.values() if tool.radius]
    chosen = min(max(min(radii) / 4.0 if radii else 0.5, AUTO_RESOLUTION[0]), AUTO_RESOLUTION[1])
    fitting = math.sqrt(area * 8 / cap) * 1.01
    return max(chosen, fitting)


def _tool_name(state) -> str:
    number = state.tool_in_spindle
    return f"T{number:g}" if type(number) is float else "T?"


def _point(position: dict) -> tuple[float, float, float]:
    return position["X"], position["Y"], position["Z"]


def _by_tool(lines):
    """Consecutive buffered lines grouped by their tool (the cutter goes with the name)."""
    group: list = []
    for item in lines:
        if group and (item[3] != group[-1][3] or item[2] != group[-1][2]):
            yield group[0][3], group
            group = []
        group.append(item)
    if group:
        yield group[0][3], group


def _inside_cut(start, end, cutter: Cutter, cut) -> bool:
    """The rapid stays inside the volume one straight cut swept, exactly (no grid): its tool
    disc within the cut's at both ends (the room left is convex, so then all along), and
    its tip no lower than the cut's tool end reached. A rapid back down into the slot just
    cut, with the tool that cut it, needs this: on the grid its walls are within a cell."""
    cut_start, cut_end, cut_cutter = cut
    if cutter.radius > cut_cutter.radius or (cutter.known and not cut_cutter.known):
        return False
    room = cut_cutter.radius - cutter.radius
    a, b = numpy.array([cut_start[:2]]), numpy.array([cut_end[:2]])
    ends = numpy.array([start[:2], end[:2]])
    reach = workpiece.distance_to_segment(ends[:, 0], ends[:, 1], numpy.repeat(a, 2, axis=0), numpy.repeat(b, 2, axis=0))
    deepest_cut = max(cut_start[2], cut_end[2]) + float(cut_cutter.lift(numpy.array([cut_cutter.radius]))[0])
    return bool((reach <= room).all()) and min(start[2], end[2]) >= deepest_cut
