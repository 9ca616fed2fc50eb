"""Klartext CAM output (plain ``L`` lines) runs as arrays: the reader takes exactly the lines
it can read, and every finding is the same as running the lines one by one."""
from __future__ import annotations

import numpy
import pytest
from hypothesis import HealthCheck, given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_text, ir
from ncverify.diagnostics import Status
from ncverify.lower.heidenhain import KlartextFrontend, KlartextLowering
from ncverify.read.heidenhain_runs import is_plain_line, read_plain_run

_HEAD = ["0 BEGIN PGM RUNS MM", "1 BLK FORM 0.1 Z X+0 Y+0 Z-20", "2 BLK FORM 0.2 X+100 Y+100 Z+0", "3 TOOL CALL 1 Z S3000",
         "4 L Z+50 R0 FMAX M3", "5 L X-10 Y-10 R0 FMAX", "6 L Z-2 F300"]
_TAIL = ["L Z+50 R0 FMAX M5", "M30", "END PGM RUNS MM"]


def cam_lines(count: int, first: int = 10) -> list[str]:
    return [f"{first + index} L X{index * 0.5:+.3f} Y{(index % 7) * 2.5:+.3f} Z{-2 - (index % 3) * 0.1:+.3f}" for index in range(count)]


def program(body: list[str]) -> str:
    return "\n".join([*_HEAD, *body, *_TAIL]) + "\n"


def findings(text: str, per_block_only: bool = False):
    result = check_text(text, "t.h", Settings(dialect="heidenhain", per_block_only=per_block_only))
    return [(d.rule, d.span, d.status.value, d.message) for d in result.diagnostics], result.blocks


def run_of(lines: list[str], line: int = 10):
    text = ("\n".join(lines) + "\n").encode()
    return read_plain_run(text, 0, line)


# ---------------------------------------------------------------------- the reader


def test_the_reader_reads_each_number_as_float_reads_its_text():
    lines = ["7 L X+10.5 Y-3 Z+0.125 R0 F800", "8 L X-0.001 FMAX", "L Y+123456789.123456 Z-7.", "9 L  Z+1 F1500.5",
             "10 L X+2,25 Y-.5 Z.75 F1,5", *cam_lines(20)]
    run = run_of(lines)
    assert run.rows == len(lines) - 1  # the last line is left to the per-block path
    assert numpy.array_equal(run.values[:5], [[10.5, -3.0, 0.125], [-0.001, numpy.nan, numpy.nan],
                                              [numpy.nan, 123456789.123456, -7.0], [numpy.nan, numpy.nan, 1.0], [2.25, -0.5, 0.75]],
                             equal_nan=True)
    assert list(run.kinds[:5]) == [1, 0, 1, 1, 1]  # FMAX is a rapid; L without it a feed move
    assert numpy.array_equal(run.feeds[:5], [800.0, numpy.nan, numpy.nan, 1500.5, 1.5], equal_nan=True)
    assert [int(offset) for offset in run.line_offsets[:2]] == [0, len(lines[0]) + 1]


def test_the_run_ends_before_a_lift_out_of_the_cut():
    lines = [*cam_lines(20), "40 L Z+5 R0 FMAX", *cam_lines(20, 41)]
    assert run_of(lines).rows == 19  # the line before the lift is run block by block


def test_a_short_streak_is_left_to_the_per_block_path():
    assert run_of(cam_lines(16)) is None
    assert run_of(cam_lines(18)).rows == 17


def test_a_line_with_anything_else_ends_the_streak():
    for odd in ["30 L X+1 Y+2 Z-1 M9", "30 L X+Q1 Y+2 Z-1", "30 L X+1 Y+2 Z-1 K5", "30 L IX+1 Y+2", "30 L X+1 Y+2 RL",
                "30 L X,5 Y+2", "30 L X+1, Y+2", "30 L X+1 Y+2 ; comment", "30 L Y+1 X+2", "30 LBL 1", "30 L X+1 Y+2 F AUTO"]:
        assert not is_plain_line(odd.encode()), odd
        assert run_of([*cam_lines(20), odd, *cam_lines(20, 31)]).rows == 19, odd


