"""ncverify's rapid-into-stock verdicts against the independent oracle (``tests/oracle.py``).

Hypothesis generates parametric programs in every dialect (datum shifts where the dialect
has a plain one, rapids whose coordinates depend on a free parameter with an assumed
range, tools of several radii). For every ``proved`` rapid the oracle runs the program at
the ends, the middle and random points of the range and must find no contact; for every
``violated`` rapid it runs the program at the witness and must find contact there.

The normal suite runs a fixed, small budget with a fixed seed; a release run raises it:

    ORACLE_EXAMPLES=2000 python -m pytest tests/test_oracle.py -q
"""
from __future__ import annotations

import os
import random
import tempfile
from pathlib import Path

from hypothesis import HealthCheck, given, settings as hypothesis_settings, strategies as st

from ncverify import Settings, check_file
from ncverify.diagnostics import Status
from tests.oracle import Case, Linear, Rapid, Shift, touching_steps

EXAMPLES = int(os.environ.get("ORACLE_EXAMPLES", "24"))
STOCK = ((0.0, 100.0), (0.0, 80.0), (-20.0, 0.0))
PARAMETER = {"iso": "#1", "sinumerik": "R1", "fagor": "P1", "heidenhain": "Q1"}
SAFE_START = Rapid(Linear(-50.0), Linear(-50.0), Linear(50.0))

integers = st.integers


def linear(low: int, high: int, factors) -> st.SearchStrategy:
    return st.builds(Linear, integers(low, high).map(float), st.sampled_from(factors))


rapids = st.builds(Rapid, linear(-60, 160, [0.0, 0.0, 1.0, -1.0, 0.5]), linear(-60, 140, [0.0, 0.0, 1.0, -2.0]), linear(-30, 30, [0.0, 0.0, 1.0, -1.0]))
shifts = st.builds(Shift, integers(-60, 60).map(float), integers(-60, 60).map(float))


@st.composite
def cases(draw, dialect: str):
    low = float(draw(integers(-20, 20)))
    steps = [SAFE_START]
    step_kinds = rapids if dialect == "fagor" else st.one_of(rapids, rapids, shifts)  # Fagor: no plain datum shift to write
    steps += draw(st.lists(step_kinds, min_size=1, max_size=5))
    return Case(STOCK, float(draw(st.sampled_from([2, 5, 8]))), 60.0, low, low + draw(integers(1, 30)), tuple(steps))


# --------------------------------------------------------------------------- the programs, per dialect

def _number(value: float) -> str:
    return f"{value:.3f}"


def _iso(case: Case) -> tuple[list[str], dict[int, int]]:
    def word(value: Linear) -> str:
        if value.factor == 0.0:
            return _number(value.constant)
        return f"[{_number(value.constant)} {'+' if value.factor > 0 else '-'} {_number(abs(value.factor))} * #1]"

    lines = ["%", "O1000", *_annotations(case, "(", ")"), "G21 G90 G54 G17", "T1 M06"]
    places = {}
    for index, step in enumerate(case.steps):
        if isinstance(step, Shift):
            lines.append(f"G52 X{_number(step.x)} Y{_number(step.y)}")
        else:
            lines.append(f"G00 X{word(step.x)} Y{word(step.y)} Z{word(step.z)}")
            places[len(lines)] = index
    return lines + ["M30", "%"], places


def _sinumerik(case: Case) -> tuple[list[str], dict[int, int]]:
    def word(value: Linear) -> str:
        return f"{value.constant:g}" if value.factor == 0.0 else f"({value.constant:g}+({value.factor:g})*R1)"

    lines = [*_annotations(case, "; ", ""), "G17 G90 G54", "T1 D1 M6"]
    places = {}
    for index, step in enumerate(case.steps):
        if isinstance(step, Shift):
            lines.append(f"TRANS X={step.x:g} Y={step.y:g}")
        else:
            lines.append(f"G0 X={word(step.x)} Y={word(step.y)} Z={word(step.z)}")
            places[len(lines)] = index
    return lines + ["M30"], places


