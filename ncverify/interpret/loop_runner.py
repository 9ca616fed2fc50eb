"""Loop passes run by one generated function each, not block by block.

A loop whose pass runs straight through (assignments of plain numbers to named variables,
straight moves whose words are expressions, tests that must come out one way, and the jump
or loop end back to the head) is compiled, once a pass has run on the block path and left
its lines lowered, into one function (:class:`_PassCode`) that runs pass after pass. For
each pass it first reads the variables the pass reads and computes every value, test and
count on floats, changing nothing; only when all of them are what the straight pass needs
does it carry the pass out, in the order of its operations: variables written, moves made
and gathered (or handed to the observer) as :meth:`~ncverify.interpret.Interpreter._move`
makes them, blocks counted, the jump or the loop's pass counted against the loop bound.
Only the first pass reads the variable tables (each later one takes the values the one
before wrote: no rule writes a variable); the counts of blocks and passes are kept in
locals and written back wherever the state can be seen (a move handed on alone, the
gathered moves handed on, the runner's end). A gathered move is kept as numbers, its
Segment and position made only when asked for (:class:`_GatheredMove`).
Anything else (a value that is not a float, a failed operation or a result past the float
range, a test that would branch, the loop bound, the analysis budget, the loop's end) stops
the runner before that pass, which the block path then runs from the loop head and reports
as it always does. The runner works on the IR: it serves every dialect's loops that lower
to a head and a transfer back to it (LinuxCNC O-word loops, Fanuc WHILE/DO/END and GOTO,
SINUMERIK WHILE, Fagor $WHILE, Klartext FN jumps) where their passes fit.
"""
from __future__ import annotations

import math

from .. import ir
from ..trace import ROTARY_AXES, RUN_AXES, Segment
from .compiled import StraightCode, factory

_MOST_LINES = 64  # lines of a pass at most
_MOST_NODES = 400  # expression nodes of a pass at most
_ATTEMPTS = 4  # builds tried at a head (its lines may not all be lowered yet) before it is given up
_IDLE = 16  # calls in a row that ran no pass before a head is given up
_HEADS = 10_000  # heads remembered; past it the table starts again
_SEGMENT_KINDS = {"rapid": "rapid", "linear": "feed"}  # the motion modes a pass may move in, and the segments they make
_RUN_AXES = frozenset(RUN_AXES)
_GIVEN_UP = _ATTEMPTS + 1


class LoopRunners:
    """The compiled loops of one interpreter, by head position. :meth:`run` is called
    wherever control lands (the interpreter's ``_run_path``): at a loop's head it runs as many
    whole passes as its compiled pass can take. The interpreter tells how it gathers moves:
    the type of its gathering observer, the most moves it gathers, the plain lines in a row
    after which it reads a batch, its test that a position holds numbers, and how a gathered
    move holds its kind of segment (``run_kinds``) and the axes its block wrote
    (``written_bits``)."""

    def __init__(self, interpreter, *, gathering: type, most_gathered: int, batch_after: int, numbers, run_kinds: dict, written_bits):
        self.interpreter = interpreter
        self.gathering, self.most_gathered, self.batch_after, self.numbers = gathering, most_gathered, batch_after, numbers
        self.run_kinds, self.written_bits = run_kinds, written_bits
        self._heads: dict[tuple, object] = {}  # head -> _Loop, or the builds tried there so far

    def run(self, head) -> None:
        key = (id(head.source), head.offset, head.block_index, head.op_index)
        entry = self._heads.get(key, 0)
        if type(entry) is int:
            if entry == 0 or entry >= _GIVEN_UP:  # the first arrival: the pass has not run yet
                if entry == 0:
                    if len(self._heads) >= _HEADS:
                        self._heads.clear()
                    self._heads[key] = 1
                return
            entry = _build(self, head)
            if type(entry) is int:
                self._heads[key] = _GIVEN_UP if entry == _NEVER else self._heads[key] + 1
                return
            self._heads[key] = entry
        if not entry.run(head):
            self._heads[key] = _GIVEN_UP


_NEVER, _AGAIN = 0, 1  # why no loop was built: never at this head, or not yet


