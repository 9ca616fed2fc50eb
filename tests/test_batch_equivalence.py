"""Straight-line code runs in batches (numpy arrays); every finding, span and block count
must be the same as running the blocks one by one."""
from __future__ import annotations

import re
import tempfile
from pathlib import Path

import numpy
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from ncverify import Settings, check_text
from ncverify.api import check_file

_NUMBER = st.one_of(
    st.floats(-500, 500, allow_nan=False).map(lambda value: f"{value:.3f}"),
    st.integers(-50_000, 50_000).map(str),
    st.integers(-9, 9).map(lambda value: f"{value}."),
)
_AXIS_WORDS = st.lists(st.sampled_from("XYZ"), unique=True, max_size=3).flatmap(
    lambda axes: st.tuples(*[_NUMBER.map(lambda number, axis=axis: axis + number) for axis in axes])
)
_PLAIN_BLOCK = st.tuples(
    st.one_of(st.none(), st.integers(1, 9999).map(lambda n: f"N{n}")),
    st.one_of(st.none(), st.sampled_from(["G0", "G1", "G00", "G01"])),
    _AXIS_WORDS,
    st.one_of(st.none(), st.sampled_from(["F200.", "F0", "F50", "F1200."])),
).flatmap(lambda parts: st.permutations([p for p in (parts[0], parts[1], *parts[2], parts[3]) if p]).map(" ".join))
_OTHER_BLOCK = st.sampled_from(
    ["G91", "G90", "M05", "M03", "G41 D1", "G40", "F0", "G20", "G21", "(WALL)", "", "G02 X1. Y1. R5.", "G1", "T2 M06", "G43 H02", "G49",
     "G01 X4. Y4. ,R1.", "G1 X-2. ,C0.5"]  # a rounded or chamfered corner ends the batch before it
)
# Arcs in the fast lowering's form between the plain blocks, and helices (an arc with a Z
# move, a full turn): the plain blocks after one are modal arcs, never part of a batch.
_ARC_BLOCK = st.sampled_from(
    ["G03 X2. Y0. I1. J0.", "G2 X0. Y0. Z-1. I5. J0. F300.", "G02 X3. Y4. R5.", "N7 G3 X-1.5 Y2.5 Z-0.5 I0.25 J-0.75", "G2 I2. J0."]
)
_BODY = st.lists(st.one_of(_PLAIN_BLOCK, _PLAIN_BLOCK, _PLAIN_BLOCK, _OTHER_BLOCK, _ARC_BLOCK), min_size=20, max_size=120)
_SMALL = st.floats(-30, 30, allow_nan=False).map(lambda value: f"{value:.3f}")
# Arcs and helices of any shape in the three planes, by centre (I/J/K) or radius (R), full
# circles (no end point), absolute or incremental, with the plain blocks they interrupt.
_ANY_ARC = st.tuples(
    st.sampled_from(["G2", "G3", "G02", "G03"]),
    st.lists(st.sampled_from("XYZ"), unique=True, max_size=3).flatmap(lambda axes: st.tuples(*[_SMALL.map(lambda n, a=a: a + n) for a in axes])),
    st.one_of(st.lists(st.sampled_from("IJK"), unique=True, min_size=1, max_size=2).flatmap(
        lambda letters: st.tuples(*[_SMALL.map(lambda n, a=a: a + n) for a in letters])),
        _SMALL.map(lambda n: ("R" + n,))),
    st.one_of(st.none(), st.sampled_from(["F400.", "F0"])),
).map(lambda parts: " ".join([parts[0], *parts[1], *parts[2], *([parts[3]] if parts[3] else [])]))
_CAM_LINE = st.lists(st.sampled_from("XYZ"), unique=True, min_size=1, max_size=3).flatmap(
    lambda axes: st.tuples(*[_SMALL.map(lambda n, a=a: a + n) for a in axes])).map(" ".join)  # as CAM writes them: every number with its point
_STREAK = st.tuples(st.sampled_from(["G0", "G1"]), st.lists(_CAM_LINE, min_size=26, max_size=45)).map(
    lambda parts: [parts[0], *parts[1]])  # long enough to be read as a batch (8 lines, then 16 more)
_ARC_BODY = st.lists(st.one_of(_STREAK, *[st.lists(part, min_size=1, max_size=3) for part in (
    _PLAIN_BLOCK, _ANY_ARC, _ARC_BLOCK, st.sampled_from(["G17", "G18", "G19", "G90", "G91", "G0", "G1", "G41 D1", "G40", "G1 X4. Y4. ,R1."]))]),
    min_size=6, max_size=30).map(lambda parts: [block for part in parts for block in part])
_HEADER = st.lists(st.sampled_from(["G43 H01 Z50.", "S1000 M03", "F300."]), unique=True)
_STOCK = ["(ncverify: stock box X-40:40 Y-40:40 Z-10:0)", "(ncverify: tool 1 radius 3 length 50 type endmill)"]


def _program(body: list[str], header: list[str]) -> str:
    return "\n".join(["O1000", "G21 G90 G17 G54", "T1 M06", *header, *body, "M30"]) + "\n"


