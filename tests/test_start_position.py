"""Where the tool starts (``[machine] start``): the first positioning rapid, and the first
rapid after a reference return or a full retract, are judged from the start position, not
from nowhere. The default start is above the stock's top by the stock's height, with the
other axes unknown; the report's assumptions state it."""
from __future__ import annotations

import json

import pytest
from hypothesis import given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_file
from ncverify.cli import main
from ncverify.diagnostics import Status
from ncverify.project import ConfigError, load_project_text

# A box 100 x 50 x 20 with its top at Z0 (default start: Z20). The tool first stands beside
# the stock at X-20 Z5; after the park line, one rapid runs from there over the stock down
# to Z-5 past its far side: from the top of the travel (or Z20) it cuts the corner at X100.
_ISO = """(ncverify: stock box X0:100 Y0:50 Z-20:0)
(ncverify: tool 1 radius 5 length 50)
T1 M06 G43 H01
G90 G00 X-20. Y25. Z5. S1000 M03
{park}
G90 G00 X120. Y25. Z-5.
M30
"""
_SINUMERIK = """%_N_PARK_MPF
; ncverify: stock box X0:100 Y0:50 Z-20:0
; ncverify: tool 1 radius 5 length 50
T1 D1
M6
G90 G0 X-20 Y25 Z5 S1000 M3
{park}
G90 G0 X120 Y25 Z-5
M30
"""
_KLARTEXT = """0 BEGIN PGM START MM
1 BLK FORM 0.1 Z X+0 Y+0 Z-20
2 BLK FORM 0.2 X+100 Y+50 Z+0
3 TOOL CALL 1 Z S1000
4 L X-20 Y+25 Z+5 R0 FMAX M3
5 {park}
6 L X+120 Y+25 Z-5 R0 FMAX
7 END PGM START MM
"""
_FAGOR = """; ncverify: stock box X0:100 Y0:50 Z-20:0
; ncverify: tool 1 radius 5 length 50
T1 D1 M6
G90 G0 X-20 Y25 Z5 S1000 M3
{park}
G90 G0 X120 Y25 Z-5
M30
"""

PARKS = [
    ("park.nc", _ISO, "G91 G28 Z0."),
    ("park.nc", _ISO, "G91 G30 P2 Z0."),
    ("park.nc", _ISO, "G53 Z0."),
    ("park.mpf", _SINUMERIK, "G0 SUPA Z0"),
    ("park.mpf", _SINUMERIK, "G0 G153 Z0"),
    ("park.mpf", _SINUMERIK, "G74 Z1=0"),
    ("park.h", _KLARTEXT, "L M140 MB MAX"),
    ("park.pim", _FAGOR, "G74 Z"),
]
NOT_PARKED = [  # the axis goes somewhere in machine coordinates that is not the reference point
    ("park.nc", _ISO, "G53 Z-100."),
    ("park.mpf", _SINUMERIK, "G0 SUPA Z-100"),
    ("park.h", _KLARTEXT, "L Z-100 R0 FMAX M91"),
    ("park.pim", _FAGOR, "G53 Z-100"),
]


def _rapid_verdicts(tmp_path, name: str, text: str, line: int | None = None, **options) -> set[Status]:
    """The verdicts of the stock rule on ``line`` (by default the rapid to X120)."""
    if line is None:
        line = next(number for number, code in enumerate(text.splitlines(), 1) if "X120" in code or "X+120" in code)
    program = tmp_path / name
    program.write_text(text, encoding="utf-8")
    result = check_file(program, Settings(**options))
    return {d.status for d in result.diagnostics if d.rule == "core.rapid-into-stock" and d.span.line == line}


@pytest.mark.parametrize("name, template, park", PARKS, ids=[park for _, _, park in PARKS])
def test_a_rapid_after_a_reference_return_or_full_retract_is_judged_from_the_start_height(tmp_path, name, template, park):
    assert _rapid_verdicts(tmp_path, name, template.format(park=park)) == {Status.VIOLATED}


@pytest.mark.parametrize("name, template, move", NOT_PARKED, ids=[move for _, _, move in NOT_PARKED])
def test_a_machine_move_elsewhere_leaves_the_height_unknown(tmp_path, name, template, move):
    assert _rapid_verdicts(tmp_path, name, template.format(park=move)) == {Status.UNKNOWN}


_FIRST_RAPID = """(ncverify: stock box X0:100 Y0:50 Z-20:0)
(ncverify: tool 1 radius 5 length 50)
T1 M06
G90 G00 X{x:g} Y{y:g} S1000 M03
G43 H01 Z5.
G01 Z-1. F100.
G00 Z5.
M30
"""


