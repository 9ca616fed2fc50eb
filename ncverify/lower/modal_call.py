"""A subprogram called modally: after every block that moves an axis until it is switched off
(Fagor ``#MCALL`` ... ``#MDOFF``, SINUMERIK ``MCALL NAME(...)`` ... ``MCALL``).

The call is state in global variables: ``$MCALL`` (on/off), ``$MCALLNAME`` (the program) and
one ``$MCALLARG:<key>`` per argument, evaluated when the call is switched on. A block that
moves carries :func:`call_after_move`, a conditional call that does not run while the
modally called program itself runs (``$INMCALL``, :func:`ncverify.interpret.modal_call.system_value`). A lowering that
uses it must not batch plain motion blocks, whose ops would lack the call.
"""
from __future__ import annotations

from .. import ir
from ..source import Span
from ..interpret.modal_call import ARGUMENT_PREFIX, INSIDE, NAME, SWITCH

_SWITCH, _NAME, _INSIDE = ir.Var(SWITCH), ir.Var(NAME), ir.Var(INSIDE)


def _argument(key: str) -> ir.Var:
    return ir.Var(f"{ARGUMENT_PREFIX}{key}")


def switch_on(span: Span, program: ir.Expr, arguments: dict, keys, missing: ir.Expr) -> list[ir.Op]:
    """Make ``program`` the modal call with ``arguments`` (by key); every key of ``keys``
    the call does not pass gets ``missing``."""
    assigns = [ir.Assign(span, _SWITCH, 1.0), ir.Assign(span, _NAME, program)]
    return assigns + [ir.Assign(span, _argument(key), arguments.get(key, missing)) for key in keys]


def switch_off(span: Span) -> ir.Op:
    return ir.Assign(span, _SWITCH, 0.0)


def moves(ops) -> bool:
    """Does a block with these ops move an axis (and so run the modal call after it)?"""
    return any(isinstance(op, ir.Move) and (op.targets or op.arc) for op in ops)


def call_after_move(span: Span, kind: str, parameters: dict) -> ir.Conditional:
    """The modal call, if one is on and its program is not running: an :class:`ir.Call` of
    ``kind`` whose argument ``name`` is the value stored for ``parameters[name]``."""
    arguments = {name: _argument(key) for name, key in parameters.items()}
    call = ir.Call(span, kind, _NAME, 1.0, arguments)
    outside = ir.Binary("EQ", _INSIDE, 0.0)
    return ir.Conditional(span, ir.Binary("AND", ir.Binary("NE", _SWITCH, 0.0), outside), [call])


def inside_check(span: Span, resolve) -> ir.Deferred:
    """An op that calls ``resolve((1.0,))`` while the modally called program runs and
    ``resolve((0.0,))`` otherwise, for the ops and notes it returns."""
    return ir.Deferred(span, (_INSIDE,), resolve)
