"""HEIDENHAIN TNC 620 Klartext: reading, lowering, cycles and their hazards."""
from __future__ import annotations

import textwrap

from hypothesis import given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_text
from ncverify.detect import detect
from ncverify.diagnostics import Status
from ncverify.dialect import setup_for
from ncverify.interpret import Interpreter
from ncverify.lower.heidenhain import KlartextLowering, stock_from_text
from ncverify.read.heidenhain import continues
from ncverify.source import ProgramSource


def program(body: str, name: str = "T") -> str:
    """A program frame around ``body``: a 100 x 100 x 20 blank, tool 1, spindle on."""
    lines = [f"0  BEGIN PGM {name} MM", "1  BLK FORM 0.1 Z X+0 Y+0 Z-20", "2  BLK FORM 0.2  X+100  Y+100  Z+0",
             "3  TOOL CALL 1 Z S2000", "4  L  Z+100 R0 FMAX M3"]
    lines += textwrap.dedent(body).strip("\n").splitlines()
    lines += ["98 L  Z+100 R0 FMAX M30", f"99 END PGM {name} MM"]
    return "\n".join(lines) + "\n"


def drilling(depth="-15", surface="+0", clearance="+2", second="+50", number=200) -> str:
    return (f"CYCL DEF {number} DRILLING ~\n    Q200={clearance} ;SET-UP CLEARANCE ~\n    Q201={depth} ;DEPTH ~\n"
            f"    Q206=+150 ;FEED RATE FOR PLNGNG ~\n    Q202=+5 ;PLUNGING DEPTH ~\n    Q210=+0 ;DWELL TIME AT TOP ~\n"
            f"    Q203={surface} ;SURFACE COORDINATE ~\n    Q204={second} ;2ND SET-UP CLEARANCE ~\n    Q211=+0 ;DWELL TIME AT DEPTH\n")


from conftest import project


def check(text: str, project_text: str = ""):
    return check_text(text, "t.h", Settings(), project(project_text))


def rules(result, status=None) -> set[str]:
    return {d.rule for d in result.diagnostics if status is None or d.status is status}


def at(result, rule, status=Status.VIOLATED):
    return [d.span.line for d in result.diagnostics if d.rule == rule and d.status is status]


class Recorder:
    """An observer that keeps what the interpreter reports."""

    def __init__(self):
        self.segments, self.holes, self.runs, self.faults = [], [], [], []

    def segment(self, segment, state):
        self.segments.append(segment)

    def motion_run(self, run, state):
        self.segments.extend(run.segment(index) for index in range(len(run)))

    def hole(self, hole, state):
        self.holes.append(hole)

    def cycle_run(self, run, state):
        self.runs.append(run)

    def change(self, change, state):
        pass

    def fault(self, fault):
        self.faults.append(fault)

    def note(self, note):
        self.faults.append(note)

    def report_verdict(self, *args):
        pass


def trace(text: str) -> Recorder:
    from ncverify.context import Context
    from ncverify.detect import Detection

    dialect = setup_for("heidenhain", Settings(), Detection("heidenhain", 1.0), Context())
    recorder = Recorder()
    interpreter = Interpreter(ProgramSource.from_text(text, "t.h"), dialect.frontend, recorder, Settings(), power_on=dialect.power_on,
                              cycle_models=dialect.cycle_models, twins={}, runtime=dialect.runtime)
    interpreter.run()
    return recorder


# --------------------------------------------------------------------------- reading


def test_detection_picks_klartext_from_the_text_alone():
    found = detect(program(drilling() + "5  L  X+10  Y+10 R0 FMAX M99\n"))
    assert found.dialect == "heidenhain" and found.confidence >= 0.5


def test_continuation_lines_end_in_a_tilde_before_or_after_the_comment():
    assert continues(b"    Q200=+2 ;SET-UP CLEARANCE ~")
    assert continues(b"5  CYCL DEF 200 DRILLING ~ ; note")
    assert not continues(b"    Q211=+0 ;DWELL TIME AT DEPTH")


