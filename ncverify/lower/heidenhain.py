"""Stage 2 for HEIDENHAIN TNC 620 Klartext: blocks into the IR, and the dialect's frontend.

Facts come from ``shared/reference/heidenhain-tnc620-a.md`` / ``-b.md`` (seed line
numbers in the comments and in ``dialects/heidenhain/cycles.toml``).

Klartext constructs whose effect depends on state the lowering cannot see are IR
operations the interpreter runs with that state: the pole ``CC`` and the moves about it
(``ir.Pole``, ``ir.PoleArc``, ``ir.TangentArc``, ``ir.PolarMove``), a label call that is a
section repeat or a subprogram call (``ir.LabelCall``), the end of a program file
(``ir.ProgramEnd``); ``CYCL DEF`` is an ``ir.CycleDefine`` the dialect's run-time module
runs (DEF-active cycles act at once, the others wait for their call); statements no other
dialect has (``CYCL CALL``, ``TRANS``, ``PATTERN DEF``, ...) are operations of their own type
(``ir.CallActiveCycle``, ``ir.Transformation``, ``ir.PatternDef``, ...: ``ir.DialectStatement``) run by
:mod:`ncverify.interpret.heidenhain.runtime`. Everything else is
plain IR: ``L`` is a ``Move``, ``R0/RL/RR`` a ``CutterComp``, ``M3/M4/M5`` a ``Spindle``, ``TOOL CALL`` a tool change
with the length compensation Klartext applies by itself, ``FN 9``-``FN 12`` conditional
jumps, Q/QL/QR parameters ``Assign``.
"""
from __future__ import annotations

import re
from functools import cache

from .. import ir, values
from ..context import Context, Stock, Tool, tool_value_problem, tools_called_in
from ..cycle_models import load_cycle_table
from ..dependencies import note_file
from ..dialect import DialectSetup
from ..read.heidenhain import Cursor, ReadError, continues as _continues, split
from ..read.heidenhain_runs import is_plain_line, read_plain_run
from ..source import Span, letter_led

_AXES = ("X", "Y", "Z", "A", "B", "C", "U", "V", "W")
_TOOL_AXIS_PLANE = {"Z": "xy", "X": "yz", "Y": "zx"}
_FN_ARITHMETIC = {1: "+", 2: "-", 3: "*", 4: "/"}
_FN_CONDITION = {9: "EQ", 10: "NE", 11: "GT", 12: "LT"}
_CONDITION_WORDS = {"EQU": "EQ", "NE": "NE", "GT": "GT", "LT": "LT"}
# Statements of _UNMODELLED that may change a preset, a datum, the tool data or the
# kinematics (a probing cycle sets presets): after them nothing is placed on the blank.
_CHANGES_STATE = frozenset({"TCH", "FUNCTION", "SPEC", "TABDATA", "PRESET", "POLARKIN", "SYSCALL"})
_FN_WRITES = frozenset({17, 27})  # FN 17: SYSWRITE (tool data, presets...), FN 27: TABWRITE
# Statements that read fine but whose effect is not modelled: (affects position?, what).
_UNMODELLED = {
    "TCH": (True, "TCH PROBE (a touch-probe cycle)"),
    "FUNCTION": (False, "FUNCTION"), "SPEC": (False, "SPEC FCT"), "DECLARE": (False, "DECLARE"),
    "SEL": (False, "SEL"), "GLOBAL": (False, "GLOBAL DEF"),
    "FK": (True, "FK free contour programming"), "FPOL": (False, "FPOL"), "FL": (True, "FK free contour programming"),
    "FLT": (True, "FK free contour programming"), "FC": (True, "FK free contour programming"), "FCT": (True, "FK free contour programming"),
    "FSELECT": (True, "FK free contour programming"), "LN": (True, "LN (3-D line with surface normal)"), "WAIT": (False, "WAIT"),
    "TABDATA": (False, "TABDATA"), "OPEN": (False, "OPEN FILE"), "PRESET": (True, "PRESET"), "MONITORING": (False, "MONITORING"),
    "POLARKIN": (True, "POLARKIN"), "LIFTOFF": (False, "LIFTOFF"), "SYSCALL": (False, "SYSCALL"),
}
# The common motion lines of CAM output, read without the tokenizer (KlartextLowering._fast_motion):
# [block number] L / CC / C / CR / CT, then words apart by blanks, each a letter run with an
# optional sign and number written as the tokenizer reads them; which runs and forms a
# function takes is sorted out word by word, anything else goes the general way.
_FAST_WORD = rb"(I?[XYZABCUVW]|RL|RR|R|DR|FMAX|F|M)([+-]?)(\d+(?:\.\d*|,\d+)?|\.\d+)?"
_FAST_LINE = re.compile(rb"[ \t]*(?:\d+[ \t]+)?(L|CC|CR|CT|C)((?:[ \t]+" + _FAST_WORD + rb")*)[ \t\r]*")
_FAST_WORDS = re.compile(_FAST_WORD)
_CIRCLE_EXTRA = {"C": ("DR", "R"), "CR": ("DR", "R"), "CT": ("R",)}  # words a circle takes beyond those of a line
_FAST_AXIS_WORDS = {prefix.encode() + axis.encode(): (axis, prefix == "I") for axis in _AXES for prefix in ("", "I")}
_M_SPINDLE = {3.0: "cw", 4.0: "ccw", 5.0: "off", 13.0: "cw", 14.0: "ccw", 19.0: "orient"}
_M_COOLANT = {7.0: "mist", 8.0: "flood", 9.0: "off", 13.0: "flood", 14.0: "flood"}
_M_STOP = {0.0: "stop", 1.0: "optional", 2.0: "end", 30.0: "end"}
# M functions rules watch: M94 (modal rotary axis display) after cycle 19, M136/M137 (feed
# per revolution on/off) at cycle 202 (seed L8095, L1890-1897).
_M_WATCHED = frozenset({94.0, 136.0, 137.0})


def _tool_call_feed(state):
    """``F AUTO``: the feed of the TOOL CALL in force, unknown (never a free parameter a
    witness could choose) when the tool call gave none."""
    feed = state.klartext.tool_feed
    return feed if feed is not None else values.fresh("FAUTO", 0.0)


_TOOL_CALL_FEED = ir.MachineValue("the feed of the TOOL CALL (F AUTO)", _tool_call_feed)


@cache
def _function_result(function: int) -> ir.MachineValue:
    """The result of FN ``function`` that reads the machine (FN 18 SYSREAD ...): unknown,
    never a free parameter a witness could choose."""
    return ir.MachineValue(f"the result of FN {function}", lambda _state: values.fresh(f"FN{function}"))


