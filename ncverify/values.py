"""Values of the abstract interpreter: a ``float`` where the value is known, a :class:`Sym`
where it depends on a parameter the program never assigns.

A Sym carries a Z3 term (for the proofs) and an interval (for cheap decisions): most
questions - is this depth negative? is this feed zero? - are settled by the interval
without calling the solver. Concrete arithmetic never touches Z3. Transcendental functions
of symbolic values become fresh Z3 variables bounded by the function's range, which
over-approximates soundly: everything the program can do is still included. Rounding
(``FIX``, ``FUP``, ``ROUND``) and ``MIN``/``MAX`` are exact (see :func:`defined`).
"""
from __future__ import annotations

import functools
import itertools
import math
import re
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass

from .solver import z3

INF = math.inf


class DomainError(ArithmeticError):
    """An operation outside its domain (division by zero, SQRT of a negative ...)."""


@dataclass(frozen=True, slots=True)
class Sym:
    """A symbolic value: a solver term and the interval it is known to lie in."""

    term: z3.ArithRef
    low: float = -INF
    high: float = INF
    exact: bool = True  # False once an approximation (a transcendental) entered the term

    def __repr__(self) -> str:
        return f"Sym({self.term}, [{self.low}, {self.high}])"

    @property
    def parameters(self) -> set[str]:
        return {str(node) for node in _leaves(self.term)}


class Vacant:
    """The ISO macro "null" value of a variable that was never set (``#0``)."""

    _instance = None

    def __new__(cls):
        if cls._instance is None:
            cls._instance = super().__new__(cls)
        return cls._instance

    def __repr__(self) -> str:
        return "<vacant>"


VACANT = Vacant()
Value = float | Sym


def _leaves(term):
    if z3.is_const(term) and term.decl().kind() == z3.Z3_OP_UNINTERPRETED:
        yield term
        return
    for child in term.children():
        yield from _leaves(child)


def parameter(name: str, low: float = -INF, high: float = INF) -> Sym:
    """A free parameter, e.g. ``#1`` read before any assignment."""
    return Sym(z3.Real(name), low, high)


_fresh_numbers: ContextVar = ContextVar("fresh_numbers", default=None)


def fresh(label: str, low: float = -INF, high: float = INF) -> Sym:
    """An unknown value that no parameter names (a position after G28, a probe result).
    Its name is ``label~n``, numbered within the current :func:`fresh_numbering`."""
    numbers = _fresh_numbers.get()
    if numbers is None:
        numbers = itertools.count(1)
        _fresh_numbers.set(numbers)
    return Sym(z3.Real(f"{label}~{next(numbers)}"), low, high, exact=False)


HELPER_MARK = "?"  # the label's first character for an existential helper (a point along a path), not an unknown quantity


def helper(label: str) -> Sym:
    """An existential helper of one question (where along a move the tool meets the stock):
    the solver picks it, it stands for nothing the program or the machine leaves unknown."""
    return fresh(HELPER_MARK + label)


_FRESH_NAME = re.compile(r"([^\s()*+/~-]+)~\d+")


def readable(text: str) -> str:
    """A term's text with its unknown values (:func:`fresh`) named as a machinist reads
    them: by what they came from, not by their internal number (``FIX~3`` is ``FIX(…)``)."""
    return _FRESH_NAME.sub(_fresh_text, text)


def _fresh_text(match: re.Match) -> str:
    label = match.group(1)
    return f"{label}(…)" if label.isupper() and label.isalpha() else label


@contextmanager
def fresh_numbering():
    """Number the unknown values of one check from 1, so that checking the same program
    twice in one process (an editor, a test run) gives the same findings word for word."""
    token = _fresh_numbers.set(itertools.count(1))
    display = _display_context.set({})
    try:
        yield
    finally:
        _display_context.reset(display)
        _fresh_numbers.reset(token)


_display_context: ContextVar = ContextVar("display_context", default=None)


def check_context() -> "z3.Context | None":
    """The Z3 context of the current check (one per :func:`fresh_numbering`), or None
    outside a check. Z3 orders the arguments of a simplified And/Or and picks a model's
    values by its internal ids, which depend on every term the process made before; terms
    translated into the check's own context give text and witnesses that depend on the
    program alone, so a second check in the same process (an editor, a batch) reads the same."""
    holder = _display_context.get()
    if holder is None:
        return None
    if "context" not in holder:
        holder["context"] = z3.Context()
    return holder["context"]


def simplified_text(term) -> str:
    """``z3.simplify`` of a term, as text, in the check's own context."""
    context = check_context()
    return str(z3.simplify(term if context is None else term.translate(context)))


