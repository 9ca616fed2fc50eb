"""The workpiece as cut so far: a height field (Z-map) over the stock, for a tool along +Z.

Material in a column of the blank runs from the stock's bottom up to a top height; cutting
only lowers tops. The field is a grid of square cells, and each cell keeps two bounds of the
material top over its whole area, so that the grid never has to be exact to be sound:

``upper``
    at least the highest material anywhere in the cell. A cut lowers it only where the
    tool covered the whole cell.
``lower``
    at most the lowest material anywhere in the cell. A cut lowers it wherever the tool
    reached any part of it.

A rapid is *clear* when every cell its tool can touch has ``upper`` below the tool's lower
surface there; it *hits* when some point of a cell lies under the tool with ``lower`` above
that surface; anything in between is *unsure* (the verdict is ``unknown``, never a pass). A cut
whose place is not known (a symbolic position, an unknown radius) may have removed material
anywhere, so it sinks ``lower`` everywhere and leaves ``upper`` alone: what was certainly
there may be gone, what may be there still may be.

Heights are stored as float32, rounded outwards (``upper`` up, ``lower`` down), so that
the rounding never turns an unsure answer into a sure one.
"""
from __future__ import annotations

import ctypes
import functools
import math
from dataclasses import dataclass, fields, replace

import numpy
import shapely

from .context import Stock
from .xy_arcs import XYArcs, length as _length  # the sweep's one distance formula (many locals here are named length)

NO_MATERIAL = -numpy.inf
_CHUNK_CELLS = 1 << 18  # cells looked at per vectorised step: bounds the scratch memory (tens of MiB); a cut's air is judged a step at a time
_SCRATCH_BYTES = 32 * 8 * _CHUNK_CELLS  # freed memory the allocator keeps for the next step: some tens of a step's arrays of float64


@dataclass(frozen=True)
class Cutter:
    """The shape of a tool's lower end, as it sweeps: ``radius``, the ``corner`` radius
    (0: flat end mill, ``radius``: ball end mill, between: bull nose) or a drill's
    ``point_angle`` in degrees (the tip is the tool's reference point). ``known`` False: the
    shape is not given, only that the end is no pointier than a 90-degree cone and no
    rounder than a ball; the sweep then takes the shape that cuts least where it claims
    material is gone, and the flat end where it may be."""

    radius: float
    corner: float = 0.0
    point_angle: float | None = None
    known: bool = True

    def lift(self, distance):
        """Height of the tool's lower surface above its tip at ``distance`` from its axis
        (numpy arrays; meaningful up to ``radius``). It never falls as the distance grows,
        which the bounds rely on. For an unknown shape: the highest it can be."""
        distance = numpy.minimum(distance, self.radius)
        if not self.known:  # the 90-degree cone's: a ball's end never lies above it (r - sqrt(r² - d²) <= d for d <= r)
            return distance
        if self.point_angle:
            return distance / math.tan(math.radians(self.point_angle) / 2.0)
        if self.corner > 0.0:
            flat = self.radius - self.corner
            beyond = numpy.maximum(distance - flat, 0.0)
            return self.corner - numpy.sqrt(numpy.maximum(self.corner ** 2 - beyond ** 2, 0.0))
        return numpy.zeros_like(distance)

    def lowest_lift(self, distance):
        """The lowest the tool's lower surface can be: its shape, or a flat end when unknown."""
        return numpy.zeros_like(numpy.asarray(distance, float)) if self.lowest_is_flat else self.lift(distance)

    @property
    def flat_end(self) -> bool:
        """Is the tool known to have a flat end (:meth:`lift` zero at every distance)?"""
        return self.known and not self.point_angle and self.corner <= 0.0

    @property
    def lowest_is_flat(self) -> bool:
        """Is the lowest surface flat (:meth:`lowest_lift` zero at every distance): a flat
        end, or a shape not known?"""
        return not self.known or self.flat_end


MEASURED_REACH = 1e9  # mm from the origin within which a path's distance to a cell is exact to far below a cell


@dataclass(frozen=True)
class RapidVerdict:
    """``clear``, ``hits`` (with a point in the material) or ``unsure`` (within the grid's error)."""

    outcome: str
    point: tuple[float, float, float] | None = None


class ModelTooLarge(ValueError):
    """The stock at the requested resolution needs more memory than the cap allows."""