class KlartextLowering:
    """Turns one logical block into IR blocks."""

    def __init__(self, tool_names: dict | None = None):
        self.tool_names = tool_names if tool_names is not None else {}
        self._begun: dict = {}  # file -> the last BEGIN PGM read in it (lines are read in order before any jump)

    def lower(self, raw: bytes, line: int, path: str | None) -> list[ir.Block]:
        block = self._fast_motion(raw, line, path)
        return [block if block is not None else self._general(raw, line, path)]

    def _fast_motion(self, raw: bytes, line: int, path) -> ir.Block | None:
        """``12 L X+10.5 IY-3 Z+0 RR F500 M3``, ``CC X.. Y..``, ``C X.. Y.. DR-``, ``CR X.. Y..
        R+6 DR-``, ``CT ..`` (the bulk of CAM output) without the tokenizer, into the blocks
        the general path makes of them (tests/test_heidenhain_fast_paths.py); None when the
        line has another form, which the general path then reads."""
        match = _FAST_LINE.fullmatch(raw)
        if match is None:
            return None
        function = match.group(1).decode()
        words = _motion_found()
        extra = _CIRCLE_EXTRA.get(function, ())
        last = match.end(1)
        for word in _FAST_WORDS.finditer(raw, match.start(2), match.end(2)):
            if not _fast_word(words, word, extra, line, path):
                return None
            last = word.end()
        begin = match.start(1) + 1
        span = Span(line, begin, line, last + 1, path)
        block = ir.Block(line, len(raw) - len(raw.lstrip()) + 1, len(raw.rstrip()) + 1, [])
        try:
            if function == "L":
                self._line_ops(block, words, span)
            elif function == "CC":
                self._pole_ops(block, words, span)
            else:
                self._circle_ops(block, function, words, span)
        except ReadError:
            return None
        return block

    def _general(self, raw: bytes, line: int, path: str | None) -> ir.Block:
        block = ir.Block(line, 1, max(len(raw.split(b"\n", 1)[0]), 1) + 1, [])
        try:
            text = split(raw, line, path)
        except ReadError as error:
            block.notes.append(ir.Note("core.syntax", str(error), error.span))
            return block
        block.start_column, block.end_column = text.first_column, max(text.end_column, text.first_column + 1)
        block.comments = tuple(text.comments)
        tokens = text.tokens
        end_span = Span(line, block.end_column, line, block.end_column, path)
        cursor = Cursor(tokens, end_span)
        if cursor.take_symbol("/"):
            block.skippable = True
        if cursor.peek() is not None and cursor.peek().kind == "number":
            cursor.next()  # the block number
        if cursor.take_symbol("/"):
            block.skippable = True
        if cursor.at_end():
            return block
        try:
            self._statement(cursor, block, path)
            if not cursor.at_end():
                token = cursor.peek()
                raise ReadError(f"unexpected {token.text!r} at the end of the block", token.span)
        except ReadError as error:
            block.ops = []
            block.notes.append(ir.Note("core.syntax", str(error), error.span))
        return block

    # ------------------------------------------------------------------ statements

    def _statement(self, cursor: Cursor, block: ir.Block, path) -> None:
        if cursor.take_symbol("*"):
            cursor.index = len(cursor.tokens)  # a structure block: "* - text"
            return
        token = cursor.peek()
        if token.kind != "name":
            raise ReadError(f"a Klartext block cannot start with {token.text!r}", token.span)
        word = token.text
        handler = _STATEMENTS.get(word)
        if handler is not None:
            handler(self, cursor, block, path)
            return
        if word in ("Q", "QL", "QR", "QS"):
            self._assignment(cursor, block)
            return
        if word == "GLOBAL" and cursor.is_name("DEF", ahead=1):
            self._global_def(cursor, block)
            return
        if word == "SEL" and cursor.is_name("CONTOUR", ahead=1):
            self._select_contour(cursor, block)
            return
        if word == "DECLARE" and cursor.is_name("CONTOUR", ahead=1):
            self._declare_contour(cursor, block)
            return
        if word == "QC":  # a contour formula QC10 = ( QC1 | QC2 ) \ QC3: which area the cycles clear, no motion (reference B 6.28)
            cursor.index = len(cursor.tokens)
            return
        if word == "SEL" and cursor.is_name("PATTERN", ahead=1):
            self._select_pattern(cursor, block)
            return
        if word == "PLANE":  # tilting the working plane: the frame is unknown until PLANE RESET
            start = cursor.next().span
            reset = cursor.take_name("RESET") is not None
            cursor.index = len(cursor.tokens)
            block.ops.append(ir.Transformation(cursor.rest_span(start), {"what": "PLANE"} if reset else {"what": "PLANE", "tilt": 1.0}))
            return
        if word in _UNMODELLED:
            affects_position, what = _UNMODELLED[word]
            start = cursor.next().span
            cursor.index = len(cursor.tokens)
            span = cursor.rest_span(start)
            affects = (("position",) if affects_position else ()) + (("state",) if word in _CHANGES_STATE else ())
            block.ops.append(ir.Unsupported(span, f"{what} is read but not modelled", affects))
            if affects_position:
                block.notes.append(ir.Note("core.unsupported-code", f"{what} is read but not modelled; the tool position after it is unknown, so checks that depend on it answer unknown", span))
            return
        raise ReadError(f"{word!r} does not start a Klartext block", token.span)

    def _begin(self, cursor, block, path):
        cursor.expect_name("BEGIN")
        cursor.expect_name("PGM")
        block.program_start = self._program_name(cursor)
        self._begun[path] = block.program_start.upper()
        unit = cursor.take_name("MM", "INCH")
        if unit is not None:
            block.ops.append(ir.SetModal(unit.span, "units", "mm" if unit.text == "MM" else "inch"))

    def _end(self, cursor, block, path):
        start = cursor.expect_name("END").span
        cursor.expect_name("PGM")
        name = self._program_name(cursor).upper()
        cursor.take_name("MM", "INCH")
        span = cursor.rest_span(start)
        begun = self._begun.get(path)
        if begun is not None and name != begun:
            block.notes.append(ir.Note("heidenhain.program-name-mismatch", f"END PGM {name} closes program {begun}: BEGIN PGM and END PGM must name the same program", span))
        block.ops.append(ir.ProgramEnd(span))

    @staticmethod
    def _program_name(cursor: Cursor, up_to_unit: bool = True) -> str:
        """A program name or path: letters, digits and the symbols a path holds, up to the
        unit (a called program's path takes the whole block: ``...\\90H7-60mm.H``)."""
        parts = []
        while not cursor.at_end() and not (up_to_unit and cursor.is_name("MM", "INCH") and cursor.index + 1 == len(cursor.tokens)):
            token = cursor.next()
            parts.append(token.text.strip('"'))
        if not parts:
            raise ReadError("the program name is missing", cursor.here())
        return "".join(parts)

    def _blk(self, cursor, block, path):
        cursor.expect_name("BLK")
        cursor.expect_name("FORM")
        cursor.index = len(cursor.tokens)  # the stock is read by program_context

    def _tool(self, cursor, block, path):
        start = cursor.expect_name("TOOL").span
        kind = cursor.expect_name("CALL", "DEF")
        number = self._tool_number(cursor)
        if kind.text == "DEF":
            cursor.index = len(cursor.tokens)
            if number is not None:
                block.ops.append(ir.ToolSelect(cursor.rest_span(start), number))
            return
        axis = cursor.take_name("X", "Y", "Z")
        words = self._tool_words(cursor)
        span = cursor.rest_span(start)
        if "S" in words:
            block.ops.append(ir.SetSpindleSpeed(span, words["S"]))
        if number is not None:
            block.ops.append(ir.ToolSelect(span, number))
            block.ops.append(ir.ToolLength(span, False))
            block.ops.append(ir.ToolChange(span))
            block.ops.append(ir.ToolLength(span, True, number))
        if number is not None or "DR" in words or "DL" in words:  # a call without a number gives the tool in the spindle new deltas
            block.ops.append(ir.ToolDelta(span, words.get("DR", 0.0), words.get("DL", 0.0)))  # on top of the table's R + DR, L + DL
        if axis is not None:
            block.ops.append(ir.SetModal(axis.span, "plane", _TOOL_AXIS_PLANE[axis.text]))
        if "F" in words:
            block.ops.append(ir.ToolFeed(span, words["F"]))

    def _tool_number(self, cursor: Cursor):
        token = cursor.peek()
        if token is None:
            return None
        if token.kind == "number":
            cursor.next()
            return float(token.text.replace(",", "."))
        if token.kind == "string":
            cursor.next()
            name = token.text.strip('"')
            return self.tool_names.get(name.upper(), name)
        if cursor.is_name("Q", "QL", "QR"):
            return cursor.parameter()
        if cursor.is_name("QS"):
            cursor.parameter()
            return None
        return None

    @staticmethod
    def _tool_words(cursor: Cursor) -> dict:
        words = {}
        while not cursor.at_end():
            name = cursor.take_name()
            if name is None:
                raise ReadError("expected a TOOL CALL word (S, F, DL, DR, DR2)", cursor.here())
            if name.text == "DR" and cursor.peek() is not None and cursor.peek().text == "2" and cursor.peek(1) is not None and cursor.peek(1).text in "+-":
                cursor.next()
            if name.text in ("S", "F", "DL", "DR", "DR2", "DL2"):
                if cursor.take_name("AUTO"):
                    continue
                words[name.text] = cursor.value()
            elif name.text in ("SPINDLE", "DR2TABLE", "DQ", "DS"):
                cursor.index = len(cursor.tokens)
            else:
                raise ReadError(f"{name.text!r} is not a TOOL CALL word", name.span)
        return words

    # ------------------------------------------------------------------ motion

    def _motion_words(self, cursor: Cursor, block: ir.Block, allowed_extra=()) -> dict:
        """The words after a path function: coordinates (``I`` = incremental), R0/RL/RR,
        F / FMAX / FAUTO, M functions, and the ``extra`` words of the function."""
        found = _motion_found()
        while not cursor.at_end():
            token = cursor.next()
            if token.kind != "name":
                raise ReadError(f"unexpected {token.text!r}", token.span)
            word = token.text
            if word in _AXES or (word[:1] == "I" and word[1:] in _AXES):
                axis = word[-1]
                value = cursor.value()
                found["targets"][axis] = value
                found["columns"][axis] = (token.span.column - 1, cursor.tokens[cursor.index - 1].span.end_column - 1)
                if word[0] == "I":
                    found["incremental"].add(axis)
            elif word == "R" and _bare(cursor) and "R" not in allowed_extra:
                pass  # a bare 'R' (older exports): the compensation stays as it is
            elif word == "M" and _bare(cursor):
                pass  # a bare 'M' (older exports): no M function
            elif word in ("RL", "RR"):
                found["comp"] = ("left" if word == "RL" else "right", token.span)
            elif word == "R" and cursor.peek() is not None and cursor.peek().text == "0":
                cursor.next()
                found["comp"] = ("off", token.span)
            elif word == "FMAX":
                found["rapid"] = True
            elif word in ("FAUTO", "FU", "FZ"):
                found["feed"] = _TOOL_CALL_FEED if word == "FAUTO" else None
                if word != "FAUTO":
                    cursor.value()
            elif word == "F" and _bare(cursor, ("MAX", "AUTO")):
                pass  # a bare 'F' (older exports): the feed stays as it is
            elif word == "F":
                if cursor.take_name("MAX"):
                    found["rapid"] = True
                elif cursor.take_name("AUTO"):
                    found["feed"] = _TOOL_CALL_FEED
                else:
                    found["feed"] = cursor.value()
            elif word == "M":
                number, span = cursor.expect_number()
                found["m"].append((number, span))
                if number == 140.0 and cursor.take_name("MB"):
                    found["extra"]["MB"] = "MAX" if cursor.take_name("MAX") else cursor.value()
            elif word in allowed_extra:
                if word in ("DR",):
                    sign = cursor.take_symbol("+", "-")
                    if sign is None:
                        raise ReadError("DR needs + or -", cursor.here())
                    found["extra"]["DR"] = sign.text
                else:
                    found["extra"][word] = cursor.value()
            else:
                raise ReadError(f"{word!r} is not a word of this block", token.span)
        return found

    def _line(self, cursor, block, path):
        start = cursor.expect_name("L")
        words = self._motion_words(cursor, block)
        self._line_ops(block, words, cursor.rest_span(start.span))

    def _line_ops(self, block, words, span):
        self._emit_motion(block, words, span, "rapid" if words["rapid"] else "linear")

    def _emit_motion(self, block, words, span, kind, arc_op=None):
        m_words = words["m"]
        machine = bool(m_words) and any(number in (91.0, 92.0) for number, _ in m_words)
        if words["feed"] is not None:
            block.ops.append(ir.SetFeed(span, words["feed"]))
        if m_words:
            self._m_before(block, m_words)
        if words["comp"] is not None:
            block.ops.append(ir.CutterComp(words["comp"][1], words["comp"][0], only_if_changed=True))
        if arc_op is not None:
            block.ops.append(arc_op)
        elif words["targets"]:
            if machine:
                block.ops.append(ir.MachineMove(span, dict(words["targets"]), zero_is_reference=False))  # M91/M92: positions of the machine maker's choosing
            elif kind == "rapid" and "Z" in words["targets"] and set(words["targets"]) <= {"X", "Y", "Z"}:
                block.ops.append(ir.Lift(span, _written(words)))
            else:
                block.ops.append(ir.Move(span, kind, dict(words["targets"]), None, {}, frozenset(words["incremental"]), words["columns"]))
        if "MB" in words["extra"]:
            block.ops.append(ir.Retract(span, words["extra"]["MB"]))
        calls = bool(m_words) and any(number in (89.0, 99.0) for number, _ in m_words)
        if words["targets"] and not calls and not machine:
            plane = [axis for axis in ("X", "Y") if axis in words["targets"]]
            relative = any(axis in words["incremental"] for axis in plane)
            block.ops.append(ir.PositioningBlock(span, {"fed": 0.0 if kind == "rapid" else 1.0, "plane": float(len(plane)), "relative": float(relative)}))
        if m_words:
            self._m_after(block, m_words, span)

    @staticmethod
    def _m_before(block, m_words):
        """M functions that act at the start of the block (spindle and coolant on)."""
        for number, span in m_words:
            if number in _M_SPINDLE and _M_SPINDLE[number] != "off":
                block.ops.append(ir.Spindle(span, _M_SPINDLE[number], apart=True))
            if number in _M_COOLANT and _M_COOLANT[number] != "off":
                block.ops.append(ir.Coolant(span, _M_COOLANT[number]))

    @staticmethod
    def _m_after(block, m_words, span):
        """M functions that act at the end of the block: spindle and coolant off, cycle
        calls, stops (the TNC fixes for each M function when it acts)."""
        for number, m_span in m_words:
            if _M_SPINDLE.get(number) == "off":
                block.ops.append(ir.Spindle(m_span, "off", apart=True))
            if _M_COOLANT.get(number) == "off":
                block.ops.append(ir.Coolant(m_span, "off"))
        for number, m_span in m_words:
            if number in _M_WATCHED:
                block.ops.append(ir.MFunction(m_span, number))
        for number, m_span in m_words:
            if number == 99.0:
                block.ops.append(ir.CallActiveCycle(m_span, {"how": "M99"}))
            elif number == 89.0:
                block.ops.append(ir.CallActiveCycle(m_span, {"how": "M89"}))
        for number, m_span in m_words:
            if number in _M_STOP:
                block.ops.append(ir.Stop(m_span, _M_STOP[number]))

    def _pole(self, cursor, block, path):
        start = cursor.expect_name("CC")
        words = self._motion_words(cursor, block)
        self._pole_ops(block, words, cursor.rest_span(start.span))

    @staticmethod
    def _pole_ops(block, words, span):
        block.ops.append(ir.Pole(span, _written(words)))

    def _circle(self, cursor, block, path):
        """``C`` arc about CC, ``CR`` arc by radius, ``CT`` tangential arc."""
        start = cursor.next()
        words = self._motion_words(cursor, block, _CIRCLE_EXTRA[start.text])
        self._circle_ops(block, start.text, words, cursor.rest_span(start.span))

    def _circle_ops(self, block, function: str, words, span):
        direction = words["extra"].get("DR")
        if words["rapid"]:
            _rapid_arc(block, span)
        if function == "CR":
            if "R" not in words["extra"] or direction is None:
                raise ReadError("CR needs a radius R and a direction DR+ or DR-", span)
            kind = "arc_ccw" if direction == "+" else "arc_cw"
            arc = ir.Move(span, kind, dict(words["targets"]), {"R": words["extra"]["R"]}, {}, frozenset(words["incremental"]), words["columns"])
            self._emit_motion(block, words, span, kind, arc)
            return
        params = _written(words)
        if function == "C":
            params["DR"] = 1.0 if direction == "+" else -1.0 if direction == "-" else 0.0
            self._emit_motion(block, words, span, None, ir.PoleArc(span, params))
        else:
            self._emit_motion(block, words, span, None, ir.TangentArc(span, params))

    def _polar(self, cursor, block, path):
        start = cursor.next()
        extra = ("PR", "IPR", "PA", "IPA", "DR")
        words = self._motion_words(cursor, block, extra)
        params = dict(words["extra"])
        if "DR" in params:
            params["DR"] = 1.0 if params["DR"] == "+" else -1.0
        params.update(_written(words))
        kind = "arc" if start.text == "CP" else ("rapid" if words["rapid"] else "linear")
        span = cursor.rest_span(start.span)
        if words["rapid"] and start.text == "CP":
            _rapid_arc(block, span)
        self._emit_motion(block, words, span, None, ir.PolarMove(span, kind, params))

    def _corner(self, cursor, block, path):
        """RND / CHF between two contour elements: the corner is cut off, the end point stays."""
        start = cursor.next()
        cursor.take_name("R")
        cursor.value()
        block.ops.append(ir.CornerRounding(start.span))
        words = self._motion_words(cursor, block)
        if words["feed"] is not None:
            block.ops.append(ir.SetFeed(cursor.rest_span(start.span), words["feed"]))

    def _approach(self, cursor, block, path):
        """APPR / DEP: the tool reaches the written point over an auxiliary path."""
        start = cursor.next()
        style = cursor.take_name("LT", "LN", "CT", "LCT", "PLT", "PLN", "PCT", "PLCT")
        if style is None:
            raise ReadError("APPR/DEP needs LT, LN, CT or LCT", cursor.here())
        words = self._motion_words(cursor, block, ("LEN", "CCA", "R", "PR", "PA", "DR"))
        span = cursor.rest_span(start.span)
        plane = {"X", "Y"}
        block.ops.append(ir.Approach(span))
        if start.text == "DEP":
            words["comp"] = ("off", start.span)  # DEP ends the radius compensation
        if start.text == "DEP" and not plane <= words["targets"].keys():
            self._emit_motion(block, dict(words, targets={}), span, "linear")
            block.ops.append(ir.Unsupported(span, "DEP without its end point", ("position",)))
            return
        self._emit_motion(block, words, span, "linear")

    def _m_only(self, cursor, block, path):
        start = cursor.here()
        words = self._motion_words(cursor, block)
        self._emit_motion(block, words, cursor.rest_span(start), "rapid" if words["rapid"] else "linear")

    def _stop(self, cursor, block, path):
        start = cursor.expect_name("STOP").span
        words = self._motion_words(cursor, block)
        self._emit_motion(block, words, cursor.rest_span(start), "linear")
        block.ops.append(ir.Stop(start, "stop"))

    # ------------------------------------------------------------------ labels, calls, parameters

    def _label(self, cursor, block, path):
        start = cursor.expect_name("LBL").span
        label = self._label_value(cursor)
        if label == 0.0:
            block.ops.append(ir.Return(cursor.rest_span(start), local_only=True))
        else:
            block.label = label

    @staticmethod
    def _label_value(cursor: Cursor):
        token = cursor.peek()
        if token is not None and token.kind == "string":
            cursor.next()
            return token.text.strip('"')
        if cursor.is_name("Q", "QL", "QR", "QS"):
            return cursor.parameter()
        number, _span = cursor.expect_number()
        return number

    def _call(self, cursor, block, path):
        start = cursor.expect_name("CALL").span
        what = cursor.expect_name("LBL", "PGM", "CYCLE")
        if what.text == "LBL":
            label = self._label_value(cursor)
            repeat = 0.0
            if cursor.take_name("REP") and not cursor.at_end():
                repeat = cursor.value()
            block.ops.append(ir.LabelCall(cursor.rest_span(start), label, repeat))
            return
        if what.text == "CYCLE":
            cursor.index = len(cursor.tokens)
            block.ops.append(ir.Unsupported(cursor.rest_span(start), "CALL CYCLE", ("position",)))
            return
        name = self._program_name(cursor, up_to_unit=False)
        block.ops.append(ir.Call(cursor.rest_span(start), "subprogram", _called_name(name)))

    def _assignment(self, cursor, block):
        start = cursor.here()
        target = cursor.parameter()
        cursor.expect_symbol("=")
        if target.name and isinstance(target.name, str) and target.name.startswith("QS"):
            cursor.index = len(cursor.tokens)  # string formulas: no numeric effect
            return
        value = cursor.expression()
        block.ops.append(ir.Assign(cursor.rest_span(start), target, value))

    def _fn(self, cursor, block, path):
        start = cursor.expect_name("FN").span
        number, _span = cursor.expect_number()
        cursor.expect_symbol(":")
        function = int(number)
        if function in _FN_CONDITION:
            cursor.expect_name("IF")
            left = cursor.value()
            word = cursor.expect_name(*_CONDITION_WORDS)
            right = cursor.value()
            cursor.expect_name("GOTO")
            cursor.expect_name("LBL")
            label = self._label_value(cursor)
            block.ops.append(ir.Jump(cursor.rest_span(start), label, ir.Binary(_CONDITION_WORDS[word.text], left, right)))
            return
        if function == 14:
            cursor.expect_name("ERROR")
            cursor.expect_symbol("=")
            error = cursor.value()
            block.ops.append(ir.Alarm(cursor.rest_span(start), error, "", "error number {number} with FN 14: ERROR"))
            return
        if function in (0, 1, 2, 3, 4, 5, 6, 7, 8, 13):
            target = cursor.parameter()
            cursor.expect_symbol("=")
            value = self._fn_value(function, cursor)
            block.ops.append(ir.Assign(cursor.rest_span(start), target, value))
            return
        if cursor.is_name("Q", "QL", "QR") and cursor.peek(2) is not None and cursor.peek(2).text == "=":
            target = cursor.parameter()
            cursor.index = len(cursor.tokens)
            block.ops.append(ir.Assign(cursor.rest_span(start), target, _function_result(function)))
            return
        cursor.index = len(cursor.tokens)  # FN 15-29 without a result: print, PLC, tables
        if function in _FN_WRITES:
            block.ops.append(ir.Unsupported(cursor.rest_span(start), f"FN {function} (a write to the control's data or tables)", ("state",)))

    @staticmethod
    def _fn_value(function: int, cursor: Cursor):
        if function in (5, 6, 7):
            cursor.take_name("SQRT", "SIN", "COS")
            return ir.Func({5: "SQRT", 6: "SIN", 7: "COS"}[function], (cursor.value(),))
        if function in (8, 13):
            first = cursor.value()
            cursor.take_name("LEN", "ANG")
            second = cursor.value()
            if function == 8:
                return ir.Func("SQRT", (ir.Binary("+", ir.Binary("*", first, first), ir.Binary("*", second, second)),))
            return ir.Func("ATAN2", (second, first))
        first = cursor.value()
        if function == 0:
            return first
        if function == 4:
            cursor.take_name("DIV")
            cursor.take_symbol("/")
        else:
            cursor.expect_symbol(_FN_ARITHMETIC[function])
        return ir.Binary(_FN_ARITHMETIC[function], first, cursor.value())

    # ------------------------------------------------------------------ cycles

    def _cycle(self, cursor, block, path):
        start = cursor.expect_name("CYCL").span
        what = cursor.expect_name("DEF", "CALL")
        if what.text == "CALL":
            self._cycle_call(cursor, block, start)
            return
        number, number_span = cursor.expect_number()
        whole = int(number)
        sub = round((number - whole) * 10)
        if number != whole:
            self._old_cycle(cursor, block, start, whole, sub)
            return
        while not cursor.at_end() and not (cursor.is_name("Q", "QS") and cursor.peek(1) is not None and cursor.peek(1).kind == "number"):
            cursor.next()  # the cycle's name, in the language the control was set to
        params, spans = self._cycle_parameters(cursor)
        block.ops.append(ir.CycleDefine(cursor.rest_span(start), f"heidenhain.{whole}", params, spans))

    def _cycle_parameters(self, cursor) -> tuple[dict, dict]:
        """``Q200=+2 ;comment ~`` lines: values, keywords (AUTO, MAX, PREDEF), strings
        (``QS500="TEXT"``, the texts of 224 and 225)."""
        params, spans = {}, {}
        while not cursor.at_end():
            parameter = cursor.expect_name("Q", "QS")
            token = cursor.next()
            if token.kind != "number":
                raise ReadError(f"expected a parameter number after {parameter.text}", token.span)
            name = f"{parameter.text}{token.text}"
            cursor.take_symbol("=")  # 'Q357+0.2' without '=' (a manual OCR defect, reference A §11)
            keyword = cursor.take_name("AUTO", "MAX", "FAUTO", "FMAX", "PREDEF", "FU", "FZ")
            if keyword is not None:
                params[name] = "FMAX" if keyword.text in ("MAX", "FMAX") else keyword.text.replace("FAUTO", "AUTO")
                if keyword.text in ("FU", "FZ") and not cursor.is_name("Q"):
                    cursor.value()
            elif cursor.peek() is not None and cursor.peek().kind == "string":
                params[name] = cursor.next().text.strip('"')
            else:
                params[name] = cursor.value()
                while not cursor.at_end() and not cursor.is_name("Q", "QS"):
                    cursor.next()  # a tolerance after a diameter (Q335=10H7)
            spans[name] = cursor.rest_span(parameter.span)
        return params, spans

    def _old_cycle(self, cursor, block, start, number, sub):
        """``CYCL DEF 7.0 DATUM SHIFT`` / ``7.1 X+60``: sub-block 0 names the cycle, the others
        carry its words (reference A §8.3-8.8)."""
        words, spans, program = {}, {}, None
        if sub == 0:
            cursor.index = len(cursor.tokens)
        elif number == 12:  # CYCL DEF 12.1 PGM name: the program the cycle call runs (reference B 6.31)
            cursor.take_name("PGM")
            program = _called_name(self._program_name(cursor, up_to_unit=False))
        elif number == 14:  # CYCL DEF 14.1 CONTOUR LABEL1 /2 /3: the label numbers in order
            labels = [token for token in cursor.tokens[cursor.index:] if token.kind in ("number", "string")]
            for index, token in enumerate(labels):
                words[f"L{index}"] = token.text.strip('"') if token.kind == "string" else float(token.text)
            cursor.index = len(cursor.tokens)
        else:
            while not cursor.at_end():
                token = cursor.next()
                if token.kind == "symbol" and token.text == "#":
                    words["#"] = cursor.value()
                    continue
                if token.kind != "name":
                    continue
                name = token.text
                if number == 8 and name in _AXES:
                    words[name] = 1.0  # CYCL DEF 8.1 X Y: the axes mirrored
                    spans[name] = token.span
                    continue
                if cursor.peek() is not None and (cursor.peek().kind == "number" or cursor.is_symbol("+", "-") or cursor.is_name("Q", "QL", "QR")):
                    try:
                        words[name] = cursor.value()
                        spans[name] = cursor.rest_span(token.span)
                    except ReadError:
                        pass
        block.ops.append(ir.OldCycle(cursor.rest_span(start), words, spans, int(number), int(sub), program))

    def _cycle_call(self, cursor, block, start):
        how = cursor.take_name("PAT", "POS")
        words = self._motion_words(cursor, block)
        params = {"how": how.text if how is not None else "CALL"}
        if how is not None and how.text == "POS":
            for axis, value in words["targets"].items():
                params[("I" if axis in words["incremental"] else "") + axis] = value
        if words["feed"] is not None:
            params["F"] = words["feed"]
        if words["rapid"]:
            params["F"] = "FMAX"
        span = cursor.rest_span(start)
        self._m_before(block, words["m"])
        block.ops.append(ir.CallActiveCycle(span, params))
        for number, m_span in words["m"]:
            if number in _M_STOP:
                block.ops.append(ir.Stop(m_span, _M_STOP[number]))

    def _pattern(self, cursor, block, path):
        """``PATTERN DEF ~ POS1( X+25 Y+33.5 Z+0 ) ~ ROW1( ... )`` (reference A §4.5)."""
        start = cursor.expect_name("PATTERN").span
        cursor.expect_name("DEF")
        params = {}
        index = 0
        while not cursor.at_end():
            form = cursor.expect_name("POS", "ROW", "PAT", "FRAME", "CIRC", "PITCHCIRC")
            cursor.expect_number()
            cursor.expect_symbol("(")
            params[f"{index}:form"] = form.text
            while not cursor.take_symbol(")"):
                word = cursor.expect_name()
                params[f"{index}:{word.text}"] = cursor.value()
            index += 1
        block.ops.append(ir.PatternDef(cursor.rest_span(start), params))

    def _global_def(self, cursor, block):
        """``GLOBAL DEF 100 GENERAL ~ Q200=+2 ~ ...``: values that cycle parameters written
        PREDEF take (reference A §4.6)."""
        start = cursor.expect_name("GLOBAL").span
        cursor.expect_name("DEF")
        cursor.expect_number()
        while not cursor.at_end() and not (cursor.is_name("Q") and cursor.peek(1) is not None and cursor.peek(1).kind == "number"):
            cursor.next()
        params = self._cycle_parameters(cursor)[0]
        block.ops.append(ir.GlobalDef(cursor.rest_span(start), params))

    def _select_pattern(self, cursor, block):
        """``SEL PATTERN "HOLES.PNT"``: the point table CYCL CALL PAT runs on (reference A §4.5)."""
        start = cursor.expect_name("SEL").span
        cursor.expect_name("PATTERN")
        name = " ".join(token.text.strip('"') for token in cursor.tokens[cursor.index:] if token.kind != "end")
        cursor.index = len(cursor.tokens)
        block.ops.append(ir.SelectPattern(cursor.rest_span(start), {"table": name}))

    def _select_contour(self, cursor, block):
        """``SEL CONTOUR "MODEL"``: the contour of the SL / OCM cycles is described in another
        program (reference B 6.28), which is not run here: the contour is unknown."""
        start = cursor.expect_name("SEL").span
        cursor.index = len(cursor.tokens)
        block.ops.append(ir.SelectContour(cursor.rest_span(start)))

    def _declare_contour(self, cursor, block):
        """``DECLARE CONTOUR QC2 = "121" DEPTH15``: a contour of a contour-definition program
        (reference B 6.28); the contour program itself is not read."""
        start = cursor.expect_name("DECLARE").span
        params = {}
        while not cursor.at_end():
            if cursor.take_name("DEPTH"):
                params["DEPTH"] = cursor.value()
            else:
                cursor.next()
        block.ops.append(ir.DeclareContour(cursor.rest_span(start), params))

    def _contour_def(self, cursor, block, path):
        """``CONTOUR DEF P1 = LBL 1 I2 = LBL 2 V3 = LBL 3``: pockets, islands, voids (reference B §6.29)."""
        start = cursor.expect_name("CONTOUR").span
        if not cursor.take_name("DEF"):
            cursor.index = len(cursor.tokens)
            block.ops.append(ir.Unsupported(cursor.rest_span(start), "CONTOUR statement", ()))
            return
        params = {}
        while not cursor.at_end():
            kind = cursor.expect_name("P", "I", "V")
            number, _span = cursor.expect_number()
            cursor.expect_symbol("=")
            cursor.expect_name("LBL")
            label = self._label_value(cursor)
            params[f"{kind.text}{int(number)}"] = label
            if cursor.take_name("DEPTH"):
                params[f"D{int(number)}"] = cursor.value()
        block.ops.append(ir.ContourDef(cursor.rest_span(start), params))

    def _trans(self, cursor, block, path):
        start = cursor.expect_name("TRANS").span
        what = cursor.expect_name("DATUM", "MIRROR", "ROTATION", "SCALE", "RESET")
        params = {"what": what.text}
        if cursor.take_name("RESET"):
            params["reset"] = 1.0
        else:
            cursor.take_name("AXIS", "TABLE", "COORD")
            while not cursor.at_end():
                word = cursor.expect_name()
                if cursor.is_symbol("+", "-") or (cursor.peek() is not None and cursor.peek().kind == "number") or cursor.is_name("Q", "QL", "QR"):
                    params[word.text] = cursor.value()
                elif what.text == "MIRROR" and word.text in _AXES:
                    params[word.text] = 1.0  # TRANS MIRROR AXIS X: the axes mirrored
        block.ops.append(ir.Transformation(cursor.rest_span(start), params))


