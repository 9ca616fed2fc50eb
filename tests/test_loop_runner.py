"""A loop pass that runs straight through is run by one generated function
(``interpret/loop_runner.py``); every report, its findings, spans, witnesses, counts of blocks
and paths, the air cutting and the cut stock, must be the one the block path gives pass by
pass, in every dialect, and wherever the runner cannot take a pass (a vacant or symbolic
value, a fault, a test that branches, the loop bound, the analysis budget) the block path
takes it from there."""
from __future__ import annotations

from unittest import mock

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ncverify import Settings, check_text
from ncverify.check import Checker
from ncverify.interpret import loop_runner
from ncverify.report import render_json

_STOCK = ["(ncverify: stock box X-40:40 Y-40:40 Z-10:0)", "(ncverify: tool 1 radius 3 length 50 type endmill)"]


def _report(program: str, path: str, **options) -> tuple:
    """The JSON report, the counts of blocks and paths, and every move, run, change and
    fault the checker was handed, with the state it saw each in; of a run also each of its
    segments as the rules may ask for it, and at each path's end the last segment (which a
    tangential arc continues), positions with their axes in order."""
    events = []

    def value(value):  # a symbolic value by its bounds: printing its term costs more than the check
        return repr(value) if type(value) is float or value is None else (type(value).__name__, getattr(value, "low", None), getattr(value, "high", None))

    def values(table: dict) -> list:
        return sorted((name, value(held)) for name, held in table.items())

    def in_order(table: dict) -> list:
        return [(name, value(held)) for name, held in table.items()]

    def made(segment) -> tuple:
        arc = segment.arc and (segment.arc.direction, segment.arc.plane, [value(held) for held in segment.arc.centre or ()],
                               value(segment.arc.radius_word))
        return in_order(segment.start), in_order(segment.end), segment.kind, segment.span, segment.block.span, segment.role, segment.cycle, arc

    def seen(state) -> tuple:
        return (values(state.position), state.modal.get("motion"), value(state.feed), values(state.local_variables),
                values(state.global_variables), sorted((key[1:], count) for key, count in state.jump_counts.items()),
                [(loop.loop_id, loop.iterations) for loop in state.loops])

    def recording(name, record):
        original = getattr(Checker, name)

        def handler(checker, *arguments):
            events.append((name, record(*arguments)))
            return original(checker, *arguments)

        return mock.patch.object(Checker, name, handler)

    def run_record(run, state):
        spans = [run.span(index) for index in range(len(run))]
        segments = [made(run.segment(index)) for index in reversed(range(len(run)))]  # in any order: each is made on its own
        return run.points.tobytes(), run.kinds.tobytes(), run.feeds.tobytes(), run.written.tobytes(), spans, segments, seen(state)

    def path_end(state):
        return in_order(state.position), None if state.last_segment is None else made(state.last_segment), state.motion_seen, seen(state)

    with (recording("segment", lambda segment, state: (values(segment.start), values(segment.end), segment.kind, segment.span, seen(state))),
          recording("motion_run", run_record),
          recording("change", lambda change, state: (change.what, change.span, value(change.old), value(change.new), seen(state))),
          recording("fault", lambda fault: (fault.rule, fault.span, fault.message, fault.status)),
          recording("path_end", path_end)):
        result = check_text(program, path, Settings(air_cutting=True, **options))  # the air statistic too
    return render_json([result], []), result.blocks, result.paths, events


def _assert_same(program: str, path: str, **options) -> None:
    assert _report(program, path, **options) == _report(program, path, loop_runner=False, **options)


def _passes_run(program: str, path: str, **options) -> int:
    """How many loop passes the generated functions ran."""
    counted = []
    original = loop_runner._PassCode.function

    def counting(code):
        run = original(code)
        if run is False:
            return run

        def counted_run(*arguments):
            passes = run(*arguments)
            counted.append(passes)
            return passes

        return counted_run

    with mock.patch.object(loop_runner._PassCode, "function", counting):
        check_text(program, path, Settings(**options))
    return sum(counted)


# ------------------------------------------------------------------ LinuxCNC O-word loops