def test_a_cycle_block_reads_every_parameter_with_keywords_and_localised_comments():
    raw = ("7 CYCL DEF 251 RECTANGULAR POCKET ~\n    Q215=+0 ;加工操作 ~\n    Q206= AUTO ;FEED ~\n    Q253= MAX ;F PRE-POS ~\n"
           "    Q357+0.2 ;CLEARANCE TO SIDE").encode()
    block = KlartextLowering().lower(raw, 7, None)[0]
    assert not block.notes
    op = block.ops[0]
    assert op.params["Q215"] == 0.0 and op.params["Q206"] == "AUTO" and op.params["Q253"] == "FMAX" and op.params["Q357"] == 0.2
    assert op.param_spans["Q253"].line == 10


def test_garbled_text_is_a_syntax_finding_with_its_column():
    result = check(program("5  L  X+10 ? Y+5 FMAX"))
    syntax = [d for d in result.diagnostics if d.rule == "core.syntax"]
    assert [(d.span.line, d.span.column) for d in syntax] == [(6, 12)]


@hypothesis_settings(max_examples=300, deadline=None)
@given(st.text(alphabet=st.sampled_from(list("LXYZQ0123456789+-.=~;*() CYLDEFRMNPAT\"\n")), max_size=80))
def test_no_text_makes_the_reader_raise(text):
    lowering = KlartextLowering()
    for number, line in enumerate(text.split("\n"), 1):
        for block in lowering.lower(line.encode(), number, None):
            assert all(note.rule in ("core.syntax", "core.unsupported-code") for note in block.notes)


def test_blk_form_is_the_stock():
    stock = stock_from_text("1 BLK FORM 0.1 Z X-10 Y+0 Z-20\n2 BLK FORM 0.2 IX+110 Y+50,5 Z+1\n")
    assert stock.x_range == (-10.0, 100.0) and stock.y_range == (0.0, 50.5) and stock.z_range == (-20.0, 1.0)


# --------------------------------------------------------------------------- motion and flow


def test_a_rapid_into_the_blank_is_found_with_no_project_file():
    result = check(program("5  L  X+50  Y+50 R0 FMAX\n6  L  Z-5 R0 FMAX\n7  L  Z+20 R0 FMAX"))
    assert 7 in at(result, "core.rapid-into-stock")


def test_a_feed_plunge_and_a_rapid_straight_back_up_is_clean():
    result = check(program("5  L  X+50  Y+50 R0 FMAX\n6  L  Z+2 R0 FMAX\n7  L  Z-5 F200\n8  L  X+60\n9  L  Z+20 R0 FMAX"))
    assert not at(result, "core.rapid-into-stock")


def test_circle_about_cc_and_polar_arc_end_where_the_geometry_says():
    recorded = trace(program("5  L  X+60  Y+50 R0 FMAX\n6  CC  X+50  Y+50\n7  C  X+40  Y+50 DR+ F300\n8  CP  IPA+90 DR+\n9  LP  PR+5  PA+0"))
    arcs = [segment for segment in recorded.segments if segment.kind == "arc"]
    assert arcs[0].end["X"] == 40.0 and arcs[0].arc.direction == "ccw" and arcs[0].arc.start_radius == arcs[0].arc.end_radius == 10.0
    assert abs(arcs[1].end["X"] - 50.0) < 1e-9 and abs(arcs[1].end["Y"] - 40.0) < 1e-9
    assert recorded.segments[-1].end["X"] == 55.0


def test_section_repeat_runs_the_section_rep_plus_one_times_and_subprograms_return():
    body = drilling() + "6  LBL 5\n7  CALL LBL 1\n8  CALL LBL 5 REP 2\n9  L  Z+100 R0 FMAX M30\n10 LBL 1\n11 L  X+10  Y+10 R0 FMAX M99\n12 LBL 0"
    recorded = trace(program(body))
    assert len(recorded.holes) == 3
    assert not [fault for fault in recorded.faults if fault.rule.startswith("core.")]


def test_fn_conditional_jump_forks_on_a_free_parameter():
    body = "5  FN 11: IF +Q1 GT +10 GOTO LBL \"DEEP\"\n6  L  X+10  Y+10 R0 FMAX\n7  L  Z-5 R0 FMAX\n8  LBL \"DEEP\""
    result = check(program(body))
    assert 8 in at(result, "core.rapid-into-stock")


# --------------------------------------------------------------------------- cycles