def _build(runners: LoopRunners, head):
    """The straight pass from ``head`` back to it, as a :class:`_Loop`; ``_NEVER`` where the
    pass holds an operation the runner does not carry out or does not come back to ``head``
    on its own, ``_AGAIN`` where its lines are not all lowered yet."""
    interpreter = runners.interpreter
    if interpreter.settings.record_values:
        return _NEVER
    remembered, text_id = interpreter.line_text, id(head.source)
    offset, first_block, first_op = head.offset, head.block_index, head.op_index
    steps, lines, plain_streak = [], [], 0
    while len(lines) < _MOST_LINES:
        line = remembered.get((text_id, offset))
        if line is None or line[5] is None:
            return _AGAIN
        if lines and plain_streak >= runners.batch_after and line[4]:
            return _NEVER  # the block path would read the rest of the streak as a batch
        lines.append(line)
        blocks = line[5]
        plain_streak = plain_streak + 1 if line[4] and len(blocks) == 1 else 0
        for block_index in range(first_block, len(blocks)):
            block = blocks[block_index]
            if block.notes or block.tape_mark or (block.program_start and first_op == 0):
                return _NEVER
            steps.append(("block",))
            for op in block.ops[first_op:]:
                step = _step(interpreter, head, op, block, line[1], len(steps) == 1)
                if step is None:
                    return _NEVER
                steps.append(step)
                if step[0] in ("jump", "loop_end"):
                    return _Loop(runners, head, steps, lines)
            first_op = 0
        first_block = 0
        offset = line[2]
    return _NEVER


def _step(interpreter, head, op, block, line_offset: int, first: bool):
    """What ``op`` does in a straight pass, or None when the runner does not carry it out:
    ``("assign", value, op)``, ``("move", op, block)``, ``("test", condition, outcome the pass
    needs)``, ``("loop_start", condition, op)`` (the head's own test only), and the transfer back
    to ``head`` that ends the pass, ``("jump", condition or None, op, line offset)`` or
    ``("loop_end", None, op)``."""
    kind = type(op)
    if kind is ir.Assign:
        target = op.target
        if not isinstance(target.name, str) or target.name == ir.ACTIVE_EDGE:
            return None
        return "assign", op.value, op
    if kind is ir.Move:
        if op.kind not in (None, "rapid", "linear") or op.arc or "NR" in op.words:
            return None
        return "move", op, block
    if kind is ir.LoopStart:
        return ("loop_start", op.condition, op) if first else None
    if kind is ir.LoopEnd:
        return "loop_end", None, op
    if kind is ir.Jump:
        if op.optional:
            return None
        if _lands_at(_landing(interpreter, op, head.source, line_offset), head):
            return "jump", op.condition, op, line_offset
        return None if op.condition is None else ("test", op.condition, False)  # not taken on a straight pass: where it goes is not asked
    return None


def _landing(interpreter, op: ir.Jump, source, line_offset: int):
    """Where the jump ``op`` (on the line of ``source`` at ``line_offset``) lands, as found
    before without a finding (:meth:`~ncverify.interpret.Interpreter.find_label` keeps those);
    None if not known. Its label is written, or read from the machine state as the block path
    reads it (Fagor's flow statements: the label of the partner line in the running program,
    which no pass changes)."""
    target = op.target
    if type(target) is ir.MachineValue:
        target = target.read(interpreter.state)
    if not (type(target) is str or (type(target) is float and target - target == 0.0)):
        return None
    frame = interpreter.state.call_stack[-1]
    current = line_offset if frame.source is source else -1
    return interpreter.landing_cache.get((id(frame.source), frame.program, target, current, op.direction, True))


def _lands_at(position, head) -> bool:
    return (position is not None and position.source is head.source and position.offset == head.offset
            and position.block_index == head.block_index and position.op_index == head.op_index)