def _assert_same_findings(program: str, project: str | None = None, **options):
    """Batched and block by block: the same findings, block count and findings past a
    rule's limit; returns the batched result. ``project``: an ``ncverify.toml`` beside the
    program (a machine's limits)."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "program.nc"
        path.write_text(program)
        if project is not None:
            (Path(folder) / "ncverify.toml").write_text(project)
        batched = check_file(str(path), Settings(**options))
        one_by_one = check_file(str(path), Settings(per_block_only=True, **options))
    assert [(d.rule, d.status, d.span, d.message) for d in batched.diagnostics] == [
        (d.rule, d.status, d.span, d.message) for d in one_by_one.diagnostics]
    assert batched.blocks == one_by_one.blocks
    assert batched.truncated == one_by_one.truncated
    return batched


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=_BODY, header=_HEADER)
def test_batched_and_block_by_block_runs_report_the_same(body, header):
    _assert_same_findings(_program(body, header))


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=_ARC_BODY, header=_HEADER, stock=st.booleans())
def test_arcs_and_helices_in_every_plane_give_the_same_findings_batched_or_block_by_block(body, header, stock):
    """With a stock and a sized tool the cut stock follows the arcs (their chords are cut
    in batches at each flush): a rapid after them is judged alike on both paths."""
    _assert_same_findings(_program(body, [*(_STOCK if stock else []), *header]))


_COORDINATE = st.floats(-40, 40, allow_nan=False).map(lambda value: f"{value:.3f}")
# A streak of CAM arcs and lines, long enough to be read as one batch: arcs by centre offsets
# (often off the circle, for the arc-geometry rule), by radius (big enough or not), full
# circles, helices, in any plane, absolute or incremental, metric or inch.
_STREAK_ARC = st.tuples(
    st.sampled_from(["G2", "G3", "G02", "G03", ""]),
    st.lists(st.sampled_from("XYZ"), unique=True, max_size=3).flatmap(lambda axes: st.tuples(*[_COORDINATE.map(lambda n, a=a: a + n) for a in axes])),
    st.one_of(st.lists(st.sampled_from("IJK"), unique=True, min_size=1, max_size=3).flatmap(
        lambda letters: st.tuples(*[_COORDINATE.map(lambda n, a=a: a + n) for a in letters])),
        st.sampled_from(["R0.5", "R5.", "R-5.", "R60.", "R-60."]).map(lambda word: (word,))),
    st.one_of(st.none(), st.sampled_from(["F500.", "F0"])),
).map(lambda parts: " ".join(word for word in [parts[0], *parts[1], *parts[2], parts[3]] if word))
_STREAK_LINE = st.tuples(st.sampled_from(["G1 ", "G0 ", ""]), _CAM_LINE).map("".join)
_MODES = st.tuples(st.sampled_from(["G17", "G18", "G19"]), st.sampled_from(["G90", "G91"]), st.sampled_from(["G21", "G20"]))
_CONSTANT_CENTRE = ["G2 I5. J0. K0.", "G3 I-2. J1. K0.5"]  # full circles: on the circle in every plane
_MIXED_STREAK = st.lists(st.one_of(_STREAK_ARC, _STREAK_LINE, st.sampled_from(_CONSTANT_CENTRE)), min_size=30, max_size=60)


def _handed_to_rules(program: str, in_run, alone, **options) -> tuple[int, int]:
    """What the check hands the rules, counted as it hands it: ``in_run(run)`` summed over
    the runs, ``alone(segment)`` over the segments that reach them one by one."""
    from unittest import mock

    from ncverify.check import Checker

    runs, segments = [], []
    run_handler, segment_handler = Checker.motion_run, Checker.segment

    def counting_runs(checker, run, state):
        runs.append(in_run(run))
        return run_handler(checker, run, state)

    def counting_segments(checker, segment, state):
        segments.append(alone(segment))
        return segment_handler(checker, segment, state)

    with mock.patch.object(Checker, "motion_run", counting_runs), mock.patch.object(Checker, "segment", counting_segments):
        check_text(program, settings=Settings(**options))
    return sum(runs), sum(segments)


def _arcs_in_runs(program: str, **options) -> int:
    """How many arcs the batched check hands the rules inside runs."""
    return _handed_to_rules(program, lambda run: len(run.arc_indices()), lambda segment: 0, **options)[0]


# Cuts the cut stock cannot place (incremental from an unknown position) at the start of a
# batch: their unknown heights must keep a later rapid into the blank unknown, as block by block.
_UNPLACED_CUTS_IN_A_BATCH = [   (   ('G17', 'G91', 'G21'),
        [   'G1 Z-5.489 X-0.000 Y-24.240', 'G2 I5. J0. K0.', 'G2 X0.010 Z-34.648 Y0.000 I-0.000', 'G1 X22.779', 'G2 X0.000 R0.5',
            'G1 X1.010 Z-25.702 Y-13.386', 'G2 I-18.964', 'G2 I5. J0. K0.', 'G0 X26.590', 'X6.411 Z-30.000 Y0.268', 'G1 X-24.349 Y0.000 Z25.538',
            'G1 Z10.208', 'G2 I5. J0. K0.', 'G2 X0.000 I4.000 J24.570', 'G2 R0.5', 'G2 I0.000', 'G2 I5. J0. K0.', 'G1 X0.000', 'G1 X0.000',
            'G2 X0.000 R5.', 'G3 I0.000', 'G2 Z0.000 I0.000', 'G2 I0.000', 'G2 X0.000 I0.000', 'G3 X0.000 J0.000', 'G1 X0.000', 'G2 I5. J0. K0.',
            'G2 I0.000', 'G2 I-32.361 F0', 'G02 J0.003 I0.000']),
    (   ('G17', 'G90', 'G21'),
        [   'G02 Y11.235 X15.927 I0.000', 'G2 R0.5', 'G2 I0.000', 'G2 I-30.811 J0.000', 'G2 I0.000', 'G2 K-40.000 J-31.577 I0.012 F500.', 'G2 I0.000',
            'G1 X0.000', 'G2 K0.000', 'G2 Y0.000 J0.000', 'G3 R0.5', 'G2 I5. J0. K0.', 'G0 Y-1.735 Z-14.864 X-2.266', 'G2 I5. J0. K0.',
            'G02 X23.274 Y-0.000 I-25.045', 'G2 I5. J0. K0.', 'G03 X-0.000 Y-0.000 Z-10.804 R-60. F500.', 'G2 I5. J0. K0.',
            'G2 Z-10.923 X4.478 Y-0.000 I31.863 K-0.000 J-14.191', 'Z-18.116 X9.846 R-60. F0', 'G3 Z0.000 R-60.', 'Y-20.170', 'G3 I-2. J1. K0.5',
            'G3 I-2. J1. K0.5', 'G0 X0.500 Y-2.807', 'G1 X-17.908', 'G02 X0.000 I0.000', 'G1 X0.000', 'G2 I5. J0. K0.', 'G1 Y0.000 X0.000', 'G3 R5.',
            'G2 I0.000', 'G2 I0.000 F500.', 'G2 I0.000', 'Y-19.936', 'Y-0.000 K0.000 J8.722 I0.000', 'R5.', 'G1 X7.896', 'G0 X27.349',
            'G0 Z1.055 Y0.000 X0.900', 'G3 Y36.160 Z0.167 R-60.', 'G3 Z0.000 Y21.512 X1.858 R5. F500.', 'G1 Z-0.000 X0.000 Y11.235',
            'G3 J0.000 I-39.000 F500.', 'G02 X-3.793 Z-0.000 I20.983 J-20.889', 'G0 X10.492', 'Y-29.514', 'G0 Z-6.388 X-27.102',
            'G3 I-2. J1. K0.5'])]


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@example(streaks=_UNPLACED_CUTS_IN_A_BATCH, header=["S1000 M03", "G43 H01 Z50.", "F300."], stock=True)
@given(streaks=st.lists(st.tuples(_MODES, _MIXED_STREAK), min_size=1, max_size=3), header=_HEADER, stock=st.booleans())
def test_streaks_of_arcs_and_lines_give_the_same_findings_batched_or_block_by_block(streaks, header, stock):
    body = [block for modes, streak in streaks for block in (*modes, "G0 X1. Y2. Z3.", "G1 F300.", *streak)]
    _assert_same_findings(_program(body, [*(_STOCK if stock else []), *header]))


_ADAPTIVE = [block for step in range(40) for block in (f"G3 X{step * 0.4:.3f} Y4. I0. J2.", f"G1 X{step * 0.4 + 0.2:.3f} Y4.",
                                                      f"G2 X{step * 0.4 + 0.2:.3f} Y0. I0. J-2.", f"G1 X{step * 0.4 + 0.4:.3f} Y0.")]


@pytest.mark.parametrize("modes, body", [
    (["G17 G90 G21"], _ADAPTIVE),
    (["G17 G90 G20"], _ADAPTIVE),
    (["G17 G91 G21"], ["G3 X0. Y4. I0. J2.", "G1 X0.2", "G2 X0. Y-4. I0. J-2.", "G1 X0.2"] * 40),
    (["G18 G90 G21"], [line.replace("Y", "Z").replace("J", "K") for line in _ADAPTIVE]),
    (["G19 G90 G21"], [line.replace("Y", "Z").replace("X", "Y").replace("J", "K").replace("I", "J") for line in _ADAPTIVE]),
    (["G17 G90 G21"], ["G2 X0.4 Y4. R2.", "G1 X0.4 Y0.", "G3 X0. Y0. Z-0.1 R0.2", "G1 Y4.5", "G2 X0.4 Y4. R0.01"] * 32),
    (["G17 G90 G21"], ["G2 I2. J0. Z-0.5", "G1 X0.4", "G3 I-2. J0.", "G1 X0."] * 40),
])
def test_arcs_run_inside_batches_with_the_same_findings(modes, body):
    """Adaptive clearing (half circles joined by short lines), incremental, in inch, in the
    other planes, by radius (one too small for its chord) and as full circles: the arcs run
    inside batches and the findings are the block path's."""
    program = _program(["G0 X0. Y0. Z1.", "G1 Z-1. F800.", *modes, *body], [*_STOCK, "G43 H01 Z50.", "S1000 M03"])
    assert _arcs_in_runs(program) >= len(body) // 4
    _assert_same_findings(program)


