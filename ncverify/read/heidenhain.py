"""Stage 1 for HEIDENHAIN Klartext: one logical block's text into tokens and expressions.

A logical block is one line, or several joined by ``\\n`` when a line ends in ``~`` (the
continuation of ``CYCL DEF 2xx``, ``PATTERN DEF``, ``GLOBAL DEF``; reference A §2). Each
physical line loses its ``;`` comment and its trailing ``~``; what is left is split into
tokens that remember their line and column. The lowering (``ncverify.lower.heidenhain``)
walks the tokens with :class:`Cursor`; formulas and ``FN`` operands go through
:func:`Cursor.expression`.

Klartext writes words without separators (``X+30``, ``RQ1832``, ``CCX+15``, ``IPA+90``):
a letter run is cut in front of a Q parameter (``RQ1832`` = ``R`` ``Q1832``), numbers
may carry a decimal comma (``TIEFE-11,95`` in the old German cycle texts).
"""
from __future__ import annotations

import re
from dataclasses import dataclass

from .limits import MAX_NESTING, MAX_TERMS, nesting_message, terms_message

from .. import ir
from ..source import Span, decode_line

_TOKEN = re.compile(
    r"""(?P<space>[ \t\f\v\r]+)
      | (?P<string>"[^"]*")
      | (?P<number>\d+(?:\.\d*|,\d+)?|\.\d+)
      | (?P<name>[A-Z][A-Z_]*?(?=Q[LRS]?\d)|[A-Z][A-Z_]*)
      | (?P<symbol>[-+*/^()=:,#\[\]<>%!&|.?@$'\\{}~_])""",
    re.VERBOSE,
)


class ReadError(Exception):
    """Text that is not Klartext: where, and what was expected."""

    def __init__(self, message: str, span: Span):
        super().__init__(message)
        self.span = span


@dataclass(frozen=True, slots=True)
class Token:
    kind: str  # name, number, string, symbol, end
    text: str
    span: Span


@dataclass(slots=True)
class Text:
    """The code of one logical block without comments, as tokens, and its comments."""

    tokens: list[Token]
    comments: list[tuple[str, Span]]
    first_column: int  # 1-based, of the first character of the block
    end_column: int
    skippable: bool = False


def split(raw: bytes, line: int, path: str | None) -> Text:
    """Tokens of a logical block. Raises :class:`ReadError` at a character no token starts with."""
    tokens: list[Token] = []
    comments: list[tuple[str, Span]] = []
    first_column, end_column = 0, 1
    comment_goes_on = False  # a ';' comment whose line ends in '~' fills the next line too
    for index, physical in enumerate(raw.split(b"\n")):
        number = line + index
        text = decode_line(physical).rstrip("\r")
        if index == 0:
            body = text.strip()
            first_column = text.index(body[:1]) + 1 if body else 1
            end_column = len(text.rstrip()) + 1
            structure = _STRUCTURE.match(text)
            if structure is not None:  # '* - text': a structure block, all comment
                _tokenize(text[: structure.end()], number, path, tokens)
                comments.append((text[structure.end() :].strip(), Span(number, structure.end() + 1, number, len(text) + 1, path)))
                continue
        if comment_goes_on:
            code, comment_at = "", -1
        else:
            code, comment_at = _code_part(text)
        if comment_at is not None:
            comment = text[comment_at + 1 :].rstrip()
            comment_goes_on = comment.endswith("~") and all(token.kind == "number" for token in tokens) and not _code_before(code)
            comments.append((comment.strip().rstrip("~").strip(), Span(number, comment_at + 2, number, len(text) + 1, path)))
        stripped = code.rstrip()
        if stripped.endswith("~"):
            stripped = stripped[:-1]
        _tokenize(stripped, number, path, tokens)
    return Text(tokens, comments, first_column, end_column)


_STRUCTURE = re.compile(r"[ \t]*(?:\d+[ \t]*)?\*")


def _code_before(code: str) -> bool:
    """Is there code besides the block number before a comment?"""
    return bool(code.strip().lstrip("0123456789").strip())


def _code_part(text: str) -> tuple[str, int | None]:
    """The text before a ``;`` comment (outside double quotes) and where the comment starts."""
    quoted = False
    for position, character in enumerate(text):
        if character == '"':
            quoted = not quoted
        elif character == ";" and not quoted:
            return text[:position], position
    return text, None


