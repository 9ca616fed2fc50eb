"""Moves the block path makes one by one (loops, macros, lines no batch reads) are gathered
and handed to the rules as one run; every finding, span, witness, block and path count must
be the same as handing them on one by one."""
from __future__ import annotations

from unittest import mock

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ncverify import Settings, check_text
from ncverify.check import Checker

_STOCK = ["(ncverify: stock box X-40:40 Y-40:40 Z-10:0)", "(ncverify: tool 1 radius 3 length 50 type endmill)"]


def _findings(program: str, path: str, **options) -> tuple:
    result = check_text(program, path, Settings(**options))
    return [(d.rule, d.status, d.span, d.message, d.witness) for d in result.diagnostics], result.blocks, result.paths


def _assert_same(program: str, path: str, **options) -> None:
    assert _findings(program, path, **options) == _findings(program, path, per_block_only=True, **options)


def _runs_handed_on(program: str, path: str, **options) -> list[int]:
    """The length of every run the checker is handed."""
    lengths = []
    original = Checker.motion_run

    def counting(checker, run, state):
        lengths.append(len(run))
        return original(checker, run, state)

    with mock.patch.object(Checker, "motion_run", counting):
        check_text(program, path, Settings(**options))
    return lengths


# ------------------------------------------------------------------ LinuxCNC O-word loops

_NAMES = ["#<i>", "#<a>", "#<b>"]
_CONSTANT = st.one_of(st.integers(-20, 20).map(str), st.floats(-20, 20, allow_nan=False).map(lambda v: f"{v:.3f}"))
_LEAF = st.one_of(_CONSTANT, st.sampled_from(_NAMES))


def _expression(leaf, functions=("SIN", "FIX", "ABS", "COS")):
    return st.recursive(leaf, lambda inner: st.one_of(
        st.tuples(inner, st.sampled_from(["+", "-", "*", "/", "MOD"]), inner).map(lambda p: f"[{p[0]} {p[1]} {p[2]}]"),
        st.tuples(st.sampled_from(functions), inner).map(lambda p: f"{p[0]}[{p[1]}]")), max_leaves=4)


_EXPRESSION = _expression(_LEAF)
_AXES = st.lists(st.sampled_from("XYZ"), unique=True, min_size=1, max_size=3)
_LINUXCNC_MOVE = st.tuples(st.sampled_from(["G0", "G1", ""]), _AXES.flatmap(
    lambda axes: st.tuples(*[_EXPRESSION.map(lambda e, a=a: f"{a}[{e}]") for a in axes]))).map(lambda p: " ".join([p[0], *p[1]]).strip())
_LINUXCNC_ARC = st.tuples(st.sampled_from(["G2", "G3"]), _EXPRESSION, _EXPRESSION, st.one_of(
    st.tuples(_CONSTANT, _CONSTANT).map(lambda c: f"I{c[0]} J{c[1]}"), st.sampled_from(["R5.", "R-5.", "R0.5", "R30."]))).map(
    lambda p: f"{p[0]} X[{p[1]}] Y[{p[2]}] {p[3]}")
_LINUXCNC_BODY_LINE = st.one_of(
    _LINUXCNC_MOVE, _LINUXCNC_MOVE, _LINUXCNC_ARC,
    st.tuples(st.sampled_from(_NAMES[1:]), _EXPRESSION).map(lambda p: f"{p[0]} = {p[1]}"),
    st.sampled_from(["F300.", "G1 X1. F0", "M5", "M3 S1000", "G91", "G90", "G18", "G17", "G41", "G40", "G4 P0.1", "(comment)",
                     "#<a> = #<nowhere>", "G0 X#<nowhere>", "o300 if [#<i> MOD 3 EQ 0]\nG0 Z5.\no300 endif",
                     "o301 if [#<i> GT 2]\no100 break\no301 endif", "G92 X0", "G92.1", "G53 G0 Z0", "G28"]),
)


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(_LINUXCNC_BODY_LINE, min_size=1, max_size=8), passes=st.integers(0, 40),
       after=st.lists(_LINUXCNC_BODY_LINE, max_size=4), stock=st.booleans(), loop_bound=st.sampled_from([5, 1000]))
