"""Lowering of Fagor 8060/8065 programs to IR blocks.

Plain ISO words go to the ISO lowering (:class:`~ncverify.lower.iso.IsoLowering`) with the
Fagor code table (``dialects/fagor/mill.toml``). This module adds what Fagor does
differently:

- **cycle blocks**: the letters a cycle declares (``dialects/fagor/cycles.toml``) are its
  parameters, not axes, offsets, M functions, speeds or tools (``G87 ... M1 D2``,
  ``G160 ... S3 T5``); the tool-axis word is the reference plane and is filed as ``Z``. The
  definition op goes before the block's move, so ``G1 X200 Y200 G83 ..`` moves first and
  then machines with the new cycle (seed L664-672);
- **what cancels a cycle** besides G80 and another cycle: a new plane, G20, ``#TOOL AX``,
  G74 (seed L597-611);
- **flow statements** ``$IF/$ELSEIF/$ELSE/$ENDIF``, ``$WHILE``, ``$DO``, ``$FOR``,
  ``$SWITCH/$CASE/$DEFAULT``, ``$BREAK``, ``$CONTINUE``, ``$GOTO``, ``(RPT N10, N20)``,
  lowered to jumps. A statement's partner lines are found from the program text when the
  jump runs: the jump target is a machine value (:meth:`FagorLowering.partner`) that
  resolves to the label ``@15`` of the partner line;
- **calls** ``#CALL``, ``#PCALL`` (a new level of local parameters, its A-Z arguments
  set P0-P25), local subroutines
  ``%L NAME`` ending with ``M17``/``M29``/``#RET``; ``#MCALL`` / ``#MDOFF`` (see
  :meth:`FagorLowering._modal_call`).

A cycle block's meaning depends on the plane, ``#TOOL AX`` and ``#LATHECY``/``#MILLCY`` in
force: it is lowered when it runs (see :class:`FagorLowering`).
"""
from __future__ import annotations

import dataclasses
import re
from functools import cache

from .. import ir
from ..cycle_models import load_cycle_table
from ..dialect import DialectSetup
from ..read.fagor import FagorLine, Statement, read_fagor_line
from ..read.iso import ReadBlock
from ..source import Span, decode_line, letter_led, lines_holding, search_any
from ..tables import CodeTable, _load, code_key
from ..values import VACANT
from . import modal_call
from .iso import IsoFrontend, IsoLowering, fast_motion_block

_PLANE_NORMAL = {"xy": "Z", "zx": "Y", "yz": "X"}
_PLANE_AXES = {"xy": ("X", "Y"), "zx": ("Z", "X"), "yz": ("Y", "Z")}
_TURNING_CODES = {f"{n}" for n in range(81, 89)}
_NO_EFFECT_INSTRUCTIONS = {"HSC", "ROUNDPAR", "MSG", "WARNING", "WAIT", "FLUSH", "SYNC", "TIME", "DSBLK", "ESBLK", "SVON",
                           "SVOFF", "TSYNC", "SELECT", "EXBLK", "MEXEC", "EXEC", "FEED", "ABORT", "CONTJOG", "COMMENT"}
_PCALL_PARAMETERS = {letter: f"P{index}" for index, letter in enumerate("ABCDEFGHIJKLMNOPQRSTUVWXYZ")}
_REPEAT_COPIES = 1000  # outside a cycle's zone, NR up to this count copies the move op
SWITCH_VALUE = "$SWITCH"


def _hole_cycle_modal(state) -> float:
    return 0.0 if state.cycle is None else 1.0


_IN_CYCLE_ZONE = ir.MachineValue("a hole cycle is modal (1) or not (0)", _hole_cycle_modal)


def _repeat_end(state):
    return state.fagor.repeat_end


_REPEAT_END = ir.MachineValue("the label of the last block of the RPT running", _repeat_end)
_MODAL_CALL_ARGUMENTS = re.compile(rb'(?im)#MCALL[ \t]+(?:"[^"\n]*"|[^\s;]+)([^\n;]*)')


@cache  # the tables are read-only: parse the TOML once per process, like iso_table
def fagor_table(machine: str = "mill") -> CodeTable:
    data = _load("fagor", "mill.toml")
    cycles = load_cycle_table("fagor")
    settings = dict(data.get("settings", {}))
    settings.update(data.get("conventions", {}))
    return CodeTable("fagor-8065", machine, dict(data["g"]), dict(data["m"]), dict(data["words"]), dict(data["power_on"]), settings, cycles)


