"""LinuxCNC forms that are not mistakes: the D word of dynamic cutter compensation is a
diameter, a code not modelled keeps its own words, and a subroutine file or a program
closed by '%' needs no M2."""
from __future__ import annotations

import pytest

from ncverify import Settings, check_file
from ncverify.diagnostics import Status


def _violated(tmp_path, text: str) -> set[str]:
    program = tmp_path / "program.ngc"
    program.write_text(text, encoding="utf-8")
    return {d.rule for d in check_file(program, Settings()).diagnostics if d.status is Status.VIOLATED}


@pytest.mark.parametrize("comp", ["G41.1 D0.25", "G42.1 D.5 L2", "g41.1d0.4", "G42.1 D[0.3*2]"])
def test_the_d_word_of_dynamic_compensation_is_a_diameter_not_a_register(tmp_path, comp):
    text = f"G21 G90 G0 X0 Y0 Z5\nS1000 M3\nG1 Z-1 F100\n{comp}\nG1 X10\nG40 G1 X20\nG0 Z5\nM2\n"
    assert "core.d-register-range" not in _violated(tmp_path, text)


def test_a_register_d_of_plain_compensation_is_still_checked(tmp_path):
    text = "G21 G90 G0 X0 Y0 Z5\nS1000 M3\nG1 Z-1 F100\nG41 D0.25\nG1 X10\nG40 G1 X20\nG0 Z5\nM2\n"
    assert "core.d-register-range" in _violated(tmp_path, text)


def test_the_words_of_a_code_not_modelled_are_its_own(tmp_path):
    """G70 D0.5: the finishing cycle's D, not a compensation register."""
    text = "G18 G21 G90 G0 X20 Z5\nS500 M3\nG70 Q100 X15 Z3 D0.5 P2\nM2\nO100 sub\nG1 X10 Z0\nO100 endsub\n"
    assert "core.d-register-range" not in _violated(tmp_path, text)


@pytest.mark.parametrize("text", [
    "o<drill> sub\nG0 X#1 Y#2\nG1 Z#3 F#4\nG0 Z1\no<drill> endsub\n",
    "(a library of one)\n; its name\nO<probe-x> SUB\nG38.2 X#1 F50\nO<probe-x> ENDSUB\n",
    "%\nG21 G90 G0 X0 Y0 Z5\nS1000 M3\nG1 Z-1 F100\nG0 Z5\nM5\n%\n",
])
def test_a_subroutine_file_or_a_program_closed_by_percent_needs_no_m2(tmp_path, text):
    assert "core.program-end-missing" not in _violated(tmp_path, text)


def test_a_program_that_runs_off_its_text_is_still_reported(tmp_path):
    text = "G21 G90 G0 X0 Y0 Z5\nS1000 M3\nG1 Z-1 F100\nG0 Z5\n"
    assert "core.program-end-missing" in _violated(tmp_path, text)


def test_a_thread_follows_the_spindle_and_needs_no_feed_word(tmp_path):
    text = "G18 G20 G90 G0 X.2 Z0\nS500 M3\nG33 Z-.5 K.05\nG0 X.3\nM2\n"
    assert "core.feed-missing" not in _violated(tmp_path, text)
    assert "core.feed-missing" in _violated(tmp_path, text.replace("G33 Z-.5 K.05", "G1 Z-.5"))


def test_a_code_the_control_lacks_is_one_finding_however_often_it_is_written(tmp_path):
    """One cause, one finding: the first block with the code, naming the lines of the others."""
    text = "G21 G90 G0 X0 Y0 Z5\n" + "G68.2 X0 Y0 Z0 I0 J0 K0\nG0 X1\n" * 4 + "G69.5\nM2\n"
    program = tmp_path / "program.ngc"
    program.write_text(text, encoding="utf-8")
    found = [d for d in check_file(program, Settings()).diagnostics if d.rule == "linuxcnc.unknown-code" and d.status is Status.VIOLATED]
    assert [d.span.line for d in found] == [2, 10]
    assert "the same code in 3 more blocks: lines 4, 6, 8" in found[0].message
