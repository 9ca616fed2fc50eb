"""The abstract machine, seen through ``check_text``: each test is a program and the finding
it must (or must not) produce.

Where a test needs to know where the tool is, the program asks the control itself: the
last line ``#3000=#5001`` raises a macro alarm whose number is the X position (``#5002``
Y, ``#5003`` Z), and the test reads that number from the finding's message.
"""
from __future__ import annotations

import re
import textwrap
import time

import pytest

from ncverify import Settings, check_file
from ncverify.diagnostics import Status


from conftest import check_program as check, findings


def rules(result) -> list[str]:
    return [d.rule for d in result.diagnostics]


def alarm_values(result) -> list[float]:
    """The numbers of the macro alarms raised, one per path that reached ``#3000=``."""
    values = []
    for diagnostic in findings(result, "core.macro-alarm"):
        match = re.search(r"#3000=(-?[0-9.e+]+|\?)", diagnostic.message)
        assert match, diagnostic.message
        values.append(float(match.group(1)))
    return values


def probed(result) -> float:
    [value] = alarm_values(result)
    return value


# --------------------------------------------------------------------------- modal motion


def test_g01_stays_in_force_so_a_block_with_only_an_axis_word_cuts():
    result = check("""
        S1000 M3
        G1 X10. F100.
        F0.
        Y20.
        M30
    """)
    [feed] = findings(result, "core.feed-missing")
    assert feed.span.line == 4


def test_g00_stays_in_force_so_a_block_with_only_an_axis_word_is_a_rapid():
    result = check("""
        S1000 M3
        G0 X10.
        F0.
        Y20.
        M30
    """)
    assert "core.feed-missing" not in rules(result)


def test_a_cutting_move_with_the_spindle_stopped_is_reported_on_its_line():
    result = check("""
        G0 X0. Y0.
        G1 X10. F100.
        M30
    """)
    [spindle] = findings(result, "core.spindle-off-cutting")
    assert (spindle.span.line, spindle.span.column) == (2, 1)


def test_g90_coordinates_are_absolute():
    result = check("""
        G90 G0 X10.
        X5.
        #3000=#5001
        M30
    """)
    assert probed(result) == 5.0


def test_g91_coordinates_are_added_to_the_position():
    result = check("""
        G90 G0 X10.
        G91 X5.
        X5.
        #3000=#5001
        M30
    """)
    assert probed(result) == 20.0


def test_g91_stays_in_force_until_g90():
    result = check("""
        G90 G0 X10. Y0.
        G91 X5.
        G90 X1.
        #3000=#5001
        M30
    """)
    assert probed(result) == 1.0


# --------------------------------------------------------------------------- units and integer words


def test_an_integer_word_on_the_e60_is_read_in_thousandths_of_a_millimetre():
    result = check("""
        G21 G90 G0 X1000
        #3000=#5001
        M30
    """, profile="mitsubishi-e60")
    assert probed(result) == 1.0


def test_an_integer_word_in_g20_is_read_in_ten_thousandths_of_an_inch():
    result = check("""
        G20 G90 G0 X1000
        #3000=#5001
        M30
    """, profile="mitsubishi-e60")
    assert probed(result) == pytest.approx(0.1)


def test_a_word_with_a_decimal_point_is_not_scaled_in_g20():
    result = check("""
        G20 G90 G0 X1.5
        #3000=#5001
        M30
    """, profile="mitsubishi-e60")
    assert probed(result) == 1.5


def test_an_integer_word_on_haas_is_a_whole_unit():
    result = check("""
        G21 G90 G0 X12
        #3000=#5001
        M30
    """, profile="haas")
    assert probed(result) == 12.0


def test_the_least_input_increment_setting_overrides_the_profile():
    result = check("""
        G21 G90 G0 X1000
        #3000=#5001
        M30
    """, profile="mitsubishi-e60", least_input_increment=0.01)
    assert probed(result) == pytest.approx(10.0)


def test_switching_to_inch_after_motion_is_reported():
    result = check("""
        G21 G90 G0 X10.
        G20
        X1.
        M30
    """)
    [switch] = findings(result, "core.inch-metric-switch")
    assert switch.span.line == 2


# --------------------------------------------------------------------------- canned cycles

DRILL_SETUP = """\
G21 G90 G17
T1 M6
G43 H1 Z50.
S1000 M3
G0 X0. Y0.
"""


def drill(program: str, **settings):
    """The program after five setup lines (tool 1 at Z50., spindle on): its first line is line 6."""
    return check(DRILL_SETUP + textwrap.dedent(program).lstrip("\n"), **settings)


