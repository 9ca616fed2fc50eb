"""The moves a hole cycle makes, as the rules receive them: each segment with the state the
checker sees when it arrives (position, parked axes, axes that leave the start position);
and the levels of its holes against the stock, plain numbers and free parameters."""
from __future__ import annotations

from unittest import mock

from ncverify import Settings, check_text
from ncverify.check import Checker
from ncverify.diagnostics import Status


def _cycle_segments(program: str, path: str = "t.nc") -> list[tuple]:
    """(kind, role, start, end, parked axes, axes leaving the start, end is the position) of
    every cycle segment the checker is handed."""
    seen = []
    original = Checker.segment

    def recording(checker, segment, state):
        if segment.cycle is not None:
            seen.append((segment.kind, segment.role, segment.start, segment.end, sorted(state.parked), sorted(state.left_start),
                         segment.end is state.position))
        return original(checker, segment, state)

    with mock.patch.object(Checker, "segment", recording):
        check_text(program, path, Settings())
    return seen


def _xyz(x, y, z) -> dict:
    return {"X": x, "Y": y, "Z": z}


def test_a_cycle_from_a_reference_return_leaves_the_parked_axis_where_it_first_moves_it():
    program = "\n".join(["G21 G90 G17 G54", "T1 M6", "G43 H1", "S1000 M3", "G0 X0 Y0 Z20.", "G28 Z30.",
                         "G98 G81 X10. Y10. Z-5. R2. F100.", "G80", "G28 X0", "G99 G83 Y5. Z-8. R3. Q2.", "X7. Y7.", "G80", "M30"]) + "\n"
    assert _cycle_segments(program) == [
        ("rapid", "between-holes", _xyz(0.0, 0.0, None), _xyz(10.0, 10.0, None), ["Z"], [], True),  # Z stays parked: X and Y move
        ("rapid", "approach", _xyz(10.0, 10.0, None), _xyz(10.0, 10.0, 2.0), [], ["Z"], True),  # Z leaves the start position
        ("feed", "infeed", _xyz(10.0, 10.0, 2.0), _xyz(10.0, 10.0, -5.0), [], [], True),
        ("rapid", "out-of-hole", _xyz(10.0, 10.0, -5.0), _xyz(10.0, 10.0, 2.0), [], [], True),  # G98 from an unknown level: R is as high
        ("rapid", "between-holes", _xyz(None, 10.0, 2.0), _xyz(None, 5.0, 2.0), ["X"], [], True),
        ("rapid", "approach", _xyz(None, 5.0, 2.0), _xyz(None, 5.0, 3.0), ["X"], [], True),
        ("feed", "infeed", _xyz(None, 5.0, 3.0), _xyz(None, 5.0, -8.0), ["X"], [], True),
        ("rapid", "out-of-hole", _xyz(None, 5.0, -8.0), _xyz(None, 5.0, 3.0), ["X"], [], True),
        ("rapid", "between-holes", _xyz(None, 5.0, 3.0), _xyz(7.0, 7.0, 3.0), [], ["X"], True),  # X leaves the start position
        ("feed", "infeed", _xyz(7.0, 7.0, 3.0), _xyz(7.0, 7.0, -8.0), [], [], True),
        ("rapid", "out-of-hole", _xyz(7.0, 7.0, -8.0), _xyz(7.0, 7.0, 3.0), [], [], True),
    ]


def test_hole_levels_in_the_stock_are_judged_as_numbers_and_as_free_parameters():
    program = "\n".join(["(ncverify: stock box X0:50 Y0:50 Z-20:0)", "G21 G90 G17 G54", "T1 M6", "G43 H1", "S1000 M3", "G0 X10. Y10. Z20.",
                         "G98 G81 X10. Y10. Z-5. R#500 F100.", "X20.", "G80",  # R from a free parameter: it may lie in the stock
                         "G98 G81 X30. Y30. Z-5. R2. F100.", "G80",  # above the stock: nothing to say
                         "#501 = 5.", "G98 G81 X30. Y30. Z-5. R[#501 - 8] F100.", "G80", "M30"]) + "\n"
    found = [(d.span.line, d.status, d.message, d.witness) for d in check_text(program, "t.nc", Settings()).diagnostics
             if d.rule == "core.clearance-below-stock"]
    assert [(line, status, message) for line, status, message, _witness in found] == [
        (7, Status.UNKNOWN, "G81: the R point Z#500 is below the top of the stock Z0: the cycle rapids into the material there"),
        (13, Status.VIOLATED, "G81: the R point Z-3 is below the top of the stock Z0: the cycle rapids into the material there"),
    ]
    assert found[0][3]["#500"] < 0.0 and found[1][3] == {}
