"""The cases of the sound-proofs work that each either are modelled or make a verdict
``unknown``: cycle sizes that are expressions (the solver's verdict, sampled against the
concrete path), cycle sizes under a scaling, the Klartext cylinder blank, a change of work
offset, and diameter or radius programming.

Every ``proved`` here is sampled: values drawn from the assumed box (its corners and random
points) are written into the program as plain numbers, and the concrete run must find no
violation where the proof said there is none.
"""
from __future__ import annotations

import textwrap

import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_text
from ncverify.diagnostics import Status


def findings(result, rule: str, line: int | None = None) -> list:
    return [d for d in result.diagnostics if d.rule == rule and (line is None or d.span.line == line)]


def statuses(result, rule: str, line: int | None = None) -> set[Status]:
    return {d.status for d in findings(result, rule, line)}


# --------------------------------------------------------------------------- cycle sizes the solver judges
# Each case: dialect, file name, the program with {define} where the parameter's range (or,
# for the concrete run, its value) goes, the rule and the line it reports on.

SINUMERIK_POCKET4 = """
    ; ncverify: stock box X0:120 Y0:80 Z-20:0
    $TC_DP1[1,1]=120 $TC_DP6[1,1]=5 $TC_DP3[1,1]=60
    {define}
    G17 G90 G54
    T1 D1 M6
    S2000 M3
    G0 X60 Y40 Z20
    POCKET4(10, 0, 2, -6, {size}, 60, 40, 3, 0.2, 0.1, 600, 150, 2, 21, 6, 0, 0, 0, 2)
    M30
"""

SINUMERIK_SLOT1 = """
    $TC_DP1[1,1]=120 $TC_DP6[1,1]=4 $TC_DP3[1,1]=60
    {define}
    G17 G90 G54
    T1 D1 M6
    S2000 M3
    G0 X0 Y0 Z20
    SLOT1(10, 0, 2, -6, 0, 4, 30, {size}, 50, 50, 20, 0, 90, 100, 300, 3, 2, 0.2, 31)
    M30
"""

FAGOR_G88 = """
    ; ncverify: tool 14 radius 5 length 90
    {define}
    G17 G90 G54
    T14 D14 M6
    S4500 M3 M8
    G0 X150 Y60 Z25 F600
    G98 G88 Z2 I-8 D2 J{size} B2 C6 L0.3 H300 V120
    G80
    M30
"""

FAGOR_G87 = """
    ; ncverify: tool 14 radius 5 length 90
    {define}
    G17 G90 G54
    T14 D14 M6
    S4500 M3 M8
    G0 X150 Y60 Z25 F600
    G99 G87 Z2 I-6 D2 J{size} K12 M1 Q6 B3 C8 L0.5 H400 V150
    G80
    M30
"""

KLARTEXT_251 = """
    0  BEGIN PGM RECT MM
    1  ; ncverify: tool 5 radius 5 length 60
    2  {define}
    3  TOOL CALL 5 Z S3500 F600
    4  L  Z+50 R0 FMAX M3 M8
    5  Q2 = {size}
    6  CYCL DEF 251 RECTANGULAR POCKET ~
        Q215=+0 ;MACHINING OPERATION ~
        Q218=+60 ;FIRST SIDE LENGTH ~
        Q219=+Q2 ;2ND SIDE LENGTH ~
        Q220=+0 ;CORNER RADIUS ~
        Q368=+0 ;ALLOWANCE FOR SIDE ~
        Q224=+0 ;ANGLE OF ROTATION ~
        Q367=+0 ;POCKET POSITION ~
        Q207=+500 ;FEED RATE MILLING ~
        Q351=+1 ;CLIMB OR UP-CUT ~
        Q201=-10 ;DEPTH ~
        Q202=+5 ;PLUNGING DEPTH ~
        Q369=+0 ;ALLOWANCE FOR FLOOR ~
        Q206=+150 ;FEED RATE FOR PLNGNG ~
        Q338=+0 ;INFEED FOR FINISHING ~
        Q200=+2 ;SET-UP CLEARANCE ~
        Q203=+0 ;SURFACE COORDINATE ~
        Q204=+50 ;2ND SET-UP CLEARANCE ~
        Q370=+1 ;TOOL PATH OVERLAP ~
        Q366=+0 ;PLUNGE ~
        Q385=+500 ;FINISHING FEED RATE
    7  L  X+80  Y+50 R0 FMAX M99
    8  END PGM RECT MM
"""

