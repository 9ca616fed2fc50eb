"""Lowering of LinuxCNC (RS274NGC) blocks to IR: the ISO lowering plus O-word control flow.

Words are distributed by the ISO lowering with LinuxCNC's own code table
(``dialects/linuxcnc/``). O-words become jumps to labels the O-word lines themselves carry,
so the interpreter's jump, loop-bound and call machinery runs them unchanged:

- ``oN if [c]`` jumps, when ``c`` is false, to the nearest following branch line of ``oN``
  (``elseif``, ``else`` or ``endif``); ``elseif``/``else`` lines are two blocks, the first
  (reached by falling out of the branch before) jumping to ``endif``, the second (reached by
  the jump) testing its own condition.
- ``while``/``endwhile``, ``do``/``while`` and ``repeat``/``endrepeat`` are backward jumps,
  counted against the loop bound; ``break`` and ``continue`` jump to the loop's exit and head.
- ``oN sub`` jumps over the definition; ``oN call`` calls it like a macro (``#1``-``#30`` are
  its arguments, named parameters without a leading ``_`` its own); ``endsub`` and
  ``return`` return, setting ``#<_value>`` when given one.

Whether ``oN while`` closes a ``do`` loop or opens a while loop depends on the lines before
it; the lowering remembers which ``do`` lines it has read (they always run, and so are
lowered, before their ``while``).
"""
from __future__ import annotations

import math
import re
from functools import cache

from .. import ir
from ..context import ArcTolerance, Context, Tool
from ..cycle_models import read_cycle_table, typed_cycle_table
from ..dialect import DialectSetup
from ..read.iso import ReadBlock, Statement, Word
from ..read.linuxcnc import POLAR, OWord, read_line
from ..resources import data_dir, read_table
from ..source import Span, decode_line, finditer_all, letter_led, line_start, lines_holding
from ..tables import CodeTable
from ..values import VACANT
from .iso import TOOL_UNSURE, IsoFrontend, IsoLowering, numbered_machine_data

LAST_PARAMETER = 5602.0  # the highest numbered parameter
ARGUMENTS = 30  # #1-#30 are a subroutine's arguments
_VALUE = ir.Var("#<_value>")
_M_CODE_WORDS = {19.0: "RQP", 61.0: "Q", 62.0: "P", 63.0: "P", 64.0: "P", 65.0: "P", 66.0: "PELQ", 67.0: "EQ", 68.0: "EQ"}
_VACANT = ir.Var("#0")
# The numbered parameters of the offsets (rs274ngc's parameter table): G92's (with its
# enable flag) always count, as G92 is a shift in force; the G54-G59.3 tables once moving.
_LINUXCNC_MACHINE_DATA = ((5210, 5219, "the G92 offset", True), (5220, 5389, "a work offset", False))

# The radius difference rs274 accepts in an arc given by its centre, measured against it
# (the differential tests): 0.02 * sqrt(2) mm in G21 and 0.002 * sqrt(2) inch in G20 (one
# tolerance per unit, not one converted), and only when also more than 0.1 % of the radius.
_ARC_TOLERANCE = ArcTolerance(metric=0.0283, inch=0.00283, relative=0.001)


@cache
def linuxcnc_table(machine: str = "mill") -> CodeTable:
    """LinuxCNC's codes; the cycles are the ISO family's hole models with LinuxCNC's levels."""
    folder = data_dir("dialects")
    mill = read_table(folder / "linuxcnc" / "mill.toml")
    g, m, words, power_on = dict(mill["g"]), dict(mill["m"]), dict(mill["words"]), dict(mill["power_on"])
    if machine == "lathe":
        lathe = read_table(folder / "linuxcnc" / "lathe.toml")
        g.update(lathe.get("g", {}))
        words.update(lathe.get("words", {}))
        power_on.update(lathe.get("power_on", {}))
    levels = read_cycle_table("linuxcnc")  # what RS274NGC does differently at the levels of the ISO hole cycles
    cycles = typed_cycle_table({name: {**model, **levels.get(name, {})} for name, model in read_cycle_table("iso").items()})
    return CodeTable("linuxcnc", machine, g, m, words, power_on, dict(mill["settings"]), cycles)


