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

import functools
import math
import weakref
from collections import deque

import numpy

from . import frames, geometry, workpiece, xy_arcs
from .context import active_edge, compensated, off_path, radius_delta
from .dialect import DIALECTS
from . import turning_stock
from .turning_stock import Turning
from .verdict import both, hazard, show
from .trace import ARC_CW
from .xy_arcs import XYArcs
from .workpiece import Cutter, RapidVerdict, Workpiece

_KEY = "workpiece"
_FEED = 1  # MotionRun kind code
_FLUSH_AT = 4096  # buffered moves per batch
_RECENT = 64  # straight cuts kept exactly, for rapids back into what they cut
_AXIS_ONLY = Cutter(0.0)  # the sweep of a tool whose radius is not known
_TOUCH = 1e-6  # mm: a rapid this close to the deepest cut is not below it
_POINTED = {"drill", "spot", "chamfer"}
_FLAT = {"endmill", "facemill", "slot", "reamer", "boring", "threadmill", "tap"}
_NOT_CUTTING = {"probe"}
AUTO_RESOLUTION = (0.05, 1.0)  # bounds of the resolution chosen from the smallest tool
_FIELD_BYTES_PER_CELL = 8  # two float32 bounds
_ARC_PART_CELLS = 16  # longest part of an arc swept as one piece, in cells: a part that meets material counts whole as cutting
_ARC_WIDTHS = (3, 3, 2, 1, 3)  # columns of a buffered arc's fields: start, end, centre, clockwise, plane axes (see _flush)


class _PathPiece:
    """One path's workpiece and its buffered cuts. Paths that fork share it until one of
    them cuts (the interpreter calls ``forked`` on rule memory when a path forks). ``piece``
    None: past the memory cap, this path is judged against the blank."""

    __slots__ = ("piece", "lines", "arcs", "buffered", "sharers", "symbolic", "recent", "deepest", "sizeless", "last_arc", "rounded_next")

    def __init__(self, piece: Workpiece | None):
        self.piece, self.lines, self.arcs, self.sharers = piece, [], [], 1  # lines (in runs of moves) and arcs buffered, not cut yet
        self.buffered = 0  # moves buffered: straight ones and arcs
        self.symbolic: list[tuple[dict, dict]] = []  # cuts whose place depends on free parameters
        self.recent: deque = deque(maxlen=_RECENT)  # the last straight cuts, exactly: (start, end, cutter)
        self.deepest = math.inf  # the lowest any tool tip has cut (arcs counted when swept): below it, the blank is whole
        self.sizeless = False  # a tool of unknown size has cut (swept as its axis only)
        self.last_arc = False  # the last cut buffered is the last arc (else the last straight move)
        self.rounded_next = False  # the next cut starts at a rounded or chamfered corner (see Material.corner_rounded)

    def forked(self) -> None:
        self.sharers += 1

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
        self.rounded_next = False

    def beside_path(self, lowest: float) -> None:
        """A cut off its programmed path: under radius compensation the tool's centre runs
        beside it by an offset the program does not fix (the register's value, a wear
        value, a stock allowance left by a larger offset), and at a rounded or chamfered
        corner it cuts the corner off. Where it cut is not known; how deep is (``lowest``:
        the tip's lowest point, which neither moves)."""
        self.piece.cut_anywhere()
        self.deepest = min(self.deepest, lowest)
        self.rounded_next = False

    def take_back_last_cut(self) -> float | None:
        """Take the last cut out of the buffer (a flush waits for the cut after it); the
        lowest point of its tip, or None when the buffer holds none."""
        entries = self.arcs if self.last_arc else self.lines
        if not entries:
            return None
        entry = entries.pop()
        fields = entry[0] if self.last_arc else entry[:2]
        starts, ends = fields[0], fields[1]
        lowest = min(starts[-1][2], ends[-1][2])
        if len(starts) > 1:
            shorter = tuple(field[:-1] for field in fields)
            entries.append((shorter, *entry[1:]) if self.last_arc else (*shorter, *entry[2:]))
        self.buffered -= 1
        if self.recent and not self.last_arc:
            self.recent.pop()
        return float(lowest)

    def take_over(self, shared: "_PathPiece") -> None:
        """Carry on from the workpiece's twin this path shared until now."""
        self.lines, self.arcs, self.symbolic = list(shared.lines), list(shared.arcs), list(shared.symbolic)
        self.buffered = shared.buffered
        self.recent = deque(shared.recent, maxlen=_RECENT)
        self.deepest, self.sizeless = shared.deepest, shared.sizeless
        self.last_arc, self.rounded_next = shared.last_arc, shared.rounded_next


