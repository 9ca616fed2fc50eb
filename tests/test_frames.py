"""Coordinate transformations: the frame maths, the interpreter's workpiece trace, and the
Klartext and SINUMERIK statements that set a frame."""
from __future__ import annotations

import math
import textwrap

import numpy
import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_text, frames, values
from ncverify.diagnostics import Status
from ncverify.context import Context
from ncverify.detect import Detection
from ncverify.dialect import setup_for
from ncverify.interpret import Interpreter
from ncverify.source import ProgramSource
from tests.test_heidenhain import Recorder, at, program, trace

PLANES = (("X", "Y", "Z"), ("Y", "Z", "X"), ("Z", "X", "Y"))
numbers = st.floats(-500, 500, allow_nan=False).map(lambda number: round(number, 3))
factors = st.sampled_from([0.5, 2.0, 1.5, -1.0, 0.25])
points = st.fixed_dictionaries({axis: numbers for axis in frames.AXES})


@st.composite
def parts(draw):
    kind = draw(st.sampled_from(["translation", "rotation", "mirror", "scaling"]))
    if kind == "translation":
        return frames.translation({axis: draw(numbers) for axis in draw(st.sets(st.sampled_from(frames.AXES)))})
    if kind == "rotation":
        return frames.rotation(draw(st.sampled_from(PLANES)), draw(numbers))
    if kind == "mirror":
        return frames.mirror(draw(st.sets(st.sampled_from(frames.AXES), min_size=1)))
    return frames.scaling({axis: draw(factors) for axis in draw(st.sets(st.sampled_from(frames.AXES)))}, {axis: draw(numbers) for axis in frames.AXES})


