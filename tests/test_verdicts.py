"""Verdicts on parametric programs: ``proved``, ``violated`` with a witness, ``unknown`` with a
reason (README "Verdicts").

The parameters are bounded by ``ncverify: assume`` annotations. A witness is checked the
way a machinist would check it: its values are written into the program TEXT in place of
each ``#n`` read (``tests/witness_text.py``) and the concrete program must give the same
finding at the same line. A ``proved`` verdict is checked the same way on sampled values.
"""
from __future__ import annotations

import json
import textwrap
from pathlib import Path

import pytest
import z3
from hypothesis import HealthCheck, given, settings, strategies as st

from ncverify import Settings, check_text
from ncverify.cli import main as cli_main
from ncverify.diagnostics import Severity, Status
from ncverify.project import load_project_text
from witness_text import assumed_ranges, literal, parameters_only, substitute, violated, with_status

STOCK = "(ncverify: stock box X0:100 Y0:80 Z-20:0)"
TOOL = "(ncverify: tool 1 radius 2 length 50)"  # a proof against the stock needs the tool's size
LEVEL_RULES = ("core.cycle-depth-sign", "core.cycle-zero-depth", "core.clearance-below-stock",
               "core.rapid-into-stock", "core.cycle-r-above-initial")
NOT_REPRODUCED = "did not reproduce"


def program(text: str) -> str:
    return textwrap.dedent(text).lstrip("\n")


def check(text: str, project: str | None = None, **options):
    context = load_project_text(textwrap.dedent(project), Path("/nowhere/ncverify.toml")) if project else None
    return check_text(text, "t.nc", Settings(**options), context)


def at(result, rule: str, line: int | None = None, status: Status | None = None) -> list:
    return [d for d in result.diagnostics if d.rule == rule and (line is None or d.span.line == line)
            and (status is None or d.status is status)]


def assert_reproduces(text: str, result, project: str | None = None, **options) -> int:
    """Every violated finding with a witness: inside the assumed ranges, and the same rule
    fires at the same line when the values are written into the program as numbers.
    Returns how many witnesses were replayed."""
    ranges = assumed_ranges(text)
    replayed = 0
    for finding in result.diagnostics:
        assert NOT_REPRODUCED not in (finding.reason or ""), finding
        if finding.status is not Status.VIOLATED or not finding.witness:
            continue
        values = parameters_only(finding.witness)
        assert values, finding.witness
        for name, value in values.items():
            if name in ranges:
                low, high = ranges[name]
                assert low <= value <= high, (finding.rule, name, value, ranges[name])
        concrete = check(substitute(text, values), project, **options)
        assert violated(concrete, finding.rule, finding.span.line), (
            f"{finding.rule} at line {finding.span.line} with {values} did not reproduce in the text:\n{substitute(text, values)}")
        replayed += 1
    return replayed


# --------------------------------------------------------------------------- proved


DRILL_PROVED = program(f"""
    {STOCK} {TOOL}
    (ncverify: assume -15 <= #1 <= -2)
    (ncverify: assume 1 <= #2 <= 5)
    G21 G17 G40 G49 G80 G90 T1 M06
    G00 G54 X10. Y10.
    G43 H01 G00 Z50. S2000 M03
    G99 G81 X10. Y10. Z#1 R#2 F100.
    X30.
    G80
    G00 Z50.
    M30
""")


def test_a_cycle_whose_levels_are_safe_for_the_whole_range_is_proved_on_every_level_rule():
    result = check(DRILL_PROVED)
    for rule in ("core.cycle-depth-sign", "core.cycle-zero-depth", "core.clearance-below-stock", "core.cycle-r-above-initial"):
        [entry] = at(result, rule, 7)
        assert entry.status is Status.PROVED and entry.severity is Severity.INFO, entry
        assert entry.message.startswith("proved impossible"), entry.message
        assert not entry.witness
    rapids = at(result, "core.rapid-into-stock", status=Status.PROVED)
    assert {d.span.line for d in rapids} >= {7, 8}  # approach, next hole at R (the retract runs up the tool's own axis: nothing to prove)
    assert not violated(result)


