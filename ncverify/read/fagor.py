"""Reader for Fagor 8060/8065 programs: one line to one :class:`FagorLine`.

A Fagor block is an ISO block (``N``, address words, ``;`` comment to the end of the line)
plus the control's own statements. The reader splits a line into

- its label (``N10``, or a ``[NAME]`` label), block skip ``/`` and comments;
- a ``$`` flow statement (``$IF P1==2``, ``$FOR P0=1,2,1``, ``$GOTO N10``...) or a ``#``
  instruction (``#CALL "SUB"``, ``#TOOL AX [X+]``, ``#LATHECY ON``...), kept as a keyword and
  its parsed arguments;
- otherwise address words as ISO :class:`~ncverify.read.iso.Word` objects, so that the ISO
  lowering can take them, plus parameter assignments (``P3=P2*2``, ``V.C.I=18``), the
  repetition count ``NR3`` and axes with a numeric suffix (``X2=25``).

Values are numbers or expressions over ``P`` parameters (``#`` + number is read as the same
parameter) and ``V.`` variables: ``X[P1+2]``, ``X(P1+2)``, ``XP1``. Operators: ``+ - * /
MOD ** == != <> < <= > >= AND OR XOR NOT`` (and the ISO ``EQ NE GT GE LT LE``).
Bad text never raises: it gives a :class:`~ncverify.read.iso.SyntaxProblem` with a column.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from .. import ir
from .limits import MAX_NESTING, MAX_TERMS, nesting_message, terms_message
from .iso import SyntaxProblem, Word

_UPPER = str.maketrans("abcdefghijklmnopqrstuvwxyz", "ABCDEFGHIJKLMNOPQRSTUVWXYZ")
_NUMBER = re.compile(r"(?:\d+\.?\d*|\.\d+)")
_NAME = re.compile(r"[A-Z][A-Z0-9_]*")
_V_NAME = re.compile(r"V\.[A-Z0-9_]+(?:\.[A-Z0-9_]+|\[[^\]]*\])*")  # V.A.ORGT[1].Z: an index, then a field
_LABEL = re.compile(r"N(\d+)(?![0-9.=])|\[([A-Z_][A-Z0-9_]*)\]")
_INDEXED_AXIS = re.compile(r"([A-Z])(\d+)[ \t]*=(?!=)")
_AXES = frozenset("XYZUVWABC")


def _homes(line: "FagorLine") -> bool:
    """Has the line a G74 (home search) so far?"""
    return any(word.letter == "G" and word.value == 74.0 for word in line.words)


def _bare(code: str, position: int) -> bool:
    """Does no value follow at ``position`` (a blank then another word, or the line's end)?"""
    rest = code[position:].lstrip(" \t")
    return not rest or "A" <= rest[0] <= "Z"

_FUNCTIONS = {
    "SIN": "SIN", "COS": "COS", "TAN": "TAN", "ASIN": "ASIN", "ACOS": "ACOS", "ATAN": "ATAN", "SQRT": "SQRT",
    "ABS": "ABS", "ROUND": "ROUND", "FUP": "FUP", "INT": "FIX", "LN": "LN", "EXP": "EXP",
}
_RELATIONS = {"==": "EQ", "!=": "NE", "<>": "NE", ">=": "GE", "<=": "LE", ">": "GT", "<": "LT",
              "EQ": "EQ", "NE": "NE", "GE": "GE", "LE": "LE", "GT": "GT", "LT": "LT"}


@dataclass(slots=True)
class Statement:
    """A ``$`` statement or ``#`` instruction: ``keyword`` (``IF``, ``FOR``, ``CALL``...),
    ``flow`` True for ``$``, the parsed ``args`` and the raw ``text`` after the keyword."""

    keyword: str
    flow: bool
    start: int
    end: int
    text: str
    args: list = field(default_factory=list)


@dataclass(slots=True)
class Assignment:
    target: ir.Var
    value: ir.Expr
    start: int
    end: int


@dataclass(slots=True)
class FagorLine:
    line: int
    start: int
    end: int
    label: float | str | None = None
    skip: bool = False
    comments: list = field(default_factory=list)  # (text, start, end)
    words: list = field(default_factory=list)  # Word
    assignments: list = field(default_factory=list)
    statement: Statement | None = None
    repeat: tuple | None = None  # (expr, start, end) of NR
    indexed_axes: list = field(default_factory=list)  # (name, start, end) of X2=..
    rpt: tuple | None = None  # (first label, last label, count, start, end) of (RPT N10, N20)
    program_start: str | None = None  # %L NAME
    problem: SyntaxProblem | None = None

    @property
    def empty(self) -> bool:
        return not (self.words or self.assignments or self.statement or self.repeat or self.indexed_axes or self.rpt)


class _Error(Exception):
    def __init__(self, message: str, column: int):
        super().__init__(message)
        self.column = column


_PAREN_COMMENT = re.compile(r"\((?!\s*RPT\b)[^)]*\)")
_RPT = re.compile(r"\(\s*RPT\s+N(\d+)\s*,\s*N(\d+)\s*\)(?:\s*N(\d+))?")
_SUBROUTINE = re.compile(r"%\s*L\s+([A-Z0-9_.]+)")


def read_fagor_line(text: str, line: int, paren_comments: bool = True) -> FagorLine:
    """Read one line (never raises)."""
    upper = text.translate(_UPPER)
    code_end = _comment_start(upper)
    result = FagorLine(line, 0, len(text.rstrip()))
    if code_end < len(text):
        result.comments.append((text[code_end + 1 :].strip(), code_end, len(text.rstrip())))
    code = upper[:code_end]
    try:
        _read(result, code, text, paren_comments)
    except _Error as error:
        column = min(error.column, max(len(code.rstrip()) - 1, 0))
        result.problem = SyntaxProblem(str(error), column, column + 1)
    except RecursionError:
        result.problem = SyntaxProblem("expression nested too deeply", 0, max(len(code), 1))
    stripped = text.strip()
    if stripped:
        result.start = text.index(stripped[0])
    return result


def _comment_start(upper: str) -> int:
    """Where ';' starts a comment, outside string quotes."""
    quoted = False
    for index, char in enumerate(upper):
        if char == '"':
            quoted = not quoted
        elif char == ";" and not quoted:
            return index
    return len(upper)


def _read(result: FagorLine, code: str, original: str, paren_comments: bool) -> None:
    position = _skip_spaces(code, 0)
    if position < len(code) and code[position] == "/":
        result.skip = True
        position = _skip_spaces(code, position + 1)
    subroutine = _SUBROUTINE.match(code, position)
    if subroutine:
        result.program_start = original[subroutine.start(1) : subroutine.end(1)]
        return
    if code[position : position + 1] == "%":
        return  # a program header line ("%NAME" or a tape mark): no block
    label = _LABEL.match(code, position)
    if label:
        result.label = float(label.group(1)) if label.group(1) else label.group(2)
        position = _skip_spaces(code, label.end())
    if paren_comments:
        code = _blank_paren_comments(result, code, original)
    if position < len(code) and code[position] in "$#" and _NAME.match(code, position + 1):
        result.statement = _statement(code, original, position)
        return
    _read_words(result, code, position)


def _blank_paren_comments(result: FagorLine, code: str, original: str) -> str:
    rpt = _RPT.search(code)
    if rpt:
        count = float(rpt.group(3)) if rpt.group(3) else 1.0
        result.rpt = (float(rpt.group(1)), float(rpt.group(2)), count, rpt.start(), rpt.end())
        code = code[: rpt.start()] + " " * (rpt.end() - rpt.start()) + code[rpt.end() :]
    for match in _PAREN_COMMENT.finditer(code):
        if _is_expression_paren(code, match.start()):
            continue
        result.comments.append((original[match.start() + 1 : match.end() - 1].strip(), match.start(), match.end()))
        code = code[: match.start()] + " " * (match.end() - match.start()) + code[match.end() :]
    return code


def _is_expression_paren(code: str, index: int) -> bool:
    """``X(P1+2)``: a parenthesis right after an address letter or an operator is an expression."""
    before = code[:index].rstrip()
    return bool(before) and (before[-1].isalpha() or before[-1] in "=+-*/[(,")


def _skip_spaces(code: str, position: int) -> int:
    while position < len(code) and code[position] in " \t\r":
        position += 1
    return position


# ---------------------------------------------------------------------- statements

_EXPRESSION_STATEMENTS = {"IF", "ELSEIF", "WHILE", "SWITCH", "CASE", "ENDDO"}


def _statement(code: str, original: str, position: int) -> Statement:
    flow = code[position] == "$"
    name = _NAME.match(code, position + 1)
    keyword = name.group(0)
    rest_start = name.end()
    text = original[rest_start:len(code)].strip()
    statement = Statement(keyword, flow, position, len(code.rstrip()), text)
    rest = code[rest_start:]
    if flow and keyword in _EXPRESSION_STATEMENTS and rest.strip():
        parser = _Expressions(code, rest_start)
        statement.args.append(parser.expression())
        while parser.peek(","):
            parser.position += 1
            statement.args.append(parser.expression())
        parser.finish()
    elif flow and keyword == "FOR":
        statement.args = _for_arguments(code, rest_start)
    elif flow and keyword in ("GOTO", "RPT"):
        statement.args = _label_list(code, rest_start)
    elif not flow and keyword in ("CALL", "PCALL", "MCALL"):
        statement.args = _call_arguments(code, original, rest_start)
    return statement


def _for_arguments(code: str, start: int) -> list:
    parser = _Expressions(code, start)
    target = parser.variable()
    if target is None:
        raise _Error("$FOR needs a parameter: $FOR P1 = start, end, step", parser.position)
    parser.expect("=")
    parts = [target, parser.expression()]
    while parser.peek(","):
        parser.position += 1
        parts.append(parser.expression())
    parser.finish()
    if len(parts) not in (3, 4):
        raise _Error("$FOR takes a start, an end and a step", start)
    return parts


def _label_list(code: str, start: int) -> list:
    """``N10, N20`` and a count: ``, 3`` or Fagor's repetition word, ``N20 NR3``."""
    labels = []
    for item in re.sub(r"\s+NR\s*(?=\d)", ",", code[start:]).split(","):
        item = item.strip()
        match = re.fullmatch(r"N(\d+)|\[([A-Z_][A-Z0-9_]*)\]|(\d+)", item)
        if match is None:
            raise _Error(f"'{item}' is not a label (N10 or [NAME])", start)
        labels.append(float(match.group(1) or match.group(3)) if match.group(2) is None else match.group(2))
    return labels


def _call_arguments(code: str, original: str, start: int) -> list:
    """``"NAME"`` or ``NAME`` or ``[path]``, then ``A1 B2``... parameter words."""
    position = _skip_spaces(code, start)
    if code[position : position + 1] == '"':
        end = code.find('"', position + 1)
        if end < 0:
            raise _Error("the program name has no closing quote", position)
        name, position = original[position + 1 : end], end + 1
    else:
        match = re.compile(r"[A-Z0-9_.\\/]+").match(code, position)
        if match is None:
            raise _Error("the call names no program", position)
        name, position = original[match.start() : match.end()], match.end()
    arguments = [name]
    parser = _Expressions(code, position)
    while True:
        parser.position = _skip_spaces(code, parser.position)
        if parser.position >= len(code.rstrip()):
            return arguments
        letter = code[parser.position]
        if not "A" <= letter <= "Z":
            raise _Error(f"unexpected '{letter}' in the call's parameters", parser.position)
        parser.position += 1
        arguments.append((letter, parser.value()))


# ---------------------------------------------------------------------- words


def _read_words(result: FagorLine, code: str, position: int) -> None:
    end = len(code.rstrip())
    while True:
        position = _skip_spaces(code, position)
        if position >= end:
            return
        char = code[position]
        if char == "P" and _is_assignment(code, position):
            position = _assignment(result, code, position)
        elif code.startswith("V.", position):
            position = _assignment(result, code, position)
        elif char == "#" and position + 1 < end and (code[position + 1].isdigit() or code[position + 1] == "["):
            position = _assignment(result, code, position)
        elif code.startswith("NR", position):
            parser = _Expressions(code, position + 2)
            value = parser.value()
            result.repeat = (value, position, parser.position)
            position = parser.position
        elif (indexed := _INDEXED_AXIS.match(code, position)) is not None:
            parser = _Expressions(code, indexed.end())
            parser.expression()
            result.indexed_axes.append((indexed.group(1) + indexed.group(2), position, parser.position))
            position = parser.position
        elif char in _AXES and _homes(result) and _bare(code, position + 1):  # G74 X Y Z: the axes to home, without values
            result.words.append(Word(char, 0.0, False, position, position + 1))
            position += 1
        elif "A" <= char <= "Z":
            parser = _Expressions(code, position + 1)
            value, has_point = parser.word_value()
            result.words.append(Word(char, value, has_point, position, parser.position))
            position = parser.position
        else:
            raise _Error(f"unexpected '{char}'", position)


def _is_assignment(code: str, position: int) -> bool:
    match = re.compile(r"P(?:\d+|\[[^\]]*\])[ \t]*=(?!=)").match(code, position)
    return match is not None


def _assignment(result: FagorLine, code: str, position: int) -> int:
    parser = _Expressions(code, position)
    target = parser.variable()
    if target is None:
        raise _Error("expected a parameter or variable", position)
    parser.expect("=")
    value = parser.expression()
    result.assignments.append(Assignment(target, value, position, parser.position))
    return parser.position


# ---------------------------------------------------------------------- expressions


class _Expressions:
    """Recursive descent over ``code`` from ``position``."""

    def __init__(self, code: str, position: int):
        self.code = code
        self.position = position
        self.depth = 0  # values open inside one another (limits.MAX_NESTING)
        self.terms = 0  # values read in this block (limits.MAX_TERMS)

    def skip(self) -> None:
        self.position = _skip_spaces(self.code, self.position)

    def peek(self, text: str) -> bool:
        self.skip()
        return self.code.startswith(text, self.position)

    def expect(self, text: str) -> None:
        if not self.peek(text):
            raise _Error(f"expected '{text}'", self.position)
        self.position += len(text)

    def finish(self) -> None:
        self.skip()
        if self.position < len(self.code.rstrip()):
            raise _Error(f"unexpected '{self.code[self.position]}'", self.position)

    def keyword(self, *names: str) -> str | None:
        self.skip()
        for name in names:
            if self.code.startswith(name, self.position):
                after = self.position + len(name)
                if name.isalpha() and after < len(self.code) and (self.code[after].isalnum() or self.code[after] == "_"):
                    continue
                self.position = after
                return name
        return None

    # A word's value: a signed number, a parameter, a variable or a bracketed expression.
    def word_value(self) -> tuple[ir.Expr, bool]:
        self.skip()
        sign = 1.0
        if self.code[self.position : self.position + 1] in ("+", "-"):
            sign = -1.0 if self.code[self.position] == "-" else 1.0
            self.position += 1
            self.skip()
        number = _NUMBER.match(self.code, self.position)
        if number:
            self.position = number.end()
            return sign * float(number.group(0)), "." in number.group(0)
        value = self.atom()
        return (value if sign > 0 else ir.Unary("-", value)), True

    def value(self) -> ir.Expr:
        return self.word_value()[0]

    def variable(self) -> ir.Var | None:
        self.skip()
        code, start = self.code, self.position
        if code.startswith("V.", start):
            match = _V_NAME.match(code, start)
            if match is None:
                raise _Error("a V. variable needs a name (V.C.Z)", start)
            self.position = match.end()
            return ir.Var(match.group(0))
        if code[start : start + 1] in ("P", "#") and start + 1 < len(code):
            following = code[start + 1]
            if following.isdigit():
                number = re.compile(r"\d+").match(code, start + 1)
                self.position = number.end()
                return ir.Var(f"P{int(number.group(0))}")
            if following == "[":
                self.position = start + 2
                index = self.expression()
                self.expect("]")
                return ir.Var(index, prefix="P")
        return None

    def expression(self) -> ir.Expr:
        left = self.conjunction()
        while (operator := self.keyword("OR", "XOR")) is not None:
            left = ir.Binary(operator, left, self.conjunction())
        return left

    def conjunction(self) -> ir.Expr:
        left = self.comparison()
        while self.keyword("AND") is not None:
            left = ir.Binary("AND", left, self.comparison())
        return left

    def comparison(self) -> ir.Expr:
        left = self.sum()
        operator = self.keyword("==", "!=", "<>", ">=", "<=", ">", "<", "EQ", "NE", "GE", "LE", "GT", "LT")
        if operator is None:
            return left
        return ir.Binary(_RELATIONS[operator], left, self.sum())

    def sum(self) -> ir.Expr:
        left = self.product()
        while True:
            self.skip()
            char = self.code[self.position : self.position + 1]
            if char not in ("+", "-"):
                return left
            self.position += 1
            left = ir.Binary(char, left, self.product())

    def product(self) -> ir.Expr:
        left = self.unary()
        while True:
            self.skip()
            if self.code.startswith("**", self.position):
                return left
            char = self.code[self.position : self.position + 1]
            if char in ("*", "/"):
                self.position += 1
                left = ir.Binary(char, left, self.unary())
            elif self.keyword("MOD") is not None:
                left = ir.Binary("MOD", left, self.unary())
            else:
                return left

    def unary(self) -> ir.Expr:
        """Every nested value passes through here: the nesting is counted here."""
        if self.depth >= MAX_NESTING:
            raise _Error(nesting_message(MAX_NESTING), self.position)
        self.depth += 1
        try:
            return self._signed()
        finally:
            self.depth -= 1

    def _signed(self) -> ir.Expr:
        self.skip()
        char = self.code[self.position : self.position + 1]
        if char in ("+", "-"):
            self.position += 1
            operand = self.unary()
            if type(operand) is float:
                return -operand if char == "-" else operand
            return ir.Unary(char, operand)
        if self.keyword("NOT") is not None:
            return ir.Binary("EQ", self.unary(), 0.0)
        base = self.atom()
        if self.peek("**"):
            self.position += 2
            exponent = self.unary()
            return ir.Func("EXP", (ir.Binary("*", exponent, ir.Func("LN", (base,))),))
        return base

    def atom(self) -> ir.Expr:
        self.terms += 1
        if self.terms > MAX_TERMS:
            raise _Error(terms_message(MAX_TERMS), self.position)
        return self._atom()

    def _atom(self) -> ir.Expr:
        self.skip()
        code, start = self.code, self.position
        if start >= len(code):
            raise _Error("a value is missing", start)
        number = _NUMBER.match(code, start)
        if number:
            self.position = number.end()
            return float(number.group(0))
        variable = self.variable()
        if variable is not None:
            return variable
        for opening, closing in (("[", "]"), ("(", ")")):
            if code.startswith(opening, start):
                self.position = start + 1
                inner = self.expression()
                self.expect(closing)
                return inner
        name = _NAME.match(code, start)
        if name and name.group(0) in _FUNCTIONS:
            self.position = name.end()
            closing = {"(": ")", "[": "]"}.get(code[_skip_spaces(code, self.position) : _skip_spaces(code, self.position) + 1])
            if closing is None:
                raise _Error(f"{name.group(0)} needs its argument in brackets", self.position)
            self.position = _skip_spaces(code, self.position) + 1
            argument = self.expression()
            self.expect(closing)
            return ir.Func(_FUNCTIONS[name.group(0)], (argument,))
        raise _Error(f"'{code[start]}' cannot start a value", start)
