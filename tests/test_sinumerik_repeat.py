"""SINUMERIK program section repetition (``REPEAT``, ``REPEATB``, ``ENDLABEL``) and the
repeat count ``P`` of a subprogram call. The values a program computes are probed with
``SETAL``, as in ``test_sinumerik.py``."""
from __future__ import annotations

import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

from conftest import findings
from test_sinumerik import check, probes

CLEAR = "R1=0 R2=0 R3=0 R4=0\n"  # the counters start at 0 (an R parameter never set is an input)


@pytest.mark.parametrize(("program", "expected"), [
    # REPEAT A: from A up to the REPEAT block, P more times (R1 counts the runs of the section)
    ("R1=0\nA: R1=R1+1\nR2=R2+10\nREPEAT A P=2\nSETAL(R1*100+R2)\nM30\n", 330),
    # without P: once more
    ("R1=0\nA: R1=R1+1\nREPEAT A\nSETAL(R1)\nM30\n", 2),
    # REPEAT A with an ENDLABEL after A: the section ends there, what follows runs once
    ("A: R1=R1+1\nENDLABEL:\nR2=R2+1\nREPEAT A P=2\nSETAL(R1*10+R2)\nM30\n", 31),
    # REPEAT A B: from A to B (B included), the blocks after B once
    ("A: R1=R1+1\nR3=R3+1\nB: R2=R2+1\nR4=R4+1\nREPEAT A B P=2\nSETAL(R1*1000+R2*100+R3*10+R4)\nM30\n", 3331),
    # REPEATB A: the block A alone
    ("A: R1=R1+1\nR2=R2+1\nREPEATB A P=3\nSETAL(R1*10+R2)\nM30\n", 41),
    # a section after the REPEAT: the label is searched forward when it is not before
    ("REPEAT A B P=2\nGOTOF B\nA: R1=R1+1\nB: R2=R2+1\nSETAL(R1*10+R2)\nM30\n", 23),
    # a REPEATB inside a repeated section ends its own repetition, not the outer one
    ("A: R1=R1+1\nB: R2=R2+1\nREPEATB B P=1\nREPEAT A P=1\nSETAL(R1*10+R2)\nM30\n", 24),
    # P=0: no repetition
    ("A: R1=R1+1\nREPEAT A P=0\nSETAL(R1)\nM30\n", 1),
])
def test_a_repeated_section_runs_as_often_as_p_says(program, expected):
    result = check(CLEAR + program)
    assert probes(result) == [expected]
    assert not findings(result, "core.loop-bound") and not findings(result, "core.label-not-found")


@pytest.mark.parametrize("repeat", ["REPEAT A P=999999999", "REPEATB A P=999999999", "REPEAT A B P=R9*R9"])
def test_a_huge_repeat_count_ends_at_the_loop_bound(repeat):
    result = check(f"R9=1000000\nG0 X0 Y0 Z10\nA: G0 X1\nB: G0 X2\n{repeat}\nSETAL(1)\nM30\n", loop_bound=50)
    assert [d.status.value for d in findings(result, "core.loop-bound")] == ["unknown"]
    assert not findings(result, "core.repeat-count-range")  # no limit of REPEAT's P is stated
    assert probes(result) == []  # the path ended at the bound, nothing after it is claimed


def test_a_repeat_of_a_missing_label_is_an_alarm():
    result = check("G0 X0\nREPEAT NOWHERE P=2\nM30\n")
    assert [d.status.value for d in findings(result, "core.label-not-found")] == ["violated"]


@pytest.mark.parametrize("text", ["REPEAT P=3", "REPEAT A B C", "REPEATB A B", "REPEATB"])
def test_a_repeat_without_its_labels_is_a_syntax_error(text):
    result = check(f"A: G0 X1\nB: G0 X2\nC: G0 X3\n{text}\nM30\n")
    assert findings(result, "core.syntax"), text


SUBPROGRAMS = "%_N_L10_SPF\nR1=R1+1\nM17\n%_N_SUB1_SPF\nR2=R2+1\nM17\n"


@pytest.mark.parametrize(("call", "expected"), [
    ("L10 P3", 30), ("L10", 10), ("SUB1 P=2", 2), ("SUB1 P2", 2), ("L10 P=2\nSUB1 P=4", 24),
])
def test_the_p_of_a_subprogram_call_is_its_repeat_count(call, expected):
    result = check(f"%_N_MAIN_MPF\nR1=0\nR2=0\n{call}\nSETAL(R1*10+R2)\nM30\n{SUBPROGRAMS}")
    assert probes(result) == [expected]


def test_a_call_repeated_past_9999_is_the_controls_alarm_and_ends_at_the_loop_bound():
    result = check(f"%_N_MAIN_MPF\nL10 P999999999\nSETAL(1)\nM30\n{SUBPROGRAMS}", loop_bound=50)
    assert [d.status.value for d in findings(result, "core.repeat-count-range")] == ["violated"]
    assert [d.status.value for d in findings(result, "core.loop-bound")] == ["unknown"]


@hypothesis_settings(max_examples=25, deadline=None, derandomize=True)
@given(st.integers(0, 6), st.integers(0, 6), st.sampled_from(["REPEAT A P={n}", "REPEAT A B P={n}", "REPEATB A P={n}"]))
def test_the_section_runs_once_plus_p_times(before, n, form):
    """Every form, any count: the labelled block A runs n + 1 times in all."""
    result = check(f"{CLEAR}R1={before}\nA: R1=R1+1\nB: R2=R2+1\n{form.format(n=n)}\nSETAL(R1)\nM30\n")
    assert probes(result) == [before + n + 1]