def test_linuxcnc_loops_give_the_same_findings_gathered_or_one_by_one(body, passes, after, stock, loop_bound):
    program = "\n".join([*(_STOCK if stock else []), "G21 G90 G17 G54", "T1 M6", "G43 H1", "S1000 M3", "G0 X0 Y0 Z5", "F500.",
                         "#<i> = 0", "#<a> = 1", "#<b> = 2", f"o100 while [#<i> LT {passes}]", *body, "#<i> = [#<i> + 1]",
                         "o100 endwhile", *after, "G0 Z50", "M2"]) + "\n"
    _assert_same(program, "t.ngc", dialect="linuxcnc", loop_bound=loop_bound)


# ------------------------------------------------------------------ Fanuc macro B: WHILE, GOTO, free parameters

_FANUC_LEAF = st.one_of(_CONSTANT, st.sampled_from(["#1", "#2", "#3", "#500"]))  # #500: a free parameter (forks)
_FANUC_EXPRESSION = _expression(_FANUC_LEAF, ("SIN", "FIX", "ABS"))
_FANUC_MOVE = st.tuples(st.sampled_from(["G0", "G1", "G01", ""]), _AXES.flatmap(
    lambda axes: st.tuples(*[_FANUC_EXPRESSION.map(lambda e, a=a: f"{a}[{e}]") for a in axes]))).map(lambda p: " ".join([p[0], *p[1]]).strip())
_FANUC_BODY_LINE = st.one_of(
    _FANUC_MOVE, _FANUC_MOVE, st.sampled_from(["G1 X1. Y2.", "G0 Z5.", "X3. Y-4.", "G2 X0 Y0 I5. J0", "G3 X10. Y0 R5."]),
    st.tuples(st.sampled_from(["#2", "#3"]), _FANUC_EXPRESSION).map(lambda p: f"{p[0]} = {p[1]}"),
    st.sampled_from(["IF [#500 GT #1] THEN #3 = 1", "IF [#1 EQ 2] GOTO 90", "IF [#500 LT 0] GOTO 90", "F0", "F200.", "M05", "G91", "G90",
                     "#3 = #1 / #500", "G0 X#7", "G52 X1.", "G68 X0 Y0 R30.", "G69", "G81 X1. Y1. Z-2. R1. F100.", "G80", "N90"]),
)


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(_FANUC_BODY_LINE, min_size=1, max_size=8), passes=st.integers(0, 10), stock=st.booleans(),
       loop_bound=st.sampled_from([4, 1000]), max_paths=st.sampled_from([2, 64]))
def test_fanuc_loops_with_jumps_and_forks_give_the_same_findings_gathered_or_one_by_one(body, passes, stock, loop_bound, max_paths):
    program = "\n".join(["O1000", *(_STOCK if stock else []), "G21 G90 G17 G54", "T1 M06", "G43 H01 Z50.", "S1000 M03", "G0 X0 Y0", "F300.",
                         "#1 = 0", "#2 = 1", f"WHILE [#1 LT {passes}] DO1", *body, "#1 = #1 + 1", "END1", "G0 Z50.", "M30"]) + "\n"
    _assert_same(program, "t.nc", loop_bound=loop_bound, max_paths=max_paths)


# ------------------------------------------------------------------ SINUMERIK and Klartext loops

_SINUMERIK_BODY_LINE = st.one_of(
    st.sampled_from(["G1 X=R1 Y=R2", "G0 Z=R1", "G1 X=R1*2 Y=R2-3 Z=-1", "G2 X=R1 Y=R2 CR=5", "G3 X=R1 Y=R2 I=2 J=0", "R2=R2+1.5",
                     "R2=R2*R1", "F500", "G91", "G90", "M5", "D2", "G1 X=R3", "TRANS X1", "ROT RPL=10"]))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(_SINUMERIK_BODY_LINE, min_size=1, max_size=6), passes=st.integers(0, 8), stock=st.booleans())