_NAMES = ["#<i>", "#<a>", "#<b>", "#<_g>", "#<nowhere>", "#5"]  # #<nowhere> is never set: vacant
_CONSTANT = st.one_of(st.integers(-20, 20).map(str), st.floats(-20, 20, allow_nan=False).map(lambda v: f"{v:.3f}"),
                      st.sampled_from(["0", "1e200", "-1e300", "1e-300"]))
_LEAF = st.one_of(_CONSTANT, st.sampled_from(_NAMES[:4]), st.sampled_from(_NAMES))


def _expression(leaf, functions=("SIN", "FIX", "ABS", "SQRT", "COS", "ROUND")):
    return st.recursive(leaf, lambda inner: st.one_of(
        st.tuples(inner, st.sampled_from(["+", "-", "*", "/", "MOD", "**", "LT", "GE", "EQ"]), inner).map(lambda p: f"[{p[0]} {p[1]} {p[2]}]"),
        st.tuples(st.sampled_from(functions), inner).map(lambda p: f"{p[0]}[{p[1]}]"),
        inner.map(lambda e: f"-{e}")), max_leaves=5)


_EXPRESSION = _expression(_LEAF)
_AXES = st.lists(st.sampled_from("XYZA"), unique=True, min_size=1, max_size=3)
_LINUXCNC_MOVE = st.tuples(st.sampled_from(["G0", "G1", "", "", "G91 G1"]), _AXES.flatmap(
    lambda axes: st.tuples(*[_EXPRESSION.map(lambda e, a=a: f"{a}[{e}]") for a in axes]))).map(lambda p: " ".join([p[0], *p[1]]).strip())
_STRAIGHT_MOVE = st.tuples(st.sampled_from(["G0", "G1", ""]), _AXES.flatmap(lambda axes: st.tuples(*[st.tuples(
    st.sampled_from(["#<i>", "#<a>", "#<_g>"]), st.sampled_from("+-*"), st.integers(-3, 3)).map(lambda p, a=a: f"{a}[{p[0]} {p[1]} {p[2]}]")
    for a in axes]))).map(lambda p: " ".join([p[0], *p[1]]).strip())  # a move the runner takes
_LINUXCNC_ASSIGNMENT = st.tuples(st.sampled_from(_NAMES[1:4] + ["#5"]), _EXPRESSION).map(lambda p: f"{p[0]} = {p[1]}")
_LINUXCNC_PLAIN = st.one_of(_LINUXCNC_MOVE, _LINUXCNC_MOVE, _LINUXCNC_ASSIGNMENT, _LINUXCNC_ASSIGNMENT)
_LINUXCNC_BODY_LINE = st.one_of(
    _LINUXCNC_PLAIN, _LINUXCNC_PLAIN, _LINUXCNC_PLAIN,
    st.tuples(_EXPRESSION, st.lists(_LINUXCNC_PLAIN, min_size=1, max_size=3)).map(  # a branch the runner hands back when it is not taken
        lambda p: "\n".join([f"o200 if [{p[0]}]", *p[1], "o200 endif"])),
    st.sampled_from(["G2 X1 Y1 R5", "F300.", "G1 X1. F0", "M5", "M3 S1000", "G91", "G90", "G92 X0", "G92.1", "G4 P0.1", "(comment)",
                     "o300 if [#<i> MOD 3 EQ 0]\nG0 Z5.\no300 else\nG0 Z4.\no300 endif", "o301 if [#<i> GT 2]\no100 break\no301 endif",
                     "G1 X1 Y2 Z3 X4", "G1 X#<nowhere>", "G0 X1e300", "#<b> = 0", "G1 X[1 / #<b>]", "G53 G0 Z0", "G28"]),
)


# set before the loop: incremental distances, a coordinate shift or offset (the moves reach the
# rules through the workpiece frame, one by one), a parked axis, a modal cycle, a motion mode
_LINUXCNC_BEFORE = st.sampled_from(["", "", "G91", "G92 X1 Y1", "G52 X2", "G28", "G81 X0 Y0 Z-1 R1", "G0", "G2 X1 Y0 R5", "G18", "G20",
                                    "F[#<a> - 1]"])


@settings(max_examples=250, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(_LINUXCNC_BODY_LINE, min_size=1, max_size=8), passes=st.integers(0, 40), form=st.sampled_from(["while", "do"]),
       before=_LINUXCNC_BEFORE, after=st.lists(_LINUXCNC_BODY_LINE, max_size=3), stock=st.booleans(), loop_bound=st.sampled_from([3, 7, 1000]))
