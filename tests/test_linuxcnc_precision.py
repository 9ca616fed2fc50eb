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
    text = "G21 G90 G0 X0 Y0 Z5\n" + "G168 X0 Y0 Z0\nG0 X1\n" * 4 + "G169\nM2\n"
    program = tmp_path / "program.ngc"
    program.write_text(text, encoding="utf-8")
    found = [d for d in check_file(program, Settings()).diagnostics if d.rule == "linuxcnc.unknown-code" and d.status is Status.VIOLATED]
    assert [d.span.line for d in found] == [2, 10]
    assert "the same code in 3 more blocks: lines 4, 6, 8" in found[0].message


@pytest.mark.parametrize("end", ["M2", "M30", "m2", "M02"])
@pytest.mark.parametrize("left_on, rule", [
    ("G81 X10 Y10 Z-2 R1\nX20\n", "core.cycle-modal-at-end"),
    ("G41 D1\nG1 X10 Y5\nX20\n", "core.comp-active-at-end"),
])
def test_m2_and_m30_put_back_the_motion_mode_and_cutter_compensation(tmp_path, end, left_on, rule):
    """LinuxCNC's program end sets the motion mode to G1 (no cycle) and turns compensation off:
    the next program does not inherit them. On the ISO family the end keeps them."""
    text = f"G21 G90 G17 G0 X0 Y0 Z5\nS1000 M3\nF100\n{left_on}{end}\n"
    assert rule not in _violated(tmp_path, text)
    iso = tmp_path / "O1.nc"
    iso.write_text(f"O1\nT1 M6\nG43 H1 Z50\n{text}", encoding="utf-8")
    assert rule in {d.rule for d in check_file(iso, Settings(dialect="iso")).diagnostics if d.status is Status.VIOLATED}


@pytest.mark.parametrize("remaps, expected", [
    (None, {("G68.2", "unknown"), ("G69", "unknown"), ("G168", "violated")}),  # not declared: a remappable code may exist
    ('["G68.2", "g69"]', {("G68.2", "unknown"), ("G69", "unknown"), ("G168", "violated")}),
    ('["G69"]', {("G68.2", "violated"), ("G69", "unknown"), ("G168", "violated")}),
    ("[]", {("G68.2", "violated"), ("G69", "violated"), ("G168", "violated")}),
])
def test_a_code_a_configuration_can_remap_depends_on_the_declared_remaps(tmp_path, remaps, expected):
    """LinuxCNC lets a configuration add free G codes of G0-G99.9 (one decimal at most) by
    REMAP: such a code is unknown until ``[machine] remaps`` says which the machine has; a
    code outside that range, or missing from the declared remaps, makes LinuxCNC refuse it."""
    if remaps is not None:
        (tmp_path / "ncverify.toml").write_text(f"[machine]\nremaps = {remaps}\n", encoding="utf-8")
    program = tmp_path / "program.ngc"
    program.write_text("G21 G90 G0 X0 Y0 Z5\nG68.2 X0 Y0 Z0 I0 J0 K0\nG0 X1\nG69\nG168 X1\nM2\n", encoding="utf-8")
    found = {(d.message.split(" ", 1)[0], d.status.value) for d in check_file(program, Settings()).diagnostics
             if d.rule == "linuxcnc.unknown-code"}
    assert found == expected


def test_remaps_that_are_not_a_list_of_codes_are_refused(tmp_path):
    (tmp_path / "ncverify.toml").write_text('[machine]\nremaps = "G68.2"\n', encoding="utf-8")
    program = tmp_path / "program.ngc"
    program.write_text("G0 X0\nM2\n", encoding="utf-8")
    with pytest.raises(Exception, match="remaps"):
        check_file(program, Settings())


_TOOL_CHANGE_THEN_CUT = "G20 G90 G17\nT4 M6\nS1000 M3\nG0 X0 Y0 Z1\nG1 Z-0.1 F10\nG1 X2\nG0 Z1\nM2\n"


@pytest.mark.parametrize("table, expected", [
    (None, {Status.UNKNOWN}),                        # lengths or touch-off in the work offset: the set-up decides
    ("T4 P4 D1.0 Z0.5 ;half-inch tool\n", {Status.VIOLATED}),
    ("T4 P4 D1.0 Z0 ;touched off in G54\n", set()),
    ("T4 P4 D1.0 ;no length\n", {Status.UNKNOWN}),
])
def test_a_missing_length_offset_matters_where_the_tool_table_holds_a_length(tmp_path, table, expected):
    """LinuxCNC's M6 applies no length offset: cutting without G43 ignores the length the tool
    table holds for the tool, and nothing is ignored where it holds none (tools touched off in
    the work offset)."""
    if table is not None:
        (tmp_path / "tool.tbl").write_text(table, encoding="utf-8")
    program = tmp_path / "program.ngc"
    program.write_text(_TOOL_CHANGE_THEN_CUT, encoding="utf-8")
    found = {d.status for d in check_file(program, Settings()).diagnostics if d.rule == "core.no-length-offset"}
    assert found == expected


def test_with_g43_nothing_is_reported_and_on_the_iso_family_it_stays_a_warning(tmp_path):
    program = tmp_path / "program.ngc"
    program.write_text(_TOOL_CHANGE_THEN_CUT.replace("T4 M6\n", "T4 M6\nG43\n"), encoding="utf-8")
    assert not [d for d in check_file(program, Settings()).diagnostics if d.rule == "core.no-length-offset"]
    iso = tmp_path / "O4.nc"
    iso.write_text("O4\n" + _TOOL_CHANGE_THEN_CUT.replace("M2", "M30"), encoding="utf-8")
    assert {d.status for d in check_file(iso, Settings(dialect="iso")).diagnostics if d.rule == "core.no-length-offset"} == {Status.VIOLATED}