def _tokenize(text: str, line: int, path: str | None, tokens: list[Token]) -> None:
    upper = _upper_outside_strings(text)
    position = 0
    while position < len(upper):
        match = _TOKEN.match(upper, position)
        if match is None or match.end() == position:
            raise ReadError(f"unexpected character {text[position]!r}", Span(line, position + 1, line, position + 2, path))
        kind = match.lastgroup
        if kind != "space":
            value = text[match.start() : match.end()] if kind == "string" else match.group()
            tokens.append(Token(kind, value, Span(line, match.start() + 1, line, match.end() + 1, path)))
        position = match.end()


def _upper_outside_strings(text: str) -> str:
    if '"' not in text:
        return text.upper()
    parts = text.split('"')
    return '"'.join(part if index % 2 else part.upper() for index, part in enumerate(parts))


def continues(raw: bytes) -> bool:
    """Does the block go on in the next line: ``~`` at the end of the code, before or after
    the line's comment (``Q200=+2 ;SET-UP CLEARANCE ~``, ``CYCL DEF 200 DRILLING ~ ;note``)?"""
    if b"~" not in raw:
        return False
    stripped = raw.rstrip()
    if stripped.endswith(b"~"):
        return True
    if b";" in raw:
        return raw.split(b";", 1)[0].rstrip().endswith(b"~")
    return False


# --------------------------------------------------------------------------- token cursor

_FUNCTIONS = {
    "SIN": "SIN", "COS": "COS", "TAN": "TAN", "ASIN": "ASIN", "ACOS": "ACOS", "ATAN": "ATAN", "SQRT": "SQRT",
    "LN": "LN", "EXP": "EXP", "ABS": "ABS", "INT": "FIX", "SQ": "SQ", "NEG": "NEG", "FRAC": "FRAC", "SGN": "SGN", "LOG": "LOG",
}
PARAMETER_PREFIXES = ("Q", "QL", "QR", "QS")
# String functions whose result is a number (STRLEN ( SRC_QS1 ), STRCOMP ( SRC_QS1 SEA_QS2 ), INSTR,
# TONUMB): the texts are not followed, so the number is an unknown value
_STRING_FUNCTIONS = frozenset({"STRLEN", "STRCOMP", "INSTR", "TONUMB"})


