"""Hazards of canned cycles, lathe compound cycles and G33 threading (reference 9.2):
the tricky cases each rule must get right, beyond its page's two examples."""
from __future__ import annotations

import textwrap

from ncverify import Settings, check_text
from ncverify.diagnostics import Status

MILL_HEAD = """
    G21 G90 G17 G54
    T1 M06
    G00 X20. Y20.
    G43 H01 Z50.
    S1500 M03
"""
LATHE_HEAD = """
    G21 G95 G54
    T0101
    G97 S1000 M03
    G00 X42. Z2.
"""


def check(body: str, machine: str = "mill", head: str | None = None):
    head = head if head is not None else (LATHE_HEAD if machine == "lathe" else MILL_HEAD)
    program = textwrap.dedent(head).lstrip("\n") + textwrap.dedent(body).lstrip("\n")
    return check_text(program, "t.nc", Settings(machine=machine))


def findings(result, rule: str, status: Status | None = Status.VIOLATED):
    return [d for d in result.diagnostics if d.rule == rule and (status is None or d.status is status)]


def lines(result, rule: str) -> list[int]:
    return [d.span.line for d in findings(result, rule)]


# --------------------------------------------------------------------------- core.comp-in-cycle


def test_comp_in_cycle_is_reported_once_per_cycle_not_per_hole():
    result = check("""
        G41 D01 X10. Y10.
        G81 X20. Y20. Z-5. R2. F100.
        X40.
        X60.
        G80
        G40 X0. Y0.
        M30
    """)
    assert lines(result, "core.comp-in-cycle") == [7]


def test_comp_cancelled_before_the_cycle_is_fine():
    result = check("""
        G41 D01 X10. Y10.
        G40 X0. Y0.
        G81 X20. Y20. Z-5. R2. F100.
        G80
        M30
    """)
    assert not findings(result, "core.comp-in-cycle", None)


# --------------------------------------------------------------------------- core.cycle-modal-at-end


def test_a_motion_code_cancels_the_cycle_before_the_end():
    result = check("""
        G81 X20. Y20. Z-5. R2. F100.
        G00 Z50.
        M30
    """)
    assert not findings(result, "core.cycle-modal-at-end", None)


def test_cycle_modal_at_m02():
    result = check("""
        G81 X20. Y20. Z-5. R2. F100.
        X40.
        M02
    """)
    assert lines(result, "core.cycle-modal-at-end") == [8]


# --------------------------------------------------------------------------- core.cycle-shift-missing


def test_g18_shift_is_k_and_i_and_k_is_not_taken_as_a_repeat_count():
    result = check("""
        G18
        G76 X20. Y20. Z-10. R2. K-0.2 F60.
        G80
        M30
    """)
    assert not findings(result, "core.cycle-shift-missing", None)
    assert not findings(result, "core.repeat-count-range", None)


def test_a_shift_letter_of_another_plane_does_not_count():
    result = check("""
        G76 X20. Y20. Z-10. R2. K-0.2 F60.
        G80
        M30
    """)
    [finding] = findings(result, "core.cycle-shift-missing")
    assert "K-0.2 is not a shift address in G17" in finding.message


def test_zero_shift_is_no_shift():
    result = check("""
        G87 X20. Y20. Z-10. R-30. I0. J0. F60.
        G80
        M30
    """)
    [finding] = findings(result, "core.cycle-shift-missing")
    assert finding.message.startswith("G87 has no shift")


def test_q_as_the_shift_is_its_own_message():
    result = check("""
        G76 X20. Y20. Z-10. R2. Q0.2 F60.
        G80
        M30
    """)
    [finding] = findings(result, "core.cycle-shift-missing")
    assert "takes its shift from Q0.2" in finding.message
    assert (finding.span.line, finding.span.column) == (6, 25)  # at the Q word


def test_shift_from_a_free_parameter_gets_a_witness():
    result = check("""
        (ncverify: assume -5 <= #1 <= 5)
        G76 X20. Y20. Z-10. R2. I#1 F60.
        G80
        M30
    """)
    [finding] = findings(result, "core.cycle-shift-missing", None)
    assert finding.status is Status.VIOLATED
    assert finding.witness == {"#1": 0.0}


def test_shift_from_an_unbounded_input_is_unknown_with_its_example_value():
    result = check("""
        G76 X20. Y20. Z-10. R2. I#1 F60.
        G80
        M30
    """)
    [finding] = findings(result, "core.cycle-shift-missing", None)
    assert finding.status is Status.UNKNOWN and finding.witness == {"#1": 0.0}
    assert "depends on the input #1 = 0" in finding.reason and "assume" in finding.reason


# --------------------------------------------------------------------------- core.single-peck


