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

import operator

from .. import ir, values

COMPILED_KINDS = frozenset({ir.Var, ir.Unary, ir.Binary, ir.Func})  # nodes worth compiling (the rest are leaves)

_ABSENT = object()  # not in a variable table


def compile_expression(interpreter, expr):
    """A closure ``run(span)`` that evaluates ``expr`` as ``interpreter.evaluate_tree`` does."""
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
    recorded for the editor, and to a computed variable number, go through
    :meth:`~ncverify.interpret.Interpreter.write_variable`."""
    value, target, span = compile_expression(interpreter, op.value), op.target, op.span
    if not isinstance(target.name, str) or interpreter.settings.record_values:
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
    operand = compile_expression(interpreter, expr.operand)

    def run(span):
        value = operand(span)
        return -value if type(value) is float else interpreter.negated(value, expr, span)

    return run


def _function(interpreter, expr: ir.Func):
    arguments = [(compile_expression(interpreter, arg), arg) for arg in expr.args]
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
        except ArithmeticError:  # values.DomainError, OverflowError
            return general(expr, [value], span)

    return run


def _binary(interpreter, expr: ir.Binary):
    """Plain floats are added, subtracted, multiplied, divided by a non-zero number and
    compared here; everything else (and every result past the float range) goes to
    :meth:`~ncverify.interpret.Interpreter.combined`."""
    left, right = compile_expression(interpreter, expr.left), compile_expression(interpreter, expr.right)
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
    def build(expr, left, right, combined):
        def run(span):
            a, b = left(span), right(span)
            if type(a) is float and type(b) is float:
                return test(a, b)
            return combined(expr, a, b, span)
        return run
    return build


_INLINE = {"+": _arithmetic(operator.add), "-": _arithmetic(operator.sub), "*": _arithmetic(operator.mul),
           "/": _arithmetic(operator.truediv), "MOD": _arithmetic(values.modulo), "**": _arithmetic(values.power),
           "EQ": _comparison(operator.eq), "NE": _comparison(operator.ne), "GT": _comparison(operator.gt),
           "GE": _comparison(operator.ge), "LT": _comparison(operator.lt), "LE": _comparison(operator.le)}