_DIALECTS = {
    "sinumerik": ("part.mpf", "R1", "; ncverify: assume {low} <= R1 <= {high}", "R1={value}"),
    "fagor": ("part.pim", "P1", "; ncverify: assume {low} <= P1 <= {high}", "P1={value}"),
    "heidenhain": ("part.h", "Q1", "; ncverify: assume {low} <= Q1 <= {high}", "Q1 = {value}"),
}

# (dialect, program, size expression, the rule, the line it reports on, low, high, expected verdict)
SIZE_CASES = {
    "sinumerik POCKET4 MINVAL proved": ("sinumerik", SINUMERIK_POCKET4, "MINVAL(R1, 20) - 2", "sinumerik.cutter-radius", 8, 8.0, 30.0, Status.PROVED),
    "sinumerik POCKET4 MAXVAL violated": ("sinumerik", SINUMERIK_POCKET4, "MAXVAL(R1, 3)", "sinumerik.cutter-radius", 8, 2.0, 30.0, Status.VIOLATED),
    "sinumerik POCKET4 ROUND violated": ("sinumerik", SINUMERIK_POCKET4, "ROUND(R1 / 2)", "sinumerik.cutter-radius", 8, 8.0, 30.0, Status.VIOLATED),
    "sinumerik POCKET4 ROUND proved": ("sinumerik", SINUMERIK_POCKET4, "ROUND(R1 / 2)", "sinumerik.cutter-radius", 8, 9.0, 30.0, Status.PROVED),
    "sinumerik POCKET4 TRUNC violated": ("sinumerik", SINUMERIK_POCKET4, "TRUNC(R1) / 2", "sinumerik.cutter-radius", 8, 9.5, 30.0, Status.VIOLATED),
    "sinumerik SLOT1 proved": ("sinumerik", SINUMERIK_SLOT1, "2 * R1", "sinumerik.cutter-radius", 7, 4.5, 6.0, Status.PROVED),
    "sinumerik SLOT1 violated": ("sinumerik", SINUMERIK_SLOT1, "2 * R1", "sinumerik.cutter-radius", 7, 3.0, 6.0, Status.VIOLATED),
    "fagor G88 INT proved": ("fagor", FAGOR_G88, "[INT[P1] + 1]", "fagor.pocket-tool-fit", 7, 5.0, 30.0, Status.PROVED),
    "fagor G88 ROUND violated": ("fagor", FAGOR_G88, "[ROUND[P1 / 3]]", "fagor.pocket-tool-fit", 7, 5.0, 30.0, Status.VIOLATED),
    "fagor G87 proved": ("fagor", FAGOR_G87, "P1", "fagor.pocket-tool-fit", 7, 8.0, 40.0, Status.PROVED),
    "fagor G87 violated": ("fagor", FAGOR_G87, "P1", "fagor.pocket-tool-fit", 7, 2.0, 40.0, Status.VIOLATED),
    "klartext 251 INT proved": ("heidenhain", KLARTEXT_251, "INT ( Q1 ) + 1", "heidenhain.tool-too-large", 10, 10.0, 40.0, Status.PROVED),
    "klartext 251 INT violated": ("heidenhain", KLARTEXT_251, "INT ( Q1 ) + 1", "heidenhain.tool-too-large", 10, 8.0, 40.0, Status.VIOLATED),
}


def _program(case, define: str) -> str:
    dialect, template, size, *_ = case
    return textwrap.dedent(template).lstrip().replace("{define}", define).replace("{size}", size)


def _check(case, define: str):
    dialect = case[0]
    return check_text(_program(case, define), _DIALECTS[dialect][0], Settings(dialect=dialect))