class FagorLowering(IsoLowering):
    """Lowers :class:`FagorLine` objects. What a cycle block means depends on the plane,
    ``#TOOL AX`` and the cycle set in force when it runs: such a block is lowered at run
    time (:class:`ir.DialectDeferred`, resolved with the plane and the typed Fagor state of
    the path, :class:`ncverify.interpret.fagor.FagorState`), so that loops, calls and forked
    paths each see their own."""

    def __init__(self, table: CodeTable):
        super().__init__(table, 0.0)
        self.lathe_turning_default = table.machine == "lathe" and bool(table.settings.get("lathe_machine_turning_cycles", True))
        self.uses_rpt = False
        self.uses_modal_call = False
        self.modal_call_letters: list[str] = []  # the argument letters any #MCALL of the program passes
        self._structures: dict[int, tuple[object, dict]] = {}

    @property
    def reads_every_block(self) -> bool:
        """RPT and #MCALL add ops to plain motion blocks: no batch reading then."""
        return self.uses_rpt or self.uses_modal_call

    def _dwell_seconds(self, rest: dict):
        """``G4 K0.5``: Fagor dwells are seconds in K (§12, uncertain); other forms as in ISO."""
        word = rest.pop("K", None)
        return word.value if word is not None else super()._dwell_seconds(rest)

    def partner(self, kind: str, line: int) -> ir.MachineValue:
        """Where a jump of the flow statement in ``line`` lands (``kind``: next, end, exit,
        head, break, continue): the label of its partner line, found from the text of the
        program the path runs when the jump runs (see :func:`program_structure`)."""
        key = f"{kind}:{line}"

        def label(state) -> str:
            return self._structure(state.call_stack[-1].source.buffer).get(key, f"@?{key}")

        return ir.MachineValue(f"the {kind} partner of the flow statement in line {line}", label)

    def _structure(self, buffer) -> dict:
        cached = self._structures.get(id(buffer))
        if cached is None or cached[0] is not buffer:
            cached = (buffer, program_structure(buffer))
            self._structures[id(buffer)] = cached
        return cached[1]

    # ------------------------------------------------------------------ one line

    def lower_line(self, line: FagorLine, path: str | None) -> list[ir.Block]:
        block = ir.Block(line.line, line.start + 1, max(line.end, line.start) + 1, [], label=line.label, skippable=line.skip)
        block.comments = tuple((text, Span.on_line(line.line, start, end, path)) for text, start, end in line.comments)
        block.program_start = line.program_start
        if line.problem is not None:
            problem = line.problem
            block.notes.append(ir.Note("core.syntax", problem.message, Span(line.line, problem.start + 1, line.line, problem.end + 1, path)))
            return [block]
        if line.statement is not None:
            return self._statement(block, line.statement, line, path)
        if line.words:
            block = self._words(block, line, path)
        self._extras(block, line, path)
        if self.uses_modal_call and modal_call.moves(_with_repeats(block.ops)):
            block.ops.append(self._modal_subroutine_call(block.span))
        if self.uses_rpt and isinstance(block.label, float):
            condition = ir.Binary("EQ", _REPEAT_END, block.label)
            block.ops.append(ir.Conditional(block.span, condition, [ir.Return(block.span, local_only=True)]))
        return [block]

    # ------------------------------------------------------------------ address words

    def _words(self, block: ir.Block, line: FagorLine, path) -> ir.Block:
        cycle_word, _entry = self._cycle_code(line.words)
        if cycle_word is None:
            ops, notes = self._word_ops(line, path, None)
            block.ops.extend(ops)
            block.notes.extend(notes)
            return block

        def resolve(plane: str, fagor) -> tuple[list, list]:
            return self._word_ops(line, path, self._setting(plane, fagor))

        block.ops.append(ir.DialectDeferred(self._span(line, cycle_word.start, cycle_word.end, path), resolve))
        return block

    def _setting(self, plane: str, fagor) -> tuple:
        """(plane, tool axis or None, turning cycles) where the block runs; ``fagor`` is the
        path's :class:`~ncverify.interpret.fagor.FagorState`."""
        turning = not fagor.mill_cycles if self.lathe_turning_default else fagor.lathe_cycles
        return plane, fagor.tool_axis, turning

    def _word_ops(self, line: FagorLine, path, setting) -> tuple[list, list]:
        words = list(line.words)
        notes: list = []
        cycle_op = None
        if setting is not None:
            cycle_word, entry = self._cycle_code(words)
            words.remove(cycle_word)
            cycle_op = self._cycle_op(notes, line, words, cycle_word, entry, path, setting)
        read = ReadBlock(line.line, line.start, line.end, words, [], line.skip)
        lowered = self.lower(read, path) if words else ir.Block(line.line, line.start + 1, line.end + 1, [])
        ops = self._cancel_cycle_where_the_control_does(lowered.ops)
        self._length_with_tool(ops)
        if cycle_op is not None:
            self._insert_cycle(ops, cycle_op)
        if line.repeat is not None:
            self._repeat(ops, notes, line, path)
        return ops, lowered.notes + notes

    def _cycle_code(self, words):
        found = (None, None)
        for word in words:
            if word.letter == "G" and isinstance(word.value, float):
                entry = self.table.g_code(word.value)
                if entry is not None and entry["effect"] in ("cycle", "cycle_call"):
                    found = (word, entry)
        return found

    def _cycle_op(self, notes, line, words, cycle_word, entry, path, setting) -> ir.Op:
        plane, tool_axis, turning = setting
        span = self._span(line, cycle_word.start, cycle_word.end, path)
        code = code_key(cycle_word.value)
        if turning and code in _TURNING_CODES:
            words[:] = [word for word in words if word.letter in "NFSTM"]
            return ir.CycleCall(span, "fagor.turning", {"G": float(code)})
        model = self.table.cycles[entry["cycle"]]
        declared = model.params
        pattern = model.pattern is not None
        normal = _PLANE_NORMAL[plane]
        axis, sign = tool_axis or (normal, "+")
        if not pattern and axis != normal:
            named = "of a secondary axis (X2, U...)" if axis == "?" else f"[{axis}{sign}], an axis in the plane whose normal is {normal}"
            notes.append(ir.Note("core.unsupported-code", f"G{code} along the #TOOL AX {named}: cycles along a tool axis other than the plane's "
                                                                 "normal are not modelled", span))
            words[:] = [word for word in words if word.letter in "NFSTM" and word.letter not in declared]
            return ir.Unsupported(span, f"G{code} along another tool axis", ("position",))
        in_plane = () if pattern else _PLANE_AXES[plane]
        params, spans = {}, {}
        for word in list(words):
            letter = word.letter
            name = "Z" if letter == normal and not pattern else letter
            if letter in in_plane or name not in declared or letter in "GN":
                continue
            if name in params:
                notes.append(ir.Note("core.duplicate-address", f"G{code}: {letter} appears twice in the cycle block; it is the cycle's "
                                                                     f"{declared[name].meaning}, not a {letter} function (the control alarms or uses one of them)",
                                           self._span(line, word.start, word.end, path)))
                words.remove(word)
                continue
            words.remove(word)
            params[name] = word.value
            spans[name] = self._span(line, word.start, word.end, path)
        if entry["effect"] == "cycle_call":
            return ir.CycleCall(span, entry["cycle"], params, spans)
        return ir.CycleDefine(span, entry["cycle"], params, spans, -1.0 if sign == "-" else 1.0)

    @staticmethod
    def _insert_cycle(ops: list, cycle_op: ir.Op) -> None:
        """Before the block's move (it positions, then machines with this cycle), else
        before any stop or call."""
        for index, op in enumerate(ops):
            if isinstance(op, (ir.Move, ir.Stop, ir.Call, ir.Return)):
                ops.insert(index, cycle_op)
                return
        ops.append(cycle_op)

    @staticmethod
    def _length_with_tool(ops: list) -> None:
        """Fagor applies the new tool's length offset with the tool change; D selects which
        of the tool's own offsets (length and radius together), not a shared register: no
        G43 is needed (§12, uncertain)."""
        for index, op in enumerate(ops):
            if isinstance(op, ir.ToolChange):
                ops.insert(index + 1, ir.LengthOffset(op.span, "with_tool", None))  # not an ISO G43: no Z jump
                return

    @staticmethod
    def _cancel_cycle_where_the_control_does(ops: list) -> list:
        """A new plane, G20, G74, M02 or M30 ends the cycle (seed L597-611): the program end
        leaves no cycle for the next program."""
        result = []
        for op in ops:
            if isinstance(op, ir.Stop) and op.kind == "end":
                result.append(ir.CycleCancel(op.span))
            if isinstance(op, ir.SetModal) and op.group == "plane":
                result.append(ir.CycleCancel(op.span, op.value))
            elif isinstance(op, ir.Home) or isinstance(op, ir.Unsupported) and op.what.startswith("G20 "):
                result.append(ir.CycleCancel(op.span))
            result.append(op)
        return result

    # ------------------------------------------------------------------ assignments, NR, X2=, RPT

    def _extras(self, block: ir.Block, line: FagorLine, path) -> None:
        for assignment in line.assignments:
            span = self._span(line, assignment.start, assignment.end, path)
            name = assignment.target.name
            if isinstance(name, str) and name.startswith("V.C.") and len(name) == 5:
                block.ops.append(ir.CycleDefine(span, "", {name[-1]: assignment.value, "$rule": "fagor.cycle-data-without-cycle"}, {name[-1]: span}))
            else:
                block.ops.append(ir.Assign(span, assignment.target, assignment.value))
        if line.repeat is not None and not line.words:
            self._repeat(block.ops, block.notes, line, path)
        for name, start, end in line.indexed_axes:
            span = self._span(line, start, end, path)
            if name == "G159":  # G159=n: the n-th zero offset of the table (the form beside G159 with its number)
                block.ops.append(ir.WorkOffset(span, "G159 (a numbered zero offset)"))
                continue
            block.notes.append(ir.Note("core.unsupported-code", f"axis {name} (an axis with a numeric suffix) is read but not modelled", span))
            block.ops.append(ir.Unsupported(span, f"axis {name}", ("position",)))
        if line.rpt is not None:
            first, last, count, start, end = line.rpt
            block.ops.extend(self._repeat_blocks(self._span(line, start, end, path), first, last, count))

    def _repeat(self, ops: list, notes: list, line: FagorLine, path) -> None:
        """NR n repeats the block's move n times. In a cycle's zone the cycle runner repeats
        the hole (so each hole knows its repeat count: ``NR3`` in G90 drills one hole three
        times); outside it the move is copied (``NR0`` and counts that are computed or above
        the copy limit stay on the move as the word ``NR``)."""
        value, start, end = line.repeat
        at = next((index for index in range(len(ops) - 1, -1, -1) if isinstance(ops[index], ir.Move)), None)
        if at is None:
            notes.append(ir.Note("fagor.repeat-without-motion", "NR repeats a block's move (and the cycle at its end): this block has no move, so NR does nothing",
                                 self._span(line, start, end, path)))
            return
        move = ops[at]
        counted = dataclasses.replace(move, words={**move.words, "NR": value}, word_columns={**move.word_columns, "NR": (start, end)})
        copyable = type(value) is float and value == int(value) and 1 <= value <= _REPEAT_COPIES
        if not copyable or any(isinstance(op, ir.CycleDefine) for op in ops):
            ops[at] = counted
            return
        ops[at : at + 1] = [ir.Conditional(move.span, ir.Binary("EQ", _IN_CYCLE_ZONE, 1.0), [counted]),
                            ir.Conditional(move.span, ir.Binary("EQ", _IN_CYCLE_ZONE, 0.0), [dataclasses.replace(move) for _ in range(int(value))])]

    @staticmethod
    def _repeat_blocks(span: Span, first, last, count) -> list[ir.Op]:
        """``(RPT N10, N20)``: run N10 to N20 as a local subroutine; the block labelled
        with the last number returns while the repeat runs."""
        return [ir.RepeatEnd(span, last), ir.Call(span, "local", first, count), ir.RepeatEnd(span, None)]

    # ------------------------------------------------------------------ statements

    def _statement(self, block: ir.Block, statement: Statement, line: FagorLine, path) -> list[ir.Block]:
        span = self._span(line, statement.start, statement.end, path)
        if statement.flow:
            return _FLOW.get(statement.keyword, _unknown_flow)(self, block, statement, span, line.line)
        handler = _INSTRUCTIONS.get(statement.keyword)
        if handler is not None:
            handler(self, block, statement, span)
        elif statement.keyword not in _NO_EFFECT_INSTRUCTIONS:
            block.notes.append(ir.Note("core.unsupported-code", f"#{statement.keyword} is read but not modelled; checks that depend on its effect answer unknown", span))
            block.ops.append(ir.Unsupported(span, f"#{statement.keyword}", ("position", "state")))
        return [block]

    # ---- # instructions

    def _call(self, block, statement, span) -> None:
        """#CALL runs the subroutine on the caller's local parameters; #PCALL opens a new
        level whose P0-P25 are the A-Z arguments (§12, uncertain; unset ones are vacant)."""
        name, *arguments = statement.args
        if statement.keyword == "CALL":
            block.ops.append(ir.Call(span, "subprogram", name))
            return
        values = {_PCALL_PARAMETERS[letter]: value for letter, value in arguments}
        block.ops.append(ir.Call(span, "macro", name, 1.0, values))

    def _modal_call(self, block, statement, span) -> None:
        """``#MCALL NAME A.. B..`` makes NAME a modal subroutine: it runs, with the arguments as
        ``#PCALL`` passes them (evaluated here, on a new level of local parameters), after
        every block that moves an axis, until ``#MDOFF`` or the next ``#MCALL`` (general
        8060/8065 knowledge, reference §12: uncertain). Not at the ``#MCALL`` block itself,
        not after the moves of the modal subroutine, and not after a block that defines a
        canned cycle (its moves are resolved when it runs)."""
        name, *arguments = statement.args
        written = dict(arguments)
        block.ops.append(modal_call.switch_on(span, name, written, self.modal_call_letters, VACANT))

    def _error(self, block, statement, span) -> None:
        """``#ERROR ["text"]``: the program stops with its own error message (a guard exit
        when it is reached only for some inputs)."""
        message = statement.text.strip().strip("[]").strip().strip('"')
        block.ops.append(ir.Alarm(span, 0.0, message, "an error with #ERROR"))

    def _modal_call_off(self, block, statement, span) -> None:
        block.ops.append(ir.ModalCallOff(span))

    def _modal_subroutine_call(self, span: Span) -> ir.ModalCallRun:
        return ir.ModalCallRun(span, "macro", {_PCALL_PARAMETERS[letter]: letter for letter in self.modal_call_letters})

    def _tool_axis(self, block, statement, span) -> None:
        match = re.fullmatch(r"(?i)AX\s*\[\s*([A-Z])(\d*)\s*([+-]?)\s*\]", statement.text)
        block.ops.append(ir.CycleCancel(span))
        axis = match.group(1).upper() if match is not None and not match.group(2) else "?"
        direction = "-" if match is not None and match.group(3) == "-" else "+"
        block.ops.append(ir.ToolAxis(span, axis if axis in "XYZ" else "?", direction))

    def _cycle_set(self, block, statement, span) -> None:
        on = statement.text.upper().startswith("ON")
        block.ops.append(ir.CycleSet(span, statement.keyword == "LATHECY", on))

    def _return(self, block, statement, span) -> None:
        block.ops.append(ir.Return(span))

    # ---- $ flow statements (labels "@line" mark the lines a jump lands on)

    def _if(self, block, statement, span, line):
        block.label = f"@{line}"
        block.ops.append(ir.Jump(span, self.partner("next", line), _negated(statement.args)))
        return [block]

    def _else_if(self, block, statement, span, line):
        leave = ir.Block(line, block.start_column, block.end_column, [ir.Jump(span, self.partner("end", line))])
        block.label = f"@{line}"
        block.ops.append(ir.Jump(span, self.partner("next", line), _negated(statement.args)))
        return [leave, block]

    def _else(self, block, statement, span, line):
        leave = ir.Block(line, block.start_column, block.end_column, [ir.Jump(span, self.partner("end", line))])
        block.label = f"@{line}"
        return [leave, block]

    def _landing(self, block, statement, span, line):
        block.label = f"@{line}"
        return [block]

    def _while(self, block, statement, span, line):
        block.label = f"@{line}"
        block.ops.append(ir.Jump(span, self.partner("exit", line), _negated(statement.args)))
        return [block]

    def _loop_end(self, block, statement, span, line):
        condition = statement.args[0] if statement.args else None
        back = ir.Block(line, block.start_column, block.end_column, [ir.Jump(span, self.partner("head", line), condition)], label=f"@{line}#c")
        block.label = f"@{line}"
        return [back, block]

    def _for(self, block, statement, span, line):
        target, start, end, *step = statement.args
        step = step[0] if step else 1.0
        if type(step) is not float or step == 0:
            block.notes.append(ir.Note("core.unsupported-code", "$FOR with a step that is zero or computed is not modelled", span))
            block.ops.append(ir.Unsupported(span, "$FOR with a computed step"))
            return [block]
        init = ir.Block(line, block.start_column, block.end_column, [ir.Assign(span, target, start), ir.Jump(span, f"@{line}#t")], label=block.label)
        advance = ir.Block(line, block.start_column, block.end_column, [ir.Assign(span, target, ir.Binary("+", target, step))], label=f"@{line}#s")
        passed = ir.Binary("GT" if step > 0 else "LT", target, end)
        test = ir.Block(line, block.start_column, block.end_column, [ir.Jump(span, self.partner("exit", line), passed)], label=f"@{line}#t")
        return [init, advance, test]

    def _switch(self, block, statement, span, line):
        if not statement.args:
            block.notes.append(ir.Note("core.syntax", "$SWITCH needs the value to compare: $SWITCH P1", span))
            return [block]
        block.ops.extend([ir.Assign(span, ir.Var(SWITCH_VALUE), statement.args[0]), ir.Jump(span, self.partner("next", line))])
        return [block]

    def _case(self, block, statement, span, line):
        if not statement.args:
            block.notes.append(ir.Note("core.syntax", "$CASE needs the value or values it matches: $CASE 1, 2", span))
            return [block]
        into_body = ir.Block(line, block.start_column, block.end_column, [ir.Jump(span, f"@{line}#b")])
        matches = None
        for value in statement.args:
            equal = ir.Binary("EQ", ir.Var(SWITCH_VALUE), value)
            matches = equal if matches is None else ir.Binary("OR", matches, equal)
        block.label = f"@{line}"
        block.ops.append(ir.Jump(span, self.partner("next", line), ir.Binary("EQ", matches, 0.0)))
        body = ir.Block(line, block.start_column, block.end_column, [], label=f"@{line}#b")
        return [into_body, block, body]

    def _goto(self, block, statement, span, line):
        if len(statement.args) != 1:
            block.notes.append(ir.Note("core.syntax", "$GOTO takes one label (N10 or [NAME])", span))
            return [block]
        block.ops.append(ir.Jump(span, statement.args[0]))
        return [block]

    def _rpt(self, block, statement, span, line):
        if len(statement.args) not in (2, 3):
            block.notes.append(ir.Note("core.syntax", "$RPT takes two labels and an optional count: $RPT N10, N20, 3", span))
            return [block]
        first, last, *count = statement.args
        block.ops.extend(self._repeat_blocks(span, first, last, count[0] if count else 1.0))
        return [block]


