"""IR expressions compiled into closures, for the expressions a loop body evaluates on every pass.

:func:`compile_expression` turns an expression tree into nested closures, one per node,
that take the evaluation's span and return the value
:meth:`~ncverify.interpret.Interpreter.evaluate_tree` would. Each node computes plain floats
itself (a loop counter, a coordinate from parameter arithmetic) and hands every other value
(vacant, text, symbolic, a comparison's outcome used as a number) to the interpreter's
general step for that node (:meth:`~ncverify.interpret.Interpreter.combined`,
:meth:`~ncverify.interpret.Interpreter.negated`,
:meth:`~ncverify.interpret.Interpreter.function_value`), so faults, their spans and symbolic
results stay those of the general evaluation. Operands are evaluated in the same order.

A variable's storage (local or global, by the frontend's scope of its name) is resolved
when the node is compiled; a variable not set on the current path is read by the general
:meth:`~ncverify.interpret.Interpreter.read_variable` (vacant, system variable, free
parameter).
"""
from __future__ import annotations

import math
import operator
from functools import lru_cache

from .. import ir, values

COMPILED_KINDS = frozenset({ir.Var, ir.Unary, ir.Binary, ir.Func})  # nodes worth compiling (the rest are leaves)

_ABSENT = object()  # not in a variable table


def compile_expression(interpreter, expr):
    """A closure ``run(span)`` that evaluates ``expr`` as ``interpreter.evaluate_tree`` does:
    the tree of closures (:func:`_closure`), run first as straight-line code where it can be
    (:func:`_straight`)."""
    general = _closure(interpreter, expr)
    return _straight(interpreter, expr, general) or general


def _closure(interpreter, expr):
    kind = type(expr)
    if kind is float and expr - expr == 0.0:
        return lambda span: expr
    if kind is ir.Var:
        return _variable(interpreter, expr)
    if kind is ir.Unary:
        return _sign(interpreter, expr)
    if kind is ir.Binary:
        return _binary(interpreter, expr)
    if kind is ir.Func:
        return _function(interpreter, expr)
    return lambda span: interpreter.evaluate_tree(expr, span)  # leaves that read the state, and a number out of range


def compile_assignment(interpreter, op: ir.Assign):
    """A closure ``run()`` that carries out ``op`` as ``interpreter._assign`` does: a value is
    written to the table of the target's scope (:func:`values.stored` of it). Assignments
    recorded for the editor, to a computed variable number, and to machine data go through
    :meth:`~ncverify.interpret.Interpreter.write_variable`."""
    value, target, span = compile_expression(interpreter, op.value), op.target, op.span
    if not isinstance(target.name, str) or interpreter.settings.record_values or interpreter.is_machine_data(target.name):
        write = interpreter.write_variable
        return lambda: write(target, value(span), span, assignment=True)
    name = target.name
    local = interpreter.is_local(name)

    def assign():
        result = value(span)
        state = interpreter.state
        (state.local_variables if local else state.global_variables)[name] = result if type(result) is float else values.stored(result)

    return assign


def _variable(interpreter, var: ir.Var):
    if not isinstance(var.name, str):  # an indirect reference: its name is computed on every read
        return lambda span: interpreter.read_variable(var, span)
    name = var.name
    local = interpreter.is_local(name)

    def read(span):
        state = interpreter.state
        value = (state.local_variables if local else state.global_variables).get(name, _ABSENT)
        return interpreter.read_variable(var, span) if value is _ABSENT else value

    return read


def _sign(interpreter, expr: ir.Unary):
    operand = _closure(interpreter, expr.operand)

    def run(span):
        value = operand(span)
        return -value if type(value) is float else interpreter.negated(value, expr, span)

    return run


def _function(interpreter, expr: ir.Func):
    arguments = [(_closure(interpreter, arg), arg) for arg in expr.args]
    convert = interpreter._arithmetic_operand
    on_number = values.number_function(expr.name) if len(arguments) == 1 else None
    if on_number is not None:
        return _one_argument(interpreter, expr, arguments[0], on_number)

    def run(span):
        known = []
        for argument, written in arguments:
            value = argument(span)
            known.append(value if type(value) is float else convert(value, written, span))
        return interpreter.function_value(expr, known, span)

    return run