def _symbolic(case):
    dialect, _template, _size, _rule, _line, low, high, _expected = case
    return _check(case, _DIALECTS[dialect][2].format(low=low, high=high))


def _concrete(case, value: float):
    return _check(case, _DIALECTS[case[0]][3].format(value=repr(float(value))))


_SYMBOLIC_RESULTS: dict = {}


def _verdict(name):
    if name not in _SYMBOLIC_RESULTS:
        _SYMBOLIC_RESULTS[name] = _symbolic(SIZE_CASES[name])
    return _SYMBOLIC_RESULTS[name]


@pytest.mark.parametrize("name", SIZE_CASES)
def test_a_cycle_size_that_is_an_expression_gets_the_solver_verdict(name):
    case = SIZE_CASES[name]
    _dialect, _template, _size, rule, line, low, high, expected = case
    result = _verdict(name)
    assert statuses(result, rule, line) == {expected}, [d.message for d in findings(result, rule)]
    for finding in findings(result, rule, line):
        if expected is Status.VIOLATED:
            witness = finding.witness[_DIALECTS[case[0]][1]]
            assert low <= witness <= high
            assert statuses(_concrete(case, witness), rule, line) == {Status.VIOLATED}  # the witness, written into the program


_PROVED_CASES = [name for name, case in SIZE_CASES.items() if case[-1] is Status.PROVED]


@pytest.mark.parametrize("name", _PROVED_CASES)
@hypothesis_settings(max_examples=12, deadline=None)
@given(fraction=st.one_of(st.sampled_from([0.0, 1.0, 0.5]), st.floats(0.0, 1.0)))
def test_every_proved_cycle_size_holds_for_values_sampled_from_the_box(name, fraction):
    case = SIZE_CASES[name]
    _dialect, _template, _size, rule, line, low, high, _expected = case
    assert statuses(_verdict(name), rule, line) == {Status.PROVED}
    value = low + fraction * (high - low)
    assert Status.VIOLATED not in statuses(_concrete(case, value), rule, line), value


@hypothesis_settings(max_examples=60, deadline=None)
@given(x=st.floats(-1e4, 1e4, allow_nan=False).map(lambda v: round(v * 4) / 4 if abs(v) < 50 else v),
       y=st.floats(-1e4, 1e4, allow_nan=False))
def test_rounding_and_min_max_mean_the_same_to_the_solver_as_to_the_concrete_path(x, y):
    """The solver's FIX, FUP, ROUND, MIN and MAX are the concrete functions exactly (halves included)."""
    import z3
    from ncverify import values

    a, b = values.parameter("a"), values.parameter("b")
    for name, args, concrete in [(name, [a], [x]) for name in ("FIX", "FUP", "ROUND")] + [(name, [a, b], [x, y]) for name in ("MIN", "MAX")]:
        term = values.defined(values.call(name, args).term)
        solver = z3.Solver()
        result = z3.Real("result")
        solver.add(a.term == z3.RealVal(repr(x)), b.term == z3.RealVal(repr(y)), result == term)
        assert solver.check() == z3.sat
        assert float(solver.model()[result].as_fraction()) == values.call(name, concrete), (name, x, y)


# --------------------------------------------------------------------------- cycle sizes under a scaling

def _scaled_pocket4(scale: str, radius: str = "8"):
    text = textwrap.dedent(SINUMERIK_POCKET4).lstrip().replace("{define}", scale).replace("{size}", radius)
    return check_text(text, "part.mpf", Settings(dialect="sinumerik"))


def test_a_sinumerik_pocket_is_judged_at_the_size_the_scale_makes_it():
    assert statuses(_scaled_pocket4(""), "sinumerik.cutter-radius", 8) == set()  # radius 8 holds the 5 mm tool
    [finding] = findings(_scaled_pocket4("SCALE X0.5 Y0.5"), "sinumerik.cutter-radius", 8)
    assert finding.status is Status.VIOLATED and "scaled by the factor 0.5" in finding.message  # radius 4 on the part
    assert statuses(_scaled_pocket4("SCALE X2 Y2", "4"), "sinumerik.cutter-radius", 8) == set()  # 4 x 2 holds it