def test_cycle_200_levels_follow_the_surface_and_clearances():
    recorded = trace(program("5  L  X+10  Y+10 R0 FMAX\n" + drilling(second="+20") + "7  CYCL CALL"))
    hole = recorded.holes[0]
    assert (hole.r_point, hole.bottom, hole.initial) == (2.0, -15.0, 20.0)
    kinds = [(segment.kind, segment.end["Z"]) for segment in recorded.segments if segment.cycle]
    assert kinds == [("rapid", 2.0), ("feed", -15.0), ("rapid", 2.0), ("rapid", 20.0)]


def test_values_are_frozen_when_the_cycle_is_defined():
    body = "5  Q1 = -15\n" + drilling(depth="+Q1") + "7  Q1 = -30\n8  L  X+10  Y+10 R0 FMAX M99"
    recorded = trace(program(body))
    assert recorded.holes[0].bottom == -15.0


def test_positive_depth_rapids_below_the_surface_and_is_reported():
    result = check(program(drilling(depth="+15") + "7  L  X+10  Y+10 R0 FMAX M99"))
    assert at(result, "heidenhain.positive-depth")
    assert at(result, "core.rapid-into-stock")


def test_depth_zero_skips_the_cycle():
    recorded = trace(program(drilling(depth="+0") + "7  L  X+10  Y+10 R0 FMAX M99"))
    assert not [segment for segment in recorded.segments if segment.cycle]
    assert at(check(program(drilling(depth="+0") + "7  L  X+10  Y+10 R0 FMAX M99")), "heidenhain.zero-depth")


def test_surface_below_the_blank_top_rapids_into_it():
    result = check(program(drilling(surface="-10") + "7  L  X+10  Y+10 R0 FMAX M99"))
    assert at(result, "core.rapid-into-stock") and at(result, "core.clearance-below-stock")


def test_call_without_a_cycle_and_with_rl_are_errors():
    assert at(check(program("5  L  X+10  Y+10 R0 FMAX\n6  CYCL CALL")), "heidenhain.call-without-cycle") == [7]
    result = check(program(drilling() + "7  L  X+10  Y+10 RL F300 M99"))
    assert at(result, "heidenhain.cycle-with-compensation")


def test_m89_drills_after_every_positioning_block_until_m99():
    body = drilling() + "7  L  X+10  Y+10 R0 FMAX M89\n8  L  X+20 R0 FMAX\n9  L  X+30 R0 FMAX M99\n10 L  X+40 R0 FMAX"
    assert len(trace(program(body)).holes) == 3


def test_pattern_def_and_cycl_call_pat_make_a_hole_at_every_point():
    body = "5  PATTERN DEF ~\n   ROW1( X+10 Y+10 D+20 NUM4 ROT+0 Z+0 ) ~\n   POS1( X+50 Y+80 Z+0 )\n" + drilling() + "7  CYCL CALL PAT FMAX"
    recorded = trace(program(body))
    assert [(hole.position["X"], hole.position["Y"]) for hole in recorded.holes] == [(10.0, 10.0), (30.0, 10.0), (50.0, 10.0), (70.0, 10.0), (50.0, 80.0)]


def test_cycle_221_runs_the_last_machining_cycle_on_its_grid():
    grid = ("CYCL DEF 221 CARTESIAN PATTERN ~\n    Q225=+10 ;STARTNG PNT 1ST AXIS ~\n    Q226=+10 ;STARTNG PNT 2ND AXIS ~\n"
            "    Q237=+20 ;SPACING IN 1ST AXIS ~\n    Q238=+30 ;SPACING IN 2ND AXIS ~\n    Q242=+3 ;NUMBER OF COLUMNS ~\n    Q243=+2 ;NUMBER OF LINES\n")
    assert len(trace(program(drilling() + grid)).holes) == 6


def test_usable_length_and_tool_size_come_from_the_tool_table():
    result = check(program(drilling(depth="-30") + "7  L  X+10  Y+10 R0 FMAX M99"), "[tools.1]\nradius = 4\nusable_length = 25")
    assert at(result, "heidenhain.usable-length")
    pocket = ("CYCL DEF 252 CIRCULAR POCKET ~\n    Q215=+0 ;MACHINING OPERATION ~\n    Q223=+8 ;CIRCLE DIAMETER ~\n    Q201=-5 ;DEPTH ~\n"
              "    Q202=+2 ;PLUNGING DEPTH ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n    Q203=+0 ;SURFACE COORDINATE ~\n    Q204=+20 ;2ND SET-UP CLEARANCE\n")
    result = check(program(pocket + "7  L  X+50  Y+50 R0 FMAX M99"), "[tools.1]\nradius = 5")
    message = [d.message for d in result.diagnostics if d.rule == "heidenhain.tool-too-large"]
    assert message and "largest tool radius that fits is 4" in message[0]