def _one_argument(interpreter, expr: ir.Func, argument, on_number):
    """SIN, FIX ... of a plain float computed here; any other argument, a domain error or
    an overflow goes to the general step, which reports it."""
    run_argument, written = argument
    convert, general = interpreter._arithmetic_operand, interpreter.function_value

    def run(span):
        value = run_argument(span)
        if type(value) is not float:
            return general(expr, [convert(value, written, span)], span)
        try:
            return float(on_number(value))
        except (ArithmeticError, ValueError):  # values.DomainError, OverflowError; an infinite or NaN argument
            return general(expr, [value], span)

    return run


def _binary(interpreter, expr: ir.Binary):
    """Plain floats are added, subtracted, multiplied, divided by a non-zero number and
    compared here; everything else (and every result past the float range) goes to
    :meth:`~ncverify.interpret.Interpreter.combined`."""
    left, right = _closure(interpreter, expr.left), _closure(interpreter, expr.right)
    combined = interpreter.combined
    op = expr.op
    inline = _INLINE.get(op)
    if inline is None:
        return lambda span: combined(expr, left(span), right(span), span)
    return inline(expr, left, right, combined)


def _arithmetic(operation):
    """A node of arithmetic on floats: the operation itself; a division by zero, a domain
    error or a result past the float range goes to the general step, which reports it."""
    def build(expr, left, right, combined):
        def run(span):
            a, b = left(span), right(span)
            if type(a) is float and type(b) is float:
                try:
                    result = operation(a, b)
                except ArithmeticError:  # ZeroDivisionError, values.DomainError
                    return combined(expr, a, b, span)
                if result - result == 0.0:
                    return result
            return combined(expr, a, b, span)
        return run
    return build


def _comparison(test):
    """A node comparing floats; a decided comparison's outcome (True, False) counts 1 or 0,
    as the general step counts it (a negated condition is ``[c] EQ 0``)."""
    def build(expr, left, right, combined):
        def run(span):
            a, b = left(span), right(span)
            if type(b) is float:
                if type(a) is float:
                    return test(a, b)
                if type(a) is bool:
                    return test(1.0 if a else 0.0, b)
            return combined(expr, a, b, span)
        return run
    return build


_INLINE = {"+": _arithmetic(operator.add), "-": _arithmetic(operator.sub), "*": _arithmetic(operator.mul),
           "/": _arithmetic(operator.truediv), "MOD": _arithmetic(values.modulo), "**": _arithmetic(values.power),
           "EQ": _comparison(operator.eq), "NE": _comparison(operator.ne), "GT": _comparison(operator.gt),
           "GE": _comparison(operator.ge), "LT": _comparison(operator.lt), "LE": _comparison(operator.le)}


# ---------------------------------------------------------------------------- straight-line code

def _straight(interpreter, expr, general):
    """``expr`` as one generated function (a loop body's arithmetic costs one call, not one
    per node) where it is made of finite numbers, named variables, signs, the arithmetic and
    comparisons the closures compute inline and the one-argument functions: it reads every
    variable first and computes on floats, and hands the whole evaluation to ``general``
    (the tree of closures) as soon as a variable holds anything but a float, an operation
    fails or a result leaves the float range. Reading a variable that is set changes
    nothing, so the general evaluation, started again, reports what it would have reported
    alone. None for any other tree, and for a bare leaf (nothing to gain)."""
    if type(expr) not in (ir.Unary, ir.Binary, ir.Func):
        return None
    code = StraightCode(interpreter)
    result = code.node(expr)
    if result is None or code.size > _STRAIGHT_NODES:
        return None
    text = code.text(result[0])
    return factory(text)(interpreter, general, _ABSENT, tuple(code.constants), tuple(code.names), tuple(code.functions))


_STRAIGHT_NODES = 48  # larger trees stay closures (generated code is compiled once per shape)
_STRAIGHT_ARITHMETIC = {"+": "{} + {}", "-": "{} - {}", "*": "{} * {}", "/": "{} / {}"}
_STRAIGHT_CALLED = {"MOD": math.fmod, "**": values.power}  # fmod raises on a zero divisor, as values.modulo does: the general step reports it
# One-argument functions written out where that gives values.call's result bit for bit on
# every float (math.radians is x * pi / 180; FIX truncates) and fails where it fails.
_STRAIGHT_FUNCTIONS = {"SIN": ("{}({} * %r)" % (math.pi / 180), math.sin), "COS": ("{}({} * %r)" % (math.pi / 180), math.cos),
                       "FIX": ("float({}({}))", math.trunc)}
_STRAIGHT_COMPARISON = {"EQ": "==", "NE": "!=", "GT": ">", "GE": ">=", "LT": "<", "LE": "<="}


