"""Context a verdict needs besides the program (README "Context: stock, tools, machine,
parameter ranges"): the project file ``ncverify.toml``, ``ncverify:`` annotations, and the
``unknown`` answers when context is missing."""
from __future__ import annotations

import json
import textwrap
from pathlib import Path

import pytest

from ncverify import Settings, check_file, check_text
from ncverify.cli import main as cli_main
from ncverify.diagnostics import Severity, Status
from ncverify.project import ConfigError, load_project_text


def program(text: str) -> str:
    return textwrap.dedent(text).lstrip("\n")


def toml(text: str) -> str:
    return textwrap.dedent(text).lstrip("\n")


def check(text: str, project: str | None = None, **options):
    context = load_project_text(toml(project), Path("/nowhere/ncverify.toml")) if project else None
    return check_text(program(text), "t.nc", Settings(**options), context)


def at(result, rule: str, line: int | None = None, status: Status | None = None) -> list:
    return [d for d in result.diagnostics if d.rule == rule and (line is None or d.span.line == line)
            and (status is None or d.status is status)]


def rules(result) -> set[str]:
    return {d.rule for d in result.diagnostics}


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


# --------------------------------------------------------------------------- the project file

PROJECT = """
    [settings]
    loop_bound = 5
    [stock]
    box = { x = [0, 120], y = [0, 80], z = [-25, 0] }
    [tools.1]
    radius = 5.0
    length = 60
    type = "drill"
    [machine]
    travel = { x = [-400, 400], y = [-250, 250], z = [-300, 0] }
    work_offsets = { G54 = [-300, -200, -250] }
    max_spindle = 12000
    max_feed = 10000
    [assume]
    "#1" = [-20, -2]
    "#2" = "#2 > #1 + 5"
    [rules]
    disable = ["core.no-length-offset"]
    severity = { "cutter-comp" = "warning", "core.spindle-over-limit" = "warning" }
"""

# Line by line: what each piece of the project file shows.
PART = """
    G21 G17 G40 G49 G80 G90
    T1 M06
    G00 G54 X10. Y10. S2000 M03
    G43 Z50. H01
    G98 G81 X10. Y10. Z#1 R#2 F100.
    G80
    G00 Z-5.
    G00 Z50.
    S15000
    G01 X20. F12000.
    T7 M06
    G00 Z400.
    G41 G02 X30. Y20. R10. D01
    G40 G01 X40. F100.
    #100=0
    WHILE [#100 LT 8] DO1
    #100=#100+1
    END1
    M30
"""


def test_every_table_of_a_valid_project_file_is_applied(tmp_path):
    write(tmp_path, "ncverify.toml", toml(PROJECT))
    result = check_file(write(tmp_path, "part.nc", program(PART)))
    # [stock]: the rapid down to Z-5. goes into the box
    [crash] = at(result, "core.rapid-into-stock", 7, Status.VIOLATED)
    assert "box X0..120 Y0..80 Z-25..0" in crash.message
    # [assume]: #1 in -20..-2 and #2 > #1 + 5 prove the hole bottom below R on the path
    # explored, but loop_bound = 5 ends that path at the WHILE below: no proof stands
    [depth] = at(result, "core.cycle-depth-sign", 5)
    assert depth.status is Status.UNKNOWN and depth.reason.startswith("paths left unexplored")
    # [tools.N]: T1 is in the table, T7 is not
    assert [d.span.line for d in at(result, "core.tool-not-in-table")] == [11]
    # [machine]: travel with the G54 values and the tool length, spindle and feed limits
    [over] = at(result, "core.travel-limit", 12, Status.VIOLATED)
    assert "210" in over.message  # 400 - 250 + 60
    assert at(result, "core.spindle-over-limit", status=Status.VIOLATED)
    assert at(result, "core.feed-over-limit", 10, Status.VIOLATED)
    assert not [d for d in result.diagnostics if d.status is Status.UNKNOWN and "ncverify.toml" in (d.reason or "")]
    # [rules]: severity by category and by rule id
    [arc] = at(result, "core.comp-on-arc")
    assert arc.severity is Severity.WARNING
    assert at(result, "core.spindle-over-limit", status=Status.VIOLATED)[0].severity is Severity.WARNING
    # [settings]: loop_bound = 5
    [loop] = at(result, "core.loop-bound")
    assert "ran 5 times" in loop.message


