"""SINUMERIK: when M functions act within their block. The 840D sets the output timing by
machine data and the reference does not give it, so the code table says it
(``dialects/sinumerik/codes.toml``, ``output``), as the ISO family and Fagor do: M3, M4, M7
and M8 before the block's motion, M5, M9 and M19 after it."""
from __future__ import annotations

import pytest

from ncverify import Settings, check_file
from ncverify.diagnostics import Status

_HEAD = "; ncverify: stock box X0:100 Y0:50 Z-20:0\nT1 D1\nM6\nG90 G0 X-10 Y10 Z5 S1000 {first}\nG1 Z-2 F100\n"


def _spindle_off_lines(tmp_path, body: str, first: str = "M3") -> set[int]:
    program = tmp_path / "order.mpf"
    program.write_text(_HEAD.format(first=first) + body + "G0 Z5\nM30\n", encoding="utf-8")
    result = check_file(program, Settings())
    return {d.span.line for d in result.diagnostics if d.rule == "core.spindle-off-cutting" and d.status is Status.VIOLATED}


@pytest.mark.parametrize("stop", ["M5", "M5 M9", "M9 M5"])
def test_a_stop_in_a_cutting_block_acts_after_its_motion(tmp_path, stop):
    """G1 X10 M5: the move is cut with the spindle on; the next cut is not."""
    assert _spindle_off_lines(tmp_path, f"G1 X10 {stop}\n") == set()
    assert _spindle_off_lines(tmp_path, f"G1 X10 {stop}\nG1 X20\n") == {7}


@pytest.mark.parametrize("start", ["M3", "M4", "M3 M8"])
def test_a_start_in_a_cutting_block_acts_before_its_motion(tmp_path, start):
    """G1 Z-1 M3 after a stop: the spindle runs before the tool moves."""
    assert _spindle_off_lines(tmp_path, f"G1 X10 {start}\n", first="M5") == {5}