def _motion_found() -> dict:
    """What the words of a path function give, as :meth:`KlartextLowering._motion_words` fills it."""
    return {"targets": {}, "incremental": set(), "columns": {}, "m": [], "extra": {}, "feed": None, "rapid": False, "comp": None}


def _fast_word(found: dict, word, extra: tuple, line: int, path) -> bool:
    """Enter one word of a fast motion line (:data:`_FAST_WORDS` match) as
    :meth:`KlartextLowering._motion_words` enters it; False for a word it would read some
    other way or refuse (it is then left to it). Axis words, the most of them, come first."""
    letters, sign, number = word.groups()
    axis_word = _FAST_AXIS_WORDS.get(letters)
    if axis_word is not None:
        if number is None:
            return False
        axis, incremental = axis_word
        found["targets"][axis] = _fast_value(sign, number)
        found["columns"][axis] = word.span()
        if incremental:
            found["incremental"].add(axis)
        return True
    if letters in (b"RL", b"RR", b"FMAX"):
        if sign or number is not None:
            return False
        if letters == b"FMAX":
            found["rapid"] = True
        else:
            found["comp"] = ("left" if letters == b"RL" else "right", Span(line, word.start() + 1, line, word.start() + 3, path))
        return True
    if letters == b"DR":
        if "DR" not in extra or not sign or number is not None:
            return False
        found["extra"]["DR"] = sign.decode()
        return True
    if number is None:
        return False  # a bare letter or a sign without its number
    if letters == b"M":
        if sign or not number.isdigit() or len(number) > 15:  # (M140 MB.. does not get here: MB is no word of the line)
            return False
        found["m"].append((float(number), Span(line, word.start(3) + 1, line, word.end() + 1, path)))
    elif letters == b"F":
        found["feed"] = _fast_value(sign, number)
    elif not sign and number == b"0":  # R0
        found["comp"] = ("off", Span(line, word.start() + 1, line, word.start() + 2, path))
    elif "R" in extra:
        found["extra"]["R"] = _fast_value(sign, number)
    else:
        return False
    return True


