"""The grammar path of the ISO reader: a block that is not plain words (macro statements,
expressions, comma words, a bare ``G``, block skip) parsed with the lark grammar in
``dialects/iso/block.lark`` into the :class:`~ncverify.read.iso.ReadBlock` the plain path
would give. Imported by :mod:`ncverify.read.iso` only when a block needs it."""
from __future__ import annotations

import math
import re
from functools import cache

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from .. import ir
from ..resources import data_dir
from ..source import Span
from .iso_blocks import ReadBlock, Statement, SyntaxProblem, Word

@cache
def _parser() -> Lark:
    grammar = (data_dir("dialects") / "iso" / "block.lark").read_text(encoding="utf-8")
    return Lark(grammar, parser="lalr", lexer="contextual", propagate_positions=True, maybe_placeholders=False)


def parse_with_grammar(block: ReadBlock, segment: str, offset: int) -> None:
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