class Material:
    """The checker's view of the material left, per path."""

    def __init__(self, checker):
        self.checker = checker
        context, settings = checker.context, checker.settings
        self.stock = context.stock
        self.tools = context.tools
        self.resolution, self.too_large = _resolution(self.stock, self.tools, context.tools_called, context.machine.kind, settings)
        self.turning = Turning(self.stock, self.tools) if turning_stock.kept(self.stock, context.machine.kind, settings) else None
        self.air: dict[str, list[float]] = {}  # tool -> [feed length, air length]
        self.final: Workpiece | None = None
        self._allocated = 0  # bytes of height fields made for this file's paths
        self.holder_rule = None  # the rule judging each feed move's holder and shank against the material before it
        self._run, self._run_done = None, 0
        self._named: tuple = (None, "T?")  # the tool number last named, and its name

    @property
    def modelled(self) -> bool:
        return self.resolution is not None or self.turning is not None

    @property
    def milled(self) -> bool:
        """The height field of a milled blank is kept (not a turned bar)."""
        return self.resolution is not None

    # -- events, after the rules have seen them
    def segment(self, segment, state) -> None:
        if not self.modelled or segment.kind == "rapid" or off_the_blank(self.checker.context, state) is not None:
            return
        if self.turning is not None:
            self.turning.segment(segment, state)
            return
        cutter = self._cutter(state)
        if cutter is None:
            return  # a probe: it touches, it does not cut
        mine = self._mine(state)
        if mine is None:
            return
        start, end = self._placed(segment, state)
        if end is None:
            mine.unplaced()
            if tool_axis_problem(state) is None:
                mine.symbolic.append((segment.start, segment.end))
            return
        offset = self._offset(state)
        if offset is None or mine.rounded_next:
            if segment.arc is None or _plane_indices(segment.arc.plane) == (0, 1, 2):  # an arc about Z keeps between its ends' heights
                mine.beside_path(min(start[2], end[2]))
            else:
                mine.unplaced()
            return
        if segment.arc is not None:
            arc = segment.arc
            centre = arc.centre if arc.centre is not None else _centre_by_radius(arc, start, end)
            if centre is None or type(centre[0]) is not float or type(centre[1]) is not float:
                mine.unplaced()
                return
            self._make_room(mine)
            mine.arcs.append((([start], [end], [centre], [arc.direction == "cw"], [_plane_indices(arc.plane)]), mine.sized(cutter), self._tool_name(state), offset))
            mine.buffered, mine.last_arc = mine.buffered + 1, True
            return
        mine.deepest = min(mine.deepest, start[2], end[2])
        cutter = mine.sized(cutter)
        if not offset:
            mine.recent.append((start, end, cutter))
        self._make_room(mine)
        mine.lines.append(([start], [end], cutter, self._tool_name(state), offset))
        mine.buffered, mine.last_arc = mine.buffered + 1, False

    def _offset(self, state) -> float | None:
        """How far the swept tool may run off the programmed path: 0 without radius
        compensation; under it, where the dialect offsets by the tool's own data
        (:attr:`DialectInfo.offset_is_tool_radius`), the tool's largest radius (with a
        programmed delta) and what that radius exceeds the swept one by. None where the
        offset is a register's value the program does not give, or where every corner is
        rounded (RNDM). Such a cut lowers ``lower`` within the offset and the swept radius
        of its path, and ``upper`` nowhere (the offset is at least that radius)."""
        if state.corners_rounded:
            return None
        if not compensated(state):
            return 0.0
        dialect = DIALECTS.get(self.checker.context.dialect or "")
        if dialect is None or not dialect.offset_is_tool_radius:
            return None
        largest, swept = self._cutter(state, largest=True), self._cutter(state)
        return 2.0 * largest.radius - swept.radius if largest and swept else None

    def _make_room(self, mine: _PathPiece) -> None:
        """Before a move joins the buffer: sweep it when it is full. The sweep waits for the
        move after the last one, which a rounded corner may still take back (see
        :meth:`corner_rounded`)."""
        if mine.buffered >= _FLUSH_AT:
            self._flush(mine)

    def corner_rounded(self, state) -> None:
        """The corner at the tool's position is rounded or chamfered (ISO ``,R``/``,C``,
        SINUMERIK ``RND``/``CHF``, Klartext ``RND``/``CHF``): the tool cuts it off, so the
        cut that ended there and the one that starts there leave their programmed paths
        near it, by as much as the rounding takes; both are taken as cuts off their path."""
        if not self.modelled or off_the_blank(self.checker.context, state) is not None:
            return
        if self.turning is not None:
            self.turning.corner_rounded(state)
            return
        mine = self._mine(state)
        if mine is None:
            return
        lowest = mine.take_back_last_cut()
        if lowest is not None:
            mine.beside_path(lowest)
        mine.rounded_next = True

    def _buffer(self, mine: _PathPiece, starts, ends, cutter: Cutter, tool: str, offset: float = 0.0) -> None:
        """Straight cuts join the buffer, which is swept every ``_FLUSH_AT`` moves and when a
        question needs the field: a batch's moves and the same moves block by block are
        swept in the same groups, so the field (the grid merges neighbouring pieces within
        a sweep) is the same on both paths. ``starts``, ``ends``: sequences of (x, y, z)."""
        for first, stop in self._flush_groups(mine, len(starts)):
            mine.lines.append((starts[first:stop], ends[first:stop], cutter, tool, offset))
            mine.last_arc = False

    def _flush_groups(self, mine: _PathPiece, count: int):
        """``count`` moves join the buffer: ``(first, stop)`` of each group the caller
        buffers, the buffer swept before a group when it is full (see :meth:`_make_room`)."""
        taken = 0
        while taken < count:
            self._make_room(mine)
            window = min(count - taken, _FLUSH_AT - mine.buffered)
            yield taken, taken + window
            mine.buffered += window
            taken += window

    def begin_run(self, run) -> None:
        """A batch of moves arrives: none of its feed moves is cut yet."""
        self._run, self._run_done = run, 0

    def motion_run(self, run, state, upto: int | None = None) -> None:
        """Cut the run's feed moves and arcs before ``upto`` (all of them when None) not cut
        yet, in order: a rapid inside the run is judged against what the run cut before it.
        A part of a run counts where it lies in the whole run."""
        if run.whole is not None:
            upto, run = run.first + (len(run) if upto is None else upto), run.whole
        if not self.modelled or run is not self._run or off_the_blank(self.checker.context, state) is not None:
            return
        stop = len(run) if upto is None else upto
        done = self._run_done
        if stop <= done:
            return
        self._run_done = stop
        if run.arcs is None:
            self._cut_straight(run, done + numpy.flatnonzero(run.kinds[done:stop] == _FEED), state)
            return
        if not self._cut_from_arrays(run, done, stop, state):
            self._cut_one_by_one(run, done, stop, state)

    def _cut_one_by_one(self, run, done: int, stop: int, state) -> None:
        """Moves ``done`` to ``stop`` of a run with arcs: each stretch of straight moves as
        one, each arc as the block path cuts it (the holder rule judges it, then
        :meth:`segment` cuts it)."""
        arcs = (done + numpy.flatnonzero(run.kinds[done:stop] >= ARC_CW)).tolist()
        for begin, end in zip([done] + [index + 1 for index in arcs], arcs + [stop]):
            self._cut_straight(run, begin + numpy.flatnonzero(run.kinds[begin:end] == _FEED), state)
            if end < stop:
                segment = run.segment(end)
                self.holder(segment, state)
                self.segment(segment, state)

    def _cut_from_arrays(self, run, done: int, stop: int, state) -> bool:
        """Moves ``done`` to ``stop`` of a run with arcs, straight from the arrays, buffered
        as the block path buffers them move by move (the same moves swept at each flush);
        False, having done nothing, where that needs more than the arrays: the lathe's
        model, the holder judged move by move, a position not known, a tool axis other than
        Z. An arc given by its radius is placed as the control places it
        (:func:`xy_arcs.radius_arc_centres`); where no circle of that radius fits, it is cut
        anywhere."""
        if self.turning is not None or tool_axis_problem(state) is not None or any(axis not in run.axes for axis in "XYZ"):
            return False
        cutting = done + numpy.flatnonzero(run.kinds[done:stop] >= _FEED)
        columns = [run.axes.index(axis) for axis in "XYZ"]
        starts, ends = run.points[cutting][:, columns], run.points[cutting + 1][:, columns]
        by_radius = ~numpy.isnan(run.arcs.radii[cutting])
        by_centre = (run.kinds[cutting] != _FEED) & ~by_radius
        if numpy.isnan(starts).any() or numpy.isnan(ends).any() or numpy.isnan(run.arcs.centres[cutting[by_centre]]).any():
            return False
        centres = run.arcs.centres[cutting]  # a copy (indexed by an array)
        if by_radius.any():
            in_plane = list(_plane_indices(run.arcs.plane)[:2])
            centres[by_radius] = xy_arcs.radius_arc_centres(starts[by_radius][:, in_plane], ends[by_radius][:, in_plane], run.arcs.radii[cutting[by_radius]],
                                                            run.kinds[cutting[by_radius]] == ARC_CW)
            by_radius &= numpy.isnan(centres[:, 0])  # no circle of that radius fits: cut anywhere
        if len(cutting) and self._holder_reaches(state, numpy.minimum(starts[:, 2], ends[:, 2])).any():
            return False
        if not len(cutting):
            return True
        cutter = self._cutter(state)
        mine = None if cutter is None else self._mine(state)
        if mine is None:
            return True  # a probe, or a path judged against the blank
        if mine.rounded_next:
            return False  # the first cut starts at a rounded corner: segment() takes it
        offset = self._offset(state)
        if offset is None:  # as segment() takes each move
            if (run.kinds[cutting] == _FEED).all() or _plane_indices(run.arcs.plane) == (0, 1, 2):
                mine.beside_path(float(numpy.minimum(starts[:, 2], ends[:, 2]).min()))
            else:
                mine.unplaced()
            return True
        for _ in range(int(numpy.count_nonzero(by_radius))):  # no centre: cut anywhere, not buffered, as in segment()
            mine.unplaced()
        cutting, starts, ends, centres = cutting[~by_radius], starts[~by_radius], ends[~by_radius], centres[~by_radius]
        straight = run.kinds[cutting] == _FEED
        centres = centres[~straight]
        sized, tool = mine.sized(cutter), self._tool_name(state)
        if straight.any():
            mine.deepest = min(mine.deepest, float(numpy.minimum(starts[straight, 2], ends[straight, 2]).min()))
            for start, end in zip(starts[straight][-_RECENT:].tolist(), ends[straight][-_RECENT:].tolist()) if not offset else ():
                mine.recent.append((tuple(start), tuple(end), sized))
        arcs = (starts[~straight], ends[~straight], centres, run.kinds[cutting[~straight]] == ARC_CW,
                numpy.tile(_plane_indices(run.arcs.plane), (len(centres), 1)))
        arcs_taken = 0
        for first, stop in self._flush_groups(mine, len(cutting)):
            lines = straight[first:stop]
            if lines.any():
                rows = numpy.flatnonzero(lines) + first
                mine.lines.append((starts[rows], ends[rows], sized, tool, offset))
            arc_count = stop - first - int(numpy.count_nonzero(lines))
            if arc_count:
                mine.arcs.append((tuple(field[arcs_taken:arcs_taken + arc_count] for field in arcs), sized, tool, offset))
            arcs_taken += arc_count
        if len(straight):
            mine.last_arc = not bool(straight[-1])
        return True

    def _cut_straight(self, run, feeds, state) -> None:
        """Cut the run's straight feed moves ``feeds`` (indices into the run)."""
        if not len(feeds):
            return
        if self.turning is not None:
            self.turning.cut_run(run, feeds, state)
            return
        cutter = self._cutter(state)
        if cutter is None:
            return
        mine = self._mine(state)
        if mine is None:
            return
        if any(axis not in run.axes for axis in "XYZ") or not tool_axis_problem(state) is None:
            self._not_placed(mine, run, feeds, state)
            return
        columns = [run.axes.index(axis) for axis in "XYZ"]
        starts, ends = run.points[feeds][:, columns], run.points[feeds + 1][:, columns]
        known = ~(numpy.isnan(starts).any(axis=1) | numpy.isnan(ends).any(axis=1))
        if not known.all():
            self._not_placed(mine, run, feeds[~known], state)
        offset = self._offset(state)
        if known.any() and offset is None:  # as segment() takes each move
            mine.beside_path(float(numpy.minimum(starts[known, 2], ends[known, 2]).min()))
            return
        if known.any() and mine.rounded_next:  # the first starts at a rounded corner: as segment() takes it
            first = int(numpy.flatnonzero(known)[0])
            mine.beside_path(min(float(starts[first, 2]), float(ends[first, 2])))
            known[first] = False
        if known.any():
            mine.deepest = min(mine.deepest, float(numpy.minimum(starts[known, 2], ends[known, 2]).min()))
        sized = mine.sized(cutter)
        for start, end in zip(starts[known][-_RECENT:].tolist(), ends[known][-_RECENT:].tolist()) if not offset else ():  # as the block path keeps them
            mine.recent.append((tuple(start), tuple(end), sized))
        starts, ends, feeds, tool = starts[known], ends[known], feeds[known], self._tool_name(state)
        done = 0
        for move in numpy.flatnonzero(self._holder_reaches(state, numpy.minimum(starts[:, 2], ends[:, 2]))).tolist():
            # as the block path takes them: the moves before buffered, this one judged against what they left, then buffered
            self._buffer(mine, starts[done:move], ends[done:move], sized, tool, offset)
            self._flush(mine)
            self._judge_holder(mine.piece, starts[move], ends[move], self._holder_parts(state), run.span(int(feeds[move])), state)
            done = move
        self._buffer(mine, starts[done:], ends[done:], sized, tool, offset)

    @staticmethod
    def _not_placed(mine: _PathPiece, run, moves, state) -> None:
        """Moves of a run the model cannot place, taken as :meth:`segment` takes them: the
        material may be gone anywhere, and with the tool along +Z their ends are kept for
        :meth:`stayed_above`."""
        mine.unplaced()
        if tool_axis_problem(state) is None:
            for index in moves.tolist():
                segment = run.segment(index)
                mine.symbolic.append((segment.start, segment.end))

    # -- questions from the rules
    def rapid(self, start, end, state, run=None, index: int | None = None) -> RapidVerdict | None:
        """Does a rapid between two known points meet what is left (None: no model)?"""
        if self.turning is not None:
            if run is not None:
                self.motion_run(run, state, upto=index)
            return self.turning.rapid(start, end, state)
        if not self.modelled or not tool_axis_problem(state) is None:
            return None
        if run is not None:
            self.motion_run(run, state, upto=index)
        mine = self._current(state)
        if mine is None or mine.piece.cuts == 0:
            return None  # nothing cut yet on this path: the blank's exact check decides, not the grid
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

    def holder(self, segment, state) -> None:
        """Before a feed move is cut: its tool's non-cutting parts against what is left (the
        moves of a batch are judged as :meth:`motion_run` cuts them; nothing where the stock is
        not compared, :func:`off_the_blank`, as no move is cut there)."""
        if not self.milled or segment.kind == "rapid" or not self._holder_parts(state) or off_the_blank(self.checker.context, state) is not None:
            return
        start, end = self._placed(segment, state)
        if end is None or not self._holder_reaches(state, numpy.array([min(start[2], end[2])]))[0] or (mine := self._current(state)) is None:
            return
        for a, b in ((start, start), (end, end)) if segment.arc is not None else ((start, end),):  # an arc's tool is surely at its ends
            self._judge_holder(mine.piece, a, b, self._holder_parts(state), segment.span, state)

    def _holder_parts(self, state) -> list:
        return self.holder_rule.parts(state) if self.holder_rule is not None else []

    def _holder_reaches(self, state, lowest):
        """Can a non-cutting part of the tool meet material on moves whose tips go down to
        ``lowest`` (one a move)? Not where every part's bottom stays above the blank's top,
        where no material ever is: shallow cuts (most of them) are then swept in batches,
        not move by move. Nor under radius compensation, where the tool's place beside the
        programmed path is not known (its cuts are not placed either: :meth:`_PathPiece.beside_path`)."""
        parts = self._holder_parts(state)
        if not parts or off_path(state):
            return numpy.zeros(len(lowest), bool)
        return lowest + min(height for height, _, _ in parts) <= self.stock.z_range[1]

    def _judge_holder(self, piece: Workpiece, start, end, parts, span, state) -> None:
        """Each non-cutting part of the tool (height above the tip, its shape, its name)
        against the material before the move; the first that meets it is reported. A part
        whose bottom stays above the blank's top meets nothing."""
        top = self.stock.z_range[1]
        for height, shape, part in parts:
            if min(start[2], end[2]) + height > top:
                continue
            verdict = piece.rapid(*[(point[0], point[1], point[2] + height) for point in (start, end)], shape)
            if verdict.outcome == "hits":
                self.holder_rule.collides(span, start, end, part, verdict.point, state)
                return

    def has_cut(self, state) -> bool:
        if self.turning is not None:
            return self.turning.has_cut(state)
        holder = state.rule_state.get(_KEY)
        return holder is not None and holder.piece is not None and holder.piece.cuts > 0

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
        if self.turning is not None:
            self.turning.finish(state)
            return
        if state.rule_state.get(_KEY) is None or (mine := self._current(state)) is None:
            return
        if self.final is None:
            self.final = mine.piece

    # -- the pieces
    def _holder(self, state) -> _PathPiece:
        holder = state.rule_state.get(_KEY)
        if holder is None:
            holder = state.rule_state[_KEY] = _PathPiece(self._allocate(
                lambda: Workpiece(self.stock, self.resolution, self._memory_cap, deferred=not self.checker.settings.air_cutting)))
        return holder

    def _tool_name(self, state) -> str:
        """"T3" for the tool in the spindle, "T?" when not known; asked on every cutting move,
        named anew only when the number is another value object (a tool change)."""
        number, name = self._named
        if state.tool_in_spindle is not number:
            number = state.tool_in_spindle
            name = f"T{number:g}" if type(number) is float else "T?"
            self._named = (number, name)
        return name

    def _mine(self, state) -> _PathPiece | None:
        """This path's own workpiece, copied from the one it shares with the paths it forked
        from; None when the copy would take the fields of all paths over the memory cap:
        this path is then judged against the blank (and the rules say so)."""
        holder = self._holder(state)
        if holder.piece is None:
            return None
        if holder.sharers == 1:
            return holder
        holder.sharers -= 1  # the last path left on it cuts it without a copy
        mine = _PathPiece(self._allocate(holder.piece.copy))
        if mine.piece is not None:
            mine.take_over(holder)
        state.rule_state[_KEY] = mine
        return mine if mine.piece is not None else None

    def _current(self, state) -> _PathPiece | None:
        """This path's workpiece as cut so far, to look at: its buffered cuts swept, but no
        copy made when it is shared (the paths sharing it share those cuts too)."""
        holder = self._holder(state)
        if holder.piece is not None:
            self._flush(holder)
        return holder if holder.piece is not None else None

    def _allocate(self, make) -> Workpiece | None:
        """A new height field from ``make`` while the fields made so far stay under the cap."""
        cells = self._field_bytes()
        if self._allocated + cells > self._memory_cap:
            self.too_large = (f"the stock as cut so far is not modelled past a fork: the paths' copies of the workpiece would take over the cap of "
                              f"{_mebibytes(self._memory_cap)}")
            return None
        self._allocated += cells
        piece = make()
        # the finalizer holds its callback for as long as the piece lives: a weak one, or this
        # model (and its checker and every piece it holds) would never be freed
        weakref.finalize(piece, _release, weakref.WeakMethod(self._release), cells)
        return piece

    def _release(self, cells: int) -> None:
        self._allocated -= cells

    def _field_bytes(self) -> int:
        x_low, y_low, x_high, y_high = workpiece.outline(self.stock).bounds
        return math.ceil((x_high - x_low) / self.resolution) * math.ceil((y_high - y_low) / self.resolution) * _FIELD_BYTES_PER_CELL

    @property
    def _memory_cap(self) -> int:
        return self.checker.settings.stock_memory

    def _flush(self, mine: _PathPiece) -> None:
        """Sweep what the buffer holds: each tool's lines in one sweep, in the order the
        tools first cut, then each tool's arcs (many arcs' chords in one sweep). Sweeps only
        lower the bounds, so their order does not change the field; grouping changes which
        moves merge into one chord, and the air statistic (judged before each sweep). One
        sweep a tool, not one each time the tools take turns: a post that drills each part
        after milling it swept two small batches a part, and a sweep costs a fixed time
        besides its moves."""
        for (cutter, tool, offset), group in _by_tool(mine.lines, 2):
            starts, ends = (_stacked(line[end] for line in group) for end in (0, 1))
            self._sweep(mine.piece, starts, ends, cutter, offset, tool)
        for (cutter, tool, offset), group in _by_tool(mine.arcs, 1):
            fields = [arcs[0] for arcs in group]
            self._sweep_arcs(mine, *(_stacked((arcs[field] for arcs in fields), width) for field, width in enumerate(_ARC_WIDTHS)), cutter, tool, offset)
        mine.lines, mine.arcs, mine.buffered = [], [], 0

    def _sweep_arcs(self, mine: _PathPiece, starts, ends, centres, clockwise, planes, cutter: Cutter, tool: str, offset: float) -> None:
        """Arcs and helices about the Z axis swept as arcs; the others (other planes, ends
        off their circle, and arcs whose tool runs ``offset`` off them under radius
        compensation) as chords within an eighth of a cell of them, each chord's sagitta
        (and the offset) its stray. An arc whose end lies on its start's ray, off its
        circle, may turn once or not at all (:func:`workpiece.unsettled_turns`): it is a
        cut that cannot be placed."""
        clockwise = clockwise.reshape(-1).astype(bool)
        unsettled = workpiece.unsettled_turns(starts, ends, centres, planes)
        if unsettled.any():
            mine.unplaced()
            settled = ~unsettled
            starts, ends, centres, clockwise, planes = starts[settled], ends[settled], centres[settled], clockwise[settled], planes[settled]
        about_z = (planes == (0, 1, 2)).all(axis=1) & (offset == 0.0)
        about_z[about_z] = xy_arcs.measurable(starts[about_z, :2], ends[about_z, :2], centres[about_z], self.resolution, workpiece.MEASURED_REACH)
        if about_z.any():
            arcs, _ = XYArcs.of(starts[about_z], ends[about_z], centres[about_z], clockwise[about_z], _ARC_PART_CELLS * self.resolution, self.resolution)
            mine.deepest = min(mine.deepest, float(arcs.low.min()))
            air = mine.piece.cut_arcs(arcs, cutter)
            if air is not None:
                self._tally_air(tool, float(arcs.length.sum()), air)
        if about_z.all():
            return
        rest = ~about_z
        starts, ends, sagitta, _ = workpiece.arc_chords(starts[rest], ends[rest], centres[rest], clockwise[rest], planes[rest], tolerance=self.resolution / 8.0)
        mine.deepest = min(mine.deepest, float((numpy.minimum(starts[:, 2], ends[:, 2]) - sagitta).min()))
        self._sweep(mine.piece, starts, ends, cutter, sagitta + offset, tool, joined=False)

    def _sweep(self, piece: Workpiece, starts, ends, cutter: Cutter, stray, tool: str, joined: bool = True) -> None:
        if not len(starts):
            return
        air = piece.cut(starts, ends, cutter, stray, joined)
        if air is not None:  # judged only with Settings.air_cutting (see Workpiece._defer)
            self._tally_air(tool, workpiece.total_length(starts, ends), air)

    def _tally_air(self, tool: str, length: float, air: float) -> None:
        """The tool cut ``length`` of feed moves, ``air`` of which surely cut nothing."""
        totals = self.air.setdefault(tool, [0.0, 0.0])
        totals[0] += length
        totals[1] += air

    @staticmethod
    def _placed(segment, state) -> tuple:
        """The move's (x, y, z) start and end on the model; (None, None) when it cannot be
        placed there: a position not known as a number, or the tool not along +Z."""
        start, end = _known_point(segment.start), _known_point(segment.end)
        if start is None or end is None or tool_axis_problem(state) is not None:
            return None, None
        return start, end

    def _cutter(self, state, largest: bool = False):
        """The swept shape of the tool in the spindle: a Cutter, None for a tool that does
        not cut (a probe), False when it is not known. The radius is the active cutting
        edge's (SINUMERIK D), with a programmed radius delta (Klartext ``TOOL CALL .. DR``)
        counted where it makes the tool smaller, or, for a rapid (``largest``), larger."""
        tool = self.tools.in_spindle(state)
        edge, delta = active_edge(state), radius_delta(state)
        if tool is not None and edge != 1.0:
            tool = tool.edge_data(edge) if type(edge) is float else None
        if tool is None or tool.radius is None or type(delta) is not float:
            return False
        radius = tool.radius + (max(delta, 0.0) if largest else min(delta, 0.0))
        if radius <= 0.0:
            return False
        if tool.type in _NOT_CUTTING:
            return None
        return cutter_of(tool, radius)

    def _rapid_cutter(self, state) -> Cutter:
        """For a rapid, a tool of unknown size is at least its axis: a thin flat rod."""
        cutter = self._cutter(state, largest=True)
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