def _fast_value(sign: bytes, number: bytes) -> float:
    """A signed number as :meth:`Cursor.value` reads it (a minus multiplies by -1)."""
    value = float(number.replace(b",", b"."))
    return value * -1.0 if sign == b"-" else value


def _bare(cursor: Cursor, keywords=()) -> bool:
    """Is an address letter written without its value (``L X+5 R F M`` in older exports)?"""
    token = cursor.peek()
    return token is None or (token.kind == "name" and token.text not in ("Q", "QL", "QR") + tuple(keywords))


def _called_name(name: str) -> str:
    """A program's name as calls, BEGIN PGM and the subprogram library write it: the file
    name without folder and extension, upper case; a number as the library indexes
    numbered files (``205`` -> ``O205``)."""
    base = re.split(r"[\\/:]", name)[-1]
    base = (base.rsplit(".", 1)[0] if "." in base else base).upper()
    return f"O{int(base)}" if base.isdigit() else base


def _written(words: dict) -> dict:
    """The axis words of a block as written: ``IX`` for an incremental X."""
    return {("I" if axis in words["incremental"] else "") + axis: value for axis, value in words["targets"].items()}


_STATEMENTS = {
    "BEGIN": KlartextLowering._begin, "END": KlartextLowering._end, "BLK": KlartextLowering._blk,
    "TOOL": KlartextLowering._tool, "L": KlartextLowering._line, "CC": KlartextLowering._pole,
    "C": KlartextLowering._circle, "CR": KlartextLowering._circle, "CT": KlartextLowering._circle,
    "LP": KlartextLowering._polar, "CP": KlartextLowering._polar, "RND": KlartextLowering._corner,
    "CHF": KlartextLowering._corner, "APPR": KlartextLowering._approach, "DEP": KlartextLowering._approach,
    "M": KlartextLowering._m_only, "STOP": KlartextLowering._stop, "LBL": KlartextLowering._label,
    "CALL": KlartextLowering._call, "FN": KlartextLowering._fn, "CYCL": KlartextLowering._cycle,
    "PATTERN": KlartextLowering._pattern, "TRANS": KlartextLowering._trans, "CONTOUR": KlartextLowering._contour_def,
}


