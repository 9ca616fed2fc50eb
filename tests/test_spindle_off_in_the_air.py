"""A feed move with the spindle stopped that stays above the top of the stock cuts nothing
(a pen plotter's move above the paper, an approach at feed); below the top it is reported.
Without a stock nothing is taken as in the air: Z0 is the part's top on many set-ups and the
table's on others (a SINUMERIK program of the corpus cuts from Z340 down)."""
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
def test_feed_moves_above_the_stock_top_are_no_finding_and_without_a_stock_they_are(z1, z2, stock):
    assert _verdicts(z1, z2, stock) == (set() if stock else {Status.VIOLATED})


@pytest.mark.parametrize("z1, z2", [(1.0, -0.5), (-2.0, 3.0), (0.0, 0.0)])
def test_a_feed_move_that_reaches_the_top_is_reported(z1, z2):
    assert Status.VIOLATED in _verdicts(z1, z2, stock=True)
    assert Status.VIOLATED in _verdicts(z1, z2, stock=False)