TOOL_T = """BEGIN TOOL.T MM
T    NAME                             L           R           R2          DL          DR          DR2         LCUTS   ANGLE   LU      PITCH
0    NULLWERKZEUG                     +0          +0          +0          +0          +0          +0          0       0       0       0
4    DRILL_D8                         +95.5       +4          +0          +0          +0          +0          30      0       28      0
9    TAP_M10                          +80         +5          +0          +0          +0          +0          20      0       40      1.25
[END]
"""


def test_tool_t_beside_the_program_is_a_tool_source_by_number_and_by_name(tmp_path):
    from ncverify import check_file

    (tmp_path / "TOOL.T").write_text(TOOL_T)
    part = tmp_path / "part.h"
    body = drilling(depth="-35") + "7  L  X+10  Y+10 R0 FMAX M99"
    part.write_text(program(body).replace("TOOL CALL 1 Z", 'TOOL CALL "DRILL_D8" Z'))
    result = check_file(part, Settings())
    assert [d.message for d in result.diagnostics if d.rule == "heidenhain.usable-length" and d.status is Status.VIOLATED]
    assert not [d for d in result.diagnostics if d.rule == "core.tool-not-in-table"]
    tap = ("CYCL DEF 207 RIGID TAPPING ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n    Q201=-18 ;DEPTH OF THREAD ~\n    Q239=+1.5 ;THREAD PITCH ~\n"
           "    Q203=+0 ;SURFACE COORDINATE ~\n    Q204=+50 ;2ND SET-UP CLEARANCE\n")
    part.write_text(program(tap + "7  L  X+10  Y+10 R0 FMAX M99").replace("TOOL CALL 1 Z", "TOOL CALL 9 Z"))
    result = check_file(part, Settings())
    assert [d for d in result.diagnostics if d.rule == "heidenhain.tap-pitch" and d.status is Status.VIOLATED]


def test_back_boring_goes_below_the_part_and_counterbores_upward():
    bore = ("CYCL DEF 204 BACK BORING ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n    Q249=+5 ;DEPTH OF COUNTERBORE ~\n    Q250=+20 ;MATERIAL THICKNESS ~\n"
            "    Q251=+3.5 ;OFF-CENTER DISTANCE ~\n    Q252=+15 ;TOOL EDGE HEIGHT ~\n    Q253=+750 ;F PRE-POSITIONING ~\n    Q254=+200 ;F COUNTERBORING ~\n"
            "    Q255=+0 ;DWELL TIME ~\n    Q203=+0 ;SURFACE COORDINATE ~\n    Q204=+50 ;2ND SET-UP CLEARANCE ~\n    Q214=+1 ;DISENGAGING DIRECTN ~\n"
            "    Q336=+0 ;ANGLE OF SPINDLE\n")
    recorded = trace(program(bore + "7  L  X+50  Y+50 R0 FMAX M99"))
    levels = [(segment.kind, segment.end["Z"]) for segment in recorded.segments if segment.cycle]
    assert levels == [("rapid", 2.0), ("rapid", -37.0), ("feed", -30.0), ("rapid", -37.0), ("rapid", 50.0)]


def test_rigid_tapping_runs_its_own_spindle():
    tap = ("CYCL DEF 207 RIGID TAPPING ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n    Q201=-18 ;DEPTH OF THREAD ~\n    Q239=+1.5 ;THREAD PITCH ~\n"
           "    Q203=+0 ;SURFACE COORDINATE ~\n    Q204=+50 ;2ND SET-UP CLEARANCE\n")
    result = check(program("5  M5\n" + tap + "7  L  X+10  Y+10 R0 FMAX M99"))
    assert not at(result, "core.spindle-off-cutting") and not at(result, "core.feed-missing")


