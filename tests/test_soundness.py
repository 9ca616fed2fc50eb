"""Soundness: ``proved`` is never said of a hazard that can happen.

Each class of cause that once turned a real hazard into ``proved`` has a test here (and a
regression program in ``corpus/``): coordinate shifts the stock check did not see, proofs
over a path budget that ran out, arcs judged by their end points, the tool taken as a line.
The property test at the end holds the stock check and the travel check to one point,
computed here independently of ncverify's frame code, for random chains of shifts,
rotations, scalings and mirror images in every dialect.
"""
from __future__ import annotations

import math
import tempfile
import textwrap
from pathlib import Path

import numpy
from hypothesis import HealthCheck, given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_file, check_text
from ncverify.diagnostics import Status


def statuses(result, rule: str, line: int) -> list[Status]:
    return sorted({d.status for d in result.diagnostics if d.rule == rule and d.span.line == line}, key=lambda status: status.value)


def iso(body: str) -> str:
    return "%\nO1000\n" + textwrap.dedent(body).strip() + "\nM30\n%\n"


# --------------------------------------------------------------------------- 1. coordinate shifts

SHIFTED_APPROACH = """
    (ncverify: stock box X0:100 Y0:100 Z-20:0)
    (ncverify: assume -160 <= #1 <= -140)
    G21 G90 G54 G17
    G00 X-20. Y50. Z50.
    {shift}
    G00 Z-5.
    G00 X#1
    G00 X-150.
"""


def test_a_g52_local_origin_reaches_the_stock_check_symbolic_and_concrete():
    result = check_text(iso(SHIFTED_APPROACH.format(shift="G52 X200.")))
    assert statuses(result, "core.rapid-into-stock", 9) == [Status.VIOLATED]  # symbolic: was "proved"
    assert statuses(result, "core.rapid-into-stock", 10) == [Status.VIOLATED]  # concrete X-150. is X50. on the blank


def test_a_g92_preset_reaches_the_stock_check():
    result = check_text(iso(SHIFTED_APPROACH.format(shift="G92 X-220.")))
    [finding] = [d for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == 9]
    assert finding.status is Status.VIOLATED and -160 <= finding.witness["#1"] <= -140


def test_a_second_g52_replaces_the_local_origin_instead_of_adding_to_it():
    result = check_text(iso("""
        (ncverify: stock box X0:100 Y0:100 Z-20:0)
        G21 G90 G54 G17
        G00 X-20. Y50. Z50.
        G52 X200.
        G52 X50.
        G00 Z-5.
        G00 X-60.
        G00 X10.
    """))
    assert statuses(result, "core.rapid-into-stock", 9) == []  # is X-10. on the blank: beside it
    assert statuses(result, "core.rapid-into-stock", 10) == [Status.VIOLATED]  # X10. is X60.


def test_a_reference_return_cancels_the_local_origin():
    result = check_text(iso("""
        (ncverify: stock box X0:100 Y0:100 Z-20:0)
        G21 G90 G54 G17
        G00 X-20. Y50. Z50.
        G52 X-200.
        G91 G28 X0.
        G90 G00 X-20.
        G00 Z-5.
        G00 X-10.
    """))
    assert statuses(result, "core.rapid-into-stock", 10) == []  # without the cancel, X-10. would be X-210. and X-20. X-220.


# --------------------------------------------------------------------------- 2. the path budget

BRANCHES = """
    (ncverify: stock box X0:100 Y0:100 Z-20:0) (ncverify: tool 1 radius 2 length 60)
    (ncverify: assume 0 <= #1 <= 10 and 0 <= #2 <= 10)
    G21 G90 G54 G17 T1 M06 G43 H01
    G00 X-20. Y50. Z50.
    G00 Z-5.
    #3 = -10.
    IF [#1 GT 5.] GOTO 10
    #3 = 40.
    N10 IF [#2 GT 5.] GOTO 20
    #3 = #3 - 5.
    N20 G00 X[#3 - #1]
"""