def _not(condition: ir.Expr) -> ir.Expr:
    return ir.Binary("EQ", condition, 0.0)


def _logical(expr):
    """RS274NGC's AND/OR/XOR are logical (non-zero is true), EXISTS tests whether a parameter
    is set: rewrite both into what the interpreter evaluates."""
    if isinstance(expr, ir.Binary):
        left, right = _logical(expr.left), _logical(expr.right)
        if expr.op in ("AND", "OR", "XOR"):
            return ir.Binary(expr.op, ir.Binary("NE", left, 0.0), ir.Binary("NE", right, 0.0))
        return ir.Binary(expr.op, left, right)
    if isinstance(expr, ir.Unary):
        return ir.Unary(expr.op, _logical(expr.operand))
    if isinstance(expr, ir.Func):
        if expr.name == "EXISTS":
            return _exists(expr.args[0])
        return ir.Func(expr.name, tuple(_logical(arg) for arg in expr.args), expr.span)
    if isinstance(expr, ir.Var) and not isinstance(expr.name, str):
        return ir.Var(_logical(expr.name), expr.span, expr.prefix)
    return expr


def _exists(target: ir.Var) -> ir.Expr:
    """Numbered parameters #1-#5602 always exist, others never; a named one once it is set."""
    if not isinstance(target.name, str):
        return ir.Binary("AND", ir.Binary("GE", _logical(target.name), 1.0), ir.Binary("LE", _logical(target.name), LAST_PARAMETER))
    if target.name.startswith("#<"):
        return ir.Binary("NE", target, _VACANT)
    return 1.0 if 1 <= int(target.name[1:]) <= LAST_PARAMETER else 0.0