def test_proved_values_hold_on_the_ends_and_the_middle_of_the_ranges():
    result = check(DRILL_PROVED)
    proved = [(d.rule, d.span.line) for d in with_status(result, Status.PROVED)]
    assert proved
    for depth in (-15.0, -8.5, -2.0):
        for r_point in (1.0, 3.0, 5.0):
            concrete = check(substitute(DRILL_PROVED, {"#1": depth, "#2": r_point}))
            assert not [d for d in violated(concrete) if (d.rule, d.span.line) in proved], (depth, r_point)


def test_proved_entries_are_info_in_the_json_and_do_not_fail_the_run(tmp_path, capsys):
    path = tmp_path / "p.nc"
    path.write_text(DRILL_PROVED, encoding="utf-8")
    code = cli_main(["check", str(path), "--format", "json"])
    document = json.loads(capsys.readouterr().out)
    assert code == 0
    entries = [d for d in document["files"][0]["diagnostics"] if d["status"] == "proved"]
    assert entries and all(d["severity"] == "info" and "witness" not in d for d in entries)
    assert document["summary"]["proved"] == len(entries)
    assert document["files"][0]["free_parameters"] == ["#1", "#2"]


def test_a_relational_assumption_proves_what_the_bounds_alone_cannot():
    text = program(f"""
        {STOCK}
        (ncverify: assume -10 <= #1 <= 3 and #2 >= #1 + 0.5 and #2 <= 5)
        G21 G90 G54
        G00 X10. Y10. Z50.
        G99 G81 Z#1 R#2 F100.
        G80
        M30
    """)
    result = check(text)
    [depth] = at(result, "core.cycle-depth-sign", 5)
    [zero] = at(result, "core.cycle-zero-depth", 5)
    assert depth.status is Status.PROVED and zero.status is Status.PROVED


def test_a_division_whose_divisor_range_excludes_zero_is_proved():
    result = check(program("""
        (ncverify: assume 4 <= #1 <= 6)
        G21 G90 G54
        #10=100./[#1-3.]
        M30
    """))
    [entry] = at(result, "core.arithmetic-domain")
    assert entry.status is Status.PROVED


# --------------------------------------------------------------------------- violated, with a witness


def test_a_depth_range_reaching_above_r_is_violated_with_a_witness_that_reproduces():
    text = program(f"""
        {STOCK}
        (ncverify: assume -10 <= #1 <= 5)
        G21 G90 G54
        G00 X10. Y10. Z50. S1000 M03
        G99 G81 Z#1 R2. F100.
        G80
        M30
    """)
    result = check(text)
    [above] = at(result, "core.cycle-depth-sign", 5)
    assert above.status is Status.VIOLATED and 2.0 < above.witness["#1"] <= 5.0
    [zero] = at(result, "core.cycle-zero-depth", 5)
    assert zero.status is Status.VIOLATED and zero.witness["#1"] == 2.0
    assert assert_reproduces(text, result) == 2


def test_an_r_point_range_reaching_into_the_stock_is_violated_with_a_witness_that_reproduces():
    text = program(f"""
        {STOCK}
        (ncverify: assume -3 <= #2 <= 5)
        G21 G90 G54
        G00 X10. Y10. Z50. S1000 M03
        G98 G81 Z-8. R#2 F100.
        G80
        M30
    """)
    result = check(text)
    [clearance] = at(result, "core.clearance-below-stock", 5)
    assert clearance.status is Status.VIOLATED and -3.0 <= clearance.witness["#2"] < 0.0
    assert at(result, "core.rapid-into-stock", 5, Status.VIOLATED)
    assert at(result, "core.cycle-depth-sign", 5, Status.PROVED)
    assert assert_reproduces(text, result) >= 2


