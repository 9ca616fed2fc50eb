"""The typed context the rules read, and the one lookup of the tool in the spindle."""
from __future__ import annotations

from types import SimpleNamespace

from ncverify import values
from ncverify.check import Checker
from ncverify.context import NO_TOOL_TABLE, Machine, RegisterLimits, RuleContext, Tool, ToolTable
from ncverify.settings import Settings

from conftest import check_program, findings

TABLE = ToolTable({3: Tool(3, radius=5.0, edges={2: Tool(3, radius=4.0)}), 7: Tool(7, pitch=1.5)})


def test_a_computed_tool_number_finds_its_tool():
    assert TABLE.numbered(3.0).radius == 5.0
    assert TABLE.numbered(4.0) is None


def test_an_unknown_or_symbolic_tool_number_finds_nothing():
    assert TABLE.numbered(None) is None
    assert TABLE.numbered(values.fresh("T")) is None


def test_the_tool_in_the_spindle_is_read_from_the_path_state():
    assert TABLE.in_spindle(SimpleNamespace(tool_in_spindle=7.0)).pitch == 1.5
    assert TABLE.in_spindle(SimpleNamespace(tool_in_spindle=None)) is None


def test_an_edge_other_than_d1_has_its_own_data():
    tool = TABLE[3]
    assert tool.edge_data(1.0) is tool
    assert tool.edge_data(2.0).radius == 4.0
    assert tool.edge_data(5.0) is None


def test_an_empty_table_is_falsy_and_a_mapping():
    assert not ToolTable() and len(TABLE) == 2 and sorted(TABLE) == [3, 7]


def test_the_context_says_whether_the_machine_is_a_lathe():
    assert RuleContext(machine=Machine(kind="lathe")).lathe
    assert not RuleContext().lathe
    assert RuleContext().limits == RegisterLimits()


def test_the_checker_holds_the_context_it_is_given():
    context = RuleContext(tools=TABLE, limits=RegisterLimits(tool_number_max=99.0))
    assert Checker(Settings(), context).context is context


def test_the_tool_radius_lookup_says_once_what_is_missing():
    program = """
        G21 G90 G54
        T1 M06
        G00 X0. Y0. Z5.
        S1000 M03
        G01 Z-1. F100.
        G12 I8. D1 F200.
        G12 I8. D1 F200.
        M30
        """
    unknown = findings(check_program(program), "core.tool-too-large")
    assert [d.reason for d in unknown] == [NO_TOOL_TABLE]
    without_radius = findings(check_program("(ncverify: tool 1 radius 3)\n" + program.replace("T1 M06", "T2 M06").replace("D1", "D2")), "core.tool-too-large")
    assert [d.reason for d in without_radius] == ["tool T2 is not in the tool table"]
    no_radius = findings(check_program(program, project_text="[tools.1]\nlength = 50"), "core.tool-too-large")
    assert [d.reason for d in no_radius] == ["tool T1 has no radius in the tool table"]


def test_the_register_limits_of_the_control_reach_the_rules():
    result = check_program("""
        G21 G90 G54
        T10000 M06
        M30
        """)
    assert [d.message for d in findings(result, "core.tool-number-range")] == ["tool number T10000 is outside 0-9999 on this control"]