@pytest.mark.parametrize("modes, body", [(["G17 G90 G21"], _ADAPTIVE), (["G17 G90 G21 G41 D1"], _ADAPTIVE[:-1] + ["G1 X0. Y0. F0"] + _ADAPTIVE)])
def test_rules_that_do_not_judge_arcs_in_runs_get_them_one_by_one_with_the_same_findings(modes, body, monkeypatch):
    """A rule whose run handler leaves arcs alone gets a run's straight stretches as runs
    and each arc as the block path's segment, with the state the block path has there
    (its feed, its motion mode): every rule taken so gives the block path's findings."""
    from ncverify.check import rule_classes

    for cls in rule_classes():
        monkeypatch.setattr(cls, "handles_arcs", False)
    program = _program(["G0 X0. Y0. Z1.", "G1 Z-1. F800.", *modes, *body], [*_STOCK, "G43 H01 Z50.", "S1000 M03"])
    assert _arcs_in_runs(program) >= len(body) // 4
    _assert_same_findings(program)


def test_every_rule_that_reads_runs_judges_their_arcs_too():
    """A rule whose run handler leaves arcs alone gets each arc of a run cut out as one
    Python segment: adaptive-clearing programs (arcs between short lines) would lose the
    batch speed."""
    from ncverify.check import Rule
    from ncverify.rule_registry import rule_classes

    assert [cls.__name__ for cls in rule_classes() if cls.motion_run is not Rule.motion_run and not cls.handles_arcs] == []


@pytest.mark.parametrize("options", [{"dialect": "linuxcnc"}, {"dialect": "fagor"}, {"profile": "fanuc"}, {"profile": "haas"}])
def test_arcs_run_inside_batches_in_every_dialect_that_reads_iso_motion(options):
    body = [*_ADAPTIVE, *["G2 X0.4 Y4. R2.", "G1 X0.4 Y0.", "G3 X0. Y0. Z-0.1 R0.2", "G1 Y4.5", "G2 X0.4 Y4. R0.01"] * 20]
    program = _program(["G0 X0. Y0. Z1.", "G1 Z-1. F800.", *body], [*_STOCK, "G43 H01 Z50.", "S1000 M03"])
    assert _arcs_in_runs(program, **options) >= len(body) // 4
    batched = check_text(program, settings=Settings(**options))
    one_by_one = check_text(program, settings=Settings(per_block_only=True, **options))
    assert [(d.rule, d.status, d.span, d.message) for d in batched.diagnostics] == [(d.rule, d.status, d.span, d.message) for d in one_by_one.diagnostics]
    assert any(d.rule == "core.arc-geometry" for d in batched.diagnostics)  # the R0.01 arcs cannot reach their end points