# --------------------------------------------------------------------------- frontend

_PROGRAM_START = re.compile(rb"(?mi)^[ \t]*\d*[ \t]*BEGIN[ \t]+PGM[ \t]+([^ \t\r\n;]+)")
_TOOL_CALL = re.compile(rb"(?i)\bTOOL[ \t]+CALL\b")
_M_END = re.compile(rb"(?i)\bM(?:30|0?2)(?![0-9])")
_BLK_FORM = re.compile(r"(?mi)^[ \t]*\d*[ \t]*BLK[ \t]+FORM[ \t]+(0\.1|0\.2|CYLINDER)\b([^;\r\n]*)")
_STOCK_WORD = re.compile(r"(?i)\b(I?[XYZ]|D|R|L|DIST|DI)[ \t]*([+-]?[0-9]+(?:[.,][0-9]*)?)")


_TOOL_CALL_NUMBER = letter_led(rb"TOOL\s+CALL\s+(\d+)")
# what leaves the tools a program loads to more than its numbered TOOL CALLs: a tool called
# by name or a Q parameter, a call of another program, a write to a table (FN 17, FN 26-28)
_TOOL_CALL_UNSURE = letter_led(rb"TOOL\s+CALL\s+[\"'Q]", rb"CALL\s+PGM", rb"SEL\s+PGM", rb"PGM\s+CALL", rb"F(?<!\wF)N\s*(?:17|26|27|28)\b",
                               rb"TAB(?:OPEN|WRITE)")