def off_the_blank(context, state) -> str | None:
    """Why the stock cannot be compared here: the work offset holds another workpiece
    (:func:`other_workpiece`), or the tool's tip is not known to stand at the programmed
    point (:func:`tip_unplaced`)."""
    return other_workpiece(context, state) or tip_unplaced(context, state)


def tip_unplaced(context, state) -> str | None:
    """Why the tool's tip is not known to stand at the programmed point (mapped through the
    frames) beyond what the frames say: state the program changed that the model does not
    follow (a work offset or tool data it wrote, the units it switched), or a tool length
    the control does not apply as the tool's own (:func:`length_problem`)."""
    return state.unfollowed or length_problem(context, state)


def length_problem(context, state) -> str | None:
    """Why the control may not hold the tool's tip at the programmed point along the tool
    axis: G44, the length offset of another tool's register, none at all once the tool
    axis moved after a tool change (where the tool table gives lengths, not on a set-up
    that touches each tool off), or a Klartext ``TOOL CALL .. DL``. None on a lathe, whose
    offsets go with the turret's tool number."""
    if context.lathe:
        return None
    mode, register, tool = state.length_mode, state.length_register, state.tool_in_spindle
    if mode == "minus":
        return "G44 subtracts the length offset, so the tool's tip is not at the programmed Z"
    if mode == "given":
        return "the length offset in force is a value the program gave (G43.1, G43.2), not the loaded tool's length"
    if mode == "off" and state.tool_changed and not context.lengths_by_set_up and state.plane_axes[2] not in state.parked and _has_length(context, state):
        return "no tool length offset is in force since the tool change, so the programmed Z is the spindle's, not the tool tip's"
    if mode == "plus" and register is None and tool is not None:
        return "G43 has no H in force: the control applies H0 (no length) or a register the program did not name"
    lengths = "the tool's tip is off the programmed Z by the difference of their lengths"
    problem = register_problem("H", register, tool, lengths) if mode == "plus" else _edge_problem(context, state) if mode == "with_tool" else None
    if problem is not None:
        return problem
    delta = state.klartext.length_delta
    if not (type(delta) is float and delta == 0.0):
        return f"TOOL CALL DL{show(delta)} puts the tool's tip that far from the programmed point"
    return None