def term_of(value: Value) -> z3.ArithRef:
    return value.term if isinstance(value, Sym) else z3.RealVal(repr(float(value)) if math.isfinite(value) else "0")


def interval(value: Value) -> tuple[float, float]:
    return (value.low, value.high) if isinstance(value, Sym) else (value, value)


def is_concrete(value) -> bool:
    return type(value) is float


# --------------------------------------------------------------------------- arithmetic


def _mul_interval(a, b):
    products = [x * y for x in a for y in b if not (math.isinf(x) and y == 0 or math.isinf(y) and x == 0)]
    return (min(products), max(products)) if products else (-INF, INF)


def _sym(term, low, high, *operands) -> Sym:
    exact = all(operand.exact for operand in operands if isinstance(operand, Sym))
    return Sym(term, low, high, exact)


def add(a: Value, b: Value) -> Value:
    if type(a) is float and type(b) is float:
        return a + b
    (al, ah), (bl, bh) = interval(a), interval(b)
    return _sym(term_of(a) + term_of(b), al + bl, ah + bh, a, b)


def sub(a: Value, b: Value) -> Value:
    if type(a) is float and type(b) is float:
        return a - b
    (al, ah), (bl, bh) = interval(a), interval(b)
    return _sym(term_of(a) - term_of(b), al - bh, ah - bl, a, b)


def mul(a: Value, b: Value) -> Value:
    if type(a) is float and type(b) is float:
        return a * b
    low, high = _mul_interval(interval(a), interval(b))
    return _sym(term_of(a) * term_of(b), low, high, a, b)


def div(a: Value, b: Value) -> Value:
    if type(b) is float:
        if b == 0.0:
            raise DomainError("division by zero")
        if type(a) is float:
            return a / b
        return mul(a, 1.0 / b)
    bl, bh = interval(b)
    if bl <= 0.0 <= bh:
        low, high = -INF, INF
    else:
        low, high = _mul_interval(interval(a), (1.0 / bh, 1.0 / bl))
    return _sym(term_of(a) / term_of(b), low, high, a, b)


def neg(a: Value) -> Value:
    if type(a) is float:
        return -a
    return _sym(-a.term, -a.high, -a.low, a)


def absolute(a: Value) -> Value:
    if type(a) is float:
        return abs(a)
    low, high = a.low, a.high
    bounds = (0.0 if low <= 0.0 <= high else min(abs(low), abs(high)), max(abs(low), abs(high)))
    return _sym(z3.If(a.term >= 0, a.term, -a.term), bounds[0], bounds[1], a)


# Functions of one argument: concrete implementation, domain check, and the range used to
# bound a fresh variable when the argument is symbolic.
def _check(condition: bool, message: str) -> None:
    if not condition:
        raise DomainError(message)


def _sqrt(x):
    _check(x >= 0, f"SQRT of a negative number ({x:g})")
    return math.sqrt(x)


def _ln(x):
    _check(x > 0, f"LN of {x:g} (needs a positive number)")
    return math.log(x)


def _asin(x):
    _check(-1 <= x <= 1, f"ASIN of {x:g} (outside -1..1)")
    return math.degrees(math.asin(x))


def _acos(x):
    _check(-1 <= x <= 1, f"ACOS of {x:g} (outside -1..1)")
    return math.degrees(math.acos(x))


def _tan(x):
    _check(abs(math.cos(math.radians(x))) > 1e-12, f"TAN of {x:g} degrees (infinite)")
    return math.tan(math.radians(x))


def _exp(x):
    _check(x < 700, f"EXP of {x:g} overflows")
    return math.exp(x)


def _round_half_away(x):
    return float(math.floor(abs(x) + 0.5) * (1 if x >= 0 else -1))


_FUNCTIONS = {
    "SIN": (lambda x: math.sin(math.radians(x)), (-1.0, 1.0)),
    "COS": (lambda x: math.cos(math.radians(x)), (-1.0, 1.0)),
    "TAN": (_tan, (-INF, INF)),
    "ASIN": (_asin, (-90.0, 90.0)),
    "ACOS": (_acos, (0.0, 180.0)),
    "ATAN": (lambda x: math.degrees(math.atan(x)), (-90.0, 90.0)),
    "SQRT": (_sqrt, (0.0, INF)),
    "LN": (_ln, (-INF, INF)),
    "EXP": (_exp, (0.0, INF)),
    "ROUND": (_round_half_away, (-INF, INF)),
    "FIX": (lambda x: float(math.floor(x) if x >= 0 else math.ceil(x)), (-INF, INF)),
    "FUP": (lambda x: float(math.ceil(x) if x >= 0 else math.floor(x)), (-INF, INF)),
    "BIN": (lambda x: x, (-INF, INF)),
    "BCD": (lambda x: x, (-INF, INF)),
}