class KlartextFrontend:
    def __init__(self, lowering: KlartextLowering, tool_table: dict[int, Tool] | None = None):
        self.lowering = lowering
        self.tool_table = tool_table or {}

    def blocks(self, raw: bytes, line: int, path: str | None = None) -> list[ir.Block]:
        return self.lowering.lower(raw, line, path)

    @staticmethod
    def continues(raw: bytes) -> bool:
        return _continues(raw)

    def is_plain(self, raw: bytes) -> bool:
        """Could this line be part of a :class:`ir.MoveBatch` (``n L X.. Y.. Z.. [R0] [F..|FMAX]``,
        see :mod:`ncverify.read.heidenhain_runs`)?"""
        return is_plain_line(raw)

    def plain_run(self, buffer, offset: int, line: int, limit: int = 1 << 20) -> ir.MoveBatch | None:
        return read_plain_run(buffer, offset, line, limit)

    def programs(self, buffer) -> list[tuple[str, int]]:
        return [(_called_name(match.group(1).decode("utf-8", "replace")), match.start()) for match in _PROGRAM_START.finditer(buffer)]

    def is_subprogram(self, buffer, start: int, end: int) -> bool:
        """A program with no TOOL CALL and no M2/M30 of its own is written to be called
        (a machining macro such as a face-milling program): its spindle and feed come
        from the caller."""
        return _TOOL_CALL.search(buffer, start, end) is None and _M_END.search(buffer, start, end) is None

    def tape_marks(self, buffer) -> list[int]:
        return []

    def program_name(self, name) -> str:
        return _called_name(name) if isinstance(name, str) else f"{name:g}"

    def describe_label(self, label) -> str:
        return f'LBL "{label}"' if isinstance(label, str) else f"LBL {label:g}"

    def label_offsets(self, buffer, label):
        written = f'"{label}"' if isinstance(label, str) else f"{label:g}"
        pattern = re.compile(rb"(?mi)^[ \t]*\d*[ \t]*LBL[ \t]*" + re.escape(written.encode()) + rb"(?![0-9.])")
        for match in pattern.finditer(buffer):
            yield match.start()

    @staticmethod
    def variable_scope(name: str) -> str:
        """QL parameters belong to one program (reference A §3); Q and QR are global."""
        return "local" if name.startswith("QL") else "global"

    def tools_called(self, source) -> frozenset[int] | None:
        """The tools the program can load (:func:`~ncverify.context.tools_called_in`)."""
        return tools_called_in(source.buffer, _TOOL_CALL_NUMBER, _TOOL_CALL_UNSURE)

    def program_context(self, source) -> Context:
        """The BLK FORM of the program as its stock, TOOL.T beside it as its tools."""
        context = Context()
        context.stock = stock_from_text(source.head(1 << 20))
        tools = dict(self.tool_table)
        if not tools and source.path is not None:
            table = next((candidate for candidate in source.path.parent.iterdir() if candidate.name.upper() == "TOOL.T"), None)
            if table is not None:
                tools, names = read_tool_table(table)
                self.lowering.tool_names.update(names)
        context.tools = tools
        return context


