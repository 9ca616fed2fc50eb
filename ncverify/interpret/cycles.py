"""Canned cycles expanded into the motion they make (part of the interpret stage).

Hole cycles follow the seven operations of the ISO model (E60 seed L2026-2046): rapid to
the hole at the current level, rapid to the R point, infeed to the bottom, the bottom
actions, retract to R, and under G98 rapid to the initial level. Back boring (G87) rapids
to R below the part and feeds up. The cycle's levels are reported as a :class:`Hole`
before its segments, so rules can judge bottom vs R point vs initial level.

Lathe compound cycles (G70-G73) take their shape from the blocks between the P and Q
sequence numbers; the shape is read, not executed, and its moves are reported as
``contour`` segments. After every lathe cycle the tool is back at the cycle's start point.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from .. import ir, values
from .runtime import Runtime
from ..cycle_models import CycleModel
from ..trace import CycleRun, Hole
from ..values import VACANT

_SHAPE_BLOCK_LIMIT = 10_000


@dataclass(frozen=True)
class DialectCycles:
    """What one dialect's run-time module adds to the shared cycle runner, by the names its
    cycle models give (every dialect module declares one ``CYCLES`` and
    :mod:`ncverify.interpret` installs them all).

    ``shapes``: one-shot cycles whose model says ``shape = "<name>"``;
    ``run(runner, op, block, model, params)`` gets this :class:`CycleRunner`, the
    :class:`ir.CycleCall`, its block, the cycle's model and its evaluated parameters, and
    returns what an op handler returns (None, or a Position when control transfers). It
    reports the cycle and its motion through the runner's public interface
    (:class:`~ncverify.interpret.runtime.Runtime`) so that every motion rule sees it.

    ``levels``: hole cycles whose model says ``levels = "<name>"`` (Fagor: the tool-axis word
    is the reference plane, I the depth); ``resolve(runner, cycle, data)`` returns
    ``(r_point, bottom)`` for the :class:`ActiveCycle` with its data so far (None where
    unknown), or ``(r_point, bottom, reference, entry)``: ``reference`` (or None) for a cycle
    that approaches below its reference plane (Fagor pockets rapid to 1 mm above the
    surface) and leaves the hole back up to it; ``entry`` (or None) where it rapids on from
    the R point down a hole made before it (Fagor thread milling from the bottom up).

    ``passes``: what a hole cycle whose model says ``passes = "<name>"`` does after the rapid
    to the hole position (Fagor G212 runs around a stud, not down its centre):
    ``run(runner, cycle, span, block, levels)`` with the :class:`ActiveCycle` and
    ``levels = (r_point, bottom, reference, entry)`` (bottom known). It emits the segments
    up to the retract (:meth:`CycleRunner.retract` ends at the G98/G99 level)."""

    shapes: dict = field(default_factory=dict)
    levels: dict = field(default_factory=dict)
    passes: dict = field(default_factory=dict)


_DIALECT_SHAPES: dict = {}
_DIALECT_LEVELS: dict = {}
_DIALECT_PASSES: dict = {}


def install(*dialects: DialectCycles) -> None:
    """Make the dialects' cycle runners known to every :class:`CycleRunner`."""
    for dialect in dialects:
        _DIALECT_SHAPES.update(dialect.shapes)
        _DIALECT_LEVELS.update(dialect.levels)
        _DIALECT_PASSES.update(dialect.passes)


@dataclass(slots=True)
class ActiveCycle:
    """The modal canned cycle: its model, its data so far and the initial level."""

    cycle: str
    model: CycleModel
    params: dict
    param_spans: dict
    initial: object  # the drilling-axis level when the cycle mode began
    definition: object = None  # span of the cycle's G code
    incremental: bool = False  # G91 was in force when the cycle was defined
    absolute: set = field(default_factory=set)  # letters set as absolute values whatever G90/G91 (Fagor V.C.x)
    up: float = 1.0  # the side the tool comes from along the drilling axis (see ir.CycleDefine.up)