def test_a_pocket_scaled_unevenly_in_the_plane_is_unknown():
    assert statuses(_scaled_pocket4("SCALE X0.5 Y1"), "sinumerik.cutter-radius") == {Status.UNKNOWN}


def test_a_symbolic_size_under_a_scale_goes_to_the_solver_scaled():
    proved = _scaled_pocket4("; ncverify: assume 10 <= R1 <= 30\nSCALE X0.5 Y0.5", "R1")
    assert statuses(proved, "sinumerik.cutter-radius", 9) == {Status.PROVED}
    shown = _scaled_pocket4("; ncverify: assume 8 <= R1 <= 30\nSCALE X0.5 Y0.5", "R1")
    [finding] = findings(shown, "sinumerik.cutter-radius", 9)
    assert finding.status is Status.VIOLATED and 8 <= finding.witness["R1"] < 10


def test_a_klartext_pocket_under_cycle_11_is_judged_scaled_and_under_cycle_26_with_two_factors_unknown():
    text = KLARTEXT_251.replace("{define}", "CYCL DEF 11.0 SCALING").replace("5  Q2 = {size}", "5  CYCL DEF 11.1 SCL {factor}").replace("+Q2 ;2ND", "+12 ;2ND")
    plain = check_text(textwrap.dedent(text.replace("{factor}", "1")).lstrip(), "part.h")
    assert statuses(plain, "heidenhain.tool-too-large") == set()  # 12 wide for a 10 mm tool
    halved = check_text(textwrap.dedent(text.replace("{factor}", "0.5")).lstrip(), "part.h")
    assert statuses(halved, "heidenhain.tool-too-large") == {Status.VIOLATED}  # 6 wide on the part
    uneven = text.replace("CYCL DEF 11.0 SCALING", "CYCL DEF 26.0 AXIS-SPECIFIC SCALING").replace("CYCL DEF 11.1 SCL {factor}", "CYCL DEF 26.1 X0.5 Y1 CCX+0 CCY+0")
    assert statuses(check_text(textwrap.dedent(uneven).lstrip(), "part.h"), "heidenhain.tool-too-large") == {Status.UNKNOWN}


def test_a_fagor_pocket_under_a_scaling_is_judged_scaled():
    text = textwrap.dedent(FAGOR_G87).lstrip().replace("{size}", "10")
    assert statuses(check_text(text.replace("{define}", ""), "part.pim", Settings(dialect="fagor")), "fagor.pocket-tool-fit") == set()
    scaled = check_text(text.replace("{define}", "G72 S0.5"), "part.pim", Settings(dialect="fagor"))
    assert Status.VIOLATED not in statuses(scaled, "fagor.pocket-tool-fit")  # G72 is not modelled: never a verdict from the written sizes
    assert statuses(scaled, "fagor.pocket-tool-fit") == {Status.UNKNOWN}


# --------------------------------------------------------------------------- a change of work offset

TWO_OFFSETS = """
    %
    O3002
    (ncverify: stock box X0:100 Y0:100 Z-20:0)
    (ncverify: tool 1 radius 5 length 60)
    (ncverify: assume 60 <= #1 <= 90 and -40 <= #2 <= -10)
    G21 G17 G90 G54
    T1 M06 G43 H01
    G00 X-20. Y50. Z50. S1000 M03
    G00 Z-5.
    G00 X#2
    G00 Z50.
    G55 X-20. Y50.
    G00 Z-5.
    G00 X#1
    M30
    %
"""