def _with_repeats(ops: list):
    """The block's ops, with the moves of an ``NR`` repeat (see ``FagorLowering._repeat``)."""
    for op in ops:
        yield from op.then if isinstance(op, ir.Conditional) else (op,)


def _negated(args: list) -> ir.Expr:
    return ir.Binary("EQ", args[0], 0.0) if args else 0.0


def _unknown_flow(lowering, block, statement, span, line):
    block.notes.append(ir.Note("core.unsupported-code", f"${statement.keyword} is read but not modelled; the rest of this path answers unknown", span))
    block.ops.append(ir.Unsupported(span, f"${statement.keyword}", ("position",)))
    return [block]


_FLOW = {
    "IF": FagorLowering._if, "ELSEIF": FagorLowering._else_if, "ELSE": FagorLowering._else, "ENDIF": FagorLowering._landing,
    "WHILE": FagorLowering._while, "ENDWHILE": FagorLowering._loop_end, "DO": FagorLowering._landing,
    "ENDDO": FagorLowering._loop_end, "FOR": FagorLowering._for, "ENDFOR": FagorLowering._loop_end,
    "SWITCH": FagorLowering._switch, "CASE": FagorLowering._case, "DEFAULT": FagorLowering._landing,
    "ENDSWITCH": FagorLowering._landing, "GOTO": FagorLowering._goto, "RPT": FagorLowering._rpt,
    "RET": lambda lowering, block, statement, span, line: (block.ops.append(ir.Return(span)), [block])[1],
}
_INSTRUCTIONS = {
    "CALL": FagorLowering._call, "PCALL": FagorLowering._call, "MCALL": FagorLowering._modal_call,
    "MDOFF": FagorLowering._modal_call_off, "TOOL": FagorLowering._tool_axis, "ERROR": FagorLowering._error,
    "LATHECY": FagorLowering._cycle_set, "MILLCY": FagorLowering._cycle_set, "RET": FagorLowering._return,
}