def test_g81_under_g99_leaves_the_tool_at_the_r_point():
    result = drill("""
        G99 G81 X10. Y0. Z-5. R2. F100.
        #3000=#5003
        M30
    """)
    assert probed(result) == 2.0


def test_g81_under_g98_returns_the_tool_to_the_initial_level():
    result = drill("""
        G98 G81 X10. Y0. Z-5. R2. F100.
        #3000=#5003
        M30
    """)
    assert probed(result) == 50.0


def test_g81_with_l_in_g91_drills_a_row_of_holes_a_pitch_apart():
    result = drill("""
        G91 G98 G81 X10. Z-7. R-48. F100. L3
        #3000=#5001
        M30
    """)
    assert probed(result) == 30.0


def test_g81_with_k_on_fanuc_drills_k_holes_a_pitch_apart():
    result = drill("""
        G91 G99 G81 X10. Z-7. R-48. F100. K3
        #3000=#5001
        M30
    """, profile="fanuc")
    assert probed(result) == 30.0


def test_g81_with_l0_stores_the_cycle_without_drilling():
    result = drill("""
        G99 G81 X10. Y0. Z-5. R2. F100. L0
        #3000=#5003
        M30
    """)
    assert probed(result) == 50.0


def test_g81_in_g91_measures_r_from_the_initial_level_and_z_from_r():
    result = drill("""
        G91 G99 G81 X10. Z-7. R-48. F100.
        #3000=#5003
        M30
    """)
    assert probed(result) == 2.0


def test_a_cycle_with_the_bottom_above_r_is_reported_at_the_z_word():
    result = drill("""
        G99 G81 X10. Y0. Z5. R2. F100.
        G80
        M30
    """)
    [depth] = findings(result, "core.cycle-depth-sign")
    assert (depth.span.line, depth.span.column) == (6, 18)


def test_the_cycle_stays_modal_so_a_later_position_block_drills_a_hole():
    result = drill("""
        G99 G81 X10. Y0. Z-5. R2. F100.
        X20. Z2.
        G80
        M30
    """)
    [zero] = findings(result, "core.cycle-zero-depth")
    assert zero.span.line == 7  # X20. Z2.


def test_g80_ends_the_cycle_so_a_later_position_block_only_moves():
    result = drill("""
        G99 G81 X10. Y0. Z-5. R2. F100.
        G80
        X20. Z2.
        M30
    """)
    assert "core.cycle-zero-depth" not in rules(result)


def test_g00_ends_the_cycle_so_a_later_position_block_only_moves():
    result = drill("""
        G99 G81 X10. Y0. Z-5. R2. F100.
        G0 X20.
        X30. Z2.
        M30
    """)
    assert "core.cycle-zero-depth" not in rules(result)


def test_g01_ends_the_cycle_too():
    result = drill("""
        G99 G81 X10. Y0. Z-5. R2. F100.
        G1 X20.
        X30. Z2.
        #3000=#5003
        M30
    """)
    assert "core.cycle-zero-depth" not in rules(result)
    assert probed(result) == 2.0


def test_a_tool_change_with_the_cycle_still_modal_is_reported():
    result = drill("""
        G99 G81 X10. Y0. Z-5. R2. F100.
        T2 M6
        G80
        M30
    """)
    [modal] = findings(result, "core.cycle-modal-at-tool-change")
    assert modal.span.line == 7  # T2 M6


# --------------------------------------------------------------------------- subprograms and macros


def test_m98_with_l_runs_a_subprogram_of_the_same_file_that_many_times():
    result = check("""
        O1000
        G90 G0 X0. Y0.
        M98 P2000 L3
        #3000=#5001
        M30
        O2000
        G91 G0 X1.
        G90
        M99
    """)
    assert probed(result) == 3.0


def test_after_m99_execution_continues_after_the_call():
    result = check("""
        O1000
        G90 G0 X0. Y0.
        M98 P2000
        G0 Y7.
        #3000=#5002
        M30
        O2000
        G0 Y3.
        M99
    """)
    assert probed(result) == 7.0


def test_a_call_to_a_program_that_does_not_exist_is_reported():
    result = check("""
        O1000
        M98 P4321
        M30
    """)
    [missing] = findings(result, "core.program-not-found")
    assert missing.span.line == 2 and "O4321" in missing.message


def test_g65_passes_a_as_1_and_b_as_2():
    result = check("""
        O1000
        G65 P9000 A5. B2.
        #3000=#100
        M30
        O9000
        #100 = #1 * 10 + #2
        M99
    """)
    assert probed(result) == 52.0


def test_g65_arguments_are_local_to_the_macro():
    result = check("""
        O1000
        #1 = 7.
        G65 P9000 A5.
        #3000=#1
        M30
        O9000
        #100 = #1
        M99
    """)
    assert probed(result) == 7.0


