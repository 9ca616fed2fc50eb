"""Compiled expressions (:mod:`ncverify.interpret.compiled`) give what the general evaluation
gives: the same value (number, vacant, symbolic, condition) or the same stop, with the same
faults at the same spans, for any expression tree and any variable contents."""
from __future__ import annotations

import math

from hypothesis import example, given, settings, strategies as st

from ncverify import Settings, ir, values
from ncverify.context import Context
from ncverify.detect import Detection
from ncverify.dialect import setup_for
from ncverify.interpret import Interpreter
from ncverify.interpret.compiled import _straight, compile_assignment, compile_expression
from ncverify.interpret.control_flow import PathEnd
from ncverify.source import ProgramSource, Span
from ncverify.values import VACANT, Condition, Sym

SPAN = Span(7, 1, 7, 30)
LOCALS, GLOBALS = ("#1", "#2", "#3"), ("#100", "#101", "#102")


class Recorder:
    """Every fault, note and verdict the evaluation reports, in order."""

    def __init__(self):
        self.reported = []

    def fault(self, fault):
        self.reported.append(("fault", fault.rule, fault.span, fault.message, fault.status))

    def note(self, note):
        self.reported.append(("note", note))

    def report_verdict(self, rule, span, message, verdict, state):
        self.reported.append(("verdict", rule, span, message))


def interpreter(contents: dict, dialect: str = "iso") -> tuple[Interpreter, Recorder]:
    setup = setup_for(dialect, Settings(), Detection(dialect, 1.0), Context())
    recorder = Recorder()
    machine = Interpreter(ProgramSource.from_text("G0 X0\nM30\n", "t.nc"), setup.frontend, recorder, Settings(solver_timeout_s=1.0),
                          power_on=setup.power_on, cycle_models=setup.cycle_models, twins={}, runtime=setup.runtime)
    machine.state.modal = dict(setup.power_on)
    machine._block = ir.Block(7, 1, 30, [])
    for name, value in contents.items():
        machine.write_variable(ir.Var(name), value)
    return machine, recorder


def shown(value):
    """A value as comparable data: a float by its bits (nan equal to nan), a symbolic value by
    its term, bounds and exactness."""
    if type(value) is float:
        return ("float", value.hex())
    if isinstance(value, Sym):
        return ("sym", str(value.term), value.low, value.high, value.exact)
    if isinstance(value, Condition):
        return ("condition", str(value.term))
    return (type(value).__name__, value if value is not VACANT else "vacant")


def outcome(evaluate, expr, recorder: Recorder):
    """What one evaluation gives: its value or its stop, and what it reported."""
    start = len(recorder.reported)
    with values.fresh_numbering():
        try:
            result = shown(evaluate(expr, SPAN))
        except PathEnd:
            result = "path ends"
    return result, recorder.reported[start:]


NUMBERS = st.one_of(
    st.sampled_from([0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 3.0, 90.0, 180.0, 700.0, 1e308, -1e308, 5e-324, math.inf, -math.inf, math.nan]),
    st.floats(min_value=-1e6, max_value=1e6, allow_nan=False),
    st.integers(-3, 3).map(float),
)
VARIABLES = st.sampled_from(LOCALS + GLOBALS + ("#0", "#500")).map(lambda name: ir.Var(name, Span(7, 3, 7, 6)))
LEAVES = st.one_of(NUMBERS, VARIABLES, st.integers(-2, 2), st.just("TEXT"))
OPERATORS = ["+", "-", "*", "/", "MOD", "**", "AND", "OR", "XOR", "EQ", "NE", "GT", "GE", "LT", "LE"]
FUNCTIONS = sorted(values.known_functions())


def _branches(children):
    binary = st.builds(ir.Binary, st.sampled_from(OPERATORS), children, children)
    sign = st.builds(ir.Unary, st.sampled_from(["-", "+"]), children)
    one = st.builds(lambda name, arg: ir.Func(name, (arg,)), st.sampled_from([name for name in FUNCTIONS if name not in ("ATAN2", "MIN", "MAX")]), children)
    two = st.builds(lambda name, a, b: ir.Func(name, (a, b)), st.sampled_from(["ATAN2", "MIN", "MAX"]), children, children)
    indirect = st.builds(lambda index: ir.Var(ir.Binary("+", index, 100.0), Span(7, 3, 7, 9)), children)
    return st.one_of(binary, sign, one, two, indirect)


EXPRESSIONS = st.recursive(LEAVES, _branches, max_leaves=12)
CONTENTS = st.one_of(NUMBERS.filter(math.isfinite), st.just(VACANT), st.just(values.parameter("P1", -5.0, 5.0)),
                     st.just(values.parameter("P2")), st.just("TEXT"))