def test_proofs_over_an_exhausted_path_budget_become_unknown():
    full = check_text(iso(BRANCHES))
    assert statuses(full, "core.rapid-into-stock", 13) == [Status.VIOLATED]  # the hazard is on the path #1 <= 5
    for disabled in (frozenset(), frozenset({"core.path-limit"})):
        cut = check_text(iso(BRANCHES), settings=Settings(max_paths=3, disabled_rules=disabled))
        [*findings] = [d for d in cut.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == 13]
        assert findings and all(d.status is Status.UNKNOWN and d.reason.startswith("paths left unexplored") for d in findings)
        assert not [d for d in cut.diagnostics if d.status is Status.PROVED]


def test_proofs_stand_when_every_path_was_explored():
    safe = BRANCHES.replace("#3 = 40.", "#3 = -40.")
    result = check_text(iso(safe))
    assert statuses(result, "core.rapid-into-stock", 13) == [Status.PROVED]


# --------------------------------------------------------------------------- 3. arcs and their extremes

def _arc_program(tmp_path: Path, high: float) -> Path:
    (tmp_path / "ncverify.toml").write_text(textwrap.dedent("""
        [machine]
        travel = { x = [-400, 100], y = [-250, 250], z = [-300, 100] }
        work_offsets = { G54 = [0, 0, -200] }
    """))
    program = tmp_path / "arc.nc"
    program.write_text(iso(f"""
        (ncverify: assume 5 <= #1 <= {high:g})
        G21 G90 G54 G17
        G00 X0. Y0. Z2.
        G01 Z-2. F100.
        G02 X0. Y0. I#1 J0.
    """))
    return program


def test_a_symbolic_arc_inside_the_travel_is_proved_through_its_whole_circle(tmp_path):
    result = check_file(_arc_program(tmp_path, 40))
    assert statuses(result, "core.travel-limit", 7) == [Status.PROVED]


def test_a_symbolic_arc_whose_extremes_may_pass_the_travel_is_not_proved(tmp_path):
    # both end points are X0.: only the swept quadrant point X = 2 * #1 reaches the limit
    result = check_file(_arc_program(tmp_path, 60))
    assert statuses(result, "core.travel-limit", 7) == [Status.UNKNOWN]


def test_an_arc_ending_on_its_start_s_ray_off_the_circle_is_judged_by_its_whole_circle(tmp_path):
    """G02 from X0 Y0 about X60 Y45 to X-0.006 Y-0.0045: the end lies on the start's ray,
    off the circle, so the arc turns once or not at all as the control's rounding falls. Its
    end points are well inside the travel; a full turn would reach X135, past it."""
    program = _arc_program(tmp_path, 40)
    program.write_text(iso("""
        G21 G90 G54 G17
        G00 X0. Y0. Z2.
        G01 Z-2. F100.
        G02 X-0.006 Y-0.0045 I60. J45.
    """))
    result = check_file(program)
    assert statuses(result, "core.travel-limit", 6) == [Status.UNKNOWN]
    assert "rounding" in [d for d in result.diagnostics if d.rule == "core.travel-limit"][0].reason


# --------------------------------------------------------------------------- one coordinate pipeline

WORK_OFFSET = (-300.0, -200.0, -250.0)


def _translation(x=0.0, y=0.0, z=0.0):
    matrix = numpy.identity(4)
    matrix[:3, 3] = (x, y, z)
    return matrix


def _rotation(degrees):
    matrix = numpy.identity(4)
    cos, sin = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    matrix[:2, :2] = ((cos, -sin), (sin, cos))
    return matrix


def _scaling(x, y, z):
    return numpy.diag((x, y, z, 1.0))


shifts = st.integers(-100, 100).map(float)
angles = st.sampled_from([0.0, 15.0, 30.0, 45.0, 90.0, 120.0, -60.0, 180.0])
factors = st.sampled_from([0.5, 1.0, 2.0])