def register_problem(letter: str, register, tool, so: str) -> str | None:
    """Why offset register ``letter`` ``register`` (an ISO H or D, numbered as the tools are)
    may not hold the loaded tool ``tool``'s data (``so``: what follows then), or None: it
    depends on a free parameter, or it is another tool's number. None where no register is
    named, or no tool is known to be loaded (the tool's own data then answer)."""
    if register is None or register is tool or (type(register) in (float, str) and register == tool):  # Klartext: a tool called by name
        return None
    if type(register) is not float:
        return f"the offset register {letter} depends on a free parameter"
    if type(tool) is float:
        return f"the offset {letter}{show(register)} is not the one of the loaded tool T{show(tool)}, so {so}"
    return None


def radius_problem(context, state) -> str | None:
    """Why the radius offset in force under radius compensation may not be the loaded
    tool's radius from the tool table: an ISO D register other than the tool's number, or
    (SINUMERIK, Fagor) an edge of the tool the table does not describe."""
    if not compensated(state):
        return None
    if state.length_mode == "with_tool":
        return _edge_problem(context, state)
    return register_problem("D", state.comp_register, state.tool_in_spindle, "the tool runs off the path by another radius")


def _edge_problem(context, state) -> str | None:
    """Why the active offset of the loaded tool (a SINUMERIK cutting edge, a Fagor D) may
    not be the one the tool table gives: an edge or offset the table does not describe."""
    register = state.comp_register  # Fagor: D selects the tool's offset; posts write D1 or the tool's own number
    if type(register) is float and register in (1.0, state.tool_in_spindle):
        return None
    edge, tool = (register if register is not None else active_edge(state)), context.tools.in_spindle(state)
    if type(edge) is not float:
        return "the active tool edge D depends on a free parameter"
    if tool is not None and tool.edge_data(edge) is None:
        return f"D{show(edge)} is an edge of tool T{show(state.tool_in_spindle)} that the tool table does not describe: its length is not known"
    return None