def _break(lowering, block, statement, span, line):
    block.ops.append(ir.Jump(span, lowering.partner("break", line)))
    return [block]


def _continue(lowering, block, statement, span, line):
    block.ops.append(ir.Jump(span, lowering.partner("continue", line)))
    return [block]


_FLOW["BREAK"] = _break
_FLOW["CONTINUE"] = _continue


# ---------------------------------------------------------------------- program structure

_STRUCTURE = re.compile(rb"(?im)^[ \t]*/?[ \t]*(?:N\d+[ \t]*)?\$(ELSEIF|ELSE|ENDIF|IF|ENDWHILE|WHILE|ENDDO|DO|ENDFOR|FOR|ENDSWITCH|SWITCH|CASE|DEFAULT|BREAK|CONTINUE)(?![A-Z0-9_])")
_LOOPS = {"WHILE": "ENDWHILE", "DO": "ENDDO", "FOR": "ENDFOR"}
_RPT, _RPT_WORD = letter_led(rb"RPT"), re.compile(rb"(?i)\bRPT\b")
_SUBROUTINE_HEADER = re.compile(rb"(?im)^[ \t]*%[ \t]*L[ \t]+([A-Za-z0-9_.]+)")
# the keywords of the lines _STRUCTURE and _SUBROUTINE_HEADER match (see source.lines_holding)
_DOLLAR, _PERCENT = re.compile(rb"\$"), re.compile(rb"%")