def test_predef_parameters_take_the_global_def_values():
    defaults = "5  GLOBAL DEF 100 GENERAL ~\n    Q200=+3 ;SET-UP CLEARANCE ~\n    Q204=+30 ;2ND SET-UP CLEARANCE ~\n    Q253=+750 ;F PRE-POSITIONING ~\n    Q208=+999 ;RETRACTION FEED RATE\n"
    recorded = trace(program(defaults + drilling(clearance="PREDEF", second="PREDEF") + "7  L  X+10  Y+10 R0 FMAX M99"))
    assert (recorded.holes[0].r_point, recorded.holes[0].initial) == (3.0, 30.0)
    unresolved = trace(program(drilling(clearance="PREDEF") + "7  L  X+10  Y+10 R0 FMAX M99"))
    assert [fault for fault in unresolved.faults if fault.rule == "core.unsupported-code" and "PREDEF" in fault.message]


def test_cycle_220_levels_replace_the_machining_cycle_and_q301_0_travels_at_set_up_clearance():
    circle = ("CYCL DEF 220 POLAR PATTERN ~\n    Q216=+50 ;CENTER IN 1ST AXIS ~\n    Q217=+50 ;CENTER IN 2ND AXIS ~\n    Q244=+60 ;PITCH CIRCLE DIAMETR ~\n"
              "    Q245=+0 ;STARTING ANGLE ~\n    Q246=+360 ;STOPPING ANGLE ~\n    Q247=+0 ;STEPPING ANGLE ~\n    Q241=+4 ;NR OF REPETITIONS ~\n"
              "    Q200=+1 ;SET-UP CLEARANCE ~\n    Q203=-5 ;SURFACE COORDINATE ~\n    Q204=+40 ;2ND SET-UP CLEARANCE ~\n    Q301=+0 ;MOVE TO CLEARANCE\n")
    recorded = trace(program(drilling() + circle))
    assert [hole.r_point for hole in recorded.holes] == [-4.0] * 4
    assert [hole.initial for hole in recorded.holes] == [-4.0, -4.0, -4.0, 35.0]


def test_tool_t_columns_left_at_zero_are_not_entered(tmp_path):
    from ncverify.lower.heidenhain import read_tool_table

    (tmp_path / "TOOL.T").write_text(TOOL_T)
    tools, names = read_tool_table(tmp_path / "TOOL.T")
    assert tools[9].usable_length == 40.0 and tools[9].pitch == 1.25 and tools[4].pitch is None
    assert tools[0].usable_length is None and names["DRILL_D8"] == 4.0


def test_tool_t_values_that_are_not_finite_are_not_entered(tmp_path):
    from ncverify.lower.heidenhain import read_tool_table

    lines = TOOL_T.splitlines()
    lines[3] = lines[3].replace("+4 ", "inf", 1)  # R of tool 4
    lines[4] = lines[4].replace("40      1.25", "nan     1.25")  # LU of tool 9
    (tmp_path / "TOOL.T").write_text("\n".join(lines[:5] + ["1e999" + lines[4][5:]] + lines[5:]) + "\n")
    tools, _names = read_tool_table(tmp_path / "TOOL.T")
    assert tools[4].radius is None and tools[4].length == 95.5
    assert tools[9].usable_length is None and tools[9].pitch == 1.25
    assert set(tools) == {0, 4, 9}


def test_call_pgm_finds_the_called_file_by_path_name_or_number(tmp_path):
    from ncverify import check_file

    main = program("5  CALL PGM TNC:\\PARTS\\205.H\n6  CALL PGM HOLES", "MAIN")
    (tmp_path / "MAIN.h").write_text(main)
    (tmp_path / "205.H").write_text("0  BEGIN PGM 205 MM\n1  L  X+10  Y+10 R0 FMAX\n2  END PGM 205 MM\n")
    (tmp_path / "HOLES.h").write_text("0  BEGIN PGM HOLES MM\n1  L  X+20  Y+20 R0 FMAX\n2  L  Z-5 R0 FMAX\n3  END PGM HOLES MM\n")
    result = check_file(tmp_path / "MAIN.h", Settings())
    assert not [d for d in result.diagnostics if d.rule in ("core.program-not-found", "heidenhain.program-name-mismatch")]
    assert [d for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.path and d.span.path.endswith("HOLES.h")]