@st.composite
def iso_chain(draw, local_origin=True):
    """G52 and G92 in any order (Fagor: its preset G92 only): the program text and the
    workpiece map (independent model)."""
    position, shift, local = numpy.array((0.0, 0.0, 300.0)), numpy.zeros(3), numpy.zeros(3)
    lines = ["G00 X0. Y0. Z300."]
    for _ in range(draw(st.integers(1, 4))):
        x, y = draw(shifts), draw(shifts)
        if local_origin and draw(st.booleans()):
            lines.append(f"G52 X{x:.1f} Y{y:.1f}")
            change = numpy.array((x, y, 0.0)) - local
            local, shift, position = numpy.array((x, y, 0.0)), shift + change, position - change
        else:
            lines.append(f"G92 X{x:.1f} Y{y:.1f}")
            new = numpy.array((x, y, position[2]))
            shift, position = shift + position - new, new
    return lines, _translation(*shift)


@st.composite
def fagor_chain(draw):
    lines, matrix = draw(iso_chain(local_origin=False))
    return [line.replace(".0", "").replace("G00", "G0") for line in lines], matrix


@st.composite
def sinumerik_chain(draw):
    """TRANS replaces the frame; ATRANS, AROT, ASCALE and AMIRROR append in the current system."""
    matrix, lines = numpy.identity(4), ["G0 X0 Y0 Z300"]
    for _ in range(draw(st.integers(1, 5))):
        kind = draw(st.sampled_from(["TRANS", "ATRANS", "AROT", "ASCALE", "AMIRROR"]))
        if kind in ("TRANS", "ATRANS"):
            x, y = draw(shifts), draw(shifts)
            lines.append(f"{kind} X={x:g} Y={y:g}")
            matrix = _translation(x, y) if kind == "TRANS" else matrix @ _translation(x, y)
        elif kind == "AROT":
            angle = draw(angles)
            lines.append(f"AROT RPL={angle:g}")
            matrix = matrix @ _rotation(angle)
        elif kind == "ASCALE":
            factor = draw(factors)
            lines.append(f"ASCALE X={factor:g} Y={factor:g}")
            matrix = matrix @ _scaling(factor, factor, 1.0)
        else:
            lines.append("AMIRROR X0")
            matrix = matrix @ _scaling(-1.0, 1.0, 1.0)
    return lines, matrix


@st.composite
def heidenhain_chain(draw):
    """Cycles 7, 8, 10 and 11: a point is scaled, rotated, mirrored, then shifted."""
    shift, mirrored, angle, factor = (0.0, 0.0), False, 0.0, 1.0
    lines = ["L X+0 Y+0 Z+300 R0 FMAX"]
    for _ in range(draw(st.integers(1, 5))):
        kind = draw(st.sampled_from([7, 8, 10, 11]))
        if kind == 7:
            shift = (draw(shifts), draw(shifts))
            lines += ["CYCL DEF 7.0 DATUM SHIFT", f"CYCL DEF 7.1 X{shift[0]:+g}", f"CYCL DEF 7.2 Y{shift[1]:+g}"]
        elif kind == 8:
            mirrored = True
            lines += ["CYCL DEF 8.0 MIRROR IMAGE", "CYCL DEF 8.1 X"]
        elif kind == 10:
            angle = draw(angles)
            lines += ["CYCL DEF 10.0 ROTATION", f"CYCL DEF 10.1 ROT{angle:+g}"]
        else:
            factor = draw(factors)
            lines += ["CYCL DEF 11.0 SCALING", f"CYCL DEF 11.1 SCL{factor:g}"]
    matrix = _translation(*shift) @ _scaling(-1.0 if mirrored else 1.0, 1.0, 1.0) @ _rotation(angle) @ _scaling(factor, factor, factor)
    return lines, matrix


def _program(dialect: str, lines: list[str], point, stock: str) -> tuple[str, str, int]:
    """The program text, its file name, and the line of the final rapid to ``point``."""
    x, y, z = point
    if dialect == "iso":
        body = ["%", "O1000", f"({stock})", "G21 G90 G54 G17", *lines, f"G00 X{x:.1f} Y{y:.1f} Z{z:.1f}", "M30", "%"]
        return "\n".join(body) + "\n", "part.nc", len(body) - 2
    if dialect == "fagor":
        body = ["; ncverify-test", f"; {stock}", "G17 G90 G54", *lines, f"G0 X{x:g} Y{y:g} Z{z:g}", "M30"]
        return "\n".join(body) + "\n", "part.pim", len(body) - 1
    if dialect == "sinumerik":
        body = [f"; {stock}", "G17 G90 G54", *lines, f"G0 X{x:g} Y{y:g} Z{z:g}", "M30"]
        return "\n".join(body) + "\n", "part.mpf", len(body) - 1
    body = ["BEGIN PGM PART MM", f"; {stock}", *lines, f"L X{x:+g} Y{y:+g} Z{z:+g} R0 FMAX", "END PGM PART MM"]
    return "\n".join(f"{number} {line}" for number, line in enumerate(body)) + "\n", "part.h", len(body) - 1


