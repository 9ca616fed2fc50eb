"""What a proof reads: every rule that can answer ``proved`` declares the kinds of machine
state it accounts for (``Rule.reads``, ``ncverify/modelled.py``), and under any
other kind that is active its ``proved`` becomes ``unknown`` with the state named.

The tests enumerate the kinds: each is made active alone on a real machine state, and
every rule's proof is offered under it. A rule that would prove under a kind it does not
read fails, and so does a rule that judges hazards without saying what it reads.
"""
from __future__ import annotations

import functools
import inspect
import textwrap

import pytest

from ncverify import Settings, check_text, frames
from ncverify.check import Checker, Rule, rule_classes
from ncverify import modelled
from ncverify.context import RuleContext
from ncverify.diagnostics import Status
from ncverify.interpret.interpreter import MachineState
from ncverify.source import Span
from ncverify.verdict import Verdict


def _state(**modal) -> MachineState:
    return MachineState(modal={"plane": "xy", **modal})


def _framed(frame) -> MachineState:
    state = _state()
    state.frame = frame
    return state


STATES = {
    modelled.TRANSLATION: lambda: _framed(frames.translation({"X": 5.0, "Z": -2.0})),
    modelled.ROTATION: lambda: _framed(frames.rotation(("X", "Y", "Z"), 180.0)),
    modelled.SCALING: lambda: _framed(frames.scaling({"X": 2.0, "Y": 2.0})),
    modelled.MIRROR: lambda: _framed(frames.mirror(["X"])),
    modelled.UNMODELLED_FRAME: lambda: _framed(frames.UNKNOWN),
    modelled.TOOL_AXIS: lambda: _state(plane="zx"),
    modelled.KINEMATICS: lambda: _state(transformation="TRACYL (cylinder surface)"),
    modelled.DIAMETER: lambda: _state(diameter="diameter"),
    modelled.RADIUS_COMPENSATION: lambda: _compensated("right"),
    modelled.TOOL_LENGTH: lambda: _with(length_mode="minus"),
    modelled.TOOL_RADIUS: lambda: _with(comp_side="left", comp_register=2.0, tool_in_spindle=1.0),
    modelled.UNFOLLOWED: lambda: _with(unfollowed="G10 L2 wrote a work offset"),
}


def _with(**fields) -> MachineState:
    state = _state()
    for name, value in fields.items():
        setattr(state, name, value)
    return state


def _compensated(side: str) -> MachineState:
    return _with(comp_side=side)


def test_every_kind_of_state_is_enumerated_and_recognised_alone():
    assert set(STATES) == set(modelled.KINDS)
    assert modelled.active(_state(), RuleContext()) == {}
    for kind, make in STATES.items():
        assert set(modelled.active(make(), RuleContext())) == _ACTIVE.get(kind, {kind}), kind


# where a frame is not known, neither is the direction the tool stands in
_ACTIVE = {modelled.UNMODELLED_FRAME: {modelled.UNMODELLED_FRAME, modelled.TOOL_AXIS},
           modelled.TOOL_RADIUS: {modelled.TOOL_RADIUS, modelled.RADIUS_COMPENSATION}}  # a radius offset is in force only under compensation


def _offered(checker: Checker, rule_id: str, state) -> Status:
    """The status a proof of ``rule_id`` is reported with under ``state``."""
    checker.diagnostics.clear()
    checker._seen.clear()
    checker.report_verdict(rule_id, Span(1, 1, 1, 2), f"{rule_id} under test", Verdict(Status.PROVED), state)
    [diagnostic] = checker.diagnostics
    return diagnostic.status


@functools.cache
def _proving_rule_ids() -> list[str]:
    return sorted({rule_id for cls in rule_classes() for rule_id in cls.ids if _judges(cls)} | {"core.arithmetic-domain"})


def _judges(cls) -> bool:
    return any("report_verdict" in inspect.getsource(klass) for klass in cls.__mro__ if klass not in (Rule, object))


@pytest.mark.parametrize("kind", modelled.KINDS)
def test_no_rule_proves_under_a_kind_of_state_it_does_not_read(kind):
    checker = Checker(Settings(max_findings_per_rule=10**6), RuleContext())
    for rule_id in _proving_rule_ids():
        status = _offered(checker, rule_id, STATES[kind]())
        reads = checker._reads.get(rule_id, frozenset())
        assert status is (Status.PROVED if _ACTIVE.get(kind, {kind}) <= reads else Status.UNKNOWN), (rule_id, kind)
        assert _offered(checker, rule_id, _state()) is Status.PROVED, rule_id  # the plain state takes every proof


def test_every_rule_that_judges_a_hazard_declares_what_it_reads():
    undeclared = [cls.__name__ for cls in rule_classes() if _judges(cls)
                  and not any("reads" in vars(klass) for klass in cls.__mro__ if klass not in (Rule, object))]
    assert undeclared == []


# --------------------------------------------------------------------------- a kinematic transformation

CYLINDER = """
    ; ncverify: stock box X0:100 Y0:100 Z-20:0
    ; ncverify: tool 1 radius 5 length 60
    ; ncverify: assume 10 <= R1 <= 20
    G17 G90 G54
    T1 D1 M6
    G0 X-50 Y50 Z50
    {on}
    G0 X=-R1-20 Y50 Z=-5
    {off}
    G0 X=-R1-20 Y50 Z=-5
"""


def test_a_rapid_under_tracyl_is_not_proved_and_is_again_after_trafoof():
    result = check_text(textwrap.dedent(CYLINDER.format(on="TRACYL(40)", off="TRAFOOF")).lstrip(), "part.mpf", Settings(dialect="sinumerik"))
    under = [d for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == 8]
    after = [d for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == 10]
    assert [d.status for d in under] == [Status.UNKNOWN] and "TRACYL" in under[0].reason
    assert [d.status for d in after] == [Status.PROVED]