def _round_blank(rest: str, words: dict) -> Stock | None:
    """``BLK FORM CYLINDER Z R.. L.. [DIST..]``: a round blank about the tool axis Z through
    the datum, its top at DIST (default 0). A cylinder along X or Y, or a hollow one (an
    inner diameter DI), is not modelled: no stock, so the stock rules say unknown."""
    radius = words.get("R", words.get("D", 0.0) / 2.0)
    length = words.get("L")
    if not rest.strip().upper().startswith("Z") or "DI" in words or not radius > 0 or not length:
        return None
    top = words.get("DIST", 0.0)
    return Stock.round_blank(radius, (top - length, top), origin="program (BLK FORM CYLINDER)")


def stock_from_text(text: str) -> Stock | None:
    """``BLK FORM 0.1 Z X.. Y.. Z..`` (MIN corner) + ``BLK FORM 0.2 X.. Y.. Z..`` (MAX
    corner, ``I`` = from the MIN corner) or ``BLK FORM CYLINDER Z R.. L..`` (reference A §4.1)."""
    corners = {}
    for match in _BLK_FORM.finditer(text):
        kind, rest = match.group(1).upper(), match.group(2)
        words = {word.upper(): float(value.replace(",", ".")) for word, value in _STOCK_WORD.findall(rest)}
        if kind == "CYLINDER":
            return _round_blank(rest, words)
        corners[kind] = words
    low, high = corners.get("0.1"), corners.get("0.2")
    if not low or not high:
        return None
    try:
        ranges = []
        for axis in "XYZ":
            first = low.get(axis)
            second = high.get(axis, None)
            if second is None and f"I{axis}" in high and first is not None:
                second = first + high[f"I{axis}"]
            if first is None or second is None:
                return None
            ranges.append((first, second))
        return Stock.box(*ranges, origin="program (BLK FORM)")
    except ValueError:
        return None