class _Loop:
    """A loop's straight pass from its head: ``steps`` (see :func:`_step`, and ``("block",)``
    where each block starts) over ``lines`` (the remembered lines, which must still be the
    ones the block path would run), compiled per motion mode, distance mode and gathering."""

    def __init__(self, runners: LoopRunners, head, steps: list, lines: list):
        self.runners = runners
        self.steps = steps
        self.lines = [((id(head.source), line[1]), line) for line in lines]
        self.transfer = steps[-1]
        self.passes_end = lines[-1][2]  # the block path's _run_from ends its visited streak here
        self.axes = {axis for step in steps if step[0] == "move" for axis in step[1].targets if axis in _RUN_AXES}  # (see _PassCode._position)
        self.codes: dict[tuple, object] = {}
        self.idle = 0

    def run(self, head) -> bool:
        """Run whole passes from ``head`` while they are straight; False once this loop is
        not worth trying again (its lines were read again, or it ran no pass too often)."""
        runners = self.runners
        interpreter = runners.interpreter
        state = interpreter.state
        remembered = interpreter.line_text
        if any(remembered.get(key) is not line for key, line in self.lines):
            return False
        position = state.position
        if (state.cycle is not None or state.parked or state.left_start or not interpreter._should_cache()
                or not runners.numbers(position) or not all(axis in position for axis in self.axes)):
            return self._idle()  # the pass that first moves X, Y or Z adds it to the position: the block path runs that one
        motion = state.modal.get("motion")
        motions = self._motions(motion)
        if motions is None:
            return self._idle()
        feed = state.feed
        gathering = (type(interpreter.observer) is runners.gathering and state.frame is None and (feed is None or type(feed) is float))
        count_key = loop_frame = None
        _kind, _condition, op, *rest = self.transfer
        if self.transfer[0] == "jump":
            landing = _landing(interpreter, op, head.source, rest[0])
            if not _lands_at(landing, head):
                return self._idle()
            count_key = (id(landing.source), landing.offset, landing.block_index)
        else:
            loop_frame = next((frame for frame in reversed(state.loops) if frame.loop_id == op.loop_id), None)
            if loop_frame is None or not _lands_at(loop_frame.head, head):
                return self._idle()
        first = self.steps[1]
        if first[0] == "loop_start" and not any(loop.loop_id == first[2].loop_id and loop.head == head for loop in state.loops):
            return self._idle()
        shape = (motion, gathering, state.modal.get("distance") == "incremental")
        code = self.codes.get(shape)
        if code is None:
            code = self.codes[shape] = _PassCode(interpreter, self.steps, motions, *shape[1:], runners).function()
        if code is False:
            return False
        passes = code(interpreter, state, state.local_variables, state.global_variables, interpreter._gathered,
                      math.nan if feed is None else feed, state.jump_counts, count_key, loop_frame, interpreter.settings.loop_bound,
                      interpreter.block_budget, interpreter._hand_on_gathered, interpreter.observer)
        if not passes:
            return self._idle()
        self.idle = 0
        visited = interpreter.visited
        last = visited[-1] if visited else None
        if last is None or last[0] is not head.source or last[1] != head.offset or last[2] != self.passes_end:
            visited.append((head.source, head.offset, self.passes_end))  # as each pass's _run_from leaves it
        return True

    def _idle(self) -> bool:
        self.idle += 1
        return self.idle < _IDLE

    def _motions(self, motion) -> list | None:
        """The motion mode before and after each move of a pass that starts in ``motion``;
        None unless every move is straight and the pass ends in the mode it started in."""
        modes, now = [], motion
        for step in self.steps:
            if step[0] == "move":
                after = step[1].kind or now
                if after not in _SEGMENT_KINDS:
                    return None
                modes.append((now, after))
                now = after
        return modes if now == motion else None


