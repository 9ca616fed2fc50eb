"""Fagor 8060/8065: the reader, the cycles' planes and motion, multiple machining, flow
statements, detection, and the manual's example programs (read from ../shared/manuals when
it is there)."""
from __future__ import annotations

import re
import textwrap
from pathlib import Path

import pytest
from hypothesis import given, settings, strategies

from fagor_trace import trace
from ncverify import Settings, check_text
from ncverify.detect import detect
from ncverify.interpret.fagor_cycles import skip_range
from ncverify.read.fagor import read_fagor_line

ROOT = Path(__file__).resolve().parents[1]
MANUAL = ROOT.parent / "shared" / "manuals" / "000_a3a484fdafe81829.txt"
REALWORLD = ROOT.parent / "shared" / "corpus-realworld"

DRILLING = """
T1 D1 M6
S1000 M3 M8
G0 G90 X0 Y0 Z25 F200
N10 G99 X15 Y15 G81 Z2 I-20
N20 X85
N30 Y85
N40 G98 X15
G80
M30
"""


def check(program: str, **options):
    return check_text(textwrap.dedent(program).lstrip("\n"), "t.pim", Settings(dialect="fagor", **options))


def reported(result) -> set[str]:
    return {d.rule for d in result.diagnostics if d.status.value == "violated"}


# --------------------------------------------------------------------------- reader


def test_reader_splits_label_words_and_comment():
    line = read_fagor_line("N10 G99 X15 Y15 G81 Z2 I-20 ; first hole", 1)
    assert line.label == 10.0 and line.problem is None
    assert [(word.letter, word.value) for word in line.words] == [("G", 99.0), ("X", 15.0), ("Y", 15.0), ("G", 81.0), ("Z", 2.0), ("I", -20.0)]
    assert line.comments[0][0] == "first hole"


def test_reader_takes_parameters_variables_and_expressions():
    line = read_fagor_line("P3=P2*2+SIN[30] V.C.I=18 G1 X[P1+2] YP4 Z-(P5/2) NR3", 1)
    assert line.problem is None
    assert [assignment.target.name for assignment in line.assignments] == ["P3", "V.C.I"]
    assert [word.letter for word in line.words] == ["G", "X", "Y", "Z"]
    assert line.repeat is not None


def test_reader_reads_statements_with_their_arguments():
    for_loop = read_fagor_line("$FOR P0=1,2,1", 1).statement
    assert for_loop.keyword == "FOR" and len(for_loop.args) == 4
    condition = read_fagor_line("$IF P1 == 2 AND P2 <> 3", 1).statement
    assert condition.keyword == "IF" and condition.flow
    call = read_fagor_line('#PCALL "SUB 1" A20 B[P1]', 1).statement
    assert call.args[0] == "SUB 1" and [letter for letter, _ in call.args[1:]] == ["A", "B"]
    assert read_fagor_line("$GOTO N20", 1).statement.args == [20.0]


def test_reader_keeps_skip_range_text_as_a_number_with_three_fraction_digits():
    assert skip_range(10.13) == (10, 130)
    assert skip_range(10.013) == (10, 13)
    assert skip_range(7.0) == (7, 7)


def test_reader_reports_bad_text_with_a_column():
    line = read_fagor_line("G1 X10 Y@5", 3)
    assert line.problem is not None and line.problem.start == 8


@settings(max_examples=300, deadline=None)
@given(strategies.text(alphabet=strategies.sampled_from(list("GXYZIJKNPVRC$#.=+-*/[]();\"0123456789 ABEFLMOQSTW%")), max_size=40))
def test_reader_never_raises(text):
    read_fagor_line(text, 1)


@settings(max_examples=100, deadline=None)
@given(strategies.text(max_size=60))
def test_the_whole_pipeline_never_raises_on_garbage(text):
    check(text + "\nM30\n")


# --------------------------------------------------------------------------- hole cycles