def test_linuxcnc_loops_report_the_same_with_the_runner_or_pass_by_pass(body, passes, form, before, after, stock, loop_bound):
    """Assignments of MOD, FIX, SIN ..., divisions by zero, vacant reads, values past the float
    range, moves in any mode and axes, tests, branches that hand the pass back, the loop bound."""
    loop = ([f"o100 while [#<i> LT {passes}]", *body, "#<i> = [#<i> + 1]", "o100 endwhile"] if form == "while"
            else ["o100 do", *body, "#<i> = [#<i> + 1]", f"o100 while [#<i> LT {passes}]"])
    program = "\n".join([*(_STOCK if stock else []), "G21 G90 G17 G54", "T1 M6", "G43 H1", "S1000 M3", "G0 X0 Y0 Z5", "F500.",
                         "#<i> = 0", "#<a> = 1", "#<b> = 2", "#<_g> = 3", before, *loop, *after, "G0 Z50", "M2"]) + "\n"
    _assert_same(program, "t.ngc", dialect="linuxcnc", loop_bound=loop_bound)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(st.one_of(_STRAIGHT_MOVE, _STRAIGHT_MOVE, _STRAIGHT_MOVE, _LINUXCNC_BODY_LINE), min_size=1, max_size=6), passes=st.integers(0, 40),
       before=_LINUXCNC_BEFORE, sizes=st.sampled_from([(3, 1), (7, 3), (16, 32), (5, 5)]), stock=st.booleans(),
       start=st.sampled_from(["G0 X0 Y0 Z5", "G0 Z5", ""]))