def test_plain_lines_with_block_numbers_compensation_and_feed_are_plain():
    for plain in ["12 L X+10.5 Y-3 Z+0 R0 F500", "L Z-1", "  12  L  X+1.  FMAX\r", "12 L X+0 Y+0 Z+0 R0 FMAX"]:
        assert is_plain_line(plain.encode()), plain


_ODD_NUMBER = st.sampled_from(["1,", ",5", "1.2.3", "+-1", "1234567890", "1.1234567", "", "+", "Q1", "1e3"])
_GOOD_NUMBER = st.from_regex(r"\A[+-]?([0-9]{1,4}([.,][0-9]{0,3})?|\.[0-9]{1,3})\Z")
_ANY_NUMBER = st.one_of(_GOOD_NUMBER, _GOOD_NUMBER, _GOOD_NUMBER, _ODD_NUMBER)
_AXES = st.lists(st.sampled_from(["X", "Y", "Z"]), min_size=1, max_size=3, unique=True).map(sorted).flatmap(
    lambda letters: st.tuples(*[_ANY_NUMBER.map(lambda number, letter=letter: letter + number) for letter in letters]))
_TAIL_WORDS = st.lists(st.one_of(st.tuples(st.sampled_from(["F", "M"]), _ANY_NUMBER).map("".join),
                                 st.sampled_from(["R0", "RL", "FMAX", "F AUTO", ";note", "R", "X+1"])), max_size=2)


@hypothesis_settings(max_examples=400, deadline=None)
@given(st.sampled_from(["12 ", "", "  7  ", "/3 "]), _AXES, _TAIL_WORDS, st.sampled_from([" ", "  ", "\t"]))
def test_a_line_the_reader_takes_means_what_the_general_lowering_reads(number, axes, tail, gap):
    raw = f"{number}L{gap}" + gap.join([*axes, *tail])
    if not is_plain_line(raw.encode()):
        return
    general = KlartextLowering()._general(raw.encode(), 1, None)
    assert not general.notes, raw
    moves = [op for op in general.ops if isinstance(op, ir.Move)]
    run = run_of([raw] * 20)
    if not moves:  # L Z.. FMAX: a lift, never in a run
        assert run is None, raw
        return
    feeds = [op.value for op in general.ops if isinstance(op, ir.SetFeed)]
    assert [run.values[0, column] for column in range(3) if not numpy.isnan(run.values[0, column])] == list(moves[0].targets.values()), raw
    assert ir.MoveBatch.KINDS[run.kinds[0]] == moves[0].kind and feeds == ([] if numpy.isnan(run.feeds[0]) else [run.feeds[0]]), raw


# ---------------------------------------------------------------------- the interpreter


@pytest.fixture
def runs_taken(monkeypatch) -> list:
    """The rows of every run the interpreter asks the reader for (0: none read)."""
    taken = []

    def recording(self, buffer, offset, line, limit=1 << 20):
        run = read_plain_run(buffer, offset, line, limit)
        taken.append(run.rows if run is not None else 0)
        return run

    monkeypatch.setattr(KlartextFrontend, "plain_run", recording)
    return taken


def test_a_long_streak_is_run_as_a_batch(runs_taken):
    text = program(cam_lines(500))
    assert findings(text) == findings(text, per_block_only=True)
    assert sum(runs_taken) > 450


def test_a_line_that_leaves_the_streak_is_read_by_the_general_lowering():
    spindle_stopped = program([*cam_lines(40), "50 L X+20 Y+5 Z-2 M5", *cam_lines(40, 51)])
    batched, _blocks = findings(spindle_stopped)
    assert ("core.spindle-off-cutting", Status.VIOLATED.value) in {(rule, status) for rule, _span, status, _message in batched}
    for odd in ["50 L X+20 Y+5 Z-2 K5", "50 L X+Q7 Y+5 Z-2", "50 L X+20 Y+5 Z-2 M5"]:
        text = program([*cam_lines(40), odd, *cam_lines(40, 51)])
        assert findings(text) == findings(text, per_block_only=True), odd
    unknown_word, _blocks = findings(program([*cam_lines(40), "50 L X+20 Y+5 Z-2 K5", *cam_lines(40, 51)]))
    assert any(rule == "core.syntax" and span.line == len(_HEAD) + 41 for rule, span, _status, _message in unknown_word)