def test_g81_reference_plane_is_z_and_depth_is_i_with_g98_g99_retract():
    run = trace(DRILLING)
    assert run.points == [(15.0, 15.0, 2.0, -20.0), (85.0, 15.0, 2.0, -20.0), (85.0, 85.0, 2.0, -20.0), (15.0, 85.0, 2.0, -20.0)]
    last = [segment for segment in run.segments if segment.cycle][-1]
    assert last.role == "retract" and last.end["Z"] == 25.0  # G98: back to the start plane


def test_incremental_z_is_from_the_start_plane_and_i_from_the_reference_plane():
    run = trace("""
        G0 G90 X0 Y0 Z25 F200
        N10 G99 G91 X15 Y15 G81 Z-23 I-22
        N20 X70
        G90 G80
        M30
    """)
    assert run.points == [(15.0, 15.0, 2.0, -20.0), (85.0, 15.0, 2.0, -20.0)]


def test_g83_bottom_is_reference_plus_pecks_times_peck():
    run = trace("G0 G90 X0 Y0 Z25 F200\nG99 G83 Z2 I-5 J4 B3\nG80\nM30\n")
    assert run.points == [(0.0, 0.0, 2.0, -18.0)]


def test_pocket_rapids_to_one_millimetre_above_the_surface():
    run = trace("G0 G90 X60 Y35 Z25 F800\nG99 G87 Z2 I-20 D2 A15 J40 K20 M1 Q10 B5\nG80\nM30\n")
    assert run.points == [(60.0, 35.0, 1.0, -20.0)]  # surface = Z2 - D2 = 0


def test_nr_repeats_the_move_and_the_hole_and_nr0_only_moves():
    run = trace("""
        G0 G90 X0 Y0 Z25 F200
        G99 G81 Z2 I-20
        G90 G01 X85
        G91 Y85 NR3
        G90 G01 X0 NR0
        G80
        M30
    """)
    assert [(x, y) for x, y, _, _ in run.points] == [(0.0, 0.0), (85.0, 0.0), (85.0, 85.0), (85.0, 170.0), (85.0, 255.0)]
    assert run.segments[-1].end["X"] == 0.0


def test_a_new_cycle_replaces_the_old_one_after_the_block_moves():
    run = trace("""
        G00 G90 X0 Y0 Z25
        N10 G81 Z2 I-20
        N15 X160 Y50 F3000
        N30 G1 X200 Y200 G83 Z2 I-2 J5
        N50 X220
        N60 G80 M30
    """)
    assert [hole.cycle for hole in run.holes] == ["fagor.G81", "fagor.G81", "fagor.G83", "fagor.G83"]
    assert run.points[2] == (200.0, 200.0, 2.0, -8.0)


def test_g80_and_a_plane_change_end_the_cycle():
    run = trace("G0 G90 X0 Y0 Z25 F200\nG81 Z2 I-20\nG18\nG17 G0 X50\nG81 Z2 I-5\nG80\nX90\nM30\n")
    assert [x for x, _, _, _ in run.points] == [0.0, 50.0]


def test_vc_values_change_the_active_cycle_as_absolute_coordinates():
    run = trace("""
        G00 G90 X0 Y0 Z60 F1000
        G99 G91 X15 Y25 G81 Z-28 I-14
        V.C.I=18
        X10
        G90 G80
        M30
    """)
    assert run.points == [(15.0, 25.0, 32.0, 18.0), (25.0, 25.0, 32.0, 18.0)]


def test_tool_axis_word_in_the_cycle_block_is_the_reference_plane_in_g19():
    run = trace("G19\nG0 G90 X25 Y0 Z0 F1000 S1000 M3\n#TOOL AX [X+]\nG81 X2 I-8 K1\nG80\nM30\n")
    assert run.holes[0].drill_axis == "X" and (run.holes[0].r_point, run.holes[0].bottom) == (2.0, -8.0)