def test_single_peck_in_g91_uses_the_resolved_depth():
    result = check("""
        G91 G83 Z-10. R-48. Q10. F100.
        G90 G80
        M30
    """)
    [finding] = findings(result, "core.single-peck")
    assert "hole depth 10" in finding.message


def test_peck_shorter_than_the_hole_is_fine():
    result = check("""
        G83 X20. Y20. Z-10. R2. Q11.9 F100.
        G80
        M30
    """)
    assert not findings(result, "core.single-peck", None)


def test_lathe_face_drilling_peck_sign_is_ignored():
    result = check("""
        G00 X0. Z5.
        G83 Z-20. R3. Q-25. F0.1
        G80
        M30
    """, machine="lathe")
    assert lines(result, "core.single-peck") == [6]


# --------------------------------------------------------------------------- core.repeat-same-hole


def test_repeats_in_g91_with_an_increment_are_a_row_of_holes():
    result = check("""
        G91 G81 X15. Z-14. R-48. L4 F150.
        G90 G80
        M30
    """)
    assert not findings(result, "core.repeat-same-hole", None)


def test_repeats_in_g91_without_an_increment_drill_the_same_hole():
    result = check("""
        G91 G81 Z-14. R-48. L3 F150.
        G90 G80
        M30
    """)
    [finding] = findings(result, "core.repeat-same-hole")
    assert "L3 in G91" in finding.message


def test_a_repeat_count_of_one_is_fine():
    result = check("""
        G81 X20. Y20. Z-5. R2. L1 F100.
        X40. L1
        G80
        M30
    """)
    assert not findings(result, "core.repeat-same-hole", None)


def test_lathe_repeat_count_is_k():
    result = check("""
        G00 X0. Z5.
        G83 Z-20. R3. Q5. K3 F0.1
        G80
        M30
    """, machine="lathe")
    [finding] = findings(result, "core.repeat-same-hole")
    assert "G83 K3" in finding.message


# --------------------------------------------------------------------------- core.cycle-parameter-value


def test_tapping_mode_zero_is_allowed():
    result = check("""
        M04
        G74 X20. Y20. Z-10. R5. F625. ,R0
        G80
        M30
    """)
    assert not findings(result, "core.cycle-parameter-value", None)


def test_lathe_tapping_mode_is_checked_from_the_table_too():
    result = check("""
        G00 X0. Z5.
        G84 Z-10. R3. F1.25 ,R3
        G80
        M30
    """, machine="lathe")
    [finding] = findings(result, "core.cycle-parameter-value")
    assert ",R3" in finding.message


def test_tapping_mode_from_a_free_parameter():
    result = check("""
        (ncverify: assume 0 <= #1 <= 5)
        G84 X20. Y20. Z-10. R5. F625. ,R#1
        G80
        M30
    """)
    [finding] = findings(result, "core.cycle-parameter-value", None)
    assert finding.status is Status.VIOLATED and finding.witness["#1"] not in (0.0, 1.0)


# --------------------------------------------------------------------------- core.lathe-arc-over-180


def test_negative_r_on_a_mill_is_the_long_arc_and_allowed():
    result = check("""
        G01 X30. Y20. F200.
        G02 X40. Y20. R-10.
        M30
    """)
    assert not findings(result, "core.lathe-arc-over-180", None)


# --------------------------------------------------------------------------- core.finish-shape-mismatch


ROUGH_OD_AND_ID = """
    G71 U1.5 R0.5
    G71 P10 Q20 U0.4 W0.1 F0.25
    G71 P30 Q40 U-0.4 W0.1 F0.25
    G70 P10 Q20
    G70 P30 Q40
    G00 X100. Z50.
    M30
    N10 G00 X20.
    G01 Z-15. F0.1
    N20 X42.
    N30 G00 X10.
    G01 Z-10. F0.1
    N40 X8.
"""


def test_each_finishing_cycle_may_finish_any_roughed_shape():
    result = check(ROUGH_OD_AND_ID, machine="lathe")
    assert not findings(result, "core.finish-shape-mismatch", None)


def test_finishing_without_roughing_is_not_checked():
    result = check("""
        G70 P10 Q20
        G00 X100. Z50.
        M30
        N10 G00 X20.
        G01 Z-15. F0.1
        N20 X42.
    """, machine="lathe")
    assert not findings(result, "core.finish-shape-mismatch", None)


# --------------------------------------------------------------------------- core.two-block-mixture


def test_the_seed_example_is_a_mixture():
    result = check("""
        G71 U1.5 R1. P50 Q115 X0.4 Z0.1
        G00 X100. Z50.
        M30
        N50 G00 X20.
        G01 Z-15. F0.1
        N115 X42.
    """, machine="lathe")
    assert lines(result, "core.two-block-mixture") == [5]