def test_a_symbolic_rapid_that_can_enter_the_stock_is_violated_and_one_that_cannot_is_proved():
    text = program(f"""
        {STOCK} {TOOL}
        (ncverify: assume -3 <= #5 <= 10)
        (ncverify: assume 2 <= #6 <= 10)
        G21 G90 G54 T1 M06 G43 H01
        G00 X10. Y10. Z50.
        G00 Z#6
        G00 Z#5
        G00 Z50.
        M30
    """)
    result = check(text)
    [safe] = at(result, "core.rapid-into-stock", 6)
    assert safe.status is Status.PROVED
    [plunge] = at(result, "core.rapid-into-stock", 7)
    assert plunge.status is Status.VIOLATED and -3.0 <= plunge.witness["#5"] < 0.0
    assert not at(result, "core.rapid-into-stock", 8)  # back up its own axis out of the material: it meets nothing new
    assert assert_reproduces(text, result) == 1


def test_a_witness_satisfies_a_relational_assumption():
    text = program(f"""
        {STOCK}
        (ncverify: assume -10 <= #1 <= -1 and #2 >= #1 - 1 and #2 <= 5)
        G21 G90 G54
        G00 X10. Y10. Z50.
        G99 G81 Z#1 R#2 F100.
        G80
        M30
    """)
    result = check(text)
    [above] = at(result, "core.cycle-depth-sign", 5)
    assert above.status is Status.VIOLATED
    one, two = above.witness["#1"], above.witness["#2"]
    assert -10 <= one <= -1 and two >= one - 1 and two <= 5 and one > two
    assert_reproduces(text, result)


MACHINE = """
    [machine]
    travel = { x = [-400, 400], y = [-250, 250], z = [-300, 0] }
    work_offsets = { G54 = [-300, -200, -250] }
    max_spindle = 8000
    max_feed = 5000
    [tools.1]
    radius = 5
    length = 60
"""


def test_machine_limits_on_parameters_are_violated_with_witnesses_that_reproduce():
    text = program("""
        (ncverify: assume 0 <= #1 <= 300)
        (ncverify: assume 1000 <= #2 <= 9000)
        (ncverify: assume 100 <= #3 <= 6000)
        G21 G17 G40 G49 G80 G90
        T1 M06
        G00 G54 X10. Y10. S#2 M03
        G43 Z#1 H01
        G01 X50. F#3
        G00 Z100.
        M30
    """)
    result = check(text, MACHINE)
    travel = at(result, "core.travel-limit", 7, Status.VIOLATED)
    assert travel and travel[0].witness["#1"] > 190  # machine Z = #1 - 250 + 60
    assert at(result, "core.spindle-over-limit", status=Status.VIOLATED)[0].witness["#2"] > 8000
    assert at(result, "core.feed-over-limit", status=Status.VIOLATED)[0].witness["#3"] > 5000
    assert assert_reproduces(text, result, MACHINE) >= 3


def test_machine_limits_proved_inside_the_travel():
    text = program("""
        (ncverify: assume 0 <= #1 <= 100)
        (ncverify: assume 1000 <= #2 <= 8000)
        G21 G17 G40 G49 G80 G90
        T1 M06
        G00 G54 X10. Y10. S#2 M03
        G43 Z#1 H01
        G01 X50. F1000.
        M30
    """)
    result = check(text, MACHINE)
    assert [d.status for d in at(result, "core.travel-limit", 6)] == [Status.PROVED]
    assert [d.status for d in at(result, "core.spindle-over-limit")] == [Status.PROVED]
    assert not violated(result)


def test_a_division_that_can_reach_zero_is_violated_at_the_zero():
    text = program("""
        (ncverify: assume 0 <= #1 <= 5)
        G21 G90 G54
        #10=100./[#1-3.]
        M30
    """)
    result = check(text)
    [entry] = at(result, "core.arithmetic-domain")
    assert entry.status is Status.VIOLATED and entry.witness == {"#1": 3.0}
    assert assert_reproduces(text, result) == 1