def test_the_project_file_is_found_in_a_folder_above_the_program(tmp_path):
    write(tmp_path, "ncverify.toml", toml(PROJECT))
    result = check_file(write(tmp_path, "jobs/2024/bracket/part.nc", program(PART)))
    assert at(result, "core.rapid-into-stock", 7, Status.VIOLATED)
    assert [d.span.line for d in at(result, "core.tool-not-in-table")] == [11]


def test_the_nearest_project_file_wins(tmp_path):
    write(tmp_path, "ncverify.toml", toml(PROJECT))
    write(tmp_path, "jobs/ncverify.toml", toml("""
        [stock]
        box = { x = [0, 120], y = [0, 80], z = [-25, -10] }
    """))
    result = check_file(write(tmp_path, "jobs/bracket/part.nc", program(PART)))
    assert not at(result, "core.rapid-into-stock", 7, Status.VIOLATED)  # Z-5. is above this stock
    assert at(result, "core.tool-not-in-table", status=Status.UNKNOWN)  # no [tools] in the nearer file


def test_without_a_project_file_the_program_is_checked_without_context(tmp_path):
    result = check_file(write(tmp_path, "part.nc", program(PART)))
    assert [d.reason for d in at(result, "core.rapid-into-stock")] == ["no stock defined"]


def test_config_on_the_command_line_names_a_file_that_is_not_above_the_program(tmp_path, capsys):
    config = write(tmp_path, "elsewhere/shop.toml", toml(PROJECT))
    part = write(tmp_path, "jobs/part.nc", program(PART))
    code = cli_main(["check", str(part), "--config", str(config), "--format", "json"])
    entries = json.loads(capsys.readouterr().out)["files"][0]["diagnostics"]
    assert code == 1
    assert any(d["rule"] == "core.rapid-into-stock" and d["line"] == 7 and d["status"] == "violated" for d in entries)
    # the [assume] ranges leave no violation; loop_bound = 5 ends the path, so no proof stands
    assert any(d["rule"] == "core.cycle-depth-sign" and d["status"] == "unknown" and d["reason"].startswith("paths left unexplored") for d in entries)


def test_config_on_the_command_line_replaces_the_file_found_upward(tmp_path, capsys):
    write(tmp_path, "ncverify.toml", toml(PROJECT))
    config = write(tmp_path, "other.toml", toml("""
        [stock]
        box = { x = [0, 120], y = [0, 80], z = [-25, -10] }
    """))
    part = write(tmp_path, "part.nc", program(PART))
    cli_main(["check", str(part), "--config", str(config), "--format", "json"])
    entries = json.loads(capsys.readouterr().out)["files"][0]["diagnostics"]
    assert not any(d["rule"] == "core.rapid-into-stock" and d["line"] == 7 and d["status"] == "violated" for d in entries)
    assert any(d["rule"] == "core.tool-not-in-table" and d["status"] == "unknown" for d in entries)


def test_a_config_file_that_does_not_exist_exits_2(tmp_path, capsys):
    part = write(tmp_path, "part.nc", program(PART))
    assert cli_main(["check", str(part), "--config", str(tmp_path / "missing.toml")]) == 2
    assert "missing.toml" in capsys.readouterr().err