class Cursor:
    """Walks a block's tokens; every ``expect_*`` raises :class:`ReadError` with a span."""

    def __init__(self, tokens: list[Token], end_span: Span):
        self.tokens = tokens
        self.index = 0
        self.end_span = end_span
        self.depth = 0  # expressions open inside one another (limits.MAX_NESTING)
        self.terms = 0  # operands read in this block (limits.MAX_TERMS)

    def peek(self, ahead: int = 0) -> Token | None:
        position = self.index + ahead
        return self.tokens[position] if position < len(self.tokens) else None

    def at_end(self) -> bool:
        return self.index >= len(self.tokens)

    def next(self) -> Token:
        token = self.peek()
        if token is None:
            raise ReadError("the block ends too early", self.end_span)
        self.index += 1
        return token

    def here(self) -> Span:
        token = self.peek()
        return token.span if token is not None else self.end_span

    def is_name(self, *names: str, ahead: int = 0) -> bool:
        token = self.peek(ahead)
        return token is not None and token.kind == "name" and (not names or token.text in names)

    def is_symbol(self, *symbols: str) -> bool:
        token = self.peek()
        return token is not None and token.kind == "symbol" and token.text in symbols

    def take_name(self, *names: str) -> Token | None:
        if self.is_name(*names):
            return self.next()
        return None

    def take_symbol(self, *symbols: str) -> Token | None:
        if self.is_symbol(*symbols):
            return self.next()
        return None

    def expect_name(self, *names: str) -> Token:
        token = self.take_name(*names)
        if token is None:
            raise ReadError(f"expected {' or '.join(names) if names else 'a word'} here", self.here())
        return token

    def expect_symbol(self, symbol: str) -> Token:
        token = self.take_symbol(symbol)
        if token is None:
            raise ReadError(f"expected {symbol!r} here", self.here())
        return token

    def expect_number(self) -> tuple[float, Span]:
        sign = self.take_symbol("+", "-")
        token = self.peek()
        if token is None or token.kind != "number":
            raise ReadError("expected a number here", self.here())
        self.index += 1
        value = float(token.text.replace(",", "."))
        if value - value != 0.0:
            raise ReadError("a number beyond any control's range", token.span)
        span = token.span if sign is None else sign.span.cover(token.span)
        return (-value if sign is not None and sign.text == "-" else value), span

    def rest_span(self, start: Span) -> Span:
        last = self.tokens[self.index - 1].span if self.index else start
        return start.cover(last)

    # ------------------------------------------------------------------ values

    def value(self):
        """A word's value: ``+30``, ``-Q5``, ``+Q120``, ``QL3``, ``(Q1*2)``, a number."""
        return self._unary()

    def expression(self):
        return self._sum()

    def _sum(self):
        left = self._product()
        while self.is_symbol("+", "-"):
            op = self.next().text
            left = ir.Binary(op, left, self._product())
        return left

    def _product(self):
        left = self._power()
        while self.is_symbol("*", "/", "%"):
            op = self.next().text
            left = ir.Binary("MOD" if op == "%" else op, left, self._power())
        return left

    def _power(self):
        base = self._unary()
        if self.take_symbol("^"):
            exponent = self._unary()
            if type(exponent) is float and exponent == int(exponent) and 0 <= exponent <= 8:
                power = 1.0  # a whole power: products, so that a negative base stays valid
                for _ in range(int(exponent)):
                    power = base if power == 1.0 else ir.Binary("*", power, base)
                return power
            return ir.Func("EXP", (ir.Binary("*", exponent, ir.Func("LN", (base,))),))
        return base

    def _unary(self):
        self.terms += 1
        if self.terms > MAX_TERMS:
            raise ReadError(terms_message(MAX_TERMS), self.here())
        if self.depth >= MAX_NESTING:
            raise ReadError(nesting_message(MAX_NESTING), self.here())
        self.depth += 1
        sign = self.take_symbol("+", "-")
        try:
            operand = self._primary()
        finally:
            self.depth -= 1
        if sign is not None and sign.text == "-":
            return operand * -1.0 if type(operand) is float else ir.Unary("-", operand)
        return operand

    def _primary(self):
        token = self.peek()
        if token is None:
            raise ReadError("a value is missing here", self.end_span)
        if token.kind == "number":
            self.index += 1
            return float(token.text.replace(",", "."))
        if token.kind == "symbol" and token.text == "(":
            self.index += 1
            inner = self._sum()
            self.expect_symbol(")")
            return inner
        if token.kind == "name":
            if token.text in PARAMETER_PREFIXES:
                return self.parameter()
            if token.text == "PI":
                self.index += 1
                return 3.141592653589793
            if token.text in _FUNCTIONS:
                self.index += 1
                return _function(_FUNCTIONS[token.text], self._unary())
            if token.text in _STRING_FUNCTIONS:
                self.index += 1
                self._skip_group()
                return ir.Var(f"{token.text}()")
        raise ReadError(f"expected a number or a Q parameter, found {token.text!r}", token.span)

    def _skip_group(self) -> None:
        """A parenthesised argument list of a string function, read past as written."""
        self.expect_symbol("(")
        depth = 1
        while depth:
            token = self.peek()
            if token is None:
                raise ReadError("')' is missing", self.end_span)
            self.index += 1
            if token.kind == "symbol" and token.text in "()":
                depth += 1 if token.text == "(" else -1

    def parameter(self) -> ir.Var:
        """``Q12``, ``QL3``, ``QR7``, ``QS2``, or an indirect ``Q(Q1+2)``."""
        prefix = self.next()
        if self.is_symbol("("):
            self.index += 1
            inner = self._sum()
            self.expect_symbol(")")
            return ir.Var(inner, prefix.span, prefix=prefix.text)
        token = self.peek()
        if token is None or token.kind != "number" or not token.text.isdigit():
            raise ReadError(f"{prefix.text} needs a parameter number", self.here())
        self.index += 1
        return ir.Var(f"{prefix.text}{int(token.text)}", prefix.span.cover(token.span))


def _function(name: str, argument):
    if name == "SQ":
        return ir.Binary("*", argument, argument)
    if name == "NEG":
        return ir.Unary("-", argument)
    if name == "FRAC":
        return ir.Binary("-", argument, ir.Func("FIX", (argument,)))
    if name == "LOG":
        return ir.Binary("/", ir.Func("LN", (argument,)), 2.302585092994046)
    if name == "SGN":
        return ir.Binary("-", ir.Binary("GT", argument, 0.0), ir.Binary("LT", argument, 0.0))
    return ir.Func(name, (argument,))