@hypothesis_settings(max_examples=25, deadline=None)
@given(x=st.integers(-200, 300), y=st.integers(-200, 300))
def test_the_first_positioning_rapid_at_the_start_height_is_clear(tmp_path_factory, x, y):
    """From the start height, a rapid in X and Y alone passes over the stock wherever it goes:
    no finding, not even unknown."""
    tmp_path = tmp_path_factory.mktemp("first")
    assert _rapid_verdicts(tmp_path, "first.nc", _FIRST_RAPID.format(x=x, y=y), 4) == set()


def test_without_a_start_position_the_first_rapid_is_unknown(tmp_path):
    (tmp_path / "ncverify.toml").write_text('[machine]\nstart = "unknown"\n', encoding="utf-8")
    assert _rapid_verdicts(tmp_path, "first.nc", _FIRST_RAPID.format(x=50, y=25), 4) == {Status.UNKNOWN}


_DIAGONAL = """(ncverify: stock box X0:100 Y0:50 Z-20:0)
(ncverify: tool 1 radius 5 length 50)
T1 M06 G43 H01
G90 G00 X-20. Y25. Z-5. S1000 M03
M30
"""


def test_a_start_position_given_in_the_project_file_decides_the_first_rapid(tmp_path):
    """Beside the stock at Z-5: from an unknown X and Y that is unknown; from a start right
    above the middle of the stock the rapid runs down through it."""
    assert _rapid_verdicts(tmp_path, "diagonal.nc", _DIAGONAL, 4) == {Status.UNKNOWN}
    (tmp_path / "ncverify.toml").write_text("[machine]\nstart = { x = 50, y = 25, z = 10 }\n", encoding="utf-8")
    assert _rapid_verdicts(tmp_path, "diagonal.nc", _DIAGONAL, 4) == {Status.VIOLATED}
    (tmp_path / "ncverify.toml").write_text("[machine]\nstart = { x = -20, y = 25, z = 100 }\n", encoding="utf-8")
    assert _rapid_verdicts(tmp_path, "diagonal.nc", _DIAGONAL, 4) == set()


def test_a_called_program_checked_alone_does_not_start_at_the_start_position(tmp_path):
    """A subprogram runs where its caller left the tool: its first rapid stays unknown."""
    text = "O2000\n(ncverify: stock box X0:100 Y0:50 Z-20:0)\nG90 G00 X-20. Y25. Z-5.\nM99\n"
    assert _rapid_verdicts(tmp_path, "O2000.nc", text, 3) == {Status.UNKNOWN}
    assert _rapid_verdicts(tmp_path, "main.nc", text.replace("M99", "M30").replace("O2000", "O1000"), 3) == {Status.UNKNOWN}


def test_the_report_states_the_start_position(tmp_path, capsys):
    program = tmp_path / "first.nc"
    program.write_text(_FIRST_RAPID.format(x=50, y=25), encoding="utf-8")
    main(["check", "--no-cache", "--format", "json", str(program)])
    entry = json.loads(capsys.readouterr().out)["files"][0]
    assert entry["assumptions"] == ["the tool starts at Z20, and reference returns and full retracts take it back there "
                                    "(the default: above the stock top by its height, other axes unknown)"]
    (tmp_path / "ncverify.toml").write_text("[machine]\nstart = { x = 0, y = 0, z = 150 }\n", encoding="utf-8")
    main(["check", "--no-cache", "--verbose", str(program)])
    assert "assumed: the tool starts at X0 Y0 Z150" in capsys.readouterr().err


def test_no_stock_and_no_start_assume_nothing(tmp_path, capsys):
    program = tmp_path / "bare.nc"
    program.write_text("G90 G00 X10. Y10.\nM30\n", encoding="utf-8")
    main(["check", "--no-cache", "--format", "json", str(program)])
    assert "assumptions" not in json.loads(capsys.readouterr().out)["files"][0]


@pytest.mark.parametrize("value, message", [
    ('"home"', 'expected a table of axes'),
    ("{ q = 1 }", "[machine] start.q: unknown axis"),
    ('{ z = "high" }', "[machine] start.z: expected a finite number"),
])
def test_a_bad_start_position_is_refused_with_its_key(tmp_path, value, message):
    with pytest.raises(ConfigError, match=message.replace("[", r"\[").replace("]", r"\]")):
        load_project_text(f"[machine]\nstart = {value}\n", tmp_path / "ncverify.toml")
