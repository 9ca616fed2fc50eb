"""The lathe bar as turned so far, per path, for the rapid-into-stock rule
(:class:`ncverify.workpiece.Bar` holds the model: two polygons of the half-section).

Every straight feed move, programmed or made by a cycle, sweeps the insert's nose: its radius from the tool table (``nose_radius``, else ``radius``: SINUMERIK's
``$TC_DP6``), its centre placed from the cutting-edge position (``edge_position``,
``$TC_DP2`` of the active edge). Without the edge position nothing is surely turned away,
so rapids over turned material stay ``unknown``; without a nose radius, at a position that
is not known, under nose radius compensation (G41/G42: the nose runs beside the programmed
contour by an offset the program does not fix), or along an arc (the lowering keeps a lathe arc's centre in program units,
which mix diameters and radii), a cut may have removed material anywhere. The program's X is read as a
diameter, as the blank check reads it, or as a radius where SINUMERIK's ``DIAMOF`` is in
force; a point on the far side of the spindle axis is a cut that cannot be placed.
"""
from __future__ import annotations

import numpy

from . import workpiece
from .context import active_edge, active_tool_number, off_path
from .workpiece import Bar, RapidVerdict

_KEY = "turned bar"
_FEED = 1  # MotionRun kind code
_FLUSH_AT = 4096  # buffered moves per batch


class _BarPath:
    """One path's bar and its buffered cuts, shared by forked paths until one of them cuts."""

    __slots__ = ("bar", "pending", "sharers", "rounded_next")

    def __init__(self, bar: Bar):
        self.bar, self.pending, self.sharers = bar, [], 1
        self.rounded_next = False  # the next cut starts at a rounded or chamfered corner (see Turning.corner_rounded)

    def off_corner(self, starts, ends):
        """The moves from ``starts`` to ``ends`` less the first one when it starts at a
        rounded corner: that one may have cut anywhere near it (the bar's bounds say so)."""
        if not self.rounded_next or not len(starts):
            return starts, ends
        self.rounded_next = False
        self.bar.cut_anywhere()
        return starts[1:], ends[1:]

    def forked(self) -> None:
        self.sharers += 1