def test_arcs_that_the_arrays_do_not_model_end_the_batch_for_the_block_path():
    """On a lathe X is a diameter, which the arrays do not scale: its arcs are left to the
    block path (the lines between them still run in batches), with the same findings."""
    body = ["G18", "G0 X20. Z1.", "G1 Z-1. F0.2", *[f"G2 X{20 + step % 2 * 2}. Z{-1 - step}. R5." if step % 2 else f"G1 X20. Z{-1 - step}." for step in range(60)]]
    program = "\n".join(["O1000", "G21 G90 G54", "T0101", "S500 M03", *body, "M30"]) + "\n"
    assert _arcs_in_runs(program, machine="lathe") == 0
    assert _arcs_in_runs(program, machine="mill") > 0


@pytest.mark.parametrize("frame", ["G68 X0. Y0. R30.", "G52 X5. Y-3.", "G92 X10. Y10."])
def test_arcs_under_a_frame_are_left_to_the_block_path(frame):
    """A rotation or a shift of the coordinates maps a run's points to the workpiece, not its
    arcs' centres: the arcs run block by block, with the same findings."""
    program = _program(["G0 X0. Y0. Z1.", "G1 Z-1. F800.", frame, *_ADAPTIVE], [*_STOCK, "G43 H01 Z50.", "S1000 M03"])
    assert _arcs_in_runs(program) == 0
    assert _arcs_in_runs(program.replace(frame, "")) > 0
    _assert_same_findings(program)
    batched = check_text(program, settings=Settings(machine="lathe"))
    one_by_one = check_text(program, settings=Settings(machine="lathe", per_block_only=True))
    assert [(d.rule, d.status, d.span, d.message) for d in batched.diagnostics] == [(d.rule, d.status, d.span, d.message) for d in one_by_one.diagnostics]


def test_a_long_plain_program_is_run_in_batches_and_finds_the_missing_feed():
    body = [f"G1 X{i * 0.1:.3f} Y{(i % 7) * 0.5:.3f}" for i in range(2000)]
    program = "\n".join(["O1000", "G21 G90 G54", "S1000 M03", "G0 X0. Y0.", *body, "M30"]) + "\n"
    result = check_text(program)
    assert [(d.rule, d.span.line) for d in result.diagnostics if d.status.value == "violated"] == [("core.feed-missing", 5)]
    assert result.blocks == 2005


def test_every_rule_that_reads_segments_reads_runs_too():
    """A rule with a segment handler and no run handler gets every run cut back into one
    Python object per block: CAM programs would lose the batch speed."""
    from ncverify.check import Rule
    from ncverify.rule_registry import rule_classes

    segment_only = [cls.__name__ for cls in rule_classes() if cls.segment is not Rule.segment and cls.motion_run is Rule.motion_run]
    assert segment_only == []


def test_the_plot_draws_the_arcs_of_a_run_as_block_by_block():
    """The picture's tool path: a run's arcs are drawn as arcs, not as chords."""
    import numpy

    from ncverify.api import check_source
    from ncverify.plot import ToolpathRecorder
    from ncverify.source import ProgramSource

    program = _program(["G0 X0. Y0. Z1.", "G1 Z-1. F800.", *_ADAPTIVE], ["G43 H01 Z50.", "S1000 M03"])
    paths = []
    for per_block_only in (False, True):
        recorder = ToolpathRecorder()
        check_source(ProgramSource.from_text(program, "<text>"), Settings(per_block_only=per_block_only), None, checker_class=recorder.checker_class())
        paths.append(recorder.path())
    (batched, batched_kinds), (one_by_one, one_by_one_kinds) = paths
    assert numpy.array_equal(batched_kinds, one_by_one_kinds)
    assert numpy.allclose(batched, one_by_one, equal_nan=True)
    assert len(batched) > 10 * len(_ADAPTIVE)  # arcs drawn as many points each



def test_the_first_feed_of_a_batch_names_a_missing_feed_limit_where_the_block_path_does():
    """With no maximum feed the rule says so at the first move with a feed, here F0 inside
    a batch; the batch used to say it at its fastest feed, many lines later."""
    streak = ["Y3.142 X0.000 Z20.586", "X3.865 Z-0.333 Y18.628", "Z-0.000", "Y-19.231 X-18.437 Z0.000", "Z27.464 Y0.800",
              "Z1.500", "Z1. F0", "Z-5.392 Y0.001", "Y0.250 X28.362 Z-4.355", "X0.000 Y20.834", "Y-0.000", "Z15.629 Y18.460",
              "X10.667", "Z29.563 Y-0.000 X26.437", "Z-25.796", "Y0.000 X-11.569", "Z10.844 X-0.000", "Z0.000 X-0.000 Y-13.669",
              "Y20.469", "X-470.543", "X3. F1200. N834"]
    program = _program(["G1", "X15.947 Z-3.784 Y-26.911", *streak], ["G43 H01 Z50."])
    assert [d.span.line for d in check_text(program).diagnostics if d.rule == "core.feed-over-limit"] == [13]
    _assert_same_findings(program)


