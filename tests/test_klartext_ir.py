"""Klartext lowers to IR operations: the constructs that need the machine state are typed
operations the interpreter runs, and the only cycle ids in the IR are cycles of the table."""
from __future__ import annotations

from pathlib import Path

import pytest

from ncverify import Settings, ir
from ncverify.context import Context
from ncverify.dialect import logical_lines, setup_for
from ncverify.interpret import Interpreter
from ncverify.source import ProgramSource

_CORPUS = sorted((Path(__file__).resolve().parent.parent / "corpus" / "heidenhain").glob("*.h"))


def lowered(text: str, path: Path | None = None) -> list[ir.Op]:
    source = ProgramSource(text.encode(), str(path or "t.h"))
    setup = setup_for("heidenhain", Settings(), None, Context())
    ops = []
    for line, _offset, _next, raw in logical_lines(source, 0, setup.frontend):
        for block in setup.frontend.blocks(raw, line):
            ops.extend(block.ops)
    return ops


def test_state_dependent_constructs_are_typed_operations():
    text = "\n".join([
        "0 BEGIN PGM T MM", "1 TOOL CALL 1 Z S2000 F300 DR+0.1", "2 CC X+50 Y+50", "3 L X+60 Y+50 R0 FMAX",
        "4 C X+40 Y+50 DR+", "5 LP PR+10 PA+90", "6 CT X+70 Y+60", "7 L Z+100 FMAX", "8 CALL LBL 1 REP 2",
        "9 APPR LT X+0 Y+0 LEN5 RL", "10 L Z+50 M140 MB MAX", "11 L X+0 M94", "12 CYCL DEF 200 DRILLING ~",
        "  Q200=+2 ;SET-UP CLEARANCE", "13 END PGM T MM", ""])
    kinds = {type(op) for op in lowered(text)}
    assert {ir.ToolLength, ir.ToolFeed, ir.ToolDelta, ir.Pole, ir.PoleArc, ir.PolarMove, ir.TangentArc, ir.Lift, ir.LabelCall,
            ir.Approach, ir.Retract, ir.MFunction, ir.CycleDefine, ir.ProgramEnd} <= kinds
    assert ir.CycleCall not in kinds


def test_statements_only_klartext_has_are_operations_of_their_own_type():
    text = "\n".join(["0 BEGIN PGM T MM", "1 CYCL DEF 12.0 PGM CALL", "2 CYCL DEF 12.1 PGM SUB1.H", "3 CYCL CALL", "4 TRANS DATUM AXIS X+10",
                      '5 SEL PATTERN "HOLES.PNT"', "6 L X+10 R0 FMAX", "7 END PGM T MM", ""])
    statements = [op for op in lowered(text) if isinstance(op, ir.DialectStatement)]
    assert [type(op) for op in statements] == [ir.OldCycle, ir.CallActiveCycle, ir.Transformation, ir.SelectPattern, ir.PositioningBlock]
    old = statements[0]
    assert (old.number, old.sub, old.program, old.params) == (12, 1, "SUB1", {})  # the cycle's own words only


@pytest.mark.parametrize("path", _CORPUS, ids=lambda path: path.name)
def test_every_cycle_id_of_a_corpus_program_is_a_cycle_number(path):
    ops = lowered(path.read_text(encoding="latin-1"), path)
    named = [op.cycle for op in ops if isinstance(op, (ir.CycleDefine, ir.CycleCall))]
    assert [cycle for cycle in named if not ir.cycle_code(cycle).isdigit()] == []


def test_the_interpreter_has_a_handler_for_every_operation_klartext_lowers_to():
    setup = setup_for("heidenhain", Settings(), None, Context())
    source = ProgramSource(b"0 BEGIN PGM T MM\n", "t.h")
    interpreter = Interpreter(source, setup.frontend, object(), Settings(), power_on=setup.power_on, cycle_models=setup.cycle_models,
                              twins={}, runtime=setup.runtime)
    emitted = {type(op) for path in _CORPUS for op in lowered(path.read_text(encoding="latin-1"), path)}
    assert emitted
    assert not {kind.__name__ for kind in emitted if kind not in interpreter._handlers}


def test_a_cycle_run_holds_only_the_programs_parameters(monkeypatch):
    """What the rules need beside the parameters (the contour, its region, the OCM shape...)
    travels as typed facts of the run, never as made-up names among its parameters."""
    from ncverify import check_file
    from ncverify.interpret.runtime import Runtime

    names, facts = set(), []
    report_cycle = Runtime.report_cycle

    def recording(runtime, run):
        names.update(run.params)
        facts.append(run.facts)
        report_cycle(runtime, run)

    monkeypatch.setattr(Runtime, "report_cycle", recording)
    for path in _CORPUS:
        check_file(path)
    assert names and all(name[:1].isalpha() for name in names)
    assert any(fact.contour is not None for fact in facts)  # the corpus has contour cycles


def test_only_cycles_that_act_when_defined_take_toleranced_sizes():
    """A tolerance text the control cannot read reaches the rules with the run of the
    definition, which only the cycles that act when defined (the OCM shapes) report."""
    from ncverify.interpret.heidenhain.runtime import DEF_ACTIVE

    models = setup_for("heidenhain", Settings(), None, Context()).cycle_models
    toleranced = {int(ir.cycle_code(cycle)) for cycle, model in models.items() if any(spec.tolerance for spec in model.params.values())}
    assert toleranced and toleranced <= DEF_ACTIVE