def test_a_cut_into_the_blank_at_rapid_inside_a_streak_is_found_at_its_line():
    body = cam_lines(60)
    body[30] = "40 L X+30 Y+50 FMAX"  # at Z-2, inside the blank
    batched, _blocks = findings(program(body))
    assert [span.line for rule, span, status, _message in batched if rule == "core.rapid-into-stock" and status == "violated"] == [len(_HEAD) + 31]
    assert batched == findings(program(body), per_block_only=True)[0]


def test_a_run_after_a_datum_shift_is_checked_where_the_shift_puts_it(runs_taken):
    above = [line.replace("Z-2", "Z+3") for line in cam_lines(60)]  # 1 mm above the blank without the shift
    above[40] = "50 L X+30 Y+50 FMAX"
    shifted, _blocks = findings(program(["7 TRANS DATUM AXIS Z-5", "8 L X+0 Y+0 Z+3 F300", *above]))
    assert sum(runs_taken) > 50
    assert [span.line for rule, span, status, _message in shifted if rule == "core.rapid-into-stock" and status == "violated"] == [len(_HEAD) + 43]
    assert shifted == findings(program(["7 TRANS DATUM AXIS Z-5", "8 L X+0 Y+0 Z+3 F300", *above]), per_block_only=True)[0]
    unshifted, _blocks = findings(program(["8 L X+0 Y+0 Z+3 F300", *above]))
    assert not [rule for rule, _span, status, _message in unshifted if rule == "core.rapid-into-stock" and status == "violated"]


# ---------------------------------------------------------------------- batch == block by block

_NUMBER = st.one_of(st.floats(-150, 150, allow_nan=False).map(lambda value: f"{value:+.3f}"), st.integers(-200, 200).map(lambda value: f"{value:+d}"),
                    st.sampled_from(["+1,5", "-.5", ".25", "7.", "-0,125"]))
_PLAIN = st.tuples(
    st.lists(st.sampled_from("XYZ"), min_size=1, max_size=3, unique=True).map(sorted).flatmap(
        lambda axes: st.tuples(*[_NUMBER.map(lambda number, axis=axis: axis + number) for axis in axes])),
    st.sampled_from(["", " R0"]),
    st.sampled_from([""] * 12 + [" F500", " F1200.5", " FMAX"]),
).map(lambda parts: "L " + " ".join(parts[0]) + parts[1] + parts[2])
_OTHER = st.sampled_from([
    "L X+10 Y+10 RL F300", "L X+60 Y+10 RR", "L X+5 Y+5 R0", "L IX+5 IY-2", "L Z+20 R0 FMAX", "L X+0 Y+0 Z+10 FMAX M9",
    "CC X+50 Y+50", "C X+50 Y+10 DR+", "CR X+30 Y+30 R+20 DR-", "; a comment", "* - ROUGHING", "LBL 5", "LBL 0", "CALL LBL 5 REP 1", "Q1 = 12",
    "L X+Q1 Y+4", "CYCL DEF 200 DRILLING Q200=+2 Q201=-5 Q206=+150 Q202=+5 Q210=+0 Q203=+0 Q204=+50 Q211=+0",
    "L X+20 Y+20 R0 FMAX M99", "L X+30 Y+30 FMAX M89", "CYCL CALL", "M5", "M3", "TOOL CALL 2 Z S4000", "L Z-3 F100",
    "TRANS DATUM AXIS X+10 Y+5", "TRANS DATUM RESET", "CYCL DEF 10.0 ROTATION", "CYCL DEF 10.1 ROT+30",
    "CYCL DEF 7.0 DATUM SHIFT", "CYCL DEF 7.1 Z-3", "CYCL DEF 11.0 SCALING", "CYCL DEF 11.1 SCL 0.5",
])
_STREAK = st.one_of(st.lists(_PLAIN, max_size=10), st.lists(_PLAIN, min_size=25, max_size=80))
_PART = st.one_of(_STREAK, _OTHER.map(lambda line: [line]))