@pytest.mark.parametrize("dialect", ["iso", "fagor"])
def test_arcs_by_radius_in_a_batch_leave_the_cut_stock_as_block_by_block(dialect):
    """Arcs given by their radius, some of which no circle of that radius fits (R3 across
    a 13 mm side, as the corners fall on the second lap): the cut stock places the others
    as the control does and takes those as cuts it cannot place (material may be gone
    anywhere), without leaving the arrays. A rapid down into the pocket afterwards, and one
    into the blank beside it, are judged as the block path judges them: the second is
    unknown, as the arcs that do not fit may have cut anywhere (``test_radius_arcs``)."""
    corners = [f"G2 X{x:.1f} Y{y:.1f} R3." if step % 2 else f"G1 X{x:.1f} Y{y:.1f}"
               for step, (x, y) in enumerate([(0.0, 10.0), (3.0, 13.0), (10.0, 13.0), (13.0, 10.0), (13.0, 0.0), (10.0, -3.0), (0.0, -3.0)] * 6)]
    after = ["G0 Z5.", "G0 X6. Y5.", "G0 Z-0.5", "G0 Z5.", "G0 X30. Y30.", "G0 Z-2."]
    program = _program(["G0 X0. Y0. Z1.", "G1 Z-1. F800.", *corners, *after], [*_STOCK, "G43 H01 Z50.", "S1000 M03"])
    if dialect == "fagor":
        program = program.replace("G21 ", "G71 ")  # Fagor's metric code
    assert _arcs_in_runs(program, dialect=dialect) >= 12
    batched = check_text(program, settings=Settings(dialect=dialect))
    one_by_one = check_text(program, settings=Settings(per_block_only=True, dialect=dialect))
    assert [(d.rule, d.status, d.span, d.message) for d in batched.diagnostics] == [(d.rule, d.status, d.span, d.message) for d in one_by_one.diagnostics]
    assert [d.status.value for d in batched.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == len(program.splitlines()) - 1] == ["unknown"]


# SINUMERIK writes the radius as CR= (a bare R is a parameter) and inch/metric as G70/G71.
_SINUMERIK_MODES = st.tuples(st.sampled_from(["G17", "G18", "G19"]), st.sampled_from(["G90", "G91"]), st.sampled_from(["G71", "G70"]))
_SINUMERIK_STREAK = _MIXED_STREAK.map(lambda blocks: [block.replace(" R", " CR=") for block in blocks])


def _sinumerik_program(body: list[str], stock: bool) -> str:
    annotations = [comment.replace("(", "; ").rstrip(")") for comment in _STOCK] if stock else []
    return "\n".join(["%_N_PART_MPF", *annotations, "G17 G90 G71 G54", "T1 D1", "M6", "S1000 M3", *body, "M30"]) + "\n"


def _assert_same_sinumerik_findings(program: str) -> None:
    batched = check_text(program, "part.mpf", settings=Settings(dialect="sinumerik"))
    one_by_one = check_text(program, "part.mpf", settings=Settings(per_block_only=True, dialect="sinumerik"))
    assert [(d.rule, d.status, d.span, d.message) for d in batched.diagnostics] == [
        (d.rule, d.status, d.span, d.message) for d in one_by_one.diagnostics]
    assert batched.blocks == one_by_one.blocks


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(streaks=st.lists(st.tuples(_SINUMERIK_MODES, _SINUMERIK_STREAK), min_size=1, max_size=3), stock=st.booleans())
def test_sinumerik_streaks_of_arcs_and_lines_give_the_same_findings_batched_or_block_by_block(streaks, stock):
    body = [block for modes, streak in streaks for block in (*modes, "G0 X1. Y2. Z3.", "G1 F300.", *streak)]
    _assert_same_sinumerik_findings(_sinumerik_program(body, stock))


def test_sinumerik_cam_arcs_by_centre_and_by_cr_run_inside_batches():
    contour = ["G1 X0. Y34. Z-0.25", "G2 X6. Y40. I6. J0.", "G1 X34. Y40.", "G2 X40. Y34. CR=6.", "G1 X40. Y6.", "G2 X34. Y0. I-6. J0.",
               "G1 X6. Y0.", "G2 X0. Y6. CR=6.", "G1 X0. Y20."]
    program = _sinumerik_program(["G0 X-10. Y20. Z5.", "G1 Z0. F300.", "G41 G1 X0. Y20. F800.", *contour * 12], stock=True)
    assert _arcs_in_runs(program, dialect="sinumerik") >= 40
    _assert_same_sinumerik_findings(program)
    # a bare R is a parameter, never a radius: the line ends the batch and the block path reads it
    with_parameter = program.replace("G2 X40. Y34. CR=6.", "G2 X40. Y34. R6.", 1)
    _assert_same_sinumerik_findings(with_parameter)


# ------------------------------------------------------------------ a CAM post's shapes around batches

_HOLE_XY = st.tuples(st.floats(-10, 50, allow_nan=False), st.floats(-10, 50, allow_nan=False)).map(lambda xy: f"X{xy[0]:.3f} Y{xy[1]:.3f}")
_CYCLE_WORDS = st.tuples(
    st.sampled_from(["G81", "G82", "G83", "G73", "G85", "G86", "G89", "G84", "G74"]),
    st.sampled_from(["Z-5.", "Z2.", "Z-1.5"]),
    st.sampled_from(["R1.", "R-1.", "R5.", ""]),  # below the top of the stock, above it, none
    st.sampled_from(["", "Q1.", "Q-1.", "Q0."]),
    st.sampled_from(["", "P100", "P0.5"]),
    st.sampled_from(["", "K2", "K0"]),
    st.sampled_from(["F150.", ""]),
).map(lambda words: " ".join(word for word in words if word))
# A hole pattern as posts write it: the cycle with the first position, the other positions
# alone on their lines (often more than the plain lines before a batch), absolute or incremental.
_HOLES = st.tuples(
    st.sampled_from(["G98", "G99"]), st.sampled_from(["G90", "G91"]), _CYCLE_WORDS, st.lists(_HOLE_XY, min_size=0, max_size=40),
    st.sampled_from(["G80", "G80 G0 Z15.", "G0 X0. Y0.", "G1 X0. Y0.", "G0", "G63", ""]),
).map(lambda parts: [f"{parts[0]} {parts[1]} {parts[2]} {parts[3][0] if parts[3] else ''}".strip(), *parts[3][1:], parts[4], "G90"])
_CONTOUR = st.tuples(st.sampled_from(["G41 D1", "G42 D1", "G41 D2"]), _STREAK, st.sampled_from(["G40 G1 X-10. Y20.", "G40"])).map(
    lambda parts: [f"{parts[0]} G1 X0. Y20. F800.", *parts[1], parts[2]])
