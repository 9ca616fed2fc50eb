"""``Rule.segment_kinds``: the checker hands a rule's ``segment`` handler only the kinds of
move it declares. A declaration may only spare a handler the moves it would pass over at
once, so every finding is the same as with every rule handed every move."""
from __future__ import annotations

import pytest

from ncverify.check import SEGMENT_KINDS, rule_classes

from conftest import check_program

MILL = """
    (ncverify: stock box X0:100 Y0:100 Z-20:0)
    (ncverify: tool 1 radius 5 length 60 cutting-length 4)
    G21 G90 G17 G54
    T1 M6
    G0 X-20 Y-20 Z10
    G1 Z-5 F0
    G1 X-10 F100
    G2 X10 Y10 R1
    S2000 M3
    G43 H1 G0 Z10
    G1 X20 Y20 Z-2 F99999
    G1 X30 Z-12 F0.2
    G3 X40 Y20 I10 J5
    G41 D1 G1 X50
    G2 X60 Y30 I0 J2
    G40 G1 X70
    G0 X50 Y50 Z-5
    M30
"""

LATHE = """
    (ncverify-test: --machine lathe)
    G18 G21 G95
    T0101
    G96 S200 M3
    G0 X40 Z2
    G1 Z-10 F30
    G2 X20 Z-20 R-12
    G1 X-1 F0.2
    G0 X50 Z5
    M30
"""


def _findings(program: str, **settings) -> list[tuple]:
    return sorted((d.rule, d.span, d.message, d.status.value) for d in check_program(program, **settings).diagnostics)


@pytest.mark.parametrize(("program", "settings"), [(MILL, {}), (LATHE, {"machine": "lathe"})])
def test_narrowed_rules_find_what_they_find_when_handed_every_move(program, settings, monkeypatch):
    narrowed = [cls for cls in rule_classes() if cls.segment_kinds != SEGMENT_KINDS]
    assert len(narrowed) >= 10  # the motion rules on rapids, feeds and arcs declare their kinds
    declared = _findings(program, **settings)
    for cls in narrowed:
        monkeypatch.setattr(cls, "segment_kinds", SEGMENT_KINDS)
    assert _findings(program, **settings) == declared
    narrowed_ids = {rule_id for cls in narrowed for rule_id in cls.ids}
    assert len({finding[0] for finding in declared} & narrowed_ids) >= 3  # the programs do reach those rules


def test_the_declared_kinds_are_kinds_of_segment():
    assert all(cls.segment_kinds and cls.segment_kinds <= SEGMENT_KINDS for cls in rule_classes())