def program_structure(buffer) -> dict[str, str]:
    """``"next:12" -> "@15"``: where each flow statement's jumps land, from the text.
    Unmatched statements map to ``"@?<what>"`` (a label no line has: the jump reports it)."""
    buffer = bytes(buffer)
    targets: dict[str, str] = {}
    stack: list[list] = []  # [keyword, line, last branch line]
    line, counted = 1, 0
    for match in lines_holding(buffer, _DOLLAR, _STRUCTURE):
        line += buffer.count(b"\n", counted, match.start())
        counted = match.start()
        keyword = match.group(1).decode().upper()
        if keyword in ("IF", "SWITCH") or keyword in _LOOPS:
            stack.append([keyword, line, line])
            continue
        if keyword in ("BREAK", "CONTINUE"):
            enclosing = next((frame for frame in reversed(stack) if frame[0] in _LOOPS or (keyword == "BREAK" and frame[0] == "SWITCH")), None)
            targets[f"{keyword.lower()}:{line}"] = f"@?{keyword}:{line}" if enclosing is None else f"&{'exit' if keyword == 'BREAK' else 'continue'}:{enclosing[1]}"
            continue
        opener = {"ELSEIF": "IF", "ELSE": "IF", "ENDIF": "IF", "CASE": "SWITCH", "DEFAULT": "SWITCH", "ENDSWITCH": "SWITCH"}.get(keyword)
        opener = opener or next(loop for loop, end in _LOOPS.items() if end == keyword)
        if not stack or stack[-1][0] != opener:
            continue  # a stray closing line: its own jumps report it
        frame = stack[-1]
        if opener in ("IF", "SWITCH"):
            targets[f"next:{frame[2]}"] = f"@{line}"
            frame[2] = line
            if keyword in ("ENDIF", "ENDSWITCH"):
                stack.pop()
                for branch_line in frame[3:]:
                    targets[f"end:{branch_line}"] = f"@{line}"
                targets[f"end:{frame[1]}"] = f"@{line}"
                targets[f"exit:{frame[1]}"] = f"@{line}"
            else:
                frame.append(line)
            continue
        stack.pop()
        head = frame[1]
        targets[f"exit:{head}"] = f"@{line}"
        targets[f"head:{line}"] = f"@{head}#s" if opener == "FOR" else f"@{head}"
        targets[f"continue:{head}"] = {"FOR": f"@{head}#s", "WHILE": f"@{head}", "DO": f"@{line}#c"}[opener]
    for key, value in list(targets.items()):
        if value.startswith("&"):
            targets[key] = targets.get(value[1:], f"@?{key}")
    return targets


