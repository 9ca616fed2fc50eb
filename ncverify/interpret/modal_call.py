"""The modal call as the interpreter runs it: which program runs after every move, with
which arguments (the IR operations :class:`ir.ModalCallOn`, :class:`ir.ModalCallOff`,
:class:`ir.ModalCallRun` and :class:`ir.NoteInsideModalCall`, written by
:mod:`ncverify.lower.modal_call`). The call is :attr:`MachineState.modal_call`, replaced,
never changed in place, so that it forks with the path.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

from .. import ir
from ..values import VACANT, stored


@dataclass(frozen=True)
class ModalCall:
    """The last modal call switched on: its program, its arguments by key (evaluated when
    it was switched on) and whether it is still on. Switching it off keeps the program:
    while that program runs, an MCALL in it still nests."""

    program: object  # the value of the program expression: a name, as a rule
    arguments: dict = field(default_factory=dict)
    on: bool = True

    def running(self, call_stack) -> bool:
        """Whether the modally called program runs now (it is on the call stack)."""
        return any(frame.program == self.program for frame in call_stack)


def active_program(state) -> str | None:
    """The program called after every move while a modal call is on, else None."""
    call = state.modal_call
    if call is None or not call.on:
        return None
    return call.program if isinstance(call.program, str) else "the modal subprogram"


def switch_on(runtime, op: ir.ModalCallOn, block):
    program = runtime.evaluate(op.program, op.span)
    arguments = {key: stored(runtime.evaluate(expr, op.span)) for key, expr in op.arguments.items()}
    runtime.state.modal_call = ModalCall(program, arguments)


def switch_off(runtime, op: ir.ModalCallOff, block):
    call = runtime.state.modal_call
    if call is not None:
        runtime.state.modal_call = replace(call, on=False)


def run_after_move(runtime, op: ir.ModalCallRun, block):
    """The call of the modal program after a block that moved, unless it runs already."""
    state = runtime.state
    call = state.modal_call
    if call is None or not call.on or call.running(state.call_stack):
        return None
    arguments = {name: call.arguments.get(key, VACANT) for name, key in op.parameters.items()}
    return runtime.call_subprogram(ir.Call(op.span, op.kind, call.program, 1.0, arguments), block)


def note_inside(runtime, op: ir.NoteInsideModalCall, block):
    call = runtime.state.modal_call
    if call is not None and call.running(runtime.state.call_stack):
        runtime.note(op.note)


HANDLERS = {ir.ModalCallOn: switch_on, ir.ModalCallOff: switch_off, ir.ModalCallRun: run_after_move,
            ir.NoteInsideModalCall: note_inside}
