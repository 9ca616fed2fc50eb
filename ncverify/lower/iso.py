"""Lowering of ISO blocks (Fanuc-style, Mitsubishi E60, Haas) to IR blocks.

What a code means comes from the profile's :class:`~ncverify.tables.CodeTable`; this module
only knows how ISO distributes a block's words among the codes in it (which letters a
G65 call, a G10 data setting or a canned cycle consumes) and the order a block executes in.
"""
from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy

from .. import ir, values
from ..context import tools_called_in
from ..cycle_models import UNKNOWN_CYCLE
from ..dialect import DialectSetup
from ..read.iso import ReadBlock, Statement, Word, read_line
from ..read.iso_runs import read_plain_run_at
from ..source import Span, decode_line, find_all, letter_led, line_start
from ..tables import CodeTable, code_key, iso_table
from ..values import VACANT

# Execution order inside one block (after LinuxCNC's and the ISO manuals' order).
_FEED, _TOOL, _SPINDLE, _DWELL, _MODAL, _OFFSET, _MOTION, _CALL, _STOP = range(9)
_STAGES = 9

_CALL_LETTERS = {"P", "L", "H", "Q"}
_CYCLE_WORDS = {"R", "Q", "P", "L", "K", "F", ",R", ",S", ",I", ",J", "I", "J", "D", "E", "A", "M"}