class Workpiece:
    """The height field of a box or polygon blank, milled with the tool along +Z."""

    def __init__(self, stock: Stock, resolution: float, memory_cap: int = 256 << 20, deferred: bool = False):
        if stock.kind not in ("box", "polygon"):
            raise ValueError(f"a {stock.kind} stock is not modelled as a height field")
        (x_low, y_low, x_high, y_high) = outline(stock).bounds
        self.resolution = float(resolution)
        self.x_low, self.y_low = x_low, y_low
        self.nx = max(1, math.ceil((x_high - x_low) / self.resolution))
        self.ny = max(1, math.ceil((y_high - y_low) / self.resolution))
        needed = 2 * 4 * self.nx * self.ny
        if needed > memory_cap:
            raise ModelTooLarge(f"the stock at {self.resolution:g} mm needs {needed / 2**20:.0f} MiB of height field, "
                                f"over the cap of {memory_cap / 2**20:.0f} MiB")
        _keep_scratch_memory()
        self.stock = stock
        self.cuts = 0  # sweeps so far, placed or not
        self.bottom, self.top = stock.z_range
        self.half_diagonal = self.resolution * math.sqrt(0.5)
        self.upper, self.lower = self._blank(stock)
        self._solid = self._solid_extent(stock)
        self.lower_emptied = False  # a cut that could not be placed emptied ``lower`` (see cut_anywhere)
        self._centres = None  # see _column_centres
        self._waiting = _Backlog() if deferred else None  # sweeps not applied yet (see _defer)
        self._most_waiting = memory_cap // 2  # bytes the deferred sweeps may hold

    def _blank(self, stock: Stock):
        """Tops of the uncut blank: cells wholly inside carry material on every point, cells
        the outline crosses only maybe. Built a band of rows at a time, so that the scratch
        arrays stay small beside the fields."""
        if stock.kind == "box":
            return self._box_blank(stock)
        upper = numpy.empty((self.ny, self.nx), numpy.float32)
        lower = numpy.empty((self.ny, self.nx), numpy.float32)
        xs = self._x(numpy.arange(self.nx))
        rows_per_band = max(1, _CHUNK_CELLS // self.nx)
        for first in range(0, self.ny, rows_per_band):
            ys = self._y(numpy.arange(first, min(first + rows_per_band, self.ny)))
            maybe, surely = self._blank_band(stock, xs, ys)
            upper[first:first + len(ys)] = numpy.where(maybe, self.top, NO_MATERIAL)
            lower[first:first + len(ys)] = numpy.where(surely, self.top, NO_MATERIAL)
        return upper, lower

    def _box_blank(self, stock: Stock):
        """A box's tops: the grid starts at its corner, so material maybe on every cell and
        surely on all but the last row and column where they stick out past its far sides.
        Those are not written but counted out wherever ``lower`` is read
        (:meth:`_solid_extent`): a column written wrote a value on every row. A top at +0,
        the usual one, is what a zeroed array holds: the system hands such an array out
        without touching its memory, so cells no cut reaches cost neither time nor memory
        (a CAM post's blank may be metres long)."""
        if numpy.float32(self.top).tobytes() == bytes(4):
            return numpy.zeros((self.ny, self.nx), numpy.float32), numpy.zeros((self.ny, self.nx), numpy.float32)
        upper = numpy.full((self.ny, self.nx), self.top, numpy.float32)
        return upper, upper.copy()

    def _solid_extent(self, stock: Stock) -> tuple[int, int]:
        """(rows, columns) from the grid's corner whose cells can hold material surely: a
        box's last row and column stick out past its far sides, and ``lower`` holds no
        material there whatever it says (:meth:`_lower_at`, :meth:`_lower_field`)."""
        if stock.kind != "box":
            return self.ny, self.nx
        half = self.resolution / 2
        return (int(numpy.count_nonzero(self._y(numpy.arange(self.ny)) + half <= stock.y_range[1])),
                int(numpy.count_nonzero(self._x(numpy.arange(self.nx)) + half <= stock.x_range[1])))

    def _blank_band(self, stock: Stock, xs, ys):
        """(maybe, surely) material in the cells of centres ``xs`` x ``ys`` (rows by columns)
        of a polygon blank."""
        grid_x, grid_y = numpy.meshgrid(xs, ys)
        inside = shapely.contains_xy(stock.outline, grid_x, grid_y)
        edge = shapely.distance(stock.outline.boundary, shapely.points(grid_x, grid_y))
        return inside | (edge < self.half_diagonal), inside & (edge >= self.half_diagonal)

    # Cutting ---------------------------------------------------------------------------

    def cut(self, starts, ends, cutter: Cutter, stray=0.0, joined: bool = True) -> float | None:
        """Sweep ``cutter`` along straight moves (arrays of (x, y, z) tip positions, one row
        a move) and lower the tops it passes under. ``stray``: how far the true path may
        leave these chords, in any direction (an arc's sagitta), one number or one a row
        (the chords of many arcs swept at once). ``joined`` False: each move is swept as it
        is, none merged with its neighbours into one chord (an arc's chords are already as
        long as their stray allows, and seldom join: on the real-world corpus 2 % did, and
        trying cost more than their sweep). Returns the length of the moves that surely cut
        nothing (air), judged before each chunk is applied; None from a deferred workpiece,
        which judges no air (see :meth:`_defer`)."""
        starts, ends = numpy.atleast_2d(numpy.asarray(starts, float)), numpy.atleast_2d(numpy.asarray(ends, float))
        if not len(starts):
            return 0.0 if self._waiting is None else None
        self.cuts += 1
        strays = numpy.broadcast_to(numpy.asarray(stray, float), len(starts))
        if self._waiting is not None and len(starts) >= _FEWEST_DEFERRED:  # the moves kept as given: made into pieces when a question first needs them
            low, high = numpy.minimum(starts, ends), numpy.maximum(starts, ends)
            reach = cutter.radius + self.half_diagonal + self.resolution + float(strays.max())  # a chord strays a quarter cell from its moves at most
            box = self._cell_boxes(*(numpy.array([value]) for value in (low[:, 0].min() - reach, low[:, 1].min() - reach, high[:, 0].max() + reach,
                                                                          high[:, 1].max() + reach)))
            self._defer(_Waiting(Workpiece._waiting_lines, (starts, ends, strays, joined), cutter, _whole_box(box), size=len(starts)))
            return None
        pieces = self._line_pieces(starts, ends, cutter, strays, joined)
        air = ~self._sweep_lines(*pieces, cutter)
        return total_length(pieces[0][air], pieces[1][air]) if self._waiting is None else None

    def _line_pieces(self, starts, ends, cutter: Cutter, strays, joined: bool):
        """The pieces :meth:`cut` sweeps for its moves: (a, b, z low, z high, slack)."""
        starts, ends, strays = self._within_slab(starts, ends, cutter, strays)
        pieces = _merge_runs(starts, ends, strays, self.resolution / 4.0, self.resolution) if joined else _as_given(starts, ends, strays)
        a, b, z_low, z_high, slack, stray = self._split_steep(*pieces)
        return a, b, z_low - stray, z_high + stray, slack + stray

    def _waiting_lines(self, starts, ends, strays, joined: bool, cutter: Cutter) -> "_Waiting":
        """A deferred :meth:`cut`'s moves made into its pieces, each with its box."""
        a, b, z_low, z_high, slack = pieces = self._line_pieces(starts, ends, cutter, strays, joined)
        reach = cutter.radius + self.half_diagonal + slack
        return _Waiting.of(Workpiece._sweep_lines, pieces, cutter, self._cell_boxes(
            numpy.minimum(a[:, 0], b[:, 0]) - reach, numpy.minimum(a[:, 1], b[:, 1]) - reach, numpy.maximum(a[:, 0], b[:, 0]) + reach,
            numpy.maximum(a[:, 1], b[:, 1]) + reach))

    def cut_arcs(self, arcs: XYArcs, cutter: Cutter) -> float | None:
        """Sweep ``cutter`` along arcs and helices about the Z axis, as :meth:`cut` sweeps
        straight moves: each part one piece, measured exactly, its drift off its circle its
        stray. Returns the length of the parts that surely cut nothing (None: deferred)."""
        if not len(arcs):
            return 0.0 if self._waiting is None else None
        self.cuts += 1
        low, high = self._slab(cutter)  # parts above or below the slab are laid on its faces, as straight moves are
        z_low, z_high = numpy.clip(arcs.low, low, high), numpy.clip(arcs.high, low, high)
        if self._waiting is not None and len(arcs) >= _FEWEST_DEFERRED:
            reach = cutter.radius + self.half_diagonal + arcs.drift
            x_low, y_low, x_high, y_high = arcs.box()
            self._defer(_Waiting.of(Workpiece._sweep_arcs, (arcs, z_low, z_high), cutter,
                                    self._cell_boxes(x_low - reach, y_low - reach, x_high + reach, y_high + reach)))
            return None
        may_cut = self._sweep_arcs(arcs, z_low, z_high, cutter)
        return float(arcs.length[~may_cut].sum()) if self._waiting is None else None

    def _sweep_lines(self, a, b, z_low, z_high, slack, cutter: Cutter):
        """Lower the fields under straight pieces; returns which may have cut."""
        return self._lower_near(self._cells_near(a, b, slack, cutter.radius + self.half_diagonal, cutter), cutter, z_low, z_high, slack)

    def _sweep_arcs(self, arcs: XYArcs, z_low, z_high, cutter: Cutter):
        """Lower the fields under the parts of arcs; returns which may have cut."""
        return self._lower_near(self._cells_near_arcs(arcs, cutter.radius + self.half_diagonal, cutter.lowest_is_flat), cutter, z_low, z_high, arcs.drift)

    # Deferred sweeps ---------------------------------------------------------------------

    def _defer(self, waiting: "_Waiting") -> None:
        """Keep a sweep to apply when a question needs the cells it reaches. Both fields
        are only ever lowered to the least of what the pieces leave on a cell, and the
        least does not depend on the order: a cell looked at after the pieces that reach it
        are applied, whenever and in whatever groups, holds what applying every sweep in
        turn leaves there. A program whose rapids stay above the blank then sweeps nothing
        (the air statistic, which judges each piece against the field before it, needs
        every sweep in turn, so a workpiece that judges it is not deferred). What waits is
        bounded: past half the memory cap (128 MiB by default: a million moves and more)
        the oldest sweeps are applied. A sweep of fewer than ``_FEWEST_DEFERRED`` moves is
        applied at once: keeping it costs about what applying it does, and so small a
        sweep comes from a flush before a question (a holder judged move by move), which
        looks near it."""
        self._waiting.add(waiting)
        while self._waiting.nbytes > self._most_waiting:
            oldest = self._waiting.pop_oldest().prepared(self)
            oldest.apply(self, oldest.left)

    def _cell_boxes(self, x_low, y_low, x_high, y_high):
        """The cells (first row, stop row, first column, stop column; one column of the
        result a piece) within the XY boxes given, a cell wider on every side: the sweep
        itself keeps within the box, rounding and all. A bound that is not a number
        (a path off to infinity) takes the grid's edge."""
        boxes = numpy.stack([*self._index_range(numpy.fmax(y_low, -numpy.inf), numpy.fmin(y_high, numpy.inf), self.y_low, self.ny),  # fmax/fmin: NaN to the edge
                             *self._index_range(numpy.fmax(x_low, -numpy.inf), numpy.fmin(x_high, numpy.inf), self.x_low, self.nx)])
        boxes[::2] -= 1
        boxes[1::2] += 1
        return boxes

    def settle(self, rows=(0, None), columns=(0, None)) -> None:
        """Apply the waiting sweeps' pieces that may reach the cells of ``rows`` and
        ``columns`` ((first, stop); the whole grid by default), so that those cells hold
        what every cut so far left (see :meth:`_defer`)."""
        if self._waiting:
            window = (rows[0], self.ny if rows[1] is None else rows[1], columns[0], self.nx if columns[1] is None else columns[1])
            self._waiting.settle(self, window)

    def _settle_near(self, start, end, reach: float) -> None:
        """:meth:`settle` the cells within ``reach`` of the XY path from ``start`` to ``end``'s box."""
        if not self._waiting:
            return
        xs, ys = numpy.array([start[0], end[0]], float), numpy.array([start[1], end[1]], float)
        rows = self._index_range(numpy.array([ys.min() - reach]), numpy.array([ys.max() + reach]), self.y_low, self.ny)
        columns = self._index_range(numpy.array([xs.min() - reach]), numpy.array([xs.max() + reach]), self.x_low, self.nx)
        self.settle((int(rows[0][0]), int(rows[1][0])), (int(columns[0][0]), int(columns[1][0])))

    def _lower_near(self, nears, cutter: Cutter, z_low, z_high, slack):
        """Lower both bounds where the pieces (``z_low``, ``z_high`` and ``slack`` one a
        piece) pass, from the cells near them (``nears``, :class:`_Near` chunks); returns
        which pieces may have cut, each judged against the field before its chunk."""
        may_cut = numpy.zeros(len(z_low), bool)
        first_cell, last_cell = self.nx * self.ny, -1
        for near in nears:
            if near.distance is None:  # a flat end's cells, judged already (see _swept_in_chunk)
                touched, lowest_lift, touched_cells = None, None, near.flat
            else:
                stray = slack.take(near.leaders).take(near.owner)
                outer = numpy.maximum(near.distance - self.half_diagonal - stray, 0.0)  # nearest the cell's points can be to the true path
                touched = outer <= cutter.radius
                lowest_lift = None if cutter.lowest_is_flat else cutter.lowest_lift(outer)
                touched_cells = near.flat[touched]
            may_cut[near.pieces] = self._may_cut(near, touched, lowest_lift, z_low)
            if near.distance is None:
                _sink_groups(self.upper, near.covered_flat, near.covered_owner, near.least(z_high), None, up=True)
            elif cutter.radius >= self.half_diagonal:  # else no cell lies wholly under the tool
                inner = near.distance + self.half_diagonal + stray  # farthest they can be
                covered = inner <= cutter.radius
                _sink_groups(self.upper, near.flat[covered], near.owner[covered], near.least(z_high),
                             None if cutter.flat_end else cutter.lift(inner[covered]), up=True)
            if not self.lower_emptied:
                _sink_groups(self.lower, touched_cells, near.owner if touched is None else near.owner[touched], near.least(z_low),
                             None if lowest_lift is None else lowest_lift[touched], up=False)
            if len(touched_cells):
                first_cell, last_cell = min(first_cell, int(touched_cells.min())), max(last_cell, int(touched_cells.max()))
        self._clear_below_bottom(first_cell, last_cell + 1)
        return may_cut

    def _may_cut(self, near: "_Near", touched, lowest_lift, z_low):
        """Which pieces of ``near`` may have cut: some cell they touch (``touched``; None:
        every cell of ``near``) has ``upper`` above the tool's lowest surface there. Every
        piece of a group touches the same cells, so with a flat lowest surface
        (``lowest_lift`` None) a piece may cut where the highest top its group touches lies
        above its own low; a shaped one is measured piece by piece."""
        tops = self.upper.reshape(-1).take(near.flat)
        if lowest_lift is None and not near.alone:
            highest = numpy.full(len(near.leaders), NO_MATERIAL, numpy.float32)
            owner = near.owner if touched is None else near.owner[touched]
            numpy.fmax.at(highest, owner, tops if touched is None else tops[touched])  # a NaN top (a NaN cut) is no cell above, as its comparison says
            return highest.take(near.group) > z_low.take(near.pieces)
        member, entry = near.entries_of_each_piece()
        if entry is not None:
            tops = tops.take(entry)
            touched = None if touched is None else touched.take(entry)
            lowest_lift = None if lowest_lift is None else lowest_lift.take(entry)
        surface = z_low.take(near.pieces).take(member)
        if lowest_lift is not None:
            surface += lowest_lift
        above = tops > surface
        may_cut = numpy.zeros(len(near.pieces), bool)
        may_cut[member[above if touched is None else touched & above]] = True
        return may_cut

    def cut_anywhere(self) -> None:
        """A cut that cannot be placed: any material may be gone, none is surely gone.
        Cuts only ever lower ``lower``, so once it is emptied it stays empty: a program that
        cuts unplaced move after move (cutter compensation) empties it once, not on every move.
        An emptied ``lower`` is one value seen by every cell, read-only: it takes no memory
        (a long blank's field need not be written through) and nothing lowers it further."""
        self.cuts += 1
        if not self.lower_emptied:
            self.lower = numpy.broadcast_to(numpy.float32(NO_MATERIAL), (self.ny, self.nx))
            self.lower_emptied = True

    def copy(self) -> "Workpiece":
        """An independent copy (paths that fork cut their own workpieces)."""
        twin = object.__new__(Workpiece)
        twin.__dict__.update(self.__dict__)
        twin.upper, twin.lower = self.upper.copy(), self.lower if self.lower_emptied else self.lower.copy()
        twin._waiting = None if self._waiting is None else self._waiting.copy()
        return twin

    def _clear_below_bottom(self, first_cell: int, end_cell: int) -> None:
        """No material below the blank's bottom. Only the cells a cut lowered (which lie
        between ``first_cell`` and ``end_cell`` of the flattened grid; ``upper`` is lowered
        only where ``lower`` is) can have gone below it: looking at the whole grid after
        every arc cost more than the cut itself on a long stock."""
        for field in (self.upper,) if self.lower_emptied else (self.upper, self.lower):
            cells = field.reshape(-1)[first_cell:end_cell]
            cells[cells <= self.bottom] = NO_MATERIAL

    def _lower_at(self, flat):
        """The lower bound at the cells ``flat`` (flat indices; a new array)."""
        if self.lower_emptied:
            return numpy.full(len(flat), NO_MATERIAL, numpy.float32)
        values = self.lower.reshape(-1).take(flat)
        if self._solid != (self.ny, self.nx):
            rows, columns = numpy.divmod(flat, self.nx)
            values[(rows >= self._solid[0]) | (columns >= self._solid[1])] = NO_MATERIAL
        return values

    def _lower_field(self, lower=None):
        """The whole lower bound (``lower``: of another field of this grid), no material on
        the cells past a box's far sides."""
        lower = self.lower if lower is None else lower
        if self._solid == (self.ny, self.nx) or (lower is self.lower and self.lower_emptied):
            return lower
        lower = lower.copy()
        lower[self._solid[0]:, :] = NO_MATERIAL
        lower[:, self._solid[1]:] = NO_MATERIAL
        return lower

    # Rapids ----------------------------------------------------------------------------

    def rapid(self, start, end, cutter: Cutter) -> RapidVerdict:
        """Does a rapid from ``start`` to ``end`` (tip positions) meet what is left? The path
        is judged a cell's height at a time; where that leaves it unsure, the lower end point
        alone, where the tool's height is exact, can still show the hit."""
        self._settle_near(start, end, cutter.radius + self.half_diagonal)
        verdict = self._rapid_path(start, end, cutter)
        if verdict.outcome != "unsure" or start[2] == end[2]:
            return verdict
        lowest = start if start[2] < end[2] else end
        at_end = self._rapid_path(lowest, lowest, cutter)
        return at_end if at_end.outcome == "hits" else verdict

    def _rapid_path(self, start, end, cutter: Cutter) -> RapidVerdict:
        if not all(abs(value) <= MEASURED_REACH for value in (start[0], start[1], end[0], end[1])):
            return RapidVerdict("unsure")  # so far out, rounding places the path's nearest points many mm off
        a, b, _ = self._within_slab(numpy.array([start], float), numpy.array([end], float), cutter, numpy.zeros(1))
        a, b, z_low, z_high, slack = self._split_steep(a, b, numpy.minimum(a[:, 2], b[:, 2]), numpy.maximum(a[:, 2], b[:, 2]), numpy.zeros(len(a)))
        upper = self.upper.reshape(-1)
        clear = True
        for near in self._cells_near(a, b, slack, cutter.radius + self.half_diagonal):
            owner, flat, distance = near.each_piece()
            cells = numpy.divmod(flat, self.nx)
            nearest = self._square_distance(cells, a[owner], b[owner])  # a point of the (closed) cell this close to the piece
            surface_high = z_high[owner] + cutter.lift(nearest)
            lower = self._lower_at(flat)
            hit = (nearest <= cutter.radius) & (lower > surface_high)
            if hit.any():
                first = int(numpy.flatnonzero(hit)[0])
                piece = owner[first:first + 1]
                on_path = _nearest_on_segment(self._x(cells[1][first]), self._y(cells[0][first]), a[piece, :2], b[piece, :2])
                level = min(float(lower[first]), float(z_high[piece[0]]))
                return RapidVerdict("hits", (float(on_path[0][0]), float(on_path[1][0]), level))
            outer = numpy.maximum(distance - self.half_diagonal, 0.0)
            reach = outer <= cutter.radius
            clear &= not bool((upper[flat][reach] > (z_low[owner] + cutter.lowest_lift(outer))[reach]).any())
        return RapidVerdict("clear" if clear else "unsure")

    # Shared machinery ------------------------------------------------------------------

    def _within_slab(self, starts, ends, cutter: Cutter, strays):
        """Moves with the tip kept between a little below the blank's bottom (by the tool's
        own tip height) and a little above its top: a piece below meets or removes every cell
        it passes over as it would at any depth below, one above meets nothing at any height
        above, so the pieces outside are laid on the slab's faces. Without this a plunge to
        Z-1e8 would be split into steps of one cell by the hundred million. ``strays`` (one
        a move) go with the pieces."""
        low, high = self._slab(cutter)
        leaving = ~((numpy.minimum(starts[:, 2], ends[:, 2]) >= low) & (numpy.maximum(starts[:, 2], ends[:, 2]) <= high))
        if not leaving.any():
            return starts, ends, strays
        # only the moves that leave the slab are cut (a batch of arcs with a helical entry
        # from above the blank has one such move among thousands); the rest stay as given
        laid_starts, laid_ends, pieces = _laid_on_slab(starts[leaving], ends[leaving], low, high)
        counts = numpy.ones(len(starts), numpy.int64)
        counts[leaving] = pieces
        laid = (counts.cumsum() - counts)[leaving].repeat(pieces) + _ramp(pieces)
        cut_starts, cut_ends = starts.repeat(counts, axis=0), ends.repeat(counts, axis=0)  # a copy of the rest, in one pass
        cut_starts[laid], cut_ends[laid] = laid_starts, laid_ends
        return cut_starts, cut_ends, strays.repeat(counts)

    def _slab(self, cutter: Cutter) -> tuple[float, float]:
        """The tip heights the sweep keeps moves between (see :meth:`_within_slab`)."""
        return self.bottom - float(cutter.lift(numpy.array(cutter.radius))) - self.resolution, self.top + self.resolution

    def _split_steep(self, a, b, z_low, z_high, *per_piece):
        """Pieces split so that none climbs or falls more than one cell. Only single moves
        can be that steep (merged runs stay within one cell), so a split piece's heights
        are its own end points'; the ``per_piece`` arrays go with each part."""
        counts = numpy.maximum(1, numpy.ceil((z_high - z_low) / self.resolution)).astype(numpy.int64)
        if (counts == 1).all():
            return a, b, z_low, z_high, *per_piece
        move = numpy.arange(len(a)).repeat(counts)
        step = _ramp(counts)
        t0, t1 = (step / counts[move])[:, None], ((step + 1) / counts[move])[:, None]
        delta = b[move] - a[move]
        start, end = a[move] + t0 * delta, a[move] + t1 * delta
        split = counts[move] > 1
        low = numpy.where(split, numpy.minimum(start[:, 2], end[:, 2]), z_low[move])
        high = numpy.where(split, numpy.maximum(start[:, 2], end[:, 2]), z_high[move])
        return start, end, low, high, *(values[move] for values in per_piece)

    def _cells_near(self, a, b, slack, reach: float, cutter: Cutter | None = None):
        """For chunks of pieces a-b, the cells whose centres lie within ``reach + slack`` of a
        piece's XY path, with their distances (:class:`_Near`). Pieces of a chunk with the
        same XY path and slack (a plunge's steps, a profile's laps at each depth) form a
        group, measured once. Only the part of each row of a piece's bounding box that can
        be that near is measured (:meth:`_row_spans`); the distance is worked out as
        :func:`distance_to_segment` does, with each piece's and row's terms computed once
        instead of once per cell. A flat-end ``cutter`` (``reach`` its radius and the half
        diagonal) some cells wide gets the cells it touches and covers instead
        (:meth:`_swept_in_chunk`): a tool whose shape is not known needs the distances (its
        surface's height over the cells it covers), as do the rapid checks."""
        reach = reach + slack
        column_low, column_high = self._index_range(numpy.minimum(a[:, 0], b[:, 0]) - reach, numpy.maximum(a[:, 0], b[:, 0]) + reach, self.x_low, self.nx)
        row_low, row_high = self._index_range(numpy.minimum(a[:, 1], b[:, 1]) - reach, numpy.maximum(a[:, 1], b[:, 1]) + reach, self.y_low, self.ny)
        size = numpy.maximum(numpy.maximum(numpy.abs(a[:, 0]), numpy.abs(a[:, 1])), numpy.maximum(numpy.abs(b[:, 0]), numpy.abs(b[:, 1])))
        heights = numpy.where(numpy.isfinite(size), row_high - row_low, 0)  # a piece running off to infinity is no distance from any cell
        segments = _Segments.of(a, b)
        rounding = self.resolution * 1e-3 + 1e-14 * size
        centres = self._column_centres()
        first_row, stop_row = self._centre_range(numpy.minimum(a[:, 1], b[:, 1]) - (reach + rounding), numpy.maximum(a[:, 1], b[:, 1]) + (reach + rounding),
                                                 self.y_low, self.ny)
        rows = numpy.where(numpy.isfinite(size), numpy.maximum(stop_row - first_row, 0), 0)  # the rows of the box whose centres can be near
        once = cutter is not None and cutter.lowest_is_flat
        for chunk, group, leaders in _grouped_chunks((column_high - column_low) * heights, _path_keys(a, b, slack), once):
            rows_of = _Rows.of(self, leaders, segments, rows, first_row, reach, rounding, column_low, column_high)
            if cutter is not None and cutter.flat_end and cutter.radius >= _SPANS_FROM_CELLS * self.resolution:
                yield _Near(chunk, group, leaders, *self._swept_in_chunk(rows_of, centres, cutter, slack))
            else:
                yield _Near(chunk, group, leaders, *self._near_in_chunk(rows_of, centres))

    def _cells_near_arcs(self, arcs: XYArcs, reach: float, once: bool = False):
        """:meth:`_cells_near` for arcs about Z: the cells of each arc's box widened by the
        reach and its drift whose centres lie within that of the arc, row by row, from the
        spans where the row crosses the arc's annulus. Arcs alike seen from above (a
        profile's corners lap after lap) are measured once (``once``: and fill a chunk
        once, see :func:`_grouped_chunks`)."""
        reach = reach + arcs.drift
        rounding = self.resolution * 1e-3 + 1e-14 * arcs.size()
        x_low, y_low, x_high, y_high = arcs.box()
        column_low, column_high = self._index_range(x_low - reach, x_high + reach, self.x_low, self.nx)
        first_row, stop_row = self._centre_range(y_low - (reach + rounding), y_high + (reach + rounding), self.y_low, self.ny)
        rows = numpy.maximum(stop_row - first_row, 0)
        centres = self._column_centres()
        for chunk, group, leaders in _grouped_chunks((column_high - column_low) * rows, arcs.keys(), once):
            owner, flat, distance = self._near_arcs_in_chunk(arcs, leaders, rows, first_row, reach + rounding, reach, column_low, column_high, centres)
            yield _Near(chunk, group, leaders, owner, flat, distance)

    def _near_arcs_in_chunk(self, arcs: XYArcs, pieces, rows, first_row, span_reach, reach, column_low, column_high, centres):
        """(owner, flat cell, distance) of the cells near the arcs ``pieces``, as
        :meth:`_near_in_chunk` gives them: each (arc, row) has two spans, left and right of
        the centre, the right one starting where the left one stops (no cell twice)."""
        piece = pieces.repeat(rows[pieces])  # one entry per (arc, row)
        place = numpy.arange(len(pieces)).repeat(rows[pieces])
        row = first_row.take(piece) + _ramp(rows[pieces])
        y = self._y(row)
        low, high = column_low.take(piece), column_high.take(piece)
        (left_first, left_stop), (right_first, right_stop) = (self._centre_range(begin, end, self.x_low, self.nx)
                                                              for begin, end in arcs.row_spans(piece, y, span_reach.take(piece)))
        left_first, left_stop = numpy.maximum(left_first, low), numpy.minimum(left_stop, high)
        right_first, right_stop = numpy.maximum(numpy.maximum(right_first, left_stop), low), numpy.minimum(right_stop, high)
        first = numpy.stack([left_first, right_first], axis=1).reshape(-1)
        entry, column = _span_cells(first, numpy.maximum(numpy.stack([left_stop, right_stop], axis=1).reshape(-1), first))
        entry >>= 1  # the span's (arc, row)
        arc = piece.take(entry)
        distance = arcs.distance(arc, centres.take(column), y.take(entry))
        near = (distance <= reach.take(arc)).nonzero()[0]
        entry = entry.take(near)
        return place.take(entry), row.take(entry) * self.nx + column.take(near), distance.take(near)

    def _near_in_chunk(self, rows: "_Rows", centres):
        """(owner, flat cell, distance) of the cells near the pieces of ``rows``, ``owner``
        the place of each one's piece among them (see :meth:`_cells_near`)."""
        entry, column = _span_cells(*rows.spans)
        cells, distance = rows.segments.near_on_rows(rows.piece, entry, centres.take(column), rows.y, rows.across, rows.reach)
        entry = entry.take(cells)
        return rows.place.take(entry), rows.row.take(entry) * self.nx + column.take(cells), distance

    def _swept_in_chunk(self, rows: "_Rows", centres, cutter: Cutter, slack):
        """(owner, flat cell, None, covered owner, covered flat cell) of a flat-end tool
        along the pieces of ``rows``: the cells it may touch and those it surely covers,
        judged as :meth:`_lower_near` judges the distances :meth:`_near_in_chunk` gives, bit
        for bit. Neither needs a cell's distance but at its ends: the points within a radius
        of a piece cross a row in one stretch, and the cells of that stretch (but for those
        within the rounding of its ends, which are measured) are all touched, or all covered."""
        stray, half = slack.take(rows.piece), self.half_diagonal

        def touched(distance, entry):
            return (distance <= rows.reach.take(entry)) & (numpy.maximum(distance - half - stray.take(entry), 0.0) <= cutter.radius)

        def covered(distance, entry):
            return (distance <= rows.reach.take(entry)) & (distance + half + stray.take(entry) <= cutter.radius)

        entry, column = self._cells_within(rows, centres, rows.reach, touched)
        touched_cells = (rows.place.take(entry), rows.row.take(entry) * self.nx + column, None)
        if cutter.radius < half:  # no cell lies wholly under the tool
            return (*touched_cells, touched_cells[0][:0], touched_cells[1][:0])
        entry, column = self._cells_within(rows, centres, cutter.radius - half - stray, covered)
        return (*touched_cells, rows.place.take(entry), rows.row.take(entry) * self.nx + column)

    def _cells_within(self, rows: "_Rows", centres, radius, keep):
        """(entry, column) of the cells of each (piece, row) entry of ``rows`` within
        ``radius`` (one an entry) of its piece, as ``keep(distance, entry)`` judges them: the
        stretch of the row within the radius less the rounding is kept whole, and only the
        cells between it and the stretch within the radius plus the rounding are measured."""
        box_first, box_stop = rows.spans
        outer_first, outer_stop = self._centre_range(*_capsule_crossing(rows.segments, rows.piece, rows.y, radius + rows.rounding, outward=True), self.x_low, self.nx)
        outer_first, outer_stop = numpy.maximum(outer_first, box_first), numpy.maximum(numpy.minimum(outer_stop, box_stop), outer_first)
        sure_first, sure_stop = self._centre_range(*_capsule_crossing(rows.segments, rows.piece, rows.y, radius - rows.rounding, outward=False), self.x_low, self.nx)
        sure_first = numpy.clip(sure_first, outer_first, outer_stop)
        sure_stop = numpy.clip(sure_stop, sure_first, outer_stop)
        edge, column = _span_cells(numpy.concatenate([outer_first, sure_stop]), numpy.concatenate([sure_first, outer_stop]))
        edge %= len(rows.piece)
        kept = keep(rows.segments.distances_on_rows(rows.piece, edge, centres.take(column), rows.y, rows.across), edge).nonzero()[0]
        entry, sure_column = _span_cells(sure_first, sure_stop)
        return numpy.concatenate([entry, edge.take(kept)]), numpy.concatenate([sure_column, column.take(kept)])

    def _row_spans(self, segments: "_Segments", reach, piece, y, column_low, column_high):
        """(first, stop) columns of each (piece, row) entry whose cell centres may lie within
        ``reach`` (one an entry) of the piece: the piece clipped to the band of rows within
        reach, its X extent widened by the reach, within the piece's bounding box
        (``column_low``, ``column_high``). The caller widens ``reach`` by more than the
        rounding of these steps and of the distances measured after them, which grows with
        the coordinates' size: the spans then hold every cell the whole box would give."""
        ax, ay, dx, dy = (terms.take(piece) for terms in (segments.ax, segments.ay, segments.dx, segments.dy))
        sloped = dy != 0.0
        # a piece all but level (dy far below the reach) gives quotients past the float range:
        # their infinity clips to the piece's end, as the limit of a level piece would
        with numpy.errstate(divide="ignore", over="ignore"):
            enter, leave = (numpy.where(sloped, (y + side * reach - ay) / numpy.where(sloped, dy, 1.0), bound) for side, bound in ((-1.0, 0.0), (1.0, 1.0)))
        t0 = numpy.minimum(enter, leave).clip(0.0, 1.0)
        t1 = numpy.maximum(enter, leave).clip(0.0, 1.0)
        x0, x1 = ax + t0 * dx, ax + t1 * dx
        first, stop = self._centre_range(numpy.minimum(x0, x1) - reach, numpy.maximum(x0, x1) + reach, self.x_low, self.nx)
        first, stop = numpy.maximum(first, column_low), numpy.minimum(stop, column_high)
        return first, numpy.maximum(stop, first)

    def _column_centres(self):
        """X of every column's centre (as :meth:`_x` gives it), made once per workpiece."""
        if self._centres is None:
            self._centres = self._x(numpy.arange(self.nx))
        return self._centres

    def _square_distance(self, cells, a, b):
        """How far the (closed) square of each cell is from the point of its piece a-b
        (row-wise) nearest its centre: a point of the cell lies that close to the path."""
        px, py = self._x(cells[1]), self._y(cells[0])
        qx, qy = _nearest_on_segment(px, py, a[:, :2], b[:, :2])
        half = self.resolution / 2.0
        return numpy.hypot(numpy.maximum(numpy.abs(qx - px) - half, 0.0), numpy.maximum(numpy.abs(qy - py) - half, 0.0))

    def _index_range(self, low, high, origin: float, count: int):
        first, last = self._cells(low, origin), self._cells(high, origin)
        return _clipped(numpy.floor(first, out=first), count), _clipped(numpy.ceil(last, out=last), count)

    def _centre_range(self, low, high, origin: float, count: int):
        """(first, stop) of the cells whose centres lie between ``low`` and ``high`` (less than
        :meth:`_index_range`, which takes every cell that reaches into them: half a cell
        fewer at each end on the mean)."""
        first, stop = self._cells(low, origin), self._cells(high, origin)
        first -= 0.5
        stop -= 0.5
        numpy.floor(stop, out=stop)
        stop += 1
        return _clipped(numpy.ceil(first, out=first), count), _clipped(stop, count)

    def _cells(self, positions, origin: float):
        """How many cells ``positions`` lie from ``origin`` along an axis (a new array, as floats)."""
        cells = positions - origin
        cells /= self.resolution
        return cells

    def _x(self, column):
        return self.x_low + (column + 0.5) * self.resolution

    def _y(self, row):
        return self.y_low + (row + 0.5) * self.resolution

    # What is left ----------------------------------------------------------------------

    def removed_volume(self) -> tuple[float, float]:
        """(at least, at most) the volume cut away, in mm³, from the two bounds."""
        self.settle()
        blank_upper, blank_lower = self._blank(self.stock)
        area = self.resolution ** 2
        least = numpy.maximum(_height(self._lower_field(blank_lower), self.bottom) - _height(self.upper, self.bottom), 0.0).sum() * area
        most = (_height(blank_upper, self.bottom) - _height(self._lower_field(), self.bottom)).sum() * area
        return float(least), float(most)


    def save_npz(self, path) -> None:
        """Both bounds and the grid, for a user to look at what the program leaves."""
        self.settle()
        numpy.savez_compressed(path, upper=self.upper, lower=self._lower_field(), x_low=self.x_low, y_low=self.y_low,
                               resolution=self.resolution, bottom=self.bottom)

    def save_stl(self, path) -> None:
        """The part as at most this much material (the upper bound) as a binary STL: a
        column per cell, with the faces between neighbours of different heights."""
        self.settle()
        heights = numpy.where(numpy.isfinite(self.upper), self.upper, self.bottom).astype(numpy.float64)
        padded = numpy.pad(heights, 1, constant_values=self.bottom)
        x = self.x_low + numpy.arange(self.nx + 1) * self.resolution
        y = self.y_low + numpy.arange(self.ny + 1) * self.resolution
        rows, columns = numpy.nonzero(heights > self.bottom)
        faces = [_quads_up(x, y, rows, columns, heights[rows, columns]), _quads_up(x, y, rows, columns, numpy.full(len(rows), self.bottom), down=True)]
        for axis, step in ((0, 1), (0, -1), (1, 1), (1, -1)):
            neighbour = padded[1 + rows + (step if axis == 0 else 0), 1 + columns + (step if axis == 1 else 0)]
            wall = heights[rows, columns] > neighbour
            faces.append(_walls(x, y, rows[wall], columns[wall], neighbour[wall], heights[rows, columns][wall], axis, step))
        _write_stl(path, numpy.concatenate(faces))


def _quads_up(x, y, rows, columns, z, down: bool = False):
    """Two triangles per cell top (or bottom, facing down)."""
    x0, x1, y0, y1 = x[columns], x[columns + 1], y[rows], y[rows + 1]
    corners = [numpy.column_stack([px, py, z]) for px, py in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]
    first, second = (corners[0], corners[1], corners[2]), (corners[0], corners[2], corners[3])
    if down:
        first, second = first[::-1], second[::-1]
    return numpy.concatenate([numpy.stack(first, axis=1), numpy.stack(second, axis=1)])


def _walls(x, y, rows, columns, low, high, axis: int, step: int):
    """The side faces of cells that stand higher than their neighbour along ``axis``."""
    if axis == 0:  # between rows: a wall along X at y of the shared edge
        edge = y[rows + (1 if step > 0 else 0)]
        a = numpy.column_stack([x[columns], edge]), numpy.column_stack([x[columns + 1], edge])
    else:
        edge = x[columns + (1 if step > 0 else 0)]
        a = numpy.column_stack([edge, y[rows]]), numpy.column_stack([edge, y[rows + 1]])
    if (axis == 0) == (step > 0):  # keep every face turned outwards
        a = a[::-1]
    p0, p1 = (numpy.column_stack([point, height]) for point, height in ((a[0], low), (a[1], low)))
    p2, p3 = numpy.column_stack([a[1], high]), numpy.column_stack([a[0], high])
    return numpy.concatenate([numpy.stack([p0, p1, p2], axis=1), numpy.stack([p0, p2, p3], axis=1)])


def _write_stl(path, triangles) -> None:
    normals = numpy.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    normals /= numpy.maximum(numpy.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    record = numpy.zeros(len(triangles), dtype=[("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
    record["normal"], record["corners"] = normals, triangles
    with open(path, "wb") as out:
        out.write(b"ncverify workpiece".ljust(80, b" "))
        out.write(numpy.uint32(len(triangles)).tobytes())
        out.write(record.tobytes())


def outline(stock: Stock):
    if stock.kind == "box":
        return shapely.box(stock.x_range[0], stock.y_range[0], stock.x_range[1], stock.y_range[1])
    return stock.outline


def _height(tops, bottom: float):
    return numpy.where(numpy.isfinite(tops), numpy.maximum(tops.astype(numpy.float64) - bottom, 0.0), 0.0)


@functools.cache
def _keep_scratch_memory() -> None:
    """Let the C library keep the sweep's freed scratch memory for the next step. Left to
    itself, glibc hands back the top of its heap whenever more than about twice the largest
    array freed so far lies free there, and serves arrays above a similar size by mapping
    fresh memory: a sweep step's arrays of a few MiB then had every page faulted in anew
    (300,000 faults, 0.6 s of system time on 200,000 arcs). Arrays of more than a quarter of
    the kept amount (a long blank's height field) are still mapped on their own, so that a
    zeroed field is paged in only where cut. Process-wide and harmless elsewhere; a C
    library without ``mallopt`` (not glibc) is left as it is."""
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError, TypeError):
        return
    trim_threshold, mmap_threshold = -1, -3  # glibc's parameter numbers (malloc.h)
    mallopt(mmap_threshold, _SCRATCH_BYTES // 4)
    mallopt(trim_threshold, _SCRATCH_BYTES)


def _clipped(cells, count: int):
    """Cell numbers (floats, overwritten) kept between 0 and ``count``, as integers."""
    return cells.clip(0, count, out=cells).astype(numpy.int64)


def _chunks(sizes):
    """Index arrays of consecutive pieces whose cell windows add up to about _CHUNK_CELLS."""
    if len(sizes) and sizes.min() >= 0 and sizes.sum() <= _CHUNK_CELLS:  # one step (what the search below finds then)
        yield numpy.arange(len(sizes))
        return
    ends = numpy.searchsorted(numpy.cumsum(sizes), numpy.arange(_CHUNK_CELLS, int(sizes.sum()) + _CHUNK_CELLS, _CHUNK_CELLS), side="right")
    start = 0
    for end in sorted(set(numpy.maximum(ends, 1).tolist())):  # not numpy.unique: it loads numpy.ma (9 ms)
        end = min(int(end), len(sizes))
        if end > start:
            yield numpy.arange(start, end)
            start = end
    if start < len(sizes):
        yield numpy.arange(start, len(sizes))


def _chunks_by_path(sizes, words):
    """:func:`_chunks` where a piece whose path (its :func:`_mixed` word) came before in its
    chunk adds nothing to the chunk: a profile's laps at each depth, counted lap by lap,
    made a chunk of each part of a CAM post, and each chunk costs a fixed time besides its
    cells (a tenth of that post's check). Words of unequal paths that mix alike (rare)
    leave one path out of the count."""
    ordered = words.take(order := words.argsort(kind="stable"))
    first = numpy.ones(len(words), bool)
    first[1:] = ordered[1:] != ordered[:-1]
    if sizes.take(order[first]).sum() <= _CHUNK_CELLS:  # one step, told without the loop below
        yield numpy.arange(len(sizes))
        return
    start, total, seen = 0, 0, set()
    for index, (size, word) in enumerate(zip(sizes.tolist(), words.tolist())):
        if word in seen:
            continue
        if total + size > _CHUNK_CELLS and index > start:
            yield numpy.arange(start, index)
            start, total, seen = index, 0, set()
        seen.add(word)
        total += size
    if start < len(sizes):
        yield numpy.arange(start, len(sizes))


def _grouped_chunks(sizes, keys, once: bool = False):
    """(chunk, group, leaders) of the pieces in chunks (:func:`_chunks` of their cell
    windows ``sizes``): within a chunk, the pieces whose ``keys`` (bit patterns, see
    :func:`_path_keys`) are all equal form a group, ``group`` each piece's place among
    ``leaders``, the first piece of each group (as :class:`_Near` takes them). ``once``:
    the cells of a group are looked at once, whatever its count of pieces (the tool's
    lowest surface is flat, so no piece's own cells are spread out), and only a group's
    first piece fills its chunk (:func:`_chunks_by_path`)."""
    words = _mixed(keys)
    alike = _any_equal(words)
    for chunk in _chunks_by_path(sizes, words) if once and alike else _chunks(sizes):
        chunk_words = words.take(chunk)
        if alike and _any_equal(chunk_words):
            group, leaders = _path_groups([key.take(chunk) for key in keys], chunk_words)
            yield chunk, group, chunk.take(leaders)
        else:
            yield chunk, numpy.arange(len(chunk)), chunk


_MIX = numpy.uint64(0x9E3779B97F4A7C15)  # an odd constant with well spread bits, to mix a path's key words into one
_FOLD = numpy.uint64(29)


def _path_keys(a, b, slack):
    """What makes pieces a-b meet the same cells at the same distances: their XY ends and
    slack, as bits (two pieces equal to the bit are measured alike)."""
    return [numpy.ascontiguousarray(values).view(numpy.uint64) for values in (a[:, 0], a[:, 1], b[:, 0], b[:, 1], slack)]


def _mixed(keys):
    """Each piece's ``keys`` mixed into one word: equal keys give equal words, and unequal
    ones seldom do. The shift folds the product's high bits back down: a product alone
    carries bits only upwards, and CAM coordinates (43.2 and 57.2) share many low bits."""
    mixed = numpy.zeros(len(keys[0]), numpy.uint64)
    for key in keys:
        mixed ^= key
        mixed *= _MIX
        mixed ^= mixed >> _FOLD
    return mixed


def _any_equal(words) -> bool:
    """Are any two ``words`` equal? (Sorting the words alone is cheap beside the pieces'
    sweep, and most batches have no two pieces alike.)"""
    words = numpy.sort(words)
    return bool((words[1:] == words[:-1]).any())


def _path_groups(keys, mixed):
    """(group of each piece, first piece of each group) of the pieces whose ``keys`` are all
    equal, groups numbered in the order of their first pieces: the pieces sorted on their
    :func:`_mixed` words, in which equal keys lie side by side (unequal keys that mix alike
    only split a group)."""
    order = mixed.argsort()
    new_run = numpy.zeros(len(order), bool)
    for key in keys:
        ordered = key.take(order)
        new_run[1:] |= ordered[1:] != ordered[:-1]
    new_run[0] = True
    firsts = numpy.minimum.reduceat(order, new_run.nonzero()[0])
    by_first = firsts.argsort()
    number = numpy.empty(len(firsts), numpy.int64)
    number[by_first] = numpy.arange(len(firsts))
    group = numpy.empty(len(order), numpy.int64)
    group[order] = number.take(new_run.cumsum() - 1)
    return group, firsts.take(by_first)


_FEWEST_DEFERRED = 16  # moves (or arc parts) a sweep needs to be deferred (see Workpiece._defer)


@dataclass(frozen=True)
class _Waiting:
    """A deferred sweep (see :meth:`Workpiece._defer`): ``sweep(workpiece, *parts,
    cutter)`` applies it, ``parts`` one entry a piece; ``boxes`` (first row, stop row,
    first column, stop column; one column a piece) hold the cells each piece can lower,
    ``box`` all of them; ``left``: the pieces not applied yet. Not prepared yet (``boxes``
    None): ``sweep`` makes the prepared one from ``parts`` (a cut's moves as given, which
    become pieces only when a question first needs them), ``box`` holds every cell it can
    lower and ``size`` counts its moves."""

    sweep: object
    parts: tuple
    cutter: Cutter
    box: tuple[int, int, int, int]
    boxes: numpy.ndarray | None = None
    left: numpy.ndarray | None = None
    size: int = 0  # pieces left (moves, before it is prepared)

    @classmethod
    def of(cls, sweep, parts: tuple, cutter: Cutter, boxes) -> "_Waiting":
        return cls(sweep, parts, cutter, _whole_box(boxes), boxes, numpy.arange(boxes.shape[1]), boxes.shape[1])

    @property
    def nbytes(self) -> int:
        """Bytes its arrays hold (pieces applied are not freed until all are)."""
        arrays = [getattr(part, field.name) for part in self.parts if isinstance(part, XYArcs) for field in fields(part)]
        arrays += [part for part in self.parts if isinstance(part, numpy.ndarray)]
        arrays += [] if self.boxes is None else [self.boxes, self.left]
        return sum(array.nbytes for array in arrays)

    def prepared(self, workpiece: "Workpiece") -> "_Waiting":
        return self if self.boxes is not None else self.sweep(workpiece, *self.parts, self.cutter)

    def split(self, window) -> tuple[numpy.ndarray, numpy.ndarray]:
        """(reaching, rest): the pieces left whose boxes meet ``window``, and the others."""
        first_row, stop_row, first_column, stop_column = window
        boxes = self.boxes.take(self.left, axis=1)
        meets = (boxes[0] < stop_row) & (boxes[1] > first_row) & (boxes[2] < stop_column) & (boxes[3] > first_column)
        return self.left[meets], self.left[~meets]

    def apply(self, workpiece: "Workpiece", pieces) -> None:
        self.sweep(workpiece, *(part.take(pieces) if isinstance(part, XYArcs) else part.take(pieces, axis=0) for part in self.parts), self.cutter)


class _Backlog:
    """A workpiece's deferred sweeps (:class:`_Waiting`), oldest first, with their boxes in
    one array: a question finds the sweeps its window meets in one step, however many wait
    (a million-move program leaves hundreds of sweeps of the buffer's size)."""

    def __init__(self, sweeps=(), boxes=None, nbytes: int = 0):
        self.sweeps = list(sweeps)
        self.boxes = numpy.empty((0, 4), numpy.int64) if boxes is None else boxes  # replaced, never written into: copies share it
        self.nbytes = nbytes  # held by the sweeps' arrays

    def __len__(self) -> int:
        return len(self.sweeps)

    def copy(self) -> "_Backlog":
        return _Backlog(self.sweeps, self.boxes, self.nbytes)  # each _Waiting is never changed, only replaced

    def add(self, waiting: "_Waiting") -> None:
        self.sweeps.append(waiting)
        self.boxes = numpy.concatenate([self.boxes, numpy.array([waiting.box], numpy.int64)])
        self.nbytes += waiting.nbytes

    def pop_oldest(self) -> "_Waiting":
        self.boxes = self.boxes[1:]
        oldest = self.sweeps.pop(0)
        self.nbytes -= oldest.nbytes
        return oldest

    def settle(self, workpiece: "Workpiece", window) -> None:
        """Apply the pieces that may reach ``window`` (first row, stop row, first column,
        stop column) to ``workpiece``; what is left of their sweeps keeps waiting."""
        first_row, stop_row, first_column, stop_column = window
        boxes = self.boxes
        meets = (boxes[:, 0] < stop_row) & (boxes[:, 1] > first_row) & (boxes[:, 2] < stop_column) & (boxes[:, 3] > first_column)
        emptied = []
        for index in numpy.flatnonzero(meets).tolist():
            waiting = self.sweeps[index].prepared(workpiece)
            reaching, rest = waiting.split(window)
            if len(reaching):
                waiting.apply(workpiece, reaching)
            self.nbytes -= self.sweeps[index].nbytes
            self.sweeps[index] = replace(waiting, left=rest, size=len(rest))
            if len(rest):
                self.nbytes += self.sweeps[index].nbytes
            else:
                emptied.append(index)
        if emptied:
            kept = numpy.ones(len(self.sweeps), bool)
            kept[emptied] = False
            self.sweeps = [waiting for waiting, keep in zip(self.sweeps, kept.tolist()) if keep]
            self.boxes = self.boxes[kept]


def _whole_box(boxes) -> tuple[int, int, int, int]:
    """The box of cells that holds every one of ``boxes`` (see :meth:`Workpiece._cell_boxes`)."""
    return int(boxes[0].min()), int(boxes[1].max()), int(boxes[2].min()), int(boxes[3].max())


@dataclass(frozen=True)
class _Near:
    """The cells near a chunk of pieces: ``pieces`` (their indices), the ``group`` of each
    (its place among ``leaders``, the first piece of each group), and an entry per (group,
    cell): its ``owner`` group, ``flat`` cell index and ``distance`` from the group's path,
    group after group, each one's cells row by row."""

    pieces: numpy.ndarray
    group: numpy.ndarray
    leaders: numpy.ndarray
    owner: numpy.ndarray
    flat: numpy.ndarray
    distance: numpy.ndarray | None  # None: a flat end's cells, each touched, and those it covers below
    covered_owner: numpy.ndarray | None = None
    covered_flat: numpy.ndarray | None = None

    @property
    def alone(self) -> bool:
        """Is every piece a group of its own (most batches)?"""
        return len(self.leaders) == len(self.pieces)

    def least(self, values):
        """The least of ``values`` (one a piece, all pieces) in each group."""
        if self.alone:
            return values.take(self.pieces)
        least = numpy.full(len(self.leaders), numpy.inf)
        numpy.minimum.at(least, self.group, values.take(self.pieces))
        return least

    def entries_of_each_piece(self):
        """(member, entry): every piece's entries, piece after piece, ``member`` its place in
        ``pieces`` and ``entry`` its group's entry (None: each piece alone, the entries as
        they are)."""
        if self.alone:
            return self.owner, None
        counts = numpy.bincount(self.owner, minlength=len(self.leaders))
        each = counts.take(self.group)
        entry = (counts.cumsum() - counts).take(self.group).repeat(each) + _ramp(each)
        return numpy.arange(len(self.pieces)).repeat(each), entry

    def each_piece(self):
        """(piece, flat cell, distance) of every piece's cells, piece after piece."""
        member, entry = self.entries_of_each_piece()
        if entry is None:
            return self.pieces.take(member), self.flat, self.distance
        return self.pieces.take(member), self.flat.take(entry), self.distance.take(entry)


@dataclass(frozen=True)
class _Rows:
    """The rows a chunk of pieces is measured on: an entry per (piece, row), with the
    ``piece``, its ``place`` among the chunk's, the ``row`` and its centre's ``y``, the
    ``across`` term of the distance, the ``reach`` and ``rounding`` of the piece, and the
    ``spans`` of columns (first, stop) whose centres may lie within the reach."""

    segments: "_Segments"
    piece: numpy.ndarray
    place: numpy.ndarray
    row: numpy.ndarray
    y: numpy.ndarray
    across: numpy.ndarray
    reach: numpy.ndarray
    rounding: numpy.ndarray
    spans: tuple

    @classmethod
    def of(cls, workpiece: Workpiece, pieces, segments: "_Segments", rows, first_row, reach, rounding, column_low, column_high):
        piece = pieces.repeat(rows[pieces])
        row = first_row.take(piece) + _ramp(rows[pieces])
        y = workpiece._y(row)
        reach, rounding = reach.take(piece), rounding.take(piece)
        spans = workpiece._row_spans(segments, reach + rounding, piece, y, column_low.take(piece), column_high.take(piece))
        return cls(segments, piece, numpy.arange(len(pieces)).repeat(rows[pieces]), row, y, (y - segments.ay.take(piece)) * segments.dy.take(piece),
                   reach, rounding, spans)


def _span_cells(first, stop):
    """(entry, column) of every cell of the spans first-stop (one an entry, stop >= first),
    span after span."""
    widths = stop - first
    entry = numpy.arange(len(first)).repeat(widths)
    return entry, numpy.arange(len(entry)) + (first - widths.cumsum() + widths).take(entry)


def _capsule_crossing(segments: "_Segments", piece, y, radius, outward: bool):
    """(left, right): where the row at ``y`` crosses the points within ``radius`` of each
    segment ``piece`` (one an entry); left > right where it does not. That set is the
    union of a disc at each end and the rectangle between, and convex, so the crossing is
    the hull of those three crossings. Where the arithmetic fails (a length whose square
    overflows) the crossing is taken for the whole row (``outward``) or for nothing."""
    ax, ay, dx, dy = (terms.take(piece) for terms in (segments.ax, segments.ay, segments.dx, segments.dy))
    with numpy.errstate(all="ignore"):
        length = _length(dx, dy)
        left, right = numpy.full(len(piece), numpy.inf), numpy.full(len(piece), -numpy.inf)
        for end_x, end_y in ((ax, ay), (ax + dx, ay + dy)):
            half_chord = numpy.sqrt(radius * radius - (y - end_y) ** 2)  # NaN where the row passes the disc
            left, right = numpy.fmin(left, end_x - half_chord), numpy.fmax(right, end_x + half_chord)
        along = y - ay
        # the rectangle: 0 <= (x - ax) dx + along dy <= length², |(x - ax) dy - along dx| <= radius length
        low_t, high_t = _solve_linear(dx, -along * dy, length * length - along * dy)
        low_s, high_s = _solve_linear(dy, along * dx - radius * length, along * dx + radius * length)
        low, high = ax + numpy.maximum(low_t, low_s), ax + numpy.minimum(high_t, high_s)
        band = (length > 0.0) & (low <= high)
        left, right = numpy.where(band, numpy.fmin(left, low), left), numpy.where(band, numpy.fmax(right, high), right)
    failed = ~numpy.isfinite(length)
    empty = radius < 0.0
    if outward:
        return numpy.where(failed, -numpy.inf, numpy.where(empty, numpy.inf, left)), numpy.where(failed, numpy.inf, numpy.where(empty, -numpy.inf, right))
    empty |= failed
    return numpy.where(empty, numpy.inf, left), numpy.where(empty, -numpy.inf, right)


def _solve_linear(factor, low, high):
    """(low, high) of the x with ``low <= x * factor <= high`` (one an entry); low > high where none."""
    with numpy.errstate(all="ignore"):
        sloped = factor != 0.0
        divided = numpy.where(sloped, factor, 1.0)
        first, second = low / divided, high / divided
        below, above = numpy.minimum(first, second), numpy.maximum(first, second)
    level_inside = (low <= 0.0) & (high >= 0.0)
    return (numpy.where(sloped, below, numpy.where(level_inside, -numpy.inf, numpy.inf)),
            numpy.where(sloped, above, numpy.where(level_inside, numpy.inf, -numpy.inf)))


def _ramp(counts):
    """0, 1, .. counts[0] - 1, 0, 1, .. counts[1] - 1, ..: each entry's place in its group."""
    return numpy.arange(int(counts.sum())) - (counts.cumsum() - counts).repeat(counts)


def _laid_on_slab(starts, ends, low: float, high: float):
    """Moves cut where they cross the heights ``low`` and ``high``, each point
    ``start + t * (end - start)`` with its Z clipped between them: (piece starts, piece
    ends, pieces a move). A height a move does not cross clips to one of its ends; the piece
    of no length it would leave there is not kept."""
    rise = ends[:, 2] - starts[:, 2]
    with numpy.errstate(divide="ignore", invalid="ignore"):
        crossings = [numpy.where(rise != 0.0, (level - starts[:, 2]) / rise, 0.0) for level in (low, high)]
    ts = numpy.sort(numpy.clip(numpy.stack([numpy.zeros(len(starts)), *crossings, numpy.ones(len(starts))], axis=1), 0.0, 1.0), axis=1)
    steps = ts.shape[1]  # each axis of the points worked out in one flat array: broadcasting over (moves, points, axes) ran loops three long
    axes = [starts[:, axis].repeat(steps) + ts.reshape(-1) * (ends[:, axis] - starts[:, axis]).repeat(steps) for axis in range(3)]
    axes[2].clip(low, high, out=axes[2])
    points = numpy.stack(axes, axis=-1).reshape(len(starts), steps, 3)
    kept = ~(ts[:, 1:] <= ts[:, :-1])
    return points[:, :-1][kept], points[:, 1:][kept], kept.sum(axis=1)


@dataclass(frozen=True)
class _Segments:
    """XY segments a-b (row-wise) as the terms :func:`_nearest_on_segment` computes from
    them, worked out once per segment."""

    ax: numpy.ndarray
    ay: numpy.ndarray
    dx: numpy.ndarray
    dy: numpy.ndarray
    divisor: numpy.ndarray  # the squared length, or infinity for a point (its nearest point is a)

    @classmethod
    def of(cls, a, b):
        return cls.between(a[:, 0], a[:, 1], b[:, 0], b[:, 1])

    @classmethod
    def between(cls, ax, ay, bx, by):
        dx, dy = bx - ax, by - ay
        length_sq = dx * dx + dy * dy
        return cls(ax, ay, dx, dy, numpy.where(length_sq > 0, length_sq, numpy.inf))

    def distance_from(self, owner, px, py):
        """:meth:`distance` of points (px, py) from segments ``owner``."""
        ay, dy = (self.ay, self.dy) if owner is None else (self.ay[owner], self.dy[owner])
        return self.distance(owner, px, py, (py - ay) * dy)

    def distance(self, owner, px, py, across):
        """Distance of points (px, py) from segments ``owner`` (None: point ``k`` from
        segment ``k``), bit for bit as :func:`distance_to_segment` gives it; ``across``:
        (py - ay) * dy of each."""
        return _length(*self._offsets(owner, px, py, across))

    def near_on_rows(self, piece, entry, px, py, across, reach):
        """Which points lie within ``reach`` of their segments, and their :meth:`distance`:
        (indices, distances). The points come in runs (the cells of a row): point ``k`` is
        measured from segment ``piece[entry[k]]`` and shares ``py``, ``across`` and ``reach``
        with the other points of its run ``entry[k]``: the inner loop of the sweep, worked in
        place. Each term is gathered point by point through one index (spreading a run's
        terms by ``repeat`` cost twice as much)."""
        distance = self.distances_on_rows(piece, entry, px, py, across)
        near = (distance <= reach.take(entry)).nonzero()[0]
        return near, distance.take(near)

    def distances_on_rows(self, piece, entry, px, py, across):
        """The :meth:`distance` of each point of :meth:`near_on_rows` (``px`` is overwritten)."""
        owner = piece.take(entry)
        terms = [values.take(owner) for values in (self.ax, self.ay, self.dx, self.dy, self.divisor)]
        qx, qy = _offsets(*terms, px, py.take(entry), across.take(entry))
        distance = numpy.multiply(qx, qx)
        distance += numpy.multiply(qy, qy, out=px)
        return numpy.sqrt(distance, out=distance)  # as _length works it out

    def _offsets(self, owner, px, py, across):
        """(x, y) from the points (px, py) to their nearest points on segments ``owner``,
        computed in place as :func:`_nearest_on_segment` does (``px`` is kept)."""
        if owner is None:
            return _offsets(self.ax, self.ay, self.dx.copy(), self.dy.copy(), self.divisor, px, py, across)
        return _offsets(*(terms.take(owner) for terms in (self.ax, self.ay, self.dx, self.dy, self.divisor)), px, py, across)


def _offsets(ax, ay, dx, dy, divisor, px, py, across):
    """:meth:`_Segments._offsets` on the terms of each point's segment (``dx`` and ``dy``
    are overwritten)."""
    t = px - ax
    t *= dx
    t += across
    t /= divisor
    t.clip(0.0, 1.0, out=t)
    dx *= t
    dx += ax
    dy *= t
    dy += ay
    return numpy.subtract(px, dx, out=dx), numpy.subtract(py, dy, out=dy)


def _nearest_on_segment(px, py, a, b):
    """The points of the XY segments a-b (row-wise) nearest to the points (px, py)."""
    dx, dy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    length_sq = dx * dx + dy * dy
    t = numpy.where(length_sq > 0, ((px - a[:, 0]) * dx + (py - a[:, 1]) * dy) / numpy.where(length_sq > 0, length_sq, 1.0), 0.0)
    t = numpy.clip(t, 0.0, 1.0)
    return a[:, 0] + t * dx, a[:, 1] + t * dy


def distance_to_segment(px, py, a, b):
    """Distance of points (px, py) from the XY segments a-b (row-wise)."""
    qx, qy = _nearest_on_segment(px, py, a, b)
    return _length(px - qx, py - qy)


def total_length(starts, ends) -> float:
    """The summed length of the moves ``starts``-``ends`` (rows of x, y, z), bit for bit
    as numpy.linalg.norm along the rows gives it (the squares added in the same order),
    without its cost on rows three wide (several times more)."""
    delta = ends - starts
    squares = delta[:, 0] * delta[:, 0]
    squares += delta[:, 1] * delta[:, 1]
    squares += delta[:, 2] * delta[:, 2]
    return float(numpy.sqrt(squares, out=squares).sum())


def _sink(field, flat, heights, up: bool) -> None:
    """Lower ``field`` (flat cell indices) to ``heights`` where they are lower, rounding the
    stored float32 outwards: up for an upper bound, down for a lower one."""
    if not len(flat):
        return
    numpy.minimum.at(field.reshape(-1), flat, _float32_outwards(heights, up))


def _sink_groups(field, flat, owners, heights, lift, up: bool) -> None:
    """:func:`_sink` for entries of groups of pieces: cell ``flat[k]`` is lowered to
    ``heights[owners[k]]`` (each group's lowest piece) plus ``lift[k]``, the tool surface's
    height over its tip there. No ``lift`` (None): the surface is flat, at the group's
    height on every cell, rounded once a group instead of once a cell (+ 0.0 stores a
    height of -0.0 as the sum with a zero lift does)."""
    if lift is None:
        numpy.minimum.at(field.reshape(-1), flat, _float32_outwards(heights + 0.0, up).take(owners))
    else:
        _sink(field, flat, heights.take(owners) + lift, up)


def _float32_outwards(heights, up: bool):
    """``heights`` as float32, rounded up (``up``) or down where the nearest float32 lies
    on the other side: what ``numpy.nextafter`` towards an infinity gives on those, done on
    the bits (sign and magnitude: one step of the magnitude is one float32 step, up for a
    value above zero, down below it), which costs several times less than its masked form."""
    stored = heights.astype(numpy.float32)
    rounded_wrong = stored < heights if up else stored > heights
    bits = stored.view(numpy.int32)
    steps = bits >> 31  # 0 above zero, -1 below (the sign bit spread)
    steps |= 1
    steps *= rounded_wrong
    if up:
        bits += steps
    else:
        bits -= steps
    return stored


_SAME_RAY = 1e-12  # sine of the angle within which two directions from a centre are taken for one ray (see unsettled_turns)
_GROUP = 64  # moves in the largest group merged into one chord
_SPANS_FROM_CELLS = 2.0  # a flat end's radius, in cells, from which its cells are taken a row's stretch at a time: below it the band is a few cells wide, nearly all of them at its edges, and working out the stretches cost more than it spared (random walks at 0.5 mm cells: even at 1 mm, twice as fast at 4 mm)
_TREE_AT_ONCE = 1024  # moves in the groups left up to which they and every group below them are judged in one step


@dataclass(frozen=True)
class _Path:
    """Moves as :func:`_merge_runs` judges them: the XY of their starts and ends, each
    one's lowest and highest Z, and ``breaks``: how many moves up to each one start away
    from the end before them."""

    x0: numpy.ndarray
    y0: numpy.ndarray
    x1: numpy.ndarray
    y1: numpy.ndarray
    low: numpy.ndarray
    high: numpy.ndarray
    breaks: numpy.ndarray

    @classmethod
    def of(cls, starts, ends):
        breaks = numpy.zeros(len(starts), numpy.int64)
        apart = starts[1:, 0] != ends[:-1, 0]
        apart |= starts[1:, 1] != ends[:-1, 1]
        apart |= starts[1:, 2] != ends[:-1, 2]
        apart.cumsum(out=breaks[1:])
        return cls(starts[:, 0], starts[:, 1], ends[:, 0], ends[:, 1], numpy.minimum(starts[:, 2], ends[:, 2]), numpy.maximum(starts[:, 2], ends[:, 2]), breaks)


def _merge_runs(starts, ends, strays, tolerance: float, rise: float):
    """Consecutive moves of a connected path merged into chords where no vertex strays more
    than ``tolerance`` from the chord in XY and the heights stay within ``rise``: CAM output
    is thousands of tiny moves, and their tool discs overlap almost wholly. Each chord
    carries its heights' range and its actual stray (``slack``), which the sweep takes off
    the tool radius where it claims material is surely gone and adds where it may be, and
    the largest of its moves' own ``strays`` (how far the true path leaves a move).

    The groups tried are those of a fixed tree: the moves in groups of 64, each split in
    halves (the first half the larger) where it does not fit, down to single moves. Level
    by level, only the halves of groups that failed are judged; once the groups left hold
    few moves (where the steps would cost more than the groups a step spares), they and
    every group below them are judged at once, each move going to the largest group over
    it that fits: the same groups."""
    path = _Path.of(starts, ends)
    count = len(starts)
    if _none_join(path, rise):  # each move is a chord of its own (a drilling cycle's plunges, moves between arcs)
        return starts, ends, path.low, path.high, _single_strays(path, numpy.arange(count)), strays
    first, length, stray = _kept_groups(path, tolerance, rise)
    group = _group_of(first, count)
    z_low, z_high = _reduce_groups(numpy.minimum, path.low, first, group), _reduce_groups(numpy.maximum, path.high, first, group)
    return starts.take(first, axis=0), ends.take(first + length - 1, axis=0), z_low, z_high, stray, _reduce_groups(numpy.maximum, strays, first, group)


def _as_given(starts, ends, strays):
    """The moves in the form :func:`_merge_runs` gives, each a chord of its own: a move is
    its own chord, which it leaves nowhere (the merge's singles measure the rounding of that
    distance, to judge them alike with its groups)."""
    return starts, ends, numpy.minimum(starts[:, 2], ends[:, 2]), numpy.maximum(starts[:, 2], ends[:, 2]), numpy.zeros(len(starts)), strays


def _none_join(path: _Path, rise: float) -> bool:
    """No two moves side by side in a group of the merge's tree start one where the other
    ends with their heights together within ``rise``. Every group of more than one move
    that fits holds such a pair, so then no such group fits, and the tree keeps every move
    alone."""
    joined = path.breaks[1:] == path.breaks[:-1]
    joined[_GROUP - 1::_GROUP] = False  # the last move of a group of 64 and the first of the next share no group
    joined &= numpy.maximum(path.high[1:], path.high[:-1]) - numpy.minimum(path.low[1:], path.low[:-1]) <= rise
    return not joined.any()


def _kept_groups(path: _Path, tolerance: float, rise: float):
    """(first, length, stray) of the groups :func:`_merge_runs` keeps, in order."""
    count = len(path.breaks)
    first = numpy.arange(0, count, _GROUP)
    length = numpy.minimum(_GROUP, count - first)
    done = []
    while len(first):
        if int(length.sum()) <= _TREE_AT_ONCE:
            done.append(_fitting_groups(path, first, length, tolerance, rise))
            break
        fits, stray = _chords_fit(path, first, length, tolerance, rise)
        done.append((first[fits], length[fits], stray[fits]))
        first, length = _halves(first[~fits], length[~fits])
    first, length, stray = (numpy.concatenate(column) for column in zip(*done))
    order = numpy.argsort(first, kind="stable")  # no two groups start alike; timsort merges the levels' sorted runs
    return first[order], length[order], stray[order]


def _group_of(first, count: int):
    """The group of each of ``count`` items cut into consecutive groups at ``first`` (from 0)."""
    starts = numpy.zeros(count, numpy.intp)
    starts[first[1:]] = 1
    return starts.cumsum(out=starts)


def _reduce_groups(ufunc, values, first, group):
    """``ufunc.reduceat(values, first)`` for consecutive groups from ``first`` (from 0, none
    empty; ``group``: each value's, see :func:`_group_of`): the same values, the same
    steps in the same order (each group's first value met once more, which changes
    nothing), by ``ufunc.at``, which costs several times less than reduceat where most
    groups are a few values long."""
    reduced = values.take(first)
    ufunc.at(reduced, group, values)
    return reduced


def _halves(first, length):
    """The two halves of each group of more than one move (the first half the larger)."""
    split = length > 1
    first, length = first[split], length[split]
    half = (length + 1) // 2
    return numpy.concatenate((first, first + half)), numpy.concatenate((half, length - half))


def _fitting_groups(path: _Path, first, length, tolerance: float, rise: float):
    """(first, length, stray) of the groups :func:`_merge_runs` keeps of the groups
    ``first``/``length`` and all of their halves, judged at once, in the order of their
    first moves: a group is kept where it fits and no group over it does."""
    trees = [_halving_tree(int(size)) for size in length.tolist()]
    every_first = numpy.concatenate([top + tree[0] for top, tree in zip(first.tolist(), trees)])
    every_length = numpy.concatenate([tree[1] for tree in trees])  # a group's halves follow it, and sort after it (below)
    fits, strays = every_length == 1, numpy.zeros(len(every_first))  # a single move always fits: its stray is found if it is kept
    groups = (~fits).nonzero()[0]
    fits[groups], strays[groups] = _chords_fit(path, every_first[groups], every_length[groups], tolerance, rise)
    fitting = fits.nonzero()[0]
    fitting = fitting[numpy.argsort(every_first[fitting] * (_GROUP + 1) + _GROUP - every_length[fitting])]  # by first move, larger first
    first, length, stray = every_first[fitting], every_length[fitting], strays[fitting]
    covered = numpy.maximum.accumulate(first + length)  # groups nest or are apart: one inside a fitting group starts before its end
    kept = numpy.ones(len(first), bool)
    kept[1:] = first[1:] >= covered[:-1]
    first, length, stray = first[kept], length[kept], stray[kept]
    single = (length == 1).nonzero()[0]
    stray[single] = _single_strays(path, first[single])
    return first, length, stray


@functools.lru_cache(maxsize=_GROUP)
def _halving_tree(size: int):
    """(first move, length) of every group of the merge's tree over ``size`` moves (at most
    a group of 64, so the cache holds at most 64 of these small arrays), from 0."""
    first, length = numpy.zeros(1, numpy.int64), numpy.array([size])
    levels = [(first, length)]
    while len(first):
        first, length = _halves(first, length)
        levels.append((first, length))
    tree = tuple(numpy.concatenate([level[column] for level in levels]) for column in (0, 1))
    for column in tree:
        column.flags.writeable = False
    return tree


def _single_strays(path: _Path, moves):
    """How far each of ``moves`` strays from its own chord: rounding, no more."""
    x1, y1 = path.x1[moves], path.y1[moves]
    return _Segments.between(path.x0[moves], path.y0[moves], x1, y1).distance_from(None, x1, y1)


def _chords_fit(path: _Path, first, length, tolerance: float, rise: float):
    """Which groups (first move, number of moves) of ``path`` may become one chord, and for
    those the most any of their vertices strays from it (0 for a group that cannot: broken,
    or failing its screen). A group is first screened by its breaks and by the vertex in
    its middle (a chord of a curve strays most there), then the groups that pass are judged
    on all of their vertices: the same answers as judging all of every group."""
    last = first + length - 1
    fits = length == 1
    strays = numpy.zeros(len(first))
    strays[fits] = _single_strays(path, first[fits])
    joined = (~fits & (path.breaks[last] == path.breaks[first])).nonzero()[0]
    first, last, length = first[joined], last[joined], length[joined]
    middle = first + (length - 1) // 2
    chords = _Segments.between(path.x0[first], path.y0[first], path.x1[last], path.y1[last])
    may_fit = chords.distance_from(None, path.x1[middle], path.y1[middle]) <= tolerance
    may_fit &= numpy.maximum(path.high[first], path.high[middle]) - numpy.minimum(path.low[first], path.low[middle]) <= rise
    judged = may_fit.nonzero()[0]
    if len(judged):
        group = numpy.arange(len(judged)).repeat(length[judged])
        owner = judged.take(group)
        index = _ramp(length[judged]) + first[owner]
        offsets = length[judged].cumsum() - length[judged]
        stray = _reduce_groups(numpy.maximum, chords.distance_from(owner, path.x1[index], path.y1[index]), offsets, group)
        strays[joined[judged]] = stray
        fits[joined[judged]] = (stray <= tolerance) & (
            _reduce_groups(numpy.maximum, path.high[index], offsets, group) - _reduce_groups(numpy.minimum, path.low[index], offsets, group) <= rise)
    return fits, strays


_ROUND_SEGMENTS = 32  # quarter-circle segments of a buffered nose
_TOUCH = 1e-6  # mm: a point tip this close to the material's edge runs along it, not in it


def _inscribed_error(radius: float) -> float:
    """How far a buffer's polygon stays inside its true circle (and 1 nm of rounding)."""
    return radius * (1.0 - math.cos(math.pi / (4 * _ROUND_SEGMENTS))) + 1e-6


class Bar:
    """A lathe bar's half-section in the (Z, radius) plane, turned by an insert of nose
    radius ``nose``. As in the height field, two shapes bound the material: ``most`` has
    only what the nose surely swept taken away, ``least`` everything it may have swept.

    Positions are the tool's programmed point as (radius, z): the insert's theoretical tip.
    Where the nose centre lies depends on the cutting-edge position (:func:`nose_centre`);
    without it the nose may be anywhere within (1 + sqrt 2) nose radii of the tip, and
    nothing is surely cut."""

    def __init__(self, stock: Stock):
        if stock.kind != "cylinder":
            raise ValueError(f"a {stock.kind} stock is not a lathe bar")
        low, high = stock.z_range
        section = shapely.box(low, 0.0, high, stock.diameter / 2.0)
        self.most, self.least = section, section
        self.cuts = 0

    def cut(self, start, end, nose: float, centre_offset=None) -> None:
        """Sweep the nose from ``start`` to ``end`` ((radius, z) tips). ``centre_offset``:
        (d_radius, d_z) from the tip to the nose centre, when the edge position is known."""
        self.cut_many([start], [end], nose, centre_offset)

    def cut_many(self, starts, ends, nose: float, centre_offset=None) -> None:
        """:meth:`cut` for many moves at once (rows of (radius, z)): one union, one difference."""
        if not len(starts):
            return
        self.cuts += 1
        self.least = self.least.difference(_swept_many(starts, ends, (0.0, 0.0), nose * (1 + math.sqrt(2)), outwards=True))
        if centre_offset is not None:
            self.most = self.most.difference(_swept_many(starts, ends, centre_offset, nose, outwards=False))

    def cut_anywhere(self) -> None:
        """A cut that cannot be placed: any material may be gone, none is surely gone."""
        self.cuts += 1
        self.least = shapely.Polygon()

    def rapid(self, start, end, nose: float, centre_offset=None) -> RapidVerdict:
        """``clear`` when no place the nose may be meets what may be left; ``hits`` when the
        nose surely meets what is surely left (its centre inside it, wherever the edge
        position puts it); ``unsure`` otherwise.

        The cuts took polygons inscribed in the nose's circles off ``most``, so a rapid
        along a line the nose has just cut finds slivers of the polygons' error left there:
        a nose coming closer to ``most`` than that error (:func:`_inscribed_error`, 0.3 µm
        per mm of nose radius) is taken as tangent to it, not in it."""
        if centre_offset is None:
            centres, reach = _path(start, end, (0.0, 0.0)), nose * (1 + math.sqrt(2))
        else:
            centres, reach = _path(start, end, centre_offset), nose
        if reach > 0.0:
            clear = centres.distance(self.most) >= reach - _inscribed_error(nose)
        else:  # a point tip: clear unless it runs through the inside
            clear = not centres.intersects(self.most.buffer(-_TOUCH))
        if self.most.is_empty or clear:
            return RapidVerdict("clear")
        if centre_offset is not None:
            overlap = _swept(start, end, centre_offset, nose, outwards=False).intersection(self.least)
        else:  # the nose centre lies within sqrt(2) nose radii of the tip, whatever the edge position
            overlap = _path(start, end, (0.0, 0.0)).intersection(self.least.buffer(-nose * math.sqrt(2) - 1e-9))
        if not overlap.is_empty and (overlap.area > 0.0 or centre_offset is None):
            point = overlap.representative_point()
            return RapidVerdict("hits", (point.y, point.x))
        return RapidVerdict("unsure")


_TIP_FROM_CENTRE = {  # cutting-edge position SL: where the theoretical tip lies from the nose centre, as (radius, z) signs
    1: (1, 1), 2: (1, -1), 3: (-1, -1), 4: (-1, 1), 5: (0, 1), 6: (1, 0), 7: (0, -1), 8: (-1, 0), 9: (0, 0),
}


def nose_centre(edge_position, nose: float):
    """(d_radius, d_z) from the theoretical tip to the nose centre for a cutting-edge
    position SL 1..9 (radius growing away from the spindle axis, Z towards the tailstock;
    SL 3: an external tool cutting towards the chuck), or None when it is not known."""
    signs = _TIP_FROM_CENTRE.get(int(edge_position)) if type(edge_position) is float and edge_position.is_integer() else None
    if signs is None:
        return None
    return -signs[0] * nose, -signs[1] * nose


def _path(start, end, offset):
    """The tip's path shifted by ``offset``, as a shapely line (or a point) in (z, radius)."""
    line = shapely.LineString([(start[1] + offset[1], start[0] + offset[0]), (end[1] + offset[1], end[0] + offset[0])])
    return shapely.Point(line.coords[0]) if line.length == 0.0 else line


def _swept(start, end, offset, radius: float, outwards: bool):
    """The nose's path (in (z, radius) coordinates) thickened by ``radius``: a polygon that
    contains the true round sweep when ``outwards``, and lies inside it otherwise."""
    chord_factor = 1.0 / math.cos(math.pi / (4 * _ROUND_SEGMENTS)) if outwards else 1.0
    return _path(start, end, offset).buffer(radius * chord_factor, quad_segs=_ROUND_SEGMENTS)


def _swept_many(starts, ends, offset, radius: float, outwards: bool):
    """The union of :func:`_swept` over rows of starts and ends, built vectorised."""
    starts, ends = numpy.asarray(starts, float), numpy.asarray(ends, float)
    shift = numpy.asarray(offset, float)[::-1]
    coords = numpy.stack([starts[:, ::-1] + shift, ends[:, ::-1] + shift], axis=1)
    lines = shapely.linestrings(coords)
    chord_factor = 1.0 / math.cos(math.pi / (4 * _ROUND_SEGMENTS)) if outwards else 1.0
    return shapely.union_all(shapely.buffer(lines, radius * chord_factor, quad_segs=_ROUND_SEGMENTS))


def unsettled_turns(starts, ends, centres, planes):
    """Which arcs (as :func:`arc_chords` takes them) end on their start's own ray from the
    centre, at another point (the end off the circle): whether such an arc turns once or
    not at all comes down to the rounding of two arc tangents, and a control's arithmetic
    may decide it either way, where :func:`arc_chords` takes the turn its own gives."""
    rows = numpy.arange(len(starts))
    first, second = (numpy.asarray(planes[:, axis], numpy.int64) for axis in (0, 1))
    return _end_on_start_ray(starts[rows, first] - centres[:, 0], starts[rows, second] - centres[:, 1],
                             ends[rows, first] - centres[:, 0], ends[rows, second] - centres[:, 1])


def turn_unsettled(start, centre, end) -> bool:
    """:func:`unsettled_turns` for one arc, given by numbers on its plane's two axes (for the
    rules, which see one arc at a time): the same arithmetic, so that the rules and the cut
    stock never part on an arc at the edge of the test."""
    return bool(_end_on_start_ray(start[0] - centre[0], start[1] - centre[1], end[0] - centre[0], end[1] - centre[1]))


def _end_on_start_ray(sx, sy, ex, ey):
    """Does the end (ex, ey) lie on the ray from the centre through the start (sx, sy), at
    another point? Offsets from the centre, numbers or arrays alike."""
    along = (sx * ex + sy * ey > 0.0) & (numpy.abs(sx * ey - sy * ex) <= _SAME_RAY * numpy.hypot(sx, sy) * numpy.hypot(ex, ey))
    return along & ((sx != ex) | (sy != ey))


def arc_chords(starts, ends, centres, clockwise, planes, tolerance: float = 0.01):
    """Chords of many circular (or helical) moves at once, none farther than ``tolerance``
    from its arc: (chord starts, chord ends) as arrays of (x, y, z), the sagitta each chord
    keeps to, and the arc each chord belongs to. Row ``k`` of the inputs is one arc: its
    start and end points, its ``centres[k]`` on the plane's two axes, whether it turns
    clockwise, and ``planes[k]``, the indices of its first, second and normal axis (G17:
    0, 1, 2). An arc that ends where it starts is a full circle."""
    starts, ends = numpy.asarray(starts, float).reshape(-1, 3), numpy.asarray(ends, float).reshape(-1, 3)
    centres, planes = numpy.asarray(centres, float).reshape(-1, 2), numpy.asarray(planes, numpy.int64).reshape(-1, 3)
    clockwise = numpy.asarray(clockwise, bool).reshape(-1)
    arcs = numpy.arange(len(starts))
    first, second, normal = planes.T
    radius = numpy.hypot(starts[arcs, first] - centres[:, 0], starts[arcs, second] - centres[:, 1])
    begin = numpy.arctan2(starts[arcs, second] - centres[:, 1], starts[arcs, first] - centres[:, 0])
    finish = numpy.arctan2(ends[arcs, second] - centres[:, 1], ends[arcs, first] - centres[:, 0])
    sweep = numpy.where(clockwise, begin - finish, finish - begin) % (2 * math.pi)
    sweep[sweep == 0.0] = 2 * math.pi  # a full circle
    with numpy.errstate(divide="ignore", invalid="ignore"):
        step = numpy.where(radius > tolerance, 2 * numpy.arccos(numpy.maximum(-1.0, 1 - tolerance / radius)), math.pi / 2)
    counts = numpy.maximum(1, numpy.ceil(sweep / step)).astype(numpy.int64)
    owner = numpy.repeat(arcs, counts + 1)  # each arc's points, its end included
    fraction = (numpy.arange(len(owner)) - numpy.repeat(numpy.cumsum(counts + 1) - (counts + 1), counts + 1)) / counts[owner]
    angles = begin[owner] + numpy.where(clockwise[owner], -1.0, 1.0) * sweep[owner] * fraction
    normal_start = starts.reshape(-1)[3 * owner + normal[owner]]
    along = (centres[owner, 0] + radius[owner] * numpy.cos(angles), centres[owner, 1] + radius[owner] * numpy.sin(angles),
             normal_start + (ends.reshape(-1)[3 * owner + normal[owner]] - normal_start) * fraction)  # each point on the plane's axes
    points = numpy.empty((len(owner), 3))
    if (planes == planes[0]).all():  # one plane (the usual batch): its axes are columns
        for axis, values in zip(planes[0].tolist(), along):
            points[:, axis] = values
    else:
        cells, row = points.reshape(-1), numpy.arange(0, 3 * len(owner), 3)  # each point's (x, y, z) in one flat array: an axis a point is a cell
        for axes, values in zip((first, second, normal), along):
            cells[row + axes[owner]] = values
    last = numpy.cumsum(counts + 1) - 1
    points[last] = ends
    sagitta = radius * (1 - numpy.cos(sweep / counts / 2))
    chord = numpy.ones(len(owner), bool)
    chord[last] = False  # a chord runs from each point but an arc's last to the next
    begins = numpy.flatnonzero(chord)
    return points.take(begins, axis=0), points.take(begins + 1, axis=0), sagitta[owner[chord]], owner[chord]