BROKEN = [
    pytest.param("[settings]\nloop_bound = 5\n[stock\nbox = 1\n", ["line 3"], id="toml-syntax"),
    pytest.param("# shop\n[settings]\nloop_bound = 5\nloop_bound = 6\n", ["line 4"], id="toml-duplicate-key"),
    pytest.param("[foo]\nx = 1\n", ["[foo]", "unknown table"], id="unknown-table"),
    pytest.param("[machine]\ntravl = 1\n", ["[machine]", "travl", "unknown key"], id="unknown-key"),
    pytest.param("[settings]\nloop_bound = \"x\"\n", ["[settings] loop_bound"], id="bad-setting-type"),
    pytest.param("[settings]\nloop_bound = 0\n", ["[settings] loop_bound", "positive"], id="bad-setting-value"),
    pytest.param("[settings]\nmachine = \"robot\"\n", ["[settings] machine", "robot"], id="bad-setting-choice"),
    pytest.param("[settings]\nfail_fast = true\n", ["[settings] fail_fast", "unknown setting"], id="unknown-setting"),
    pytest.param("[stock]\nbox = { x = [0, 120], y = [0, 80] }\n", ["[stock] box: z is missing"], id="box-without-z"),
    pytest.param("[stock]\nbox = { x = [5, 1], y = [0, 1], z = [-1, 0] }\n", ["[stock] box.x"], id="box-reversed"),
    pytest.param("[stock]\nbox = { x = [0, 1], y = [0, 1], z = [-1, 0], w = [0, 1] }\n", ["box.w", "unknown key"], id="box-extra-key"),
    pytest.param("[stock]\nbox = { x = [0, 1], y = [0, 1], z = [-1, 0] }\ncylinder = { d = 5, z = [-1, 0] }\n",
                 ["[stock]", "exactly one"], id="two-stocks"),
    pytest.param("[tools.x]\nradius = 1\n", ["[tools.x]"], id="tool-key-not-a-number"),
    pytest.param("[tools.1]\nradius = -1\n", ["[tools.1] radius", "positive"], id="tool-negative-radius"),
    pytest.param("[tools.1]\nradius = 1\ntype = \"laser\"\n", ["[tools.1] type", "laser"], id="tool-bad-type"),
    pytest.param("[tools.1]\nradius = 1\nflutes = 4\n", ["[tools.1]", "flutes"], id="tool-unknown-key"),
    pytest.param("[machine]\ntravel = { q = [0, 1] }\n", ["[machine] travel.q"], id="unknown-axis"),
    pytest.param("[machine]\nwork_offsets = { G54 = \"x\" }\n", ["[machine] work_offsets.G54"], id="bad-work-offset"),
    pytest.param("[assume]\n\"#1\" = 5\n", ["[assume] '#1'"], id="assume-not-a-range"),
    pytest.param("[assume]\n\"#1\" = \"#1 >\"\n", ["[assume] '#1'", "cannot read"], id="assume-bad-text"),
    pytest.param("[rules]\ndisable = [\"core.nope\"]\n", ["[rules] disable", "core.nope"], id="disable-unknown-rule"),
    pytest.param("[rules]\nseverity = { \"core.comp-on-arc\" = \"fatal\" }\n", ["[rules] severity.core.comp-on-arc"], id="bad-severity"),
    pytest.param("[rules]\nseverity = { \"core.nope\" = \"info\" }\n", ["[rules] severity.core.nope"], id="severity-unknown-rule"),
]


@pytest.mark.parametrize(("text", "named"), BROKEN)
def test_a_broken_project_file_exits_2_naming_the_file_and_the_place(tmp_path, capsys, text, named):
    write(tmp_path, "ncverify.toml", text)
    part = write(tmp_path, "part.nc", program(PART))
    assert cli_main(["check", str(part)]) == 2
    error = capsys.readouterr().err
    assert "ncverify.toml" in error
    for fragment in named:
        assert fragment in error, error


@pytest.mark.parametrize(("text", "named"), BROKEN[:1] + BROKEN[8:9])
def test_a_broken_project_file_given_with_config_exits_2_too(tmp_path, capsys, text, named):
    config = write(tmp_path, "shop.toml", text)
    part = write(tmp_path, "part.nc", program(PART))
    assert cli_main(["check", str(part), "--config", str(config)]) == 2
    error = capsys.readouterr().err
    assert "shop.toml" in error and all(fragment in error for fragment in named)


def test_check_file_raises_config_error_for_a_broken_project_file(tmp_path):
    write(tmp_path, "ncverify.toml", "[stock]\nbox = { x = [0, 120], y = [0, 80] }\n")
    with pytest.raises(ConfigError, match=r"ncverify\.toml: \[stock\] box: z is missing"):
        check_file(write(tmp_path, "part.nc", program(PART)))


LOOP = """
    G21 G90 G54
    #100=0
    WHILE [#100 LT 8] DO1
    #100=#100+1
    END1
    M30
"""


def test_project_settings_apply_when_the_command_line_leaves_the_option_out(tmp_path, capsys):
    write(tmp_path, "ncverify.toml", "[settings]\nloop_bound = 5\n")
    part = write(tmp_path, "loop.nc", program(LOOP))
    cli_main(["check", str(part), "--format", "json"])
    entries = json.loads(capsys.readouterr().out)["files"][0]["diagnostics"]
    assert [d["rule"] for d in entries] == ["core.loop-bound"]
    assert "ran 5 times" in entries[0]["message"]


def test_the_command_line_wins_over_project_settings(tmp_path, capsys):
    write(tmp_path, "ncverify.toml", "[settings]\nloop_bound = 5\n")
    part = write(tmp_path, "loop.nc", program(LOOP))
    cli_main(["check", str(part), "--format", "json", "--loop-bound", "20"])
    assert json.loads(capsys.readouterr().out)["files"][0]["diagnostics"] == []