def _has_length(context, state) -> bool:
    """May the loaded tool have a length (not known from the tool table to be 0)?"""
    tool = context.tools.in_spindle(state)
    return tool is None or tool.length != 0.0


def tool_axis_problem(state) -> str | None:
    """Why the tool is not known to stand along +Z of the workpiece, or None."""
    if state.plane_axes[2] != "Z":
        return f"the tool axis is {state.plane_axes[2]} (working plane)"
    if state.fagor.tool_axis not in (None, ("Z", "+")):
        return "#TOOL AX sets a tool axis other than Z+"
    frame = frames.program_to_workpiece(state)
    if frame is not None and not (frame.keeps_axis("Z") and type(frame.linear[2][2]) is float and frame.linear[2][2] > 0):
        return "the active frame turns or mirrors the tool axis"
    return None


def cutter_of(tool, radius: float) -> Cutter:
    """A tool table entry, of radius ``radius`` (a programmed delta counted), as the shape
    the model sweeps (asked on every cutting move: no copy of the entry is made, and the
    one shape is made once, which also lets the buffer group a tool's moves by identity)."""
    return _cutter_shape(tool.type, radius, tool.corner, tool.point_angle or tool.angle)


@functools.lru_cache(maxsize=64)
def _cutter_shape(kind: str | None, radius: float, corner: float | None, point_angle: float | None) -> Cutter:
    if kind == "ball":
        return Cutter(radius, corner=radius)
    if corner and (kind == "bullnose" or kind in _FLAT):  # a corner radius given to an end mill rounds its end too
        return Cutter(radius, corner=min(corner, radius))
    if kind in _POINTED and point_angle:
        return Cutter(radius, point_angle=point_angle)
    if kind in _FLAT:
        return Cutter(radius)
    return Cutter(radius, known=False)