class Turning:
    """The checker's view of the turned bar, per path."""

    def __init__(self, stock, tools):
        self.stock, self.tools = stock, tools

    # -- events
    def segment(self, segment, state) -> None:
        mine, insert = self._mine(state), self._insert(state)
        start, end = self._section(segment.start, state), self._section(segment.end, state)
        if insert is None or start is None or end is None or segment.arc is not None or off_path(state):
            mine.bar.cut_anywhere()
            mine.rounded_next = False
            return
        self._buffer(mine, *mine.off_corner(numpy.array([start]), numpy.array([end])), insert)

    def cut_run(self, run, feeds, state) -> None:
        """The feed moves ``feeds`` (indices) of a batch of moves."""
        mine, insert = self._mine(state), self._insert(state)
        if insert is None or "X" not in run.axes or "Z" not in run.axes or off_path(state):
            mine.bar.cut_anywhere()
            mine.rounded_next = False
            return
        columns = [run.axes.index("X"), run.axes.index("Z")]
        starts, ends = run.points[feeds][:, columns], run.points[feeds + 1][:, columns]
        scale = _x_scale(state)
        starts[:, 0] *= scale
        ends[:, 0] *= scale
        known = ~(numpy.isnan(starts).any(axis=1) | numpy.isnan(ends).any(axis=1)) & (starts[:, 0] >= 0) & (ends[:, 0] >= 0)
        if not known.all():
            mine.bar.cut_anywhere()
        self._buffer(mine, *mine.off_corner(starts[known], ends[known]), insert)

    def finish(self, state) -> None:
        if state.rule_state.get(_KEY) is not None:
            self._flush(self._mine(state))

    def corner_rounded(self, state) -> None:
        """The corner at the tool's position is rounded or chamfered: the cut that ended
        there (the last one buffered: a flush waits for the move after it) and the one that
        starts there run off their programmed paths near it, so both may have cut anywhere."""
        mine = self._mine(state)
        if mine.pending:
            starts, ends, insert = mine.pending.pop()
            if len(starts) > 1:
                mine.pending.append((starts[:-1], ends[:-1], insert))
        mine.bar.cut_anywhere()
        mine.rounded_next = True

    # -- questions
    def rapid(self, start, end, state) -> RapidVerdict | None:
        """Does a rapid between two known points (program X, Y, Z) meet what is left of
        the bar? None when X lies beyond the spindle axis (the blank decides)."""
        section = [self._section({"X": point[0], "Z": point[2]}, state) for point in (start, end)]
        if None in section:
            return None
        mine = self._mine(state)
        self._flush(mine)
        insert = self._insert(state)
        if insert is None:  # the insert's size is not known: its tip can show a hit, nothing more
            verdict = mine.bar.rapid(*section, 0.0)
            verdict = verdict if verdict.outcome == "hits" else RapidVerdict("unsure")
        else:
            verdict = mine.bar.rapid(*section, *insert)
        if verdict.point is None:
            return verdict
        radius, z = verdict.point
        return RapidVerdict(verdict.outcome, (radius / _x_scale(state), 0.0, z))  # back in program X

    def has_cut(self, state) -> bool:
        holder = state.rule_state.get(_KEY)
        return holder is not None and (holder.bar.cuts > 0 or bool(holder.pending))

    # -- the pieces
    def _mine(self, state) -> _BarPath:
        holder = state.rule_state.get(_KEY)
        if holder is None:
            holder = state.rule_state[_KEY] = _BarPath(Bar(self.stock))
        elif holder.sharers > 1:  # shapely geometries never change in place: a new holder is the copy
            holder.sharers -= 1
            twin = _BarPath(Bar(self.stock))
            twin.bar.most, twin.bar.least, twin.bar.cuts, twin.pending = holder.bar.most, holder.bar.least, holder.bar.cuts, list(holder.pending)
            twin.rounded_next = holder.rounded_next
            holder = state.rule_state[_KEY] = twin
        return holder

    def _insert(self, state):
        """(nose radius, nose centre from the tip or None) of the edge in use, or None when
        the nose radius is not known."""
        tool = self.tools.numbered(active_tool_number(state, lathe=True))
        edge = active_edge(state)
        if tool is not None:
            tool = tool.edge_data(edge) if type(edge) is float else None
        if tool is None:
            return None
        nose = tool.nose_radius if tool.nose_radius is not None else tool.radius
        if nose is None or nose < 0.0:
            return None
        return nose, workpiece.nose_centre(tool.edge_position, nose)

    @staticmethod
    def _section(position: dict, state):
        """(radius, z) of a position, or None when it is not known or beyond the axis."""
        x, z = position.get("X"), position.get("Z")
        if type(x) is not float or type(z) is not float or x < 0.0:
            return None
        return x * _x_scale(state), z

    def _buffer(self, mine: _BarPath, starts, ends, insert) -> None:
        """Buffer the moves, the buffer cut first when it is full: a flush waits for the
        moves after the last one, which a rounded corner may still take back."""
        if sum(len(item[0]) for item in mine.pending) >= _FLUSH_AT:
            self._flush(mine)
        if len(starts):
            mine.pending.append((starts, ends, insert))

    @staticmethod
    def _flush(mine: _BarPath) -> None:
        """Cut what is buffered, one union per run of moves with the same insert."""
        group: list = []
        for item in [*mine.pending, None]:
            if group and (item is None or item[2] != group[0][2]):
                starts, ends = numpy.concatenate([entry[0] for entry in group]), numpy.concatenate([entry[1] for entry in group])
                mine.bar.cut_many(starts, ends, *group[0][2])
                group = []
            if item is not None:
                group.append(item)
        mine.pending = []


def kept(stock, machine: str | None, settings) -> bool:
    """The bar is turned in the model: a lathe, a cylinder stock, the model not turned off."""
    return machine == "lathe" and stock is not None and stock.kind == "cylinder" and settings.stock_resolution != 0


def _x_scale(state) -> float:
    """From the program's X to the radius: a half for a diameter, one under DIAMOF."""
    return 1.0 if state.modal.get("diameter") == "radius" else 0.5
