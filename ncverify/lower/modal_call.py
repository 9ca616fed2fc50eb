"""A subprogram called modally: after every block that moves an axis until it is switched off
(Fagor ``#MCALL`` ... ``#MDOFF``, SINUMERIK ``MCALL NAME(...)`` ... ``MCALL``).

The lowering writes the IR operations :class:`ir.ModalCallOn`, :class:`ir.ModalCallOff` and,
on every block that moves, :class:`ir.ModalCallRun`; the interpreter keeps the call as typed
machine state that forks with the path (:mod:`ncverify.interpret.modal_call`). A lowering that
uses it must not batch plain motion blocks, whose ops would lack the call.
"""
from __future__ import annotations

from .. import ir
from ..source import Span


def switch_on(span: Span, program: ir.Expr, arguments: dict, keys, missing: ir.Expr) -> ir.ModalCallOn:
    """Make ``program`` the modal call with ``arguments`` (by key); every key of ``keys``
    the call does not pass gets ``missing``."""
    return ir.ModalCallOn(span, program, {key: arguments.get(key, missing) for key in keys})


def moves(ops) -> bool:
    """Does a block with these ops move an axis (and so run the modal call after it)?"""
    return any(isinstance(op, ir.Move) and (op.targets or op.arc) for op in ops)