MEMORY = st.dictionaries(st.sampled_from(LOCALS + GLOBALS), CONTENTS, max_size=6)


@settings(max_examples=400, deadline=None)
@given(expr=EXPRESSIONS, contents=MEMORY)
@example(expr=ir.Binary("GE", 1.0, ir.Var("#100")), contents={"#100": 1.0})  # equal operands: GE is not GT
@example(expr=ir.Binary("LE", ir.Var("#1"), ir.Var("#2")), contents={"#1": -0.0, "#2": 0.0})
def test_a_compiled_expression_gives_the_value_or_the_stop_the_general_evaluation_gives(expr, contents):
    machine, recorder = interpreter(contents)
    general = outcome(machine.evaluate_tree, expr, recorder)
    run = compile_expression(machine, expr)
    assert outcome(lambda e, span: run(span), expr, recorder) == general


@settings(max_examples=100, deadline=None)
@given(expr=EXPRESSIONS, contents=MEMORY)
def test_an_expression_evaluated_again_and_again_keeps_its_value_and_faults(expr, contents):
    """``evaluate`` walks the tree the first time and runs the compiled closure after."""
    machine, recorder = interpreter(contents)
    general = outcome(machine.evaluate_tree, expr, recorder)
    assert [outcome(machine.evaluate, expr, recorder) for _ in range(3)] == [general] * 3


@settings(max_examples=100, deadline=None)
@given(expr=EXPRESSIONS, contents=st.dictionaries(st.sampled_from(["#1", "#31", "#<i>", "#<_g>"]), CONTENTS, max_size=4))
def test_named_parameters_of_linuxcnc_read_the_same_compiled(expr, contents):
    """LinuxCNC: named parameters, local and global, and a named one never set (an error there)."""
    machine, recorder = interpreter(contents, "linuxcnc")
    for candidate in (expr, ir.Binary("+", ir.Var("#<i>"), expr), ir.Binary("LT", ir.Var("#<_g>"), ir.Var("#<unset>"))):
        general = outcome(machine.evaluate_tree, candidate, recorder)
        run = compile_expression(machine, candidate)
        assert outcome(lambda e, span: run(span), candidate, recorder) == general


STRAIGHT_OPERATORS = ["+", "-", "*", "/", "MOD", "**", "EQ", "NE", "GT", "GE", "LT", "LE"]
ONE_ARGUMENT = [name for name in FUNCTIONS if values.number_function(name) is not None]
STRAIGHT = st.recursive(st.one_of(NUMBERS, VARIABLES), lambda children: st.one_of(
    st.builds(ir.Binary, st.sampled_from(STRAIGHT_OPERATORS), children, children),
    st.builds(ir.Unary, st.just("-"), children),
    st.builds(lambda name, arg: ir.Func(name, (arg,)), st.sampled_from(ONE_ARGUMENT), children)), max_leaves=10)
LOOP_BODY = [ir.Binary("EQ", ir.Binary("LT", ir.Var("#1"), 12500.0), 0.0), ir.Binary("*", ir.Binary("MOD", ir.Var("#1"), 200.0), 0.5),
             ir.Binary("*", ir.Func("FIX", (ir.Binary("/", ir.Var("#1"), 200.0),)), 0.5), ir.Binary("+", ir.Var("#100"), 1.0),
             ir.Binary("-", ir.Unary("-", 1.0), ir.Binary("*", 0.2, ir.Func("SIN", (ir.Binary("*", ir.Var("#101"), 3.6),))))]


@settings(max_examples=400, deadline=None)
@given(expr=STRAIGHT, contents=st.dictionaries(st.sampled_from(LOCALS + GLOBALS), st.one_of(NUMBERS, CONTENTS), max_size=6))
@example(expr=ir.Binary("NE", ir.Binary("GT", ir.Var("#1"), 0.0), ir.Binary("LE", 1.0, ir.Var("#100"))), contents={"#1": 2.0, "#100": 0.5})
@example(expr=ir.Binary("+", ir.Var("#1"), 1.0), contents={"#1": math.inf})
@example(expr=ir.Binary("MOD", ir.Var("#1"), 1.0), contents={"#1": math.inf})  # fmod(inf, 1): a domain error, not a traceback
def test_straight_line_code_gives_what_the_general_evaluation_gives(expr, contents):
    """Arithmetic, comparisons (also of comparisons' outcomes), signs and one-argument
    functions on numbers, infinite and nan ones included, and on every other content: the
    straight-line code's value, or the general evaluation's when it hands over."""
    machine, recorder = interpreter(contents)
    general = outcome(machine.evaluate_tree, expr, recorder)
    run = _straight(machine, expr, lambda span: machine.evaluate_tree(expr, span))
    if run is not None:
        assert outcome(lambda e, span: run(span), expr, recorder) == general