class StraightCode:
    """The lines of one straight-line function: variable reads, then steps on floats (also
    the steps of a whole loop pass, :mod:`.loop_runner`)."""

    def __init__(self, interpreter):
        self.interpreter = interpreter
        self.reads, self.steps, self.checked = [], [], []
        self.constants, self.names, self.functions = [], [], []
        self.size = 0

    def node(self, expr) -> tuple[str, bool] | None:
        """The Python operand computing ``expr`` and whether it is a comparison's outcome
        (a bool), or None when ``expr`` is not straight-line arithmetic."""
        self.size += 1
        kind = type(expr)
        if kind is float:
            if expr - expr != 0.0:
                return None
            self.constants.append(expr)
            return f"c{len(self.constants) - 1}", False
        if kind is ir.Var:
            return self._read(expr)
        if kind is ir.Unary:
            operand = self.node(expr.operand)
            return None if operand is None or operand[1] else self._step(f"-{operand[0]}", checked=False)
        if kind is ir.Binary:
            return self._binary(expr)
        if kind is ir.Func and len(expr.args) == 1 and values.number_function(expr.name) is not None:
            argument = self.node(expr.args[0])
            if argument is None or argument[1]:
                return None
            template, function = _STRAIGHT_FUNCTIONS.get(expr.name, ("float({}({}))", values.number_function(expr.name)))
            return self._step(template.format(self._function(function), argument[0]))
        return None

    def _read(self, var: ir.Var):
        if not isinstance(var.name, str):
            return None
        self.names.append(var.name)
        table = "local" if self.interpreter.is_local(var.name) else "global_"
        name = f"v{len(self.reads)}"
        self.reads.append(f"{name} = {table}.get(n{len(self.names) - 1}, ABSENT)\n        if type({name}) is not float:\n            return general(span)")
        return name, False

    def _binary(self, expr: ir.Binary):
        left, right = self.node(expr.left), self.node(expr.right)
        if left is None or right is None:
            return None
        op = expr.op
        if op in _STRAIGHT_COMPARISON:
            operands = [f"(1.0 if {text} else 0.0)" if outcome else text for text, outcome in (left, right)]
            return self._step(f"{operands[0]} {_STRAIGHT_COMPARISON[op]} {operands[1]}", checked=False, outcome=True)
        if left[1] or right[1]:
            return None  # a comparison's outcome in arithmetic: the general step converts it
        if op in _STRAIGHT_ARITHMETIC:
            return self._step(_STRAIGHT_ARITHMETIC[op].format(left[0], right[0]))
        if op in _STRAIGHT_CALLED:
            return self._step(f"{self._function(_STRAIGHT_CALLED[op])}({left[0]}, {right[0]})")
        return None

    def _function(self, function) -> str:
        self.functions.append(function)
        return f"f{len(self.functions) - 1}"

    def _step(self, computed: str, checked: bool = True, outcome: bool = False):
        name = f"t{len(self.steps)}"
        self.steps.append(f"{name} = {computed}")
        if checked:
            self.checked.append(name)
        return name, outcome

    def text(self, result: str) -> str:
        """The source of a factory ``make(interpreter, general, ABSENT, c, n, f)`` of the function."""
        unpack = "".join(f"    {', '.join(f'{letter}{index}' for index in range(count))}, = {letter}\n"
                         for letter, count in (("c", len(self.constants)), ("n", len(self.names)), ("f", len(self.functions))) if count)
        reads = "".join(f"        {read}\n" for read in self.reads)
        steps = "".join(f"            {step}\n" for step in self.steps)
        checks = f"        if {' or '.join(f'{name} - {name} != 0.0' for name in self.checked)}:\n            return general(span)\n" if self.checked else ""
        return ("def make(interpreter, general, ABSENT, c, n, f):\n" + unpack
                + "    def run(span):\n        state = interpreter.state\n"
                + "        local, global_ = state.local_variables, state.global_variables\n" + reads
                + f"        try:\n{steps}        except (ArithmeticError, ValueError):\n            return general(span)\n"
                + checks + f"        return {result}\n    return run\n")


@lru_cache(maxsize=512)
def factory(text: str):
    """The factory defined by ``text`` (one per shape of tree: a loop's expressions share a few)."""
    namespace = {}
    exec(compile(text, "<straight-line expression>", "exec"), namespace)  # noqa: S102 - text generated above from a fixed grammar
    return namespace["make"]