def test_sinumerik_loops_give_the_same_findings_gathered_or_one_by_one(body, passes, stock):
    program = "\n".join([*(_STOCK if stock else []), "G17 G90 G71 G54", "T1 D1", "M6", "S1000 M3", "G0 X0 Y0 Z5", "F300", "R1=0", "R2=0",
                         f"WHILE R1<{passes}", *body, "R1=R1+1", "ENDWHILE", "G0 Z50", "M30"]) + "\n"
    _assert_same(program, "t.mpf", dialect="sinumerik")


_KLARTEXT_BODY_LINE = st.sampled_from(["L IX+2 IY+1 R0 F500", "L X+5 Y+5 Z-1", "L IZ-0.5 FMAX", "CC X+0 Y+0", "C X+5 Y+0 DR-",
                                       "CR X+0 Y+5 R+5 DR+", "L X+Q1 Y+Q2", "FN 1: Q2 = Q2 + 1", "L X+Q2 RL F300", "L X+0 R0",
                                       "M5", "M3", "CYCL DEF 7.0 DATUM SHIFT", "CYCL DEF 7.1 X+1", "L X+4 Y+4 R0 FMAX M99",
                                       "L X+8 Y+4 R0 FMAX M89", "L X+8 FMAX", "L IY+3 F200", "CYCL DEF 200 DRILLING Q200=+2 Q201=-5 Q206=+150 "
                                       "Q202=+5 Q210=+0 Q203=+0 Q204=+15 Q211=+0"])


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(_KLARTEXT_BODY_LINE, min_size=1, max_size=8), repeats=st.integers(0, 6), cycle=st.booleans())
def test_klartext_label_repeats_give_the_same_findings_gathered_or_one_by_one(body, repeats, cycle):
    """Positioning lines keep the moves gathered unless an M89 cycle waits on positions or a
    cycle's end needs the next positioning checked."""
    drilling = ["CYCL DEF 200 DRILLING Q200=+2 Q201=-5 Q206=+150 Q202=+5 Q210=+0 Q203=+0 Q204=+15 Q211=+0", "L X+1 Y+1 R0 FMAX M99"]
    lines = ["BEGIN PGM T MM", "BLK FORM 0.1 Z X-40 Y-40 Z-10", "BLK FORM 0.2 X+40 Y+40 Z+0", "TOOL CALL 1 Z S1000", "L Z+50 R0 FMAX M3",
             *(drilling if cycle else []), "FN 0: Q1 = 3", "FN 0: Q2 = 0", "LBL 1", *body, "CALL LBL 1 REP " + str(repeats),
             "L Z+50 R0 FMAX", "M30", "END PGM T MM"]
    program = "\n".join(f"{number} {line}" for number, line in enumerate(lines)) + "\n"
    _assert_same(program, "t.h")


# ------------------------------------------------------------------ straight-line code into the stock

_POCKET_MOVE = st.tuples(st.sampled_from(["G0", "G1", "G00", "G01", "", "G2", "G3"]), st.integers(0, 100), st.integers(0, 60), st.integers(-6, 3),
                         st.sampled_from(["", " F600.", " F0"])).map(
    lambda p: f"{p[0]} X{p[1]}. Y{p[2]}. Z{p[3]}.{' R30.' if p[0] in ('G2', 'G3') else ''}{p[4]}".strip())


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(moves=st.lists(st.one_of(_POCKET_MOVE, _POCKET_MOVE, _POCKET_MOVE, st.sampled_from(["M05", "M03", "G91", "G90", "Z2.", "X50."])),
                      min_size=3, max_size=14), first=st.sampled_from(["G43 H01 Z50.", "G43 H01 X0 Y0 Z50.", "G0 Y5. X5."]),
       passes=st.integers(1, 6))