def test_the_stock_is_not_judged_under_a_second_work_offset_unless_the_project_says_it_holds_the_same_blank():
    from conftest import check_program

    alone = check_program(TWO_OFFSETS, "two.nc")
    assert statuses(alone, "core.rapid-into-stock", 10) == {Status.PROVED}  # beside the blank under G54
    assert statuses(alone, "core.rapid-into-stock", 14) == set()  # under G55: another part, not judged ...
    [said] = [d for d in findings(alone, "core.rapid-into-stock") if d.reason == "another work offset"]
    assert said.status is Status.UNKNOWN and "G54 to G55" in said.message  # ... and said so, once
    shared = check_program(TWO_OFFSETS, "two.nc", '[machine]\none_workpiece = ["G54", "G55"]\n')
    assert statuses(shared, "core.rapid-into-stock", 14) == {Status.VIOLATED}  # the same blank: X60..90 at Z-5 is inside it


def test_a_move_after_a_change_of_work_offset_starts_where_the_old_offset_left_the_tool():
    """Selecting G55 does not move the tool: its place in G55's coordinates depends on the
    offsets' values, so a rapid that moves one axis after the change starts from an unknown
    place and is never shown to cross the blank on the old offset's coordinates."""
    from conftest import check_program

    text = TWO_OFFSETS.replace("G55 X-20. Y50.", "G55").replace("G00 X#1\n", "G00 X50.\n")
    shared = check_program(text, "two.nc", '[machine]\none_workpiece = ["G54", "G55"]\n')
    assert statuses(shared, "core.rapid-into-stock", 13) <= {Status.UNKNOWN}
    assert statuses(shared, "core.rapid-into-stock", 14) <= {Status.UNKNOWN}


def test_the_project_file_names_the_offsets_that_share_the_blank_as_a_list():
    from conftest import project
    from ncverify.project import ConfigError

    assert project('[machine]\none_workpiece = ["g54", "G55"]\n').machine.one_workpiece == {"G54", "G55"}
    with pytest.raises(ConfigError):
        project('[machine]\none_workpiece = "G54"\n')


# --------------------------------------------------------------------------- BLK FORM CYLINDER

ROUND_BLANK = """
    0  BEGIN PGM CYL MM
    1  ; ncverify: tool 1 radius 5 length 60
    2  {define}
    3  BLK FORM CYLINDER Z R25 L100
    4  TOOL CALL 1 Z S2000
    5  L  X+40 Y+0 Z+50 R0 FMAX M3
    6  L  Z-5 R0 FMAX
    7  L  X+30 Y+30 R0 FMAX
    8  L  X+Q1 Y+0 R0 FMAX
    9  L  X+0 Y+{near} R0 FMAX
    10 L  Z+50 R0 FMAX
    11 END PGM CYL MM
"""


def _round(define: str, near: str = "29"):
    return check_text(textwrap.dedent(ROUND_BLANK).lstrip().replace("{define}", define).replace("{near}", near), "cyl.h")


def test_blk_form_cylinder_is_a_round_blank_about_the_tool_axis_not_a_lathe_bar():
    result = _round("Q1 = 35", "100")
    assert statuses(result, "core.rapid-into-stock") <= {Status.UNKNOWN}  # every rapid stays outside R25 + the tool's 5
    assert not findings(result, "core.rapid-into-stock", 10)  # Y100 is far off the blank (a lathe bar ignores Y)
    inside = _round("Q1 = 28")
    assert statuses(inside, "core.rapid-into-stock", 9) == {Status.VIOLATED}  # the tool's side reaches R23..33 at Y0
    describe = findings(inside, "core.rapid-into-stock", 9)[0].message
    assert "round blank D50 about Z Z-100..0" in describe


def test_a_cylinder_along_another_axis_or_a_hollow_one_is_no_stock():
    from ncverify.lower.heidenhain import stock_from_text

    assert stock_from_text("1 BLK FORM CYLINDER Z R25 L100\n").diameter == 50
    assert stock_from_text("1 BLK FORM CYLINDER X R25 L100\n") is None
    assert stock_from_text("1 BLK FORM CYLINDER Z R25 L100 DIST+0 DI20\n") is None


