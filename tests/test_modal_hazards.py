"""Modes and settings that act where the program does not expect it (ncverify/checks/modal_hazards.py):
G63 left on, tool length compensation traps, G30 P, G10, G92, feed units, G96 at the centre,
M codes on cutting blocks."""
from __future__ import annotations

import textwrap

import pytest

from ncverify.diagnostics import Status


from conftest import check_program as check


def found(result, rule: str) -> list[tuple[int, str]]:
    return [(d.span.line, d.message) for d in result.diagnostics if d.rule == rule and d.status is Status.VIOLATED]


def lines(result, rule: str) -> list[int]:
    return [line for line, _ in found(result, rule)]


def both_ways(program: str, **settings):
    """The same findings whether plain blocks run in batches or one by one."""
    batched = check(program, **settings)
    one_by_one = check(program, per_block_only=True, **settings)
    assert [(d.rule, d.span, d.message) for d in batched.diagnostics] == [(d.rule, d.span, d.message) for d in one_by_one.diagnostics]
    return batched


MILL_HEADER = """
    G21 G90 G17 G54
    T1 M06
    G00 X0. Y0.
    G43 H01 Z50.
    S1000 M03
"""


def mill(body: str) -> str:
    """The mill header (lines 1-5) and the body from line 6 on."""
    return textwrap.dedent(MILL_HEADER).lstrip("\n") + textwrap.dedent(body).lstrip("\n")


def _plain_cut(count: int, z: str = "Z-1.") -> str:
    return "\n".join(f"G01 X{index * 0.5:.3f} Y{(index % 5) * 0.5:.3f} {z}" for index in range(count))


# --------------------------------------------------------------------------- G63


def test_g63_cut_along_the_tool_axis_is_a_tap_and_a_cut_across_it_is_reported_once():
    result = check(mill("""
        G63
        G01 Z-10. F200.
        Z5.
        X20. F300.
        Y20.
        G64
        X0.
        M30
    """))
    assert lines(result, "core.tapping-mode-left-on") == [9]


def test_g63_is_reported_again_after_g64_then_g63():
    result = check(mill("""
        G63
        G01 X10. F200.
        G64
        G63
        X20.
        M30
    """))
    assert lines(result, "core.tapping-mode-left-on") == [7, 10]


def test_g63_restated_while_in_force_is_the_same_episode():
    result = check(mill("""
        G63
        G01 X10. F200.
        G63
        X20.
        M30
    """))
    assert lines(result, "core.tapping-mode-left-on") == [7]


def test_g84_in_g63_is_a_tap():
    result = check(mill("""
        G63
        G84 X10. Y10. Z-10. R2. F200.
        X20.
        G80
        M30
    """))
    assert lines(result, "core.tapping-mode-left-on") == []


def test_g63_in_a_batch_of_plain_blocks():
    taps = "\n".join(f"G01 Z{-5 - index % 2:.1f}" for index in range(20))  # along Z only: taps
    program = mill("G63\nF300.\n" + taps + "\n" + _plain_cut(20, "Z-6.") + "\nM30\n")
    result = both_ways(program)
    assert lines(result, "core.tapping-mode-left-on") == [29]


# --------------------------------------------------------------------------- tool length compensation


def test_g49_alone_moves_z_and_g49_with_a_reference_return_does_not():
    result = check(mill("""
        G49
        G43 H01 Z50.
        G49 G91 G28 Z0.
        G90
        M30
    """))
    assert lines(result, "core.length-offset-without-z") == [6]


def test_h0_cancels_like_g49():
    result = check(mill("""
        H0
        M30
    """))
    [(line, message)] = found(result, "core.length-offset-without-z")
    assert line == 6 and message.startswith("H0 cancels")


def test_restating_the_same_offset_moves_nothing():
    result = check(mill("""
        G43 H01
        M30
    """))
    assert found(result, "core.length-offset-without-z") == [] and found(result, "core.length-offset-change-moves") == []


def test_a_new_h_while_on_is_reported_without_z_and_not_with_z():
    result = check(mill("""
        H02
        G43 H03 Z50.
        M30
    """))
    assert lines(result, "core.length-offset-change-moves") == [6]
    assert lines(result, "core.length-offset-without-z") == []


def test_g43_to_g44_on_the_same_register_flips_the_sign():
    result = check(mill("""
        G44
        M30
    """))
    assert lines(result, "core.length-offset-change-moves") == [6]
    assert lines(result, "core.length-offset-minus") == [6]


def test_g44_is_reported_where_it_is_switched_on_only():
    result = check("""
        G21 G90 G17 G54
        T1 M06
        G44 H01 Z50.
        G44 H01 Z40.
        M30
    """)
    assert lines(result, "core.length-offset-minus") == [3]


def test_tool_change_with_the_offset_on_is_reported_at_the_first_z_move_before_the_new_g43():
    result = check(mill("""
        G91 G28 Z0.
        G90
        T2 M06
        G00 X20. Y20.
        Z30.
        G43 H02 Z50.
        M30
    """))
    [(line, message)] = found(result, "core.length-offset-across-tool-change")
    assert line == 8 and "line 10" in message and "T2" in message