# Rounding and MIN/MAX of symbolic values stay named in their term, so that a finding shows
# FIX(Q1 / 2), not a formula; :func:`defined` puts their exact definition in their place
# for the solver (Z3's ToInt is the floor). Each maps a bound the way it maps a value
# (they are monotone), which gives the interval.
@functools.cache
def _named() -> dict:
    """The Z3 function of each name (made on first use: Z3 is imported only when needed)."""
    return {name: z3.Function(name, *(z3.RealSort(),) * (arity + 1)) for name, arity in (("FIX", 1), ("FUP", 1), ("ROUND", 1), ("MIN", 2), ("MAX", 2))}


def _floor(term):
    return z3.ToReal(z3.ToInt(term))


@functools.cache
def _definitions() -> tuple:
    x, y = z3.Var(0, z3.RealSort()), z3.Var(1, z3.RealSort())
    bodies = {"FIX": z3.If(x >= 0, _floor(x), -_floor(-x)), "FUP": z3.If(x >= 0, -_floor(-x), _floor(x)),
              "ROUND": z3.If(x >= 0, _floor(x + 0.5), -_floor(0.5 - x)), "MIN": z3.If(x <= y, x, y), "MAX": z3.If(x >= y, x, y)}
    return tuple((_named()[name], body) for name, body in bodies.items())


def defined(term):
    """``term`` with every named rounding and MIN/MAX replaced by its definition."""
    return z3.substitute_funs(term, *_definitions())


_ON_BOUNDS = {"FIX": lambda x: float(math.trunc(x)), "FUP": lambda x: float(math.ceil(x) if x >= 0 else math.floor(x)), "ROUND": _round_half_away}


def _rounded(name: str, argument: Sym) -> Sym:
    low, high = ((_ON_BOUNDS[name](bound) if math.isfinite(bound) else bound) for bound in (argument.low, argument.high))
    return _sym(_named()[name](argument.term), low, high, argument)


def extreme(name: str, a: Value, b: Value) -> Value:
    """``MIN``/``MAX`` of two values, exact for symbolic ones."""
    if type(a) is float and type(b) is float:
        return min(a, b) if name == "MIN" else max(a, b)
    (al, ah), (bl, bh) = interval(a), interval(b)
    pick = min if name == "MIN" else max
    return _sym(_named()[name](term_of(a), term_of(b)), pick(al, bl), pick(ah, bh), a, b)


def call(name: str, args: list[Value]) -> Value:
    if name == "ABS":
        return absolute(args[0])
    if name in ("MIN", "MAX"):
        return extreme(name, *args)
    if name == "ATAN2":
        y, x = args
        if type(y) is float and type(x) is float:
            _check(not (y == 0 and x == 0), "ATAN of 0/0")
            return math.degrees(math.atan2(y, x)) % 360.0
        return fresh("ATAN", 0.0, 360.0)
    implementation, (low, high) = _FUNCTIONS[name]
    argument = args[0]
    if type(argument) is float:
        try:
            return float(implementation(argument))
        except OverflowError as error:
            raise DomainError(f"{name} of {argument:g} overflows") from error
        except ValueError as error:  # an infinite or NaN argument (SIN, FIX, ...)
            raise DomainError(f"{name} of {argument:g} has no value") from error
    if name == "SQRT":
        _check(argument.high >= 0, f"SQRT of a negative number (at most {argument.high:g})")
    if name == "LN":
        _check(argument.high > 0, f"LN of a number that is at most {argument.high:g}")
    if name in _ON_BOUNDS:
        return _rounded(name, argument)
    return fresh(name, low, high)


def number_function(name: str):
    """What :func:`call` computes for one plain number given to the one-argument function
    ``name`` (it may raise :class:`DomainError` or an overflow), or None for the others."""
    entry = _FUNCTIONS.get(name)
    return None if entry is None else entry[0]


def known_functions() -> set[str]:
    return set(_FUNCTIONS) | {"ABS", "ATAN2", "MIN", "MAX"}


# --------------------------------------------------------------------------- logic

_COMPARE = {
    "EQ": lambda a, b: a == b,
    "NE": lambda a, b: a != b,
    "GT": lambda a, b: a > b,
    "GE": lambda a, b: a >= b,
    "LT": lambda a, b: a < b,
    "LE": lambda a, b: a <= b,
}
COMPARISONS = frozenset(_COMPARE)