def test_a_macro_moves_to_the_positions_its_arguments_give():
    result = check("""
        O1000
        G90 G0 X0. Y0.
        G65 P9000 X12. Y3.
        #3000=#5001 + #5002 * 100
        M30
        O9000
        G0 X#24 Y#25
        M99
    """)
    assert probed(result) == 312.0


def test_a_variable_the_macro_was_not_given_is_reported_where_it_is_read():
    result = check("""
        O1000
        G65 P9000 A5.
        M30
        O9000
        #100 = #1 + #4
        M99
    """)
    [vacant] = findings(result, "core.undefined-variable")
    assert (vacant.span.line, vacant.span.column, vacant.span.end_column) == (5, 13, 15)
    assert "#4" in vacant.message


def test_m98_recursion_is_stopped_at_the_call_depth():
    started = time.perf_counter()
    result = check("""
        O1
        M98 P2
        M30
        O2
        M98 P2
        M99
    """)
    assert time.perf_counter() - started < 10
    [depth] = findings(result, "core.call-depth")
    assert depth.span.line == 5


# --------------------------------------------------------------------------- macro control flow


def test_a_while_loop_computes_positions_until_its_condition_is_false():
    result = check("""
        #1 = 0
        WHILE [#1 LT 5] DO1
        G90 G0 X[#1 * 10.]
        #1 = #1 + 1
        END1
        #3000=#5001
        M30
    """)
    assert probed(result) == 40.0


def test_nested_while_loops_run_the_inner_loop_for_each_outer_pass():
    result = check("""
        #100 = 0
        #1 = 0
        WHILE [#1 LT 3] DO1
        #2 = 0
        WHILE [#2 LT 4] DO2
        #100 = #100 + 1
        #2 = #2 + 1
        END2
        #1 = #1 + 1
        END1
        #3000=#100
        M30
    """)
    assert probed(result) == 12.0


def test_if_goto_jumps_over_the_blocks_between():
    result = check("""
        #100 = 3
        G90 G0 X1.
        IF [#100 EQ 3] GOTO 50
        G0 X99.
        N50 #3000=#5001
        M30
    """)
    assert probed(result) == 1.0


def test_if_goto_falls_through_when_its_condition_is_false():
    result = check("""
        #100 = 2
        G90 G0 X1.
        IF [#100 EQ 3] GOTO 50
        G0 X99.
        N50 #3000=#5001
        M30
    """)
    assert probed(result) == 99.0


def test_if_then_assigns_only_when_true():
    result = check("""
        #100 = 1
        #101 = 1
        #102 = 1
        IF [#100 GT 5] THEN #101 = 7
        IF [#100 LT 5] THEN #102 = 8
        #3000=#101 * 10 + #102
        M30
    """)
    assert probed(result) == 18.0


def test_a_goto_to_a_missing_sequence_number_is_reported():
    result = check("""
        GOTO 77
        M30
    """)
    [missing] = findings(result, "core.label-not-found")
    assert missing.span.line == 1


def test_sequence_numbers_reused_as_forward_labels_in_each_section_are_not_reported():
    # each GOTO lands on the nearest copy after it, the one its own section means
    result = check("""
        #1=1
        IF [#1 EQ 1] GOTO 5
        #2=1
        N5 #3=1
        IF [#2 EQ 1] GOTO 5
        #4=1
        N5 M30
    """)
    assert findings(result, "core.duplicate-label") == []


def test_a_goto_that_lands_on_the_next_block_while_a_copy_stands_behind_it_is_reported():
    # the loop head N10 is taken by the copy right after the jump: the loop never closes
    result = check("""
        #1=0
        N10 #1=#1+1
        IF [#1 LT 3] GOTO 20
        GOTO 30
        N20 GOTO 10
        (COPIED BLOCK)
        N10 #1=#1+10
        N30 M30
    """)
    [doubtful] = findings(result, "core.duplicate-label", Status.VIOLATED)
    assert doubtful.span.line == 5


def test_a_goto_that_wraps_to_the_top_past_a_nearer_copy_is_reported():
    # no N10 after the jump: the search restarts at the top and takes line 2, not line 4
    result = check("""
        #1=0
        N10 #1=#1+1
        #2=0
        N10 #2=#2+1
        IF [#2 LT 3] GOTO 10
        M30
    """)
    assert [d.span.line for d in findings(result, "core.duplicate-label", Status.VIOLATED)] == [5]


def test_a_lathe_cycle_naming_a_repeated_number_is_still_reported():
    result = check("""
        G18 G99 T101 S500 M03
        G0 X52. Z2.
        G71 U1. R0.5
        G71 P45 Q50 U0.4 W0.1 F0.2
        N45 G0 X20.
        N45 G1 Z-20.
        N50 X52.
        G0 X100. Z100. M05
        M30
    """, machine="lathe")
    assert findings(result, "core.duplicate-label", Status.VIOLATED)


