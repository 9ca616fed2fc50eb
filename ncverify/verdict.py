"""Verdicts on symbolic values, below the interpreter and the checker.

A hazard is a concrete truth value or a :class:`~ncverify.values.Condition` over the free
parameters; :func:`judge` turns it into a :class:`Verdict` (violated with a witness, proved,
or unknown with the solver's reason). :func:`evaluate_constraint` computes the hazard of a
data-only rule constraint from ``rules/``. The interpreter (which replays witnesses and
checks project assumptions) and the checker both use this module, so it imports neither.
"""
from __future__ import annotations

import ast
import math
import operator
from dataclasses import dataclass, field


from .solver import z3
from . import values
from .diagnostics import Status
from .values import Condition, Sym

# --------------------------------------------------------------------------- judging symbolic values


@dataclass(frozen=True)
class Verdict:
    """Whether a hazard occurs, with a witness when it does."""

    status: Status
    witness: dict[str, float] = field(default_factory=dict)
    reason: str | None = None


def judge(hazard: "bool | Condition", path_condition: list, timeout_s: float = 5.0) -> Verdict | None:
    """Does the hazard occur? ``None`` when it certainly does not (concrete False)."""
    if hazard is True:
        return Verdict(Status.VIOLATED)
    if hazard is False:
        return None
    context = values.check_context()  # the check's own: a model that depends on the program alone

    def local(term):
        term = values.defined(term)
        return term if context is None else term.translate(context)

    solver = z3.Solver(ctx=context)
    solver.set("timeout", int(timeout_s * 1000))
    for condition in path_condition:
        if isinstance(condition, Condition):
            solver.add(local(condition.term))
    solver.add(local(hazard.term))
    answer = solver.check()
    if answer == z3.unsat:
        return Verdict(Status.PROVED)
    if answer == z3.sat:
        model = solver.model()
        witness = {}
        for declaration in model.decls():
            value = model[declaration]
            if z3.is_rational_value(value):
                witness[declaration.name()] = float(value.numerator_as_long()) / float(value.denominator_as_long())
            elif z3.is_algebraic_value(value):
                witness[declaration.name()] = float(value.approx(10).as_decimal(10).rstrip("?"))
        # sorted: the model lists its values in an order that varies from one check to the next in one process
        named = {k: v for k, v in sorted(witness.items()) if _names_a_parameter(k)}
        if _avoidable_by_unnamed_values(solver, model, hazard, local, context):
            return Verdict(Status.UNKNOWN, named, "it happens only for some values of a quantity ncverify does not know (a rounding, "
                                                  "a comparison of text, a probe result or another value no parameter names)")
        return Verdict(Status.VIOLATED, named)
    return Verdict(Status.UNKNOWN, reason=f"the solver gave no answer within {timeout_s:g} s ({solver.reason_unknown()})")


def _names_a_parameter(name: str) -> bool:
    """Parameters are named by the program; ``label~n`` are :func:`values.fresh` unknowns and
    ``!`` names the solver's own."""
    return "~" not in name and "!" not in name


def _avoidable_by_unnamed_values(solver, model, hazard: Condition, local, context) -> bool:
    """With the parameters fixed at the model's values, can the unknowns no parameter names
    (:func:`values.fresh`) still keep the hazard from happening? Then the hazard is no
    evidence of a fault: it needs one of those unknowns to take a particular value. A
    solver that cannot tell counts as avoidable."""
    assertions = list(solver.assertions())
    constants = _constants(assertions)
    fixed = [constant for constant in constants if _names_a_parameter(constant.decl().name()) or constant.decl().name().startswith(values.HELPER_MARK)]
    if len(fixed) == len(constants):
        return False
    check = z3.Solver(ctx=context)
    check.set("timeout", 2000)
    check.add(*assertions[:-1])  # the path condition; the hazard was added last
    check.add(z3.Not(local(hazard.term)))
    for constant in fixed:
        check.add(constant == model.eval(constant, model_completion=True))
    return check.check() != z3.unsat


def _constants(terms) -> list:
    """The uninterpreted constants (parameters and unknowns) the terms mention."""
    found, seen, stack = [], set(), list(terms)
    while stack:
        term = stack.pop()
        if term.get_id() in seen:
            continue
        seen.add(term.get_id())
        if z3.is_const(term) and term.decl().kind() == z3.Z3_OP_UNINTERPRETED:
            found.append(term)
        stack.extend(term.children())
    return found