def test_a_loop_body_of_plain_numbers_runs_as_straight_line_code_without_handing_over():
    machine, recorder = interpreter({"#1": 417.0, "#100": 3.0, "#101": -2.5})
    for expr in LOOP_BODY:
        handed_over = []
        run = _straight(machine, expr, handed_over.append)
        assert run is not None and outcome(lambda e, span: run(span), expr, recorder) == outcome(machine.evaluate_tree, expr, recorder)
        assert handed_over == [] and recorder.reported == []


def test_a_variable_not_holding_a_number_hands_the_whole_evaluation_over():
    machine, recorder = interpreter({"#1": VACANT, "#100": values.parameter("P1", -5.0, 5.0)})
    for expr in LOOP_BODY:
        handed_over = []
        assert _straight(machine, expr, handed_over.append)(SPAN) is None and handed_over == [SPAN]


def tables(machine: Interpreter) -> tuple[dict, dict]:
    state = machine.state
    return ({name: shown(value) for name, value in state.local_variables.items()},
            {name: shown(value) for name, value in state.global_variables.items()})


@settings(max_examples=200, deadline=None)
@given(expr=EXPRESSIONS, contents=MEMORY, target=st.sampled_from(LOCALS + GLOBALS).map(ir.Var))
def test_a_compiled_assignment_stores_what_the_general_one_stores(expr, contents, target):
    """Conditions are stored as 1, 0 or an unknown between them; vacant, text and symbolic
    values as they are; local names in the local table."""
    op = ir.Assign(SPAN, target, expr)
    general, general_log = interpreter(contents)
    fast, fast_log = interpreter(contents)

    def assign_generally(op, span):
        general.write_variable(op.target, general.evaluate_tree(op.value, span), span, assignment=True)

    assert outcome(assign_generally, op, general_log) == outcome(lambda op, span: compile_assignment(fast, op)(), op, fast_log)
    assert tables(fast) == tables(general)


def test_the_fast_path_stops_where_the_general_one_does():
    """Plain numbers that leave the float range or divide by zero take the general step."""
    machine, recorder = interpreter({"#100": 0.0, "#101": 1e308})
    for expr in (ir.Binary("/", 1.0, ir.Var("#100")), ir.Binary("*", ir.Var("#101"), 10.0), ir.Binary("+", ir.Var("#101"), ir.Var("#101")),
                 ir.Func("SQRT", (ir.Unary("-", 4.0),)), ir.Func("ASIN", (2.0,))):
        assert outcome(lambda e, span: compile_expression(machine, e)(span), expr, recorder)[0] == "path ends"
    assert [entry[1] for entry in recorder.reported] == ["core.arithmetic-domain"] * 5
    messages = [entry[3] for entry in recorder.reported]
    assert "division by zero" in messages[0] and "overflows" in messages[1] and "SQRT of a negative number (-4)" in messages[3]


def test_a_function_of_an_infinite_or_nan_number_is_a_domain_fault_on_both_paths():
    """SIN of infinity and FIX of NaN have no value: a finding at the block, not a crash."""
    machine, recorder = interpreter({"#100": math.inf, "#101": math.nan})
    for expr in (ir.Func("SIN", (ir.Var("#100"),)), ir.Func("FIX", (ir.Var("#101"),))):
        assert outcome(machine.evaluate_tree, expr, recorder)[0] == "path ends"
        assert outcome(lambda e, span: compile_expression(machine, e)(span), expr, recorder)[0] == "path ends"
    assert [entry[1] for entry in recorder.reported] == ["core.arithmetic-domain"] * 4
    assert "SIN of inf has no value" in recorder.reported[0][3]


def test_text_in_a_logical_operation_or_ordered_against_vacant_is_not_followed():
    """Either way the outcome is unknown (a condition on a fresh value), never a crash."""
    machine, recorder = interpreter({"#100": "TEXT"})
    against_vacant = machine.evaluate_tree(ir.Binary("GE", ir.Var("#100"), ir.Var("#0")), SPAN)
    combined = machine.evaluate_tree(ir.Binary("AND", ir.Var("#100"), ir.Binary("EQ", ir.Var("#100"), "TEXT")), SPAN)
    assert isinstance(against_vacant, Condition) and isinstance(combined, Condition)
    assert recorder.reported == []