def test_the_witness_is_reported_in_the_json():
    text = program(f"""
        {STOCK}
        (ncverify: assume -10 <= #1 <= 5)
        G21 G90 G54
        G00 X10. Y10. Z50.
        G99 G81 Z#1 R2. F100.
        G80
        M30
    """)
    entries = check(text).to_json()["diagnostics"]
    [entry] = [d for d in entries if d["rule"] == "core.cycle-depth-sign"]
    assert entry["status"] == "violated" and -10 <= entry["witness"]["#1"] <= 5


# --------------------------------------------------------------------------- unknown, with the reason


_L_STOCK = "(ncverify: stock polygon X0 Y0, X100 Y0, X100 Y50, X60 Y50, X60 Y20, X0 Y20 Z-20:0)"  # notch above Y20 left of X60


def test_a_symbolic_rapid_into_a_polygon_stock_is_violated_with_a_witness_inside_the_outline():
    result = check(program(f"""
        {_L_STOCK}
        (ncverify: assume 0 <= #1 <= 100)
        G21 G90 G54
        G00 X#1 Y30. Z50.
        G00 Z-5.
        M30
    """))
    [entry] = at(result, "core.rapid-into-stock", 5)
    assert entry.status is Status.VIOLATED and 60 < entry.witness["#1"] < 100


def test_a_symbolic_rapid_down_into_the_notch_of_a_polygon_stock_is_proved():
    result = check(program(f"""
        {_L_STOCK} {TOOL}
        (ncverify: assume 5 <= #1 <= 55)
        G21 G90 G54 T1 M06 G43 H01
        G00 X#1 Y30. Z50.
        G00 Z-5.
        M30
    """))
    [entry] = at(result, "core.rapid-into-stock", 5)
    assert entry.status is Status.PROVED


def test_a_symbolic_dogleg_rapid_is_judged_on_the_box_its_ends_span():
    text = program(f"""
        {_L_STOCK} {TOOL}
        (ncverify: assume 70 <= #1 <= 90)
        G21 G90 G54 T1 M06 G43 H01
        G00 X30. Y30. Z-5.
        G00 X#1 Z10.
        M30
    """)
    [straight] = at(check(text), "core.rapid-into-stock", 5)
    [dogleg] = at(check(text, rapid_path="dogleg"), "core.rapid-into-stock", 5)
    assert straight.status is Status.PROVED  # out of the notch rising: above Z0 before it reaches X60
    assert dogleg.status is Status.VIOLATED  # X may move first, at Z-5, into the stock beyond X60


def test_a_branch_past_the_path_budget_is_unknown_with_the_reason():
    result = check(program("""
        (ncverify: assume -10 <= #1 <= 10)
        G21 G90 G54
        IF [#1 GT 0] GOTO 100
        N100 M30
    """), max_paths=1)
    [entry] = at(result, "core.path-limit")
    assert entry.status is Status.UNKNOWN and "max_paths" in entry.reason


def test_a_solver_without_an_answer_gives_unknown_with_the_reason(monkeypatch):
    monkeypatch.setattr(z3.Solver, "check", lambda self, *args: z3.unknown)
    result = check(program(f"""
        {STOCK}
        (ncverify: assume -10 <= #1 <= 5)
        G21 G90 G54
        G00 X10. Y10. Z50.
        G99 G81 Z#1 R2. F100.
        G80
        M30
    """))
    [entry] = at(result, "core.cycle-depth-sign", 5)
    assert entry.status is Status.UNKNOWN and "solver gave no answer" in entry.reason