def test_cycles_along_a_negative_tool_axis_drill_toward_plus():
    run = trace("G19\nG1 X-25 Y0 Z0 F1000 S1000 M3\n#TOOL AX [X-]\nG81 X-2 I8 K1\nM30\n")
    [hole] = run.holes
    assert (hole.drill_axis, hole.up, hole.r_point, hole.bottom) == ("X", -1.0, -2.0, 8.0)
    assert [(segment.role, segment.end["X"]) for segment in run.segments if segment.cycle] == [("approach", -2.0), ("infeed", 8.0), ("out-of-hole", -2.0), ("retract", -25.0)]


def test_a_tool_axis_in_the_plane_is_not_modelled():
    run = trace("G17\nG1 X-25 Y0 Z0 F1000 S1000 M3\n#TOOL AX [X+]\nG81 X-2 I8 K1\nM30\n")
    assert not run.holes and "core.unsupported-code" in run.rules()


def test_lathe_software_reads_g81_as_a_turning_cycle_until_millcy_on():
    assert not trace("G0 X0 Y0 Z25 S500 M3\nG81 Z2 I-20\nG80\nM30\n", machine="lathe").holes
    assert len(trace("#MILLCY ON\nG0 X0 Y0 Z25 S500 M3\nG81 Z2 I-20\nG80\n#MILLCY OFF\nM30\n", machine="lathe").holes) == 1
    assert not trace("#LATHECY ON\nG0 X0 Y0 Z25 S500 M3\nG81 Z2 I-20\nG80\n#LATHECY OFF\nM30\n").holes


def test_letters_of_a_cycle_block_are_its_parameters_not_m_d_s_t_functions():
    run = trace("T7 D7 M6\nS900 M3\nG0 G90 X60 Y35 Z25 F800\nG87 Z2 I-20 D2 J40 K20 M1 Q10 B5\nG80\nM30\n")
    assert run.holes[0].params["M"] == 1.0 and run.holes[0].params["D"] == 2.0
    assert not any(fault.rule == "core.syntax" for fault in run.faults + run.notes)


# --------------------------------------------------------------------------- multiple machining


PATTERNS = [
    ("G160 A30 X1200 I100 P2.003 Q6 R12", 9),
    ("G160 A30 I100 K13 P2.003 Q6 R12", 9),
    ("G161 A30 X700 I100 Y180 J60 P2.005 Q9.011", 13),
    ("G162 X700 K8 J60 D4 P2.005 Q9.011 R15.019", 20),
    ("G163 X200 Y200 K12 C1 F200 P2.004 Q8", 8),
    ("G164 X200 Y200 B225 I45 C3 F200 P2", 5),
    ("G165 X-280 Y-40 A60 C1 F200", 2),
]


@pytest.mark.parametrize("pattern, holes", PATTERNS)
def test_pattern_machines_its_points_less_the_skipped_ones(pattern, holes):
    run = trace(f"G0 G90 X200 Y300 Z50 F100 S500\nG98 G81 Z-8 I-22\n{pattern}\nG80\nM30\n")
    assert len(run.holes) == holes and not run.faults


def test_circle_pattern_points_lie_on_the_circle():
    run = trace("G0 G90 X100 Y0 Z50 F100 S500\nG98 G81 Z2 I-5\nG163 X-100 Y0 K4\nG80\nM30\n")
    assert [(round(x, 6), round(y, 6)) for x, y, _, _ in run.points] == [(100.0, 0.0), (0.0, 100.0), (-100.0, 0.0), (0.0, -100.0)]


@pytest.mark.parametrize("pattern, rule", [
    ("G160 X1200 I100 K13", "fagor.pattern-parameters"),
    ("G160 X1250 I100", "fagor.pattern-parameters"),
    ("G163 X200 Y0 I35", "fagor.pattern-parameters"),
    ("G164 X200 Y0 B100 I45", "fagor.pattern-parameters"),
    ("G165 X200 Y0 A60 I50", "fagor.pattern-parameters"),
    ("G160 X1200 I100 P5.006 Q20.022 R12.015", "fagor.pattern-skip-list"),
    ("G160 X1200 I100 Q10.13", "fagor.pattern-skip-list"),
])
def test_pattern_alarms(pattern, rule):
    result = check(f"G0 G90 X200 Y300 Z50 F100 S500 M3\nG98 G81 Z-8 I-22\n{pattern}\nG80\nM30\n")
    assert rule in reported(result)