def test_an_explicit_command_line_value_equal_to_the_default_still_wins(tmp_path, capsys):
    write(tmp_path, "ncverify.toml", "[settings]\nloop_bound = 5\n")
    part = write(tmp_path, "loop.nc", program(LOOP))
    cli_main(["check", str(part), "--format", "json", "--loop-bound", "10000"])
    assert json.loads(capsys.readouterr().out)["files"][0]["diagnostics"] == []


DOGLEG = """
    (ncverify: stock box X0:100 Y0:80 Z-20:0)
    G21 G90 G54
    G00 X110. Y10. Z-5.
    G00 X90. Z5.
    M30
"""


def test_rapid_path_from_the_project_settings(tmp_path):
    part = write(tmp_path, "dogleg.nc", program(DOGLEG))
    assert not at(check_file(part), "core.rapid-into-stock", 4, Status.VIOLATED)  # straight: over the corner edge
    write(tmp_path, "ncverify.toml", "[settings]\nrapid_path = \"dogleg\"\n")
    assert at(check_file(part), "core.rapid-into-stock", 4, Status.VIOLATED)  # X first, at Z-5.: in the corner


def test_a_dogleg_rapid_finds_at_least_what_the_straight_one_finds():
    text = """
        (ncverify: stock box X0:100 Y0:80 Z-20:0)
        G21 G90 G54
        G00 X-10. Y10. Z5.
        G00 X10. Z-5.
        M30
    """
    assert at(check(text), "core.rapid-into-stock", 4, Status.VIOLATED)
    assert at(check(text, rapid_path="dogleg"), "core.rapid-into-stock", 4, Status.VIOLATED)


def test_project_machine_type_applies_and_the_command_line_overrides_it(tmp_path, capsys):
    write(tmp_path, "ncverify.toml", "[settings]\nmachine = \"lathe\"\n")
    part = write(tmp_path, "p.nc", program("G21 G90\nG00 X20. Z5.\nM30\n"))
    assert check_file(part).machine == "lathe"
    cli_main(["check", str(part), "--format", "json", "--machine", "mill"])
    assert json.loads(capsys.readouterr().out)["files"][0]["machine"] == "mill"


COMP_AND_LENGTH = """
    G21 G17 G40 G49 G80 G90
    T1 M06
    G00 G54 X0. Y0. S1000 M03
    Z5.
    G01 Z-1. F100.
    G41 G02 X20. Y20. R20. D01
    G40 G01 X40.
    M30
"""


@pytest.mark.parametrize("name", ["core.comp-on-arc", "cutter-comp"])
def test_rules_disable_by_rule_id_or_category(name):
    before = check(COMP_AND_LENGTH)
    assert "core.comp-on-arc" in rules(before) and "core.no-length-offset" in rules(before)
    after = check(COMP_AND_LENGTH, f'[rules]\ndisable = ["{name}"]\n')
    assert "core.comp-on-arc" not in rules(after)
    assert "core.no-length-offset" in rules(after)


def test_rules_disable_a_category_takes_every_rule_of_it():
    result = check(COMP_AND_LENGTH, '[rules]\ndisable = ["tool-missing", "cutter-comp"]\n')
    assert not [d for d in result.diagnostics if d.category in ("tool-missing", "cutter-comp")]


@pytest.mark.parametrize("name", ["core.comp-on-arc", "cutter-comp"])
def test_rules_severity_by_rule_id_or_category(name):
    result = check(COMP_AND_LENGTH, f'[rules]\nseverity = {{ "{name}" = "info" }}\n')
    [arc] = at(result, "core.comp-on-arc")
    assert arc.severity is Severity.INFO
    [length] = at(result, "core.no-length-offset")
    assert length.severity is Severity.WARNING  # untouched


def test_a_rule_id_severity_wins_over_its_category():
    result = check(COMP_AND_LENGTH, '[rules]\nseverity = { "cutter-comp" = "info", "core.comp-on-arc" = "warning" }\n')
    assert at(result, "core.comp-on-arc")[0].severity is Severity.WARNING


def test_project_disable_and_command_line_disable_add_up(tmp_path, capsys):
    write(tmp_path, "ncverify.toml", '[rules]\ndisable = ["cutter-comp"]\n')
    part = write(tmp_path, "p.nc", program(COMP_AND_LENGTH))
    cli_main(["check", str(part), "--format", "json", "--disable", "core.no-length-offset"])
    entries = json.loads(capsys.readouterr().out)["files"][0]["diagnostics"]
    assert not {d["rule"] for d in entries} & {"core.comp-on-arc", "core.no-length-offset"}


# --------------------------------------------------------------------------- annotations

BOX = "(ncverify: stock box X0:100 Y0:80 Z-20:0)"