def test_ocm_circle_pocket_needs_room_for_the_inside_corner_factor_and_allowance():
    circle = ("CYCL DEF 1272 OCM CIRCLE ~\n    Q650=+0 ;FIGURE TYPE ~\n    Q223=+20 ;CIRCLE DIAMETER ~\n    Q367=+0 ;POCKET POSITION ~\n"
              "    Q203=+0 ;SURFACE COORDINATE ~\n    Q201=-10 ;DEPTH ~\n    Q368=+0.5 ;ALLOWANCE FOR SIDE ~\n    Q369=+0.2 ;ALLOWANCE FOR FLOOR ~\n"
              "    Q260=+50 ;CLEARANCE HEIGHT ~\n    Q578=+0.2 ;INSIDE CORNER FACTOR\n")
    rough = ("CYCL DEF 272 OCM ROUGHING ~\n    Q215=+0 ;MACHINING OPERATION ~\n    Q202=+5 ;PLUNGING DEPTH ~\n    Q370=+0.4 ;TOOL PATH OVERLAP ~\n"
             "    Q207=+500 ;FEED RATE MILLING ~\n    Q568=+0.6 ;PLUNGING FACTOR ~\n    Q253=+750 ;F PRE-POSITIONING ~\n    Q200=+2 ;SET-UP CLEARANCE\n")
    text = program(circle + rough + "7  L  X+50  Y+50 R0 FMAX M99")
    assert at(check(text, "[tools.1]\nradius = 8"), "heidenhain.tool-too-large")
    assert not at(check(text, "[tools.1]\nradius = 6"), "heidenhain.tool-too-large")
    recorded = trace(text)
    assert [segment.end["Z"] for segment in recorded.segments if segment.cycle] == [2.0, -10.0, 50.0]


def test_face_milling_233_runs_from_q227_down_to_q386_and_leaves_the_plane_position_unknown():
    face = ("CYCL DEF 233 FACE MILLING ~\n    Q215=+0 ;MACHINING OPERATION ~\n    Q389=+2 ;MILLING STRATEGY ~\n    Q350=+1 ;MILLING DIRECTION ~\n"
            "    Q218=+100 ;FIRST SIDE LENGTH ~\n    Q219=+100 ;2ND SIDE LENGTH ~\n    Q227=+2 ;STARTNG PNT 3RD AXIS ~\n    Q386=+0 ;END POINT 3RD AXIS ~\n"
            "    Q369=+0 ;ALLOWANCE FOR FLOOR ~\n    Q202=+1 ;MAX. PLUNGING DEPTH ~\n    Q370=+1 ;TOOL PATH OVERLAP ~\n    Q207=+500 ;FEED RATE MILLING ~\n"
            "    Q385=+500 ;FINISHING FEED RATE ~\n    Q253=+750 ;F PRE-POSITIONING ~\n    Q357=+2 ;CLEARANCE TO SIDE ~\n    Q200=+2 ;SET-UP CLEARANCE ~\n"
            "    Q204=+50 ;2ND SET-UP CLEARANCE\n")
    recorded = trace(program(face + "7  L  X+0  Y+0 R0 FMAX M99\n8  L  IX+10 R0 FMAX"))
    assert [segment.end["Z"] for segment in recorded.segments if segment.cycle] == [4.0, 0.0, 4.0, 52.0]
    assert [fault for fault in recorded.faults if fault.rule == "heidenhain.position-after-cycle"]