def test_tool_change_followed_by_its_own_g43_is_not_reported():
    result = check(mill("""
        G91 G28 Z0.
        G90
        T2 M06
        G00 X20. Y20.
        G43 H02 Z50.
        M30
    """))
    assert found(result, "core.length-offset-across-tool-change") == []


def test_stale_length_offset_in_a_batch_of_plain_blocks():
    level = "\n".join(f"G01 X{index:.1f} Y{index % 3:.1f}" for index in range(20))  # no Z motion yet
    program = mill("T2 M06\nF300.\n" + level + "\n" + _plain_cut(20, "Z-2.") + "\nM30\n")
    result = both_ways(program)
    [(line, message)] = found(result, "core.length-offset-across-tool-change")
    assert line == 6 and "line 28" in message


def test_length_rules_stay_off_on_a_lathe():
    result = check("""
        G21 G54
        T0101
        G43 H01
        G49
        M30
    """, machine="lathe")
    assert not [d for d in result.diagnostics if d.rule.startswith("core.length-offset")]


# --------------------------------------------------------------------------- G30 P


@pytest.mark.parametrize("words, reported", [("P2", False), ("P3", False), ("P4", False), ("", True), ("P0", True), ("P5", True), ("P#1", False)])
def test_g30_reference_point_number(words, reported):
    result = check(f"""
        #1=3
        G91 G30 {words} Z0.
        M30
    """)
    assert bool(found(result, "core.reference-point-number")) is reported


def test_g30_without_p_is_a_remark_not_a_warning():
    """No P is the documented default (the 2nd reference point), the usual tool-change
    retract: said at severity info, while a P that picks no point stays a warning."""
    severities = {words: [d.severity.value for d in check(f"G91 G30 {words} Z0.\nM30\n").diagnostics
                          if d.rule == "core.reference-point-number" and d.status is Status.VIOLATED] for words in ("", "P5")}
    assert severities == {"": ["info"], "P5": ["warning"]}


def test_g30_p5_names_the_point_that_does_not_exist():
    result = check("G91 G30 P5 Z0.\nM30\n")
    [(_, message)] = found(result, "core.reference-point-number")
    assert "not a 5th" in message


# --------------------------------------------------------------------------- G10


@pytest.mark.parametrize("block, reported", [
    ("G10 L2 P0 X1.", False), ("G10 L2 P6 X1.", False), ("G10 L2 P7 X1.", True), ("G10 L2 X1.", True),
    ("G10 L20 P1 X1.", False), ("G10 L20 P48 X1.", False), ("G10 L20 P49 X1.", True), ("G10 L20 X1.", True),
    ("G10 L10 P60 R5.", False), ("G10 L2 P[3+4] X1.", True),
])
def test_g10_default_substitution(block, reported):
    result = check(f"G90 {block}\nM30\n")
    assert bool(found(result, "core.g10-default-substitution")) is reported


def test_g10_in_g91_once_in_the_main_program_is_not_reported():
    result = check("G91 G10 L2 P1 X5.\nG90\nM30\n")
    assert found(result, "core.g10-incremental-repeat") == []


def test_g10_in_g90_inside_a_loop_is_not_reported():
    result = check("""
        #1=0
        WHILE [#1 LT 3] DO1
        G90 G10 L2 P1 X[#1*5.]
        #1=#1+1
        END1
        M30
    """)
    assert found(result, "core.g10-incremental-repeat") == []


def test_g10_in_g91_in_a_subprogram_is_reported():
    result = check("""
        O1000
        M98 P2000 L2
        M30
        O2000
        G91 G10 L2 P1 X5.
        G90
        M99
    """)
    [(line, message)] = found(result, "core.g10-incremental-repeat")
    assert line == 5 and "O2000" in message


def test_g10_in_g91_in_a_goto_loop_is_reported_when_it_runs_again():
    result = check("""
        #1=0
        N10 G91 G10 L2 P1 X5.
        G90
        #1=#1+1
        IF [#1 LT 3] GOTO10
        M30
    """)
    [(line, message)] = found(result, "core.g10-incremental-repeat")
    assert line == 2 and "already run" in message


# --------------------------------------------------------------------------- G92


def test_g92_once_is_fine_and_a_second_time_is_reported():
    result = check("""
        G92 X0. Y0. Z50.
        G00 X10.
        G92 X0.
        M30
    """)
    [(line, message)] = found(result, "core.g92-repeated")
    assert line == 3 and "line 1" in message


def test_g92_in_a_loop_is_reported():
    result = check("""
        #1=0
        WHILE [#1 LT 2] DO1
        G92 X0.
        #1=#1+1
        END1
        M30
    """)
    assert lines(result, "core.g92-repeated") == [3]