def test_cuts_and_rapids_in_the_stock_give_the_same_findings_gathered_or_one_by_one(moves, first, passes):
    """Cuts, then rapids through what they left (the cut stock), with the axes first set in
    any order (a run's columns are X, Y, Z whatever the order the position was set in), as
    short runs (one by one) and, repeated by a loop, long ones."""
    program = "\n".join(["O1", "(ncverify: stock box X0:100 Y0:60 Z-20:0)", "(ncverify: tool 1 radius 5 length 60 type endmill)",
                         "G21 G90 G17 G40 G49 G80 G54", "T1 M06", first, "S6000 M03", "G00 X35. Y20.", "Z2.", "G01 Z-5. F150.", "#1 = 0",
                         f"WHILE [#1 LT {passes}] DO1", *moves, "#1 = #1 + 1", "END1", "G00 Z50.", "M30"]) + "\n"
    _assert_same(program, "t.nc")


# ------------------------------------------------------------------ the gathering itself

_LOOP = "\n".join(["G21 G90 G17 G54", "T1 M6", "G43 H1", "S1000 M3", "G0 X0 Y0 Z5", "G1 Z-1 F500", "#<i> = 0", "o100 while [#<i> LT 50]",
                   "#<x> = [[#<i> MOD 10] * 0.5]", "G1 X#<x> Y[FIX[#<i> / 10]]", "G2 X[#<x> + 1] Y0 I0.5 J0", "#<i> = [#<i> + 1]",
                   "o100 endwhile", "G0 Z50", "M2"]) + "\n"


def test_the_moves_of_a_loop_reach_the_rules_as_runs():
    """A loop's moves, lines and arcs, are handed on together, not one by one."""
    assert sum(_runs_handed_on(_LOOP, "t.ngc", dialect="linuxcnc")) >= 100
    assert not _runs_handed_on(_LOOP, "t.ngc", dialect="linuxcnc", per_block_only=True)


def test_a_move_to_a_free_parameter_is_handed_on_alone():
    """A move whose end depends on a free parameter (#500) is not gathered: runs carry numbers."""
    program = "\n".join(["O1000", "G21 G90 G17 G54", "T1 M06", "G43 H01 Z50.", "S1000 M03", "G0 X0 Y0", "G1 Z-1. F300.", "#1 = 0",
                         "WHILE [#1 LT 50] DO1", "G1 X#1 Y#500", "#1 = #1 + 1", "END1", "M30"]) + "\n"
    assert sum(_runs_handed_on(program, "t.nc")) < 5
    assert sum(_runs_handed_on(program.replace("Y#500", "Y1."), "t.nc")) > 50


def test_feed_words_keep_the_moves_gathered():
    """A feed word between the moves, or on each move's line, changes only the feed, which
    every gathered move carries: the loop's moves still reach the rules as runs, and what
    they find is what the moves one by one find (a feed of zero among them)."""
    program = "\n".join(["O1000", "G21 G90 G17 G54", "T1 M06", "G43 H01 Z50.", "S1000 M03", "G0 X0 Y0", "G1 Z-1. F300.", "#1 = 0",
                         "WHILE [#1 LT 50] DO1", "G1 X#1 Y1. F[200 + #1]", "F0", "G1 Y2.", "F500.", "#1 = #1 + 1", "END1", "M30"]) + "\n"
    assert sum(_runs_handed_on(program, "t.nc")) >= 100
    _assert_same(program, "t.nc")


def test_klartext_positioning_lines_keep_the_moves_gathered():
    """A Klartext line's positioning step changes nothing a rule reads while no cycle waits
    on it: the lines' moves reach the rules together."""
    lines = ["BEGIN PGM T MM", "TOOL CALL 1 Z S1000", "L Z+50 R0 FMAX M3", "L X+0 Y+0 R0 F500",
             *[line for n in range(1, 41) for line in (f"FN 0: Q1 = {n}", f"L X+Q1 Y+{n % 3}")], "M30", "END PGM T MM"]  # no batch reads them
    program = "\n".join(f"{number} {line}" for number, line in enumerate(lines)) + "\n"
    assert _runs_handed_on(program, "t.h") == [41]  # from the line with F500 on