_RELATION_NAMES = {"<": "LT", "<=": "LE", ">": "GT", ">=": "GE", "==": "EQ", "!=": "NE"}
_ON_NUMBERS = {relation: function for symbol, name, function in (("<", "LT", operator.lt), ("<=", "LE", operator.le), (">", "GT", operator.gt),
                                                                   (">=", "GE", operator.ge), ("==", "EQ", operator.eq), ("!=", "NE", operator.ne))
               for relation in (symbol, name)}


def hazard(op: str, a, b) -> "bool | Condition":
    """``a op b`` as a hazard condition, with ISO relation names or symbols. When a value
    is symbolic the answer stays a condition even if intervals decide it, so that the
    verdict is ``proved`` (or ``violated`` with a witness) rather than silence."""
    if type(a) is float and type(b) is float:
        return _ON_NUMBERS[op](a, b)  # what compare() gives two numbers, without its lookups
    outcome = values.compare(_RELATION_NAMES.get(op, op), a, b)
    if type(outcome) is bool and (isinstance(a, Sym) or isinstance(b, Sym)):
        return Condition(z3.BoolVal(outcome))
    return outcome


def show(value) -> str:
    """A value as a machinist reads it: 12.5, or the expression for a symbolic one."""
    if type(value) is float:
        return f"{value:.4f}".rstrip("0").rstrip(".") if math.isfinite(value) else str(value)
    if isinstance(value, Sym):
        return values.readable(values.simplified_text(value.term))
    return str(value)


# --------------------------------------------------------------------------- constraint expressions

_RELATIONS = {ast.Lt: "LT", ast.LtE: "LE", ast.Gt: "GT", ast.GtE: "GE", ast.Eq: "EQ", ast.NotEq: "NE"}


class _Missing(Exception):
    pass


def evaluate_constraint(tree: ast.Expression, names: dict) -> "bool | Condition":
    """True (or a condition) when the parameters are wrong; a missing name makes the
    comparison it sits in false."""
    return _truth(_guarded(tree.body, names))


def _truth(value):
    return value if isinstance(value, (bool, Condition)) else values.truth(value)


def _eval(node, names):
    if isinstance(node, ast.BoolOp):
        op = "AND" if isinstance(node.op, ast.And) else "OR"
        result = _guarded(node.values[0], names)
        for operand in node.values[1:]:
            result = values.logical(op, _truth(result), _truth(_guarded(operand, names)))
        return result
    if isinstance(node, ast.UnaryOp):
        operand = _eval(node.operand, names)
        if isinstance(node.op, ast.Not):
            return values.negate(_truth(operand))
        return values.neg(operand)
    if isinstance(node, ast.Compare):
        left = _eval(node.left, names)
        result = True
        for operator, right_node in zip(node.ops, node.comparators):
            right = _eval(right_node, names)
            step = values.compare(_RELATIONS[type(operator)], left, right)
            result = values.logical("AND", result, step) if result is not True else step
            left = right
        return result
    if isinstance(node, ast.BinOp):
        left, right = _eval(node.left, names), _eval(node.right, names)
        operation = {ast.Add: values.add, ast.Sub: values.sub, ast.Mult: values.mul, ast.Div: values.div}[type(node.op)]
        return operation(left, right)
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
        if node.func.id == "missing":
            return names.get(node.args[0].id) is None
        arguments = [_eval(arg, names) for arg in node.args]
        if node.func.id == "abs":
            return values.absolute(arguments[0])
        if node.func.id in ("min", "max"):
            return _min_max(node.func.id, arguments)
        if node.func.id == "whole":
            return values.is_whole(arguments[0])
        if node.func.id == "digits":
            return float(len(str(int(abs(arguments[0]))))) if type(arguments[0]) is float else values.fresh("digits")
    if isinstance(node, ast.Name):
        value = names.get(node.id)
        if value is None or isinstance(value, str):  # a string where a number belongs is another rule's finding
            raise _Missing(node.id)
        return value
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
        return float(node.value)
    raise ValueError(f"not allowed in a constraint: {ast.dump(node)}")


def _guarded(node, names):
    try:
        return _eval(node, names)
    except _Missing:
        return False


def _min_max(name, arguments):
    if all(type(argument) is float for argument in arguments):
        return min(arguments) if name == "min" else max(arguments)
    return values.fresh(name)


def both(first, second):
    """Both hazard conditions (True, False or conditions)."""
    if first is True or second is False:
        return second
    if second is True or first is False:
        return first
    return Condition(z3.And(first.term, second.term))
