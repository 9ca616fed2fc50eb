"""Fagor 8060/8065: the tool-axis sign, the turning-cycle set, rigid tapping, modal
subroutines (#MCALL) and where pockets and thread mills leave the tool."""
from __future__ import annotations

from pathlib import Path

import pytest

from fagor_trace import trace
from hypothesis import given, settings, strategies
from ncverify import Settings, check_text
from ncverify.context import Tool
from ncverify.project import ConfigError, load_project_text


from conftest import check_program


def check(program: str, project_text: str = ""):
    return check_program(program, "t.pim", project_text, dialect="fagor")


def findings(result, status: str = "violated") -> dict[str, list]:
    found: dict[str, list] = {}
    for diagnostic in result.diagnostics:
        if diagnostic.status.value == status:
            found.setdefault(diagnostic.rule, []).append(diagnostic)
    return found


# --------------------------------------------------------------------------- the tool-axis sign


def test_a_pocket_along_minus_z_approaches_one_millimetre_below_the_surface():
    run = trace("G0 G90 X60 Y35 Z-25 F800 S900 M3\n#TOOL AX [Z-]\nG99 G88 Z-2 I20 D2 J20 B5\nG80\nM30\n")
    [hole] = run.holes
    assert (hole.up, hole.r_point, hole.bottom) == (-1.0, -1.0, 20.0)  # surface = Z-2 + 2 = 0, approach at Z-1
    assert [segment.end["Z"] for segment in run.segments if segment.cycle][-1] == -2.0  # G99: back to the reference plane


def test_drilling_along_minus_x_judges_the_depth_toward_plus_x():
    correct = check("G19\nG1 G90 X-25 Y0 Z0 F1000 S1000 M3\n#TOOL AX [X-]\nG81 X-2 I8 K1\nG80\nM30\n")
    reversed_depth = check("G19\nG1 G90 X-25 Y0 Z0 F1000 S1000 M3\n#TOOL AX [X-]\nG81 X-2 I-12 K1\nG80\nM30\n")
    assert "core.cycle-depth-sign" not in findings(correct)
    assert "core.cycle-depth-sign" in findings(reversed_depth)


def test_a_rapid_into_the_stock_along_minus_x_is_found():
    program = "; ncverify: stock box X0:100 Y-50:50 Z-30:0\nG19\nG1 G90 X-25 Y0 Z-10 F1000 S1000 M3\n#TOOL AX [X-]\nG81 X{} I8 K1\nG80\nM30\n"
    assert "core.rapid-into-stock" in findings(check(program.format(5)))  # the reference plane X5 is inside the blank
    assert "core.rapid-into-stock" not in findings(check(program.format(-2)))


def test_the_start_plane_on_the_wrong_side_of_the_reference_plane_is_reported_for_either_sign():
    result = check("G18\nG1 G90 X0 Y25 Z0 F1000 S1000 M3\n#TOOL AX [Y-]\nG81 Y2 I-8 K1\nG80\nM30\n")
    assert {"core.cycle-depth-sign", "core.cycle-r-above-initial"} <= findings(result).keys()


@pytest.mark.parametrize("reference, inside", [(2, True), (-2, False)])
def test_a_reference_plane_inside_the_stock_along_minus_x_is_reported(reference, inside):
    program = f"; ncverify: stock box X0:80 Y0:120 Z-40:0\nG19\nG0 G90 X-30 Y20 Z-12 S2000 M3\n#TOOL AX [X-]\nG98 G81 X{reference} I30 F180\nG80\nM30\n"
    found = findings(check(program)).get("core.clearance-below-stock", [])
    assert bool(found) is inside
    if inside:
        assert "R point X2" in found[0].message and "face X0" in found[0].message


def test_a_reference_plane_along_x_over_a_polygon_stock_is_unknown_not_passed():
    program = ("; ncverify: stock polygon X0 Y0, X80 Y0, X80 Y120, X0 Y120 Z-40:0\nG19\nG0 G90 X-30 Y20 Z-12 S2000 M3\n#TOOL AX [X-]\n"
               "G98 G81 X2 I30 F180\nG80\nM30\n")
    [finding] = findings(check(program), "unknown").get("core.clearance-below-stock", [])
    assert "along X" in finding.message and "polygon" in finding.message


# --------------------------------------------------------------------------- the cycle set (H28)


def test_turning_cycles_are_reported_once_as_not_verified():
    result = check("#LATHECY ON\nG0 G90 X0 Y0 Z25 S800 M3\nG81 Z2 I-20\nG82 Z2 I-20 B3\nG80\n#LATHECY OFF\nM30\n")
    unknown = findings(result, "unknown")["fagor.turning-cycle"]
    assert len(unknown) == 1 and "milling-cycles manual does not define the turning cycles" in unknown[0].message
    assert "fagor.cycle-set-left-on" not in findings(result)