def test_gathered_moves_handed_on_within_a_pass_report_the_same(body, passes, before, sizes, stock, start):
    """With runs of a few moves (the most gathered, the fewest handed on as a run), the
    runner's passes hand their moves on between two moves of a pass, and the moves it
    gathered are made into segments and positions for the rules (run by run or one by one)
    as the block path made them, also where the loop starts with axes not yet moved."""
    program = "\n".join([*(_STOCK if stock else []), "G21 G90 G17 G54", "T1 M6", "G43 H1", "S1000 M3", start, "F500.", "#<i> = 0",
                         "#<a> = 1", "#<b> = 2", "#<_g> = 3", before, f"o100 while [#<i> LT {passes}]", *body, "#<i> = [#<i> + 1]",
                         "o100 endwhile", "G0 Z50", "M2"]) + "\n"
    most, fewest = sizes
    with mock.patch("ncverify.interpret.interpreter._GATHERED_MOVES", most), mock.patch("ncverify.interpret.interpreter._SHORTEST_RUN", fewest):
        _assert_same(program, "t.ngc", dialect="linuxcnc")


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(passes=st.integers(0, 400), lines=st.integers(1, 30))
def test_the_analysis_budget_stops_a_loop_at_the_same_block(passes, lines):
    """The budget of blocks (the program's length plus loop bound x 2000) stops the runner's
    passes where it stops the block path's."""
    program = "\n".join(["G21 G90 G17 G54", "T1 M6", "G43 H1", "G0 X0 Y0 Z5", "F500.", "#<i> = 0", f"o100 while [#<i> LT {passes}]",
                         *[f"G1 X[#<i> + {n}] Y{n}" for n in range(lines)], "#<i> = [#<i> + 1]", "o100 endwhile", "M2"]) + "\n"
    with mock.patch("ncverify.interpret.interpreter.Interpreter.__init__", _small_budget(passes * (lines + 3) // 2)):
        _assert_same(program, "t.ngc", dialect="linuxcnc")


def _small_budget(blocks: int):
    from ncverify.interpret.interpreter import Interpreter

    original = Interpreter.__init__

    def init(self, *arguments, **keywords):
        original(self, *arguments, **keywords)
        self.block_budget = blocks

    return init


# ------------------------------------------------------------------ Fanuc macro B: WHILE/DO/END and GOTO loops

_FANUC_LEAF = st.one_of(_CONSTANT, st.sampled_from(["#1", "#2", "#3", "#500", "#100"]))  # #500: free (symbolic); #100 vacant
_FANUC_EXPRESSION = _expression(_FANUC_LEAF, ("SIN", "FIX", "ABS", "SQRT"))
_FANUC_MOVE = st.tuples(st.sampled_from(["G0", "G1", "G01", "", "G91 G1"]), _AXES.flatmap(
    lambda axes: st.tuples(*[_FANUC_EXPRESSION.map(lambda e, a=a: f"{a}[{e}]") for a in axes]))).map(lambda p: " ".join([p[0], *p[1]]).strip())
_FANUC_BODY_LINE = st.one_of(
    _FANUC_MOVE, _FANUC_MOVE, st.sampled_from(["G1 X1. Y2.", "G0 Z5.", "X3. Y-4.", "G2 X0 Y0 I5. J0"]),
    st.tuples(st.sampled_from(["#2", "#3"]), _FANUC_EXPRESSION).map(lambda p: f"{p[0]} = {p[1]}"),
    st.sampled_from(["IF [#500 GT #1] THEN #3 = 1", "IF [#1 EQ 2] GOTO 90", "IF [#2 GT 100] GOTO 90", "IF [#500 LT 0] GOTO 90", "F200.",
                     "M05", "G91", "G90", "#3 = #1 / #500", "#3 = #1 / [#2 - #2]", "G0 X#7", "G52 X1.", "G81 X1. Y1. Z-2. R1. F100.", "G80",
                     "N90"]),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(_FANUC_BODY_LINE, min_size=1, max_size=8), passes=st.integers(0, 30), form=st.sampled_from(["while", "goto"]),
       stock=st.booleans(), loop_bound=st.sampled_from([4, 1000]), max_paths=st.sampled_from([2, 64]))
def test_fanuc_loops_report_the_same_with_the_runner_or_pass_by_pass(body, passes, form, stock, loop_bound, max_paths):
    loop = ([f"WHILE [#1 LT {passes}] DO1", *body, "#1 = #1 + 1", "END1"] if form == "while"
            else ["N10", *body, "#1 = #1 + 1", f"IF [#1 LT {passes}] GOTO 10"])
    program = "\n".join(["O1000", *(_STOCK if stock else []), "G21 G90 G17 G54", "T1 M06", "G43 H01 Z50.", "S1000 M03", "G0 X0 Y0", "F300.",
                         "#1 = 0", "#2 = 1", *loop, "G0 Z50.", "M30"]) + "\n"
    _assert_same(program, "t.nc", loop_bound=loop_bound, max_paths=max_paths)


# ------------------------------------------------------------------ SINUMERIK, Fagor and Klartext loops

_SINUMERIK_BODY_LINE = st.sampled_from(["G1 X=R1 Y=R2", "G0 Z=R1", "G1 X=R1*2 Y=R2-3 Z=-1", "X=SIN(R1*10) Y=R2/R3", "R2=R2+1.5",
                                        "R2=R2*R1", "R3=R3-1", "R2=SQRT(R3)", "F500", "G91", "G90", "M5", "G1 X=R4", "G2 X=R1 Y=R2 CR=5",
                                        "TRANS X1", "IF R1==2 GOTOF END_L", "END_L:", "G1 X=IC(R2) Y=AC(R1)", "G0 X=AC(R1+1) Z=IC(-1)"])


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(_SINUMERIK_BODY_LINE, min_size=1, max_size=6), passes=st.integers(0, 30), stock=st.booleans(),
       form=st.sampled_from(["while", "repeat", "for"]), before=st.sampled_from(["", "G91", "TRANS X2", "ROT Z30", "DIAMON"]),
       loop_bound=st.sampled_from([5, 1000]))
def test_sinumerik_loops_report_the_same_with_the_runner_or_pass_by_pass(body, passes, stock, form, before, loop_bound):
    loop = {"while": [f"WHILE R1<{passes}", *body, "R1=R1+1", "ENDWHILE"],
            "repeat": ["REPEAT", *body, "R1=R1+1", f"UNTIL R1>={passes}"],
            "for": [f"FOR R5=1 TO {passes}", *body, "R1=R1+1", "ENDFOR"]}[form]
    program = "\n".join([*(_STOCK if stock else []), "G17 G90 G71 G54", "T1 D1", "M6", "S1000 M3", "G0 X0 Y0 Z5", "F300", "R1=0", "R2=0",
                         "R3=2", before, *loop, "G0 Z50", "M30"]) + "\n"
    _assert_same(program, "t.mpf", dialect="sinumerik", loop_bound=loop_bound)


_FAGOR_BODY_LINE = st.sampled_from(["G1 XP1 YP2", "G0 ZP1", "G1 X[P1*2] Y[P2-3] Z-1", "P2=P2+1.5", "P2=P2*P1", "P3=P3-1", "P2=SQRT[P3]",
                                    "F500", "G91", "G90", "M5", "G1 XP4"])


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(_FAGOR_BODY_LINE, min_size=1, max_size=6), passes=st.integers(0, 30), loop_bound=st.sampled_from([5, 1000]))
def test_fagor_loops_report_the_same_with_the_runner_or_pass_by_pass(body, passes, loop_bound):
    program = "\n".join(["G71 G90 G17 G54", "T1 D1", "M6", "S1000 M3", "G0 X0 Y0 Z5", "F300", "P1=0", "P2=0", "P3=2",
                         f"$WHILE P1<{passes}", *body, "P1=P1+1", "$ENDWHILE", "G0 Z50", "M30"]) + "\n"
    _assert_same(program, "t.pim", dialect="fagor", loop_bound=loop_bound)