def test_valid_skip_list_is_accepted():
    result = check("G0 G90 X200 Y300 Z50 F100 S500 M3\nG98 G81 Z-8 I-22\nG160 X2400 I100 P5.006 Q12.015 R20.022\nG80\nM30\n")
    assert "fagor.pattern-skip-list" not in reported(result)


# --------------------------------------------------------------------------- flow statements


def x_of_last_move(program: str) -> float:
    run = trace(program)
    return [segment for segment in run.segments if segment.role == "programmed"][-1].end["X"]


@pytest.mark.parametrize("value, x", [(1, 10.0), (2, 20.0), (3, 30.0)])
def test_if_elseif_else_take_one_branch(value, x):
    assert x_of_last_move(f"""
        P1={value}
        G0 X0 Y0 Z10
        $IF P1==1
          G0 X10
        $ELSEIF P1==2
          G0 X20
        $ELSE
          G0 X30
        $ENDIF
        M30
    """) == x


def test_while_for_and_do_loops_run_their_counts():
    assert x_of_last_move("G0 X0 Y0 Z10\nP1=0\n$WHILE P1<4\nP1=P1+1\nG91 G0 X1\n$ENDWHILE\nG90\nM30\n") == 4.0
    assert x_of_last_move("G0 X0 Y0 Z10\n$FOR P2=1,5,2\nG91 G0 X1\n$ENDFOR\nG90\nM30\n") == 3.0
    assert x_of_last_move("G0 X0 Y0 Z10\n$FOR P2=3,1,-1\nG91 G0 X1\n$ENDFOR\nG90\nM30\n") == 3.0
    assert x_of_last_move("G0 X0 Y0 Z10\nP1=0\n$DO\nP1=P1+1\nG91 G0 X1\n$ENDDO P1<2\nG90\nM30\n") == 2.0


def test_break_leaves_the_loop_and_continue_skips_the_rest_of_the_pass():
    assert x_of_last_move("G0 X0 Y0 Z10\n$FOR P1=1,10,1\n$IF P1==3\n$BREAK\n$ENDIF\nG91 G0 X1\n$ENDFOR\nG90\nM30\n") == 2.0
    assert x_of_last_move("G0 X0 Y0 Z10\n$FOR P1=1,4,1\n$IF P1==2\n$CONTINUE\n$ENDIF\nG91 G0 X1\n$ENDFOR\nG90\nM30\n") == 3.0


@pytest.mark.parametrize("value, x", [(1, 11.0), (2, 2.0), (7, 99.0)])
def test_switch_runs_the_matching_case_until_break(value, x):
    assert x_of_last_move(f"""
        G0 X0 Y0 Z10
        $SWITCH {value}
        $CASE 1
          G0 X11
          $BREAK
        $CASE 2
          G0 X2
          $BREAK
        $DEFAULT
          G0 X99
        $ENDSWITCH
        M30
    """) == x


def test_goto_rpt_and_local_subroutine_calls():
    assert x_of_last_move("G0 X0 Y0 Z10\n$GOTO N20\nG0 X5\nN20 G0 X7\nM30\n") == 7.0
    run = trace("G0 X0 Y0 Z10\nN10 G91 G0 X1\nN20 G0 Y1\n(RPT N10, N20) N3\nG90\nM30\n")
    assert [segment.end["X"] for segment in run.segments if segment.role == "programmed"][-1] == 4.0
    called = trace('%L MOVE\nG0 X P0\n#RET\nG0 X0 Y0 Z10\n#PCALL MOVE A42\nM30\n')
    assert [segment.end["X"] for segment in called.segments][-1] == 42.0


def test_unmatched_if_reports_the_missing_partner():
    result = check("P1=0\n$IF P1==1\nG0 X5\nM30\n")
    assert "core.label-not-found" in reported(result)


# --------------------------------------------------------------------------- detection