class _PassCode(StraightCode):
    """The generated function of a loop's pass (see the module's docstring):
    ``run(interpreter, state, local, global_, gathered, feed, counts, count_key, loop_frame,
    bound, budget, hand_on, observer)`` runs passes while they are straight and returns how
    many it ran. Names and values of the program are passed in, not written into the code,
    so that loops of one shape share it."""

    def __init__(self, interpreter, steps: list, motions: list, gathering: bool, incremental: bool, runners: LoopRunners):
        super().__init__(interpreter)
        self.objects: list = list(RUN_AXES)  # k0, k1, k2: the axes of p0, p1, p2
        self.current: dict[str, str] = {}  # variable -> the operand holding its value at this point of the pass
        self.tests, self.limit, self.effects, self.finish = [], [], [], []
        self.read: dict[str, str] = {}  # variable -> the operand holding its value at the pass's start
        # the pass counter against the loop bound and the blocks run: kept in locals, written
        # back wherever the state is seen (a move handed on, gathered moves handed on, the end)
        self.counter = "count" if steps[-1][0] == "jump" else "iterations"
        self.store = [f"interpreter.blocks_run = blocks\n{'counts[count_key] = count' if self.counter == 'count' else 'loop_frame.iterations = iterations'}"]
        moves = [step[1] for step in steps if step[0] == "move" and step[1].targets]
        self.gathered = [gathering and op.span.path is None and _RUN_AXES.issuperset(op.targets) for op in moves]
        self.axes = [axis for axis in RUN_AXES if any(axis in op.targets for op in moves)]  # X, Y, Z as the pass moves them
        self.moves_made = 0
        self.runners = runners
        self.built = self._pass(steps, iter(motions), incremental)

    def function(self):
        """The generated function, or False when the pass has an expression that is not
        straight-line arithmetic or a value that is a comparison's outcome."""
        if not self.built:
            return False
        return factory(self.text_of_pass())(_ABSENT, Segment, tuple(self.constants), tuple(self.names), tuple(self.functions), tuple(self.objects))

    def _position(self, values: str = "p") -> str:
        """The position dict as the block path has it at this point of the pass: the stretch's
        base with the pass's X, Y, Z from the operands ``values``0..2 (the runner starts only
        where the position already holds every one of X, Y, Z the pass moves, so no key is
        added and their order is the block path's)."""
        axes = ", ".join(f"{self._object(axis)}: {values}{RUN_AXES.index(axis)}" for axis in self.axes)
        return f"{{**base, {axes}}}" if axes else "base"

    def _object(self, value) -> str:
        """The name of ``value`` in the generated code (the axes X, Y, Z are always k0..k2)."""
        if type(value) is str and value in RUN_AXES:
            return f"k{RUN_AXES.index(value)}"
        self.objects.append(value)
        return f"k{len(self.objects) - 1}"

    def _read(self, var: ir.Var):
        if not isinstance(var.name, str):
            return None
        known = self.current.get(var.name)
        if known is not None:
            return known, False
        self.names.append(var.name)
        table = "local" if self.interpreter.is_local(var.name) else "global_"
        name = self.current[var.name] = self.read[var.name] = f"v{len(self.reads)}"
        self.reads.append(f"{name} = {table}.get(n{len(self.names) - 1}, ABSENT)\nif type({name}) is not float:\n    return 0")
        return name, False

    def _number(self, expr) -> str | None:
        """The operand of a value the pass uses as a number (a comparison's outcome is not)."""
        operand = self.node(expr)
        return None if operand is None or operand[1] else operand[0]

    def _pass(self, steps, motions, incremental: bool) -> bool:
        for step in steps:
            kind = step[0]
            if kind == "assign":
                value = self._number(step[1])
                if value is None:
                    return False
                name = step[2].target.name
                if self.interpreter.is_machine_data(name):
                    return False  # the block path notes what it changes
                table = "local" if self.interpreter.is_local(name) else "global_"
                self.effects.append(f"{table}[{self._object(name)}] = {value}")
                self.current[name] = value
            elif kind == "move":
                if not self._move(step[1], step[2], next(motions), incremental):
                    return False
            elif kind in ("test", "loop_start", "jump") and step[1] is not None:
                condition = self.node(step[1])
                if condition is None:
                    return False
                needed = step[2] if kind == "test" else True
                self.tests.append(f"if {'not ' if needed else ''}{condition[0]}:\n    break")
        if self.size > _MOST_NODES:
            return False
        blocks = sum(1 for step in steps if step[0] == "block")
        counter = self.counter
        self.limit = [f"if {counter} + 1 {'>' if counter == 'count' else '>='} bound:\n    break", f"if blocks + {blocks} > budget:\n    break"]
        self.effects.insert(0, f"blocks += {blocks}")
        # the next pass reads what this one wrote (no rule writes a variable): only the first reads the tables
        self.effects += [f"{counter} += 1", *(f"{read} = {self.current[name]}" for name, read in self.read.items() if self.current[name] != read)]
        return True

    def _move(self, op: ir.Move, block, motion: tuple, incremental: bool) -> bool:
        """The effects of a straight move, as :meth:`~ncverify.interpret.Interpreter._move` and
        :meth:`~ncverify.interpret.Interpreter._gather_segment` have them, on the pass's X, Y, Z
        (``p0``..``p2``) and ``base``, the position dict of the stretch. A gathered move keeps
        its end as numbers (its Segment and position are made when asked for); a move handed
        on alone is made as the block path makes it, and its end becomes the base."""
        before, after = motion
        effects = self.effects
        if op.kind is not None and after != before:  # the same mode again changes nothing
            effects.append(f"modal['motion'] = {self._object(after)}")
        if not op.targets:
            return True
        if ROTARY_AXES.intersection(op.targets):
            return False  # the block path notes a turn of the part (Interpreter._turned)
        index, self.moves_made = self.moves_made, self.moves_made + 1
        gathered, last = self.gathered[index], self.moves_made == len(self.gathered)
        targets = {}
        for axis, expr in op.targets.items():
            value = self._number(expr)
            if value is None:
                return False
            if (incremental and axis not in op.absolute) or axis in op.incremental:
                now = f"p{RUN_AXES.index(axis)}" if axis in _RUN_AXES else f"start.get({self._object(axis)})"
                value = f"None if {now} is None else {now} + {value}"
            targets[axis] = value
        if gathered:
            runners, move = self.runners, self._object(_GatheredMove(_SEGMENT_KINDS[after], op.span, block, self.axes))
            effects.append(f"if not gathered:\n    interpreter._gathered_from = {self._object(before)}\n"
                           f"    interpreter._gathered_start = {self._position()}")
            if last:
                effects.append("b0, b1, b2 = p0, p1, p2")
                self.finish = [f"state.position = {self._position()}", f"state.last_segment = {move}.segment({self._position('b')}, state.position)"]
            effects += [f"p{RUN_AXES.index(axis)} = {value}" for axis, value in targets.items()]
            effects += [f"gathered.append((p0, p1, p2, feed, {runners.run_kinds[_SEGMENT_KINDS[after]]}, {runners.written_bits(tuple(op.targets))}, "
                        f"{self._object(after)}, {move}, base))",  # the layout of interpreter._GATHERED_FIELDS
                        f"if len(gathered) >= {runners.most_gathered}:\n    state.motion_seen = True\n" + _indented(self.store, 1) + "    hand_on()"]
            return True
        effects.append(f"start = {'base' if self._clean(index) else self._position()}")
        ends = []
        for axis, value in targets.items():
            if axis in _RUN_AXES:
                effects.append(f"p{RUN_AXES.index(axis)} = {value}")
                value = f"p{RUN_AXES.index(axis)}"
            ends.append(f"{self._object(axis)}: {value}")
        effects += [f"base = state.position = {{**start, {', '.join(ends)}}}", "state.motion_seen = True",
                    f"segment = Segment({self._object(_SEGMENT_KINDS[after])}, start, base, {self._object(op.span)}, {self._object(block)}, 'programmed', None, None)",
                    *self.store, "observer.segment(segment, state)"]
        if last:
            self.finish = ["state.position = base", "state.last_segment = segment"]
        return True

    def _clean(self, index: int) -> bool:
        """Is the position before the pass's ``index``-th move (one handed on alone) the base:
        was the move before it (the pass's last, for its first) handed on alone too? (At the
        runner's start the position is the base anyway.)"""
        return not self.gathered[(index - 1) % len(self.gathered)]

    def text_of_pass(self) -> str:
        """The source of ``make(ABSENT, Segment, c, n, f, k)``, which returns the pass runner."""
        unpack = "".join(f"    {', '.join(f'{letter}{index}' for index in range(count))}, = {letter}\n"
                         for letter, count in (("c", len(self.constants)), ("n", len(self.names)), ("f", len(self.functions)),
                                               ("k", len(self.objects))) if count)
        # one sum of the results: it is infinite or NaN if any of them is (or, past the float range, when none is: then the block path takes the pass)
        checks = [f"checked = {' + '.join(self.checked)}\nif checked - checked != 0.0:\n    break"] if self.checked else []
        finish = [*self.store, *self.finish, *(["state.motion_seen = True"] if self.finish else [])]
        start = [*self.reads, "count = counts.get(count_key, 0)" if self.counter == "count" else "iterations = loop_frame.iterations",
                 "modal, base, passes, blocks = state.modal, state.position, 0, interpreter.blocks_run", "p0, p1, p2 = base.get(k0), base.get(k1), base.get(k2)"]
        body = ["try:\n" + _indented(self.steps or ["pass"], 1) + "except (ArithmeticError, ValueError):\n    break",
                *checks, *self.tests, *self.limit, *self.effects, "passes += 1"]
        return ("def make(ABSENT, Segment, c, n, f, k):\n" + unpack
                + "    def run(interpreter, state, local, global_, gathered, feed, counts, count_key, loop_frame, bound, budget, hand_on, observer):\n"
                + _indented(start, 2) + "        while True:\n" + _indented(body, 3) + "        if passes:\n" + _indented(finish, 3)
                + "        return passes\n    return run\n")


def _indented(lines: list[str], depth: int) -> str:
    return "".join("    " * depth + row + "\n" for line in lines for row in line.split("\n"))


_ABSENT = object()  # not in a variable table


class _GatheredMove:
    """A move of a compiled pass among the interpreter's gathered moves (their layout:
    ``interpreter._GATHERED_FIELDS``): its Segment and end position are made only when
    asked for, from the numbers the pass gathered and the stretch's base."""

    __slots__ = ("kind", "span", "block", "axes")

    def __init__(self, kind: str, span, block, axes: list):
        self.kind, self.span, self.block = kind, span, block
        self.axes = [(axis, RUN_AXES.index(axis)) for axis in axes]  # the pass's X, Y, Z and their fields

    def position(self, move: tuple) -> dict:
        """Where ``move`` (gathered by this move of the pass) ends, as the block path has it."""
        return {**move[-1], **{axis: move[column] for axis, column in self.axes}}

    def segment(self, start: dict, end: dict) -> Segment:
        return Segment(self.kind, start, end, self.span, self.block, "programmed", None, None)