class IsoLowering:
    """Lowers :class:`ReadBlock` objects for one profile and machine type."""

    def __init__(self, table: CodeTable, least_input_increment: float | None = None):
        self.table = table
        increment = table.settings.get("least_input_increment", 0.0)
        self.increment = increment if least_input_increment is None else least_input_increment
        self.feed_increment = table.settings.get("feed_per_rev_increment", 0.0)
        self.scaled_letters = frozenset(table.words["length"]) | frozenset(table.words["angle"])
        self.axis_letters = frozenset(table.words["axes"])
        self.twins = dict(table.words.get("incremental_twins", {}))
        self.max_m_words = int(table.settings.get("m_words_per_block", 4))
        self.lathe = table.machine == "lathe"

    # ------------------------------------------------------------------ entry point

    def lower(self, read: ReadBlock, path: str | None = None) -> ir.Block:
        block = ir.Block(read.line, read.start + 1, read.end + 1, [], skippable=read.skip)
        self._block, self._path = block, path
        block.comments = tuple((text, Span.on_line(read.line, start, end, path)) for text, start, end in read.comments)
        if read.problem:
            block.notes.append(ir.Note("core.syntax", read.problem.message, self._span(read, read.problem.start, read.problem.end, path)))
            return block
        if read.percent:
            block.tape_mark = True
            return block
        if read.directive:
            block.notes.append(ir.Note("core.unsupported-code", f"'{read.directive}' is a simulator or editor directive, not G-code; ignored (a real control alarms)", block.span))
            return block
        words: list[Word] = []
        for item in read.items:
            if isinstance(item, Statement):
                self._lower_statement(block, item, read, path)
            else:
                words.append(item)
        if words:
            self._lower_words(block, read, words, path)
        return block

    @staticmethod
    def _span(read: ReadBlock, start: int, end: int, path: str | None) -> Span:
        return Span(read.line, start + 1, read.line, end + 1, path)

    # ------------------------------------------------------------------ macro statements

    def _lower_statement(self, block: ir.Block, item: Statement, read: ReadBlock, path) -> None:
        span = self._span(read, item.start, item.end, path)
        kind = item.kind
        if kind == "assign":
            block.ops.append(self._assignment(item.target, item.value, span, block))
        elif kind == "if_goto":
            block.ops.append(ir.Jump(span, item.value, item.condition))
        elif kind == "goto":
            block.ops.append(ir.Jump(span, item.value))
        elif kind == "if_then":
            block.ops.append(ir.Conditional(span, item.condition, [self._assignment(item.target, item.value, span, block)]))
        elif kind == "while":
            block.ops.append(ir.LoopStart(span, item.number, item.condition))
        elif kind == "end":
            block.ops.append(ir.LoopEnd(span, item.number))

    @staticmethod
    def _assignment(target: ir.Var, value: ir.Expr, span: Span, block: ir.Block) -> ir.Op:
        if target.name == "#3000":
            message = block.comments[0][0].strip() if block.comments else ""
            return ir.Alarm(span, value, message)
        return ir.Assign(span, target, value)

    # ------------------------------------------------------------------ address words

    def _lower_words(self, block: ir.Block, read: ReadBlock, words: list[Word], path) -> None:
        stages: list[list[ir.Op]] = [[] for _ in range(_STAGES)]
        codes: list[tuple[dict, Word]] = []
        m_words: list[Word] = []
        rest: dict[str, Word] = {}
        dynamic: list[Word] = []
        for word in words:
            letter = word.letter
            if word.value is None and letter != "G":
                block.notes.append(ir.Note("core.syntax", f"address {letter} has no value", self._span(read, word.start, word.end, path)))
                continue
            if letter == "G":
                if word.value is not None and not isinstance(word.value, float):
                    dynamic.append(word)
                    continue
                entry = self.table.g_code(word.value or 0.0)
                if entry is None:
                    block.notes.append(ir.Note("core.unknown-code", f"G{code_key(word.value or 0.0)} is not a code of this control ({self.table.profile} {self.table.machine}); its effect is not modelled", self._span(read, word.start, word.end, path)))
                    stages[_MOTION].append(ir.Unsupported(self._span(read, word.start, word.end, path), f"G{code_key(word.value or 0.0)}", ("position", "state")))
                    continue
                if word.value is None:
                    block.notes.append(ir.Note("core.bare-g", "a bare 'G' is read as G00: this block moves at rapid", self._span(read, word.start, word.end, path)))
                codes.append((entry, word))
            elif letter == "M":
                if not isinstance(word.value, float):
                    dynamic.append(word)
                    continue
                m_words.append(word)
            elif letter == "N":
                block.label = word.value if isinstance(word.value, float) else None
            elif letter == "O":
                block.program_start = f"O{int(word.value)}" if isinstance(word.value, float) and math.isfinite(word.value) else None
            else:
                if letter in rest:
                    block.notes.append(ir.Note("core.duplicate-address", f"address {letter} appears twice in the block; the control uses one of them (alarm on most controls)", self._span(read, word.start, word.end, path)))
                rest[letter] = word
        if dynamic:
            self._defer(block, read, words, dynamic, path)
            return
        for twin, axis in self.twins.items():
            if twin in rest and axis in rest:
                word = rest[twin]
                block.notes.append(ir.Note("core.duplicate-address", f"{axis} and {twin} both give the {axis} end point; the control uses one of them (alarm on most controls)", self._span(read, word.start, word.end, path)))
        codes = self._last_of_each_group(block, read, codes, path)
        self._lower_m_words(block, read, m_words, stages, rest, path)
        self._lower_codes(block, read, codes, rest, stages, path)
        for stage in stages:
            block.ops.extend(stage)
        corner = rest.get(",R") or rest.get(",C")  # corner rounding or chamfer at this move's end (a tapping cycle's ,R: see _corner_rounding)
        if corner is not None and any(type(op) is ir.Move for op in block.ops):
            block.ops.append(ir.CornerRounding(self._span(read, corner.start, corner.end, path)))

    def _defer(self, block: ir.Block, read: ReadBlock, words: list[Word], dynamic: list[Word], path) -> None:
        """``G#3`` / ``M#5``: lower again once the interpreter knows the values."""

        def resolve(values: tuple[float, ...]) -> tuple[list[ir.Op], list[ir.Note]]:
            substituted = {id(word): value for word, value in zip(dynamic, values)}
            concrete = [
                Word(word.letter, substituted[id(word)], False, word.start, word.end) if id(word) in substituted else word
                for word in words
            ]
            again = ReadBlock(read.line, read.start, read.end, concrete, read.comments, read.skip)
            lowered = self.lower(again, path)
            return lowered.ops, lowered.notes

        span = self._span(read, dynamic[0].start, dynamic[-1].end, path)
        block.ops.append(ir.Deferred(span, tuple(word.value for word in dynamic), resolve))
        block.label = next((w.value for w in words if w.letter == "N" and isinstance(w.value, float)), None)

    def _last_of_each_group(self, block, read, codes, path):
        """Several G codes of one modal group in a block: the last one wins (seed L1386)."""
        by_group: dict[str, tuple[dict, Word]] = {}
        for entry, word in codes:
            group = entry["group"]
            if group != "00" and group in by_group and by_group[group][1].value != word.value:
                earlier = by_group[group][1]
                block.notes.append(ir.Note(
                    "core.same-group-codes",
                    f"G{code_key(earlier.value or 0.0)} and G{code_key(word.value or 0.0)} are in the same modal group; the control keeps only the last, G{code_key(word.value or 0.0)}",
                    self._span(read, earlier.start, word.end, path),
                ))
            by_group[group if group != "00" else f"00-{id(word)}"] = (entry, word)
        kept = {id(word) for _, word in by_group.values()}
        return [(entry, word) for entry, word in codes if id(word) in kept]

    # ------------------------------------------------------------------ M words

    def _lower_m_words(self, block, read, m_words, stages, rest, path) -> None:
        if len(m_words) > self.max_m_words:
            dropped = m_words[: len(m_words) - self.max_m_words]
            block.notes.append(ir.Note(
                "core.too-many-m-codes",
                f"{len(m_words)} M codes in one block; this control takes at most {self.max_m_words} and ignores "
                + ", ".join(f"M{code_key(w.value)}" for w in dropped),
                self._span(read, dropped[0].start, dropped[-1].end, path),
            ))
            m_words = m_words[-self.max_m_words :]
        for word in m_words:
            span = self._span(read, word.start, word.end, path)
            entry = self.table.m_code(word.value)
            if entry is None:
                continue  # machine-specific M codes (clamps, doors, chip conveyor): no modelled effect
            effect = entry["effect"]
            # switching on acts before the block's motion, switching off after it (G1 X10 M5 cuts with the spindle on)
            stage = _STOP if entry.get("state") in ("off", "orient") else _SPINDLE
            if effect == "spindle":
                stages[stage].append(ir.Spindle(span, entry["state"]))
            elif effect == "coolant":
                stages[stage].append(ir.Coolant(span, entry["state"]))
            elif effect == "tool_change":
                stages[_TOOL].append(ir.ToolChange(span))
            elif effect == "stop":
                stages[_STOP].append(ir.Stop(span, entry["kind"], tuple(entry.get("resets", ()))))
            elif effect == "call":
                stages[_CALL].append(self._call(entry["kind"], span, rest, read, path))
            elif effect == "return":
                target = self._pop(rest, "P")
                stages[_STOP].append(ir.Return(span, target))

    def _call(self, kind: str, span: Span, rest: dict, read, path) -> ir.Call:
        program = self._pop(rest, "P")
        repeat = self._pop(rest, "L", 1.0)
        start = self._pop(rest, "H") if kind == "subprogram" else None
        if program is None:
            program = -1.0
        return ir.Call(span, kind, program, repeat, {}, start)

    @staticmethod
    def _pop(rest: dict, letter: str, default=None):
        word = rest.pop(letter, None)
        return default if word is None else word.value

    # ------------------------------------------------------------------ G codes and axes

    def _lower_codes(self, block, read, codes, rest, stages, path) -> None:
        motion_kind = None
        motion_span = None
        consumer = None  # the code that takes the block's non-modal words
        for entry, word in codes:
            span = self._span(read, word.start, word.end, path)
            effect = entry["effect"]
            if effect == "move":
                motion_kind = entry["kind"]
                motion_span = span
            elif effect == "modal":
                stages[_MODAL].append(ir.SetModal(span, entry["modal"], entry["value"]))
            elif effect == "comp":
                stages[_MODAL].append(ir.CutterComp(span, entry["side"], None))
                if entry.get("d_is_diameter"):  # LinuxCNC G41.1/G42.1: D is the tool's diameter, not an offset register
                    rest.pop("D", None)
            elif effect == "length":
                stages[_MODAL].append(ir.LengthOffset(span, entry["mode"], None))
                if entry.get("takes_axes"):  # LinuxCNC G43.1 Z..: the offset's value, not a move
                    for letter in self.axis_letters & rest.keys():
                        rest.pop(letter)
            elif effect == "work_offset":
                name = f"G{code_key(word.value)}"
                if name == "G54.1":
                    number = self._pop(rest, "P")
                    name = f"G54.1 P{code_key(number)}" if isinstance(number, float) else name
                stages[_OFFSET].append(ir.WorkOffset(span, name))
            elif effect == "cycle_cancel":
                stages[_MODAL].append(ir.CycleCancel(span))
            elif effect == "none":
                continue
            else:
                consumer = (entry, word, span)
        self._lower_registers(rest, stages, read, path, consumer)
        self._lower_feed_speed_tool(rest, stages, read, path, consumer)
        if consumer is not None:
            self._lower_consumer(consumer, rest, stages, read, path, block)
        self._lower_motion(motion_kind, motion_span, rest, stages, read, path, block)

    def _lower_registers(self, rest, stages, read, path, consumer) -> None:
        """D and H without a G41/G43 in the block change the register of the active mode."""
        if consumer is not None and consumer[0]["effect"] in ("macro_call", "cycle_call", "unsupported"):
            return  # the words belong to the call or to the code not modelled (LinuxCNC G70 D: a cut depth)
        modal_ops = stages[_MODAL]
        for letter, op_type in (("D", ir.CutterComp), ("H", ir.LengthOffset)):
            word = rest.pop(letter, None)
            if word is None:
                continue
            for op in modal_ops:
                if isinstance(op, op_type):
                    op.register = self._value(word)
                    break
            else:
                span = self._span(read, word.start, word.end, path)
                modal_ops.append(op_type(span, "keep", self._value(word)))

    def _lower_feed_speed_tool(self, rest, stages, read, path, consumer) -> None:
        if consumer is not None and consumer[0]["effect"] in ("macro_call", "frame"):
            return  # the words are the call's arguments, or the factors of a scaling (Fagor G72 S)
        word = rest.pop("F", None)
        if word is not None:
            value = word.value
            if isinstance(value, float) and not word.has_point and self.feed_increment:
                value = ir.IncrementCount(value, "feed")
            stages[_FEED].append(ir.SetFeed(self._span(read, word.start, word.end, path), value))
        word = rest.pop("S", None)
        if word is not None:
            clamp = consumer is not None and consumer[0].get("spindle_clamp", False)
            stages[_FEED].append(ir.SetSpindleSpeed(self._span(read, word.start, word.end, path), word.value, clamp))
        word = rest.pop("T", None)
        if word is not None:
            stages[_FEED].append(self._tool_select(word, read, path))

    def _tool_select(self, word: Word, read, path) -> ir.ToolSelect:
        span = self._span(read, word.start, word.end, path)
        value = word.value
        if not self.lathe or not isinstance(value, float) or not math.isfinite(value):
            return ir.ToolSelect(span, value)
        digits = word.end - word.start - 1
        if value >= 100 or digits >= 3:
            return ir.ToolSelect(span, float(int(value) // 100), float(int(value) % 100))
        return ir.ToolSelect(span, value, value)

    def _lower_consumer(self, consumer, rest, stages, read, path, block) -> None:
        entry, word, span = consumer
        effect = entry["effect"]
        if effect == "dwell":
            stages[_DWELL].append(ir.Dwell(span, self._dwell_seconds(rest)))
        elif effect == "shift":
            values = self._take_axes(rest)
            extra = {letter: self._value(w) for letter, w in rest.items()}
            rest.clear()
            stages[_OFFSET].append(ir.CoordinateShift(span, entry["kind"], values, extra))
        elif effect == "reference":
            incremental = frozenset(self.twins[letter] for letter in rest if letter in self.twins)
            values = self._take_axes(rest)
            extra = {letter: self._value(w) for letter, w in rest.items()}
            rest.clear()
            stages[_MOTION].append(ir.ReferenceReturn(span, entry["kind"], values, extra, incremental))
        elif effect == "machine_move":
            stages[_MOTION].append(ir.MachineMove(span, self._take_axes(rest)))
        elif effect == "home":
            stages[_MOTION].append(ir.Home(span, tuple(self._take_axes(rest))))
        elif effect == "macro_call":
            program = self._pop(rest, "P")
            repeat = self._pop(rest, "L", 1.0)
            arguments = {letter: w.value for letter, w in rest.items()}  # passed as written: the macro decides units
            rest.clear()
            stages[_CALL].append(ir.Call(span, "macro", -1.0 if program is None else program, repeat, arguments))
        elif effect in ("cycle", "cycle_call"):
            params, spans = self._cycle_params(rest, read, path, entry["cycle"])
            op_type = ir.CycleDefine if effect == "cycle" else ir.CycleCall
            stages[_MOTION].append(op_type(span, entry["cycle"], params, spans))
        elif effect == "frame":
            stages[_MOTION].append(self._frame(entry, word, span, rest))
        elif effect == "unsupported":
            stages[_MOTION].append(ir.Unsupported(span, f"G{code_key(word.value)} ({entry['meaning']})", tuple(entry.get("affects", ()))))
            block.notes.append(ir.Note("core.unsupported-code", f"G{code_key(word.value)} ({entry['meaning']}) is read but not modelled; checks that depend on its motion answer unknown", span))
            rest.clear()

    @staticmethod
    def _frame(entry, word, span, rest) -> ir.SetFrame:
        """A coordinate transformation that is not modelled (scaling, rotation) leaves the
        frame unknown until its cancel resets it; written values that all equal the table's
        ``neutral`` value (Fagor ``G72 S1``) cancel it too."""
        written = [w.value for w in rest.values()]
        rest.clear()
        neutral = entry.get("neutral")
        cancels = neutral is not None and written and all(type(value) is float and value == neutral for value in written)
        group = entry.get("group") if entry.get("group") not in (None, "00") else code_key(word.value)  # G72 .. G72 S1: the code is its own group
        return ir.SetFrame(span, "reset" if cancels else entry["component"], what=f"G{code_key(word.value)} ({entry['meaning']})", group=group)

    def _cycle_params(self, rest, read, path, cycle_id) -> tuple[dict, dict]:
        """The words a cycle takes. For a modal hole cycle the hole position (the plane
        axes) stays behind for the Move; a one-shot cycle takes every word."""
        model = self.table.cycles.get(cycle_id, UNKNOWN_CYCLE)
        declared = model.params
        one_shot = model.infeed is None and model.shape is not None
        params, spans = {}, {}
        for letter in list(rest):
            if one_shot or letter in declared or letter in _CYCLE_WORDS and letter not in self.axis_letters:
                if not one_shot and letter in self.axis_letters and letter not in ("Z", "X", "W", "U") and letter not in declared:
                    continue
                word = rest.pop(letter)
                kind = (declared[letter].kind if letter in declared else None) or ("count" if letter in ("L", "K") else None)
                params[letter] = word.value if kind in ("code", "count") else self._value(word)
                spans[letter] = self._span(read, word.start, word.end, path)
        return params, spans

    def _lower_motion(self, motion_kind, motion_span, rest, stages, read, path, block) -> None:
        targets: dict[str, ir.Expr] = {}
        spans: dict[str, Span] = {}
        columns: dict[str, tuple[int, int]] = {}
        incremental = set()
        arc: dict[str, ir.Expr] = {}
        words: dict[str, ir.Expr] = {}
        for letter, word in rest.items():
            value = self._value(word)
            spans[letter] = self._span(read, word.start, word.end, path)
            columns[letter] = (word.start, word.end)
            if letter in self.twins:
                axis = self.twins[letter]
                targets[axis] = value
                incremental.add(axis)
                columns[axis] = columns[letter]
            elif letter in self.axis_letters:
                targets[letter] = value
            elif letter in ("I", "J", "K", "R") and (motion_kind in ("arc_cw", "arc_ccw") or motion_kind is None):
                arc[letter] = value
                words[letter] = value
            else:
                words[letter] = value
        if motion_span is None and not (targets or arc or words):
            return
        for word_span in spans.values():
            motion_span = word_span if motion_span is None else motion_span.cover(word_span)
        stages[_MOTION].append(ir.Move(motion_span, motion_kind, targets, arc or None, words, frozenset(incremental), columns))

    # ------------------------------------------------------------------ values

    def _value(self, word: Word) -> ir.Expr:
        value = word.value
        if self.increment and isinstance(value, float) and not word.has_point and word.letter.lstrip(",") in self.scaled_letters:
            if 1 <= abs(value) < 1000 and word.letter in self.axis_letters:
                self._block.notes.append(ir.Note("core.decimal-point", _decimal_point_message(word.letter, value, self.increment),
                                                 Span(self._block.line, word.start + 1, self._block.line, word.end + 1, self._path)))
            return ir.IncrementCount(value, "length")
        return value

    def _dwell_seconds(self, rest: dict) -> ir.Expr | None:
        """G04 X/U are seconds (scaled like lengths when written without a point); P is
        milliseconds, or seconds when written with a decimal point (Haas)."""
        for letter in ("X", "U"):
            word = rest.pop(letter, None)
            if word is not None:
                return self._value(word)
        word = rest.pop("P", None)
        if word is None:
            return None
        if word.has_point or not isinstance(word.value, float):
            return word.value
        return word.value / 1000.0

    def _take_axes(self, rest: dict) -> dict[str, ir.Expr]:
        values = {}
        for letter in list(rest):
            if letter in self.axis_letters:
                word = rest.pop(letter)
                axis = self.twins.get(letter, letter)
                values[axis] = self._value(word)
        return values


def _decimal_point_message(letter: str, value: float, increment: float) -> str:
    return (f"{letter}{value:g} has no decimal point, so this control reads it in least input increments: "
            f"{value * increment:g} mm (or {value * increment / 10:g} in), not {value:g}; write {letter}{value:g}. if whole units are meant")


# ---------------------------------------------------------------------- front end

# Possessive and atomic: a number or a run of blanks is only ever taken whole (a shorter
# take leaves a digit, a point or a blank where a letter must follow), so a line that fails
# fails at once instead of retrying every split of every number.
# What the fast lowering takes, and what may join a batch: the plain blocks and arcs with
# their centre or radius words.
# G only with a motion code the fast lowering takes (0-3, however written): a line with G80,
# G90 or G98 G81 goes to the general lowering at once, not after the fast one reads it whole
_FAST_LINE = re.compile(rb"[ \t]*+(?:(?:[NXYZABCFIJKR][ \t]*+[+-]?+(?>\d+\.?\d*|\.\d+)"
                        rb"|G[ \t]*+[+-]?+(?:0*+[0-3](?:\.0*+)?+|0++(?:\.0*+)?+|0*+\.0++)(?![0-9.]))[ \t]*+)++")
_PLAIN_WORD_BYTES = re.compile(rb"(CR=|[NGXYZABCFIJKR])[ \t]*([+-]?(?:\d+\.?\d*|\.\d+))")
_LETTERS = {letter.encode(): letter for letter in "NGXYZABCFIJKR"} | {b"CR=": "R"}  # SINUMERIK's CR= is an arc's radius word
_NUMBER_BYTES = rb"([+-]?(?:\d+\.?\d*|\.\d+))"
# Nearly all CAM output writes its words in this order; one match reads the whole block.
_CANONICAL_LETTERS = ("N", "G", "X", "Y", "Z", "I", "J", "K", "R", "F")
_CANONICAL = re.compile(
    rb"[ \t]*(?:N(\d+)[ \t]*)?(?:G(0?[0-3])(?![0-9.])[ \t]*)?"
    + b"".join(rb"(?:" + letter + _NUMBER_BYTES + rb"[ \t]*)?" for letter in (b"X", b"Y", b"Z", b"I", b"J", b"K", b"R", b"F"))
)
_FAST_MOTION = {0.0: "rapid", 1.0: "linear", 2.0: "arc_cw", 3.0: "arc_ccw"}
_PROGRAM_START = re.compile(rb"(?i)[ \t]*(?:%[ \t]*)?(?:N\d+[ \t]*)?[O:][ \t]*(\d+)")
_PROGRAM_END = re.compile(rb"(?i)M0*(?:2|30)(?![0-9.])")
_RETURN = re.compile(rb"(?i)M99(?![0-9.])")
_SETUP = re.compile(rb"(?i)(?<![A-Z])(?:M0*6|G5[4-9])(?![0-9])")


# What a word does in a plain motion line (FastMotionForm.roles).
_WORD_LABEL, _WORD_MOTION, _WORD_FEED, _WORD_AXIS, _WORD_ARC = range(5)


@dataclass(frozen=True, slots=True)
class FastMotionForm:
    """What a dialect's lowering makes of a plain motion line, for :func:`lower_fast_motion`:
    its axis letters (incremental twins excluded), least input increments (0: numbers are
    mm or inch), the label an ``N`` number gives its block (ISO: the number; SINUMERIK:
    ``N<number>``, which ``GOTOF N100`` finds), which letters give an arc's centre or radius, and whether those belong to
    the move's span, words and columns (ISO) or to its arc only (SINUMERIK), and the lines
    it takes (``line``; a line in the usual word order always). ``roles``: what each letter
    does, looked up once a word."""

    axis_letters: frozenset
    increment: float = 0.0
    feed_increment: float = 0.0
    number_label: Callable[[str], object] = float
    arc_letters: frozenset = frozenset("IJKR")
    arc_words_in_span: bool = True
    line: re.Pattern = _FAST_LINE
    roles: dict = field(init=False, repr=False, compare=False, hash=False)

    def __post_init__(self):
        roles = dict.fromkeys(self.arc_letters, _WORD_ARC)
        roles.update(dict.fromkeys(self.axis_letters, _WORD_AXIS))
        roles.update(N=_WORD_LABEL, G=_WORD_MOTION, F=_WORD_FEED)
        object.__setattr__(self, "roles", roles)


def fast_motion_block(raw: bytes, line: int, path: str | None, form: FastMotionForm) -> ir.Block | None:
    """The line lowered by :func:`lower_fast_motion` when it has the plain form, else None."""
    canonical = _CANONICAL.fullmatch(raw)
    if canonical is not None and canonical.lastindex is None:
        canonical = None  # a blank line: no word
    if canonical is None and not form.line.fullmatch(raw):
        return None
    return lower_fast_motion(raw, line, path, form, canonical)


def _plain_words(raw: bytes, canonical: re.Match | None) -> list[tuple[str, bytes, int, int]]:
    """(letter, number, start, end) of each word of a plain line, in the order written
    (0-based columns, the letter's to the number's end)."""
    if canonical is not None:  # each number follows its letter directly
        spans = canonical.regs
        return [(_CANONICAL_LETTERS[index], text, spans[index + 1][0] - 1, spans[index + 1][1])
                for index, text in enumerate(canonical.groups()) if text is not None]
    return [(_LETTERS[match.group(1)], match.group(2), match.start(1), match.end(2)) for match in _PLAIN_WORD_BYTES.finditer(raw)]


def lower_fast_motion(raw: bytes, line: int, path: str | None, form: FastMotionForm, canonical: re.Match | None = None) -> ir.Block | None:
    """The fast path: ``[N..] [G0-G3] axis words [I J K | R] [F..]`` straight to IR,
    without reader objects (centre and radius words only on an arc or a modal move, as
    the general lowering takes them). Returns None when the block needs the general
    lowering. ``canonical``: the block's match of the usual word order, when it has one.
    The words come in the order written, so the move's span runs from the first of its
    words to the end of the last."""
    roles, increment, arc_words_in_span = form.roles, form.increment, form.arc_words_in_span
    label = kind = move_start = feed_op = None
    numbered = False
    move_end = 0
    targets = {}
    columns = {}
    arc = {}
    for letter, text, start, end in _plain_words(raw, canonical):
        role = roles.get(letter)
        if role == _WORD_AXIS:
            if letter in targets:
                return None
            if increment and b"." not in text:
                count = float(text)
                if 1 <= abs(count) < 1000:
                    return None  # a decimal-point trap: the general path reports it
                targets[letter] = ir.IncrementCount(count, "length")
            else:
                targets[letter] = float(text)
            columns[letter] = (start, end)
        elif role == _WORD_ARC:
            if letter in arc or (increment and b"." not in text):
                return None
            arc[letter] = float(text)
            if not arc_words_in_span:
                continue
            columns[letter] = (start, end)
        elif role == _WORD_MOTION:
            if kind is not None:
                return None
            kind = _FAST_MOTION.get(float(text))
            if kind is None:
                return None
        elif role == _WORD_FEED:
            if feed_op is not None:
                return None
            feed = ir.IncrementCount(float(text), "feed") if form.feed_increment and b"." not in text else float(text)
            feed_op = ir.SetFeed(Span(line, start + 1, line, end + 1, path), feed)
            continue
        elif role == _WORD_LABEL and not numbered:
            numbered = True
            label = form.number_label(text)
            continue
        else:
            return None
        if move_start is None:
            move_start = start
        move_end = end
    if arc and kind in ("rapid", "linear"):
        return None  # centre words on a straight move: the general lowering says what they are
    if move_start is None and arc:
        return None  # centre words alone: the general lowering places them
    stripped = raw.strip()
    first = raw.index(stripped[:1]) if stripped else 0
    block = ir.Block(line, first + 1, first + len(stripped) + 1, [], label=label)
    if feed_op is not None:
        block.ops.append(feed_op)
    if move_start is not None:
        span = Span(line, move_start + 1, line, move_end + 1, path)
        block.ops.append(ir.Move(span, kind, targets, arc or None, dict(arc) if arc_words_in_span else {}, frozenset(), columns))
    return block


_TOOL_WORD = letter_led(rb"T(?<![A-Z_#<]T)\s*(\d+)")
# what leaves the tools a program loads to more than its T words: a T word with a computed
# number, a call of a program that may be another file (M98, M198, G65, G66), G10 (it
# writes tool offsets)
TOOL_UNSURE = (rb"T(?<![A-Z_#<]T)\s*[-+#\[<]", rb"M(?<![A-Z]M)\s*0*(?:98|198)(?!\d)", rb"G(?<![A-Z]G)\s*0*(?:10|65|66)(?!\d)")


class IsoFrontend:
    """What the interpreter asks of a dialect: blocks of a line, where programs start, and
    where a sequence number may be. Programs are ``O`` numbers; labels are ``N`` numbers."""

    dialect = "iso"
    tool_unsure = letter_led(*TOOL_UNSURE)

    def __init__(self, lowering: IsoLowering):
        self.lowering = lowering
        self.fast_form = FastMotionForm(lowering.axis_letters - frozenset(lowering.twins), lowering.increment, lowering.feed_increment)

    def tools_called(self, source) -> frozenset[int] | None:
        """The tools the program can load (:func:`~ncverify.context.tools_called_in`)."""
        return tools_called_in(source.buffer, _TOOL_WORD, self.tool_unsure)

    def blocks(self, raw: bytes, line: int, path: str | None) -> list[ir.Block]:
        block = fast_motion_block(raw, line, path, self.fast_form)
        return [block] if block is not None else self._lower_text(decode_line(raw), line, path)

    def _lower_text(self, text: str, line: int, path: str | None) -> list[ir.Block]:
        """The general path: the line read into blocks, each lowered."""
        return [self.lowering.lower(read, path) for read in read_line(text, line)]

    def _plain_motion(self, raw: bytes, line: int, path: str | None, canonical: re.Match | None = None) -> ir.Block | None:
        """The fast lowering of a plain motion line (:func:`lower_fast_motion`), or None."""
        return lower_fast_motion(raw, line, path, self.fast_form, canonical)

    def is_plain(self, raw: bytes) -> bool:
        """Could this line be part of a :class:`ir.MoveBatch`? (Straight moves, and arcs
        in the fast lowering's form.)"""
        return _FAST_LINE.fullmatch(raw) is not None

    def plain_run(self, buffer, offset: int, line: int, limit: int = 1 << 20) -> ir.MoveBatch | None:
        """The plain blocks from ``offset`` on, arcs among them, as one :class:`ir.MoveBatch`
        (see :mod:`ncverify.read.iso_runs`); None when the streak is short."""
        if self.lowering.twins or "X" not in self.lowering.axis_letters:
            return None
        run = read_plain_run_at(buffer, offset, limit, stop_at_small_integers=bool(self.lowering.increment), arcs=True)
        if run is None:
            return None
        table, pointless = run.table, run.pointless
        motion = table[:, 1]
        kinds = numpy.where(numpy.isnan(motion), -1, motion).astype(numpy.int8)
        return ir.MoveBatch(offset, offset + run.length, line, run.line_starts + offset, kinds, ("X", "Y", "Z"), table[:, 2:5],
                          pointless[:, 2:5] & bool(self.lowering.increment), table[:, 5],
                          pointless[:, 5] & bool(self.lowering.feed_increment), run.blocks, run.arc_words, run.worded)

    def programs(self, buffer) -> list[tuple[str, int]]:
        """``(name, offset of its first line)`` for every program header in the buffer.
        Candidates are found by their letter, then the line's start is checked (a scan
        anchored at every line start costs a second per million lines)."""
        found = []
        for candidate in find_all(buffer, (b"O", b"o", b":")):
            start = line_start(buffer, candidate)
            match = _PROGRAM_START.match(buffer, start)
            if match is not None and match.start(1) > candidate and (not found or found[-1][1] != start):
                found.append((f"O{int(match.group(1))}", start))
        return found

    def tape_marks(self, buffer) -> list[int]:
        """Offsets of the '%' lines: text between a closing mark and the next opening one
        is not part of any program."""
        return [start for start in (line_start(buffer, candidate) for candidate in find_all(buffer, (b"%",)))
                if not bytes(buffer[start : buffer.find(b"%", start)]).strip()]

    def is_subprogram(self, buffer, start: int, end: int) -> bool:
        """Is the program between the offsets a subprogram: it returns with M99, never ends
        with M02/M30, and sets up no tool or work offset of its own (a main program that
        loops with M99, as on a bar feeder, does)?"""
        tail = max(start, end - 65536)  # an end code sits near the end: look there first
        if _PROGRAM_END.search(buffer, tail, end) or _PROGRAM_END.search(buffer, start, tail + 16):
            return False
        return _RETURN.search(buffer, start, end) is not None and _SETUP.search(buffer, start, end) is None

    def program_name(self, number: float) -> str:
        return f"O{int(number)}"

    def describe_label(self, label) -> str:
        return f"sequence number N{label:g}"

    def variable_scope(self, name: str) -> str:
        """#1-#33 are a macro's local variables; the rest are common or system variables."""
        number = name[1:]
        return "local" if number.isdigit() and 1 <= int(number) <= 33 else "global"

    def system_variable(self, name: str, state):
        """The system variables the machine state can answer; the rest stay free parameters."""
        if name == "#0":
            return VACANT  # always vacant: "#0" is how a macro writes "no value"
        number = int(name[1:]) if name[1:].isdigit() else 0
        if number < 1000:
            return None
        if number == 4109:
            return state.feed if state.feed is not None else 0.0
        if number == 4119:
            return state.spindle_speed if state.spindle_speed is not None else 0.0
        if number == 4120:
            return state.tool_in_spindle if state.tool_in_spindle is not None else VACANT
        if 5001 <= number <= 5003:
            value = state.position.get("XYZ"[number - 5001])
            return value if value is not None else values.fresh(name)
        return None

    def machine_data(self, name: str) -> tuple[str, bool] | None:
        """What writing system variable ``name`` changes that the model does not follow,
        and whether that counts before the first move (see
        :meth:`~ncverify.interpret.Interpreter.unfollowed`); None for any other variable."""
        return numbered_machine_data(name, _ISO_MACHINE_DATA)

    def label_offsets(self, buffer, label: float):
        """Offsets of lines that may carry sequence number ``label`` (the interpreter
        confirms by reading the line)."""
        pattern = re.compile(rb"(?mi)^[^\n(]*?N0*" + str(int(label)).encode() + rb"(?![0-9.])")
        for match in pattern.finditer(buffer):
            yield match.start()


# System variables a program can write whose values the model does not follow (Fanuc-style
# numbering, which Mitsubishi and Haas share): (first, last, what they hold, counts before
# the first move). Tool offsets always count: the tool table gives the tools' real sizes.
_ISO_MACHINE_DATA = ((2001, 2999, "tool offset data", True), (10001, 13999, "tool offset data", True),
                     (5201, 5399, "a work offset", False), (7001, 7999, "a work offset", False), (14001, 19999, "a work offset", False))


def numbered_machine_data(name: str, ranges: tuple) -> tuple[str, bool] | None:
    """``(what, counts before the first move)`` of the range of ``ranges`` that numbered
    variable ``name`` (``#5221``) falls in, or None."""
    number = int(name[1:]) if name[:1] == "#" and name[1:].isdigit() else None
    if number is None:
        return None
    return next(((what, before_moves) for first, last, what, before_moves in ranges if first <= number <= last), None)


def setup(settings, detection, project) -> DialectSetup:
    """The ISO tables for the profile and machine (command line > project file > detection)."""
    profile = settings.profile or detection.profile or "mitsubishi-e60"
    machine = settings.machine or project.machine.kind or detection.machine or "mill"
    table = iso_table(profile, machine)
    increment = settings.least_input_increment
    if increment is None and detection.whole_units:
        increment = 0.0
    lowering = IsoLowering(table, increment)
    limits = {name: float(table.settings.get(name, default))
              for name, default in (("d_register_max", 99), ("h_register_max", 99), ("tool_number_max", 9999))}
    return DialectSetup(IsoFrontend(lowering), table.power_on, table.cycles, profile, machine,
                        dict(table.words.get("incremental_twins", {})), lowering.increment, lowering.feed_increment, limits)