def test_fagor_programs_detect_as_fagor():
    for path in sorted((ROOT / "corpus" / "fagor").glob("*.pim")):
        assert detect(path.read_text()).dialect == "fagor", path.name
    assert detect(textwrap.dedent(DRILLING)).dialect == "fagor"


def test_iso_programs_still_detect_as_iso():
    for path in sorted((ROOT / "corpus" / "iso").glob("*.nc")):
        assert detect(path.read_text(errors="replace")).dialect == "iso", path.name


@pytest.mark.skipif(not (REALWORLD / "fanuc").is_dir(), reason="the real-world corpus is not beside the repository")
def test_real_world_fanuc_programs_still_detect_as_iso():
    for path in sorted(p for p in (REALWORLD / "fanuc").rglob("*") if p.is_file()):
        raw = path.read_bytes()[:65536]
        unclaimed = "fadal" in path.name or "millmaster" in path.name  # ISO lookalikes ncverify does not read
        assert detect(raw.decode("latin-1"), raw).dialect == ("unclaimed" if unclaimed else "iso"), path.name


# --------------------------------------------------------------------------- the manual's examples

# (first line, last line): the example programs the reference lists (section 13)
EXAMPLES = [(613, 624), (674, 727), (745, 777), (788, 845), (888, 908), (997, 1017), (1063, 1087), (1144, 1165), (1202, 1222),
            (1312, 1330), (1412, 1456), (1531, 1571), (2065, 2078), (2145, 2158), (2225, 2238), (2302, 2314), (2380, 2392), (2437, 2449)]


def _manual_programs(first: int, last: int) -> list[str]:
    """The NC lines of the printed examples between two lines, one program per M30: ASCII
    lines that start like a block (the annotation column is Chinese; schematic lines with
    '···' are dropped)."""
    lines = MANUAL.read_text(encoding="utf-8").splitlines()[first - 1 : last]
    programs, current = [], []
    for line in lines:
        if re.match(r"[A-Z#$%]", line) and line.isascii():
            current.append(line.rstrip())
            if re.search(r"\bM30\b", line):
                programs.append("\n".join(current) + "\n")
                current = []
    if current:
        programs.append("\n".join(current) + "\n")
    return programs


@pytest.mark.skipif(not MANUAL.is_file(), reason="the Fagor cycles manual is not beside the repository")
@pytest.mark.parametrize("first, last", EXAMPLES, ids=[f"L{first}-{last}" for first, last in EXAMPLES])
def test_manual_example_reads_and_runs_without_syntax_findings(first, last):
    programs = _manual_programs(first, last)
    assert programs
    for program in programs:
        result = check_text(program, f"manual-L{first}.pim", Settings(dialect="fagor"))
        assert not [d for d in result.diagnostics if d.rule in ("core.syntax", "core.unknown-code", "fagor.pattern-parameters", "fagor.pattern-skip-list")], program


def _findings(first: int, last: int, program: int) -> list:
    return check_text(_manual_programs(first, last)[program], "manual.pim", Settings(dialect="fagor")).diagnostics


@pytest.mark.skipif(not MANUAL.is_file(), reason="the Fagor cycles manual is not beside the repository")
def test_manual_defects_are_reported():
    # L1453: the incremental G87 floor lands 23 mm deeper than its absolute twin's
    assert "fagor.pocket-incremental-depth" in {d.rule for d in _findings(1412, 1456, -1)}
    assert "fagor.pocket-incremental-depth" not in {d.rule for d in _findings(1412, 1456, -2)}
    # L1568: the incremental circular pocket is printed as G87, without K
    missing = [d for d in _findings(1531, 1571, -1) if d.rule == "core.cycle-missing-parameter"]
    assert missing and "K" in missing[0].message
    # L760-772: with [Y+] the printed values drill from the wrong side
    assert "core.cycle-depth-sign" in {d.rule for d in _findings(745, 777, 0) if d.status.value == "violated"}


