"""The classes of false findings on real programs, each shown with programs written here:
inputs are not mistakes, guard exits are the program's own checks, programs stored on the
control, subprograms from the wrong file, M functions within a block, legitimate
spindle-off motion, a parked tool and its length offset, languages ncverify does not claim,
an assumed ISO profile, and the text report people read."""
from __future__ import annotations

import textwrap

import pytest

from ncverify import Settings, check_file, check_text
from ncverify.cli import main
from ncverify.detect import detect
from ncverify.diagnostics import Severity, Status


def check(program: str, path: str = "t.nc", **settings):
    return check_text(textwrap.dedent(program).lstrip("\n"), path, Settings(**settings))


def found(result, rule: str, status: Status | None = Status.VIOLATED) -> list:
    return [d for d in result.diagnostics if d.rule == rule and (status is None or d.status is status)]


# --------------------------------------------------------------------------- inputs


def test_a_division_by_an_unbounded_input_is_unknown_with_the_input_and_its_example():
    result = check("""
        O100
        #2 = 100. / #7
        G0 X#2
        M30
    """)
    [finding] = found(result, "core.arithmetic-domain", None)
    assert finding.status is Status.UNKNOWN and finding.witness == {"#7": 0.0}
    assert "depends on the input #7 = 0" in finding.reason


def test_an_assume_range_that_allows_the_bad_value_makes_it_violated_again():
    result = check("""
        O100
        (ncverify: assume -5 <= #7 <= 5)
        #2 = 100. / #7
        G0 X#2
        M30
    """)
    [finding] = found(result, "core.arithmetic-domain")
    assert finding.witness == {"#7": 0.0}


def test_a_guard_the_program_writes_itself_bounds_the_input_on_the_path_past_it():
    """IF [#7 EQ 0] jumps to an alarm: past the guard #7 cannot be 0, so the division is
    proved safe there, and the alarm itself is only the program checking its argument."""
    result = check("""
        O100
        IF [#7 EQ 0] GOTO 90
        #2 = 100. / #7
        G0 X#2
        M30
        N90 #3000 = 1 (DIVISOR MISSING)
    """)
    assert not found(result, "core.arithmetic-domain", Status.VIOLATED)
    assert not found(result, "core.arithmetic-domain", Status.UNKNOWN)
    [alarm] = found(result, "core.macro-alarm")
    assert alarm.severity is Severity.INFO and "guard" in alarm.message


# --------------------------------------------------------------------------- guard exits


@pytest.mark.parametrize("program, path", [
    ("O200\nIF [#1 LT 0] THEN #3000 = 5 (NEGATIVE)\nG0 X#1\nM30\n", "g.nc"),
    ("IF R1 < 0\n  SETAL(65000)\nENDIF\nG0 X=R1\nM30\n", "g.mpf"),
    ("$IF P1 < 0\n#ERROR [\"NEGATIVE\"]\n$ENDIF\nG0 X[P1]\nM30\n", "g.pim"),
    ("0 BEGIN PGM G MM\n1 FN 12: IF +Q1 LT +0 GOTO LBL 9\n2 L X+Q1 R0 FMAX\n3 M30\n4 LBL 9\n5 FN 14: ERROR = 1000\n6 END PGM G MM\n", "g.h"),
])
def test_an_alarm_reached_only_for_some_inputs_is_an_info_guard(program, path):
    result = check_text(program, path, Settings())
    [alarm] = found(result, "core.macro-alarm")
    assert alarm.severity is Severity.INFO


def test_an_alarm_on_every_path_is_still_a_warning():
    result = check("""
        O300
        #1 = 2
        IF [#1 GT 1] THEN #3000 = 7 (ALWAYS)
        M30
    """)
    [alarm] = found(result, "core.macro-alarm")
    assert alarm.severity is Severity.WARNING


# --------------------------------------------------------------------------- programs not here


@pytest.mark.parametrize("program, path", [
    ("O1\nG65 P9810 Z-5.\nM30\n", "m.nc"),
    ("O1\nM98 P4321\nM30\n", "m.nc"),
    ("0 BEGIN PGM M MM\n1 CALL PGM TNC:\\MAKRO\\REF.H\n2 END PGM M MM\n", "m.h"),
])
def test_a_program_that_is_not_here_is_unknown_not_an_alarm(program, path):
    result = check_text(program, path, Settings())
    [finding] = found(result, "core.program-not-found", None)
    assert finding.status is Status.UNKNOWN and "--subprogram-path" in finding.reason


def test_a_subprogram_in_several_files_is_unknown_naming_them(tmp_path):
    (tmp_path / "a.nc").write_text("O3001\nG0 X1.\nM99\n")
    (tmp_path / "b.nc").write_text("O3001\nG0 X2.\nM99\n")
    (tmp_path / "main.nc").write_text("O1\nM98 P3001\nM30\n")
    [finding] = found(check_file(tmp_path / "main.nc"), "core.program-not-found", None)
    assert finding.status is Status.UNKNOWN and "a.nc" in finding.message and "b.nc" in finding.message