CHAINS = {"iso": iso_chain(), "fagor": fagor_chain(), "sinumerik": sinumerik_chain(), "heidenhain": heidenhain_chain()}


@hypothesis_settings(max_examples=15, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(dialect=st.sampled_from(sorted(CHAINS)), data=st.data(),
       point=st.tuples(st.integers(-50, 50), st.integers(-50, 50), st.integers(-20, 20)).map(lambda p: tuple(map(float, p))))
def test_the_stock_check_and_the_travel_check_see_the_same_point(dialect, data, point):
    lines, matrix = data.draw(CHAINS[dialect])
    workpiece = (matrix @ numpy.array((*point, 1.0)))[:3]
    stock = "ncverify: stock box " + " ".join(f"{axis}{value - 0.4:.4f}:{value + 0.4:.4f}" for axis, value in zip("XYZ", workpiece))
    machine = workpiece + WORK_OFFSET
    text, name, line = _program(dialect, lines, point, stock)
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "ncverify.toml").write_text(
            f"[machine]\ntravel = {{ x = [{machine[0] - 0.5}, {machine[0] + 0.5}], y = [{machine[1] - 0.5}, {machine[1] + 0.5}], z = [-10000, 10000] }}\n"
            f"work_offsets = {{ G54 = {list(WORK_OFFSET)} }}\n")
        program = Path(folder) / name
        program.write_text(text)
        result = check_file(program, Settings(dialect=dialect))
    # the end point is inside the small stock around the point, and within 0.5 mm of it in the travel
    assert statuses(result, "core.rapid-into-stock", line) == [Status.VIOLATED], text
    assert Status.VIOLATED not in statuses(result, "core.travel-limit", line), text


# --------------------------------------------------------------------------- 4. the tool as a cylinder

BESIDE = """
    (ncverify: stock box X0:100 Y0:100 Z-20:0)
    {tool}
    (ncverify: assume {low} <= #1 <= {high})
    G21 G90 G54 {plane}
    T1 M06 G43 H01
    G00 X-30. Y50. Z50.
    G00 X[-#1]
    G00 Z-5.
"""
TOOL_R5 = "(ncverify: tool 1 radius 5 length 60)"


def _beside(tool=TOOL_R5, low=2, high=20, plane="G17"):
    return check_text(iso(BESIDE.format(tool=tool, low=low, high=high, plane=plane)))


def test_a_rapid_whose_axis_misses_the_stock_but_whose_side_is_over_it_is_violated():
    result = _beside()
    [plunge] = [d for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == 10]
    assert plunge.status is Status.VIOLATED and 2 <= plunge.witness["#1"] < 5  # the axis 2-5 mm from the face


def test_a_rapid_a_tool_radius_clear_of_the_stock_is_proved():
    assert statuses(_beside(low=6), "core.rapid-into-stock", 10) == [Status.PROVED]


def test_without_the_tool_radius_or_along_another_tool_axis_the_rapid_is_not_proved():
    without_radius = _beside(tool="", low=6)
    assert statuses(without_radius, "core.rapid-into-stock", 10) == [Status.UNKNOWN]
    assert "tool radius not known" in [d for d in without_radius.diagnostics if d.span.line == 10 and d.rule == "core.rapid-into-stock"][0].reason
    tool_along_y = _beside(low=6, plane="G18")
    assert statuses(tool_along_y, "core.rapid-into-stock", 10) == [Status.UNKNOWN]