def _resolution(stock, tools, called, machine, settings) -> tuple[float | None, str | None]:
    """The cell size when the model is kept, else None and, when the model was wanted but
    does not fit the memory cap, why (the rules then judge against the blank and say so).
    Not kept: turned off, no stock, a lathe bar (:mod:`.turning_stock` keeps that). Cells
    come from the smallest of the tools the program can load (``called``; None: of every
    tool in the table): a machine's whole magazine in its table, engraving tools and all,
    should not make every program's cells as fine as its finest tool."""
    wanted, cap = settings.stock_resolution, settings.stock_memory
    if wanted == 0 or stock is None or machine == "lathe" or stock.kind not in ("box", "polygon"):
        return None, None
    x_low, y_low, x_high, y_high = workpiece.outline(stock).bounds
    area = (x_high - x_low) * (y_high - y_low)
    fitting = math.sqrt(area * _FIELD_BYTES_PER_CELL / cap) * 1.01  # the finest cells the cap allows
    if wanted is not None:
        return (wanted, None) if wanted >= fitting else (None, _too_large(stock, f"cells of {wanted:g} mm", wanted, area, cap))
    radii = [tool.radius for number, tool in tools.items() if tool.radius and (called is None or number in called)]
    smallest = min(radii) if radii else None
    chosen = min(max(smallest / 4.0 if smallest else 0.5, AUTO_RESOLUTION[0]), AUTO_RESOLUTION[1])
    if smallest is not None and fitting > smallest:  # cells wider than the tool: none of its cuts would surely clear a cell
        return None, _too_large(stock, f"cells no wider than the smallest tool radius {smallest:g} mm", smallest, area, cap)
    return max(chosen, fitting), None