@dataclass(frozen=True, slots=True)
class Condition:
    """A branch condition that depends on free parameters."""

    term: z3.BoolRef


def compare(op: str, a: Value, b: Value) -> "bool | Condition":
    if type(a) is float and type(b) is float:
        return _COMPARE[op](a, b)
    (al, ah), (bl, bh) = interval(a), interval(b)
    decided = _decide_by_interval(op, al, ah, bl, bh)
    if decided is not None:
        return decided
    return Condition(_COMPARE[op](term_of(a), term_of(b)))


def is_whole(a: Value) -> "bool | Condition":
    """Is the value a whole number (a count of pecks, of points)?"""
    if type(a) is float:
        return a.is_integer()
    return Condition(z3.IsInt(term_of(a)))


def _decide_by_interval(op, al, ah, bl, bh) -> bool | None:
    if op in ("LT", "GE"):
        if ah < bl:
            return op == "LT"
        if al >= bh:
            return op == "GE"
    elif op in ("GT", "LE"):
        if al > bh:
            return op == "GT"
        if ah <= bl:
            return op == "LE"
    elif op in ("EQ", "NE"):
        if ah < bl or al > bh:
            return op == "NE"
    return None


def stored(value):
    """What a variable holds when ``value`` is written to it: a decided condition as 1 or 0,
    an undecided one as a fresh unknown between 0 and 1; any other value as it is."""
    if isinstance(value, (bool, Condition)):
        return 1.0 if value is True else 0.0 if value is False else fresh("condition", 0.0, 1.0)
    return value


def truth(value) -> "bool | Condition":
    """Truth of a numeric value used as a condition (non-zero is true)."""
    if isinstance(value, (bool, Condition)):
        return value
    return compare("NE", value, 0.0)


def logical(op: str, a, b) -> "bool | Condition | float":
    """AND / OR / XOR: logical on conditions, bitwise on integers (ISO macro semantics)."""
    if isinstance(a, (bool, Condition)) or isinstance(b, (bool, Condition)):
        a, b = truth(a), truth(b)
        if type(a) is bool and type(b) is bool:
            return {"AND": a and b, "OR": a or b, "XOR": a != b}[op]
        ta = a.term if isinstance(a, Condition) else z3.BoolVal(a)
        tb = b.term if isinstance(b, Condition) else z3.BoolVal(b)
        return Condition({"AND": z3.And, "OR": z3.Or, "XOR": z3.Xor}[op](ta, tb))
    if type(a) is float and type(b) is float and math.isfinite(a) and math.isfinite(b):
        ia, ib = int(a), int(b)
        return float({"AND": ia & ib, "OR": ia | ib, "XOR": ia ^ ib}[op])
    return fresh(op)


def negate(condition: "bool | Condition") -> "bool | Condition":
    return (not condition) if type(condition) is bool else Condition(z3.Not(condition.term))


def modulo(a: Value, b: Value) -> Value:
    if type(a) is float and type(b) is float:
        if b == 0.0:
            raise DomainError("MOD by zero")
        if math.isinf(a):
            raise DomainError(f"MOD of {a:g}")  # fmod's domain error, not a value
        return math.fmod(a, b)
    return fresh("MOD")


def power(a: Value, b: Value) -> Value:
    """``a ** b`` (RS274NGC): a negative base needs a whole exponent, as in C's pow."""
    if type(a) is float and type(b) is float:
        if a < 0 and not b.is_integer() or a == 0 and b < 0:
            raise DomainError(f"{a:g} ** {b:g} has no real value")
        try:
            return float(a**b)
        except OverflowError as error:
            raise DomainError(f"{a:g} ** {b:g} overflows") from error
    return fresh("POWER")


def distance_sq(a1, a2, b1, b2):
    """Squared distance of two points in a plane (exact for symbolic values)."""
    d1, d2 = sub(a1, b1), sub(a2, b2)
    if type(d1) is float and type(d2) is float:  # the usual case, asked for every arc
        return d1 * d1 + d2 * d2
    return add(mul(d1, d1), mul(d2, d2))


def distance(a1, a2, b1, b2):
    """Distance of two points; None when it depends on free parameters (the arc rule then
    answers unknown rather than compare radii it cannot compute exactly)."""
    d1, d2 = sub(a1, b1), sub(a2, b2)
    if type(d1) is float and type(d2) is float:
        return math.hypot(d1, d2)
    return None