def test_gathered_runs_stay_short_in_a_long_loop():
    """Memory stays flat: a long loop's moves are handed on in runs of bounded length."""
    program = _LOOP.replace("LT 50", "LT 3000")
    lengths = _runs_handed_on(program, "t.ngc", dialect="linuxcnc", loop_bound=10_000)
    assert sum(lengths) >= 6000 and max(lengths) <= 4096


# ------------------------------------------------------------------ Klartext contours: lines, CC, C, CR, CT under compensation

_KLARTEXT_NUMBER = st.integers(-30, 30).map(lambda v: f"{v:+d}")
_KLARTEXT_POINT = st.tuples(st.sampled_from(["X", "IX"]), _KLARTEXT_NUMBER, st.sampled_from(["Y", "IY"]), _KLARTEXT_NUMBER).map(
    lambda p: f"{p[0]}{p[1]} {p[2]}{p[3]}")
_KLARTEXT_DEPTH = st.sampled_from(["", "", " Z-1", " Z-2", " IZ-0.5", " Z+Q5"])  # Q5: read from the machine (symbolic)
_KLARTEXT_TAIL = st.sampled_from(["", "", "", " RL", " RR", " R0", " F200", " FMAX", " RR F800", " M3"])
_KLARTEXT_CONTOUR_LINE = st.one_of(
    st.tuples(_KLARTEXT_POINT, _KLARTEXT_DEPTH, _KLARTEXT_TAIL).map(lambda p: f"L {p[0]}{p[1]}{p[2]}"),
    st.tuples(_KLARTEXT_POINT, _KLARTEXT_DEPTH, st.sampled_from(["DR-", "DR+"]), _KLARTEXT_TAIL).map(lambda p: f"C {p[0]}{p[1]} {p[2]}{p[3]}"),
    st.tuples(_KLARTEXT_POINT, st.sampled_from(["R+6", "R-6", "R+40", "R+0.5"]), st.sampled_from(["DR-", "DR+"]), _KLARTEXT_TAIL).map(
        lambda p: f"CR {p[0]} {p[1]} {p[2]}{p[3]}"),
    st.tuples(_KLARTEXT_POINT, _KLARTEXT_DEPTH, _KLARTEXT_TAIL).map(lambda p: f"CT {p[0]}{p[1]}{p[2]}"),
    _KLARTEXT_POINT.map(lambda p: f"CC {p}"),
    st.sampled_from(["CC", "CC Y+0 Z+0", "C Y+5 Z-1 DR+", "CC X+Q5 Y+0", "C X+Q5 Y+3 DR-", "CT X+Q1 Y+Q2", "L X+Q5 Y+0",
                     "CP IPA+90 DR+", "LP PR+10 PA+45", "RND R2", "FN 1: Q1 = Q1 + 1", "FN 0: Q2 = Q1 * 2",
                     "FN 12: IF +Q1 LT +Q5 GOTO LBL 3", "FN 9: IF +Q1 EQU +5 GOTO LBL 3", "L X+4 Y+4 R0 FMAX M99",
                     "L X+8 Y+4 R0 FMAX M89", "CYCL DEF 7.0 DATUM SHIFT", "CYCL DEF 7.1 X+1", "M5", "TOOL CALL 1 Y S1000",
                     "CYCL DEF 200 DRILLING Q200=+2 Q201=-5 Q206=+150 Q202=+5 Q210=+0 Q203=+0 Q204=+15 Q211=+0"]),
)


def _klartext_contour_program(contour: list, passes: int, repeats: int, stock: bool) -> str:
    """The contour written ``passes`` times over in a label section, run once more per repeat."""
    lines = ["BEGIN PGM T MM", *(["BLK FORM 0.1 Z X-40 Y-40 Z-10", "BLK FORM 0.2 X+40 Y+40 Z+0"] if stock else []),
             "TOOL CALL 1 Z S1000", "L Z+50 R0 FMAX M3", "FN 0: Q1 = 3", "FN 0: Q2 = 0", "FN 18: SYSREAD Q5 = ID20 NR1",
             "L X+0 Y+0 R0 FMAX", "L Z+2 R0 FMAX", "L Z-1 F300", "LBL 1", *contour * passes, "CALL LBL 1 REP " + str(repeats), "LBL 3",
             "L Z+50 R0 FMAX", "M30", "END PGM T MM"]
    return "\n".join(f"{number} {line}" for number, line in enumerate(lines)) + "\n"


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(contour=st.lists(_KLARTEXT_CONTOUR_LINE, min_size=1, max_size=12), passes=st.integers(1, 8), repeats=st.integers(0, 3),
       stock=st.booleans())
