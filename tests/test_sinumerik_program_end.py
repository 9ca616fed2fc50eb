"""Where a SINUMERIK program's text ends without its end code.

A file stored as ``NAME.SPF`` is a subprogram (it is called, never run as a main program).
The cycles manual ends subprograms with M17 or RET and main programs with M2/M30, and lists
no alarm and no implicit return for a subprogram whose text ends without one: that end is
``unknown``. A main program that runs off its text stays a warning.
"""
from __future__ import annotations

import pytest

from ncverify import Settings, check_file
from ncverify.diagnostics import Status

CONTOUR = "G1 G90 X10 Y0 F300\nY20\nX0\nY0\n"


def _program_end(tmp_path, name: str, text: str) -> list:
    program = tmp_path / name
    program.write_text(text, encoding="utf-8")
    return [d for d in check_file(program, Settings()).diagnostics if d.rule == "core.program-end-missing"]


@pytest.mark.parametrize("name", ["CONTOUR.SPF", "contour.spf", "L100.Spf"])
def test_a_subprogram_file_without_m17_ends_unknown_not_violated(tmp_path, name):
    found = _program_end(tmp_path, name, CONTOUR)
    assert [d.status for d in found] == [Status.UNKNOWN]
    assert "M17/RET" in found[0].message and "M02/M30" not in found[0].message


@pytest.mark.parametrize("end", ["M17", "RET", "m17"])
def test_a_subprogram_file_with_its_end_gives_nothing(tmp_path, end):
    assert _program_end(tmp_path, "CONTOUR.SPF", CONTOUR + end + "\n") == []


@pytest.mark.parametrize("name", ["CONTOUR.MPF", "contour.mpf"])
def test_the_same_text_as_a_main_program_is_still_a_warning(tmp_path, name):
    text = "%_N_CONTOUR_MPF\nT1 D1 M6\nS1000 M3\nG0 X0 Y0 Z2\nG1 Z-1 F100\n" + CONTOUR
    assert [d.status for d in _program_end(tmp_path, name, text)] == [Status.VIOLATED]


def test_a_called_subprogram_without_m17_returns_and_the_caller_is_checked_on(tmp_path):
    """The subprogram that runs into the next program's header is unknown at that header,
    and what the main program does after the call is still checked."""
    text = ("%_N_MAIN_MPF\nT1 D1 M6\nS1000 M3\nG0 X0 Y0 Z2\nSIDE\nM5\nG1 Z-3 F100\nG0 Z50\nM30\n"
            "%_N_SIDE_SPF\nG1 Z-1 F200\nX20\n%_N_OTHER_SPF\nG1 X5\nM17\n")
    program = tmp_path / "MAIN.MPF"
    program.write_text(text, encoding="utf-8")
    diagnostics = check_file(program, Settings()).diagnostics
    ends = [(d.span.line, d.status) for d in diagnostics if d.rule == "core.program-end-missing"]
    assert ends == [(13, Status.UNKNOWN)]
    assert (7, Status.VIOLATED) in {(d.span.line, d.status) for d in diagnostics if d.rule == "core.spindle-off-cutting"}