def test_grooving_second_block_carries_r_legitimately():
    result = check("""
        G75 R0.5
        G75 X30. Z-20. P2000 Q3000 R0.1 F0.05
        G00 X100. Z50.
        M30
    """, machine="lathe")
    assert not findings(result, "core.two-block-mixture", None)


def test_g73_mixture():
    result = check("""
        G73 U3. R3 P10 Q20 F0.25
        G00 X100. Z50.
        M30
        N10 G00 X20.
        N20 X42.
    """, machine="lathe")
    [finding] = findings(result, "core.two-block-mixture")
    assert finding.span.line == 5
    assert "U3 is ambiguous, X relief (first block) / X allowance (second block)" in finding.message


# --------------------------------------------------------------------------- core.thread-parameters


def test_finishing_allowance_not_less_than_the_thread_height():
    result = check("""
        G76 P011060 R1.5
        G76 X27.4 Z-30. P1.3 Q0.35 F2.
        G00 X100. Z50.
        M30
    """, machine="lathe")
    [finding] = findings(result, "core.thread-parameters")
    assert "finishing allowance R1.5" in finding.message and finding.span.line == 6


def test_zero_lead_height_and_first_cut():
    result = check("""
        G76 P011060 R0.05
        G76 X27.4 Z-30. P0. Q0. F0.
        G00 X100. Z50.
        M30
    """, machine="lathe")
    messages = " | ".join(d.message for d in findings(result, "core.thread-parameters"))
    assert "thread height P0 is not positive" in messages
    assert "first cut depth Q0 is not positive" in messages
    assert "lead F0 is not positive" in messages
    assert "finishing allowance" not in messages


def test_fanuc_style_thread_words_give_no_false_alarm():
    result = check("""
        G76 P021060 Q100 R0.05
        G76 X27.4 Z-30. P1300 Q350 F2.
        G00 X100. Z50.
        M30
    """, machine="lathe")
    assert not findings(result, "core.thread-parameters", None)


# --------------------------------------------------------------------------- core.thread-start-angle


def test_q0_is_outside_the_lathe_range_but_inside_the_mill_range():
    lathe = check("""
        G33 Z-30. F2. Q0.
        G00 X100. Z50.
        M30
    """, machine="lathe")
    assert lines(lathe, "core.thread-start-angle") == [5]
    mill = check("""
        G00 X0. Y0. Z5.
        G33 Z-30. F2. Q0.
        G00 Z50.
        M30
    """)
    assert not findings(mill, "core.thread-start-angle", None)


def test_start_angle_without_a_point_counts_thousandths():
    program = textwrap.dedent(LATHE_HEAD).lstrip("\n") + "G33 Z-30. F2. Q90000\nG00 X100. Z50.\nM30\n"
    result = check_text(program, "t.nc", Settings(machine="lathe", least_input_increment=0.001))
    assert not findings(result, "core.thread-start-angle", None)
    result = check_text(program.replace("Q90000", "Q900000"), "t.nc", Settings(machine="lathe", least_input_increment=0.001))
    [finding] = findings(result, "core.thread-start-angle")
    assert "Q900 (Q without a decimal point counts in 0.001 degree steps)" in finding.message


def test_modal_g33_block_is_checked_too():
    result = check("""
        G33 Z-30. F2. Q90.
        G00 X42. Z2.
        G33 Z-30.
        Z-40. Q400.
        G00 X100. Z50.
        M30
    """, machine="lathe")
    [finding] = findings(result, "core.thread-start-angle")
    assert finding.span.line == 8 and "Q400" in finding.message


def test_a_tapping_mode_in_a_later_hole_block_is_a_code_not_a_length():
    """``X40. ,R1`` is lowered as a plain move whose words scale like lengths; the cycle
    takes ,R as written."""
    program = textwrap.dedent(MILL_HEAD).lstrip("\n") + textwrap.dedent("""
        G84 X20. Y20. Z-10. R5. F625. ,R1
        X40. ,R1
        G80
        M30
    """).lstrip("\n")
    result = check_text(program, "t.nc", Settings(least_input_increment=0.001))
    assert not findings(result, "core.cycle-parameter-value", None)


def test_lathe_repeat_count_in_a_later_hole_block():
    result = check_text(textwrap.dedent(LATHE_HEAD).lstrip("\n") + textwrap.dedent("""
        G00 X0. Z5.
        G83 Z-20. R3. Q5. F0.1
        C90. K2
        G80
        M30
    """).lstrip("\n"), "t.nc", Settings(machine="lathe", least_input_increment=0.001))
    [finding] = findings(result, "core.repeat-same-hole")
    assert finding.span.line == 7 and "G83 K2" in finding.message