def test_annotation_stock_box():
    result = check(f"""
        {BOX}
        G21 G90 G54
        G00 X10. Y10. Z50.
        G00 Z-5.
        M30
    """)
    [crash] = at(result, "core.rapid-into-stock", 4, Status.VIOLATED)
    assert "box X0..100 Y0..80 Z-20..0" in crash.message


def test_annotation_stock_cylinder_on_a_lathe():
    result = check("""
        (ncverify: stock cylinder D50 Z-100:0)
        G21 G90
        G00 X80. Z5.
        G00 X20. Z-10.
        M30
    """, machine="lathe")
    [crash] = at(result, "core.rapid-into-stock", 4, Status.VIOLATED)
    assert "bar D50" in crash.message


def test_annotation_stock_polygon():
    result = check("""
        (ncverify: stock polygon X0 Y0, X100 Y0, X100 Y50, X0 Y50 Z-20:0)
        G21 G90 G54
        G00 X-10. Y10. Z-5.
        G00 X50. Z-6.
        G00 X150. Y10.
        G00 Z50.
        M30
    """)
    assert at(result, "core.rapid-into-stock", 4, Status.VIOLATED)
    assert not at(result, "core.rapid-into-stock", 6, Status.VIOLATED)  # outside the outline


def test_a_level_rapid_through_a_polygon_stock_is_found():
    result = check("""
        (ncverify: stock polygon X0 Y0, X100 Y0, X100 Y50, X0 Y50 Z-20:0)
        G21 G90 G54
        G00 X-10. Y10. Z-5.
        G00 X50.
        M30
    """)
    assert at(result, "core.rapid-into-stock", 4, Status.VIOLATED)


def test_a_dogleg_rapid_along_one_axis_into_a_polygon_stock_is_found():
    """The box a one-axis dog-leg spans has no width in Y: it is a line, not nothing."""
    result = check("""
        (ncverify: stock polygon X0 Y0, X100 Y0, X100 Y50, X0 Y50 Z-20:0)
        G21 G90 G54
        G00 X-10. Y10. Z-5.
        G00 X50. Z10.
        M30
    """, rapid_path="dogleg")
    assert at(result, "core.rapid-into-stock", 4, Status.VIOLATED)


def test_annotation_tool_with_every_key():
    result = check("""
        (ncverify: tool 2 radius 4 length 80 corner 0.5 cutting-length 20 usable-length 30 angle 90 pitch 1.5 nose-radius 0.4 edge 2 type endmill)
        G21 G90 G54
        T2 M06
        T3 M06
        M30
    """)
    assert not [d for d in result.diagnostics if d.rule == "core.bad-annotation"]
    assert [d.span.line for d in at(result, "core.tool-not-in-table", status=Status.VIOLATED)] == [4]


def test_annotation_tool_length_is_used_for_the_travel_limit():
    project = """
        [machine]
        travel = { x = [-400, 400], y = [-250, 250], z = [-300, 0] }
        work_offsets = { G54 = [-300, -200, -250] }
    """
    text = """
        (ncverify: tool 1 radius 3 length {length})
        G21 G90 G54
        T1 M06
        G43 Z50. H01
        M30
    """
    assert not at(check(text.format(length=60), project), "core.travel-limit", 4, Status.VIOLATED)
    assert at(check(text.format(length=250), project), "core.travel-limit", 4, Status.VIOLATED)


def test_a_named_tool_annotation_does_not_break_the_tool_table():
    result = check("""
        (ncverify: tool "spot" radius 5 type spot)
        (ncverify: tool 1 radius 3)
        G21 G90 G54
        T3 M06
        M30
    """)
    [missing] = at(result, "core.tool-not-in-table", 4, Status.VIOLATED)
    assert "None" not in missing.message


def test_annotation_assume_forms():
    text = """
        {BOX}
        (ncverify: assume {assumption})
        G21 G90 G54
        G00 X10. Y10. Z50.
        G99 G81 Z#1 R#2 F100.
        G80
        M30
    """
    def depth(assumption):
        result = check(text.format(BOX=BOX, assumption=assumption))
        return [d.status for d in at(result, "core.cycle-depth-sign", 5)]

    assert depth("-20 <= #1 <= -2 and 1 <= #2 <= 5") == [Status.PROVED]
    assert depth("-20 <= #1 < -2 AND 1 < #2 <= 5") == [Status.PROVED]
    assert depth("#1 == -5. and #2 == 2.") == [Status.PROVED]
    assert depth("-20 <= #1 <= 10 and #2 == 2") == [Status.VIOLATED]
    assert depth("-20 <= #1 <= 10 and #1 + 3 <= #2 and #2 <= 20") == [Status.PROVED]