def test_a_batch_sweeps_its_cuts_in_the_groups_the_blocks_would():
    """Found by the property below: the batch swept its feed moves apart from the ones
    buffered before it, the blocks all in one sweep, and the grid merges neighbouring
    pieces within a sweep, so the rapid's crash was placed at X0.25 on one path and X0.75
    on the other."""
    moves = ["L X+0.000", "L X-1.500 Y+0.000", "L X+0.000 Y+0.000", "L X-0,125 Y+0.000 Z+71.800", "L Y+15.471 F1200.5",
             "L Y+0.000 Z-35.880", "L X-0.000 Y+0.000 Z-37.795", "L X+97.427 Y+92.000 Z+0.000", "L X+0.000 Y-0.000 Z+0.000",
             "L X+0.000", "L X-0.000", "L X+40.535 Y-47.000 Z+0.000", "L X+21.768", "L X+0.000 Y+59.561 Z+0.000 F1200.5",
             "L X+0.000 Y+130.893", "L X+0.000", "L X+0.000", "L X-64.081 Y+0.000 Z-0,125 F500", "L X+0.000", "L X+3 Y+1,5",
             "L X+0.000 FMAX", "L X+24.881", "L X+0.000 Y+0.000 Z+0.000"]
    text = program([f"{number} {move}" for number, move in enumerate(moves, start=len(_HEAD))])
    batched = findings(text)
    assert batched == findings(text, per_block_only=True)
    assert any(finding[0] == "core.rapid-into-stock" and finding[2] == "violated" for finding in batched[0])


@hypothesis_settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(st.lists(_PART, min_size=1, max_size=8))
def test_batched_and_block_by_block_runs_report_the_same(parts):
    body = [f"{number} {line}" for number, line in enumerate((line for part in parts for line in part), start=len(_HEAD))]
    text = program(body)
    assert findings(text) == findings(text, per_block_only=True)


# ---------------------------------------------------------------------- contours: arcs, poles, compensation


def test_arcs_by_radius_and_about_the_pole_are_read_with_their_centres_and_directions():
    lines = [*cam_lines(4), "20 CR X+6.000 Y+40.000 R+6.000 DR-", "21 CC X+6 Y+34", "22 C X+12 Y+34 DR+ F250", "23 L X+1 Y+2 R0 F200",
             "24 CC X-1,5 Y+2", "25 C Y+5 DR-", "26 CR X+0 R-7.5 DR+", *cam_lines(20, 27)]
    run = run_of(lines)
    cw, ccw = ir.MoveBatch.KINDS.index("arc_cw"), ir.MoveBatch.KINDS.index("arc_ccw")
    assert list(run.kinds[4:11]) == [cw, -1, ccw, 1, -1, cw, ccw]
    assert numpy.array_equal(run.arc_words[4:11], [[numpy.nan, numpy.nan, numpy.nan, 6.0], [numpy.nan] * 4, [6.0, 34.0, numpy.nan, numpy.nan],
                                                   [numpy.nan] * 4, [numpy.nan] * 4, [-1.5, 2.0, numpy.nan, numpy.nan],
                                                   [numpy.nan, numpy.nan, numpy.nan, -7.5]], equal_nan=True)
    assert numpy.array_equal(run.values[4:11], [[6.0, 40.0, numpy.nan], [numpy.nan] * 3, [12.0, 34.0, numpy.nan], [1.0, 2.0, numpy.nan],
                                                [numpy.nan] * 3, [numpy.nan, 5.0, numpy.nan], [0.0, numpy.nan, numpy.nan]], equal_nan=True)
    assert run.centres_absolute
    assert list(numpy.flatnonzero(run.keeps_motion)) == [5, 6, 8, 9]  # CC and C leave the motion mode alone
    assert list(numpy.flatnonzero(run.compensation_off)) == [7]
    assert numpy.array_equal(run.poles[4:10], [[numpy.nan] * 2, [6.0, 34.0], [numpy.nan] * 2, [numpy.nan] * 2, [-1.5, 2.0], [numpy.nan] * 2], equal_nan=True)
    assert numpy.array_equal(run.feeds[4:8], [numpy.nan, numpy.nan, 250.0, 200.0], equal_nan=True)


def test_an_arc_about_a_pole_set_before_the_streak_ends_it():
    lines = [*cam_lines(20), "40 C X+5 Y+5 DR+", "41 CC X+0 Y+0", "42 C X+5 Y+0 DR-", *cam_lines(20, 43)]
    assert run_of(lines).rows == 19  # the arc's centre is in the state, not in the text the reader sees
    assert run_of(["41 CC X+0 Y+0", *lines[20:]]).rows == 23  # all but the last line, the pole set first