class LinuxcncLowering(IsoLowering):
    """ISO word lowering with O-words, RS274NGC expressions and active comments."""

    def __init__(self, table: CodeTable, remaps: frozenset[str] | None = None):
        super().__init__(table, 0.0)
        self.max_m_words = 5  # RS274NGC: one M word per modal group, up to five groups
        self.loops: dict[tuple, tuple[str, int]] = {}  # (path, o-name) -> (loop kind, line of its head)
        self.remaps = remaps  # the G codes the machine's configuration remaps; None: not declared

    def _unknown_code(self, note: ir.Note) -> None:
        """A G code LinuxCNC lacks. One that a configuration may add by remapping (a free code
        of G0-G99.9 with at most one decimal) is unknown until ``[machine] remaps`` lists the
        machine's remaps; any other, or one the declared remaps lack, makes LinuxCNC refuse
        the block (an error)."""
        code = note.message.split(" ", 1)[0]  # the lowering's message starts with the code ("G68.2 is not a code ...")
        note.rule = "linuxcnc.unknown-code"
        if _REMAPPABLE.fullmatch(code) and (self.remaps is None or code in self.remaps):
            note.status = "unknown"
            if self.remaps is None:
                note.message = f"{code} is not a built-in LinuxCNC code: a machine's configuration can add it by a remap (REMAP={code} in its INI file)"
                note.reason = f'the machine\'s remaps are not declared: list them in ncverify.toml, [machine] remaps = ["{code}"] ([] for none)'
            else:
                note.message = f"{code} runs the remap of the machine's configuration: its effect is not modelled"
                note.reason = "a remapped code runs the configuration's own subroutine"
            return
        note.message = note.message.replace("its effect is not modelled", "LinuxCNC stops with 'Unknown g code used'")

    def _dwell_seconds(self, rest: dict) -> ir.Expr | None:
        """G4 P is in seconds, with or without a decimal point."""
        word = rest.pop("P", None)
        return None if word is None else word.value

    def lower_line(self, read: ReadBlock, path) -> list[ir.Block]:
        for item in read.items:
            if isinstance(item, Statement):
                item.value = _logical(item.value)
            elif hasattr(item, "value") and isinstance(item.value, (ir.Binary, ir.Unary, ir.Func, ir.Var)):
                item.value = _logical(item.value)
        tool_set = self._tool_set(read, path)
        self._drop_m_code_words(read)
        owords = [item for item in read.items if isinstance(item, OWord)]
        if not owords or read.problem:
            polar = [item for item in read.items if isinstance(item, Word) and item.letter in POLAR]
            read.items = [item for item in read.items if item not in polar]
            block = self.lower(read, path)
            block.ops.extend(tool_set)
            if polar:
                self._polar_unsupported(block, polar, read, path)
            self._comment_actions(block)
            for note in block.notes:
                if note.rule == "core.unknown-code":
                    self._unknown_code(note)
            return [block]
        oword = owords[0]
        read.items = [item for item in read.items if not isinstance(item, OWord)]
        head = self.lower(read, path)  # the N word, if any
        head.label = None
        oword.args = [_logical(arg) for arg in oword.args]
        span = Span(read.line, oword.start + 1, read.line, oword.end + 1, path)
        blocks = self._oword_blocks(oword, span, read.line, path)
        first = blocks[0]
        first.notes = head.notes + first.notes
        first.comments = head.comments
        for block in blocks:
            block.start_column, block.end_column = read.start + 1, read.end + 1
        return blocks

    # ------------------------------------------------------------------ O-words

    def _oword_blocks(self, oword: OWord, span: Span, line: int, path) -> list[ir.Block]:
        name, keyword, args = oword.name, oword.keyword, oword.args

        def block(label=None, *ops):
            return ir.Block(line, 1, 1, list(ops), label=f"{name}|{label}" if label else None)

        def jump(label, condition=None, direction="forward"):
            return ir.Jump(span, f"{name}|{label}", condition, direction)

        condition = args[0] if args else None
        needs_condition = keyword in ("IF", "ELSEIF", "WHILE", "REPEAT")
        if needs_condition and condition is None:
            result = block()
            result.notes.append(ir.Note("core.syntax", f"{name} {keyword.lower()} needs a bracketed expression", span))
            return [result]
        if keyword == "SUB":
            return [block(None, jump("after-sub"))]
        if keyword in ("ENDSUB", "RETURN"):
            ops = [ir.Assign(span, _VALUE, args[0])] if args else []
            ops.append(ir.Return(span))
            return [block(None, *ops), block("after-sub")] if keyword == "ENDSUB" else [block(None, *ops)]
        if keyword == "CALL":
            arguments = {f"#{index}": args[index - 1] if index <= len(args) else 0.0 for index in range(1, ARGUMENTS + 1)}
            return [block(None, ir.Call(span, "macro", name, 1.0, arguments))]
        if keyword == "IF":
            return [block(None, jump("branch", _not(condition)))]
        if keyword == "ELSEIF":
            return [block(None, jump("endif")), block("branch", jump("branch", _not(condition)))]
        if keyword == "ELSE":
            return [block(None, jump("endif")), block("branch")]
        if keyword == "ENDIF":
            return [block("branch"), block("endif")]
        return self._loop_blocks(oword, span, line, path, block, jump, condition)

    def _loop_blocks(self, oword, span, line, path, block, jump, condition) -> list[ir.Block]:
        name, keyword = oword.name, oword.keyword
        key = (path, name)
        known = self.loops.get(key)
        if keyword == "DO":
            self.loops[key] = ("do", line)
            return [block("do")]
        if keyword == "WHILE":
            if known is not None and known[0] == "do" and known[1] < line:
                return [block("check", jump("do", condition, "backward")), block("exit")]
            self.loops[key] = ("while", line)
            return [block("head", jump("exit", _not(condition)))]
        if keyword == "REPEAT":
            self.loops[key] = ("repeat", line)
            counter = ir.Var(f"#<~repeat {name}>")
            return [block(None, ir.Assign(span, counter, condition)),
                    block("head", jump("exit", ir.Binary("LE", counter, 0.5)), ir.Assign(span, counter, ir.Binary("-", counter, 1.0)))]
        if keyword in ("ENDWHILE", "ENDREPEAT"):
            return [block(None, jump("head", direction="backward")), block("exit")]
        if keyword == "BREAK":
            return [block(None, jump("exit"))]
        if keyword == "CONTINUE":
            if known is not None and known[0] == "do":
                return [block(None, jump("check"))]
            return [block(None, jump("head", direction="backward"))]
        result = block()
        result.notes.append(ir.Note("core.syntax", f"{name} {keyword.lower()} is not an O-word statement", span))
        return [result]

    def _tool_set(self, read: ReadBlock, path) -> list[ir.Op]:
        """M61 Q..: the tool in the spindle is tool Q from now on, without a change (the
        operations a tool change makes, for the rules that read the loaded tool)."""
        m61 = next((item for item in read.items if isinstance(item, Word) and item.letter == "M" and item.value == 61.0), None)
        number = next((item for item in read.items if isinstance(item, Word) and item.letter == "Q"), None)
        if m61 is None or number is None:
            return []
        span = Span(read.line, m61.start + 1, read.line, number.end + 1, path)
        return [ir.ToolSelect(span, number.value), ir.ToolChange(span)]

    @staticmethod
    def _drop_m_code_words(read: ReadBlock) -> None:
        """The words an M code takes (M19 R Q P, M66 P E L Q, M62-M65 P, M67/M68 E Q, M61 Q)
        are its own: left in, they would read as a move (and drill a hole under a modal cycle)."""
        taken = set()
        for item in read.items:
            if isinstance(item, Word) and item.letter == "M" and isinstance(item.value, float):
                taken |= set(_M_CODE_WORDS.get(item.value, ""))
        if taken:
            read.items = [item for item in read.items if not (isinstance(item, Word) and item.letter in taken)]

    @staticmethod
    def _polar_unsupported(block: ir.Block, polar: list, read: ReadBlock, path) -> None:
        """``@`` (distance) and ``^`` (angle): polar coordinates are read, not modelled; the
        block's motion (and a cycle it defines) goes somewhere unknown."""
        span = Span(read.line, polar[0].start + 1, read.line, polar[-1].end + 1, path)
        block.ops = [op for op in block.ops if not isinstance(op, (ir.Move, ir.CycleDefine))]  # a cycle would drill at the wrong place
        block.ops.append(ir.Unsupported(span, "polar coordinates (@ distance, ^ angle)", ("position",)))
        block.notes.append(ir.Note("core.unsupported-code", "polar coordinates (@ distance, ^ angle) are read but not modelled; "
                                   "checks that depend on where this block moves answer unknown", span))

    # ------------------------------------------------------------------ active comments

    def _comment_actions(self, block: ir.Block) -> None:
        """``(abort, text)`` stops the program with an error, as the interpreter does."""
        for text, span in block.comments:
            command, _, message = text.strip().partition(",")
            if command.strip().lower() == "abort" and _:
                block.ops.append(ir.Alarm(span, 0.0, message.strip(), "(abort,...)"))