_MISSING_PARTNERS = {"next": "$ELSEIF/$ELSE/$ENDIF (or next $CASE/$DEFAULT/$ENDSWITCH)", "end": "$ENDIF/$ENDSWITCH",
                     "exit": "loop end ($ENDWHILE/$ENDFOR/$ENDDO)", "head": "loop start ($WHILE/$FOR/$DO)",
                     "break": "loop or $SWITCH", "continue": "loop"}


def _has_code(text) -> bool:
    """Does the text hold a block, not only blank and comment lines?"""
    return re.search(rb"(?m)^[ \t]*[^;\s]", text) is not None


class FagorFrontend:
    """What the interpreter asks of the Fagor dialect (see :mod:`ncverify.dialect`)."""

    dialect = "fagor"

    def __init__(self, lowering: FagorLowering):
        self.lowering = lowering
        self.paren_comments = bool(lowering.table.settings.get("paren_comments", True))
        self.local_parameters = int(lowering.table.settings.get("local_parameters", 26))
        self._line_starts: dict[int, tuple[object, list]] = {}
        self._plain = IsoFrontend(lowering)  # plain motion blocks read as in ISO

    def blocks(self, raw: bytes, line: int, path: str | None) -> list[ir.Block]:
        if not self.lowering.reads_every_block:
            block = fast_motion_block(raw, line, path, self._plain.fast_form)
            if block is not None:
                return [block]
        text = decode_line(raw)
        return self.lowering.lower_line(read_fagor_line(text, line, self.paren_comments), path)

    def is_plain(self, raw: bytes) -> bool:
        """Plain motion (``[N..] [G0-G3] X.. Y.. Z.. [F..]``) is the same as in ISO: the
        ISO batch reader takes it (not in a program that repeats labelled blocks with RPT,
        whose labelled blocks carry a return, nor in one with #MCALL, whose moves carry the
        modal call)."""
        return not self.lowering.reads_every_block and self._plain.is_plain(raw)

    def plain_run(self, buffer, offset: int, line: int, limit: int = 1 << 20):
        return None if self.lowering.reads_every_block else self._plain.plain_run(buffer, offset, line, limit)

    # ---- programs: "%L NAME" local subroutines; the rest is the main program

    def programs(self, buffer) -> list[tuple[str, int]]:
        if search_any(buffer, _RPT) and _RPT_WORD.search(buffer):  # the letters alone are found several times faster
            self.lowering.uses_rpt = True
        modal_calls = [match.group(1).upper() for match in _MODAL_CALL_ARGUMENTS.finditer(buffer)]
        if modal_calls:
            self.lowering.uses_modal_call = True
            letters = {letter.decode() for rest in modal_calls for letter in re.findall(rb"([A-Z])\s*[-+0-9.\[(P#]", rest)}
            self.lowering.modal_call_letters = sorted(letters | set(self.lowering.modal_call_letters))
        found = []
        subroutine_end = re.compile(rb"(?im)^[^;\n]*(?:\bM(?:17|29)(?![0-9])|#RET\b|\$RET\b)[^\n]*\n?")
        position = 0
        main_start = None
        for match in lines_holding(buffer, _PERCENT, _SUBROUTINE_HEADER):
            if main_start is None and _has_code(buffer[position : match.start()]):
                main_start = position
            found.append((match.group(1).decode(), match.start()))
            end = subroutine_end.search(buffer, match.end())
            position = end.end() if end else len(buffer)
        if found and main_start is None and _has_code(buffer[position:]):
            main_start = position
        if main_start is not None:
            found.append(("main", main_start))
        return sorted(found, key=lambda item: item[1])

    def is_subprogram(self, buffer, start: int, end: int) -> bool:
        return re.match(rb"[ \t]*%[ \t]*L[ \t]", bytes(buffer[start : start + 64])) is not None

    def tape_marks(self, buffer) -> list[int]:
        return []

    def program_name(self, number) -> str:
        return number if isinstance(number, str) else f"{number:g}"

    # ---- labels

    def label_offsets(self, buffer, label):
        if isinstance(label, str) and label.startswith("@"):
            number = re.match(r"@(\d+)", label)
            starts = self._starts(buffer)
            if number is not None and int(number.group(1)) <= len(starts):
                yield starts[int(number.group(1)) - 1]
            return
        if isinstance(label, str):
            pattern = rb"(?mi)^[ \t]*/?[ \t]*(?:N\d+[ \t]*)?\[" + re.escape(label.encode()) + rb"\]"
        else:
            pattern = rb"(?mi)^[ \t]*/?[ \t]*N0*" + str(int(label)).encode() + rb"(?![0-9.])"
        for match in re.finditer(pattern, buffer):
            yield match.start()

    def describe_label(self, label) -> str:
        if isinstance(label, str) and label.startswith("@?"):
            what, _, line = label[2:].partition(":")
            partner = _MISSING_PARTNERS.get(what, "statement")
            return f"the {partner} that belongs to the flow statement in line {line} (there is none)"
        if isinstance(label, str) and label.startswith("@"):
            return f"the flow statement in line {label[1:]}"
        if isinstance(label, str):
            return f"label [{label}]"
        return f"block N{label:g}"

    def _starts(self, buffer) -> list[int]:
        cached = self._line_starts.get(id(buffer))
        if cached is None or cached[0] is not buffer:
            starts = [0] + [match.end() for match in re.finditer(rb"\n", buffer)]
            cached = (buffer, starts)
            self._line_starts[id(buffer)] = cached
        return cached[1]

    # ---- variables

    def variable_scope(self, name: str) -> str:
        """P0-P25 belong to the subroutine level (configurable); the rest are global."""
        if name[:1] == "P" and name[1:].isdigit() and int(name[1:]) < self.local_parameters:
            return "local"
        return "global"

    @staticmethod
    def machine_data(name: str) -> tuple[str, bool] | None:
        """Any ``V.`` system variable but a canned cycle's parameters (``V.C.``): what the
        machine's variables hold the model does not follow once the program moves (see
        :meth:`~ncverify.interpret.Interpreter.unfollowed`)."""
        if name.upper().startswith("V.") and not name.upper().startswith("V.C."):
            return "machine data", False
        return None

    def system_variable(self, name: str, state):
        if name.startswith("$"):
            return 0.0
        if name.startswith("V.C.") and len(name) == 5 and state.cycle is not None:
            return state.cycle_data.get(name[-1])
        return None


def setup(settings, detection, project) -> DialectSetup:
    """The Fagor tables for the machine type (command line > project file > detection)."""
    machine = settings.machine or project.machine.kind or detection.machine or "mill"
    table = fagor_table(machine)
    lowering = FagorLowering(table)
    limits = {name: float(table.settings.get(name, default))
              for name, default in (("d_register_max", 999), ("h_register_max", 999), ("tool_number_max", 99999999))}
    return DialectSetup(FagorFrontend(lowering), table.power_on, table.cycles, "fagor-8065", machine, {}, 0.0, 0.0, limits)
