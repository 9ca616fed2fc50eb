"""A feed move with the spindle stopped that stays above the top of the stock cuts nothing
(a pen plotter's move above the paper, an approach at feed); below the top it is reported.
Without a stock Z0 is the part's top on many set-ups and the table's on others (a SINUMERIK
program of the corpus cuts from Z340 down): a move that reaches Z0 touches the part or the
table either way and is reported; one that stays above Z0 is reported where the program cuts
across the plane with the spindle running at that height or higher, and is ``unknown``
otherwise."""
from __future__ import annotations

import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_text
from ncverify.diagnostics import Status

_PROGRAM = "{stock}G90 G0 X0 Y0 Z10.\nG1 X5. Y5. Z{z1:g} F100.\nG1 X10. Z{z2:g}\nM3 S1000\nG1 Z-1.\nM30\n"


def _verdicts(z1: float, z2: float, stock: bool) -> set:
    text = _PROGRAM.format(stock="(ncverify: stock box X-50:50 Y-50:50 Z-10:0)\n" if stock else "", z1=z1, z2=z2)
    result = check_text(text, "air.nc", Settings())
    return {d.status for d in result.diagnostics if d.rule == "core.spindle-off-cutting"}


@hypothesis_settings(max_examples=25, deadline=None)
@given(z1=st.integers(1, 50), z2=st.integers(1, 50), stock=st.booleans())
def test_feed_moves_above_the_stock_top_are_no_finding_and_without_a_stock_unknown(z1, z2, stock):
    assert _verdicts(z1, z2, stock) == (set() if stock else {Status.UNKNOWN})


@pytest.mark.parametrize("z1, z2", [(1.0, -0.5), (-2.0, 3.0), (0.0, 0.0)])
def test_a_feed_move_that_reaches_the_top_is_reported(z1, z2):
    assert Status.VIOLATED in _verdicts(z1, z2, stock=True)
    assert Status.VIOLATED in _verdicts(z1, z2, stock=False)


@pytest.mark.parametrize("stock", [True, False])
def test_a_cut_after_a_move_in_the_air_in_the_same_stretch_is_still_reported(stock):
    """The first spindle-off move above the work does not hide a later one into it."""
    header = "(ncverify: stock box X-50:50 Y-50:50 Z-10:0)\n" if stock else ""
    text = header + "G90 G0 X0 Y0 Z10.\nG1 X5. Z2. F100.\nG1 Z-1.\nG0 Z10.\nM3 S1000\nG1 Z-1.\nM30\n"
    found = {(d.span.line - bool(stock), d.status) for d in check_text(text, "air.nc", Settings()).diagnostics
             if d.rule == "core.spindle-off-cutting"}
    assert found == {(3, Status.VIOLATED)}


def test_a_pen_plotter_above_z0_without_a_stock_is_unknown_never_an_error():
    """The plotter drives at Z1 above the paper before its 'spindle' starts (no stock given)."""
    text = "G20 G90 G54\nT1 M06\nG00 X0. Y0.\nG43 H01 Z1.0\nG01 X0.25 Y-2.75 F12.0\nM03 S1000\nZ0.0\nX0.25 Y-1.75\nG00 Z1.\nM30\n"
    found = [d for d in check_text(text, "pen.nc", Settings()).diagnostics if d.rule == "core.spindle-off-cutting"]
    assert [(d.span.line, d.status) for d in found] == [(5, Status.UNKNOWN)]
    assert "stock" in found[0].reason


@pytest.mark.parametrize("moves", ["G1 X20. F100.\nG1 X30.\n", "G1 X20. F100.\nG1 X30.\nG1 X40.\nG1 X50.\nG1 X60.\nG1 X70.\n" * 3])
def test_a_lathe_without_a_stock_takes_nothing_as_in_the_air(moves):
    """On a lathe Z runs along the part: its sign says nothing of where the material is."""
    text = "G18 G21 G99\nG50 S2000\nT0101\nG0 X40. Z5.\n" + moves + "M3 S500\nG1 X10. F0.2\nM30\n"
    found = {d.status for d in check_text(text, "lathe.nc", Settings()).diagnostics if d.rule == "core.spindle-off-cutting"}
    assert found == {Status.VIOLATED}


@pytest.mark.parametrize("off_z, cut_z, expected", [
    (338.0, 338.0, Status.VIOLATED),  # a table-zero set-up: the program cuts at Z338 with the spindle on
    (338.0, 340.0, Status.VIOLATED),
    (5.0, 0.0, Status.UNKNOWN),       # above everything the program cuts: no stock to say more
    (2.5, 2.0, Status.UNKNOWN),
])
def test_without_a_stock_the_program_s_own_cutting_height_decides(off_z, cut_z, expected):
    """A spindle-off move above Z0 is a cut where the program feeds across the plane with the
    spindle running at that height or higher; a plunge alone does not count as cutting height."""
    text = (f"G90 G0 X0 Y0 Z400.\nM3 S1000\nG1 Z{cut_z + 5:g} F100.\nG1 Z{cut_z:g}\nG1 X50.\nG0 Z400.\nM5\n"
            f"G0 X0 Y0\nG1 Z{off_z:g} F100.\nG1 X50.\nG0 Z400.\nM30\n")
    found = [(d.span.line, d.status) for d in check_text(text, "table.nc", Settings()).diagnostics if d.rule == "core.spindle-off-cutting"]
    assert found == [(9, expected)]


@pytest.mark.parametrize("per_block_only", [False, True])
def test_a_plunge_that_writes_the_same_x_again_is_no_cutting_height(per_block_only):
    """``G1 X10. Z20.`` at X10 is a plunge: X is written again, not moved (it was once told
    apart by identity, so a new float of the same value counted as a cut across)."""
    text = "G21 G90 G17\nG0 X10. Y10. Z50.\nS1000 M3\nG1 X10. Z20. F100\nM5\nG1 X30. Z25.\nM30\n"
    found = [(d.span.line, d.status) for d in check_text(text, "plunge.nc", Settings(dialect="iso", per_block_only=per_block_only)).diagnostics
             if d.rule == "core.spindle-off-cutting"]
    assert found == [(6, Status.UNKNOWN)]


def _spindle_off_findings(text: str) -> set:
    return {(d.span.line, d.status) for d in check_text(text, "start.nc", Settings()).diagnostics
            if d.rule == "core.spindle-off-cutting"}


@pytest.mark.parametrize("stock, expected", [("", {Status.UNKNOWN}),
                                               ("(ncverify: stock box X-50:50 Y-50:50 Z-10:0)\n", set())])
def test_a_feed_move_before_any_z_is_never_an_error(stock, expected):
    """No Z yet: without a stock the tool is where the operator left it, in the air or in
    the part (unknown); with one it starts parked above it. The first Z move comes down from
    there to Z2, above the part."""
    text = stock + "G90 G0 X0 Y0\nG1 X30. Y0 F1000.\nZ2.\nM3 S1000\nG1 Z-1. F100.\nX0.\nG0 Z50.\nM30\n"
    assert {status for _, status in _spindle_off_findings(text)} == expected


@pytest.mark.parametrize("depth", [-1.0, 0.0])
def test_a_first_z_move_into_the_part_with_the_spindle_stopped_is_still_reported(depth):
    text = f"G90 G0 X0 Y0\nG1 X30. Y0 F1000.\nG1 Z{depth:g} F100.\nM3 S1000\nX0.\nG0 Z50.\nM30\n"
    assert (3, Status.VIOLATED) in _spindle_off_findings(text)