def test_a_turning_cycle_ends_the_milling_cycle_and_leaves_the_position_unknown():
    run = trace("G0 G90 X0 Y0 Z25 S800 M3\nG81 Z2 I-20\n#LATHECY ON\nG81 Z2 I-20\n#LATHECY OFF\nX50\nM30\n")
    assert len(run.holes) == 1 and run.segments[-1].start["Z"] is None


# --------------------------------------------------------------------------- rigid tapping (H19)


TAPPING = "T4 D4 M6\nS500 M3\nG0 G90 X30 Y30 Z25 F750\nG99 G84 Z2 I-15 R{}\nG80\nM30\n"


def test_rigid_tapping_needs_a_spindle_encoder():
    without = "[machine]\nspindle_encoder = false\n"
    assert "fagor.rigid-tapping-encoder" in findings(check(TAPPING.format(1), without))
    assert "fagor.rigid-tapping-encoder" not in findings(check(TAPPING.format(0), without))
    assert "fagor.rigid-tapping-encoder" not in findings(check(TAPPING.format(1), "[machine]\nspindle_encoder = true\n"))


def test_rigid_tapping_from_a_computed_r_is_judged_not_skipped():
    [finding] = findings(check("; ncverify: assume 0 <= P1 <= 1\n" + TAPPING.format("P1"), "[machine]\nspindle_encoder = false\n"))["fagor.rigid-tapping-encoder"]
    assert finding.witness == {"P1": 1.0}


def test_spindle_encoder_must_be_true_or_false():
    with pytest.raises(ConfigError, match="spindle_encoder"):
        load_project_text("[machine]\nspindle_encoder = 1\n", Path("ncverify.toml"))


def test_rigid_tapping_without_the_machine_capability_is_unknown():
    assert "fagor.rigid-tapping-encoder" in findings(check(TAPPING.format(1)), "unknown")


# --------------------------------------------------------------------------- #MCALL / #MDOFF


SPOT = """
    %L SPOT
    G91 G1 Z-3 F100
    G0 Z3
    G90
    #RET
    G0 G90 X0 Y0 Z5
    #MCALL SPOT
    G0 X10
    G0 X20
    #MDOFF
    G0 X30
    M30
"""


def test_mcall_runs_the_subroutine_after_every_move_until_mdoff():
    run = trace(SPOT)
    plunges = [segment.end["X"] for segment in run.segments if segment.kind == "feed"]
    assert plunges == [10.0, 20.0]  # not at #MCALL itself, not after X30, not inside SPOT


def test_mcall_passes_its_arguments_as_local_parameters():
    run = trace("%L SPOT\nG1 Z P0 F100\nG0 Z5\n#RET\nG0 G90 X0 Y0 Z5\n#MCALL SPOT A-4\nG0 X10\n#MDOFF\nM30\n")
    assert [segment.end["Z"] for segment in run.segments if segment.kind == "feed"] == [-4.0]


def test_without_mcall_the_same_moves_make_no_call():
    run = trace(SPOT.replace("#MCALL SPOT", ""))
    assert not [segment for segment in run.segments if segment.kind == "feed"]


# --------------------------------------------------------------------------- pockets and thread mills (§6)


def test_a_pocket_under_g99_goes_back_to_the_reference_plane_above_its_approach():
    run = trace("G0 G90 X60 Y35 Z25 F800 S900 M3\nG99 G87 Z5 I-20 D4 J40 K20 B5\nG80\nM30\n")
    cycle = [(segment.role, segment.kind, segment.end["Z"]) for segment in run.segments if segment.cycle]
    assert cycle == [("approach", "rapid", 2.0), ("infeed", "feed", -20.0), ("out-of-hole", "rapid", 2.0), ("out-of-hole", "rapid", 5.0)]


def test_bore_and_thread_milling_rapid_to_the_centre_even_in_g1():
    run = trace("G1 G90 X0 Y0 Z25 F800 S900 M3\nG210 Z2 I-20 J30 B2\nG1 X50\nG80\nM30\n")
    assert [segment.kind for segment in run.segments if segment.role == "between-holes"] == ["rapid"]


def test_a_thread_mill_ends_above_the_centre_at_the_retract_plane():
    run = trace("G0 G90 X40 Y40 Z25 S900 M3 F300\nG98 G212 Z2 I-15 J20 K1.5 B1.5 E3\nG80\nM30\n")
    last = [segment for segment in run.segments if segment.cycle][-1]
    assert (last.end["X"], last.end["Y"], last.end["Z"]) == (40.0, 40.0, 25.0)