def test_several_assume_annotations_add_up():
    result = check(f"""
        {BOX}
        (ncverify: assume -20 <= #1 <= -2)
        (ncverify: assume 1 <= #2 <= 5)
        G21 G90 G54
        G00 X10. Y10. Z50.
        G99 G81 Z#1 R#2 F100.
        G80
        M30
    """)
    assert [d.status for d in at(result, "core.cycle-depth-sign", 6)] == [Status.PROVED]


def test_annotations_are_case_insensitive():
    result = check("""
        (NCVERIFY: STOCK BOX x0:100 y0:80 z-20:0)
        (NcVerify: Tool 1 Radius 3 Length 60 Type DRILL)
        (NCVERIFY: ASSUME -20 <= #1 <= -2 AND 1 <= #2 <= 5)
        G21 G90 G54
        T1 M06 G43 H01
        G00 X10. Y10. Z50.
        G99 G81 Z#1 R#2 F100.
        G80
        G00 Z-5. (NCVERIFY: IGNORE CORE.RAPID-INTO-STOCK)
        M30
    """)
    assert not at(result, "core.bad-annotation")
    assert not at(result, "core.tool-not-in-table")
    assert [d.status for d in at(result, "core.cycle-depth-sign", 7)] == [Status.PROVED]
    assert [(s.rule, s.line) for s in result.suppressed] == [("core.rapid-into-stock", 9)]


def test_semicolon_comments_carry_annotations_too():
    result = check("""
        ; ncverify: stock box X0:100 Y0:80 Z-20:0
        G21 G90 G54 ; ncverify: assume -20 <= #1 <= -2
        G00 X10. Y10. Z50.
        G99 G81 Z#1 R2. F100.
        G80
        G00 Z-5.
        G00 Z50. ; ncverify: ignore rapid-into-stock
        M30
    """, stock_resolution=0.0)  # the blank: the retract is a finding to suppress
    assert not at(result, "core.bad-annotation")
    assert at(result, "core.rapid-into-stock", 6, Status.VIOLATED)
    assert [d.status for d in at(result, "core.cycle-depth-sign", 4)] == [Status.PROVED]
    assert [(s.rule, s.line) for s in result.suppressed] == [("core.rapid-into-stock", 7)]


@pytest.mark.parametrize("annotation", [
    "stock box X0:100 Y0:80",
    "stock cube 10",
    "stock polygon X0 Y0, X10 Y0 Z-5:0",
    "stock polygon X0 Y0, X10, X10 Y10 Z-5:0",
    "stock box X0:100 Y0:80 Z0:0",
    "stok box X0:100 Y0:80 Z-20:0",
    "tool 1",
    "tool 1 radius -3",
    "tool 1 radius 3 flutes 4",
    "tool 1 radius 3 type laser",
    "tool 1 radius 3 usable-length 21E400",  # inf: the holder check once failed on it (fuzzing)
    "tool 1 radius 3 length nan",
    "tool 1 radius " + "9" * 400,
    "assume #1 <",
    "assume #1 > [2]",
    "assume foo(#1) > 2",
    "assume -160 <= #1 <= -1" + "5" * 400,  # overflowed the constraint evaluator (fuzzing)
    "assume #1 < 1e400",
    "ignore",
    "ignore Bad Name!",
    "",
])
def test_a_malformed_annotation_is_a_bad_annotation_finding(annotation):
    result = check(f"""
        G21 G90 G54
        (ncverify: {annotation})
        G00 X10. Y10. Z50.
        M30
    """)
    [bad] = at(result, "core.bad-annotation")
    assert bad.status is Status.VIOLATED and bad.span.line == 2
    assert "cannot read this ncverify annotation" in bad.message


def test_an_annotation_stock_wins_over_the_project_file():
    project = """
        [stock]
        box = { x = [0, 100], y = [0, 80], z = [-20, -10] }
    """
    text = """
        {annotation}
        G21 G90 G54
        G00 X10. Y10. Z50.
        G00 Z-5.
        G00 Z50.
        M30
    """
    assert not at(check(text.format(annotation=""), project), "core.rapid-into-stock", 4, Status.VIOLATED)
    assert at(check(text.format(annotation=BOX), project), "core.rapid-into-stock", 4, Status.VIOLATED)


