"""A hazard that happens only for some values of a quantity ncverify does not know (the
rounding of an input, a text comparison, a system value, a probe result: values no
parameter names) is no evidence of a fault: ``unknown``, never ``violated`` with a witness
that sets such a value. Where it happens whatever that quantity is, it stays ``violated``."""
from __future__ import annotations

import textwrap

import pytest

from ncverify import Settings, check_text
from ncverify.diagnostics import Status


def _divisions(program: str, path: str, **settings) -> list:
    result = check_text(textwrap.dedent(program).lstrip("\n"), path, Settings(**settings))
    return [d for d in result.diagnostics if d.rule == "core.arithmetic-domain"]


@pytest.mark.parametrize("program, path", [
    ("PROC GROOVE(REAL ANG)\nR4=90/(1+TRUNC((90-ANG)/7))\nG0 X=R4\nM17\n", "groove.spf"),   # the 038 construct
    ("PROC SPLIT(REAL A)\nR1=10/(TRUNC(A/3)-2)\nG0 X=R1\nM17\n", "split.spf"),
    ("O100\n#2 = 10. / [FIX[#7 / 4.] - 1.]\nG0 X#2\nM30\n", "fix.nc"),
    ("O100\n#2 = 10. / [ROUND[#7] + 3.]\nG0 X#2\nM30\n", "round.nc"),
])
def test_a_divisor_zero_only_for_some_rounding_of_an_input_is_not_violated(program, path):
    findings = _divisions(program, path)
    assert findings and all(d.status is not Status.VIOLATED for d in findings)


def test_a_divisor_zero_whatever_the_unknown_quantity_is_still_violated():
    """#7 * FIX(#8 / 4) with #7 = 0 allowed: zero for every value of the rounding."""
    [finding] = _divisions("(ncverify: assume -5 <= #7 <= 5)\nO100\n#2 = 10. / [#7 * FIX[#8 / 4.]]\nG0 X#2\nM30\n", "zero.nc")
    assert finding.status is Status.VIOLATED and finding.witness["#7"] == 0.0


def test_an_assumed_input_through_a_rounding_stays_unknown_not_proved():
    """With #7 assumed in 0..3, FIX(#7/4) is 0 there and the divisor 1 - 1 = 0 for every
    allowed value; ncverify does not know FIX's values, so it may not prove the opposite."""
    findings = _divisions("(ncverify: assume 0 <= #7 <= 3)\nO100\n#2 = 10. / [FIX[#7 / 4.] + 1. - 1.]\nG0 X#2\nM30\n", "assumed.nc")
    assert findings and all(d.status is not Status.PROVED for d in findings)


@pytest.mark.parametrize("program, path", [
    ("O100\n#1 = 10. / #5221\nG0 X#1\nM30\n", "offset.nc"),                        # a work offset: a system variable
    ("O100\n#1 = 10. / #4001\nG0 X#1\nM30\n", "modal.nc"),                         # a modal state read back
    ("P1 = 10 / V.G.TOOL\nG0 X P1\nM30\n", "tool.pim"),                            # Fagor: the tool in the spindle
    ("R1 = 10 / $AA_IM[X]\nG0 X=R1\nM30\n", "axis.mpf"),                           # SINUMERIK: an axis position
    ("0 BEGIN PGM S MM\n1 FN 18: SYSREAD Q1 = ID20 NR1\n2 Q2 = 10 / Q1\n3 END PGM S MM\n", "sysread.h"),
])
def test_a_division_by_a_system_value_is_never_violated(program, path):
    """System variables and machine data are the machine's: values the program reads, never
    free parameters a witness may set to zero."""
    findings = _divisions(program, path)
    assert findings and all(d.status is not Status.VIOLATED for d in findings)