class CycleRunner(Runtime):
    """Expands canned cycles into motion for the interpreter: the modal hole cycles on the
    shared hole model, lathe compound cycles, and the one-shot cycles the dialects declare.
    Dialect runners get this object and use its public :class:`Runtime` interface and the
    shared hole model (:meth:`drill_axis`, :meth:`make_hole`, :meth:`retract`)."""

    # ------------------------------------------------------------------ helpers

    def drill_axis(self, model: CycleModel) -> str:
        """The axis a hole cycle drills along: its model's, else the working plane's normal."""
        return model.drill_axis or self.state.plane_axes[2]

    # ------------------------------------------------------------------ modal hole cycles

    def define(self, op: ir.CycleDefine, block):
        """A cycle becomes modal. ``cycle = ""`` changes the data of the active cycle only
        (Fagor ``V.C.I=..``; the rule to report when no cycle is active is
        ``params["$rule"]``); a model with ``fresh_data`` starts from its own defaults and
        the current level each time it is defined, and with ``runs_at_definition`` its
        defining block always machines (at the block's end point, or here)."""
        state = self.state
        if not op.cycle:
            return self._change_data(op)
        model = self.cycle_model(op.cycle)
        axis = self.drill_axis(model)
        fresh = bool(model.fresh_data)
        if state.cycle is None or fresh:
            initial = state.position.get(axis)
        else:
            initial = state.cycle.initial
        if fresh:
            state.cycle_data = {}
        params = self.words(op.params, op.span)
        state.cycle_data.update(params)
        spans = dict(state.cycle.param_spans) if state.cycle and not fresh else {}
        spans.update(op.param_spans)
        state.cycle = ActiveCycle(op.cycle, model, state.cycle_data, spans, initial, op.span, state.modal.get("distance") == "incremental", up=op.up)
        has_move = any(isinstance(later, ir.Move) for later in block.ops[block.ops.index(op) + 1 :])
        if not has_move and (params.keys() & {axis, "R"} or model.runs_at_definition):
            return self._holes(op.span, block, {}, frozenset(), None)
        return None

    def _change_data(self, op: ir.CycleDefine):
        state = self.state
        if state.cycle is None:
            letters = ", ".join(letter for letter in op.params if not letter.startswith("$"))
            self._interp._fault(op.params.get("$rule", "core.cycle-missing-parameter"), op.span, f"cycle parameter {letters} is changed while no canned cycle is active: the control alarms")
            return None
        params = self.words({letter: expr for letter, expr in op.params.items() if not letter.startswith("$")}, op.span)
        state.cycle_data.update(params)
        state.cycle.absolute.update(params)
        state.cycle.param_spans.update(op.param_spans)
        return None

    def modal_hole(self, op: ir.Move, block):
        """A block with position or hole data while a cycle is modal makes a hole."""
        state = self.state
        cycle = state.cycle
        model = cycle.model
        if model.shape == "box":
            return self._box(op, block)
        axis = self.drill_axis(model)
        data = self.words(_counts_unscaled(op.words, model), op.span) if op.words else {}  # mostly a new position alone
        positioning = dict(op.targets)
        if axis in positioning and not model.axis_word_moves:  # Fagor: the tool-axis word moves, then the cycle runs
            bottom_expr = positioning.pop(axis)
            bottom = self._interp.value(bottom_expr, op.span)
            if bottom is not VACANT:
                data[_bottom_letter(axis, op, self._interp.twins)] = bottom
        cycle.param_spans.update(op.word_spans())
        state.cycle_data.update(data)
        if not positioning and not data:
            return None
        return self._holes(op.span, block, positioning, op.incremental, op)

    def modal_call(self, op: ir.Move, block):
        """A modal cycle called after a positioning move (SINUMERIK ``MCALL``): its
        dialect shape runs with the arguments evaluated when the call was made modal."""
        cycle = self.state.cycle
        run = _DIALECT_SHAPES.get(cycle.model.shape)
        if run is None:
            return None
        call = ir.CycleCall(op.span, cycle.cycle, {}, dict(cycle.param_spans))
        return run(self, call, block, cycle.model, dict(cycle.params))

    def _holes(self, span, block, positioning: dict, incremental, op):
        state = self.state
        cycle = state.cycle
        repeat = state.cycle_data.pop(cycle.model.repeat_letter or "L", None)  # Fagor: NR (L is a parameter there)
        if repeat is None and ("K" not in cycle.model.params or cycle.model.params["K"].kind == "count"):
            repeat = state.cycle_data.pop("K", None)  # not the shift K of mill G76/G87
        if repeat is None:
            repeat = 1.0
        if type(repeat) is not float:
            self._interp._unsupported_here(span, "a hole repeat count that depends on a free parameter")
            return None
        if not 0 <= repeat <= 9999:
            self._interp._fault("core.repeat-count-range", span, f"repeat count {repeat:g} is outside 0-9999")
            return None
        if repeat == 0 and cycle.model.zero_repeat_moves:  # Fagor NR0: the move without machining
            kind = "rapid" if state.modal.get("motion") == "rapid" else "feed"
            self.move_to(self._interp._targets(positioning, incremental, span), span, block, "programmed", None, kind)
            return None
        for _ in range(int(repeat)):
            targets = self._interp._targets(positioning, incremental, span)
            self.make_hole(cycle, span, block, targets, repeat)
        return None

    def make_hole(self, cycle, span, block, targets: dict, repeat: float = 1.0) -> None:
        interp = self._interp
        state = interp.state
        model = cycle.model
        axis = model.drill_axis or state.plane_axes[2]  # drill_axis()
        data = state.cycle_data
        incremental = state.modal.get("distance") == "incremental"
        initial = cycle.initial
        r_point, bottom, *beyond = self._levels(model, axis, data, initial, incremental)
        reference, entry = (*beyond, None, None)[:2]
        missing = tuple(letter for letter, spec in model.params.items()
                        if spec.required and letter not in data and not _has_twin(letter, data, interp.twins) and not (model.r_incremental and letter == "R"))
        hole_position = dict(state.position)
        hole_position.update(targets)
        hole = Hole(cycle.cycle, model, span, block, axis, hole_position, initial, r_point, bottom, dict(data), dict(cycle.param_spans), missing, cycle.definition, repeat, cycle.up)
        interp.observer.hole(hole, state)
        if model.starts_spindle and state.spindle == "off":
            state.spindle = "cw"  # Fagor: a cycle starts a stopped spindle clockwise (rules saw it stopped)
        if missing or bottom is None:
            state.move_to(targets)
            return
        passes = _DIALECT_PASSES.get(model.passes)
        steps = self._hole_steps(cycle, axis, targets, (r_point, bottom, reference, entry), passes is None)
        self.move_through(steps, span, block, cycle.cycle)
        if passes is not None:
            passes(self, cycle, span, block, (r_point, bottom, reference, entry))

    def _hole_steps(self, cycle: ActiveCycle, axis: str, targets: dict, levels: tuple, down: bool) -> list:
        """The moves of one hole as :meth:`move_through` takes them, from where the tool
        stands to the hole (``targets``) and, with ``down``, into it and out (a dialect's
        passes make the rest)."""
        state = self.state
        model = cycle.model
        r_point, bottom, reference, entry = levels
        positioning = "rapid"
        if model.positions_in_motion_mode and state.modal.get("motion") != "rapid":
            positioning = "feed"  # Fagor: the move to the hole is made in the interpolation in force (G1: at feed)
        steps = []
        if model.rises_to_r:  # LinuxCNC: a tool below the R point first rises to it, then positions
            level = state.position.get(axis)
            if type(level) is float and type(r_point) is float and (level - r_point) * cycle.up < 0:
                steps.append(({axis: r_point}, "approach", "rapid"))
        steps.append((targets, "between-holes", positioning))
        if not down:
            return steps
        if model.infeed == "back_bore":
            return [*steps, ({axis: r_point}, "through-bore", "rapid"), ({axis: bottom}, "infeed", "feed"), ({axis: cycle.initial}, "retract", "rapid")]
        steps.append(({axis: r_point}, "approach", "rapid"))
        if entry is not None:
            steps.append(({axis: entry}, "into-hole", "rapid"))
        steps.append(({axis: bottom}, "infeed", "feed"))
        retract_kind = "feed" if model.retract == "feed" else "rapid"
        straight_out = model.retract_to_higher and not model.feeds_out_to_r and reference is None and state.modal.get("cycle_return") != "r_point"
        if not straight_out:  # LinuxCNC leaves the hole straight to the G98 level, at the cycle's retract kind
            steps.append(({axis: r_point}, "out-of-hole", retract_kind))
        if reference is not None:
            steps.append(({axis: reference}, "out-of-hole", "rapid"))
        retract = self._retract_step(cycle, r_point, *((retract_kind, "out-of-hole") if straight_out else ()))
        if retract is not None:
            steps.append(retract)
        return steps

    def retract(self, cycle: ActiveCycle, span, block, r_point=None, kind: str = "rapid", role: str = "retract") -> None:
        """G98: rapid back to the initial level (G99 stays at the R point); with
        ``retract_to_higher`` (LinuxCNC) to the higher of the initial level and R."""
        step = self._retract_step(cycle, r_point, kind, role)
        if step is not None:
            self.move_to(step[0], span, block, step[1], cycle.cycle, step[2])

    def _retract_step(self, cycle: ActiveCycle, r_point=None, kind: str = "rapid", role: str = "retract") -> tuple | None:
        """:meth:`retract` as a step of :meth:`move_through`; None under G99."""
        if self.state.modal.get("cycle_return") == "r_point" or cycle.initial is None:
            return None
        level = cycle.initial
        if cycle.model.retract_to_higher and type(level) is float and type(r_point) is float:
            level = max(level * cycle.up, r_point * cycle.up) * cycle.up
        return {self.drill_axis(cycle.model): level}, role, kind

    def _levels(self, model: CycleModel, axis: str, data: dict, initial, incremental: bool):
        """R point and bottom on the drilling axis (seed L2059 and the lathe table L2890)."""
        resolve = _DIALECT_LEVELS.get(model.levels)
        if resolve is not None:
            return resolve(self, self.state.cycle, data)
        bottom_letter = axis
        twin = next((t for t, a in self._interp.twins.items() if a == axis), None)
        r_word = data.get("R")
        if model.r_incremental:
            return self._lathe_levels(axis, data, initial, twin)
        if r_word is None:
            r_point = None
        elif incremental:  # G91: R from the initial level, Z from the R point
            r_point = None if initial is None else values.add(initial, r_word)
        else:
            r_point = r_word
        bottom_word = data.get(bottom_letter)
        if bottom_word is None:
            return r_point, None
        if incremental:
            return r_point, None if r_point is None else values.add(r_point, bottom_word)
        return r_point, bottom_word

    def _lathe_levels(self, axis, data, initial, twin):
        if initial is None:
            return None, None
        incremental_bottom = data.get(twin) if twin else None
        absolute_bottom = data.get(axis)
        r_distance = values.absolute(data.get("R", 0.0))
        if incremental_bottom is not None:
            toward = -1.0 if _is_negative(incremental_bottom) else 1.0
        elif absolute_bottom is not None:
            toward = -1.0 if _is_negative(values.sub(absolute_bottom, initial)) else 1.0
        else:
            return None, None
        r_point = values.add(initial, values.mul(r_distance, toward))
        bottom = values.add(r_point, incremental_bottom) if incremental_bottom is not None else absolute_bottom
        return r_point, bottom

    # ------------------------------------------------------------------ lathe box cycles

    def _box(self, op: ir.Move, block):
        """G77/G78/G79 (Fanuc list-A G90/G92/G94): rapid in, cut, feed out, rapid back."""
        state = self.state
        cycle = state.cycle
        data = self.words(op.words, op.span)
        state.cycle_data.update(data)
        targets = self._interp._targets(op.targets, op.incremental, op.span)
        if not targets:
            return None
        start = state.position
        x_end, z_end = targets.get("X", start.get("X")), targets.get("Z", start.get("Z"))
        face = cycle.cycle.endswith("G79")
        name = cycle.cycle
        cut = "thread" if cycle.model.thread else "feed"
        interp = self._interp
        interp.observer.cycle_run(CycleRun(name, cycle.model, op.span, block, dict(state.cycle_data), op.word_spans()), state)
        first, second = ({"Z": z_end}, {"X": x_end}) if face else ({"X": x_end}, {"Z": z_end})
        self.move_to(first, op.span, block, "approach", name)
        self.move_to(second, op.span, block, "infeed", name, cut)
        back_first = {"Z": start.get("Z")} if face else {"X": start.get("X")}
        self.move_to(back_first, op.span, block, "retract", name, "feed")
        self.move_to({"X": start.get("X"), "Z": start.get("Z")}, op.span, block, "retract", name)
        return None

    # ------------------------------------------------------------------ one-shot cycles

    def call(self, op: ir.CycleCall, block):
        state = self.state
        model = self.cycle_model(op.cycle)
        params = self.words(op.params, op.span)
        shape = model.shape
        if shape in _DIALECT_SHAPES:
            return _DIALECT_SHAPES[shape](self, op, block, model, params)
        if shape == "circle":
            return self._circle(op, block, model, params)
        first_block = bool(model.two_blocks) and self._is_first_block(model, params)
        stored = state.lathe_cycle_data.setdefault(op.cycle, {})
        if first_block:
            stored.clear()
            stored.update({f"first_{letter}": value for letter, value in params.items()})
            self._interp.observer.cycle_run(CycleRun(op.cycle, model, op.span, block, dict(stored), dict(op.param_spans), True), state)
            return None
        self._interp.observer.cycle_run(CycleRun(op.cycle, model, op.span, block, params, dict(op.param_spans)), state)
        start = state.position
        if shape == "contour":
            self._contour(op, block, params)
        elif shape in ("groove", "thread"):
            self._straight_cycle(op, block, params, "thread" if shape == "thread" else "feed")
        state.move_to(start)
        return None

    @staticmethod
    def _is_first_block(model: CycleModel, params: dict) -> bool:
        """The first block of a two-block cycle carries only the first-block letters
        (G71 U R, G76 P R): the second one has P/Q or an end point."""
        return bool(params) and set(params) <= set(model.first_block) and not (params.keys() & {"X", "Z"})

    def _straight_cycle(self, op, block, params, cut: str) -> None:
        targets = {}
        for axis, twin in (("X", "U"), ("Z", "W")):
            if axis in params:
                targets[axis] = params[axis]
            elif twin in params and self.state.position.get(axis) is not None:
                targets[axis] = values.add(self.state.position[axis], params[twin])
        if targets:
            self.move_to(targets, op.span, block, "infeed", op.cycle, cut)

    def _contour(self, op: ir.CycleCall, block, params: dict) -> None:
        """Report the finishing shape between sequence numbers P and Q as contour moves."""
        interp = self._interp
        first, last = params.get("P"), params.get("Q")
        if type(first) is not float or type(last) is not float:
            return
        start = interp.find_label(first, op.param_spans.get("P", op.span))
        end = interp.find_label(last, op.param_spans.get("Q", op.span))
        if (end.offset, end.block_index) < (start.offset, start.block_index):
            interp._fault("core.shape-order", op.span, f"the shape's first block N{first:g} comes after its last block N{last:g}: the control alarms")
            return
        self._walk_shape(op, block, start, end)

    def _walk_shape(self, op, block, start, end) -> None:
        interp = self._interp
        state = self.state
        source = start.source
        path = None if source is interp.source else source.name
        count = 0
        for line_number, offset, _next, raw in source.lines_from(start.offset):
            if offset > end.offset:
                return
            for index, shape_block in enumerate(interp.frontend.blocks(raw, line_number, path)):
                if offset == start.offset and index < start.block_index:
                    continue
                count += 1
                if count > _SHAPE_BLOCK_LIMIT:
                    return
                if any(isinstance(shape_op, ir.Return) for shape_op in shape_block.ops):
                    return
                for shape_op in shape_block.ops:
                    if isinstance(shape_op, ir.SetModal) and shape_op.group in ("distance", "plane"):
                        state.modal[shape_op.group] = shape_op.value
                    if isinstance(shape_op, ir.Move) and shape_op.targets:
                        targets = interp._targets(shape_op.targets, shape_op.incremental, shape_op.span)
                        self.move_to(targets, shape_op.span, shape_block, "contour", op.cycle, "feed")
                if offset == end.offset and index >= end.block_index:
                    return

    def _circle(self, op: ir.CycleCall, block, model: CycleModel, params: dict):
        """G12/G13: out from the centre, a full circle, back to the centre."""
        state = self.state
        self._interp.observer.cycle_run(CycleRun(op.cycle, model, op.span, block, params, dict(op.param_spans)), state)
        radius = params.get("I")
        first, _second, _normal = state.plane_axes
        centre = state.position.get(first)
        if radius is None or centre is None:
            return None
        out = values.add(centre, values.absolute(radius))
        self.move_to({first: out}, op.span, block, "infeed", op.cycle, "feed")
        self.move_to({first: centre}, op.span, block, "retract", op.cycle, "feed")
        return None