def test_an_annotation_tool_wins_over_the_project_file():
    project = """
        [tools.1]
        radius = 3
        length = 60
        [machine]
        travel = { x = [-400, 400], y = [-250, 250], z = [-300, 0] }
        work_offsets = { G54 = [-300, -200, -250] }
    """
    text = """
        {annotation}
        G21 G90 G54
        T1 M06
        G43 Z50. H01
        M30
    """
    assert not at(check(text.format(annotation=""), project), "core.travel-limit", 4, Status.VIOLATED)
    result = check(text.format(annotation="(ncverify: tool 1 radius 3 length 250)"), project)
    assert at(result, "core.travel-limit", 4, Status.VIOLATED)


def test_project_tools_the_annotations_do_not_name_stay_in_the_table():
    project = "[tools.1]\nradius = 3\n[tools.2]\nradius = 4\n"
    result = check("""
        (ncverify: tool 3 radius 2)
        G21 G90 G54
        T1 M06
        T2 M06
        T3 M06
        T4 M06
        M30
    """, project)
    assert [d.span.line for d in at(result, "core.tool-not-in-table")] == [6]


IGNORES = f"""
    {BOX}
    G21 G90 G54
    G00 X10. Y10. Z50.
    (ncverify: ignore core.rapid-into-stock)
    G00 Z-5.
    G00 Z50. (ncverify: ignore rapid-into-stock)
    G00 Z-5.
    (ncverify: ignore feed, core.spindle-off-cutting, rapid-into-stock)

    (a plain comment between)
    G01 X20. Y20. Z-2.
    G00 Z-8.
    G00 Z50.
    M30
"""


def test_ignore_on_its_own_line_applies_to_the_next_block_and_at_the_end_of_a_block_to_that_block():
    result = check(IGNORES, stock_resolution=0.0)  # the blank: the retracts are findings too
    crashes = {d.span.line for d in at(result, "core.rapid-into-stock", status=Status.VIOLATED)}
    assert crashes == {7, 12, 13}  # 5 and 6 are suppressed; the ignore before 11 does not reach 12
    suppressed = {(s.rule, s.line) for s in result.suppressed}
    assert suppressed == {("core.rapid-into-stock", 5), ("core.rapid-into-stock", 6),
                          ("core.feed-missing", 11), ("core.spindle-off-cutting", 11)}
    assert at(result, "core.feed-missing") == [] and at(result, "core.spindle-off-cutting") == []


def test_suppressed_findings_are_in_the_json_and_not_in_the_diagnostics(tmp_path, capsys):
    part = write(tmp_path, "p.nc", program(IGNORES))
    cli_main(["check", str(part), "--format", "json"])
    entry = json.loads(capsys.readouterr().out)["files"][0]
    assert {"rule": "core.rapid-into-stock", "line": 5, "by": "annotation"} in entry["suppressed"]
    assert {"rule": "core.feed-missing", "line": 11, "by": "annotation"} in entry["suppressed"]
    reported = {(d["rule"], d["line"]) for d in entry["diagnostics"]}
    assert not reported & {(s["rule"], s["line"]) for s in entry["suppressed"]}


def test_an_ignore_does_not_reach_past_its_block():
    result = check(f"""
        {BOX}
        G21 G90 G54
        G00 X10. Y10. Z50.
        G00 Z-5. (ncverify: ignore rapid-into-stock)
        G00 Z50.
        M30
    """, stock_resolution=0.0)  # the blank: the retract is a finding the ignore must not reach
    assert [d.span.line for d in at(result, "core.rapid-into-stock", status=Status.VIOLATED)] == [5]


# --------------------------------------------------------------------------- unknown for want of context

DRILLING = """
    G21 G17 G40 G49 G80 G90
    T1 M06
    G00 G54 X10. Y10. S1000 M03
    G43 Z50. H01
    G00 Z5.
    G99 G81 Z-5. R2. F100.
    X20.
    X30.
    G80
    G00 Z50.
    X60. Y40.
    G00 Z5.
    G00 Z50.
    M30
"""


def test_without_a_stock_the_stock_rules_answer_unknown_once_per_file():
    result = check(DRILLING)
    [rapid] = at(result, "core.rapid-into-stock")
    assert rapid.status is Status.UNKNOWN and rapid.reason == "no stock defined"
    assert "no stock defined" in rapid.message
    [clearance] = at(result, "core.clearance-below-stock")
    assert clearance.status is Status.UNKNOWN and clearance.reason == "no stock defined"


def test_without_travel_limits_the_travel_check_answers_unknown_naming_the_travel():
    [travel] = at(check(DRILLING), "core.travel-limit")
    assert travel.status is Status.UNKNOWN and "travel" in travel.reason and "[machine]" in travel.reason