def test_circle_lines_with_anything_else_are_not_plain():
    for odd in ["CR X+1 Y+2 R+5", "CR X+1 Y+2 DR-", "CR R+5 DR+", "CC X+1", "CC IX+1 Y+2", "C X+1 Y+2", "C DR+", "C X+1 Y+2 DR- RR",
                "CR X+1 Y+2 R+5 DR- FMAX", "CT X+1 Y+2", "C X+1 Y+2 DR+ M3", "CC Y+1 X+2", "CR X+1 Y+2 Z-1 R+5 DR-",
                "CR X+30 Y+5 R0 DR-"]:  # R0 is the compensation word, and this CR has no radius (found by fuzzing)
        assert not is_plain_line(odd.encode()), odd
    for plain in ["CR X+1 Y+2 R+5 DR-", "7 CR Y+2 R5 DR+ F300", "CC X+1 Y+2", "C X+1 DR-", "  12 C X+1 Y+2 DR+ F1,5\r", "CR X+1 R00 DR-",
                  "CR X+1 R+0 DR+", "CR Y+1 R0,5 DR-"]:
        assert is_plain_line(plain.encode()), plain


_CIRCLE_NUMBER = st.floats(-60, 60, allow_nan=False).map(lambda value: f"{value:+.3f}")
_CIRCLE_LINE = st.one_of(
    st.tuples(st.sampled_from(["X", "Y", "XY"]), _CIRCLE_NUMBER, _CIRCLE_NUMBER, st.sampled_from(["R+", "R-", "R"]),
              st.one_of(_CIRCLE_NUMBER.map(lambda n: n[1:]), st.sampled_from(["0", "00", "0.", "5"])),
              st.sampled_from(["DR-", "DR+"]), st.sampled_from(["", " F400"])).map(
        lambda p: "CR " + " ".join(f"{axis}{number}" for axis, number in zip(p[0], p[1:3])) + f" {p[3]}{p[4]} {p[5]}{p[6]}"),
    st.tuples(_CIRCLE_NUMBER, _CIRCLE_NUMBER).map(lambda p: f"CC X{p[0]} Y{p[1]}"),
    st.tuples(st.sampled_from(["X", "Y", "XY"]), _CIRCLE_NUMBER, _CIRCLE_NUMBER, st.sampled_from(["DR-", "DR+"]), st.sampled_from(["", " F250"])).map(
        lambda p: "C " + " ".join(f"{axis}{number}" for axis, number in zip(p[0], p[1:3])) + f" {p[3]}{p[4]}"),
)


@hypothesis_settings(max_examples=200, deadline=None)
@given(st.lists(_CIRCLE_LINE, min_size=1, max_size=6), st.sampled_from(["12 ", ""]))
def test_a_circle_line_the_reader_takes_means_what_the_general_lowering_reads(circles, number):
    for refused in (line for line in circles if not is_plain_line(line.encode())):  # CR .. R0: the general lowering finds no radius
        assert KlartextLowering()._general(refused.encode(), 1, None).notes, refused
    lines = [number + line for line in ["CC X+0 Y+0", *circles] if is_plain_line(line.encode())]
    run = run_of([*lines, *cam_lines(20)])
    assert run.rows == len(lines) + 19
    for row, raw in enumerate(lines):
        ops = KlartextLowering()._general(raw.encode(), 1, None).ops
        move = next((op for op in ops if isinstance(op, (ir.Move, ir.PoleArc, ir.Pole))), None)
        feeds = [op.value for op in ops if isinstance(op, ir.SetFeed)]
        assert feeds == ([] if numpy.isnan(run.feeds[row]) else [run.feeds[row]]), raw
        written = {axis: float(value) for axis, value in zip("XYZ", run.values[row]) if not numpy.isnan(value)}
        if isinstance(move, ir.Pole):
            assert run.kinds[row] == -1 and not written and list(run.poles[row]) == [move.words["X"], move.words["Y"]], raw
        elif isinstance(move, ir.PoleArc):
            assert written == {axis: move.words[axis] for axis in "XY" if axis in move.words}, raw
            assert ir.MoveBatch.KINDS[run.kinds[row]] == ("arc_ccw" if move.words["DR"] > 0 else "arc_cw") and run.keeps_motion[row], raw
        else:
            assert written == move.targets and ir.MoveBatch.KINDS[run.kinds[row]] == move.kind, raw
            assert run.arc_words[row, 3] == move.arc["R"] and not run.keeps_motion[row], raw