def test_symbolic_rapids_against_the_round_blank_get_a_verdict():
    result = _round("; ncverify: assume 31 <= Q1 <= 40")
    assert statuses(result, "core.rapid-into-stock", 9) == {Status.PROVED}  # from X30 Y30 down to X31..40 Y0: R30 is kept
    [finding] = findings(result, "core.rapid-into-stock", 10)  # from X31..40 Y0 to X0 Y29 cuts across the blank
    assert finding.status is Status.VIOLATED and 31 <= finding.witness["Q1"] <= 40


@hypothesis_settings(max_examples=10, deadline=None)
@given(fraction=st.one_of(st.sampled_from([0.0, 1.0]), st.floats(0.0, 1.0)))
def test_the_round_blank_proof_holds_for_values_sampled_from_the_box(fraction):
    value = 31.0 + fraction * 9.0
    assert Status.VIOLATED not in statuses(_round(f"Q1 = {value!r}", "100"), "core.rapid-into-stock", 9)


# --------------------------------------------------------------------------- diameter or radius programming

LATHE_BAR = """
    ; ncverify: stock cylinder D40 Z-80:0
    ; ncverify: tool 1 radius 0.4 length 0
    G18 G90 G54 {mode}
    T1 D1
    G0 X60 Z5
    G0 X30 Z-10
    G0 X60
    M30
"""
LATHE_PROJECT = "[machine]\ntype = \"lathe\"\nlathe_x = \"diameter\"\ntravel = { x = [0, 100], z = [-200, 50] }\nwork_offsets = { G54 = [0, 0, 0] }\n"


def _bar(mode: str, travel: str = LATHE_PROJECT):
    from conftest import check_program

    return check_program(LATHE_BAR.replace("{mode}", mode), "bar.mpf", travel, dialect="sinumerik", machine="lathe")


LINUXCNC_BAR = """
    (ncverify: stock cylinder D40 Z-80:0)
    (ncverify: tool 1 radius 0.4 length 0)
    G18 G90 G54 {mode}
    T1 M6
    G0 X60 Z5
    G0 X15 Z-10
    G0 X60
    M30
"""


def test_linuxcnc_reads_x_as_a_radius_until_g7():
    from conftest import check_program

    def bar(mode):
        return check_program(LINUXCNC_BAR.replace("{mode}", mode), "bar.ngc", LATHE_PROJECT, dialect="linuxcnc", machine="lathe")

    assert statuses(bar("G7"), "core.rapid-into-stock", 7) == {Status.VIOLATED}  # a diameter of 15 inside the D40 bar
    for mode in ("", "G8"):  # a radius of 15: inside too, but the bar's radius model is not there: unknown, never a guess
        assert Status.VIOLATED not in statuses(bar(mode), "core.rapid-into-stock"), mode
        assert "lathe X as a radius" in {d.reason for d in findings(bar(mode), "core.rapid-into-stock")}, mode


def test_the_bar_is_judged_only_where_x_is_known_to_be_a_diameter():
    assert statuses(_bar("DIAMON"), "core.rapid-into-stock", 7) == {Status.VIOLATED}  # X30 is inside the D40 bar
    for mode in ("DIAMOF", "DIAM90", ""):  # X30 would be a radius of 30, outside it; or nobody knows
        result = _bar(mode)
        assert Status.VIOLATED not in statuses(result, "core.rapid-into-stock"), mode
        assert any(d.status is Status.UNKNOWN and d.reason in ("lathe X as a radius", "diameter mode not known")
                   for d in findings(result, "core.rapid-into-stock")), mode


def test_the_travel_check_reads_x_by_the_diameter_mode():
    far = LATHE_PROJECT.replace("x = [0, 100]", "x = [0, 50]").replace('lathe_x = "diameter"', 'lathe_x = "radius"')
    assert Status.VIOLATED not in statuses(_bar("DIAMON", travel=far), "core.travel-limit", 5)  # X60 is a radius of 30 within the travel's 50
    assert Status.VIOLATED in statuses(_bar("DIAMOF", travel=far), "core.travel-limit", 5)  # X60 is a radius of 60
    assert Status.VIOLATED not in statuses(_bar("DIAM90", travel=far), "core.travel-limit")