_OWORD_LINE = rb"(?im)^[ \t]*(?:/[ \t]*)?(?:N[ \t]*[\d.]+[ \t]*)?O[ \t]*"
_SUB = re.compile(_OWORD_LINE + rb"(\d+|<[^>\n]*>)[ \t]*S[ \t]*U[ \t]*B(?![ \t]*[A-Z])")
_FANUC_PROGRAM = re.compile(rb"(?im)^[ \t]*O[ \t]*(\d+)[ \t]*(?:\([^)\n]*\)[ \t]*|;[^\n]*)?\r?$")  # O1 ... M99, called by M98
_ENDSUB = rb"[ \t]*E[ \t]*N[ \t]*D[ \t]*S[ \t]*U[ \t]*B"


def _name_pattern(name: str) -> bytes:
    """How O-word ``name`` (``o100``, ``o<my sub>``) may be written: any case, spaces inside."""
    body = name[1:]
    if body.startswith("<"):
        inner = rb"[ \t]*".join(re.escape(bytes([char])) for char in body[1:-1].encode())
        return rb"<[ \t]*" + inner + rb"[ \t]*>"
    return rb"0*" + body.encode() + rb"(?![0-9])"


_OWORD_CALL = letter_led(rb"O\s*(<[^>]*>|\d+)\s*call")
_LETTER_O = letter_led(rb"O")  # what every O-word line holds: the whole-text scans try their patterns on those lines only