def close(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(math.isclose(a[axis], b[axis], abs_tol=1e-6) for axis in a)


# --------------------------------------------------------------------------- frame maths


@hypothesis_settings(max_examples=200, deadline=None)
@given(st.lists(parts(), min_size=1, max_size=4), points)
def test_a_composed_frame_maps_like_its_parts_applied_innermost_first(chain, point):
    composed = frames.IDENTITY
    for part in chain:
        composed = frames.compose(composed, part)
    by_parts = point
    for part in reversed(chain):
        by_parts = part.to_workpiece(by_parts)
    assert close(composed.to_workpiece(point), by_parts)


@hypothesis_settings(max_examples=100, deadline=None)
@given(st.sets(st.sampled_from(frames.AXES), min_size=1), st.sampled_from(PLANES), numbers, points)
def test_mirroring_twice_and_rotating_back_are_the_identity(axes, plane, angle, point):
    assert frames.compose(frames.mirror(axes), frames.mirror(axes)).is_identity
    undone = frames.compose(frames.rotation(plane, angle), frames.rotation(plane, -angle))
    assert close(undone.to_workpiece(point), point)


@hypothesis_settings(max_examples=100, deadline=None)
@given(st.lists(parts(), min_size=1, max_size=3), points)
def test_the_inverse_brings_a_point_back(chain, point):
    frame = frames.IDENTITY
    for part in chain:
        frame = frames.compose(frame, part)
    assert close(frame.inverse().to_workpiece(frame.to_workpiece(point)), point)


@hypothesis_settings(max_examples=100, deadline=None)
@given(st.lists(parts(), min_size=1, max_size=3), st.lists(points, min_size=1, max_size=6), st.sampled_from([("X", "Y", "Z"), ("X", "Y")]), numbers)
def test_the_vectorised_run_maps_every_point_to_the_very_floats_of_the_per_point_path(chain, rows, axes, z):
    """Bit for bit, not just close: a batch's rapid back along the cut it just made is clear
    by the exact check of the last cuts, which needs the two ends to be the same floats on
    both paths. (A matrix product per row left one of them an ulp off under a rotation, and
    the batch said unknown where the block path said clear: found by fuzzing.)"""
    frame = frames.IDENTITY
    for part in chain:
        frame = frames.compose(frame, part)
    array = numpy.array([[row[axis] for axis in axes] for row in rows])
    others = {} if "Z" in axes else {"Z": z}
    mapped_axes, mapped = frame.map_points(axes, array, others)
    for row, out in zip(rows, mapped):
        expected = frame.to_workpiece({**{axis: row[axis] for axis in axes}, **others})
        assert [float(out[mapped_axes.index(axis)]) for axis in mapped_axes] == [expected[axis] for axis in mapped_axes]


def test_a_symbolic_shift_stays_linear_and_a_symbolic_angle_is_unknown():
    depth = values.parameter("#1", -20.0, -1.0)
    shifted = frames.translation({"Z": depth}).to_workpiece({"X": 1.0, "Y": 2.0, "Z": 5.0})
    assert values.interval(shifted["Z"]) == (-15.0, 4.0)
    turned = frames.rotation(("X", "Y", "Z"), depth).to_workpiece({"X": 1.0, "Y": 2.0, "Z": 5.0})
    assert turned["X"] is None and turned["Y"] is None and turned["Z"] == 5.0


def test_an_arc_stays_an_arc_only_under_a_similarity_of_its_plane():
    assert frames.mirror(["X"]).plane_similarity(("X", "Y", "Z")) == (1.0, True)
    assert frames.compose(frames.mirror(["X"]), frames.mirror(["Y"])).plane_similarity(("X", "Y", "Z")) == (1.0, False)
    assert frames.scaling({"X": 2.0, "Y": 2.0}).plane_similarity(("X", "Y", "Z")) == (2.0, False)
    assert frames.scaling({"X": 2.0, "Y": 0.5}).plane_similarity(("X", "Y", "Z")) is None
    assert frames.rotation(("X", "Y", "Z"), 30.0).plane_similarity(("Z", "X", "Y")) is None  # the arc leaves its plane


# --------------------------------------------------------------------------- Klartext


def shifted(x: str, y: str, z: str = "") -> str:
    return f"CYCL DEF 7.0 DATUM SHIFT\nCYCL DEF 7.1 X{x}\nCYCL DEF 7.2 Y{y}\n" + (f"CYCL DEF 7.3 Z{z}\n" if z else "")


def klartext(body: str):
    return check_text(program(body), "t.h", Settings())


def test_a_datum_shift_that_moves_the_program_onto_the_blank_finds_the_rapid_into_it():
    found = klartext(shifted("+200", "+200") + "L X-150 Y-150 R0 FMAX\nL Z-5 R0 FMAX\n")
    assert at(found, "core.rapid-into-stock") == [10]  # the plunge; the retract straight up the tool's axis after it meets nothing new


def test_a_datum_shift_that_moves_the_program_clear_of_the_blank_finds_nothing():
    found = klartext(shifted("+200", "+200") + "L X+50 Y+50 R0 FMAX\nL Z-5 R0 FMAX\n")
    # the first move runs at the start height, above the blank: clear although X and Y were not set yet
    assert not at(found, "core.rapid-into-stock") and not at(found, "core.rapid-into-stock", Status.UNKNOWN)


def test_the_tool_does_not_move_when_the_datum_moves_so_its_height_stays_known():
    recorded = trace(program(shifted("+10", "+10", "-5") + "L X+5 Y+5 R0 FMAX\n"))
    move = recorded.segments[1]
    assert move.start["Z"] == 100.0 and move.end == {"X": 15.0, "Y": 15.0, "Z": 100.0}


def test_an_incremental_datum_shift_adds_to_the_last_one_and_247_resets_it():
    body = shifted("+10", "+10") + "CYCL DEF 7.0 DATUM SHIFT\nCYCL DEF 7.1 IX+5\nL X+0 Y+0 R0 FMAX\n"
    body += "CYCL DEF 247 DATUM SETTING ~\n  Q339=+1 ;DATUM NUMBER\nL X+0 Y+0 R0 FMAX\n"
    ends = [segment.end for segment in trace(program(body)).segments[1:]]
    assert (ends[0]["X"], ends[0]["Y"]) == (15.0, 10.0) and (ends[1]["X"], ends[1]["Y"]) == (0.0, 0.0)


def test_shift_then_mirror_then_rotation_about_the_shifted_datum():
    """Seed L8161-8178: the datum shift comes first, rotation (L7890-7899) and mirror image
    (L7847-7850) act about the shifted datum. Reading: a programmed point is rotated, then
    mirrored, then shifted; X+10 Y+0 under shift (50, 50), mirror X and ROT+90 lands at
    X50 Y60 (mirroring first would give X50 Y40)."""
    body = shifted("+50", "+50") + "CYCL DEF 8.0 MIRROR IMAGE\nCYCL DEF 8.1 X\nCYCL DEF 10.0 ROTATION\nCYCL DEF 10.1 ROT+90\nL X+10 Y+0 R0 FMAX\n"
    end = trace(program(body)).segments[-2].end
    assert (end["X"], end["Y"]) == (50.0, 60.0)


def test_mirroring_one_axis_reverses_the_arc_and_neutral_values_reset():
    body = "L X+10 Y+0 R0 FMAX\nCYCL DEF 8.0 MIRROR IMAGE\nCYCL DEF 8.1 Y\nCC X+0 Y+0\nC X+0 Y+10 DR+\nCYCL DEF 8.0 MIRROR IMAGE\nCYCL DEF 8.1\nC X+10 Y+0 DR-\n"
    arcs = [segment for segment in trace(program(body)).segments if segment.arc is not None]
    assert arcs[0].arc.direction == "cw" and arcs[0].end["Y"] == -10.0
    assert arcs[1].arc.direction == "cw" and arcs[1].end["Y"] == 0.0


def test_scaling_scales_coordinates_and_cycle_depths_alike():
    body = ("CYCL DEF 11.0 SCALING\nCYCL DEF 11.1 SCL 0.5\nCYCL DEF 200 DRILLING ~\n  Q200=+2 ;SET-UP CLEARANCE ~\n  Q201=-10 ;DEPTH ~\n"
            "  Q206=+150 ;FEED ~\n  Q202=+5 ;PLUNGING DEPTH ~\n  Q210=+0 ;DWELL ~\n  Q203=+0 ;SURFACE ~\n  Q204=+50 ;2ND ~\n  Q211=+0 ;DWELL\n"
            "L X+100 Y+100 R0 FMAX M99\n")
    hole = trace(program(body)).holes[0]
    assert hole.bottom == -5.0 and hole.r_point == 1.0 and (hole.position["X"], hole.position["Y"]) == (50.0, 50.0)


def test_an_arc_under_unequal_axis_scaling_is_not_judged():
    body = "CYCL DEF 26.0 AXIS-SPEC. SCALING\nCYCL DEF 26.1 X2 Y1 CCX+0 CCY+0\nL X+10 Y+0 R0 FMAX\nCC X+0 Y+0\nC X+0 Y+10 DR+\n"
    recorded = trace(program(body))
    assert any("unequal scaling" in fault.message for fault in recorded.faults)
    assert recorded.segments[-2].arc.centre is None


def test_a_datum_table_row_leaves_the_position_unknown_with_the_reason():
    found = klartext("CYCL DEF 7.0 DATUM SHIFT\nCYCL DEF 7.1 #5\nL X+50 Y+50 R0 FMAX\nL Z-5 R0 FMAX\n")
    assert any("datum table" in d.message and d.status is Status.UNKNOWN for d in found.diagnostics)
    assert not at(found, "core.rapid-into-stock")


def test_a_tilted_plane_leaves_later_positions_unknown_until_reset():
    body = "PLANE SPATIAL SPA+0 SPB+45 SPC+0 TURN MB MAX FMAX\nL X+50 Y+50 R0 FMAX\nL Z-5 R0 FMAX\nPLANE RESET STAY\nL Z+50 R0 FMAX\nL X+50 Y+50 Z-5 R0 FMAX\n"
    found = klartext(body)
    assert at(found, "core.rapid-into-stock")[:1] == [11] and at(found, "core.unsupported-code", Status.UNKNOWN)
    assert [d.span.line for d in found.diagnostics if d.rule == "core.rapid-into-stock" and "tilted" in d.message] == [7]


def test_trans_datum_shifts_like_cycle_7_and_its_reset_cancels_it():
    body = "TRANS DATUM AXIS X+200 Y+200\nL X-150 Y-150 R0 FMAX\nL Z-5 R0 FMAX\nL Z+50 R0 FMAX\nTRANS DATUM RESET\nL X-150 Y-150 R0 FMAX\nL Z-5 R0 FMAX\n"
    assert at(klartext(body), "core.rapid-into-stock") == [8]  # down into the blank (back up the tool's own axis meets nothing new)


# --------------------------------------------------------------------------- SINUMERIK

BLANK = 'WORKPIECE(,"",,"RECTANGLE",0,0,-20,-80,100,100)\nT1 D1\nM6\nG17 G90 G54\nS3000 M3\nG0 X0 Y0 Z50\n'  # X-50..50 Y-50..50 Z-20..0


def sinumerik(body: str):
    return check_text(BLANK + textwrap.dedent(body).lstrip("\n") + "G0 Z50\nM30\n", "t.mpf", Settings(dialect="sinumerik"))


def crashes(result) -> list[int]:
    return [d.span.line for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.status is Status.VIOLATED]


def test_sinumerik_trans_moves_the_program_onto_the_blank_and_a_bare_trans_resets():
    found = sinumerik("TRANS X200 Y200\nG0 X-200 Y-190\nG0 Z-5\nG0 Z50\nTRANS\nG0 X-200 Y-190\nG0 Z-5\n")
    assert crashes(found) == [9]  # down into the blank (back up the tool's own axis meets nothing new)


def test_sinumerik_atrans_and_arot_append_in_the_transformed_system():
    """TRANS X100, then AROT RPL=90 about the shifted origin, then ATRANS X10 along the
    rotated X axis: X-10 Y100 -> X0 Y100 -> rotated X-100 Y0 -> shifted X0 Y0, on the blank."""
    found = sinumerik("TRANS X100\nAROT RPL=90\nATRANS X10\nG0 X-10 Y100\nG0 Z-5\n")
    assert crashes(found) == [11]


def test_sinumerik_rot_replaces_the_frame_and_mirror_reverses_arcs():
    found = sinumerik("TRANS X500\nROT RPL=90\nG0 X10 Y-20\nG0 Z-5\n")
    assert crashes(found) == [10]  # the TRANS is gone: X10 Y-20 lands at X20 Y10


def test_sinumerik_a_spatial_rotation_leaves_positions_unknown():
    found = sinumerik("ROT X30\nG0 X10 Y10\nG0 Z-5\n")
    assert not crashes(found)
    assert any(d.rule == "core.unsupported-code" and "ROT X" in d.message for d in found.diagnostics)


def test_sinumerik_g58_replaces_the_absolute_part_and_g59_the_additive_part():
    found = sinumerik("TRANS X300\nATRANS X5\nG58 X-5\nG0 X0 Y0\nG0 Z-5\nG0 Z50\nG59 X300\nG0 X0 Y0\nG0 Z-5\n")
    assert crashes(found) == [11]  # G58: -5 + 5 = 0 on X; G59 X300: -5 + 300, clear of the blank


def test_sinumerik_cycle800_makes_positions_unknown_until_deselected():
    found = sinumerik("CYCLE800(1,\"TC1\",0,57,0,0,0,0,45,0,0,0,0,1,100)\nG0 X0 Y0\nG0 Z-5\nG0 Z50\nCYCLE800()\nG0 X0 Y0\nG0 Z-5\n")
    assert crashes(found) == [13]


def sinumerik_trace(text: str) -> Recorder:
    dialect = setup_for("sinumerik", Settings(dialect="sinumerik"), Detection("sinumerik", 1.0), Context())
    recorder = Recorder()
    Interpreter(ProgramSource.from_text(text, "t.mpf"), dialect.frontend, recorder, Settings(dialect="sinumerik"), power_on=dialect.power_on,
                cycle_models=dialect.cycle_models, twins={}, runtime=dialect.runtime).run()
    return recorder


@pytest.mark.parametrize("statement", ["MIRROR X0", "AMIRROR X0", "SCALE X-2 Y2"])
def test_sinumerik_mirroring_one_plane_axis_reverses_the_arc(statement):
    recorded = sinumerik_trace(f"G17 G90\n{statement}\nG0 X20 Y0 Z5\nG2 X0 Y20 I-20 J0 F100\nM30\n")
    arc = recorded.segments[-1]
    factor = 2.0 if "SCALE" in statement else 1.0
    assert arc.arc.direction == "ccw" and arc.end["Y"] == 20.0 * factor and arc.arc.centre == (0.0, 0.0)
    assert arc.arc.start_radius == 20.0 * factor


def test_a_clearance_height_is_judged_where_the_datum_shift_puts_it():
    from ncverify.check import rule_definitions

    page = rule_definitions()["heidenhain.sl-clearance-height"].example("Use instead")
    lowered = page.replace("9  CYCL CALL", "CYCL DEF 7.0 DATUM SHIFT\nCYCL DEF 7.1 Z-60\n9  CYCL CALL")
    assert not at(check_text(page, "t.h", Settings()), "heidenhain.sl-clearance-height")
    assert at(check_text(lowered, "t.h", Settings()), "heidenhain.sl-clearance-height")  # Q7=+50 is Z-10 on the blank
    tilted = page.replace("9  CYCL CALL", "CYCL DEF 19.0 WORKING PLANE\nCYCL DEF 19.1 A+0 B+30 C+0\n9  CYCL CALL")
    unknown = [d for d in check_text(tilted, "t.h", Settings()).diagnostics if d.rule == "heidenhain.sl-clearance-height"]
    assert [d.status for d in unknown] == [Status.UNKNOWN]  # where Q7 lies on the blank is not known under a tilt


@pytest.mark.parametrize("mirror", ["", "MIRROR X0\n"])
def test_a_mirror_swaps_the_compensation_side_with_the_arc_so_an_inside_arc_stays_inside(mirror):
    tool = "$TC_DP1[1,1]=120\n$TC_DP6[1,1]=5\n"
    inside = sinumerik(f"{tool}{mirror}G0 X20 Y0\nG1 G41 X20 Y0 F200\nG3 X17 Y3 CR=3\nG40\n")
    outside = sinumerik(f"{tool}{mirror}G0 X20 Y0\nG1 G41 X20 Y0 F200\nG2 X17 Y-3 CR=3\nG40\n")
    assert [d for d in inside.diagnostics if d.rule == "core.comp-gouge" and d.status is Status.VIOLATED]
    assert not [d for d in outside.diagnostics if d.rule == "core.comp-gouge"]


def test_a_scaling_factor_of_zero_is_out_of_range():
    found = klartext("CYCL DEF 11.0 SCALING\nCYCL DEF 11.1 SCL 0\nCYCL DEF 11.0 SCALING\nCYCL DEF 11.1 SCL 1\n")
    assert [d.message for d in found.diagnostics if d.rule == "heidenhain.scaling-factor"] == [
        "cycle 11: scaling factor SCL 0 is outside 0.000001-99.999999 (seed L7926-7954)"]


def test_a_rotation_that_cancels_rl_is_reported_only_when_the_contour_goes_on_without_it():
    start = "L X-20 Y+10 R0 FMAX\nL Z-5 R0 F200\nL X+10 Y+10 RL F300\nCYCL DEF 10.0 ROTATION\nCYCL DEF 10.1 ROT+15\n"
    assert at(klartext(start + "L X+90 Y+10\n"), "heidenhain.rotation-cancels-compensation") == [11]
    assert not at(klartext(start + "L X+90 Y+10 RL\n"), "heidenhain.rotation-cancels-compensation")
    assert not at(klartext(start.replace(" RL ", " R0 ") + "L X+90 Y+10\n"), "heidenhain.rotation-cancels-compensation")


def test_a_rotated_pocket_runs_where_the_rotation_puts_it():
    pocket = ("CYCL DEF 251 RECTANGULAR POCKET ~\n  Q215=+0 ;MACHINING OPERATION ~\n  Q218=+40 ;FIRST SIDE LENGTH ~\n  Q219=+20 ;2ND SIDE LENGTH ~\n"
              "  Q220=+2 ;CORNER RADIUS ~\n  Q368=+0 ;ALLOWANCE FOR SIDE ~\n  Q224=+0 ;ANGLE OF ROTATION ~\n  Q367=+0 ;POCKET POSITION ~\n"
              "  Q207=+500 ;FEED RATE FOR MILLING ~\n  Q351=+1 ;CLIMB OR UP-CUT ~\n  Q201=-5 ;DEPTH ~\n  Q202=+5 ;PLUNGING DEPTH ~\n"
              "  Q369=+0 ;ALLOWANCE FOR FLOOR ~\n  Q206=+150 ;FEED RATE FOR PLNGNG ~\n  Q338=+0 ;INFEED FOR FINISHING ~\n  Q200=+2 ;SET-UP CLEARANCE ~\n"
              "  Q203=+0 ;SURFACE COORDINATE ~\n  Q204=+50 ;2ND SET-UP CLEARANCE ~\n  Q370=+1 ;TOOL PATH OVERLAP ~\n  Q366=+1 ;PLUNGE ~\n  Q385=+500 ;FINISHING FEED RATE\n")
    body = shifted("+50", "+50") + "CYCL DEF 10.0 ROTATION\nCYCL DEF 10.1 ROT+90\n" + pocket + "L X+30 Y+0 R0 FMAX M99\n"
    plunge = next(segment for segment in trace(program(body)).segments if segment.role == "infeed")
    assert (round(plunge.end["X"], 9), plunge.end["Y"], plunge.end["Z"]) == (50.0, 80.0, -5.0)


@hypothesis_settings(max_examples=15, deadline=None)
@given(st.sampled_from(["TRANS X30 Y-20\n", "ROT RPL=35\n", "TRANS X-40\nAMIRROR Y0\n", "SCALE X2 Y2 Z0.5\n"]),
       st.lists(st.tuples(st.sampled_from(["G0", "G1"]), numbers, numbers, st.sampled_from([-5.0, 2.0, 20.0])), min_size=12, max_size=30))
def test_plain_blocks_under_a_frame_give_the_same_findings_in_a_batch_as_one_by_one(frame, moves):
    text = BLANK + frame + "F300\n" + "".join(f"{code} X{x:g} Y{y:g} Z{z:g}\n" for code, x, y, z in moves) + "G0 Z50\nM30\n"

    def found(per_block_only: bool):
        result = check_text(text, "t.mpf", Settings(dialect="sinumerik", per_block_only=per_block_only))
        return sorted((d.rule, d.span.line, d.status.value, d.message) for d in result.diagnostics)

    assert found(False) == found(True)


def test_a_disengaging_direction_from_a_free_parameter_under_a_mirror_is_unknown():
    from ncverify.check import rule_definitions

    page = rule_definitions()["heidenhain.disengage-mirror"].example("Example")
    found = check_text(page.replace("Q214=+1 ", "Q214=+Q50 "), "t.h", Settings())
    assert at(found, "heidenhain.disengage-mirror", Status.UNKNOWN) and not at(found, "heidenhain.disengage-mirror")
    assert not at(check_text(page.replace("Q214=+1 ", "Q214=+0 "), "t.h", Settings()), "heidenhain.disengage-mirror", Status.UNKNOWN)
