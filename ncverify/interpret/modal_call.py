"""The modal call as the interpreter sees it: which program runs after every move, and the
values of the variables the lowering (:mod:`ncverify.lower.modal_call`) reads and writes.
"""
from __future__ import annotations

from ..values import VACANT

SWITCH, NAME, INSIDE = "$MCALL", "$MCALLNAME", "$INMCALL"
ARGUMENT_PREFIX = "$MCALLARG:"


def active_program(state) -> str | None:
    """The program called after every move while a modal call is on, else None."""
    if state.global_variables.get(SWITCH) in (None, 0.0, VACANT):
        return None
    name = state.global_variables.get(NAME)
    return name if isinstance(name, str) else "the modal subprogram"


def running_program(state) -> str | None:
    """The name of the modally called program if it is running now."""
    name = state.global_variables.get(NAME)
    return name if any(frame.program == name for frame in state.call_stack) else None


def system_value(name: str, state):
    """``$INMCALL``, ``$MCALL`` before any modal call, and an argument no call stored
    (vacant); None for any other name."""
    if name == INSIDE:
        return 0.0 if running_program(state) is None else 1.0
    if name == SWITCH:
        return 0.0
    if name.startswith(ARGUMENT_PREFIX):
        return VACANT
    return None
