"""Reader for LinuxCNC's RS274NGC: one line, one block, to the ISO reader's words.

RS274NGC ignores spaces and case outside comments, ends a block at the line's end (``;``
starts a comment that runs to it), writes every expression in brackets with its own operator
precedence (``**`` above ``* / MOD`` above ``+ -`` above the comparisons above ``AND OR
XOR``), and names parameters by number (``#31``), by name (``#<depth>``, ``#<_global>``) or
indirectly (``##1``). Control flow is written with O-words: ``o100 if [..]``, ``o<name>
call [..] [..]``. The reader hands back the ISO family's :class:`~ncverify.read.iso.ReadBlock`
with :class:`~ncverify.read.iso.Word` and assignment :class:`~ncverify.read.iso.Statement`
items, plus :class:`OWord` items, so the ISO lowering distributes the words.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

from .. import ir
from .iso import ReadBlock, Statement, SyntaxProblem, Word
from .limits import MAX_TERMS, terms_message

FUNCTIONS = {"ABS", "ACOS", "ASIN", "ATAN", "COS", "EXP", "FIX", "FUP", "ROUND", "LN", "SIN", "SQRT", "TAN", "EXISTS"}
OWORD_KEYWORDS = {"SUB", "ENDSUB", "CALL", "RETURN", "IF", "ELSEIF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "DO",
                  "REPEAT", "ENDREPEAT", "BREAK", "CONTINUE"}
# Binary operators by precedence level, lowest first (RS274NGC: logical, relational, additive,
# multiplicative, power).
_LEVELS = (("AND", "OR", "XOR"), ("EQ", "NE", "GT", "GE", "LT", "LE"), ("+", "-"), ("*", "/", "MOD"), ("**",))
_OPERATOR = re.compile(r"\*\*|[-+*/]|AND|OR|XOR|MOD|EQ|NE|GT|GE|LT|LE")
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)")
_FUNCTION = re.compile("|".join(sorted(FUNCTIONS, key=len, reverse=True)))
_KEYWORD = re.compile("|".join(sorted(OWORD_KEYWORDS, key=len, reverse=True)))
_MAX_DEPTH = 60
POLAR = "@^"  # polar distance and angle words


@dataclass(slots=True)
class OWord:
    """An O-word statement: ``name`` is ``o100`` or ``o<name>`` (lower case), ``keyword``
    upper case, ``args`` the bracketed expressions after it (call arguments, a condition,
    a repeat count, a return value)."""

    name: str
    keyword: str
    args: list = field(default_factory=list)
    start: int = 0
    end: int = 0


class ReadError(Exception):
    def __init__(self, message: str, column: int):
        super().__init__(message)
        self.column = column


class _Text:
    """The line with its comments and spaces taken out, each character keeping the column
    it had (RS274NGC squeezes spaces before it reads a line)."""

    def __init__(self, chars: list[tuple[str, int]]):
        self.chars = "".join(char for char, _ in chars).upper()
        self.columns = [column for _, column in chars]
        self.position = 0
        self.terms = 0  # values read in this line (limits.MAX_TERMS)

    def column(self, index: int | None = None) -> int:
        index = self.position if index is None else index
        if index < len(self.columns):
            return self.columns[index]
        return self.columns[-1] + 1 if self.columns else 0

    def peek(self, count: int = 1) -> str:
        return self.chars[self.position : self.position + count]

    def at_end(self) -> bool:
        return self.position >= len(self.chars)

    def expect(self, char: str) -> None:
        if self.peek() != char:
            found = f"'{self.peek()}'" if self.peek() else "the end of the line"
            raise ReadError(f"expected '{char}', found {found}", self.column())
        self.position += 1


def read_line(text: str, line: int) -> list[ReadBlock]:
    """The block of one line (an empty list for an empty line)."""
    chars, comments, problem = _split_comments(text)
    if not chars and not comments:
        return [] if problem is None else [ReadBlock(line, problem.start, problem.end, [], problem=problem)]
    first = min([column for _, column in chars] + [start for _, start, _ in comments])
    last = max([column + 1 for _, column in chars] + [end for _, _, end in comments])
    block = ReadBlock(line, first, last, [], comments)
    if problem is not None:
        block.problem = problem
        return [block]
    body = _Text(chars)
    if body.chars.startswith("%") and body.chars.strip("%") == "":
        block.percent = True
        return [block]
    try:
        _read_items(body, block)
    except ReadError as error:
        block.problem = SyntaxProblem(str(error), error.column, max(last, error.column + 1))
        block.items = []
    return [block]


def _split_comments(text: str):
    """Characters outside comments (no spaces), the comments, and an unclosed '(' as a problem."""
    chars: list[tuple[str, int]] = []
    comments: list[tuple[str, int, int]] = []
    index = 0
    length = len(text)
    while index < length:
        char = text[index]
        if char == "(":
            close = text.find(")", index + 1)
            if close < 0:
                return chars, comments, SyntaxProblem("comment is not closed: '(' has no ')' before the end of the line", index, length)
            comments.append((text[index + 1 : close], index, close + 1))
            index = close + 1
            continue
        if char == ";":
            comments.append((text[index + 1 :], index, length))
            break
        if char not in " \t\r\n":
            chars.append((char, index))
        index += 1
    return chars, comments, None


def _read_items(body: _Text, block: ReadBlock) -> None:
    if body.peek() == "/":
        block.skip = True
        body.position += 1
    if body.peek() == "N":
        start = body.column()
        body.position += 1
        number = _read_number(body)
        block.items.append(Word("N", number, True, start, body.column()))
    if body.peek() == "O":
        block.items.append(_read_oword(body))
        return
    while not body.at_end():
        start = body.column()
        char = body.peek()
        if char == "#":
            target = _read_parameter(body)
            body.expect("=")
            value = _read_value(body)
            block.items.append(Statement("assign", start, body.column(body.position - 1) + 1, target=target, value=value))
        elif char.isalpha() or char in POLAR:
            body.position += 1
            value = _read_value(body)
            block.items.append(Word(char, value, True, start, body.column(body.position - 1) + 1))
        else:
            raise ReadError(f"'{char}' cannot start a word here", start)


def _read_oword(body: _Text) -> "OWord | Word":
    start = body.column()
    body.position += 1
    if body.peek() == "<":
        name = f"o<{_read_name(body)}>"
    else:
        number = _read_number(body)
        if not math.isfinite(number):
            raise ReadError(f"O-word number {number:g} is not a number a control reads", start)
        name = f"o{int(number)}"
    match = _KEYWORD.match(body.chars, body.position)
    if match is None and body.at_end() and not name.startswith("o<"):
        return Word("O", float(name[1:]), True, start, body.column(body.position - 1) + 1)  # a Fanuc-style program number (M98 target)
    if match is None:
        raise ReadError(f"{name} needs a keyword (sub, call, if, while, ...)", body.column())
    body.position = match.end()
    oword = OWord(name, match.group(0), [], start)
    while body.peek() == "[":
        oword.args.append(_read_bracket(body, 0))
    if not body.at_end():
        raise ReadError(f"unexpected '{body.peek()}' after {name} {oword.keyword.lower()}", body.column())
    oword.end = body.column(body.position - 1) + 1
    return oword


def _read_name(body: _Text) -> str:
    close = body.chars.find(">", body.position)
    if close < 0:
        raise ReadError("a name in '<' has no closing '>'", body.column())
    name = body.chars[body.position + 1 : close].lower()
    if not name:
        raise ReadError("an empty name '<>'", body.column())
    body.position = close + 1
    return name


def _read_number(body: _Text) -> float:
    match = _NUMBER.match(body.chars, body.position)
    if match is None:
        found = f"'{body.peek()}'" if body.peek() else "the end of the line"
        raise ReadError(f"expected a number, found {found}", body.column())
    body.position = match.end()
    return float(match.group(0))


def _read_parameter(body: _Text) -> ir.Var:
    start = body.column()
    body.expect("#")
    if body.peek() == "<":
        return ir.Var(f"#<{_read_name(body)}>")
    if body.peek() in ("#", "["):
        return ir.Var(_read_value(body))
    number = _read_number(body)
    if not math.isfinite(number) or number != int(number) or number < 0:
        raise ReadError(f"parameter number #{number:g} is not a whole number", start)
    return ir.Var(f"#{int(number)}")


def _read_value(body: _Text, depth: int = 0) -> ir.Expr:
    """A real value: a number, a parameter, a bracketed expression or a function, with an
    optional sign."""
    if depth > _MAX_DEPTH:
        raise ReadError("expression nested too deeply", body.column())
    body.terms += 1
    if body.terms > MAX_TERMS:
        raise ReadError(terms_message(MAX_TERMS), body.column())
    char = body.peek()
    if char in ("+", "-") and body.peek(2)[1:] in ("[", "#") or char in ("+", "-") and _FUNCTION.match(body.chars, body.position + 1):
        body.position += 1
        operand = _read_value(body, depth + 1)
        return ir.Unary("-", operand) if char == "-" else operand
    if char == "[":
        return _read_bracket(body, depth + 1)
    if char == "#":
        return _read_parameter(body)
    function = _FUNCTION.match(body.chars, body.position)
    if function is not None:
        return _read_function(body, function.group(0), depth)
    return _read_number(body)


def _read_function(body: _Text, name: str, depth: int) -> ir.Expr:
    body.position += len(name)
    if name == "EXISTS":
        body.expect("[")
        target = _read_parameter(body)
        body.expect("]")
        return ir.Func("EXISTS", (target,))
    argument = _read_bracket(body, depth + 1)
    if name == "ATAN":
        body.expect("/")
        return ir.Func("ATAN2", (argument, _read_bracket(body, depth + 1)))
    return ir.Func(name, (argument,))


def _read_bracket(body: _Text, depth: int) -> ir.Expr:
    body.expect("[")
    value = _read_expression(body, 0, depth)
    body.expect("]")
    return value


def _read_expression(body: _Text, level: int, depth: int) -> ir.Expr:
    if level == len(_LEVELS):
        return _read_value(body, depth + 1)
    left = _read_expression(body, level + 1, depth)
    while True:
        match = _OPERATOR.match(body.chars, body.position)
        if match is None or match.group(0) not in _LEVELS[level]:
            return left
        body.position = match.end()
        right = _read_expression(body, level + 1, depth)
        left = ir.Binary(match.group(0), left, right)
