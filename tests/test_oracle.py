"""ncverify's stock and travel verdicts against the independent oracle (``tests/oracle.py``).

Hypothesis draws parametric programs (``tests/oracle_programs.py``) in every dialect:
transforms, loops, subprogram calls, half circles, a drilling cycle, tool changes, and a
free parameter with an assumed range. For every ``proved`` verdict of the rapid-into-stock
and travel rules, the oracle runs the program at both ends, the middle and random points
of the range and must find the hazard at none of them; for every ``violated`` one it runs
the program at the witness and must find the hazard there.

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
from tests import oracle
from tests.oracle_programs import DIALECTS, PARAMETER, cases, project_file, write

EXAMPLES = int(os.environ.get("ORACLE_EXAMPLES", "30"))
HAZARDS = {"core.rapid-into-stock": oracle.touching, "core.travel-limit": oracle.outside_travel}


def verdicts(dialect: str, case: oracle.Case):
    """The program's text (for messages), its tags per (file, line), and the findings of the
    two rules per (file, line)."""
    written = write(dialect, case)
    texts = {name: "\n".join(lines) + "\n" for name, lines in written.files.items()}
    main = next(iter(texts))
    with tempfile.TemporaryDirectory() as folder:
        for name, text in texts.items():
            (Path(folder) / name).write_text(text)
        (Path(folder) / "ncverify.toml").write_text(project_file(case))
        # the oracle knows the blank only: the verdicts it holds up are those against the blank
        # (the stock as cut so far has its own brute-force tests in test_workpiece.py)
        result = check_file(Path(folder) / main, Settings(dialect=dialect, stock_resolution=0.0))
    found = {}
    for diagnostic in result.diagnostics:
        if diagnostic.rule in HAZARDS:
            place = (Path(diagnostic.span.path).name if diagnostic.span.path else main, diagnostic.span.line)
            found.setdefault(place, []).append(diagnostic)
    shown = "\n".join(f"--- {name}\n{text}" for name, text in texts.items())
    return shown, written.places, found


def samples(case: oracle.Case, seed) -> list[float]:
    """The ends and the middle of the assumed range, and random points in it."""
    chance = random.Random(str(seed))
    return [case.low, case.high, (case.low + case.high) / 2, *(chance.uniform(case.low, case.high) for _ in range(5))]


def disagreements(dialect: str, case: oracle.Case) -> list[str]:
    """Every proof the oracle contradicts and every witness it does not reproduce."""
    text, places, found = verdicts(dialect, case)
    parameter, wrong = PARAMETER[dialect], []
    for (place, diagnostics) in found.items():
        tags = places.get(place, set())
        for diagnostic in diagnostics:
            hazard = HAZARDS[diagnostic.rule]
            if diagnostic.status is Status.PROVED:
                wrong += [f"{diagnostic.rule} proved at {place}, but the hazard happens for {parameter}={value}"
                          for value in samples(case, place) if hazard(case, value) & tags]
            elif diagnostic.status is Status.VIOLATED and tags:
                value = diagnostic.witness.get(parameter)
                values = [value] if value is not None else samples(case, place)
                if value is not None and not case.low - 1e-6 <= value <= case.high + 1e-6:
                    wrong.append(f"{diagnostic.rule} at {place}: witness {diagnostic.witness} outside the assumed range")
                elif not any(hazard(case, value, near=True) & tags for value in values):
                    wrong.append(f"{diagnostic.rule} violated at {place} ({diagnostic.witness}), but the oracle finds no hazard there")
    wrong += _unreported(dialect, case, places, found)
    return [f"{message}\n{text}" for message in wrong]


def _unreported(dialect: str, case: oracle.Case, places: dict, found: dict) -> list[str]:
    """Rapids into the stock on a line where the rule said nothing (silence reads as safe).
    A path whose position became unknown is said once, at its first rapid: the lines after
    it are left out."""
    if any(d.reason == "position unknown" and d.span.line != _first_rapid_line(places) for diagnostics in found.values() for d in diagnostics):
        return []
    reported = {place for place, diagnostics in found.items() if any(d.rule == "core.rapid-into-stock" for d in diagnostics)}
    missed = set()
    for value in samples(case, "unreported"):
        hit = oracle.touching(case, value)
        missed |= {place for place, tags in places.items() if place not in reported and hit & tags}
    return [f"core.rapid-into-stock said nothing at {place}, but the tool crashes into the stock there" for place in sorted(missed)]


def _first_rapid_line(places: dict) -> int:
    return min(line for (_, line), tags in places.items() if (0,) in tags)


@hypothesis_settings(max_examples=EXAMPLES, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(dialect=st.sampled_from(DIALECTS), data=st.data())
def test_every_proof_and_every_witness_agrees_with_the_oracle(dialect, data):
    case = data.draw(cases(dialect))
    assert disagreements(dialect, case) == []
