"""Fagor's run-time state and operations: ``#TOOL AX`` and the cycle set (``#LATHECY`` /
``#MILLCY``) as typed state of the path (``state.fagor``, replaced, never changed in place,
so that forked paths keep their own), and the cycle blocks whose meaning depends on it,
which the lowering (:mod:`ncverify.lower.fagor`) resolves when they run.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

from .. import ir


@dataclass(frozen=True)
class FagorState:
    """What a Fagor cycle block means depends on besides the plane."""

    tool_axis: tuple[str, str] | None = None  # #TOOL AX: (axis, "+" or "-"), axis "?" for one not modelled; None: never set
    lathe_cycles: bool = False  # #LATHECY ON in force
    mill_cycles: bool = False  # #MILLCY ON in force


def _tool_axis(runtime, op: ir.ToolAxis, block):
    runtime.state.fagor = replace(runtime.state.fagor, tool_axis=(op.axis, op.direction))


def _cycle_set(runtime, op: ir.CycleSet, block):
    changed = {"lathe_cycles" if op.turning else "mill_cycles": op.on}
    runtime.state.fagor = replace(runtime.state.fagor, **changed)


def _resolve(runtime, op: ir.DialectDeferred, block):
    """A cycle block: lowered for the plane and the Fagor state in force here."""
    state = runtime.state
    ops, notes = op.resolve(state.modal["plane"], state.fagor)
    return runtime.run_lowered(ops, notes, block)


OPERATIONS = {ir.ToolAxis: _tool_axis, ir.CycleSet: _cycle_set, ir.DialectDeferred: _resolve}