def grid(columns: float, rows: float) -> list[tuple[int, int]]:
    """(column, row) of every point of a pattern of ``columns`` x ``rows``, row by row; none
    when either count is below 1 (callers bound the product by the loop bound, and a billion
    rows of no columns must not be walked row by row)."""
    columns, rows = int(max(columns, 0.0)), int(max(rows, 0.0))
    if not columns or not rows:
        return []
    return [(column, row) for row in range(rows) for column in range(columns)]


def _counts_unscaled(words: dict, model: CycleModel) -> dict:
    """Code and count words of a hole block (``,R1``, lathe ``K3``) as written: the Move's
    lowering cannot know the cycle and scales them like lengths (``_cycle_params`` does
    not)."""
    declared = model.params

    def is_count(letter: str, expr) -> bool:
        kind = (declared[letter].kind if letter in declared else None) or ("count" if letter in ("L", "K") else None)
        return type(expr) is ir.IncrementCount and kind in ("code", "count")

    if not any(is_count(letter, expr) for letter, expr in words.items()):
        return words
    return {letter: expr.count if is_count(letter, expr) else expr for letter, expr in words.items()}


def _bottom_letter(axis: str, op: ir.Move, twins: dict) -> str:
    if axis in op.incremental:
        for twin, target in twins.items():
            if target == axis:
                return twin
    return axis


def _has_twin(letter: str, data: dict, twins: dict) -> bool:
    return any(target == letter and twin in data for twin, target in twins.items())


def _is_negative(value) -> bool:
    low, high = values.interval(value)
    return high < 0 or (low < 0 and high <= 0)