# --------------------------------------------------------------------------- tool table

_TOOL_COLUMNS = {"R": "radius", "L": "length", "LU": "usable_length", "LCUTS": "cutting_length", "ANGLE": "angle", "PITCH": "pitch", "R2": "corner",
                 "T-ANGLE": "point_angle"}


def _add_delta(tool: Tool, field: str, text: str) -> None:
    """Add a TOOL.T delta column's value to the tool's ``field`` (left alone when either is
    not a number, or the sum is no size)."""
    try:
        delta = float(text.replace(",", ".") or 0)
    except ValueError:
        return
    value = getattr(tool, field)
    if value is not None and tool_value_problem(field, value + delta) is None:
        setattr(tool, field, value + delta)


def read_tool_table(path) -> tuple[dict[int, Tool], dict[str, float]]:
    """TOOL.T: a header line naming the columns, then one line per tool (fixed columns,
    split here by the header's column starts). R + DR, L + DL and R2 + DR2 are what the
    control uses."""
    note_file(path)
    try:
        lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        return {}, {}
    header_index = next((index for index, line in enumerate(lines) if re.match(r"\s*T\s+NAME\b", line.upper())), None)
    if header_index is None:
        return {}, {}
    header = lines[header_index].upper()
    starts = [match.start() for match in re.finditer(r"\S+", header)]
    names = header.split()
    tools, by_name = {}, {}
    for line in lines[header_index + 1 :]:
        if line.strip().startswith("[END]") or not line.strip():
            continue
        cells = {}
        for index, name in enumerate(names):
            end = starts[index + 1] if index + 1 < len(starts) else len(line)
            cells[name] = line[starts[index] : end].strip()
        try:
            number = int(float(cells.get("T", "")))
        except (ValueError, OverflowError):  # not a number, or inf
            continue
        tool = Tool(number, cells.get("NAME") or None, origin="TOOL.T")
        for column, field in _TOOL_COLUMNS.items():
            try:
                value = float(cells.get(column, "").replace(",", "."))
            except ValueError:
                continue
            if tool_value_problem(field, value) is None and (value > 0 or column in ("ANGLE", "R2", "T-ANGLE")):  # LU, LCUTS, PITCH 0: not entered
                setattr(tool, field, value)
        for field, column in (("radius", "DR"), ("length", "DL"), ("corner", "DR2")):  # R + DR, L + DL, R2 + DR2: what the control uses
            _add_delta(tool, field, cells.get(column, "0"))
        tools[number] = tool
        if tool.name:
            by_name[tool.name.upper()] = float(number)
    return tools, by_name




def setup(settings, detection, project) -> DialectSetup:
    """Klartext on a milling machine, metric until BEGIN PGM says otherwise; TOOL.T from
    the subprogram path or the program's folder is a tool source."""
    tools, names = {}, {}
    for folder in settings.subprogram_path:
        from pathlib import Path

        candidate = Path(folder) / "TOOL.T"
        if candidate.is_file():
            tools, names = read_tool_table(candidate)
            break
    lowering = KlartextLowering(names)
    power_on = {"plane": "xy", "units": "mm", "distance": "absolute", "feed_mode": "per_minute", "motion": "rapid",
                "arc_distance": "incremental", "path_mode": "exact", "cycle_return": "initial", "spindle_mode": "rpm"}
    limits = {"tool_number_max": 32767.0, "h_register_max": 32767.0, "d_register_max": 32767.0}
    return DialectSetup(KlartextFrontend(lowering, tools), power_on, load_cycle_table("heidenhain"), None, "mill", {}, None, 0.0, limits)


def _rapid_arc(block, span) -> None:
    """FMAX on a circle block: the arc runs at rapid traverse, which the arc's checks (made
    for a feed) do not cover: whether it passes through the blank is not known."""
    block.notes.append(ir.Note("core.rapid-into-stock", "FMAX on a circle block: the arc runs at rapid traverse, and a rapid arc's path is not checked "
                               "against the blank", span, "unknown", "rapid arc (FMAX on a circle block) not modelled"))