# Complete example programs the manual prints as correct, with the findings that are true of
# them: the V.C examples program no spindle speed before the cycle starts the spindle.
CORRECT_EXAMPLES = [((788, 845), {"fagor.cycle-starts-spindle"}), ((888, 908), set()), ((997, 1017), set()), ((1063, 1087), set()),
                    ((1144, 1165), set()), ((1202, 1222), set()), ((1312, 1330), set()), ((1441, 1449), set()), ((1556, 1564), set())]


@pytest.mark.skipif(not MANUAL.is_file(), reason="the Fagor cycles manual is not beside the repository")
@pytest.mark.parametrize("lines, true_findings", CORRECT_EXAMPLES, ids=[f"L{first}-{last}" for (first, last), _ in CORRECT_EXAMPLES])
def test_manual_correct_examples_give_no_false_alarm(lines, true_findings):
    for program in _manual_programs(*lines):
        assert reported(check_text(program, "manual.pim", Settings(dialect="fagor"))) <= true_findings, program


@pytest.mark.skipif(not MANUAL.is_file(), reason="the Fagor cycles manual is not beside the repository")
def test_manual_axis_sign_examples_drill_along_x_correctly_and_along_y_from_the_wrong_side():
    along_x = {d.rule for d in _findings(747, 757, 0) if d.status.value == "violated"}
    along_y = [d for d in _findings(762, 772, 0) if d.rule == "core.cycle-depth-sign" and d.status.value == "violated"]
    assert not along_x & {"core.cycle-depth-sign", "core.cycle-r-above-initial", "core.cycle-zero-depth"}
    assert [d.span.line for d in along_y] == [4, 8]  # [Y-] with the approach from +Y, and [Y+] from -Y (reference §14)


def test_nr_repeats_an_incremental_move_outside_a_cycle_too():
    assert x_of_last_move("G0 G90 X0 Y0 Z10\nG91 G1 X10 F500 NR4\nG90\nM30\n") == 40.0


@settings(max_examples=300, deadline=None)
@given(strategies.lists(strategies.tuples(strategies.sampled_from("GXYZFIJKR"), strategies.sampled_from(["0", "1", "2", "3", "-1.5", "10", "250.25"])), min_size=1, max_size=6),
       strategies.booleans())
def test_plain_motion_fast_path_reads_like_the_full_reader(words, labelled):
    from ncverify.lower.fagor import FagorFrontend, FagorLowering, fagor_table

    text = ("N10 " if labelled else "") + " ".join(letter + value for letter, value in words)
    frontend = FagorFrontend(FagorLowering(fagor_table()))
    fast = frontend.blocks(text.encode(), 1, None)
    full = frontend.lowering.lower_line(read_fagor_line(text, 1), None)
    assert fast == full


def test_a_letter_twice_in_a_cycle_block_is_reported_not_read_as_a_function():
    result = check("T7 D7 M6\nS900 M3\nG0 G90 X60 Y35 Z25 F800\nG87 Z2 I-20 D2 J40 K20 B5 D1\nG80\nM30\n")
    assert "core.duplicate-address" in {d.rule for d in result.diagnostics}


def test_g4_k_is_a_dwell_in_seconds():
    from ncverify import ir
    from ncverify.lower.fagor import FagorLowering, fagor_table

    [block] = FagorLowering(fagor_table()).lower_line(read_fagor_line("G4 K2.5", 1), None)
    assert [op.seconds for op in block.ops if isinstance(op, ir.Dwell)] == [2.5]


def test_a_pocket_surface_distance_too_large_rapids_into_the_stock():
    program = "; ncverify: stock box X0:200 Y0:100 Z-30:0\nT7 D7 M6\nS900 M3\nG0 G90 X60 Y35 Z25 F800\nG99 G87 Z2 I-20 D{} J40 K20 B5\nG80\nG0 Z50\nM30\n"
    assert "core.rapid-into-stock" in reported(check(program.format(5)))  # surface taken at Z-3: the rapid ends at Z-2
    assert "core.rapid-into-stock" not in reported(check(program.format(2)))