def _too_large(stock, cells: str, size: float, area: float, cap: int) -> str:
    needed = area / size ** 2 * _FIELD_BYTES_PER_CELL
    return (f"the stock as cut so far is not modelled: the blank ({stock.describe()}) at {cells} needs {_mebibytes(needed)}, "
            f"over the cap of {_mebibytes(cap)}")


def _mebibytes(size: float) -> str:
    mebibytes = size / 2**20
    return f"{mebibytes:,.0f} MiB" if mebibytes >= 10 else f"{mebibytes:.2g} MiB"


def _centre_by_radius(arc, start: tuple, end: tuple) -> tuple[float, float] | None:
    """The centre of an arc given by its radius word (:func:`xy_arcs.radius_arc_centres`),
    None when the radius is not a number or no circle of it joins the ends."""
    if type(arc.radius_word) is not float:
        return None
    first, second, _normal = _plane_indices(arc.plane)
    centre = xy_arcs.radius_arc_centres(numpy.array([[start[first], start[second]]]), numpy.array([[end[first], end[second]]]),
                                        numpy.array([arc.radius_word]), numpy.array([arc.direction == "cw"]))[0]
    return None if numpy.isnan(centre[0]) else (float(centre[0]), float(centre[1]))


@functools.lru_cache(maxsize=16)
def _plane_indices(plane: tuple[str, str, str]) -> tuple[int, int, int]:
    """The columns of a plane's axes in (X, Y, Z)."""
    return tuple("XYZ".index(axis) for axis in plane)