_KLARTEXT_BODY_LINE = st.sampled_from(["L X+Q1 Y+Q2 F500", "L Z+Q1", "L IX+2 IY+1", "FN 1: Q2 = Q2 + 1.5", "FN 3: Q2 = Q2 * Q1",
                                       "FN 2: Q3 = Q3 - 1", "FN 5: Q2 = SQRT Q3", "FN 4: Q4 = Q1 DIV Q3", "L X+Q4", "L X+Q9", "M5",
                                       "FN 9: IF +Q1 EQU +2 GOTO LBL 3", "CC X+0 Y+0", "C X+5 Y+0 DR-"])


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(_KLARTEXT_BODY_LINE, min_size=1, max_size=6), passes=st.integers(0, 30), stock=st.booleans(),
       loop_bound=st.sampled_from([5, 1000]))
def test_klartext_jump_loops_report_the_same_with_the_runner_or_pass_by_pass(body, passes, stock, loop_bound):
    lines = ["BEGIN PGM T MM", *(["BLK FORM 0.1 Z X-40 Y-40 Z-10", "BLK FORM 0.2 X+40 Y+40 Z+0"] if stock else []),
             "TOOL CALL 1 Z S1000", "L Z+50 R0 FMAX M3", "FN 0: Q1 = 0", "FN 0: Q2 = 0", "FN 0: Q3 = 2", "L X+0 Y+0 R0 FMAX", "L Z-1 F300",
             "LBL 1", *body, "FN 1: Q1 = Q1 + 1", f"FN 12: IF +Q1 LT +{passes} GOTO LBL 1", "LBL 3", "L Z+50 R0 FMAX", "M30", "END PGM T MM"]
    program = "\n".join(f"{number} {line}" for number, line in enumerate(lines)) + "\n"
    _assert_same(program, "t.h", loop_bound=loop_bound)


# ------------------------------------------------------------------ the runner runs