class LinuxcncFrontend(IsoFrontend):
    """Programs are the file's main code and its ``oN sub`` definitions; labels are O-words."""

    dialect = "linuxcnc"
    tool_unsure = letter_led(*TOOL_UNSURE, rb"M(?<![A-Z]M)\s*0*61(?!\d)")  # M61 sets the tool number without a T word

    def __init__(self, lowering: LinuxcncLowering):
        super().__init__(lowering)
        self.structure_notes: dict[int, list[ir.Note]] = {}  # line -> O-word structure findings of the main file

    def tools_called(self, source) -> frozenset[int] | None:
        """As in ISO, and none told when the program calls a subroutine it does not define
        (a file of its own, whose T words are not in this text): defined as the program
        index finds its ``sub`` lines (a ``sub`` in a comment defines none)."""
        def names(matches):
            return {match.group(1).lower().replace(b" ", b"") for match in matches}

        if names(finditer_all(source.buffer, _OWORD_CALL)) - names(lines_holding(source.buffer, _LETTER_O, _SUB)):
            return None
        return super().tools_called(source)

    def _lower_text(self, text: str, line: int, path: str | None) -> list[ir.Block]:
        blocks = []
        for read in read_line(text, line):
            blocks.extend(self.lowering.lower_line(read, path))
        return self._with_structure_notes(blocks, line, path)

    def _with_structure_notes(self, blocks: list[ir.Block], line: int, path) -> list[ir.Block]:
        notes = self.structure_notes.get(line) if path is None else None
        if notes and blocks:
            blocks[0].notes.extend(note for note in notes if note not in blocks[0].notes)
        return blocks

    def programs(self, buffer) -> list[tuple[str, int]]:
        """The main program at the top, then each subroutine from the line after its ``sub``."""
        found = [("main", 0)]
        for match in lines_holding(buffer, _LETTER_O, _FANUC_PROGRAM):
            found.append((f"O{int(match.group(1))}", match.start()))
        for match in lines_holding(buffer, _LETTER_O, _SUB):
            newline = buffer.find(b"\n", match.end())
            body = len(buffer) if newline < 0 else newline + 1
            found.append((self.program_name(_oword_name(match.group(1))), body))
        return found

    def program_extent(self, buffer, start: int) -> int:
        """Where the program starting at ``start`` ends: a subroutine at the end of its
        ``endsub`` line, the main program at the end of the file."""
        if start == 0 or _FANUC_PROGRAM.match(buffer, start):
            return len(buffer)
        sub_line = line_start(buffer, max(start - 2, 0))
        match = _SUB.match(buffer, sub_line)
        if match is None:
            return len(buffer)
        pattern = re.compile(_OWORD_LINE + re.escape(match.group(1)).replace(rb"\ ", rb"[ \t]*") + _ENDSUB)
        end = pattern.search(buffer, start)
        if end is None:
            return len(buffer)
        newline = buffer.find(b"\n", end.end())
        return len(buffer) if newline < 0 else newline + 1

    @staticmethod
    def text_end_ends_program(buffer) -> bool:
        """LinuxCNC ends a program at its closing '%' as at M2, and a file that opens with
        ``o<name> sub`` is a subroutine file, run by a call, not as a program: neither needs
        M2/M30 at the end of its text."""
        lines = [line.strip() for line in bytes(buffer).splitlines() if line.strip() and not line.strip().startswith((b";", b"("))]
        return bool(lines) and (lines[-1] == b"%" or _SUB.match(lines[0] + b"\n") is not None)

    def is_subprogram(self, buffer, start: int, end: int) -> bool:
        """Everything but the main code at the top is called (``sub`` bodies, ``O1`` programs)."""
        return start != 0

    def tape_marks(self, buffer) -> list[int]:
        """'%' only brackets a LinuxCNC file; no program text lies outside the marks."""
        return []

    def program_name(self, number) -> str:
        if isinstance(number, str):
            body = number[1:] if number[:1].lower() == "o" else number
            if body.startswith("<"):
                return body[1:-1].replace(" ", "").upper()
            return f"O{int(body.split('.')[0] or '0')}" if body.replace(".", "").isdigit() else body.upper()
        return f"O{int(number)}" if math.isfinite(number) else f"O{number:g}"

    def describe_label(self, label) -> str:
        if isinstance(label, str) and "|" in label:
            name, role = label.split("|", 1)
            return f"the {role} of {name}"
        return super().describe_label(label)

    def label_offsets(self, buffer, label):
        if not (isinstance(label, str) and "|" in label):
            yield from super().label_offsets(buffer, label)
            return
        name = label.split("|", 1)[0]
        pattern = re.compile(_OWORD_LINE + _name_pattern(name))
        for match in pattern.finditer(buffer):
            yield match.start()

    def variable_scope(self, name: str) -> str:
        """#1-#30 and named parameters without a leading '_' belong to the subroutine."""
        if name.startswith("#<"):
            return "global" if name.startswith("#<_") else "local"
        number = name[1:]
        return "local" if number.isdigit() and 1 <= int(number) <= ARGUMENTS else "global"

    g43_takes_the_loaded_tool = True  # G43 without H: the tool in the spindle then (rs274ngc)

    def machine_data(self, name: str) -> tuple[str, bool] | None:
        """The numbered parameters of the offsets (G92's, then G54-G59.3's, see
        :meth:`IsoFrontend.machine_data`)."""
        return numbered_machine_data(name, _LINUXCNC_MACHINE_DATA)

    def unset_is_vacant(self, name: str) -> bool:
        """A named parameter that was never set does not exist (reading it is an error)."""
        return name.startswith("#<")

    def system_variable(self, name: str, state):
        if name == "#0":
            return VACANT
        if name.startswith("#<_"):
            return self._predefined(name[3:-1], state)
        if not name[1:].isdigit():
            return None
        number = int(name[1:])
        if 5420 <= number <= 5422:
            value = state.position.get("XYZ"[number - 5420])
            return value
        if number == 5400:
            return float(state.tool_in_spindle) if isinstance(state.tool_in_spindle, float) else None
        return None

    @staticmethod
    def _predefined(name: str, state):
        modal = state.modal
        if name in ("x", "y", "z"):
            return state.position.get(name.upper())
        if name == "metric":
            return 1.0 if modal.get("units") == "mm" else 0.0
        if name == "imperial":
            return 1.0 if modal.get("units") == "inch" else 0.0
        if name == "absolute":
            return 1.0 if modal.get("distance") == "absolute" else 0.0
        if name == "incremental":
            return 1.0 if modal.get("distance") == "incremental" else 0.0
        if name in ("value", "value_returned"):
            return VACANT
        return VACANT if not name.startswith("ini[") and not name.startswith("hal[") else None

    def program_context(self, source) -> Context:
        """LinuxCNC's tool table (``tool.tbl``) beside the program; the O-word structure of
        the program is checked here too, once, before it runs."""
        context = Context()
        self.structure_notes = oword_structure(source.buffer)
        table = None
        if source.path is not None:
            table = next((candidate for candidate in source.path.parent.iterdir() if candidate.name.lower() == "tool.tbl"), None)
        if table is not None:
            context.tools = read_tool_table(table.read_text(encoding="utf-8", errors="replace"))
        return context