def test_the_tool_body_above_a_tip_below_the_stock_touches_it():
    # the tip at Z-30 under a plate 20 deep: the body up to Z30 passes through it
    result = check_text(iso("""
        (ncverify: stock box X0:100 Y0:100 Z-20:0)
        (ncverify: tool 1 radius 5 length 60)
        G21 G90 G54 G17
        T1 M06 G43 H01
        G00 X-30. Y50. Z-30.
        G00 X50.
    """))
    assert statuses(result, "core.rapid-into-stock", 8) == [Status.VIOLATED]


# --------------------------------------------------------------------------- what the stock proof reads

# A symbolic rapid clear of the stock in the plain state (tool along +Z, radius known, no
# frame, every path explored). Under each state the rule models it stays provable; under
# each state it does not read, it must not be proved.
CLEAR = """
    ; ncverify: stock box X0:100 Y0:100 Z-20:0
    ; ncverify: tool 1 radius 5 length 60
    ; ncverify: assume 10 <= R1 <= 20
    G90 G54 {plane}
    T1 D1 M6
    G0 X-50 Y50 Z50
    {state}
    G0 X=-R1-20 Y50 Z=-5
"""
MODELLED = {"none": "", "translation": "TRANS X=-10", "rotation": "ROT RPL=180", "scale": "SCALE X=2 Y=2", "mirror": "MIRROR Y0"}
NOT_MODELLED = {
    "tilted plane": "ROT X=30",
    "rotation by a free parameter": "ROT RPL=R1",
    "scale by a free parameter": "SCALE X=R1 Y=R1",
    "tool axis Y (G18)": "G18",
    "tool axis X (G19)": "G19",
    "no tool radius": "T2 D1 M6",
}


def _clear(state: str):
    text = textwrap.dedent(CLEAR.format(plane="G17", state=state)).lstrip()
    return check_text(text, "part.mpf", Settings(dialect="sinumerik"))


def test_the_rapid_is_proved_under_every_state_the_stock_rule_models():
    for name, state in MODELLED.items():
        assert statuses(_clear(state), "core.rapid-into-stock", 8) == [Status.PROVED], name


def test_the_rapid_is_never_proved_under_a_state_the_stock_rule_does_not_read():
    for name, state in NOT_MODELLED.items():
        result = _clear(state)
        assert Status.PROVED not in statuses(result, "core.rapid-into-stock", 8), name
        assert [d for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.status is Status.UNKNOWN], name  # said, not silent


# --------------------------------------------------------------------------- proof reach: symbolic cycle sizes

POCKET_252 = Path(__file__).with_name("data_symbolic_pocket.h")


def test_a_klartext_circular_pocket_of_symbolic_diameter_gets_a_verdict():
    template = POCKET_252.read_text()
    tight = check_text(template.replace("{low}", "8"), "p.h")
    [finding] = [d for d in tight.diagnostics if d.rule == "heidenhain.tool-too-large"]
    assert finding.status is Status.VIOLATED and 8 <= finding.witness["Q1"] <= 10  # a 10 mm tool in a pocket of 10 or less
    roomy = check_text(template.replace("{low}", "10.5"), "p.h")
    assert [d.status for d in roomy.diagnostics if d.rule == "heidenhain.tool-too-large"] == [Status.PROVED]


def test_the_stock_proof_takes_the_radius_of_the_active_cutting_edge():
    text = textwrap.dedent("""
        ; ncverify: stock box X0:100 Y0:100 Z-20:0
        ; ncverify: assume 5 <= R1 <= 20
        $TC_DP1[1,1]=120 $TC_DP6[1,1]=2 $TC_DP3[1,1]=60
        $TC_DP1[1,2]=120 $TC_DP6[1,2]=8 $TC_DP3[1,2]=60
        G17 G90 G54
        T1 {edge} M6
        G0 X-50 Y50 Z50
        G0 X=-R1 Y50 Z=-5
        M30
    """).lstrip()
    small = check_text(text.format(edge="D1"), "part.mpf", Settings(dialect="sinumerik"))
    assert statuses(small, "core.rapid-into-stock", 8) == [Status.PROVED]
    large = check_text(text.format(edge="D2"), "part.mpf", Settings(dialect="sinumerik"))
    assert statuses(large, "core.rapid-into-stock", 8) == [Status.VIOLATED]  # the 8 mm edge reaches over the face from 5 mm away