def test_straight_loops_of_every_dialect_run_in_the_runner():
    """The loops below run all but their first two passes (the first leaves its lines
    lowered) and, where the test is at the bottom, their last in the generated code. (A
    Klartext line that moves also notes where it went, a step of the dialect's own that
    the runner does not take: only its computing loops run there.)"""
    linuxcnc = "\n".join(["G21 G90 G17 G54", "T1 M6", "G43 H1", "G0 X0 Y0 Z5", "G1 Z-1 F800", "#<i> = 0", "o100 while [#<i> LT 100]",
                          "#<x> = [[#<i> MOD 20] * 0.5]", "#<y> = [FIX[#<i> / 20] * 0.5]", "G1 X#<x> Y#<y> Z[-1 - 0.2 * SIN[#<i> * 3.6]]",
                          "#<i> = [#<i> + 1]", "o100 endwhile", "G0 Z50", "M2"]) + "\n"
    fanuc = "O1\nG21 G90 G54\nT1 M06\nG43 H01 Z50.\nG0 X0 Y0\nG1 Z-1. F300.\n#1 = 0\nWHILE [#1 LT 100] DO1\nG1 X#1 Y[#1 * 2]\n#1 = #1 + 1\nEND1\nM30\n"
    goto = "O1\nG21 G90 G54\nT1 M06\nG43 H01 Z50.\nG0 X0 Y0\nG1 Z-1. F300.\n#1 = 0\nN10 G1 X#1\n#1 = #1 + 1\nIF [#1 LT 100] GOTO 10\nM30\n"
    sinumerik = "G17 G90 G71 G54\nT1 D1\nM6\nG0 X0 Y0 Z5\nF300\nR1=0\nWHILE R1<100\nG1 X=R1 Y=R1*2\nR1=R1+1\nENDWHILE\nM30\n"
    fagor = "G71 G90 G17 G54\nT1 D1\nM6\nG0 X0 Y0 Z5\nF300\nP1=0\n$WHILE P1<100\nG1 XP1 Y[P1*2]\nP1=P1+1\n$ENDWHILE\nM30\n"
    klartext = "\n".join(f"{n} {line}" for n, line in enumerate([
        "BEGIN PGM T MM", "TOOL CALL 1 Z S1000", "L Z+50 R0 FMAX M3", "FN 0: Q1 = 0", "FN 0: Q2 = 0", "L X+0 Y+0 R0 FMAX", "LBL 1",
        "FN 2: Q2 = Q2 - Q1", "FN 1: Q1 = Q1 + 1", "FN 12: IF +Q1 LT +100 GOTO LBL 1", "L X+0 Y+Q2", "M30", "END PGM T MM"])) + "\n"
    for program, path, passes in ((linuxcnc, "t.ngc", 98), (fanuc, "t.nc", 98), (goto, "t.nc", 97), (sinumerik, "t.mpf", 98),
                                  (fagor, "t.pim", 98), (klartext, "t.h", 97)):
        assert _passes_run(program, path) == passes, path
        assert _passes_run(program, path, loop_runner=False) == 0
        _assert_same(program, path)


def test_a_pass_that_reads_a_free_parameter_goes_pass_by_pass():
    """A pass whose value depends on a free parameter (#500) is the block path's; so is a
    pass in which a branch is taken, and the runner takes the next straight passes again."""
    program = "\n".join(["O1", "G21 G90 G54", "T1 M06", "G43 H01 Z50.", "G0 X0 Y0", "G1 Z-1. F300.", "#1 = 0", "WHILE [#1 LT 60] DO1",
                         "G1 X#1 Y#500", "#1 = #1 + 1", "END1", "M30"]) + "\n"
    assert _passes_run(program, "t.nc") == 0
    branching = "\n".join(["G21 G90 G17 G54", "T1 M6", "G43 H1", "G0 X0 Y0 Z5", "G1 Z-1 F800", "#<i> = 0", "o100 while [#<i> LT 60]",
                           "o200 if [[#<i> MOD 20] NE 10]", "G1 X#<i>", "o200 endif", "#<i> = [#<i> + 1]", "o100 endwhile", "M2"]) + "\n"
    assert 50 <= _passes_run(branching, "t.ngc") < 58
    _assert_same(branching, "t.ngc")


def test_a_pass_that_moves_an_axis_for_the_first_time_on_its_path_goes_pass_by_pass():
    """Two paths share the loop's compiled pass; on the second one the pass's X move is
    skipped in the first passes, so X is not in the position yet when the pass first moves
    it: the block path runs that pass (which adds X where the block path adds it), the
    runner the ones after it."""
    for order in (("#2 = 0", "#2 = 3"), ("#2 = 3", "#2 = 0")):
        program = "\n".join(["O1000", "G21 G90 G17 G54", "T1 M06", "G43 H01 Z50.", "S1000 M03", "F300.", order[0], "IF [#500 GT 0] GOTO 5",
                             order[1], "N5", "#1 = 0", "N10 G1 Y#1", "IF [#1 LT #2] GOTO 20", "G1 X[#1 * 2]", "N20 #1 = #1 + 1",
                             "IF [#1 LT 30] GOTO 10", "G0 Z50.", "M30"]) + "\n"
        assert _passes_run(program, "t.nc") >= 50
        _assert_same(program, "t.nc")