STUD = "; ncverify: stock box X0:100 Y0:100 Z-30:0\nT1 D1 M6\nG0 G90 X40 Y40 Z25 S900 M3 F300\nG98 G212 Z2 D{d} I-15 J20 K1.5 B{b}{e} Q90\nG80\nM30\n"
RADIUS_4 = "[tools.1]\nradius = 4\n"


def test_g212_runs_around_the_stud_at_the_entry_radius_not_down_its_centre():
    run = trace(STUD.format(d=2, b=1.5, e=" E3"), tools={1: Tool(1, radius=4.0)})
    cycle = [(segment.role, segment.kind, segment.end["Y"], segment.end["Z"]) for segment in run.segments if segment.cycle]
    assert cycle == [("approach", "rapid", 40.0, 2.0), ("to-thread", "rapid", 57.0, 2.0), ("to-thread", "rapid", 57.0, 0.0),  # J20/2 + 4 + E3 at Q90
                     ("infeed", "feed", 57.0, -15.0), ("out-of-hole", "rapid", 57.0, 2.0), ("retract", "rapid", 57.0, 25.0),
                     ("retract", "rapid", 40.0, 25.0)]


def test_g212_entry_rapids_are_judged_against_the_blank():
    too_low = check(STUD.format(d=4, b=1.5, e=" E3"), RADIUS_4)  # the surface taken at Z-2: the rapid beside the stud ends 2 mm in the blank
    [finding] = findings(too_low)["core.rapid-into-stock"]
    assert finding.span.line == 4 and "X40 Y57 Z2 to X40 Y57 Z-2" in finding.message
    assert "core.rapid-into-stock" not in findings(check(STUD.format(d=2, b=1.5, e=" E3"), RADIUS_4))


def test_g212_upward_without_e_rapids_down_through_the_stud():
    result = check(STUD.format(d=0, b=-1.5, e=""), RADIUS_4)
    messages = [d.message for d in findings(result)["core.rapid-into-stock"]]
    assert any("over the stud's centre" in message and "to X40 Y40 Z-15" in message for message in messages)


def test_g212_upward_with_e_goes_down_cleared_material_the_blank_does_not_know():
    result = check(STUD.format(d=0, b=-1.5, e=" E3"), RADIUS_4)
    assert "core.rapid-into-stock" not in findings(result)
    assert any("beside the stud" in d.message for d in findings(result, "unknown")["core.rapid-into-stock"])


def test_g212_without_the_tool_radius_leaves_its_passes_unjudged():
    result = check(STUD.format(d=4, b=1.5, e=" E3"))
    assert "core.rapid-into-stock" not in findings(result)
    assert any("tool radius is not in the tool table" in d.message for d in findings(result, "unknown")["core.rapid-into-stock"])


def test_g82_retract_coordinate_is_judged_along_minus_z_too():
    program = "G0 G90 X0 Y0 Z-40 F200 S800 M3\n#TOOL AX [Z-]\nG99 G82 Z-2 I20 B4 H{}\nG80\nM30\n"
    assert "fagor.g82-retract-coordinate" in findings(check(program.format(3)))  # Z3 is past the first peck's bottom Z2
    assert "fagor.g82-retract-coordinate" not in findings(check(program.format(-1)))


def test_bore_milling_without_a_floor_pass_is_reported_in_a_blind_hole_only():
    program = "; ncverify: stock box X0:100 Y0:100 Z-40:0\nG0 G90 X50 Y50 Z25 F400 S2500 M3\nG99 G210 Z2 I{} J30 B-2\nG80\nM30\n"
    assert "fagor.bore-milling-no-floor" in findings(check(program.format(-20)))
    assert "fagor.bore-milling-no-floor" not in findings(check(program.format(-42)))  # through the blank


def test_bore_milling_with_a_computed_pitch_is_judged_not_skipped():
    program = "; ncverify: stock box X0:100 Y0:100 Z-40:0\n; ncverify: assume -3 <= P1 <= 3\nG0 G90 X50 Y50 Z25 F400 S2500 M3\nG99 G210 Z2 I-20 J30 B P1\nG80\nM30\n"
    [finding] = findings(check(program))["fagor.bore-milling-no-floor"]
    assert finding.witness["P1"] < 0