_POST_LINES = st.sampled_from(["T1 M6", "T2 M6", "S8000 M3", "S3000", "M5", "G43 H1", "G43 H2", "M8", "M9", "F300.", "(PROFILE)",
                               "G0 Z15.", "G0 Z5.", "G1 Z-1. F300.", "G0 X-10. Y20.", "G98", "G99"])
_POST_BODY = st.lists(st.one_of(_HOLES, _CONTOUR, st.lists(_POST_LINES, min_size=1, max_size=4)), min_size=3, max_size=10).map(
    lambda parts: [line for part in parts for line in part])
_POST_TOOLS = ["(ncverify: tool 1 radius 3 length 50 type endmill)", "(ncverify: tool 2 radius 1.5 length 40 type drill)"]


def _post_program(body: list[str], tools: bool) -> str:
    head = ["(ncverify: stock box X-20:60 Y-20:60 Z-20:0)", *(_POST_TOOLS if tools else []), "G21 G90 G94 G17 G40 G49 G80 G54", "T1 M6", "G43 H1", "S8000 M3", "G0 X-10. Y20. Z15."]
    return "\n".join(["O1000", *head, *body, "G0 Z50.", "M30"]) + "\n"


def _in_fagor_letters(line: str) -> str:
    """A hole cycle's line as Fagor writes it: the tool-axis word is the reference plane, I the depth."""
    return re.sub(r"\bR(-?[0-9.]+)", r"I\1", line) if re.search(r"\bG[78]\d\b", line) else line


# A machine whose travel, feed and speed limits the posts' programs cross now and then.
_TIGHT_MACHINE = ("[machine]\ntravel = { X = [-15.0, 45.0], Y = [-15.0, 45.0], Z = [-4.0, 60.0] }\nwork_offsets = { G54 = [0.0, 0.0, 0.0] }\n"
                  "max_feed = 500.0\nmax_spindle = 5000.0\n")


@settings(max_examples=90, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=_POST_BODY, tools=st.booleans(), dialect=st.sampled_from(["iso", "linuxcnc", "fagor"]), machine=st.booleans())
def test_hole_patterns_contours_and_tool_changes_give_the_same_findings_batched_or_block_by_block(body, tools, dialect, machine):
    """A CAM post's program: hole cycles (R, Z, Q, P and K words, G98/G99, incremental
    positions, tapping; ended by G80 or by a motion code) whose moves reach the rules as
    runs (their holes ahead of them), compensated contours that are batches, tool changes,
    spindle, feed and comment lines between them; on a machine of unknown limits, or of
    limits they cross."""
    program = _post_program([_in_fagor_letters(line) for line in body] if dialect == "fagor" else body, tools)
    _assert_same_findings(program, _TIGHT_MACHINE if machine else None, dialect=dialect)


def test_a_hole_judged_against_the_cut_stock_sees_the_holes_before_it_cut():
    """Found by the test above: Fagor holes at one place, their reference plane (Z) below the
    top of the stock. Block by block the holes before the last have drilled there when it is
    judged, and the cut stock clears its level; with their moves held back for one run, the
    last hole was judged against stock they had not cut yet, an ``unknown`` the block path
    does not give. The rule now has the held moves handed on before it asks the cut stock."""
    body = ["G1 Z-1. F300.", "G98 G90 G81 Z-5. I1. F150. X0.000 Y0.000", "G99 G90 G81 Z-5. I1. F150. X0.000 Y0.000", "X0.000 Y0.000"]
    _assert_same_findings(_post_program(body, True), dialect="fagor")


def _hole_moves(program: str, **options) -> tuple[int, int]:
    """How many moves of hole cycles the check hands the rules inside runs, and one by one."""
    return _handed_to_rules(program, lambda run: len(run) if run.cycle_moves else 0, lambda segment: segment.cycle is not None, **options)


_PATTERN = ["T2 M6", "S3000 M3", "G43 H2", "G0 Z5.", "G98 G81 X5. Y5. Z-5. R1. F150.",
            *[f"X{5 + (index % 5) * 7.5:.3f} Y{5 + (index // 5) * 10.0:.3f}" for index in range(1, 20)], "G80", "G0 Z15."]


@pytest.mark.parametrize("options", [{"dialect": "iso"}, {"dialect": "linuxcnc"}, {"profile": "fanuc"}, {"profile": "haas"}, {"dialect": "fagor"}])
def test_the_moves_of_a_hole_pattern_reach_the_rules_as_one_run(options):
    """Every rule that judges holes or moves in these dialects was reviewed for it
    (Rule.judges_cycle_runs, Rule.judges_holes_before_moves): a new rule that is not turns
    the runs off, and this test says so."""
    program = _post_program([_in_fagor_letters(line) for line in _PATTERN] if options.get("dialect") == "fagor" else _PATTERN, tools=True)
    in_runs, alone = _hole_moves(program, **options)
    assert (in_runs, alone) == (_hole_moves(program, per_block_only=True, **options)[1], 0)
    assert in_runs >= 20 * 4


_HOLES_AT = [f"X{5 + index * 2.5:.3f} Y5." for index in range(1, 20)]


@pytest.mark.parametrize("body, rule, present", [
    # no feed yet: the first infeed of the pattern is named as the cycle's
    (["G0 Z5.", "G98 G81 X5. Y5. Z-5. R1.", *_HOLES_AT, "G80"], "core.feed-missing", "cycle infeed with no feed rate"),
    # G41 just switched on: a cycle's moves do not settle it, the arc after the pattern does
    (["G0 Z5.", "G41 D1", "G98 G81 X5. Y5. Z-5. R1. F150.", *_HOLES_AT, "G80", "G2 X10. Y10. R5. F300."], "core.comp-on-arc", "the first move after it is an arc"),
    # a tap's feed is its pitch times the speed: not judged as a feed in mm/min, nor as a cut under G63
    (["G0 Z5.", "G63", "G94 G84 X5. Y5. Z-5. R1. F0.5", *_HOLES_AT, "G80"], "core.feed-plausibility", None),
    (["G0 Z5.", "G63", "G94 G84 X5. Y5. Z-5. R1. F0.5", *_HOLES_AT, "G80"], "core.tapping-mode-left-on", None),
])
def test_hole_moves_in_runs_are_judged_by_their_cycle_as_one_by_one(body, rule, present):
    program = _post_program(body, tools=True)
    batched = check_text(program)
    one_by_one = check_text(program, settings=Settings(per_block_only=True))
    assert [(d.rule, d.status, d.span, d.message) for d in batched.diagnostics] == [(d.rule, d.status, d.span, d.message) for d in one_by_one.diagnostics]
    found = [d.message for d in batched.diagnostics if d.rule == rule]
    assert (found == []) if present is None else any(present in message for message in found)
    assert _hole_moves(program)[0] >= 19 * 4


