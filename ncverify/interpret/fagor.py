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
    repeat_end: object = -1.0  # (RPT N10, N20) running: the label of its last block (N20); -1 otherwise


def _tool_axis(runtime, op: ir.ToolAxis, block):
    runtime.state.fagor = replace(runtime.state.fagor, tool_axis=(op.axis, op.direction))


def _cycle_set(runtime, op: ir.CycleSet, block):
    changed = {"lathe_cycles" if op.turning else "mill_cycles": op.on}
    runtime.state.fagor = replace(runtime.state.fagor, **changed)


def _repeat_end(runtime, op: ir.RepeatEnd, block):
    last = -1.0 if op.label is None else runtime.evaluate(op.label, op.span)
    runtime.state.fagor = replace(runtime.state.fagor, repeat_end=last)


def _resolve(runtime, op: ir.DialectDeferred, block):
    """A cycle block: lowered for the plane and the Fagor state in force here."""
    state = runtime.state
    ops, notes = op.resolve(state.modal["plane"], state.fagor)
    return runtime.run_lowered(ops, notes, block)


OPERATIONS = {ir.ToolAxis: _tool_axis, ir.CycleSet: _cycle_set, ir.RepeatEnd: _repeat_end, ir.DialectDeferred: _resolve}