def _by_tool(buffered: list, key_from: int):
    """((cutter, tool, offset), entries) of the ``buffered`` entries, whose fields from
    ``key_from`` on are the cutter, the tool and the compensation's offset, grouped by those
    in the order each first comes."""
    groups: dict[tuple, list] = {}
    for entry in buffered:
        groups.setdefault(entry[key_from:], []).append(entry)
    return groups.items()


def _stacked(pieces, width: int = 3) -> numpy.ndarray:
    """The buffered rows as one (n, ``width``) array: a batch buffers arrays, a single move a
    list of one row; the lists are joined in Python and made one array, not one each."""
    arrays, loose = [], []
    for piece in pieces:
        if isinstance(piece, numpy.ndarray):
            if loose:
                arrays.append(numpy.array(loose, dtype=float).reshape(-1, width))
                loose = []
            arrays.append(numpy.reshape(piece, (-1, width)))
        else:
            loose.extend(piece)
    if loose:
        arrays.append(numpy.array(loose, dtype=float).reshape(-1, width))
    return numpy.concatenate(arrays)


def _known_point(position: dict) -> tuple[float, float, float] | None:
    """(x, y, z) of a position where all three are numbers, else None."""
    x, y, z = position.get("X"), position.get("Y"), position.get("Z")
    return (x, y, z) if type(x) is float and type(y) is float and type(z) is float else None


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


def _release(release: weakref.WeakMethod, cells: int) -> None:
    """A freed piece's cells go back to its model, if that is still alive."""
    method = release()
    if method is not None:
        method(cells)