def test_a_folder_named_with_subprogram_path_says_which_file_holds_it(tmp_path):
    library = tmp_path / "subs"
    library.mkdir()
    (library / "O3001.nc").write_text("O3001\nG1 X2.\nM99\n")
    (tmp_path / "other.nc").write_text("O3001\nG0 X5.\nM99\n")
    (tmp_path / "main.nc").write_text("O1\nS1000 M3\nM98 P3001\nM30\n")
    result = check_file(tmp_path / "main.nc", Settings(subprogram_path=(library,)))
    assert not found(result, "core.program-not-found", None)
    assert [d.span.path for d in found(result, "core.feed-missing")] == [str(library / "O3001.nc")]


# --------------------------------------------------------------------------- M functions in a block


def test_m05_in_a_cutting_block_acts_after_the_motion():
    result = check("""
        G21 G90 G54
        S1000 M03
        G0 X0. Y0. Z1.
        G1 Z-1. F100.
        G1 X10. M05
        G0 Z10.
        M30
    """)
    assert not found(result, "core.spindle-off-cutting")


def test_m03_in_a_cutting_block_acts_before_the_motion():
    result = check("""
        G21 G90 G54
        G0 X0. Y0. Z1.
        S1000
        G1 Z-1. F100. M03
        M05
        G1 X10.
        M30
    """)
    assert [d.span.line for d in found(result, "core.spindle-off-cutting")] == [6]


# --------------------------------------------------------------------------- spindle-off motion


def test_a_program_that_never_starts_the_spindle_gets_one_unknown():
    """A measuring routine: G01 moves to touch with the spindle stopped, no M03 anywhere."""
    result = check("""
        O9810
        G90 G0 X0. Y0. Z5.
        G1 Z-2. F200.
        G1 X10. F500.
        G1 X0.
        M30
    """)
    assert not found(result, "core.spindle-off-cutting")
    assert len(found(result, "core.spindle-off-cutting", Status.UNKNOWN)) == 1


# --------------------------------------------------------------------------- length offset with Z parked


def test_g43_without_z_right_after_a_tool_change_is_not_reported():
    result = check("""
        G21 G90 G54
        G53 Z0.
        T2 M06
        G43 H02
        G0 X0. Y0.
        Z5.
        M30
    """)
    assert not found(result, "core.length-offset-without-z")


def test_g49_without_z_over_the_part_is_still_reported():
    result = check("""
        G21 G90 G54
        T2 M06
        G43 H02 Z50.
        G0 X0. Y0. Z2.
        G49
        M30
    """)
    assert [d.span.line for d in found(result, "core.length-offset-without-z")] == [5]


# --------------------------------------------------------------------------- languages not claimed


@pytest.mark.parametrize("text, name", [
    ("N1 O1 (PART)\nN2 L100\nN3 X1. Y2.\nN4 M17\nN5 G0 G90 X0 Y0 E1\nN6 H1 Z10.\nN7 L101\nN8 M2\n", "Fadal"),
    ("%\n// header line\n//O0001\nG70\nG0 X1. Y1.\nM02\n", "MillMaster"),
    ("O1000\nVC1=10\nIF [VC1 GT 5] N100\nCALL OSUB1\nN100 M02\n", "Okuma"),
])
def test_an_iso_lookalike_gives_one_dialect_unsupported_finding(text, name):
    result = check_text(text, "x.nc", Settings())
    assert [d.rule for d in result.diagnostics] == ["core.dialect-unsupported"]
    assert name in result.diagnostics[0].message and result.diagnostics[0].status is Status.UNKNOWN


def test_a_plain_fanuc_program_is_not_taken_for_a_lookalike():
    text = "%\nO1000 (BRACKET)\nG21 G90 G54\nT1 M06\nG43 H1 Z50.\nS1000 M3\nG81 X10. Y10. Z-5. R2. F100.\nG80\nM30\n%\n"
    assert detect(text).dialect == "iso"


def test_the_extension_tips_a_close_call_and_is_named_in_the_evidence():
    text = "G90 G0 X10. Y10.\nG1 Z-2. F100.\nM30\n"
    assert detect(text, suffix=".pim").dialect == "fagor"
    assert detect(text, suffix=".nc").dialect == "iso"
    assert ".pim" in detect(text, suffix=".pim").evidence


def test_verbose_says_why(tmp_path, capsys):
    program = tmp_path / "p.nc"
    program.write_text("G21 G90\nS1000 M3\nG0 X0.\nM30\n")
    main(["check", "--verbose", str(program)])
    err = capsys.readouterr().err
    assert "read as iso" in err and "profile mitsubishi-e60 (assumed" in err


# --------------------------------------------------------------------------- assumed profile


def test_a_code_the_assumed_profile_lacks_is_unknown_not_a_warning():
    result = check("G21 G90 G91.1\nS1000 M3\nG0 X0.\nM30\n")
    [finding] = found(result, "core.unknown-code", None)
    assert finding.status is Status.UNKNOWN and "--profile" in finding.reason


# --------------------------------------------------------------------------- the text report