def _comparable(array) -> list:
    """An array's numbers as a list that compares equal where they are (NaN as None)."""
    return numpy.where(numpy.isnan(array), None, array).tolist()


def _events_to_rules(program: str, dialect: str) -> list:
    """Every run and lone move the check hands the rules, as numbers and the segments the
    rules may ask for (kind, ends, span, role, cycle)."""
    from unittest import mock

    from ncverify.check import Checker

    events = []
    run_handler, segment_handler = Checker.motion_run, Checker.segment

    def segment_of(segment):
        return segment.kind, segment.start, segment.end, segment.span, segment.role, segment.cycle

    def taking_runs(checker, run, state):
        events.append(("run", _comparable(run.points), run.kinds.tolist(), _comparable(run.feeds), run.written.tolist(), run.cycle_moves,
                       [segment_of(run.segment(index)) for index in range(len(run))]))
        return run_handler(checker, run, state)

    def taking_segments(checker, segment, state):
        events.append(("alone", segment_of(segment)))
        return segment_handler(checker, segment, state)

    with mock.patch.object(Checker, "motion_run", taking_runs), mock.patch.object(Checker, "segment", taking_segments):
        check_text(program, settings=Settings(dialect=dialect))
    return events


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(st.one_of(_HOLES, st.lists(_POST_LINES, min_size=1, max_size=3)), min_size=1, max_size=5).map(
    lambda parts: [line for part in parts for line in part]), dialect=st.sampled_from(["iso", "linuxcnc", "fagor"]))
def test_a_holes_moves_gathered_in_one_go_are_the_moves_gathered_one_by_one(body, dialect):
    """``Runtime.move_through`` gathers a hole's moves with the conditions asked once: the
    rules get the very runs and lone moves that ``move_to`` and ``_gather_segment`` make of
    them one move at a time (hole patterns absolute and incremental, G98 and G99, K repeats,
    ended every way)."""
    from unittest import mock

    from ncverify.interpret.interpreter import Interpreter

    body = ["G0 Z15.", *body]  # a second move: from there on the tool has left the start position, whose moves go alone
    program = _post_program([_in_fagor_letters(line) for line in body] if dialect == "fagor" else body, tools=True)
    in_one_go = _events_to_rules(program, dialect)
    with mock.patch.object(Interpreter, "_gather_hole_moves", lambda *arguments: False):
        one_by_one = _events_to_rules(program, dialect)
    assert in_one_go == one_by_one


def test_a_rule_not_reviewed_for_hole_runs_leaves_each_hole_move_to_go_alone(monkeypatch):
    """One rule in scope whose hole handler may read what the moves before change is enough:
    the holes' moves then reach the rules one by one, as the block path hands them."""
    from ncverify.checks.holes import HoleLevels

    monkeypatch.setattr(HoleLevels, "judges_holes_before_moves", False)
    in_runs, alone = _hole_moves(_post_program(_PATTERN, tools=True))
    assert in_runs == 0 and alone >= 20 * 4


def test_a_rapid_crash_after_hundreds_of_retracts_in_one_run_is_found():
    """The run path once judged only a rule's limit of candidate rapids (200), counting the
    retracts out of the cut that it then lets pass: the crash after them went unreported."""
    passes = [line for index in range(260) for line in (f"G1 X{index * 0.2:.3f} Y0. Z-1.", "G1 Y10.", "G0 Z5.", f"G0 X{index * 0.2 + 0.2:.3f} Y0.")]
    head = ["(ncverify: stock box X-20:60 Y-20:60 Z-20:0)", "(ncverify: tool 1 radius 0.1 length 40 type endmill)", "G21 G90 G17 G54", "T1 M6", "S3000 M3",
            "G43 H1", "G0 X0. Y0. Z5.", "F500."]
    program = "\n".join(["O1", *head, *passes, "G0 X30. Y30. Z-3.", "M30"]) + "\n"
    crashes = [d.span.line for d in _assert_same_findings(program).diagnostics if d.rule == "core.rapid-into-stock"]
    assert crashes == [2 + len(head) + len(passes)]


def test_more_rapids_into_the_stock_than_a_rule_reports_are_counted_alike_in_runs():
    holes = [f"X{5 + (index % 20) * 2.0:.3f} Y{5 + (index // 20) * 2.0:.3f}" for index in range(1, 300)]
    for return_level in ("G98", "G99"):  # R below the stock's top: every rapid down to it, and with G99 between the holes, is a crash
        program = _post_program([f"{return_level} G81 X5. Y5. Z-5. R-1. F150.", *holes, "G80"], tools=True)
        assert _assert_same_findings(program).truncated["core.rapid-into-stock"] > 0


def test_moves_past_the_travel_are_each_reported_in_runs_as_block_by_block():
    """The run path once reported five end points past the travel per axis and run; the
    block path reports each (the report keeps a rule's first findings and counts the rest)."""
    moves = [f"G2 X{150 + index:.3f} Y{-150 - index:.3f} R40." if index % 3 == 0 else f"G1 X{150 + index:.3f} Y{-150 - index:.3f}" for index in range(300)]
    program = "\n".join(["O1", "G21 G90 G17 G54", "T1 M6", "S3000 M3", "G0 X0. Y0. Z5.", "F500.", *moves, "M30"]) + "\n"
    machine = "[machine]\ntravel = { X = [-100.0, 100.0], Y = [-100.0, 100.0], Z = [-100.0, 100.0] }\nwork_offsets = { G54 = [0.0, 0.0, 0.0] }\n"
    assert _assert_same_findings(program, machine).truncated["core.travel-limit"] > 0