def test_klartext_contours_with_arcs_give_the_same_findings_gathered_or_one_by_one(contour, passes, repeats, stock):
    """Arcs about CC (C), by radius (CR) and tangential (CT) join the gathered lines, and CC
    keeps them gathered: with the compensation on or off, M89/M99 cycles, FN jumps (free
    ones fork), coordinates from a parameter read from the machine, a frame, a plane change,
    arcs in another plane than the run's, the cut stock: the same as one by one."""
    _assert_same(_klartext_contour_program(contour, passes, repeats, stock), "t.h")


def test_a_compensated_klartext_contour_reaches_the_rules_as_runs():
    """A CAM post's contour under RR, lines between arcs about CC, by radius and tangential,
    is handed on in long runs; with an arc about a pole read from the machine, that arc
    goes alone and the moves around it still as runs."""
    passes = [line for depth in range(1, 9) for line in (
        f"L X+0 Y+34 Z-{depth}", "CC X+6 Y+34", "C X+6 Y+40 DR-", "L X+34 Y+40", "CR X+40 Y+34 R+6 DR-", "L X+40 Y+6",
        "CT X+34 Y+0", "L X+6 Y+0", "CC X+6 Y+6", "C X+0 Y+6 DR-")]
    lines = ["BEGIN PGM T MM", "BLK FORM 0.1 Z X-20 Y-20 Z-20", "BLK FORM 0.2 X+60 Y+60 Z+0", "TOOL CALL 1 Z S8000", "L Z+50 R0 FMAX M3",
             "FN 18: SYSREAD Q5 = ID20 NR1", "L X-10 Y+20 R0 FMAX", "L Z+0 R0 F300", "L X+0 Y+20 RR F800", *passes, "L Z+50 R0 FMAX",
             "M30", "END PGM T MM"]
    program = "\n".join(f"{number} {line}" for number, line in enumerate(lines)) + "\n"
    assert _runs_handed_on(program, "t.h") == [8 * 8 + 1]  # the moves from RR on, not counting CC
    symbolic = _runs_handed_on(program.replace("CC X+6 Y+6", "CC X+Q5 Y+6", 1), "t.h")
    assert symbolic[0] == 8 * 8 + 1 - 9  # the 8 moves before it went one by one (a replay of a witness may follow, Q5 pinned)
    _assert_same(program, "t.h")


def test_klartext_arcs_in_two_planes_never_share_a_run():
    """A run holds one plane for its arcs: an arc about a CC given in Y and Z (a YZ arc)
    among arcs in XY goes alone, and the arcs of every run handed on, gathered or read as
    a batch, lie in its plane."""
    corner = ["L X+0 Y+5", "CC X+0 Y+0", "C X+5 Y+0 DR-", "CR X+0 Y+5 R+5 DR+"]
    contour = [*corner * 12, "CC Y+0 Z+0", "C Y+5 Z-1 DR+", *corner * 12]
    program = _klartext_contour_program(contour, 1, 0, True)
    mixed, planes = [], set()
    original = Checker.motion_run

    def planes_checked(checker, run, state):
        mixed.extend(index for index in run.arc_indices() if run.segment(index).arc.plane != run.arcs.plane)
        planes.update(run.segment(index).arc.plane for index in run.arc_indices())
        return original(checker, run, state)

    with mock.patch.object(Checker, "motion_run", planes_checked):
        check_text(program, "t.h", Settings())
    assert not mixed and planes == {("X", "Y", "Z")}  # the YZ arc goes alone
    assert sum(_runs_handed_on(program, "t.h")) >= 60  # most of the 72 XY arcs and lines in runs
    _assert_same(program, "t.h")