def test_every_solver_query_gets_the_configured_timeout(monkeypatch):
    seen = []
    original = z3.Solver.set

    def record(self, *args, **keys):
        if args and args[0] == "timeout":
            seen.append(args[1])
        return original(self, *args, **keys)

    monkeypatch.setattr(z3.Solver, "set", record)
    check(program(f"""
        {STOCK}
        (ncverify: assume -10 <= #1 <= 5)
        G21 G90 G54
        G00 X10. Y10. Z50.
        G99 G81 Z#1 R2. F100.
        G80
        M30
    """), solver_timeout_s=0.25)
    assert seen and set(seen) == {250}


# --------------------------------------------------------------------------- bugs found while writing these tests


def test_a_witness_names_only_parameters_of_the_program():
    result = check(program(f"""
        {STOCK}
        (ncverify: assume -3 <= #5 <= 10)
        G21 G90 G54
        G00 X10. Y10. Z50.
        G00 Z#5
        M30
    """))
    [plunge] = at(result, "core.rapid-into-stock", 5)
    assert plunge.status is Status.VIOLATED
    assert set(plunge.witness) == {"#5"}


def test_a_first_rapid_to_a_symbolic_point_inside_the_stock_is_not_dropped():
    text = program(f"""
        {STOCK}
        (ncverify: assume -8 <= #1 <= -2)
        G21 G90 G54
        G00 X10. Y10. Z#1
        M30
    """)
    assert violated(check(substitute(text, {"#1": -5.0})), "core.rapid-into-stock", 4)
    assert at(check(text), "core.rapid-into-stock", 4), "no verdict at all for the rapid"


@pytest.mark.parametrize("r_point", ["-2.", "#2"])
def test_the_clearance_of_a_hole_beside_the_stock_is_not_violated(r_point):
    text = program(f"""
        {STOCK}
        (ncverify: assume 120 <= #3 <= 150)
        (ncverify: assume -2 <= #2 <= 2)
        G21 G90 G54
        G00 X130. Y10. Z50.
        G99 G81 X#3 Y10. Z-5. R{r_point} F100.
        G80
        M30
    """)
    result = check(text)
    for value in (120.0, 135.0, 150.0):  # the hole is beside the stock for every allowed #3
        assert not violated(check(substitute(text, {"#3": value, "#2": -2.0})), "core.clearance-below-stock")
    entries = at(result, "core.clearance-below-stock")
    assert all(d.status is Status.PROVED for d in entries), [(d.status, d.reason) for d in entries]


def test_an_arc_with_parametric_end_points_is_not_left_as_did_not_reproduce():
    result = check(program("""
        (ncverify: assume 0 <= #4 <= 50)
        G21 G90 G54 G17
        G00 X#4 Y0. Z5. S1000 M03
        G01 Z-1. F100.
        G02 X[#4+20.] Y0. R15.
        G03 X#4 Y0. I-10. J0.
        M30
    """))
    entries = at(result, "core.arc-geometry")
    assert entries and all(NOT_REPRODUCED not in (d.reason or "") for d in entries), [d.reason for d in entries]
    assert all(d.status is Status.PROVED for d in entries)


def test_one_place_never_gets_both_proved_and_violated():
    result = check(program(f"""
        {STOCK}
        (ncverify: assume -10 <= #1 <= 10)
        G21 G90 G54
        G00 X10. Y10. Z50. S1000 M03
        IF [#1 GT 0] GOTO 100
        N100 G99 G81 Z#1 R2. F100.
        G80
        M30
    """))
    assert [d.status for d in at(result, "core.cycle-depth-sign", 6)] == [Status.VIOLATED]


def test_a_bracketed_constant_with_a_decimal_point_is_a_length_in_mm():
    result = check(program("""
        G21 G90 G54
        G00 X10. Y10. Z[3.]
        #3000=#5003
        M30
    """))
    assert not at(result, "core.decimal-point")
    [alarm] = at(result, "core.macro-alarm")
    assert "#3000=3:" in alarm.message, alarm.message