def test_a_macro_alarm_is_reported_with_its_message_and_ends_the_path():
    result = check("""
        G90 G0 X0.
        #3000=1 (TOOL BROKEN)
        G1 X10.
        M30
    """)
    [alarm] = findings(result, "core.macro-alarm")
    assert alarm.span.line == 2
    assert "TOOL BROKEN" in alarm.message and "#3000=1" in alarm.message
    assert "core.feed-missing" not in rules(result)


def test_a_while_loop_without_an_exit_ends_with_loop_bound_unknown():
    started = time.perf_counter()
    result = check("""
        WHILE [1 EQ 1] DO1
        G90 G0 X1.
        END1
        M30
    """, loop_bound=200)
    assert time.perf_counter() - started < 10
    [bound] = findings(result, "core.loop-bound")
    assert bound.status is Status.UNKNOWN
    assert bound.span.line == 3


def test_a_goto_loop_without_an_exit_ends_with_loop_bound_unknown():
    result = check("""
        N10 G90 G0 X1.
        GOTO 10
        M30
    """, loop_bound=200)
    [bound] = findings(result, "core.loop-bound")
    assert bound.status is Status.UNKNOWN


def test_a_while_loop_reads_its_body_a_bounded_number_of_times(monkeypatch):
    import ncverify.lower.iso as lower

    reads = []
    original = lower.read_line

    def counting(*arguments, **keywords):
        reads.append(arguments[1])
        return original(*arguments, **keywords)

    monkeypatch.setattr(lower, "read_line", counting)
    result = check("""
        #1 = 0
        WHILE [#1 LT 100] DO1
        #101 = #101 + 1
        #102 = #102 + 1
        #1 = #1 + 1
        END1
        M30
    """)
    assert rules(result) == []
    assert len(reads) < 30  # 7 lines; a subprogram called 100 times reads its lines once


def test_a_free_parameter_in_a_branch_forks_the_analysis():
    result = check("""
        IF [#500 GT 10.] GOTO 20
        G90 G0 X1.
        #3000=#5001
        M30
        N20 G90 G0 X2.
        #3000=#5001
        M30
    """)
    assert result.paths >= 2
    assert "#500" in result.free_parameters
    assert sorted(alarm_values(result)) == [1.0, 2.0]


def test_a_hazard_that_depends_on_a_free_parameter_comes_with_a_witness():
    result = check("""
        S1000 M3
        G90 G0 X0. Y0. Z5.
        G1 X10. F#500
        M30
    """)
    [feed] = findings(result, "core.feed-missing")
    assert feed.witness and feed.witness["#500"] <= 0


# --------------------------------------------------------------------------- subprogram files


def test_a_subprogram_in_another_folder_is_found_through_the_subprogram_path(tmp_path):
    library = tmp_path / "library"
    library.mkdir()
    (library / "O5000.nc").write_text("O5000\nG91 G0 X4.\nG90\nM99\n", encoding="utf-8")
    main = tmp_path / "jobs" / "main.nc"
    main.parent.mkdir()
    main.write_text("O100\nG90 G0 X1.\nM98 P5000\n#3000=#5001\nM30\n", encoding="utf-8")

    assert findings(check_file(main), "core.program-not-found")
    result = check_file(main, Settings(subprogram_path=(library,)))
    assert not findings(result, "core.program-not-found")
    assert probed(result) == 5.0


def test_a_finding_inside_a_subprogram_file_names_that_file(tmp_path):
    library = tmp_path / "library"
    library.mkdir()
    (library / "O5001.nc").write_text("O5001\nS1000 M3\nG1 X4.\nM99\n", encoding="utf-8")
    main = tmp_path / "main.nc"
    main.write_text("O100\nG90 G0 X1.\nM98 P5001\nM30\n", encoding="utf-8")
    result = check_file(main, Settings(subprogram_path=(library,)))
    [feed] = findings(result, "core.feed-missing")
    assert feed.span.path is not None and feed.span.path.endswith("O5001.nc")
    assert feed.span.line == 3


def test_a_subprogram_in_the_same_folder_is_found_without_a_setting(tmp_path):
    (tmp_path / "O6000.nc").write_text("O6000\nG91 G0 X2.\nG90\nM99\n", encoding="utf-8")
    main = tmp_path / "main.nc"
    main.write_text("O100\nG90 G0 X1.\nM98 P6000\n#3000=#5001\nM30\n", encoding="utf-8")
    assert probed(check_file(main)) == 3.0