def test_without_work_offset_values_the_travel_check_answers_unknown_naming_the_offset():
    project = "[machine]\ntravel = { x = [-400, 400], y = [-250, 250], z = [-300, 0] }\n"
    [travel] = at(check(DRILLING, project), "core.travel-limit")
    assert travel.status is Status.UNKNOWN and "work offset G54" in travel.reason
    [g55] = at(check(DRILLING.replace("G54", "G55"), project + "work_offsets = { G54 = [0, 0, 0] }\n"), "core.travel-limit")
    assert g55.status is Status.UNKNOWN and "work offset G55" in g55.reason


def test_without_the_tool_length_the_travel_check_answers_unknown_naming_the_register():
    project = """
        [machine]
        travel = { x = [-400, 400], y = [-250, 250], z = [-300, 0] }
        work_offsets = { G54 = [-300, -200, -250] }
        [tools.1]
        radius = 3
    """
    [travel] = at(check(DRILLING, project), "core.travel-limit")
    assert travel.status is Status.UNKNOWN and "length of the tool on H1" in travel.reason
    assert travel.span.line == 4
    complete = check(DRILLING, project + "length = 60\n")
    assert not [d for d in at(complete, "core.travel-limit") if d.status is not Status.PROVED]


def test_each_missing_context_is_answered_once_and_fails_only_with_fail_on_unknown(tmp_path, capsys):
    part = write(tmp_path, "p.nc", program(DRILLING))
    assert cli_main(["check", str(part), "--format", "json"]) == 0
    entry = json.loads(capsys.readouterr().out)["files"][0]
    unknown = [(d["rule"], d["reason"]) for d in entry["diagnostics"] if d["status"] == "unknown"]
    assert len(unknown) == len(set(unknown)) == len({rule for rule, _ in unknown})
    assert {rule for rule, _ in unknown} >= {"core.rapid-into-stock", "core.clearance-below-stock", "core.travel-limit",
                                             "core.tool-not-in-table", "core.spindle-over-limit", "core.feed-over-limit"}
    assert cli_main(["check", str(part), "--fail-on-unknown"]) == 1


def test_the_text_report_folds_missing_context_into_one_line(tmp_path, capsys):
    part = write(tmp_path, "p.nc", program(DRILLING))
    cli_main(["check", str(part)])
    out = capsys.readouterr().out
    lines = [line for line in out.splitlines() if "not checked for want of context" in line]
    assert len(lines) == 1
    assert "core.rapid-into-stock (no stock defined)" in lines[0]
    assert "core.travel-limit" in lines[0]


_LATHE_PROGRAM = """
    G21 G18 G99
    G54 T0101
    G50 S2000
    G96 S180 M03
    G00 X82. Z2.
    G01 Z-40. F0.2
    G00 X120. Z5.
    M30
"""
_LATHE_MACHINE = """
    [machine]
    type = "lathe"
    travel = { x = [-10, 100], z = [-500, 0] }
    work_offsets = { G54 = [0, 0, -200] }
"""


def test_lathe_travel_needs_to_know_whether_x_is_a_diameter_and_still_checks_z():
    result = check(_LATHE_PROGRAM, _LATHE_MACHINE.replace("z = [-500, 0]", "z = [-220, 0]"), machine="lathe")
    travel = at(result, "core.travel-limit")
    assert [d.status for d in travel if "lathe_x" in (d.reason or "")] == [Status.UNKNOWN]
    assert [(d.span.line, d.status) for d in travel if "Z" in d.message] == [(6, Status.VIOLATED)]  # Z-40 - 200 = -240


def test_lathe_travel_in_radius_halves_the_programmed_diameter():
    radius = check(_LATHE_PROGRAM, _LATHE_MACHINE + 'lathe_x = "radius"\n', machine="lathe")
    assert not [d for d in at(radius, "core.travel-limit") if d.status is Status.VIOLATED]  # X120 is 60 of radius
    diameter = check(_LATHE_PROGRAM, _LATHE_MACHINE + 'lathe_x = "diameter"\n', machine="lathe")
    [beyond] = [d for d in at(diameter, "core.travel-limit") if d.status is Status.VIOLATED]
    assert beyond.span.line == 7 and "X would reach machine position 120" in beyond.message


def test_a_bad_lathe_x_is_a_project_file_error():
    with pytest.raises(ConfigError, match="lathe_x"):
        load_project_text('[machine]\nlathe_x = "radial"\n', Path("/nowhere/ncverify.toml"))