# --------------------------------------------------------------------------- the corpus programs of these cases

CORPUS = __import__("pathlib").Path(__file__).resolve().parents[1] / "corpus"


@pytest.mark.parametrize("program, rule, line", [
    ("sinumerik/param-pocket-minval-proved.mpf", "sinumerik.cutter-radius", 9),
    ("fagor/param-pocket-int-proved.pim", "fagor.pocket-tool-fit", 11),
])
def test_the_proved_corpus_programs_prove_the_tool_fit(program, rule, line):
    from ncverify import check_file

    assert statuses(check_file(CORPUS / program), rule, line) == {Status.PROVED}


@pytest.mark.parametrize("program, rule, line, parameter, low, high", [
    ("sinumerik/param-pocket-rounded-violated.mpf", "sinumerik.cutter-radius", 10, "R1", 8.0, 9.0),
    ("heidenhain/param-rect-pocket-violated.h", "heidenhain.tool-too-large", 14, "Q1", 8.0, 9.0),
])
def test_the_violated_corpus_programs_name_a_witness_where_the_rounding_makes_the_pocket_too_small(program, rule, line, parameter, low, high):
    from ncverify import check_file

    [finding] = findings(check_file(CORPUS / program), rule, line)
    assert finding.status is Status.VIOLATED and low <= finding.witness[parameter] < high


# --------------------------------------------------------------------------- radius compensation
# Under G41/G42 the tool runs beside the programmed path by the offset register's value,
# which the program does not give: a rapid's place in the plane is not the tool's.

_BESIDE = """
    (ncverify: stock box X0:100 Y0:100 Z-20:0)
    (ncverify: tool 1 radius 5 type endmill)
    (ncverify: assume 0 <= #1 <= 3)
    G21 G90 G17 G54
    T1 M06
    G43 H01 Z50.
    S6000 M03
    G00 X-10. Y-10.
    {on}G00 X-10. Y50. Z{depth}
    G00 X-6. Y{y}
    G40 G00 Z50.
    M30
"""


@pytest.mark.parametrize("y", ["60.", "[60. + #1]"])
def test_a_rapid_beside_the_blank_under_radius_compensation_is_unknown_never_passed(y):
    """Down beside the blank's side (1 mm of room for the tool's radius): clear as written,
    concrete or proved for every allowed value; under G41 the offset may put the tool into
    the side, so the same rapids are unknown, with the compensation named."""
    def rapid(on):
        result = check_text(textwrap.dedent(_BESIDE.format(on=on, depth="-5.", y=y)), "t.nc", Settings())
        return {(d.span.line, d.status) for d in findings(result, "core.rapid-into-stock")}, findings(result, "core.rapid-into-stock")

    plain, _ = rapid("")
    assert plain <= {(11, Status.PROVED)}
    compensated, found = rapid("G41 D1 ")
    assert compensated and all(status is Status.UNKNOWN for _, status in compensated)
    assert all("radius compensation" in (d.reason or "") + d.message for d in found)


def test_a_rapid_above_the_blank_under_radius_compensation_is_still_clear():
    """The offset acts in the plane: a rapid above the blank's top meets it nowhere."""
    result = check_text(textwrap.dedent(_BESIDE.format(on="G41 D1 ", depth="5.", y="60.")), "t.nc", Settings())
    assert findings(result, "core.rapid-into-stock") == []


def test_rapids_of_a_batch_under_radius_compensation_are_judged_as_block_by_block():
    program = textwrap.dedent(_BESIDE.format(on="G41 D1 ", depth="-5.", y="60.")).replace(
        "G00 X-6. Y60.\n", "".join(f"G00 X-6. Y{60 + step}.\n" for step in range(30)))
    batched, alone = (check_text(program, "t.nc", Settings(per_block_only=flag)) for flag in (False, True))
    assert [(d.span.line, d.status) for d in findings(batched, "core.rapid-into-stock")] == \
        [(d.span.line, d.status) for d in findings(alone, "core.rapid-into-stock")] != []