_REMAPPABLE = re.compile(r"G\d{1,2}(?:\.\d)?")  # the range of G codes a configuration may remap (one decimal at most)

_OPENERS = {"SUB": "sub", "IF": "if", "WHILE": "while", "DO": "do", "REPEAT": "repeat"}
_CLOSERS = {"ENDSUB": "sub", "ENDIF": "if", "ENDWHILE": "while", "ENDREPEAT": "repeat"}


def oword_structure(buffer) -> dict[int, list[ir.Note]]:
    """O-word lines that do not pair up as RS274NGC requires, which its interpreter refuses
    before it runs them: a closing or middle O-word with no open construct of the same
    name, a subroutine defined inside another, an O-name opening two constructs in one
    subroutine, constructs never closed. Only lines that start with an O-word are read."""
    notes: dict[int, list[ir.Note]] = {}
    stack: list[tuple[str, str, int, Span]] = []  # (kind, name, line, span)
    opened: list[dict[str, int]] = [{}]  # per subroutine level: name -> line that opened it

    def report(span: Span, message: str) -> None:
        notes.setdefault(span.line, []).append(ir.Note("linuxcnc.oword-structure", message, span))

    pattern = re.compile(_OWORD_LINE)
    line, counted = 1, 0
    for match in pattern.finditer(buffer):
        start = match.start()
        newline = buffer.find(b"\n", start)
        raw = bytes(buffer[start : len(buffer) if newline < 0 else newline])
        line += bytes(buffer[counted:start]).count(b"\n")  # a file may be an mmap: count piecewise
        counted = start
        for read in read_line(decode_line(raw), line):
            for item in read.items:
                if isinstance(item, OWord):
                    _pair(item, Span(line, item.start + 1, line, item.end + 1), stack, opened, report)
    for kind, name, _line, span in stack:
        report(span, f"{name} {kind} is never closed (no {name} end{kind if kind != 'do' else ''}{' or ' + name + ' while' if kind == 'do' else ''}): "
                     "LinuxCNC stops when it looks for it")
    return notes