def test_the_clearance_of_a_cycle_is_judged_for_its_holes_over_the_stock_too():
    text = program(f"""
        {STOCK}
        (ncverify: assume 120 <= #3 <= 150)
        G21 G90 G54
        G00 X130. Y10. Z50.
        G99 G81 X#3 Y10. Z-5. R-2. F100.
        X40.
        G80
        M30
    """)
    assert violated(check(substitute(text, {"#3": 130.0})), "core.clearance-below-stock", 5)
    statuses = [d.status for d in at(check(text), "core.clearance-below-stock") if "R point" in d.message]
    assert statuses == [Status.VIOLATED], statuses


# --------------------------------------------------------------------------- property: pinned = concrete

_VALUES = (-25.0, -10.0, -5.0, -1.0, 0.0, 0.5, 2.0, 3.0, 10.0, 30.0, 60.0)
_CYCLES = ("G81", "G83 Q2.", "G73 Q1.", "G82 P500")


@st.composite
def drilling_and_contour(draw):
    """A concrete program body that reads #1-#5, and the values of #1-#5 (hole and contour
    positions #3, #4 over the stock or beside it)."""
    values = {f"#{n}": draw(st.sampled_from(_VALUES)) for n in range(1, 6)}
    pick = lambda *options: draw(st.sampled_from(options))  # noqa: E731
    body = ["G21 G17 G40 G49 G80 G90", "T1 M06", f"G00 G54 X{pick('10.', '#3')} Y{pick('10.', '#4')} S2000 M03",
            f"G43 Z{pick('50.', '#5', '#2')} H01"]
    for step in draw(st.lists(st.integers(0, 4), min_size=1, max_size=4)):
        if step == 0:
            body += [f"{pick('G98', 'G99')} {pick(*_CYCLES)} X{pick('20.', '#3', '#4')} Y{pick('20.', '#4')} "
                     f"Z{pick('#1', '-5.', '#2')} R{pick('#2', '2.', '#5')} F100.",
                     f"X{pick('40.', '#3', '[#3+10.]')}", "G80"]
        elif step == 1:
            body += [f"G00 Z{pick('#2', '#5', '5.')}", f"G01 Z{pick('#1', '-3.')} F100.",
                     f"G01 X{pick('#3', '60.', '[#3+20.]')} Y{pick('#4', '30.')}", f"G00 Z{pick('#5', '50.')}"]
        elif step == 2:
            body.append(f"G00 X{pick('#3', '70.', '[#4+5.]')} Y{pick('#4', '40.')}")
        elif step == 3:
            body.append(f"G00 Z{pick('#1', '#2', '#5', '20.')}")
        else:
            body.append(f"G01 X{pick('#3', '80.')} Z{pick('#1', '-2.')} F200.")
    body += ["G00 Z50.", "M30"]
    return values, body


_HEAD = [STOCK, "(ncverify: tool 1 radius 5 length 60)"]


def _violations(result) -> set:
    return {(d.rule, d.span.line) for d in violated(result)}


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(drilling_and_contour())
def test_pinned_parameters_give_the_same_violations_as_assigned_ones(case):
    """``#1=-5.`` at the top, or ``ncverify: assume #1 == -5.`` with the same line count:
    the symbolic analysis with every parameter pinned agrees with the concrete one."""
    values, body = case
    assigned = "\n".join(_HEAD + [f"{name}={literal(value)}" for name, value in values.items()] + body) + "\n"
    pinned = "\n".join(_HEAD + [f"(ncverify: assume {name} == {literal(value)})" for name, value in values.items()] + body) + "\n"
    # against the blank: the solver judges symbolic rapids against it, and the cut stock only
    # through the concrete replay of a witness (which makes a crash the cuts avoid unknown)
    concrete, symbolic = check(assigned, stock_resolution=0.0), check(pinned, stock_resolution=0.0)
    assert _violations(symbolic) == _violations(concrete)
    assert not [d for d in symbolic.diagnostics if NOT_REPRODUCED in (d.reason or "")]


# --------------------------------------------------------------------------- property: proved holds, violated reproduces