_TOOL = "; ncverify: tool 1 radius 3 length 40 type endmill"
_CONTOUR_PART = st.one_of(
    st.lists(st.one_of(_PLAIN, _PLAIN, _CIRCLE_LINE), min_size=25, max_size=70).map(lambda lines: ["CC X+20 Y+20", *lines]),
    st.lists(st.one_of(_PLAIN, _CIRCLE_LINE), max_size=6),
    st.sampled_from(["L X+10 Y+10 RL F300", "L X+60 Y+10 RR F500", "L X+5 Y+5 R0", "L Z+20 R0 FMAX", "L X+30 Y+30 Z-1 RR", "M5",
                     "CYCL DEF 10.0 ROTATION", "CYCL DEF 10.1 ROT+30", "TOOL CALL 1 X S3000", "TOOL CALL 1 Z S3000", "RND R2", "CHF 1",
                     "CT X+5 Y+5"]).map(lambda line: [line]),
)


@hypothesis_settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(st.lists(_CONTOUR_PART, min_size=1, max_size=6), st.booleans())
def test_contours_of_lines_and_arcs_under_compensation_give_the_same_findings_batched_or_block_by_block(parts, tool):
    """Arcs by radius and about the pole, poles, R0 lines and RL/RR contours in streaks long
    enough to be batched, with the tool's radius known (the cut stock then offsets
    compensated cuts) or not."""
    lines = [*([_TOOL] if tool else []), *(line for part in parts for line in part)]
    text = program([f"{number} {line}" for number, line in enumerate(lines, start=len(_HEAD))])
    assert findings(text) == findings(text, per_block_only=True)


def test_a_cam_contour_under_compensation_runs_in_batches_with_its_arcs(runs_taken):
    laps = []
    for lap in range(30):
        z = -0.25 * (lap + 1)
        laps += [f"L X+0 Y+34 Z{z:+.3f}", "CC X+6 Y+34", "C X+6 Y+40 DR-", "L X+34 Y+40", "CC X+34 Y+34", "C X+40 Y+34 DR-", "L X+40 Y+6",
                 "CR X+34 Y+0 R+6 DR-", "L X+6 Y+0", "CC X+6 Y+6", "C X+0 Y+6 DR-", "L X+0 Y+20"]
    body = [_TOOL, "L X-10 Y+20 R0 FMAX", "L Z+0 R0 F300", "L X+0 Y+20 RR F800", *laps, "L X-10 Y+20 R0", "L Z+50 R0 FMAX", "L X+80 Y+80 FMAX",
            "L Z-1 FMAX"]  # a rapid down into the blank, away from the contour
    text = program([f"{number} {line}" for number, line in enumerate(body, start=len(_HEAD))])
    batched, _blocks = findings(text)
    assert sum(runs_taken) > 300
    assert batched == findings(text, per_block_only=True)[0]
    assert [status for rule, _span, status, _message in batched if rule == "core.rapid-into-stock"] == ["violated"]


def test_a_rapid_back_along_the_cut_just_made_under_a_rotation_is_judged_alike_batched_or_block_by_block():
    """Found by fuzzing: under CYCL DEF 10 the batch mapped its points to the workpiece by a
    matrix product that left one end an ulp off the block path's, so the exact check of the
    last cuts failed there and the batch said unknown where the block path said clear."""
    body = [_TOOL, "CYCL DEF 10.0 ROTATION", "CYCL DEF 10.1 ROT+30", "L Z+50 R0 FMAX", "L X+80 Y+30 R0 FMAX", "L Z-1 F300", "L X+80 Y+30",
            "L X+60 Y+30", "L X+5 Y+10", "L X+2.5 Y+6", "L X+5 Y+10 FMAX", *(f"L X+{50 + step} Y+{50 + step % 3}" for step in range(20))]
    text = program([f"{number} {line}" for number, line in enumerate(body, start=len(_HEAD))])
    batched, _blocks = findings(text)
    assert batched == findings(text, per_block_only=True)[0]
    assert not [rule for rule, _span, _status, _message in batched if rule == "core.rapid-into-stock"]