def _pair(oword: OWord, span: Span, stack, opened, report) -> None:
    name, keyword = oword.name, oword.keyword
    if keyword == "WHILE" and stack and stack[-1][:2] == ("do", name):
        stack.pop()
        return
    if keyword in _OPENERS:
        kind = _OPENERS[keyword]
        if kind == "sub" and any(entry[0] == "sub" for entry in stack):
            report(span, f"{name} sub is defined inside another subroutine: LinuxCNC refuses nested subroutine definitions")
        scope = opened[-1]
        if kind != "sub" and name in scope:
            report(span, f"{name} already opens the construct in line {scope[name]}: LinuxCNC refuses a duplicate O-word label")
        scope.setdefault(name, span.line)
        stack.append((kind, name, span.line, span))
        if kind == "sub":
            opened.append({})
        return
    if keyword in _CLOSERS:
        kind = _CLOSERS[keyword]
        if stack and stack[-1][:2] == (kind, name):
            stack.pop()
            if kind == "sub" and len(opened) > 1:
                opened.pop()
            return
        report(span, f"{name} {keyword.lower()} closes no open {name} {kind}" + (f" (the innermost open construct is {stack[-1][1]} {stack[-1][0]})" if stack else "")
               + ": LinuxCNC stops here")
        return
    if keyword == "RETURN":  # rs274 takes a return of any label inside a subroutine definition
        if not any(entry[0] == "sub" for entry in stack):
            report(span, f"{name} return is not in a subroutine definition: LinuxCNC stops here")
        return
    wanted = {"ELSEIF": ("if",), "ELSE": ("if",), "BREAK": ("while", "do", "repeat"), "CONTINUE": ("while", "do", "repeat")}.get(keyword)
    if wanted is not None and not any(entry[0] in wanted and entry[1] == name for entry in stack):
        report(span, f"{name} {keyword.lower()} is outside any {name} {' / '.join(wanted)}: LinuxCNC stops here")


def _oword_name(raw: bytes) -> str:
    text = raw.decode("ascii", "replace")
    return "o" + (text.replace(" ", "").replace("\t", "").lower() if text.startswith("<") else str(int(text)))


_TOOL_WORD = re.compile(r"([TPDZXYIJQ])\s*([-+]?(?:\d+\.?\d*|\.\d+))", re.IGNORECASE)


def read_tool_table(text: str) -> dict[int, Tool]:
    """``T1 P1 D6.0 Z-12.5 ;comment`` lines: tool number, pocket, diameter, length offset Z."""
    tools = {}
    for line in text.splitlines():
        code = line.split(";", 1)[0]
        words = {letter.upper(): float(value) for letter, value in _TOOL_WORD.findall(code)}
        if "T" not in words or not all(map(math.isfinite, words.values())):
            continue
        number = int(words["T"])
        diameter = words.get("D")
        tools[number] = Tool(number, radius=None if diameter is None else diameter / 2.0, length=words.get("Z"))
    return tools


def setup(settings, detection, project) -> DialectSetup:
    machine = settings.machine or project.machine.kind or detection.machine or "mill"
    table = linuxcnc_table(machine)
    lowering = LinuxcncLowering(table, project.machine.remaps)
    limits = {"d_register_max": 99999.0, "h_register_max": 99999.0, "tool_number_max": 99999.0}
    # LinuxCNC refuses an arc whose end radius differs from its start radius by more than 0.001 in
    # (0.0254 mm) and by more than 0.1 % of the start radius (found by running rs274)
    return DialectSetup(LinuxcncFrontend(lowering), table.power_on, table.cycles, None, machine,
                        dict(table.words.get("incremental_twins", {})), 0.0, 0.0, limits, arc_tolerance=_ARC_TOLERANCE,
                        lengths_by_set_up=True)  # M6 applies no length; tools touched off in the work offset have none
