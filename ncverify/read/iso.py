"""Reader for the ISO family (Fanuc-style, Mitsubishi E60/M60, Haas): text to blocks of words.

A line holds one or more blocks (``;`` ends a block); ``( )`` comments may sit anywhere
between words. Most CAM output is plain words (``N120 G1 X10.5 Y-3 F800``): those blocks
take a regex fast path and never build a lark tree. Everything else - macro statements,
expressions, comma words, a bare ``G``, block skip - goes through the lark grammar in
``dialects/iso/block.lark``. Both paths produce the same :class:`ReadBlock`, which a
property test checks.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from functools import cache

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from .. import ir
from ..resources import data_dir
from ..source import Span


@dataclass(slots=True)
class Word:
    """An address word. ``value`` is a float for a literal number (as written, not yet
    scaled by the least input increment) or an expression; ``None`` for a bare address."""

    letter: str  # "G", "X", ... or ",R" for a comma word
    value: "float | ir.Expr | None"
    has_point: bool
    start: int  # 0-based columns in the line, end exclusive
    end: int


@dataclass(slots=True)
class Statement:
    """A macro statement: ``assign``, ``if_goto``, ``if_then``, ``while``, ``end``, ``goto``."""

    kind: str
    start: int
    end: int
    target: "ir.Var | None" = None
    value: "ir.Expr | None" = None
    condition: "ir.Expr | None" = None
    number: int | None = None  # the m of DO m / END m


@dataclass(slots=True)
class SyntaxProblem:
    message: str
    start: int
    end: int


@dataclass(slots=True)
class ReadBlock:
    line: int
    start: int  # 0-based, end exclusive, in the decoded line
    end: int
    items: list  # Word | Statement, in source order
    comments: list = field(default_factory=list)  # (text, start, end)
    skip: bool = False
    problem: SyntaxProblem | None = None
    percent: bool = False  # a '%' tape mark line
    directive: str | None = None  # a simulator / editor directive line ($Inches, #region)


_UPPER = str.maketrans("abcdefghijklmnopqrstuvwxyz", "ABCDEFGHIJKLMNOPQRSTUVWXYZ")
_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)"
_PLAIN_CODE = re.compile(rf"[ \t]*(?:[A-Z][ \t]*{_NUMBER}[ \t]*)*")
_PLAIN_WORD = re.compile(rf"([A-Z])[ \t]*({_NUMBER})")
_COMMENT = re.compile(r"\([^)]*\)")
# Macro output to a port (Fanuc macro B, Haas): DPRNT[..] / BPRNT[..] print, POPEN / PCLOS open and close the port
_OUTPUT_STATEMENT = re.compile(r"[ \t]*(?:(N[ \t]*\d+)[ \t]*)?(?:[DB]PRNT[ \t]*\[[^\n]*\]|POPEN|PCLOS)[ \t]*")
# A line of a CNC simulator's or editor's own ($Inches, $AddRegPart, #region): not G-code.
_DIRECTIVE = re.compile(r"\$[A-Z]|#[A-Z]")
# After ';' (end of block), prose rather than words is a comment (Mastercam, Mach3 posts):
# a lower-case letter, or a word of several letters that is no macro keyword.
_FREE_TEXT = re.compile(r"[^;(]*[a-z]|\s*(?!(?:IF|GOTO|WHILE|WH|END|DO|THEN)(?![A-Za-z]))[A-Za-z]{2,}")


def read_line(text: str, line: int, force_grammar: bool = False) -> list[ReadBlock]:
    """Read one decoded line into its blocks."""
    code = text.translate(_UPPER)
    stripped = code.strip()
    if not stripped:
        return []
    if _DIRECTIVE.match(stripped):
        start = code.index(stripped[0])
        return [ReadBlock(line, start, start + len(stripped), [], directive=text.strip())]
    if stripped.startswith("%"):
        start = code.index("%")
        rest = code[start + 1 :]
        blocks = [ReadBlock(line, start, start + 1, [], percent=True)]
        if rest.strip():
            blocks += read_line(" " * (start + 1) + text[start + 1 :], line, force_grammar)
        return blocks
    if "(" not in code and ";" not in code and ")" not in code:
        return [_read_block(code, text, line, 0, len(code), (), force_grammar)]
    return _read_segments(code, text, line, force_grammar)


def _read_segments(code: str, text: str, line: int, force_grammar: bool) -> list[ReadBlock]:
    """Split a line at ';' outside comments and collect its comments."""
    blocks = []
    comments: list = []
    segment_start = 0
    position = 0
    length = len(code)
    while position < length:
        char = code[position]
        if char == "(":
            close = code.find(")", position + 1)
            if close < 0:
                block = _read_block(code, text, line, segment_start, position, comments, force_grammar)
                block.end = length
                block.problem = block.problem or SyntaxProblem(
                    "comment is not closed: '(' has no ')' before the end of the line", position, length
                )
                blocks.append(block)
                return blocks
            comments.append((text[position + 1 : close], position, close + 1))
            position = close + 1
            continue
        if char == ")":
            block = _read_block(code, text, line, segment_start, length, comments, force_grammar)
            block.problem = block.problem or SyntaxProblem("')' without an opening '('", position, position + 1)
            blocks.append(block)
            return blocks
        if char == ";":
            if code[segment_start:position].strip() or comments:
                blocks.append(_read_block(code, text, line, segment_start, position, comments, force_grammar))
            comments = []
            segment_start = position + 1
            if _FREE_TEXT.match(text, segment_start):
                blocks.append(ReadBlock(line, position, length, [], [(text[segment_start:].strip(), position, length)]))
                return blocks
        position += 1
    if code[segment_start:].strip() or comments:
        blocks.append(_read_block(code, text, line, segment_start, length, comments, force_grammar))
    return blocks


def _read_block(code, text, line, start, end, comments, force_grammar) -> ReadBlock:
    segment = code[start:end]
    if comments:
        for _, comment_start, comment_end in comments:
            if start <= comment_start < end:
                offset = comment_start - start
                segment = segment[:offset] + " " * (comment_end - comment_start) + segment[offset + comment_end - comment_start :]
    content = segment.strip()
    first = start + (len(segment) - len(segment.lstrip()))
    last = start + len(segment.rstrip())
    if not content:
        first, last = (comments[0][1], comments[-1][2]) if comments else (start, end)
    block = ReadBlock(line, first, last, [], list(comments))
    output = _OUTPUT_STATEMENT.fullmatch(segment)
    if output is not None:  # macro output (DPRNT, BPRNT, POPEN, PCLOS): data to a port, no machine state
        if output.group(1) is not None:
            block.items = [Word("N", float(output.group(1)[1:]), False, start + output.start(1), start + output.end(1))]
        return block
    if not force_grammar and _PLAIN_CODE.fullmatch(segment):
        block.items = [
            Word(match.group(1), float(match.group(2)), "." in match.group(2), match.start() + start, match.end() + start)
            for match in _PLAIN_WORD.finditer(segment)
        ]
        return block
    _parse_with_grammar(block, segment, start)
    return block


# --------------------------------------------------------------------------- grammar path


@cache
def _parser() -> Lark:
    grammar = (data_dir("dialects") / "iso" / "block.lark").read_text(encoding="utf-8")
    return Lark(grammar, parser="lalr", lexer="contextual", propagate_positions=True, maybe_placeholders=False)


def _parse_with_grammar(block: ReadBlock, segment: str, offset: int) -> None:
    too_complex = _too_complex(segment)
    if too_complex:
        block.problem = SyntaxProblem(too_complex, offset, offset + len(segment.rstrip()))
        return
    try:
        tree = _parser().parse(segment)
    except UnexpectedInput as error:
        block.problem = _describe(error, segment, offset)
        return
    items = _ToItems(offset, block.line).transform(tree)
    block.skip = any(item == "SKIP" for item in items)
    block.items = [item for item in items if item not in ("SKIP", "MARK") and not isinstance(item, tuple)]


_MAX_NESTING = 100
_MAX_OPERATORS = 200
_OPERATOR = re.compile(r"[-+*/]|AND|OR|XOR|MOD|EQ|NE|GT|GE|LT|LE")


def _whole(text: str) -> int:
    """A whole number as written (``#12``, ``DO1``), however many digits: through ``float``
    a 400-digit number would be infinite. A fraction is cut as the control cuts it."""
    try:
        return int(text)
    except ValueError:
        value = float(text)
        return int(value) if math.isfinite(value) else -1


def _too_complex(segment: str) -> str | None:
    """Controls nest brackets a few levels deep (Fanuc: 5); an expression far beyond what
    any control takes is refused here rather than parsed recursively."""
    depth = deepest = 0
    for char in segment:
        if char == "[":
            depth += 1
            deepest = max(deepest, depth)
        elif char == "]":
            depth -= 1
    if deepest > _MAX_NESTING:
        return f"brackets nested {deepest} deep: no control accepts that (Fanuc allows 5)"
    operators = len(_OPERATOR.findall(segment))
    if operators > _MAX_OPERATORS:
        return f"an expression with {operators} operators is too long for a control's block buffer"
    return None


def _describe(error: UnexpectedInput, segment: str, offset: int) -> SyntaxProblem:
    if segment.count("[") > segment.count("]"):
        opening = segment.rfind("[")
        return SyntaxProblem("'[' is not closed: the expression needs its ']'", offset + opening, offset + len(segment.rstrip()))
    column = max(getattr(error, "column", 1) or 1, 1) - 1
    if isinstance(error, UnexpectedEOF) or column >= len(segment):
        stripped = segment.rstrip()
        return SyntaxProblem("block ends in the middle of a word or expression", offset + max(len(stripped) - 1, 0), offset + max(len(stripped), 1))
    char = segment[column]
    if char.isdigit() or char == ".":
        what = f"number {char!r} has no address letter (a space inside a number?)"
    elif isinstance(error, UnexpectedCharacters):
        if ord(char) > 127 or not char.isprintable():
            what = f"character {char!r} (U+{ord(char):04X}) cannot appear outside a comment"
        else:
            what = f"unexpected {char!r}"
    elif isinstance(error, UnexpectedToken) and error.token.type == "$END":
        what = "block ends in the middle of a word or expression"
    else:
        token = getattr(error, "token", char)
        what = f"unexpected {str(token)!r}"
        if str(token)[:1].isalpha() and _follows_letter(segment, column):
            what += " (an address letter needs a number after it)"
    end = column + 1
    while end < len(segment) and segment[end].isalnum() and segment[column].isalnum():
        end += 1
    return SyntaxProblem(what, offset + column, offset + end)


def _follows_letter(segment: str, column: int) -> bool:
    before = segment[:column].rstrip()
    return bool(before) and before[-1].isalpha()


class _ToItems(Transformer):
    """Lark tree to reader items; expressions become dialect-neutral ``ir`` nodes."""

    def __init__(self, offset: int, line: int):
        super().__init__()
        self.offset = offset
        self.line = line

    def _cols(self, meta) -> tuple[int, int]:
        return meta.column - 1 + self.offset, meta.end_column - 1 + self.offset

    def start(self, children):
        return children

    def block_skip(self, _children):
        return "SKIP"

    def comment(self, children):
        return ("comment",)

    @v_args(meta=True)
    def word(self, meta, children):
        start, end = self._cols(meta)
        letter = str(children[0])
        if len(children) == 1:
            return Word(letter, None, False, start, end)
        value, has_point = children[1]
        return Word(letter, value, has_point, start, end)

    @v_args(meta=True)
    def program_mark(self, meta, children):
        start, end = self._cols(meta)
        return Word("O", float(children[0]) if children else None, False, start, end) if children else "MARK"

    @v_args(meta=True)
    def comma_word(self, meta, children):
        start, end = self._cols(meta)
        value, has_point = children[1]
        return Word("," + str(children[0]), value, has_point, start, end)

    def signed_number(self, children):
        text = "".join(str(child) for child in children)
        return float(text), "." in text

    def signed_ref(self, children):
        """A variable or [expression]: its value is in the program's units, never in least
        input increments (so it counts as written with a point)."""
        if len(children) == 2 and str(children[0]) == "-":
            return ir.Unary("-", children[1]), True
        return children[-1], True

    @v_args(meta=True)
    def assignment(self, meta, children):
        start, end = self._cols(meta)
        return Statement("assign", start, end, target=children[0], value=children[1])

    @v_args(meta=True)
    def if_goto(self, meta, children):
        start, end = self._cols(meta)
        return Statement("if_goto", start, end, condition=children[0], value=children[1])

    @v_args(meta=True)
    def if_then(self, meta, children):
        start, end = self._cols(meta)
        assignment = children[1]
        return Statement("if_then", start, end, condition=children[0], target=assignment.target, value=assignment.value)

    @v_args(meta=True)
    def while_do(self, meta, children):
        start, end = self._cols(meta)
        return Statement("while", start, end, condition=children[0], number=_whole(children[-1]))

    @v_args(meta=True)
    def loop_end(self, meta, children):
        start, end = self._cols(meta)
        return Statement("end", start, end, number=_whole(children[0]))

    @v_args(meta=True)
    def goto(self, meta, children):
        start, end = self._cols(meta)
        return Statement("goto", start, end, value=children[0])

    def number(self, children):
        return float(children[0])

    def bracket(self, children):
        return children[0]

    @v_args(meta=True)
    def variable(self, meta, children):
        start, end = self._cols(meta)
        index = children[0]
        name = f"#{_whole(index)}" if isinstance(index, Token) else index
        return ir.Var(name, Span.on_line(self.line, start, end))

    def comparison(self, children):
        left, relation, right = children
        return ir.Binary(str(relation), left, right)

    def binary(self, children):
        left, operator, right = children
        return ir.Binary(str(operator), left, right)

    def unary(self, children):
        sign, operand = children
        return operand if str(sign) == "+" else ir.Unary("-", operand)

    def function(self, children):
        name = _FUNCTION_ALIASES.get(str(children[0]), str(children[0]))
        return ir.Func(name, (children[1],))

    def atan2(self, children):
        operands = [child for child in children if not isinstance(child, Token)]
        return ir.Func("ATAN2", tuple(operands))


_FUNCTION_ALIASES = {"ATN": "ATAN", "SQR": "SQRT", "RND": "ROUND"}