@pytest.mark.parametrize("first, second, x", [(3, 1, 10.0), (3, 5, 20.0), (1, 1, 20.0)])
def test_conditions_combine_with_and_and_parentheses(first, second, x):
    assert x_of_last_move(f"P1={first}\nP2={second}\nG0 X0 Y0 Z10\n$IF (P1>2) AND (P2<3) ; both\nG0 X10\n$ELSE\nG0 X20 (other)\n$ENDIF\nM30\n") == x


def test_a_contour_program_with_a_fagor_instruction_detects_as_fagor():
    assert detect("#HSC ON [CONTERROR 0.01]\nT1 D1 M6\nG0 X0 Y0 Z5\nG1 Z-1 F300\nX50\nY50\nM30\n").dialect == "fagor"


def test_positioning_in_a_cycle_zone_uses_the_interpolation_in_force():
    run = trace("G0 G90 X0 Y0 Z25 F200\nG99 G81 Z2 I-20\nG1 X50\nG0 X90\nG80\nM30\n")
    kinds = [segment.kind for segment in run.segments if segment.role == "between-holes"]
    assert kinds == ["feed", "rapid"]


def test_a_computed_repeat_count_outside_a_cycle_is_not_modelled():
    run = trace("G0 G90 X0 Y0 Z10\nG91 G1 X10 F500 NR[P7]\nG90\nM30\n")
    assert "core.unsupported-code" in run.rules()


def test_the_tool_length_counts_in_the_z_travel():
    project = '[machine]\ntravel = { z = [-400, 0] }\nwork_offsets = { G54 = [0, 0, -300] }\n[tools.1]\nradius = 4\nlength = 150\n'
    from ncverify.project import load_project_text

    program = "T1 D1 M6\nS1000 M3\nG0 G90 X0 Y0 Z{}\nM30\n"
    context = load_project_text(project, Path("ncverify.toml"))
    high = check_text(program.format(200), "t.pim", Settings(dialect="fagor"), context)  # -300 + 200 + 150 = 50: above 0
    low = check_text(program.format(100), "t.pim", Settings(dialect="fagor"), context)
    assert "core.travel-limit" in reported(high) and "core.travel-limit" not in reported(low)


def test_each_path_reads_its_cycle_blocks_with_its_own_plane():
    run = trace("G0 G90 X0 Y0 Z25 S800 M3\n$IF P9==1\nG18\nM30\n$ENDIF\nG81 Z2 I-20\nG80\nM30\n")
    assert [(hole.drill_axis, hole.r_point, hole.bottom) for hole in run.holes] == [("Z", 2.0, -20.0)]


def test_a_cycle_block_in_a_loop_follows_the_tool_axis_of_each_pass():
    run = trace("G0 G90 X0 Y0 Z25 S800 M3\n$FOR P1=1,2,1\n$IF P1==2\n#TOOL AX [Z-]\n$ENDIF\nG81 Z2 I-20\nG80\n$ENDFOR\nM30\n")
    assert [hole.up for hole in run.holes] == [1.0, -1.0]


def test_each_path_keeps_its_own_tool_axis_and_cycle_set():
    run = trace("G0 G90 X0 Y0 Z25 S800 M3\n#TOOL AX [Z-]\n$IF P9==1\n#TOOL AX [X+]\n#LATHECY ON\n$ENDIF\nG81 Z2 I-20\nG80\nM30\n")
    assert [hole.up for hole in run.holes] == [-1.0]  # P9 = 1 turns (no hole), the other path drills along Z-
    assert sorted((state.fagor.tool_axis, state.fagor.lathe_cycles) for state in run.states) == [(("X", "+"), True), (("Z", "-"), False)]


def test_pcall_gives_the_subroutine_its_own_local_parameters():
    run = trace('%L MOVE\nP0=P0+5\nG0 X P0\n#RET\nP0=1\nG0 X0 Y0 Z10\n#PCALL MOVE A42\nG0 Y P0\nM30\n')
    ends = [(segment.end["X"], segment.end["Y"]) for segment in run.segments]
    assert ends[-2:] == [(47.0, 0.0), (47.0, 1.0)]  # the caller's P0 is still 1 after the call
