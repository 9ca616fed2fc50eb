"""Stage 3, interpret: run the IR on an abstract machine and stream the trace to the rules.

The machine state holds the position of every axis, every modal group, the active tool and
offsets, spindle, coolant, the modal canned cycle and the call stack. Values are floats
where known and :class:`~ncverify.values.Sym` where they depend on a free parameter.

This module runs blocks and carries out the operations that change the machine: modal
codes, offsets and frames, feed, spindle, tools, moves, cycles and variables. Straight-line
code streams, and a long streak of plain blocks runs as one batch. Where execution goes
next (branches, jumps, loops, labels, calls and returns, program ends) is in
:mod:`ncverify.interpret.control_flow`, a mixin of :class:`Interpreter`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import lru_cache, partial
from operator import itemgetter

import numpy

from .. import frames, ir, values
from .control_flow import ControlFlow, CallFrame, LoopFrame, PathEnd, Position
from .cycles import ActiveCycle, CycleRunner
from .runtime import moved_to
from .fagor import FagorState
from .heidenhain.state import KlartextState
from . import compiled, loop_runner, modal_call
from .arc_geometry import arc_by_centre, arc_by_radius, arc_through, end_heading, tangent_arc, unplaced_arc
from ..context import ToolTable, compensated
from ..settings import Settings
from ..source import ProgramSource, Span
from ..trace import ROTARY_AXES, RUN_AXES, Arc, Change, Fault, MotionRun, Segment, any_in_row
from ..dialect import logical_lines
from ..values import VACANT, Condition, DomainError, Sym
from ..verdict import evaluate_constraint, hazard, judge, show
from ..project import assumption_bounds, assumption_names, parameter_name

_ARC_KINDS = {"arc_cw": "cw", "arc_ccw": "ccw", "arc_through": None, "arc_tangent": None}  # None: the geometry gives the direction
_CENTRE_LETTERS = {"X": "I", "Y": "J", "Z": "K"}  # the word giving the arc centre's offset along each axis
_SEGMENT_KIND = {"rapid": "rapid", "linear": "feed", "arc_cw": "arc", "arc_ccw": "arc", "arc_through": "arc", "arc_tangent": "arc", "thread": "thread"}
_PLANES = {"xy": ("X", "Y", "Z"), "zx": ("Z", "X", "Y"), "yz": ("Y", "Z", "X")}


# ------------------------------------------------------------------------- machine state


@dataclass(frozen=True)
class FrameStatements:
    """The programmable frame statements in force (:func:`frames.after_statement`), and
    whether a tilted plane (CYCLE800) is on, which is kept apart from them. Replaced, never
    changed in place, so that it forks with the path."""

    programmable: frames.Frame = frames.IDENTITY
    layers: dict = field(default_factory=dict)
    swivel: bool = False
    unmodelled: frozenset = frozenset()  # the modal groups of ISO-style transformations that are on and not modelled


@dataclass(slots=True)
class MachineState:
    position: dict = field(default_factory=dict)
    modal: dict = field(default_factory=dict)
    feed: object = None
    spindle_speed: object = None
    spindle_clamp: object = None
    spindle: str = "off"
    coolant: str = "off"
    comp_side: str = "off"
    comp_register: object = None
    corners_rounded: bool = False  # SINUMERIK RNDM: every corner of the contour is rounded
    length_mode: str = "off"
    length_register: object = None
    tool_selected: object = None
    tool_in_spindle: object = None
    tool_offset: object = None
    tool_changed: bool = False
    cycle: ActiveCycle | None = None
    cycle_data: dict = field(default_factory=dict)
    lathe_cycle_data: dict = field(default_factory=dict)
    motion_seen: bool = False
    global_variables: dict = field(default_factory=dict)
    local_variables: dict = field(default_factory=dict)
    call_stack: list = field(default_factory=list)  # CallFrame per running program, the main program first
    loops: list = field(default_factory=list)
    jump_counts: dict = field(default_factory=dict)
    path_condition: list = field(default_factory=list)
    last_reference_via: dict = field(default_factory=dict)
    rule_state: dict = field(default_factory=dict)  # per-path memory of the rules (and of nothing else)
    klartext: KlartextState = field(default_factory=KlartextState)  # HEIDENHAIN dialect state (replaced, never changed in place)
    fagor: FagorState = field(default_factory=FagorState)  # Fagor dialect state (replaced, never changed in place)
    modal_call: modal_call.ModalCall | None = None  # the last modal call switched on (replaced, never changed in place)
    feed_inherited: bool = False  # a called program checked alone: its caller set the feed
    coordinate_shift: dict = field(default_factory=dict)  # G92/G52: machine = program + work offset + shift (None: unknown)
    frame: frames.Frame | None = None  # program -> workpiece coordinates (None: the identity)
    frame_statements: FrameStatements = field(default_factory=FrameStatements)
    # Axes standing at the machine's start or reference position ([machine] start): unknown
    # in program coordinates, placed there by the rules that judge where the tool comes from
    parked: frozenset = frozenset()
    left_start: frozenset = frozenset()  # axes parked until the last move: the segment it makes starts there
    last_segment: Segment | None = None  # the last move made: a tangential arc continues it
    # What the program changed that the model does not follow (a work offset or tool data it
    # wrote, the units it switched, once it began moving; a line it could not read): where
    # the tool's tip stands on the blank is not known from then on (ncverify.modelled.UNFOLLOWED)
    unfollowed: str | None = None
    set_up_written: str | None = None  # the same written before the first move: the stock is described in it, the project file's offsets are not

    def fork(self) -> "MachineState":
        twin = MachineState(**{name: getattr(self, name) for name in self.__slots__})
        for name in ("position", "modal", "cycle_data", "lathe_cycle_data", "global_variables", "jump_counts", "last_reference_via", "rule_state", "coordinate_shift"):
            setattr(twin, name, dict(getattr(self, name)))
        for memory in twin.rule_state.values():
            forked = getattr(memory, "forked", None)
            if forked is not None:
                forked()  # rule memory that changes in place (the workpiece): both paths copy it before changing it
        twin.local_variables = dict(self.local_variables)
        twin.call_stack = [CallFrame(**{n: getattr(f, n) for n in f.__slots__}) for f in self.call_stack]
        twin.loops = [LoopFrame(l.loop_id, l.head, l.iterations) for l in self.loops]
        twin.path_condition = list(self.path_condition)
        return twin

    def move_to(self, updates: dict) -> None:
        """Positions are copy-on-write: segments keep the dicts they were given. An axis
        moved to anything but its reference position is no longer parked."""
        self.position = {**self.position, **updates}
        self.leave_start(updates)

    def leave_start(self, axes) -> None:
        """The axes move: those that were parked are not any more, but the segment of this
        move still starts at the start position."""
        if self.parked or self.left_start:
            self.left_start = self.parked.intersection(axes)
            self.parked = self.parked.difference(axes)

    def park(self, axes) -> None:
        """The axes reach the machine's start or reference position (unknown in program
        coordinates)."""
        axes = tuple(axes)
        self.position = {**self.position, **dict.fromkeys(axes)}
        self.parked = self.parked.union(axes)
        self.left_start = self.left_start.difference(axes)

    @property
    def plane_axes(self) -> tuple[str, str, str]:
        return _PLANES[self.modal["plane"]]


# ------------------------------------------------------------------------- interpreter


class Interpreter(ControlFlow):
    """Runs one program (and the subprograms it calls) and reports to ``observer``.

    ``observer`` receives ``segment``, ``hole``, ``cycle_run``, ``change``, ``fault`` and
    ``note`` calls (see :mod:`ncverify.check`). ``runtime`` is the dialect's run-time hooks
    (:attr:`ncverify.dialect.DialectInfo.runtime`), if it has any; ``tools`` the tool table
    cycles read the tool in the spindle from."""

    def __init__(self, source: ProgramSource, frontend, observer, settings: Settings, *, power_on: dict,
                 cycle_models: dict, twins: dict, machine: str = "mill", increment: float = 0.0,
                 feed_increment: float = 0.0, library=None, assumptions=(), pins: dict | None = None, runtime=None,
                 tools: ToolTable | None = None, parked_at_start: tuple[str, ...] = ()):
        self.cycle_models = cycle_models
        self._dialect_batch_allowed = getattr(runtime, "batch_allowed", None)
        self._dialect_after_batch = getattr(runtime, "after_batch", None)
        self._system_variable = getattr(frontend, "system_variable", None)
        self._machine_data = getattr(frontend, "machine_data", None)
        self._machine_names: dict[str, tuple[str, bool] | None] = {}  # _machine_data_of's answers
        self._g43_takes_the_loaded_tool = getattr(frontend, "g43_takes_the_loaded_tool", False)
        self.twins = twins
        self.assigned: dict[int, list[tuple[str, object]]] = {}  # line -> (variable, value) of assignment statements, with settings.record_values
        self.tools = tools if tools is not None else ToolTable()
        self.source = source
        self.frontend = frontend
        self.observer = observer
        self.settings = settings
        self.power_on = dict(power_on)
        self.machine = machine
        self.increment = increment
        self.feed_increment = feed_increment
        self.library = library
        self.cycles = CycleRunner(self)
        self.programs: dict[int, dict[str, int]] = {}
        self.line_cache: dict[tuple[int, int], list[ir.Block]] = {}
        self.line_text: dict[tuple[int, int], list] = {}  # (source, offset) -> the line there (_read_lines), with its blocks once lowered
        self._seen: dict[int, object] = {}  # id -> expression evaluated before (kept, so that the id stays its own)
        self._closures: dict[int, object] = {}  # id -> compiled closure of an expression or assignment in _seen
        self._local_names: dict[str, bool] = {}  # variable name -> is it local (frontend.variable_scope)
        self.label_cache: dict[tuple[int, str, float], list[int]] = {}
        self.landing_cache: dict[tuple, Position] = {}  # (source, program, label, from offset, direction, branch) -> where a jump lands
        self.visited: list[tuple[ProgramSource, int, int]] = []
        self.paths_started = 0
        self.blocks_run = 0
        self.block_budget = settings.loop_bound * 2000 + source.line_number_at(len(source))
        self.free_parameters: dict[str, Sym] = {}
        self.pins = pins or {}  # free parameters fixed to a witness's values, for its replay
        self.state = MachineState()
        self.parked_at_start = frozenset(parked_at_start)  # the axes [machine] start places
        self.state.path_condition = self._assume(assumptions)
        self.assumed_conditions = len(self.state.path_condition)  # what a path knows before any branch
        if hasattr(observer, "call_site"):
            observer.call_site = self.call_site
        self._handlers = {
            ir.SetModal: self._set_modal, ir.Move: self._move, ir.Dwell: self._nothing,
            ir.CutterComp: self._cutter_comp, ir.CornerRounding: self._corner_rounding, ir.LengthOffset: self._length_offset,
            ir.WorkOffset: self._work_offset, ir.CoordinateShift: self._coordinate_shift, ir.SetFrame: self._set_frame,
            ir.ReferenceReturn: self._reference_return, ir.MachineMove: self._machine_move, ir.Home: self._home,
            ir.SetFeed: self._set_feed, ir.SetSpindleSpeed: self._set_spindle_speed,
            ir.Spindle: self._spindle, ir.Coolant: self._coolant, ir.ToolSelect: self._tool_select,
            ir.ToolChange: self._tool_change, ir.CycleDefine: self._cycle_define,
            ir.CycleCancel: self._cycle_cancel, ir.CycleCall: self._cycle_call, ir.Assign: self._assign,
            ir.Jump: self._jump, ir.LoopStart: self._loop_start, ir.LoopEnd: self._loop_end,
            ir.Conditional: self._conditional, ir.Call: self._call, ir.Return: self._return,
            ir.Stop: self._stop, ir.Alarm: self._alarm, ir.Deferred: self._deferred,
            ir.Unsupported: self._unsupported, ir.ProgramEnd: self._program_file_end,
            ir.ToolLength: self._tool_length, ir.Approach: self._nothing,
        }
        for kind, run in (modal_call.HANDLERS | getattr(runtime, "OPERATIONS", {})).items():
            self._handlers[kind] = partial(run, self.cycles)
        self._gathered: list[tuple] = []  # moves not yet handed on (_gather), each as _GATHERED_FIELDS lays it out
        self._gathered_from = None  # the motion mode before the first of them
        self._gathered_start: dict = {}  # the position before the first of them
        self._gathered_plane = None  # the plane of the arcs among them (None: no arc)
        self._gathered_holes = False  # they are the moves of a hole pattern (a modal hole cycle's)
        self._run_observer = observer  # where the gathered moves go
        self._inert_between_moves = getattr(runtime, "INERT_BETWEEN_MOVES", {})  # dialect operation -> when it leaves the moves gathered
        self._gathers_hole_moves = getattr(observer, "gathers_hole_moves", False)  # see Checker.gathers_hole_moves
        if hasattr(observer, "motion_run") and not settings.per_block_only:
            self.observer = GatheringObserver(observer, self._hand_on_gathered, self._gathered, lambda: self._gathered_holes)
            if hasattr(observer, "hand_on_held_moves"):
                observer.hand_on_held_moves = self._hand_on_gathered
        self._loop_runners = None
        if settings.loop_runner and not settings.per_block_only:
            self._loop_runners = loop_runner.LoopRunners(self, gathering=GatheringObserver, most_gathered=_GATHERED_MOVES, batch_after=_BATCH_AFTER,
                                                         numbers=_numbers, run_kinds=_RUN_KIND, written_bits=_written_bits)

    # ------------------------------------------------------------------ running

    def run(self) -> None:
        main_name, main_start, called = self._main_program()
        state = self.state
        state.modal = dict(self.power_on)
        state.call_stack = [CallFrame("called" if called else "main", main_name, self.source, main_start, None)]
        if called:
            state.spindle = "inherited"
            state.feed_inherited = True
        else:
            state.parked = self.parked_at_start
        worklist = [(state, Position(self.source, main_start))]
        while worklist:
            self.state, position = worklist.pop()
            self.paths_started += 1
            self._forks = worklist
            try:
                self._run_path(position)
            except PathEnd:
                pass
            self._hand_on_gathered()
            path_end = getattr(self.observer, "path_end", None)  # observers that keep per-path models (the cut stock) close them here
            if path_end is not None:
                path_end(self.state)
        self._sweep_unvisited()

    def _run_path(self, position: Position) -> None:
        loops = self._loop_runners
        while True:
            if loops is not None:
                loops.run(position)  # at a loop's head: the straight passes that follow, compiled
            position = self._run_from(position)

    def _run_from(self, position: Position) -> Position:
        """Run blocks from ``position`` until control transfers; return the new position.
        After a streak of plain blocks, the rest of the streak is run as one batch."""
        source = position.source
        first_block, first_op = position.block_index, position.op_index
        cache = self._should_cache()
        frontend_blocks = self.frontend.blocks
        path = self._path_name(source)
        self._line_source = source
        streak_end = position.offset
        plain_streak = 0
        try:
            lines = self._remembered_lines(source, position.offset) if cache else self._read_lines(source, position.offset)
            for line in lines:
                line_number, offset, next_offset, raw, plain, blocks = line
                if plain_streak >= _BATCH_AFTER and plain:
                    plain_streak = 0  # not allowed here (a hole cycle's positions): asked again after as many plain lines, not at the next
                    run = self.frontend.plain_run(source.buffer, offset, line_number) if self._batch_allowed() else None
                    end = None if run is None else self._execute_batch(run, source, path)
                    if end is not None:
                        streak_end = end
                        return Position(source, end) if end < len(source) else self._end_of_text(source)
                if blocks is None:
                    blocks = self._blocks(source, offset, line_number, raw, path, cache, frontend_blocks)
                    if cache:
                        line[5] = blocks
                self._line_offset = offset
                streak_end = next_offset
                plain_streak = plain_streak + 1 if plain and len(blocks) == 1 else 0
                for block_index in range(first_block, len(blocks)):
                    self._block_index = block_index
                    transfer = self._execute_block(blocks[block_index], first_op)
                    first_op = 0
                    if transfer is not None:
                        return transfer
                first_block = 0
            return self._end_of_text(source)
        finally:
            visited = self.visited
            last = visited[-1] if visited else None
            if last is None or last[0] is not source or last[1] != position.offset or last[2] != streak_end:
                visited.append((source, position.offset, streak_end))  # a loop's next pass reaches the same lines: kept once

    # ------------------------------------------------------------------ batches of plain blocks

    def _batch_allowed(self) -> bool:
        state = self.state
        return (not self.settings.per_block_only and state.cycle is None and not state.loops
                and (frames.program_to_workpiece(state) is None or frames.program_to_workpiece(state).is_numeric)
                and state.modal.get("motion") in ir.MoveBatch.KINDS and not isinstance(state.feed, Sym)
                and not any(isinstance(value, Sym) for value in state.position.values())
                and not state.parked and self._dialect_allows_batch(state))

    def _dialect_allows_batch(self, state) -> bool:
        """A dialect whose plain blocks also change state of its own says when a batch may skip that."""
        return self._dialect_batch_allowed is None or self._dialect_batch_allowed(state)

    def _execute_batch(self, run: ir.MoveBatch, source: ProgramSource, path) -> int | None:
        """Run a batch of plain blocks with arrays (the per-block path's twin). From the first
        row the arrays do not take as the block path would (:meth:`_batch_rows`) on, the
        rows are left to the block path: returns where the batch ended, None when it ran none."""
        state = self.state
        axes = run.axes
        start_point = numpy.array([_as_float(state.position.get(axis)) for axis in axes])
        motion_before = float(ir.MoveBatch.KINDS.index(state.modal["motion"]))
        kinds = _forward_fill(run.kinds.astype(numpy.float64), -1, motion_before)
        scale = self.increment / 10.0 if state.modal.get("units") == "inch" else self.increment
        written = ~numpy.isnan(run.values)
        values = numpy.where(run.scaled, run.values * scale, run.values) if run.scaled.any() else run.values
        if state.modal.get("distance") == "incremental":  # added in order, from the start, as block by block
            points = numpy.cumsum(numpy.vstack([start_point, numpy.nan_to_num(values)]), axis=0)[1:]
        else:
            points = numpy.vstack([_forward_fill(values[:, column], None, start_point[column]) for column in range(len(axes))]).T
        arc_written = numpy.zeros(run.rows, dtype=bool) if run.arc_words is None else any_in_row(~numpy.isnan(run.arc_words))
        moving_rows = any_in_row(written) | arc_written
        rows = self._batch_rows(run, kinds, numpy.vstack([start_point, points]), moving_rows, arc_written)
        if rows == 0:
            return None
        if rows < run.rows:
            run, kinds, written, points, moving_rows = run.head(rows), kinds[:rows], written[:rows], points[:rows], moving_rows[:rows]
        modes = kinds if run.keeps_motion is None else _forward_fill(numpy.where(run.keeps_motion, -1.0, kinds), -1, motion_before)
        state.left_start = frozenset()  # a batch never runs from the start position (see _batch_allowed)
        feeds = run.feeds
        if state.modal.get("feed_mode") == "per_revolution" and self.feed_increment:
            feeds = numpy.where(run.feed_scaled, feeds * self.feed_increment, feeds)
        feeds = _forward_fill(feeds, None, _as_float(state.feed))
        moving = numpy.flatnonzero(moving_rows)
        chosen = slice(None) if len(moving) == len(moving_rows) else moving  # every row moves, as a rule: no copies
        self.blocks_run += run.blocks
        segment_points = numpy.vstack([start_point, points[chosen]])
        segment_kinds = kinds[chosen].astype(numpy.int8)
        if len(moving):
            arcs = self._batch_arcs(run, chosen, segment_points, segment_kinds)
            block_of = self._batch_block_reader(run, moving, source, path)
            others = {axis: value for axis, value in state.position.items() if axis not in axes}
            # an arc's segment is asked for by the rules and then by the material: made once
            segment_of = lru_cache(maxsize=1)(partial(_batch_segment, axes, segment_points, segment_kinds, arcs, others, block_of))
            moving_feeds = feeds[chosen]
            motions = None if modes is kinds else [ir.MoveBatch.KINDS[int(mode)] for mode in modes[chosen]]
            self.observer.motion_run(MotionRun(axes, segment_points, segment_kinds, moving_feeds, written[chosen], partial(_batch_span, block_of),
                                               segment_of, arcs, partial(_batch_state_at, state, segment_kinds, moving_feeds, motions=motions)), state)
        state.position = dict(state.position, **{axis: _as_value(value) for axis, value in zip(axes, points[-1])})
        if len(moving):
            state.last_segment = segment_of(len(moving) - 1)
        state.modal["motion"] = ir.MoveBatch.KINDS[int(modes[-1])]
        if not numpy.isnan(feeds[-1]):
            state.feed = float(feeds[-1])
        state.motion_seen = state.motion_seen or bool(len(moving))
        if self._dialect_after_batch is not None:
            self._dialect_after_batch(state, run)
        return run.end_offset

    def _batch_rows(self, run: ir.MoveBatch, kinds, positions, moving, arc_written) -> int:
        """How many rows of the batch the arrays run as the block path would: all up to the
        first with centre words on a straight move, or the first arc they do not model (no
        arc words were read, a plane axis is not the batch's or is read as a diameter, the
        start or end in the plane is unknown, a frame maps program to workpiece coordinates:
        runs are mapped as points, an arc's centre would not be), or the first that ends radius
        compensation while it is on. ``positions[r]``: where row ``r`` starts."""
        arc = moving & (kinds >= _FIRST_ARC_KIND)
        odd = arc_written & (kinds < _FIRST_ARC_KIND)
        if run.compensation_off is not None and compensated(self.state):
            odd |= run.compensation_off
        if arc.any():
            first, second, _normal = self.state.plane_axes
            if (run.arc_words is None or first not in run.axes or second not in run.axes or (self._x_scale() != 1.0 and "X" in (first, second))
                    or frames.program_to_workpiece(self.state) is not None):
                odd |= arc
            else:
                in_plane = positions[:, [run.axes.index(first), run.axes.index(second)]]
                unknown = any_in_row(numpy.isnan(in_plane))
                odd |= arc & (unknown[:-1] | unknown[1:])
        bad = numpy.flatnonzero(odd)
        return int(bad[0]) if bad.size else run.rows

    def _batch_arcs(self, run: ir.MoveBatch, moving, points, kinds) -> BatchArcs | None:
        """The arcs among a batch's moves (``moving``: their rows, or a slice of them; see
        :meth:`_arc`, whose meaning this keeps), None when there are none."""
        if not (kinds >= _FIRST_ARC_KIND).any():
            return None
        plane = self.state.plane_axes
        words = run.arc_words[moving]
        columns = [run.axes.index(plane[0]), run.axes.index(plane[1])]
        offsets = numpy.nan_to_num(words[:, [_CENTRE_WORD[plane[0]], _CENTRE_WORD[plane[1]]]])  # an offset not written is 0
        centres = offsets if run.centres_absolute or self.state.modal.get("arc_distance") == "absolute" else points[:-1][:, columns] + offsets
        radii = words[:, _RADIUS_WORD]
        centres = numpy.where((~numpy.isnan(radii) | (kinds < _FIRST_ARC_KIND))[:, None], numpy.nan, centres)  # four times a masked assignment's speed
        return BatchArcs(plane, columns, centres, radii)

    def _batch_block_reader(self, run: ir.MoveBatch, moving_rows, source: ProgramSource, path):
        """Re-reads the block of the run's ``index``-th move (its row in ``moving_rows``), for
        a report's span or an arc's segment (the last few are kept: an arc's block is asked
        for by its span and its segment, by several rules)."""

        @lru_cache(maxsize=4)
        def block_of(index: int) -> ir.Block:
            row = int(moving_rows[index])
            offset = int(run.line_offsets[row])
            end = source.buffer.find(b"\n", offset)
            raw = bytes(source.buffer[offset : len(source.buffer) if end < 0 else end]).rstrip(b"\r")
            return self.frontend.blocks(raw, run.first_line + row, path)[0]

        return block_of

    def _should_cache(self) -> bool:
        """Keep lowered lines when they are likely to run again: inside a loop, in a called
        program, or once a jump was taken (GOTO and O-word loops are jumps back), so a loop
        body is read and lowered once, not on every pass."""
        return bool(self.state.loops) or len(self.state.call_stack) > 1 or bool(self.state.jump_counts)

    def _read_lines(self, source: ProgramSource, offset: int):
        """The lines of :func:`logical_lines` from ``offset`` as :meth:`_run_from` takes them:
        ``[line number, offset, next offset, text, is it plain, None]`` (blocks not lowered yet)."""
        is_plain = self.frontend.is_plain
        for line_number, start, next_offset, raw in logical_lines(source, offset, self.frontend):
            yield [line_number, start, next_offset, raw, is_plain(raw), None]

    def _remembered_lines(self, source: ProgramSource, offset: int):
        """:meth:`_read_lines` from ``offset``, each line read from the text once and then
        remembered with its blocks once lowered, so that a loop's next pass neither reads nor
        lowers its body again."""
        remembered, text_id = self.line_text, id(source)
        reader, reader_at = None, -1
        while True:
            line = remembered.get((text_id, offset))
            if line is None:
                if reader_at != offset:
                    reader = self._read_lines(source, offset)
                line = next(reader, None)
                if line is None:
                    return
                reader_at = line[2]
                if len(remembered) > _REMEMBERED_LINES:
                    remembered.clear()
                remembered[(text_id, offset)] = line
            yield line
            offset = line[2]

    def _blocks(self, source, offset, line_number, raw, path, cache, frontend_blocks):
        if cache or self.state.loops:
            key = (id(source), offset)
            blocks = self.line_cache.get(key)
            if blocks is None:
                blocks = frontend_blocks(raw, line_number, path)
                if len(self.line_cache) > _REMEMBERED_LINES:
                    self.line_cache.clear()
                self.line_cache[key] = blocks
            return blocks
        return frontend_blocks(raw, line_number, path)

    def _execute_block(self, block: ir.Block, first_op: int):
        """Run one block's operations; returns a Position when control transfers."""
        state = self.state
        if block.program_start and first_op == 0:
            frame = state.call_stack[-1]
            if frame.start != self._line_offset and not (frame.start == 0 and self._is_first_program(self._line_source, self._line_offset)):
                return self._program_ran_into_next(block, frame)
        if block.notes:
            for note in block.notes:
                self.observer.note(note)
                if note.rule == "core.syntax":  # what the line does is not known: it may have written an offset, a frame...
                    self.unfollowed(f"line {note.span.line} was not read ({note.message})", before_moves=True)
        if block.tape_mark and self._closes_tape(self._line_source, self._line_offset):
            self._end_of_text(self._line_source)
        self.blocks_run += 1
        if self.blocks_run > self.block_budget:
            self._fault("core.loop-bound", block.span, f"analysis stopped after {self.blocks_run:,} blocks", "unknown",
                        "the program runs longer than the analysis budget (its length plus loop bound x 2000 blocks)")
            raise PathEnd
        self._block = block
        ops = block.ops
        handlers = self._handlers
        gathered = self._gathered
        for op_index in range(first_op, len(ops)):
            self._op_index = op_index
            op = ops[op_index]
            kind = type(op)
            if gathered and kind not in _ALWAYS_BETWEEN_GATHERED and not self._keeps_moves_gathered(op, kind):
                self._hand_on_gathered()
            transfer = handlers[kind](op, block)
            if transfer is not None:
                return transfer
        return None

    # ------------------------------------------------------------------ reporting helpers

    def _fault(self, rule: str, span: Span, message: str, status: str = "violated", reason: str | None = None,
               severity: str | None = None) -> None:
        self.observer.fault(Fault(rule, span, message, status, reason, severity))

    def _change(self, what: str, span: Span, block, old=None, new=None, register=None, words=None) -> None:
        self.observer.change(Change(what, span, block, old, new, register, words), self.state)

    # ------------------------------------------------------------------ expressions

    def evaluate(self, expr, span: Span | None = None):
        """Value of an IR expression; VACANT passes through (callers decide what it means).

        An expression evaluated a second time (a loop body's, a called program's: their
        lowered lines are kept) is compiled into a closure (:mod:`.compiled`) that gives the
        same values and faults without walking the tree again."""
        if type(expr) is float and expr - expr == 0.0:
            return expr  # a number as written (inf and nan are faults of evaluate_tree)
        run = self._closures.get(id(expr))
        if run is not None:
            return run(span)
        if type(expr) in compiled.COMPILED_KINDS:
            run = self._compile_on_second_run(expr, compiled.compile_expression)
            if run is not None:
                return run(span)
        return self.evaluate_tree(expr, span)

    def _compile_on_second_run(self, node, compile):
        """``compile(self, node)``, kept in ``_closures`` by the node's id, once ``node`` runs a
        second time (its lowered line was kept for a loop's next pass or another call); None
        the first time."""
        key = id(node)
        if key in self._seen:  # _seen holds the node, so no other object has its id
            run = self._closures[key] = compile(self, node)
            return run
        if len(self._seen) >= _COMPILED_LIMIT:
            self._seen.clear()
            self._closures.clear()
        self._seen[key] = node
        return None

    def evaluate_tree(self, expr, span: Span | None = None):
        """:meth:`evaluate` by walking the tree: the general evaluation every value, vacant,
        text and symbolic, goes through, and the one compiled closures fall back to."""
        kind = type(expr)
        if kind is ir.IncrementCount:  # an integer counted in least increments: its value in mm or inch
            expr, kind = self._scale_increment(expr), float
        if kind is float:
            if expr - expr != 0.0:  # inf or nan: a number no control holds
                self._domain_error("a number beyond the control's range", span)
            return expr
        if kind is int:
            return float(expr)
        if kind is str:
            return expr
        if kind is ir.Var:
            return self.read_variable(expr, span)
        if kind is ir.Unary:
            return self.negated(self.evaluate_tree(expr.operand, span), expr, span)
        if kind is ir.Binary:
            return self.combined(expr, self.evaluate_tree(expr.left, span), self.evaluate_tree(expr.right, span), span)
        if kind is ir.Func:
            return self.function_value(expr, [self._arithmetic_operand(self.evaluate_tree(arg, span), arg, span) for arg in expr.args], span)
        if kind is ir.MachineValue:
            return expr.read(self.state)
        if kind is Sym or expr is VACANT:
            return expr  # a value already evaluated (a modal call's stored argument)
        raise TypeError(f"not an expression: {expr!r}")

    def negated(self, operand, expr: ir.Unary, span):
        """The value of ``expr`` (a sign) once its operand's value is known."""
        return values.neg(self._arithmetic_operand(operand, expr.operand, span))

    def function_value(self, expr: ir.Func, arguments: list, span):
        """The value of ``expr`` once its arguments are known as operands
        (:meth:`_arithmetic_operand` of each, taken as each is evaluated)."""
        try:
            return values.call(expr.name, arguments)
        except DomainError as error:
            self._domain_error(str(error), span)

    def combined(self, expr: ir.Binary, left, right, span):
        """The value of ``expr`` once its operands' values are known; a number past the
        float range is a domain fault."""
        result = self._binary(expr.op, left, right, expr, span)
        if type(result) is float and result - result != 0.0:
            self._domain_error("the result overflows the control's number range", span)
        return result

    def _scale_increment(self, expr: ir.IncrementCount) -> float:
        if expr.kind == "feed":
            per_rev = self.state.modal.get("feed_mode") == "per_revolution"
            return expr.count * self.feed_increment if per_rev and self.feed_increment else expr.count
        scale = self.increment / 10.0 if self.state.modal.get("units") == "inch" else self.increment
        return expr.count * scale

    def _binary(self, op: str, left, right, expr: ir.Binary, span):
        if type(left) is float and type(right) is float:  # plain numbers (loop counters): no operand to convert
            return self._arithmetic(op, left, right, expr, span)
        if op in values.COMPARISONS:
            if left is VACANT or right is VACANT:
                return self._compare_vacant(op, left, right)
            if isinstance(left, str) or isinstance(right, str):
                return self._compare_text(op, left, right)
            return values.compare(op, self._as_number(left), self._as_number(right))
        if op in ("AND", "OR", "XOR"):
            return values.logical(op, _logical_operand(left), _logical_operand(right))
        left = self._arithmetic_operand(left, expr.left, span)
        right = self._arithmetic_operand(right, expr.right, span)
        return self._arithmetic(op, left, right, expr, span)

    def _arithmetic(self, op: str, left, right, expr: ir.Binary, span):
        """``left op right`` for operands that are numbers or symbolic values."""
        if op in values.COMPARISONS:
            return values.compare(op, left, right)
        if op in ("AND", "OR", "XOR"):
            return values.logical(op, left, right)
        try:
            if op == "+":
                return values.add(left, right)
            if op == "-":
                return values.sub(left, right)
            if op == "*":
                return values.mul(left, right)
            if op == "/":
                if isinstance(right, Sym):
                    self._symbolic_divisor(right, expr.right, span)
                return values.div(left, right)
            if op == "MOD":
                return values.modulo(left, right)
            if op == "**":
                return values.power(left, right)
        except DomainError as error:
            self._domain_error(str(error), span)
        raise ValueError(f"unknown operator {op}")

    @staticmethod
    def _compare_vacant(op: str, left, right) -> bool:
        """Fanuc: vacant equals only vacant in EQ/NE; elsewhere it counts as 0."""
        if op in ("EQ", "NE"):
            same = (left is VACANT) == (right is VACANT) and (left is VACANT or left == right)
            return same if op == "EQ" else not same
        left = 0.0 if left is VACANT else left
        right = 0.0 if right is VACANT else right
        if isinstance(left, str) or isinstance(right, str):
            return Interpreter._compare_text(op, left, right)
        return values.compare(op, left, right)

    @staticmethod
    def _compare_text(op: str, left, right) -> "bool | Condition":
        """Strings compare with strings (``IF $MN_.. <> "X"`` once both are known); a string
        against a number or an unknown value is not followed: either outcome."""
        if isinstance(left, str) and isinstance(right, str):
            return {"EQ": left == right, "NE": left != right, "LT": left < right, "LE": left <= right,
                    "GT": left > right, "GE": left >= right}[op]
        return values.truth(values.fresh("text", 0.0, 1.0))

    @staticmethod
    def _as_number(value):
        """A comparison's outcome used as a number: 1 or 0 (between 0 and 1 when symbolic)."""
        if isinstance(value, (bool, Condition)):
            return 1.0 if value is True else 0.0 if value is False else values.fresh("condition", 0.0, 1.0)
        return value

    def value(self, expr, span=None):
        """An expression's value where a number is needed (a word, a parameter of a
        cycle): comparisons count 1 or 0; VACANT passes through."""
        result = self.evaluate(expr, span)
        return result if type(result) is float else self._as_number(result)

    def _arithmetic_operand(self, value, expr, span):
        if value is VACANT:
            name = expr.name if isinstance(expr, ir.Var) else "a variable"
            where = expr.span if isinstance(expr, ir.Var) and expr.span else span or self._block.span
            self._fault("core.undefined-variable", where, f"{name} is vacant (never set, not passed as an argument); the control computes with 0")
            return 0.0
        if isinstance(value, str):
            return values.fresh("text")  # a string in arithmetic: a value the checker does not follow
        return self._as_number(value)

    def _symbolic_divisor(self, divisor: Sym, written: ir.Expr, span) -> None:
        """A divisor that depends on free parameters: can it be zero on this path? The
        message names the parameter the program divides by, if it divides by one."""
        verdict = judge(hazard("==", divisor, 0.0), self.state.path_condition, self.settings.solver_timeout_s)
        if verdict is None:
            return
        value = show(divisor)
        named = written.name if isinstance(written, ir.Var) and isinstance(written.name, str) else None
        what = f"{named} = {value}" if named is not None and named != value else value
        self.observer.report_verdict("core.arithmetic-domain", span or self._block.span,
                                     f"division by {what}, which can be zero: the control stops with a calculation alarm", verdict, self.state)

    def _domain_error(self, message: str, span) -> None:
        self._fault("core.arithmetic-domain", span or self._block.span, f"{message}: the control stops with a calculation alarm")
        raise PathEnd

    def variable_name(self, var: ir.Var, span=None) -> str:
        if isinstance(var.name, str):
            return var.name
        index = self.evaluate(var.name, span)
        if type(index) is not float:
            self._unsupported_here(var.span or span, "a variable whose number depends on a free parameter")
            raise PathEnd
        return f"{var.prefix}{int(round(index))}"

    def is_local(self, name: str) -> bool:
        """Is variable ``name`` local to a program? (The frontend's scope depends on the name alone.)"""
        local = self._local_names.get(name)
        if local is None:
            local = self._local_names[name] = self.frontend.variable_scope(name) == "local"
        return local

    def read_variable(self, var: ir.Var, span=None):
        name = self.variable_name(var, span)
        state = self.state
        if self.is_local(name):
            if name in state.local_variables:
                return state.local_variables[name]
            if self._in_macro() or getattr(self.frontend, "unset_is_vacant", _never)(name):
                return VACANT
            return self._free_parameter(name)
        if name in state.global_variables:
            return state.global_variables[name]
        if self._system_variable is not None:
            system = self._system_variable(name, state)
            if system is not None:
                return system
        return self._free_parameter(name)

    def _assume(self, assumptions) -> list:
        """Free parameters named in assumptions get their bounds; the assumptions start
        every path's condition."""
        conditions = []
        for assumption in assumptions:
            unbounded = {node: values.parameter(parameter_name(node)) for node in assumption_names(assumption.tree)}
            condition = evaluate_constraint(assumption.tree, unbounded)  # for the solver: no interval may decide it
            if condition is not True:
                conditions.append(condition)
            for node, (low, high) in assumption_bounds(assumption.tree).items():
                name = parameter_name(node)
                known = self.free_parameters.get(name, values.parameter(name))
                self.free_parameters[name] = values.Sym(known.term, max(low, known.low), min(high, known.high))
        return conditions

    def _in_macro(self) -> bool:
        return any(frame.kind == "macro" for frame in self.state.call_stack)

    def _free_parameter(self, name: str) -> Sym:
        if name in self.pins:
            return float(self.pins[name])
        parameter = self.free_parameters.get(name)
        if parameter is None:
            parameter = values.parameter(name)
            self.free_parameters[name] = parameter
        return parameter

    def write_variable(self, var: ir.Var, value, span=None, assignment: bool = False) -> None:
        name = self.variable_name(var, span)
        value = values.stored(value)
        data = self._machine_data_of(name)
        if data is not None:
            what, before_moves = data
            self.unfollowed(f"{name} written: the program changed {what}", before_moves)
        if assignment and self.settings.record_values and span is not None and span.path is None:
            self.assigned.setdefault(span.line, []).append((name, value))
        if self.is_local(name):
            self.state.local_variables[name] = value
        else:
            self.state.global_variables[name] = value

    def is_machine_data(self, name) -> bool:
        """Does writing variable ``name`` change machine data (a work offset, a frame, tool
        data) that the model does not follow? (The dialect's ``machine_data``.)"""
        return isinstance(name, str) and self._machine_data_of(name) is not None

    def _machine_data_of(self, name: str) -> tuple[str, bool] | None:
        """The dialect's ``machine_data`` of ``name``, asked once per name (every assignment
        asks)."""
        if self._machine_data is None:
            return None
        if name not in self._machine_names:
            self._machine_names[name] = self._machine_data(name)
        return self._machine_names[name]

    def unfollowed(self, why: str, before_moves: bool = False) -> None:
        """The program changed state the model does not follow (``why``): from its first move
        on (``before_moves``: even before it), where the tool's tip stands on the blank is not
        known for the rest of the path. Before the first move a work offset or the units are
        set up as the stock is described, so they do not count then; they are kept apart
        (``set_up_written``) for the travel check, whose offsets come from the project file."""
        state = self.state
        if before_moves or state.motion_seen:
            if state.unfollowed is None:
                state.unfollowed = why
        elif state.set_up_written is None:
            state.set_up_written = why

    def condition(self, expr, span) -> "bool | Condition":
        value = self.evaluate(expr, span)
        if value is VACANT:
            return False
        return values.truth(value)

    # ------------------------------------------------------------------ op handlers: state

    def _nothing(self, op, block):
        return None

    def _tool_length(self, op: ir.ToolLength, block):
        """The control applies the tool's length by itself: no register, no change to report."""
        state = self.state
        tool = self.cycles.words({"T": op.tool} if op.tool is not None else {}, op.span)
        state.length_mode = "plus" if op.on else "off"
        state.length_register = tool.get("T")
        return None

    def _set_modal(self, op: ir.SetModal, block):
        state = self.state
        old = state.modal.get(op.group)
        state.modal[op.group] = op.value
        if op.group == "units" and old != op.value:
            self._change("units", op.span, block, old, op.value)
            if old is not None:
                self.unfollowed(f"the units were switched from {old} to {op.value}: the stock, the tools and the machine's data stay as described")
        elif op.group in _WATCHED_MODAL:
            self._change(op.group, op.span, block, old, op.value)
        return None

    def _cutter_comp(self, op: ir.CutterComp, block):
        if op.only_if_changed and op.side == self.state.comp_side:
            return None
        old, register = self._switch_offset(op.side, op.register, op.span, "comp_side", "comp_register")
        self._change("cutter_comp", op.span, block, old, self.state.comp_side, register)
        return None

    def _corner_rounding(self, op: ir.CornerRounding, block):
        """The corner at the tool's position is cut off (its moves leave their programmed
        paths near it), or every corner from here on (SINUMERIK RNDM). Not in a canned
        cycle, whose block's ISO ``,R`` is the tapping mode."""
        if op.modal is not None:
            self.state.corners_rounded = op.modal
        elif self.state.cycle is None:
            self._change("corner_rounding", op.span, block)
        return None

    def _length_offset(self, op: ir.LengthOffset, block):
        old, register = self._switch_offset(op.mode, op.register, op.span, "length_mode", "length_register")
        state = self.state
        if op.mode == "plus" and op.register is None and self._g43_takes_the_loaded_tool:
            state.length_register = state.tool_in_spindle  # LinuxCNC: G43 alone takes the loaded tool's offset, and keeps it past M6
        if register == 0.0:
            state.length_mode = "off"  # H0 cancels like G49 (seed L1830)
        if op.mode == "off":
            state.length_register = None
        self._change("length_offset", op.span, block, old, state.length_mode, register)
        return None

    def _switch_offset(self, mode: str, register_expr, span, mode_field: str, register_field: str):
        """G40-G42 and G43/G44/G49: a new mode ("keep" leaves it) and a new register."""
        state = self.state
        old = getattr(state, mode_field)
        register = self._register(register_expr, span)
        if mode != "keep":
            setattr(state, mode_field, mode)
        if register is not None:
            setattr(state, register_field, register)
        return old, register

    def _register(self, expr, span):
        if expr is None:
            return None
        value = self.value(expr, span)
        return None if value is VACANT else value

    def _work_offset(self, op: ir.WorkOffset, block):
        """Another work offset leaves the tool where it is on the machine; where that is in
        the new offset's coordinates depends on the offsets' values, which the program does
        not hold, so the position is unknown until the program sets it again. (Before any
        selection the power-on offset, G54 in the ISO family, is in force.)"""
        state = self.state
        previous = state.modal.get("work_offset")
        if previous != op.name and (previous is not None or op.name != "G54"):
            state.move_to(dict.fromkeys(state.position))
        state.modal["work_offset"] = op.name
        return None

    def _set_feed(self, op: ir.SetFeed, block):
        value = self.value(op.value, op.span)
        if value is not VACANT:
            self.state.feed = value
        return None

    def _set_spindle_speed(self, op: ir.SetSpindleSpeed, block):
        value = self.value(op.value, op.span)
        if value is VACANT:
            return None
        if op.clamp:
            self.state.spindle_clamp = value
        else:
            self.state.spindle_speed = value
        return None

    def _spindle(self, op: ir.Spindle, block):
        state = self.state
        old = state.spindle
        if op.state != "orient":
            state.spindle = op.state
        if op.apart:
            block = ir.Block(block.line, block.start_column, block.end_column, [])
        self._change("spindle", op.span, block, old, op.state)
        return None

    def _coolant(self, op: ir.Coolant, block):
        self.state.coolant = op.state
        return None

    def _tool_select(self, op: ir.ToolSelect, block):
        state = self.state
        number = self.evaluate(op.number, op.span)
        state.tool_selected = number
        self._change("tool_select", op.span, block, None, number)
        if op.offset is not None:
            offset = self.evaluate(op.offset, op.span)
            state.tool_in_spindle = number
            state.tool_offset = offset
            state.tool_changed = True
            self._change("tool_change", op.span, block, None, number, offset)
        return None

    def _tool_change(self, op: ir.ToolChange, block):
        state = self.state
        old = state.tool_in_spindle
        state.tool_in_spindle = state.tool_selected
        state.tool_changed = True
        self._change("tool_change", op.span, block, old, state.tool_in_spindle)
        return None

    def _unsupported(self, op: ir.Unsupported, block):
        if "position" in op.affects:
            self.state.move_to(dict.fromkeys(self.state.position))
        if "state" in op.affects:  # it may have written an offset, a frame, tool data
            self.unfollowed(f"{op.what}: what it changes is not known", before_moves=True)
        return None

    def _unsupported_here(self, span, what: str) -> None:
        self._fault("core.unsupported-code", span, f"{what} is not modelled; the rest of this path is not analysed", "unknown", what)

    # ------------------------------------------------------------------ coordinates

    def _target(self, axis: str, value, incremental: bool):
        """Absolute end coordinate of ``axis`` for a written value."""
        if incremental or self.state.modal.get("distance") == "incremental":
            current = self.state.position.get(axis)
            return None if current is None else values.add(current, value)
        return value

    def _targets(self, written: dict, incremental_axes, span) -> dict:
        targets = {}
        for axis, expr in written.items():
            value = self.value(expr, span)
            if value is VACANT:
                continue  # a vacant variable makes the address absent (Fanuc)
            targets[axis] = self._target(axis, value, axis in incremental_axes)
        return targets

    def _coordinate_shift(self, op: ir.CoordinateShift, block):
        if op.kind == "set_position":
            new = op_values(op.values, self, op.span)
            shift = self.state.coordinate_shift
            for axis, value in new.items():
                old, known = self.state.position.get(axis), shift.get(axis, 0.0)
                shift[axis] = None if old is None or known is None else values.add(known, values.sub(old, value))
            self.state.move_to(new)
            speed = op.words.get("S")
            if speed is not None:
                self.state.spindle_clamp = self.evaluate(speed, op.span)
            if new:
                self._change("set_position", op.span, block, None, new)
        elif op.kind == "data":
            words = op_values(op.words, self, op.span)
            self._change("data_setting", op.span, block, op_values(op.values, self, op.span), words)
            self._data_written(words)
        elif op.kind == "shared_offset":  # LinuxCNC G52: sets, not adds to, the offset G92 shares
            shifted = {}
            for axis, value in op_values(op.values, self, op.span).items():
                current, known = self.state.position.get(axis), self.state.coordinate_shift.get(axis, 0.0)
                shifted[axis] = None if current is None or known is None else values.sub(values.add(current, known), value)
                self.state.coordinate_shift[axis] = value
            self.state.move_to(shifted)
        elif op.kind == "local":
            shifted = {}
            for axis, local in op_values(op.values, self, op.span).items():
                before = self._set_local_origin(axis, local)  # G52 replaces the local origin; it does not add to it
                change = None if local is None or before is None else values.sub(local, before)
                current = self.state.position.get(axis)
                shifted[axis] = None if current is None or change is None else values.sub(current, change)
            self.state.move_to(shifted)
        self._watch_workpiece()
        return None

    def _data_written(self, words: dict) -> None:
        """G10: L2 and L20 write a work offset (after the first move it moves the part in
        program coordinates); every other L writes tool or machine data the model does not
        read, whenever it comes."""
        kind = words.get("L")
        written = f"G10 L{show(kind)}" if kind is not None else "G10"
        if type(kind) is float and kind in (2.0, 20.0):
            self.unfollowed(f"{written} wrote a work offset")
        else:
            self.unfollowed(f"{written} wrote tool or machine data", before_moves=True)

    def _set_local_origin(self, axis: str, local):
        """Make ``local`` the G52 local origin of ``axis`` (part of the coordinate shift,
        beside G92's part); returns the local origin it replaces."""
        memory, shift = self.state.rule_state, self.state.coordinate_shift
        before = memory.get(("local-origin", axis), 0.0)
        memory[("local-origin", axis)] = local
        known = shift.get(axis, 0.0)
        shift[axis] = None if known is None or local is None else values.add(values.sub(known, before), local)
        return before

    def _watch_workpiece(self) -> None:
        """From the first frame or coordinate shift on, the observer gets the trace in
        workpiece coordinates (:func:`frames.program_to_workpiece`)."""
        if not isinstance(self.observer, frames.WorkpieceObserver):
            self.observer = frames.WorkpieceObserver(self.observer, self)

    def set_frame(self, frame: frames.Frame) -> None:
        """Make ``frame`` the map from program to workpiece coordinates. The tool does not
        move: its position is re-expressed in the new program coordinates (unknown where
        the new frame cannot be inverted). From the first frame on, the observer gets the
        trace in workpiece coordinates."""
        state = self.state
        new = None if frame.is_identity else frame
        workpiece = state.frame.to_workpiece(state.position) if state.frame is not None else state.position
        back = frames.IDENTITY if new is None else new.inverse()
        if back is None:
            state.move_to({axis: None for axis in frames.AXES if axis in state.position})
        else:
            state.position = back.to_workpiece(workpiece)
        state.frame = new
        if new is not None:
            self._watch_workpiece()

    def _set_frame(self, op: ir.SetFrame, block):
        """A programmable frame statement (:func:`frames.after_statement`), or a tilted
        plane (CYCLE800), which is kept apart and leaves positions unknown until reset."""
        state = self.state
        statements = state.frame_statements
        if op.group is not None:
            return self._set_group_frame(op)
        swivel = statements.swivel
        if op.component in ("swivel", "swivel_off"):  # a tilted plane (CYCLE800): a frame of its own, kept apart from the programmable one
            swivel = op.component == "swivel"
            frame, layers = statements.programmable, statements.layers
        else:
            frame, layers = frames.after_statement(op, op_values(op.values, self, op.span), statements.programmable,
                                                   statements.layers, state.plane_axes)
        if frame is None or swivel:
            why = frames.UNMODELLED.get(op.component, "")
            self._fault("core.unsupported-code", op.span, f"{op.what or 'this coordinate transformation'} is not modelled{why}: positions after it are unknown "
                        "until it is reset", "unknown", op.what or "a coordinate transformation")
        state.frame_statements = FrameStatements(frame or frames.UNKNOWN, layers, swivel, statements.unmodelled)
        self.set_frame(frames.UNKNOWN if swivel or frame is None or statements.unmodelled else frame)
        return None

    def _set_group_frame(self, op: ir.SetFrame):
        """An ISO-style transformation (G68, G51, Fagor G72), which is not modelled: positions
        are unknown while one of any group is on; a cancel (G69, G50, G72 S1) ends only the
        transformation of its own group (G50 leaves a G68 rotation on)."""
        statements = self.state.frame_statements
        if op.component == "reset":
            unmodelled = statements.unmodelled - {op.group}
        else:
            unmodelled = statements.unmodelled | {op.group}
            why = frames.UNMODELLED.get(op.component, "")
            self._fault("core.unsupported-code", op.span, f"{op.what or 'this coordinate transformation'} is not modelled{why}: positions after it are unknown "
                        "until it is reset", "unknown", op.what or "a coordinate transformation")
        self.state.frame_statements = replace(statements, unmodelled=unmodelled)
        self.set_frame(frames.UNKNOWN if unmodelled or statements.swivel or statements.programmable is frames.UNKNOWN else statements.programmable)
        return None

    def _reference_return(self, op: ir.ReferenceReturn, block):
        state = self.state
        if op.which == "check":
            return None
        if op.which == "from_reference":
            start = state.position
            state.move_to(state.last_reference_via)
            self._emit("rapid", start, op.span, block, "reference")
            start = state.position
            state.move_to(self._targets(op.via, op.incremental, op.span))
            self._emit("rapid", start, op.span, block, "reference")
            return None
        targets = self._targets(op.via, op.incremental, op.span)
        start = state.position
        state.move_to(targets)
        state.last_reference_via = dict(targets)
        self._emit("rapid", start, op.span, block, "reference")
        written_absolute = {axis: expr for axis, expr in op.via.items() if axis not in op.incremental}
        self._change("reference_return", op.span, block, op_values(written_absolute, self, op.span), op.which, None,
                     op_values({"P": op.words["P"]}, self, op.span) if "P" in op.words else {})
        if op.which in ("home", "secondary"):
            state.park(targets)  # at the machine reference point: unknown in work coordinates
        else:  # "stored" (LinuxCNC): to the position its parameters hold (G28.1), every axis when none is named
            start = state.position
            state.move_to(dict.fromkeys(targets or [axis for axis in state.position if axis in _STORED_AXES] or "XYZ"))
            self._emit("rapid", start, op.span, block, "reference")
        for axis in targets:  # a reference return cancels the axis's G52 local origin
            if ("local-origin", axis) in state.rule_state:
                self._set_local_origin(axis, 0.0)
        return None

    def _machine_move(self, op: ir.MachineMove, block):
        """A move in machine coordinates: unknown in program coordinates; to machine zero
        where the dialect's machine zero is the reference point (G53 Z0 on the ISO family,
        ``SUPA Z0`` on SINUMERIK), the axis is parked there."""
        home = [axis for axis, expr in op.targets.items() if op.zero_is_reference and _is_zero(self.value(expr, op.span))]
        self.state.move_to(dict.fromkeys(op.targets))
        self.state.park(home)
        return None

    def _home(self, op: ir.Home, block):
        self.state.park(op.axes or tuple(self.state.position) or ("X", "Y", "Z"))
        return None

    # ------------------------------------------------------------------ motion

    def _move(self, op: ir.Move, block):
        state = self.state
        kind = op.kind
        motion_before = state.modal.get("motion")
        modal_cycle = state.cycle is not None and state.cycle.model.called_after_motion  # SINUMERIK MCALL
        if kind is not None:
            if state.cycle is not None and state.cycle.model.motion_codes_keep_cycle:
                state.modal["motion"] = kind  # Fagor: G0/G1 position in the cycle's zone
                return self.cycles.modal_hole(op, block)
            if state.cycle is not None and kind != "thread" and not modal_cycle:
                self._cancel_cycle()
            state.modal["motion"] = kind
        elif state.cycle is not None and not modal_cycle:
            return self.cycles.modal_hole(op, block)
        else:
            kind = state.modal["motion"]
        if "NR" in op.words and state.cycle is None:  # Fagor: a computed or zero block repeat count
            self._unsupported_here(op.span, "a block repeat count NR that is computed or zero")
        if not op.targets and not op.arc:
            return None
        start = state.position
        end = dict(start)
        incremental = state.modal["distance"] == "incremental"
        all_written = True
        for axis, expr in op.targets.items():
            value = expr if type(expr) is float and expr - expr == 0.0 else self.value(expr, op.span)  # inf, nan: evaluate's fault
            if value is VACANT:
                all_written = False
                continue  # a vacant variable makes the address absent (Fanuc)
            if (incremental and axis not in op.absolute) or axis in op.incremental:
                current = start.get(axis)
                value = None if current is None else values.add(current, value)
            end[axis] = value
        state.position = end
        state.leave_start(op.targets)
        state.motion_seen = True
        if ROTARY_AXES.intersection(op.targets):
            self._turned(end, op.targets)
        if kind == "thread" and op.words:
            self._change("thread", op.span, block, None, op_values(op.words, self, op.span))  # G33 Q start angle, E lead
        arc = self._arc(op, kind, start) if kind in _ARC_KINDS else None
        segment = state.last_segment = Segment(_SEGMENT_KIND[kind], start, end, op.span, block, "programmed", None, arc)
        if not (all_written and not modal_cycle and self._gather(segment, op, motion_before)):
            self.observer.segment(segment, state)
        if modal_cycle:
            return self.cycles.modal_call(op, block)  # the MCALL cycle runs after every positioning
        return None

    def _turned(self, end: dict, written) -> None:
        """A rotary axis a move wrote stands off 0 (a whole turn) on a mill: the part on a
        rotary table, or the head, is no longer set as the stock is described."""
        if self.machine == "lathe":
            return
        for axis in ROTARY_AXES.intersection(written):
            value = end.get(axis)
            if not (type(value) is float and value % 360.0 == 0.0):
                self.unfollowed(f"the rotary axis {axis} turned to {show(value)}: the part or the head is no longer set as the stock is described",
                                before_moves=True)

    def _gather(self, segment: Segment, op: ir.Move, motion_before) -> bool:
        """Keep a programmed move the block path makes, to hand it on with the moves next to
        it as one run (:meth:`_gather_segment`): False when the run cannot carry it exactly
        (then it goes on alone), as for a straight move with centre words, which a batch
        leaves to the block path."""
        if segment.arc is None and op.arc:
            return False
        return self._gather_segment(segment, op.targets, motion_before)

    def _gather_segment(self, segment: Segment, written, motion_before, hole: bool = False) -> bool:
        """Keep a programmed move (``written``: the axes its block wrote), to hand it on with
        the moves next to it as one run (:meth:`_hand_on_gathered`), as a batch is: False when
        the run cannot carry it exactly (then it goes on alone). A run carries moves of
        concrete values along X, Y and Z (the other axes stand still, as in a batch), not from
        the start position, with no cycle, frame or coordinate shift in force, each straight
        or an arc whose centre or radius is known (X not a diameter), its arcs all in one
        plane; its rapids, feeds and arcs are judged as a batch's. Every other event, and
        every operation but moves, assignments, jumps and loop bookkeeping, hands the run on
        first (:class:`GatheringObserver`, :meth:`_execute_block`); so do a fork and the
        path's end.

        ``hole``: the move is one of a modal hole cycle's (``written``: the axes it takes).
        Those make runs of their own where the observer's rules judge such runs, and holes
        ahead of their moves, as they judge each move (:attr:`Checker.gathers_hole_moves`): a
        hole event leaves them gathered, the cycle's end hands them on (:meth:`_cancel_cycle`).
        Programmed moves are gathered only with no cycle in force, hole moves only with one,
        so the two never share a run."""
        state = self.state
        if type(self.observer) is not GatheringObserver or state.frame is not None or state.parked or state.left_start:
            return False
        if hole:
            if state.cycle is None or state.cycle.model.shape or not self._gathers_hole_moves:
                return False  # a one-shot cycle's, a lathe box cycle's or a modal call's moves go alone
        elif state.cycle is not None:
            return False
        feed = state.feed
        if not (feed is None or type(feed) is float) or segment.kind not in _RUN_KIND or segment.span.path is not None:
            return False  # a move of a called file goes alone, as before: the toolpath picture leaves those segments out
        start, end, arc = segment.start, segment.end, segment.arc
        gathered = self._gathered
        if not _RUN_AXES.issuperset(written) or not _numbers(end) or not (gathered and start is _made_end(gathered[-1]) or _numbers(start)):
            return False
        if arc is not None:
            if not ((self._x_scale() == 1.0 or "X" not in arc.plane[:2])
                    and (type(arc.radius_word) is float if arc.centre is None else all(type(value) is float for value in arc.centre))):
                return False
            if self._gathered_plane is not None and arc.plane != self._gathered_plane:
                return False  # a run's arcs share one plane (Klartext CC names the plane of the arcs about it)
            self._gathered_plane = arc.plane
        if not gathered:
            self._gathered_from, self._gathered_start, self._gathered_holes = motion_before, start, hole
        kind = _RUN_KIND[segment.kind] + (arc is not None and arc.direction == "ccw")
        gathered.append((end.get("X"), end.get("Y"), end.get("Z"), math.nan if feed is None else feed, kind, _written_bits(tuple(written)),
                         state.modal.get("motion"), segment, None))
        if len(gathered) >= _GATHERED_MOVES:
            self._hand_on_gathered()
        return True

    def _gather_hole_moves(self, steps: list, span, block, cycle: str) -> bool:
        """Make and gather the moves of :meth:`Runtime.move_through` as :meth:`Runtime.move_to`
        and :meth:`_gather_segment` make and gather them one by one, their conditions asked
        once: False, having done nothing, when some move would go on alone."""
        state = self.state
        feed = state.feed
        if (type(self.observer) is not GatheringObserver or state.frame is not None or state.parked or state.left_start or state.cycle is None
                or state.cycle.model.shape or not self._gathers_hole_moves or span.path is not None or not (feed is None or type(feed) is float)
                or not _numbers(state.position)):
            return False
        for targets, _role, _kind in steps:
            if not _RUN_AXES.issuperset(targets) or not _numbers(targets):
                return False
        motion, gathered = state.modal.get("motion"), self._gathered
        feed = math.nan if feed is None else feed
        for targets, role, kind in steps:
            start = state.position
            end, moved = moved_to(start, targets)
            if end is None:
                continue
            state.position = end
            segment = state.last_segment = Segment(kind, start, end, span, block, role, cycle)
            if not gathered:
                self._gathered_from, self._gathered_start, self._gathered_holes = motion, start, True
            gathered.append((end.get("X"), end.get("Y"), end.get("Z"), feed, _RUN_KIND[kind], _written_bits(tuple(moved)), motion, segment, None))
            if len(gathered) >= _GATHERED_MOVES:
                self._hand_on_gathered()
        return True

    def _keeps_moves_gathered(self, op, kind) -> bool:
        """May ``op`` run while moves are gathered? Moves decide for themselves (:meth:`_gather`);
        assignments, jumps and loop bookkeeping change no state a rule reads, except an
        assignment to the active cutting edge or to machine data (:meth:`is_machine_data`;
        a variable whose number is computed may be that); a feed word changes only the feed, which each
        gathered move keeps as its own (a move at a feed that is not a number is not
        gathered); a dialect's operation when its runtime says so."""
        if kind is ir.SetFeed:
            return True
        if kind in _BETWEEN_GATHERED:
            return kind is not ir.Assign or (isinstance(op.target.name, str) and op.target.name != ir.ACTIVE_EDGE
                                             and not self.is_machine_data(op.target.name))
        inert = self._inert_between_moves.get(kind)
        return inert is not None and inert(self.state)

    def _hand_on_gathered(self) -> None:
        """Hand the gathered moves (:meth:`_gather`) to the observer: as one MotionRun, with
        the state as a batch has it (at the run's start, in the motion mode before it), or,
        when they are too few to make a run pay, one by one, with the state as the block path
        has it at each (its feed too: feed words keep moves gathered); then put back the state
        as it is now."""
        gathered = self._gathered
        if not gathered:
            return
        moves = gathered[:]
        gathered.clear()
        plane, self._gathered_plane = self._gathered_plane, None
        holes, self._gathered_holes = self._gathered_holes, False
        state, start = self.state, self._gathered_start
        now = state.position, state.modal.get("motion"), state.feed
        try:
            if len(moves) < _SHORTEST_RUN:
                for index, move in enumerate(moves):
                    segment = _gathered_segment(moves, start, index)
                    state.position, state.modal["motion"], state.feed = segment.end, move[_MOTION], _as_value(move[_FEED])
                    self._run_observer.segment(segment, state)
            else:
                run = _gathered_run(moves, start, plane, state, holes)
                state.position, state.modal["motion"], state.feed = start, self._gathered_from, _as_value(moves[0][_FEED])
                self._run_observer.motion_run(run, state)
        finally:
            state.position, state.modal["motion"], state.feed = now

    def _emit(self, kind: str, start: dict, span, block, role: str = "programmed", cycle: str | None = None, arc: Arc | None = None,
              written=None) -> None:
        """Report the move from ``start`` to the current position. A dialect's programmed
        contour element that leaves the motion mode alone (``written``: the axes its block
        wrote; None for any other move) may join the gathered moves (:meth:`_gather_segment`)."""
        state = self.state
        segment = state.last_segment = Segment(kind, start, state.position, span, block, role, cycle, arc)
        if written is None or not self._gather_segment(segment, written, state.modal.get("motion")):
            self.observer.segment(segment, state)

    def _x_scale(self) -> float:
        """X positions to radial distances: halved where X is a diameter, by the mode in force
        (SINUMERIK DIAMON, DIAM90 and DIAMOF, LinuxCNC G7 and G8) or, with none, on a lathe."""
        mode = self.state.modal.get("diameter")
        if mode is None:
            return 0.5 if self.machine == "lathe" else 1.0
        return 1.0 if mode == "radius" else 0.5

    def _arc(self, op: ir.Move, kind: str, start: dict) -> Arc:
        state = self.state
        first, second, normal = state.plane_axes
        scale_first = self._x_scale() if first == "X" else 1.0
        scale_second = self._x_scale() if second == "X" else 1.0
        s1, s2 = start.get(first), start.get(second)
        e1, e2 = state.position.get(first), state.position.get(second)
        direction = _ARC_KINDS[kind]
        arc_words = op.arc or {}
        radius_expr = arc_words.get("R")
        if None in (s1, s2, e1, e2):
            return unplaced_arc((first, second, normal), direction or "ccw")
        if direction is None:
            return self._arc_from_geometry(op, kind, start, (first, second, normal), scale_first * scale_second)
        s1, s2, e1, e2 = _scaled(s1, scale_first), _scaled(s2, scale_second), _scaled(e1, scale_first), _scaled(e2, scale_second)
        if radius_expr is not None:
            radius = self.value(radius_expr, op.span)
            if radius is VACANT:
                return unplaced_arc((first, second, normal), direction)
            return arc_by_radius(direction, (first, second, normal), radius, s1, s2, e1, e2)
        letter1, letter2 = _CENTRE_LETTERS[first], _CENTRE_LETTERS[second]
        offset1 = self.value(arc_words.get(letter1, 0.0), op.span)
        offset2 = self.value(arc_words.get(letter2, 0.0), op.span)
        offset1 = 0.0 if offset1 is VACANT else offset1
        offset2 = 0.0 if offset2 is VACANT else offset2
        if state.modal.get("arc_distance") == "absolute":
            c1, c2 = offset1, offset2
        else:  # SINUMERIK I=AC(..) gives one coordinate of the centre itself, read like the axis's own positions
            c1 = _scaled(offset1, scale_first) if letter1 in op.absolute else values.add(s1, offset1)
            c2 = _scaled(offset2, scale_second) if letter2 in op.absolute else values.add(s2, offset2)
        return arc_by_centre(direction, (first, second, normal), c1, c2, s1, s2, e1, e2)

    def _arc_from_geometry(self, op: ir.Move, kind: str, start: dict, plane: tuple, scale: float) -> Arc:
        """SINUMERIK CT (tangent to the previous element) and CIP (through I1/J1/K1): an arc
        in the plane, or one with no centre (its sweep unknown) where the model stops: a
        helix or an inclined circle, a diameter axis, a direction or point not known."""
        first, second, normal = plane
        end = self.state.position
        if scale != 1.0 or start.get(normal) != end.get(normal):
            return unplaced_arc(plane)
        points = (start[first], start[second]), (end[first], end[second])
        if kind == "arc_tangent":
            if self.machine == "lathe":  # the element before may have been read in diameters (DIAMON)
                return unplaced_arc(plane)
            return tangent_arc(plane, end_heading(self.state.last_segment, start, plane), *points)
        middle = [self._intermediate(op, start, axis) for axis in plane]
        if middle[0] is None or middle[1] is None or (middle[2] is not None and middle[2] != start.get(normal)):
            return unplaced_arc(plane)
        return arc_through(plane, points[0], (middle[0], middle[1]), points[1])

    def _intermediate(self, op: ir.Move, start: dict, axis: str):
        """CIP's intermediate point on ``axis`` (I1= J1= K1=), absolute or from the start as
        the end point is read (G90/G91, =AC(..)/=IC(..)); None when not written."""
        word = _CENTRE_LETTERS[axis] + "1"
        expr = (op.arc or {}).get(word)
        value = None if expr is None else self.value(expr, op.span)
        if value is None or value is VACANT:
            return None
        if (self.state.modal["distance"] == "incremental" and word not in op.absolute) or word in op.incremental:
            return None if start.get(axis) is None else values.add(start[axis], value)
        return value

    # ------------------------------------------------------------------ cycles

    def _cycle_define(self, op: ir.CycleDefine, block):
        return self.cycles.define(op, block)

    def _cycle_cancel(self, op: ir.CycleCancel, block):
        if op.plane_change_to is None or op.plane_change_to != self.state.modal["plane"]:
            self._cancel_cycle()
        return None

    def _cancel_cycle(self) -> None:
        if self._gathered_holes:
            self._hand_on_gathered()  # while the rules still see the cycle in force, as they saw each move
        self.state.cycle = None
        self.state.cycle_data = {}

    def _cycle_call(self, op: ir.CycleCall, block):
        return self.cycles.call(op, block)

    # ------------------------------------------------------------------ macro statements

    def _assign(self, op: ir.Assign, block):
        run = self._closures.get(id(op)) or self._compile_on_second_run(op, compiled.compile_assignment)
        if run is not None:
            run()
            return None
        value = self.evaluate(op.value, op.span)
        self.write_variable(op.target, value, op.span, assignment=True)
        return None

    def _alarm(self, op: ir.Alarm, block):
        number = self.evaluate(op.number, op.span)
        shown = f"{number:g}" if type(number) is float else "?"
        text = f" ({op.message})" if op.message else ""
        raised = f"the program raises {op.statement.format(number=shown)}{text}"
        if len(self.state.path_condition) > self.assumed_conditions:
            # reached only for some values of the inputs: the program checking its arguments
            self._fault("core.macro-alarm", op.span, f"{raised} when its inputs fail the check before it (a guard exit, not a fault)",
                        severity="info")
        else:
            self._fault("core.macro-alarm", op.span, f"{raised}: the control stops here")
        raise PathEnd

    # ------------------------------------------------------------------ computed codes

    def _deferred(self, op: ir.Deferred, block):
        resolved = []
        for expr in op.exprs:
            value = self.evaluate(expr, op.span)
            if type(value) is not float:
                self._unsupported_here(op.span, "a G/M code computed from a free parameter")
                raise PathEnd
            resolved.append(value)
        ops, notes = op.resolve(tuple(resolved))
        return self.run_lowered(ops, notes, block)

    def run_lowered(self, ops: list, notes: list, block):
        """Run the ops a block lowered only now turned out to be (and report its notes)."""
        for note in notes:
            self.observer.note(note)
        block = replace(block, ops=ops)  # handlers that look at the block's other ops see the resolved ones
        for inner in ops:
            transfer = self._handlers[type(inner)](inner, block)
            if transfer is not None:
                return transfer
        return None


def op_values(written: dict, interpreter: "Interpreter", span) -> dict:
    """The values of words as written (not made absolute)."""
    evaluated = {}
    for axis, expr in written.items():
        value = interpreter.value(expr, span)
        if value is not VACANT:
            evaluated[axis] = value
    return evaluated


_REMEMBERED_LINES = 20_000  # lowered lines (and their text) kept for the next pass of a loop
_COMPILED_LIMIT = 100_000  # expressions kept with their closures; past it the cache starts again
_FIRST_ARC_KIND = ir.MoveBatch.KINDS.index("arc_cw")  # kinds from here on are arcs: cw, then ccw
_CENTRE_WORD = {"X": 0, "Y": 1, "Z": 2}  # the columns of I, J, K in MoveBatch.arc_words
_RADIUS_WORD = 3
_RUN_SEGMENT_KIND = ("rapid", "feed", "arc", "arc")


_STORED_AXES = frozenset("XYZABC")  # the axes a LinuxCNC G28/G30 without axis words sends to their stored positions
_GATHERED_MOVES = 4096  # moves gathered into one run at most (memory stays flat in program length)
_SHORTEST_RUN = 32  # fewer gathered moves go on one by one: the rules' work per run outweighs their work per move
_RUN_KIND = {"rapid": 0, "feed": 1, "arc": _FIRST_ARC_KIND}  # a segment's kind in a MotionRun (+1: a counter-clockwise arc)
_RUN_AXES = frozenset(RUN_AXES)
_BETWEEN_GATHERED = frozenset({ir.Move, ir.Assign, ir.Jump, ir.LoopStart, ir.LoopEnd})  # operations moves stay gathered across
_ALWAYS_BETWEEN_GATHERED = frozenset({ir.Move, ir.Jump, ir.LoopStart, ir.LoopEnd})  # ... whatever they are: not asked (_keeps_moves_gathered)


def _numbers(position: dict) -> bool:
    """Is every coordinate of ``position`` a number or unknown (None), none symbolic?"""
    for value in position.values():
        if type(value) is not float and value is not None:
            return False
    return True


# A gathered move (Interpreter._gather_segment, and the loop runner's generated passes) is one
# tuple: where it ends on X, Y and Z (None: unknown), its feed (NaN: none), its kind in a
# MotionRun, which of X, Y, Z its block wrote (bits 1, 2, 4), the motion mode it left in
# force, its source and its base. The source is the block path's Segment (base None) or, for a
# loop pass's move, an object that makes the Segment when it is asked for (``position(move)``,
# its end; ``segment(start, end)``; ``span``): base is then the position the runner started
# from (or its last move handed on alone), shared by all the moves of that stretch.
_GATHERED_FIELDS = ("x", "y", "z", "feed", "kind", "written", "motion", "source", "base")
_FEED, _MOTION, _SOURCE, _BASE = (_GATHERED_FIELDS.index(name) for name in ("feed", "motion", "source", "base"))


_WRITTEN_BITS = numpy.array([1, 2, 4], dtype=numpy.uint8)  # X, Y, Z in a gathered move's axes written


@lru_cache(maxsize=16)
def _written_bits(written: tuple) -> int:
    """The axes ``written`` (all among X, Y, Z) as a gathered move holds them."""
    return sum(int(bit) for axis, bit in zip(RUN_AXES, _WRITTEN_BITS) if axis in written)


def _made_end(move: tuple) -> dict | None:
    """The end position of a gathered move's Segment where the block path made one."""
    source = move[_SOURCE]
    return source.end if type(source) is Segment else None


def _gathered_segment(moves: list, start: dict, index: int) -> Segment:
    """The Segment of the ``index``-th of gathered ``moves`` (``start``: where the first
    starts), as the block path makes it: a loop pass's move starts where the move before it
    in the same stretch ends, or, first in its stretch, at the stretch's base."""
    move = moves[index]
    source, base = move[_SOURCE], move[_BASE]
    if type(source) is Segment:
        return source
    if index:
        before = moves[index - 1]
        start = before[_SOURCE].position(before) if before[_BASE] is base else base
    return source.segment(start, source.position(move))


def _gathered_run(moves: list, start: dict, plane, state, holes: bool = False) -> MotionRun:
    """The MotionRun of gathered moves (``start``: where the first starts; ``plane``: their
    arcs' plane, None without arcs; ``holes``: they are a hole cycle's): the batch's form,
    with the block path's segments and spans, made when asked for."""
    # column by column: zip(*moves) makes an iterator of each move, which costs more
    x, y, z, feeds, kinds, written, motions, sources = (list(map(itemgetter(field), moves)) for field in range(_BASE))
    axes = RUN_AXES
    points = numpy.empty((len(moves) + 1, len(axes)), dtype=numpy.float64)
    points[0] = [start.get(axis) for axis in axes]  # an unknown coordinate (None) is NaN
    points[1:, 0], points[1:, 1], points[1:, 2] = x, y, z
    kinds = numpy.array(kinds, dtype=numpy.int8)
    feeds = numpy.array(feeds, dtype=numpy.float64)
    segment_of = lru_cache(maxsize=1)(partial(_gathered_segment, moves, start))  # asked for by the rules, then by the material
    written = numpy.array(written, dtype=numpy.uint8)[:, None] & _WRITTEN_BITS != 0
    return MotionRun(axes, points, kinds, feeds, written, lambda index: sources[index].span, segment_of,
                     None if plane is None else _gathered_arcs(sources, plane, axes), partial(_batch_state_at, state, kinds, feeds, motions=motions),
                     cycle_moves=holes)


def _gathered_arcs(sources: tuple, plane: tuple, axes: tuple) -> BatchArcs:
    """The arcs among gathered moves (all in ``plane``; only the block path's Segments
    have any) as a batch holds them: their plane, its axes' columns, each arc's centre
    (NaN: none, or given by its radius) and radius word (NaN: none)."""
    arcs = [source.arc if type(source) is Segment else None for source in sources]
    centres = numpy.array([arc.centre if arc is not None and arc.centre is not None else (math.nan, math.nan) for arc in arcs], dtype=numpy.float64)
    radii = numpy.array([arc.radius_word if arc is not None and arc.centre is None else math.nan for arc in arcs], dtype=numpy.float64)
    return BatchArcs(plane, [axes.index(plane[0]), axes.index(plane[1])], centres, radii)


class GatheringObserver:
    """Stands between the interpreter and its observer while moves may be gathered
    (:meth:`Interpreter._gather`): every event first hands the gathered moves on
    (``hand_on``), so the observer sees them in the order they happened; a hole leaves a
    hole pattern's moves gathered (``holes_gathered()``), its rules judge it ahead of them."""

    def __init__(self, observer, hand_on, gathered: list, holes_gathered=lambda: False):
        self.inner = observer
        self._hand_on = hand_on
        self._gathered = gathered  # the moves hand_on hands on (mostly none: then no call is made)
        self._holes_gathered = holes_gathered  # are the gathered moves a hole pattern's? (then a hole leaves them gathered)

    def hole(self, hole, state) -> None:
        if self._gathered and not self._holes_gathered():
            self._hand_on()
        self.inner.hole(hole, state)

    def segment(self, segment, state) -> None:
        if self._gathered:
            self._hand_on()
        self.inner.segment(segment, state)

    def __getattr__(self, name):
        attribute = getattr(self.inner, name)
        if not callable(attribute):
            return attribute
        hand_on, gathered = self._hand_on, self._gathered

        def after_gathered(*arguments, **keywords):
            if gathered:
                hand_on()
            return attribute(*arguments, **keywords)

        setattr(self, name, after_gathered)  # made once per kind of event
        return after_gathered


def _batch_span(block_of, index: int) -> Span:
    """The span of a batch's ``index``-th move, as its block gives it."""
    block = block_of(index)
    moves = [op for op in block.ops if isinstance(op, _BATCH_MOVES)]
    return moves[0].span if moves else block.span


def _batch_segment(axes, points, kinds, arcs, others: dict, block_of, index: int) -> Segment:
    """The Segment the block path makes of a batch's ``index``-th move."""
    start = dict(others, **{axis: _as_value(v) for axis, v in zip(axes, points[index].tolist())})
    end = dict(others, **{axis: _as_value(v) for axis, v in zip(axes, points[index + 1].tolist())})
    kind = int(kinds[index])
    arc = arcs.arc(index, kind, start, end) if kind >= _FIRST_ARC_KIND else None
    return Segment(_RUN_SEGMENT_KIND[kind], start, end, _batch_span(block_of, index), block_of(index), "programmed", None, arc)


def _batch_state_at(state, kinds, feeds, segment: Segment, index: int, motions: list | None = None) -> None:
    """Put the state as the block path has it when it reports the batch's ``index``-th
    move: at its end, in its motion mode (``motions``: the mode each move left in force,
    where that is not its kind: a Klartext arc leaves the mode alone), with its feed."""
    state.position = segment.end
    state.modal["motion"] = ir.MoveBatch.KINDS[int(kinds[index])] if motions is None else motions[index]
    feed = float(feeds[index])
    if feed == feed:
        state.feed = feed


@dataclass(slots=True)
class BatchArcs:
    """The arcs of a batch's moves: their plane, the columns of its two axes in the batch's
    points, and each move's centre in the plane (NaN: not an arc, or one given by its radius)
    and radius word (NaN: none)."""

    plane: tuple[str, str, str]
    columns: list
    centres: object  # numpy float64 (moves, 2)
    radii: object  # numpy float64 (moves,)

    def arc(self, index: int, kind: int, start: dict, end: dict) -> Arc:
        """The Arc the block path makes of move ``index``."""
        direction = "cw" if kind == _FIRST_ARC_KIND else "ccw"
        first, second, _normal = self.plane
        s1, s2, e1, e2 = start[first], start[second], end[first], end[second]
        radius = float(self.radii[index])
        if radius == radius:
            return arc_by_radius(direction, self.plane, radius, s1, s2, e1, e2)
        c1, c2 = self.centres[index].tolist()
        return arc_by_centre(direction, self.plane, c1, c2, s1, s2, e1, e2)


_BATCH_AFTER = 4  # plain blocks in a row before the rest of the streak is read as a batch
_BATCH_MOVES = (ir.Move, ir.PoleArc)  # the operations whose span is a batch row's move's (Klartext C: an arc about the pole)
_WATCHED_MODAL = frozenset({"feed_mode", "spindle_mode", "path_mode"})  # groups whose codes make a Change


def _as_float(value) -> float:
    return math.nan if value is None else float(value)


def _as_value(value: float):
    return None if math.isnan(value) else float(value)


def _forward_fill(column, empty, initial: float):
    """Carry the last written value down a column; ``empty`` marks unwritten entries
    (None: NaN). Entries before the first written one get ``initial``."""
    missing = numpy.isnan(column) if empty is None else column == empty
    index = numpy.where(missing, 0, numpy.arange(1, len(column) + 1))
    numpy.maximum.accumulate(index, out=index)
    padded = numpy.concatenate(([initial], numpy.where(missing, numpy.nan, column)))
    return padded[index]


def _logical_operand(value):
    """An operand of AND, OR and XOR: vacant counts as 0, text as a value the checker does
    not follow."""
    if value is VACANT:
        return 0.0
    return values.fresh("text") if isinstance(value, str) else value


def _is_zero(value) -> bool:
    return type(value) is float and value == 0.0


def _scaled(value, scale: float):
    return value if scale == 1.0 else values.mul(value, scale)


def _never(name: str) -> bool:
    """A dialect's parameters are free until set, unless its frontend says otherwise."""
    return False