def _fagor(case: Case) -> tuple[list[str], dict[int, int]]:
    lines = [*_annotations(case, "; ", ""), "G17 G90 G54", "T1 D1 M6"]
    places = {}
    for index, step in enumerate(case.steps):
        for number, value in zip((10, 11, 12), (step.x, step.y, step.z)):
            lines.append(f"P{number} = {value.constant:g} + {value.factor:g} * P1")
        lines.append("G0 X P10 Y P11 Z P12")
        places[len(lines)] = index
    return lines + ["M30"], places


def _heidenhain(case: Case) -> tuple[list[str], dict[int, int]]:
    body = ["BEGIN PGM ORACLE MM", *_annotations(case, "; ", ""), "TOOL CALL 1 Z S3000"]
    places = {}
    for index, step in enumerate(case.steps):
        if isinstance(step, Shift):
            body += ["CYCL DEF 7.0 DATUM SHIFT", f"CYCL DEF 7.1 X{step.x:+g}", f"CYCL DEF 7.2 Y{step.y:+g}"]
            continue
        for number, value in zip((10, 11, 12), (step.x, step.y, step.z)):
            body.append(f"Q{number} = {value.constant:g} + {value.factor:g} * Q1")
        body.append("L X+Q10 Y+Q11 Z+Q12 R0 FMAX")
        places[len(body)] = index
    body.append("END PGM ORACLE MM")
    return [f"{number} {line}" for number, line in enumerate(body)], places


def _annotations(case: Case, open_: str, close: str) -> list[str]:
    """Stock, tool and the assumed range in comments; ``{parameter}`` is filled in per dialect."""
    (x_low, x_high), (y_low, y_high), (z_low, z_high) = case.stock
    return [f"{open_}ncverify: stock box X{x_low:g}:{x_high:g} Y{y_low:g}:{y_high:g} Z{z_low:g}:{z_high:g}{close}",
            f"{open_}ncverify: tool 1 radius {case.radius:g} length {case.length:g}{close}",
            f"{open_}ncverify: assume {case.low:g} <= {{parameter}} <= {case.high:g}{close}"]


WRITERS = {"iso": (_iso, "part.nc"), "sinumerik": (_sinumerik, "part.mpf"), "fagor": (_fagor, "part.pim"), "heidenhain": (_heidenhain, "part.h")}


def _verdicts(dialect: str, case: Case):
    """The program text (the assumption names the dialect's parameter), and per rapid step index the rapid-into-stock findings on its line."""
    write, name = WRITERS[dialect]
    lines, places = write(case)
    text = "\n".join(lines).replace("{parameter}", PARAMETER[dialect]) + "\n"
    with tempfile.TemporaryDirectory() as folder:
        program = Path(folder) / name
        program.write_text(text)
        result = check_file(program, Settings(dialect=dialect))
    found = {}
    for diagnostic in result.diagnostics:
        if diagnostic.rule == "core.rapid-into-stock" and diagnostic.span.line in places:
            found.setdefault(places[diagnostic.span.line], []).append(diagnostic)
    return text, found


def _samples(case: Case, seed: int) -> list[float]:
    chance = random.Random(seed)
    return [case.low, case.high, (case.low + case.high) / 2, *(chance.uniform(case.low, case.high) for _ in range(5))]


@hypothesis_settings(max_examples=EXAMPLES, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(dialect=st.sampled_from(sorted(WRITERS)), data=st.data())
def test_every_proof_and_every_witness_agrees_with_the_oracle(dialect, data):
    case = data.draw(cases(dialect))
    text, found = _verdicts(dialect, case)
    for step, diagnostics in found.items():
        for diagnostic in diagnostics:
            if diagnostic.status is Status.PROVED:
                for value in _samples(case, step):
                    assert step not in touching_steps(case, value), f"proved, but the tool touches the stock at {PARAMETER[dialect]}={value}:\n{text}"
            elif diagnostic.status is Status.VIOLATED and diagnostic.witness:
                value = diagnostic.witness.get(PARAMETER[dialect])
                assert value is not None and case.low - 1e-6 <= value <= case.high + 1e-6, (diagnostic.witness, text)
                assert step in touching_steps(case, value, touch=-1e-3), f"violated at {value}, but the oracle finds no contact:\n{text}"