@st.composite
def cycle_with_ranges(draw):
    low = draw(st.sampled_from((-20.0, -12.0, -6.0, -3.0, -1.0, 0.0, 1.0, 2.0)))
    width = draw(st.sampled_from((0.5, 1.0, 3.0, 8.0, 15.0)))
    top = draw(st.sampled_from((0.0, 1.0, -1.0)))
    symbolic_r = draw(st.booleans())
    r_low = draw(st.sampled_from((-3.0, -1.0, 0.0, 1.0, 2.0)))
    r_point = "#2" if symbolic_r else literal(draw(st.sampled_from((-1.0, 0.0, 2.0, 3.0, 5.0))))
    initial = draw(st.sampled_from(("50.", "3.", "1.5")))
    x = draw(st.sampled_from(("10.", "50.", "150.")))
    retract = draw(st.sampled_from(("G98", "G99")))
    lines = [f"(ncverify: stock box X0:100 Y0:80 Z-30:{literal(top)})",
             f"(ncverify: assume {literal(low)} <= #1 <= {literal(low + width)})"]
    if symbolic_r:
        lines.append(f"(ncverify: assume {literal(r_low)} <= #2 <= {literal(r_low + 4.0)})")
    lines += ["G21 G17 G40 G49 G80 G90", f"G00 G54 X{x} Y10.", f"G00 Z{initial} S1000 M03",
              f"{retract} G81 X{x} Y10. Z#1 R{r_point} F100.", f"X[{x}+5.]", "G80", f"G00 Z{initial}", "M30"]
    ranges = {"#1": (low, low + width)}
    if symbolic_r:
        ranges["#2"] = (r_low, r_low + 4.0)
    return "\n".join(lines) + "\n", ranges


def _samples(ranges: dict, draw_fraction) -> list[dict]:
    names = sorted(ranges)
    corners = [{}]
    for name in names:
        low, high = ranges[name]
        corners = [dict(c, **{name: value}) for c in corners for value in (low, high)]
    middle = {name: (low + high) / 2 for name, (low, high) in ranges.items()}
    inside = {name: low + (high - low) * draw_fraction(name) for name, (low, high) in ranges.items()}
    return corners + [middle, inside]


@settings(max_examples=50, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cycle_with_ranges(), st.data())
def test_proved_holds_on_sampled_values_and_violated_reproduces(case, data):
    text, ranges = case
    result = check(text, stock_resolution=0.0)  # the blank, as the solver sees it (see the test above)
    findings = [d for d in result.diagnostics if d.rule in LEVEL_RULES]
    assert not [d for d in findings if NOT_REPRODUCED in (d.reason or "")]
    assert_reproduces(text, result, stock_resolution=0.0)
    proved = {(d.rule, d.span.line) for d in findings if d.status is Status.PROVED}
    if not proved:
        return
    fraction = lambda name: data.draw(st.integers(0, 1000), label=f"thousandths of {name}") / 1000  # noqa: E731
    for values in _samples(ranges, fraction):
        concrete = check(substitute(text, values))
        wrong = [(d.rule, d.span.line) for d in violated(concrete) if (d.rule, d.span.line) in proved]
        assert not wrong, f"proved but violated for {values}: {wrong}"


@given(st.sampled_from(["<", "<=", ">", ">=", "==", "!=", "LT", "LE", "GT", "GE", "EQ", "NE"]),
       st.floats(allow_nan=True, allow_infinity=True), st.floats(allow_nan=True, allow_infinity=True))
def test_a_hazard_between_two_numbers_is_what_the_value_comparison_says(relation, a, b):
    """Two numbers skip the general comparison (it runs for every hole and move): the answer
    must be the one it gives, NaN and infinities included."""
    from ncverify import values
    from ncverify.verdict import hazard

    name = {"<": "LT", "<=": "LE", ">": "GT", ">=": "GE", "==": "EQ", "!=": "NE"}.get(relation, relation)
    assert hazard(relation, a, b) is values.compare(name, a, b)