def test_the_tool_calls_radius_delta_adds_to_the_table_radius_on_the_path_it_is_called_on():
    circle = ("CYCL DEF 1272 OCM CIRCLE ~\n    Q650=+0 ;FIGURE TYPE ~\n    Q223=+20 ;CIRCLE DIAMETER ~\n    Q367=+0 ;POCKET POSITION ~\n"
              "    Q203=+0 ;SURFACE COORDINATE ~\n    Q201=-10 ;DEPTH ~\n    Q368=+0.5 ;ALLOWANCE FOR SIDE ~\n    Q369=+0.2 ;ALLOWANCE FOR FLOOR ~\n"
              "    Q260=+50 ;CLEARANCE HEIGHT ~\n    Q578=+0.2 ;INSIDE CORNER FACTOR\n")
    rough = ("CYCL DEF 272 OCM ROUGHING ~\n    Q215=+0 ;MACHINING OPERATION ~\n    Q202=+5 ;PLUNGING DEPTH ~\n    Q370=+0.4 ;TOOL PATH OVERLAP ~\n"
             "    Q207=+500 ;FEED RATE MILLING ~\n    Q568=+0.6 ;PLUNGING FACTOR ~\n    Q253=+750 ;F PRE-POSITIONING ~\n    Q200=+2 ;SET-UP CLEARANCE\n")
    text = program(circle + rough + "7  L  X+50  Y+50 R0 FMAX M99")
    assert at(check(text.replace("TOOL CALL 1 Z S2000", "TOOL CALL 1 Z S2000 DR+2"), "[tools.1]\nradius = 6"), "heidenhain.tool-too-large")
    branch = "5  FN 9: IF +Q1 EQU +0 GOTO LBL 1\n6  TOOL CALL 1 Z S2000 DR+2\n7  LBL 1\n"
    forked = check(program(branch + circle + rough + "8  L  X+50  Y+50 R0 FMAX M99"), "[tools.1]\nradius = 6")
    assert at(forked, "heidenhain.tool-too-large")  # the path through the second TOOL CALL
    free = check(text.replace("TOOL CALL 1 Z S2000", "TOOL CALL 1 Z S2000 DR+Q1"), "[tools.1]\nradius = 6")
    assert not at(free, "heidenhain.tool-too-large") and at(free, "heidenhain.tool-too-large", Status.UNKNOWN)


def test_f_auto_moves_at_the_feed_of_the_tool_call_in_force():
    limit = "[machine]\nmax_feed = 400"
    moves = "5  L  X+10 Y+10 R0 FMAX\n6  L  X+20 F AUTO"
    fast = program(moves).replace("TOOL CALL 1 Z S2000", "TOOL CALL 1 Z S2000 F500")
    assert at(check(fast, limit), "core.feed-over-limit") == [7]
    assert not at(check(fast.replace("F500", "F300"), limit), "core.feed-over-limit")
    unknown = check(program(moves), limit)  # no feed in the tool call: unknown, never one a witness could choose
    assert not at(unknown, "core.feed-over-limit") and at(unknown, "core.feed-over-limit", Status.UNKNOWN) == [7]


def test_a_broken_constraint_is_reported_at_each_definition_however_often_its_words_repeat():
    """Holes with the same words and levels share their constraints' outcomes: a second
    definition with the same words is still reported at its own line, and one between them
    that keeps the constraint is not."""
    body = (drilling(depth="+0") + "7  L  X+10  Y+10 R0 FMAX M99\n8  L  X+20  Y+10 R0 FMAX M99\n" + drilling(depth="-15")
            + "9  L  X+30  Y+10 R0 FMAX M99\n" + drilling(depth="+0") + "10  L  X+40  Y+10 R0 FMAX M99\n")
    text = program(body)
    zero_depth_lines = [number for number, line in enumerate(text.splitlines(), 1) if "Q201=+0" in line]
    assert len(zero_depth_lines) == 2
    assert sorted(at(check(text), "heidenhain.zero-depth")) == zero_depth_lines


def test_a_program_that_calls_its_tool_by_name_is_a_main_program():
    """Only a program with no TOOL CALL of any kind (and no M2/M30) is run as a called
    macro whose caller started the spindle: one that calls its tool by name is not."""
    named = ('0  BEGIN PGM NAMED MM\n1  BLK FORM 0.1 Z X+0 Y+0 Z-20\n2  BLK FORM 0.2  X+100  Y+100  Z+0\n3  TOOL CALL "MILL_D10" Z\n'
             "4  L  X+10  Y+10 R0 FMAX\n5  L  Z+5 R0 FMAX\n6  L  Z-2 R0 F200\n7  L  X+50 R0\n8  L  Z+50 R0 FMAX\n9  END PGM NAMED MM\n")
    macro = named.replace('3  TOOL CALL "MILL_D10" Z\n', "")
    assert at(check(named), "core.spindle-off-cutting", Status.UNKNOWN) == [7]  # its 7th line: the first feed move
    assert "core.spindle-off-cutting" not in rules(check(macro))