def test_g83_depth_is_judged_against_the_far_face_along_minus_x():
    program = "; ncverify: stock box X0:80 Y0:120 Z-40:0\nG19\nG0 G90 X-30 Y20 Z-12 S2000 M3\n#TOOL AX [X-]\nG98 G83 X-2 I{} J4 F180\nG80\nM30\n"
    assert "fagor.g83-depth" in findings(check(program.format(30)))  # 4 pecks of 30 end at X118, far past the face at X80
    assert "fagor.g83-depth" not in findings(check(program.format(5)))


def test_a_far_face_the_stock_does_not_give_answers_unknown():
    program = "; ncverify: stock polygon X0 Y0, X80 Y0, X80 Y120 Z-40:0\nG19\nG0 G90 X-30 Y20 Z-12 S2000 M3\n#TOOL AX [X-]\nG98 G83 X-2 I5 J4 F180\nG80\nM30\n"
    [finding] = findings(check(program), "unknown")["fagor.g83-depth"]
    assert finding.reason != "no stock defined"


@settings(max_examples=60, deadline=None)
@given(strategies.sampled_from(["G81 Z{z} I{i}", "G82 Z{z} I{i} B2 D{d}", "G85 Z{z} I{i}", "G87 Z{z} I{i} D{d} J20 K10 B3", "G88 Z{z} I{i} D{d} J15 B3",
                                "G210 Z{z} I{i} D{d} J20 B2"]),
       strategies.integers(-30, 30), strategies.integers(-30, 30), strategies.integers(-30, 30), strategies.integers(0, 4), strategies.booleans())
def test_a_cycle_along_minus_z_is_the_mirror_of_the_same_cycle_along_plus_z(cycle, start, reference, depth, surface, g99):
    def run(sign):
        block = cycle.format(z=sign * reference, i=sign * depth, d=surface)
        stock = "Z-25:0" if sign > 0 else "Z0:25"
        program = f"; ncverify: stock box X0:50 Y0:50 {stock}\nG0 G90 X10 Y10 Z{sign * start} F300 S1000 M3\n#TOOL AX [Z{'+' if sign > 0 else '-'}]\n{'G99' if g99 else 'G98'} {block}\nG80\nM30\n"
        result = check_text(program, "t.pim", Settings(dialect="fagor", stock_resolution=0.0))  # the cut stock is kept along +Z only
        levels = [(hole.r_point, hole.bottom) for hole in trace(program).holes]
        return levels, reported_hazards(result)

    (up_levels, up_findings), (down_levels, down_findings) = run(1), run(-1)
    assert down_levels == [(-r_point, -bottom) for r_point, bottom in up_levels]
    assert down_findings == up_findings


def reported_hazards(result) -> set[str]:
    hazards = {"core.cycle-depth-sign", "core.cycle-zero-depth", "core.cycle-r-above-initial", "fagor.g82-retract-coordinate",
               "core.rapid-into-stock", "fagor.bore-milling-no-floor", "core.clearance-below-stock"}
    return {d.rule for d in result.diagnostics if d.status.value == "violated" and d.rule in hazards}


def test_a_thread_milled_upward_rapids_down_the_predrilled_hole_first():
    program = "G0 G90 X50 Y50 Z25 F300 S2000 M3\nG99 G211 Z2 I-15 J20 K1.2 B{}\nG80\nM30\n"
    upward = [(segment.role, segment.kind, segment.end["Z"]) for segment in trace(program.format(-1.5)).segments if segment.cycle]
    downward = [segment.role for segment in trace(program.format(1.5)).segments if segment.cycle]
    assert upward[:2] == [("approach", "rapid", 2.0), ("into-hole", "rapid", -15.0)]
    assert "into-hole" not in downward


def test_the_rapid_down_the_predrilled_hole_is_not_judged_safe():
    result = check("; ncverify: stock box X0:100 Y0:100 Z-30:0\nG0 G90 X50 Y50 Z25 F300 S2000 M3\nG99 G211 Z2 I-15 J20 K1.2 B-1.5\nG80\nM30\n")
    assert any(d.span.line == 3 for d in findings(result, "unknown").get("core.rapid-into-stock", []))


# --------------------------------------------------------------------------- counts must be whole numbers (H10, H3)


@pytest.mark.parametrize("cycle, rule, count, wrong", [
    ("G82 Z2 I-20 B3 J{}", "fagor.g82-parameters", "2.5", True),
    ("G82 Z2 I-20 B3 J{}", "fagor.g82-parameters", "2", False),
    ("G83 Z2 I-5 J{}", "fagor.g83-peck-count", "3.5", True),
    ("G83 Z2 I-5 J{}", "fagor.g83-peck-count", "3", False),
])
def test_a_peck_count_must_be_a_whole_number(cycle, rule, count, wrong):
    result = check(f"G0 G90 X0 Y0 Z25 S800 M3 F200\n{cycle.format(count)}\nG80\nM30\n")
    messages = [d.message for d in findings(result).get(rule, [])]
    assert bool(messages) is wrong, messages
    if wrong:
        assert f"J{count}" in messages[0] and "whole number" in messages[0]