def test_text_prints_unknown_where_the_severity_stands_and_ends_with_failures(tmp_path, capsys):
    (tmp_path / "a.nc").write_text("O1\nM98 P4321\nM30\n")
    (tmp_path / "b.nc").write_text("G21 G90\nG01 X10. Y5.\nS1000 M03\nM30\n")
    main(["check", str(tmp_path)])
    out = capsys.readouterr().out
    assert ": unknown core.program-not-found:" in out
    tail = out[out.index("file(s) checked"):]
    assert "files with findings (1):" in tail and "b.nc" in tail and "rules that fired most: core.feed-missing (1)" in tail
    assert out.count("not checked for want of context") == 1 and "[machine]" in out


def test_proved_verdicts_are_listed_only_on_request(tmp_path, capsys):
    program = tmp_path / "p.nc"
    program.write_text("(ncverify: assume 1 <= #7 <= 5)\nG21 G90\n#2 = 100. / #7\nS1000 M3\nG0 X#2\nM30\n")
    main(["check", str(program)])
    plain = capsys.readouterr().out
    main(["check", "--show-proved", str(program)])
    shown = capsys.readouterr().out
    assert ": info core.arithmetic-domain" not in plain and "proved" in plain
    assert "core.arithmetic-domain" in shown


def test_a_finding_in_a_called_file_carries_its_call_site(tmp_path, capsys):
    (tmp_path / "O5001.nc").write_text("O5001\nG1 X4.\nM99\n")
    main_program = tmp_path / "main.nc"
    main_program.write_text("O1\nS1000 M3\nG0 X0. Y0.\nM98 P5001\nM30\n")
    [finding] = found(check_file(main_program), "core.feed-missing")
    assert finding.span.path == str(tmp_path / "O5001.nc")
    assert finding.to_json()["related"] == [{"line": 4, "column": 1, "message": "called from here"}]
    main(["check", str(main_program)])
    assert f"(called from {main_program}:4)" in capsys.readouterr().out


# --------------------------------------------------------------------------- annotations


@pytest.mark.parametrize("written, meant", [("face-mill", "facemill"), ("groove", "grooving"), ("thread", "threading"),
                                            ("Ball_Nose", "ball"), ("spot-drill", "spot"), ("cut-off", "parting")])
def test_tool_types_accept_common_spellings(written, meant):
    result = check(f"(ncverify: tool 3 radius 4 type {written})\nG21 G90\nM30\n")
    assert not found(result, "core.bad-annotation", None)
    from ncverify.context import canonical_tool_type
    assert canonical_tool_type(written) == meant


def test_a_grooving_tool_takes_a_width_and_an_unknown_type_or_key_lists_the_accepted_ones():
    assert not found(check("(ncverify: tool 4 radius 0.2 type groove width 3)\nG21 G90\nM30\n"), "core.bad-annotation", None)
    [bad_type] = found(check("(ncverify: tool 4 radius 2 type wobbler)\nG21 G90\nM30\n"), "core.bad-annotation", None)
    assert "accepted:" in bad_type.message and "facemill" in bad_type.message
    [bad_key] = found(check("(ncverify: tool 4 radius 2 flutes 3)\nG21 G90\nM30\n"), "core.bad-annotation", None)
    assert "accepted:" in bad_key.message and "width" in bad_key.message


# --------------------------------------------------------------------------- system constants


def test_pi_is_a_value_and_machine_data_an_input_never_a_violation():
    result = check("R1=$PI\nR2=10/(R1-3)\nR4=10/$AA_IM[X]\nG0 X=R2 Y=R4\nM30\n", "c.mpf")
    assert "$PI" not in result.free_parameters
    divisions = found(result, "core.arithmetic-domain", None)
    assert [d.span.line for d in divisions] == [3] and divisions[0].status is Status.UNKNOWN


# --------------------------------------------------------------------------- profile and machine type


@pytest.mark.parametrize("text, profile, machine", [
    ("N10G50S2000\nN20G96S200M3\nN30T0101\nN40G0X50.Z2.\nN50G1Z-10.F0.2\nM30\n", "fanuc", "lathe"),
    ("N1G21G90G54\nN2T1M6\nN3G43H1Z50.\nN4G187P1\nN5S1000M3\nN6G0X10.Y10.\nM30\n", "haas", "mill"),
    ("N10 G50 S2000\nN20 G96 S200 M3\nN30 T0101\nN40 G0 X50. Z2.\nM30\n", "fanuc", "lathe"),
])
def test_profile_and_machine_type_are_found_in_blocks_written_without_spaces(text, profile, machine):
    found_here = detect(text)
    assert (found_here.profile, found_here.machine) == (profile, machine)


def test_m05_acts_after_the_motion_on_fagor_too():
    result = check("G90 G0 X0 Y0 Z1\nS1000 M3\nG1 Z-1 F100\nG1 X10 M5\nG1 X20\nM30\n", "f.pim")
    assert result.dialect == "fagor"
    assert [d.span.line for d in found(result, "core.spindle-off-cutting")] == [5]