def test_rapids_straight_up_out_of_the_cut_pass_in_a_run_as_block_by_block():
    """A run's rapids that enter the blank are judged one by one, except those straight up
    the tool's axis from where it stands (a retract), which the run passes as the block
    path's retract test does. A rapid straight down, one up with a sideways step, and one
    down beside the cut are still judged (and the last is a crash)."""
    rows = []
    for row in range(12):
        y = row * 6.0 - 36.0
        rows += [f"G1 X0. Y{y:.1f} Z-1.", f"G1 X20. Y{y:.1f}", f"G2 X20. Y{y + 4:.1f} I0. J2.", "G0 Z5.", f"G0 X0. Y{y + 6:.1f}",
                 "G0 Z1.", "G0 Z-0.5" if row % 3 == 0 else "G0 Z2.", "G0 X1. Z6." if row % 4 == 0 else "G0 Z6."]
    program = _program(["G0 X0. Y0. Z1.", "G1 Z-1. F800.", *rows, "G0 X30. Y-30. Z5.", "G0 Z-5."], [*_STOCK, "G43 H01 Z50.", "S1000 M03"])
    assert _arcs_in_runs(program) >= 10
    _assert_same_findings(program)
    crashes = [d.span.line for d in check_text(program).diagnostics if d.rule == "core.rapid-into-stock" and d.status.value == "violated"]
    assert len(crashes) >= 3 and crashes[-1] == len(program.splitlines()) - 1  # rapids down into the blank beside the cuts, and the last one


@given(rows=st.lists(st.lists(st.booleans(), min_size=4, max_size=4), max_size=40), columns=st.integers(1, 4))
def test_any_in_row_is_numpys_any_along_rows(rows, columns):
    """The column-by-column reduction the batch and the run handlers use."""
    import numpy

    from ncverify.trace import any_in_row

    mask = numpy.array(rows, dtype=bool).reshape(len(rows), 4)[:, :columns]
    found = any_in_row(mask)
    assert found.dtype == bool and numpy.array_equal(found, mask.any(axis=1))
    assert not numpy.shares_memory(found, mask)


_HEIGHT = st.integers(1, 9).map(lambda z: f"{z}.")
# low moves across the plane and lifts along Z alone: a lift before a move across is no cut
# at its height, the end of the move across is
_RAMP = st.lists(st.one_of(st.tuples(st.integers(0, 3), st.integers(0, 1), st.integers(1, 4)).map(lambda move: "X{}. Y{}. Z{}.".format(*move)),
                           _HEIGHT.map(lambda z: f"Z{z}")), min_size=40, max_size=60)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(start=_HEIGHT, ramp=_RAMP, lift=_HEIGHT)
def test_the_highest_cut_of_a_batch_is_the_block_paths(start, ramp, lift):
    """Without a stock a feed move above Z0 with the spindle stopped is judged against the
    highest end of a spindle-on feed move across the plane: a batch's is its moves' ends."""
    _assert_same_findings(_program(["G0 X0. Y0.", "S1000 M03", f"G1 Z{start} F100.", *ramp, "M05", f"G0 Z{lift}", f"G1 X9. Z{lift}"], []))


def _mill_then_drill(parts: int) -> str:
    """Parts milled with T1 (a zigzag whose corners no merge joins) then drilled with T2, part
    after part: the tools take turns within one buffer of the cut stock."""
    body = []
    for part in range(parts):
        y = 8.0 * part - 30.0
        body += ["T1 M06", "G43 H01 Z20.", "S8000 M03", f"G0 X-30. Y{y:.1f}", "G0 Z1.", "G1 Z-1. F300."]
        body += [f"G1 X{-30.0 + 4.0 * (step + 1):.1f} Y{y + (step % 2) * 2.0:.1f}" for step in range(12)]
        body += ["G0 Z20.", "T2 M06", "G43 H02 Z20.", "S3000 M03", f"G98 G81 X-20. Y{y + 1.0:.1f} Z-5. R1. F150.", f"X-10. Y{y + 1.0:.1f}", "G80"]
    return _program(body, [_STOCK[0], "(ncverify: tool 1 radius 3 length 50 type endmill)", "(ncverify: tool 2 radius 2 length 60 type drill)"])


def test_a_buffer_where_the_tools_take_turns_is_swept_once_a_tool_leaving_the_field_move_by_move_sweeps_leave(monkeypatch):
    """Milling and drilling part after part: the buffered lines are swept in one sweep a
    tool, and the field left is the one that sweeping every move on its own, in program
    order, leaves (sweeps only lower the bounds)."""
    from ncverify import material, workpiece

    swept = []
    cut = workpiece.Workpiece.cut

    def recorded(piece, starts, ends, cutter, *rest, **options):
        swept.append((piece, len(numpy.atleast_2d(starts)), cutter.radius))
        return cut(piece, starts, ends, cutter, *rest, **options)

    monkeypatch.setattr(workpiece.Workpiece, "cut", recorded)
    program = _mill_then_drill(5)
    check_text(program)
    by_tool = [(moves, radius) for _, moves, radius in swept]
    assert by_tool == [(5 * 13, 3.0), (5 * 2, 2.0)]  # 12 zigzag moves and the plunge a part, two plunges
    field = swept[-1][0]

    swept.clear()
    monkeypatch.setattr(material, "_by_tool", lambda buffered, key_from: [(entry[key_from:], [entry]) for entry in buffered])
    check_text(program)
    assert len(swept) == 5 * (13 + 2)
    field.settle()
    swept[-1][0].settle()
    assert numpy.array_equal(field.upper, swept[-1][0].upper) and numpy.array_equal(field.lower, swept[-1][0].lower)