def test_a_peck_count_from_a_free_parameter_is_refuted_with_a_fractional_witness():
    program = "; ncverify: assume 1 <= P1 <= 4\nG0 G90 X0 Y0 Z25 S800 M3 F200\nG83 Z2 I-5 J P1\nG80\nM30\n"
    [finding] = [d for d in check(program).diagnostics if d.rule == "fagor.g83-peck-count"]
    assert finding.status.value == "violated"
    [(name, value)] = finding.witness.items()
    assert name == "P1" and 1 <= value <= 4 and not float(value).is_integer()


# --------------------------------------------------------------------------- NR in a cycle's zone (H1, H2)


NR_IN_ZONE = "G0 G90 X0 Y0 Z25 F200 S900 M3\nG99 G81 Z2 I-20\n{}\nG90 G80\nM30\n"


def test_nr_in_g90_drills_the_same_hole_again():
    result = check(NR_IN_ZONE.format("X10 Y10 NR3"))
    [finding] = findings(result)["core.repeat-same-hole"]
    assert (finding.span.line, finding.span.column, finding.span.end_column) == (3, 9, 12)  # the NR3 word
    assert "G81 NR3 in G90" in finding.message and "X10 Y10" in finding.message and "3 times" in finding.message


def test_nr_in_the_defining_block_drills_the_same_hole_again():
    result = check("G0 G90 X0 Y0 Z25 F200 S900 M3\nG99 G81 Z2 I-20 X10 Y10 NR2\nG80\nM30\n")
    assert [d.span.line for d in findings(result)["core.repeat-same-hole"]] == [2]


@pytest.mark.parametrize("block", ["G91 X10 NR3", "G91 X10 Y-5 NR4", "X10 Y10 NR0", "X10 Y10 NR1", "G91 X10 NR1"])
def test_nr_that_spaces_the_holes_or_does_not_repeat_is_not_reported(block):
    assert "core.repeat-same-hole" not in findings(check(NR_IN_ZONE.format(block)), "violated")


@settings(max_examples=30, deadline=None)
@given(strategies.integers(1, 6), strategies.integers(-20, 20).filter(bool))
def test_nr_in_g91_makes_a_row_of_holes_one_increment_apart(count, step):
    run = trace(NR_IN_ZONE.format(f"G91 X{step} NR{count}"))
    assert [hole.position["X"] for hole in run.holes][1:] == [float(step * k) for k in range(1, count + 1)]


def test_nr_outside_a_cycle_zone_still_runs_a_modal_subroutine_call():
    run = trace("%L SPOT\nG91 G1 Z-3 F100\nG0 Z3\nG90\n#RET\nG0 G90 X0 Y0 Z5\n#MCALL SPOT\nG91 G0 X10 NR2\nG90\n#MDOFF\nM30\n")
    assert 20.0 in [segment.end["X"] for segment in run.segments if segment.kind == "feed"]  # after the last repeat at least


# --------------------------------------------------------------------------- G86 back-off (H18)


BORE = "T6 D6 M6\nS600 M3 M8\nG0 G90 X50 Y50 Z25 F60\nG98 G86 Z2 I-30 {}\nX80\nG80\nM30\n"


@pytest.mark.parametrize("words, verdict", [("A0 Q0 D-0.3", "unknown"), ("A1 Q90 E0.2", "unknown"), ("A0 Q0", "violated"), ("A1 Q0 D0 E0", "violated"),
                                            ("A0 D0.3", "violated"), ("R1", None), ("Q0 D0.2", None)])
def test_g86_back_off_direction_is_unknown_and_a_missing_back_off_is_reported(words, verdict):
    found = [d for d in check(BORE.format(words)).diagnostics if d.rule == "fagor.g86-back-off"]
    assert {d.status.value for d in found} == ({verdict} if verdict else set())
    if verdict == "unknown":
        [finding] = found  # once for the definition, not again at X80
        assert finding.span.line == 4 and "Q" in finding.message and "into the wall" in finding.message


def test_g86_back_off_direction_with_a_computed_mode_is_unknown_too():
    found = [d for d in check("; ncverify: assume 0 <= P1 <= 1\n" + BORE.format("A P1 Q0 D-0.3")).diagnostics if d.rule == "fagor.g86-back-off"]
    assert [d.status.value for d in found if d.status.value != "proved"] == ["unknown"]  # A may be A0 or A1