def test_a_lathe_speed_clamp_is_not_a_coordinate_setting():
    result = check("""
        G21 G54
        G92 S2000
        T0101
        G92 S2500
        M30
    """, machine="lathe")
    assert found(result, "core.g92-repeated") == []


# --------------------------------------------------------------------------- feed plausibility


@pytest.mark.parametrize("mode, feed, reported", [
    ("G95", "F0.2", False), ("G95", "F5.", False), ("G95", "F150.", True), ("G95", "F20", False),
    ("G94", "F0.5", True), ("G94", "F1.", False), ("G20 G94", "F0.03", True), ("G20 G94", "F0.05", False),
    ("G20 G95", "F0.3", True), ("G20 G95", "F0.01", False),
])
def test_feed_plausibility(mode, feed, reported):
    result = check(f"""
        {mode}
        S1000 M03
        G01 X10. {feed}
        M30
    """)
    assert bool(found(result, "core.feed-plausibility")) is reported


def test_a_tap_feed_per_revolution_is_its_pitch():
    result = check(mill("""
        G95
        G84 X10. Y10. Z-20. R2. F6.
        G80
        M30
    """))
    assert found(result, "core.feed-plausibility") == []


def test_a_thread_lead_is_not_a_feed():
    result = check("""
        G95
        S200 M03
        G33 Z-30. F6.
        M30
    """)
    assert found(result, "core.feed-plausibility") == []


def test_a_lathe_whose_program_does_not_state_the_feed_mode_is_not_judged():
    program = """
        G21 G54
        T0101
        G97 S1000 M03
        G00 X30. Z2.
        G01 Z-10. F0.2
        {mode}
        G01 X40. F0.25
        M30
    """
    assert found(check(program.format(mode=""), machine="lathe"), "core.feed-plausibility") == []
    assert lines(check(program.format(mode="G94"), machine="lathe"), "core.feed-plausibility") == [7]


def test_feed_plausibility_once_per_feed_value_in_batches():
    rows = [f"G01 X{index:.1f} Y{index % 3:.1f} F{'0.5' if index < 20 or index >= 30 else '300.'}" for index in range(40)]
    program = mill("\n".join(rows) + "\nM30\n")
    result = both_ways(program)
    assert lines(result, "core.feed-plausibility") == [6, 36]


# --------------------------------------------------------------------------- G96 at the centre


LATHE = """
    G21 G95 G54
    T0101
    G92 S2500
    {body}
    M30
"""


def test_css_facing_to_the_centre_is_reported_once_per_g96():
    result = check(LATHE.format(body="""G96 S200 M03
    G00 X55. Z0.
    G01 X-1.6 F0.15
    G00 Z2. X55.
    G01 X-1.6 Z0.
    G97 S1000
    G96 S180
    G00 X40. Z-1.
    G01 X0.
    """), machine="lathe")
    assert lines(result, "core.css-toward-center") == [6, 12]


def test_css_g96_restated_with_a_new_speed_is_the_same_episode():
    result = check(LATHE.format(body="""G96 S200 M03
    G00 X55. Z0.
    G01 X-1.6 F0.15
    G96 S180
    G00 Z2. X55.
    G01 X-1.6 Z0.
    """), machine="lathe")
    assert lines(result, "core.css-toward-center") == [6]


def test_css_cut_starting_at_the_centre_and_g97_on_the_axis():
    result = check(LATHE.format(body="""G97 S1000 M03
    G00 X0. Z2.
    G01 Z-10. F0.1
    G96 S200
    G01 X20.
    """), machine="lathe")
    [(line, message)] = found(result, "core.css-toward-center")
    assert line == 8 and "S2500" in message


def test_css_without_a_clamp_says_there_is_no_limit():
    result = check("""
        G21 G95 G54
        T0101
        G96 S200 M03
        G00 X30. Z0.
        G01 X0. F0.1
        M30
    """, machine="lathe")
    [(_, message)] = found(result, "core.css-toward-center")
    assert "no spindle speed clamp" in message


def test_css_rule_is_for_lathes():
    result = check("G96 S200 M03\nG01 X0. F100.\nM30\n")
    assert found(result, "core.css-toward-center") == []


# --------------------------------------------------------------------------- M codes with motion


@pytest.mark.parametrize("block, reported", [
    ("G00 X10. M03", False), ("G01 X10. M05", True), ("X10. M03", True), ("G02 X10. Y0. R5. M19", True),
    ("M03", False), ("G01 M03", False),
])
def test_spindle_code_in_a_cutting_block(block, reported):
    result = check(f"""
        G21 G90 G17 G54
        S1000 M03
        G01 X0. Y0. F100.
        {block}
        M30
    """)
    assert bool(found(result, "core.m-code-with-motion")) is reported


def test_spindle_code_on_a_hole_of_the_modal_cycle_is_not_a_cutting_block():
    result = check(mill("""
        G81 X10. Y10. Z-5. R2. F100.
        X20. M03
        G80
        M30
    """))
    assert found(result, "core.m-code-with-motion") == []
