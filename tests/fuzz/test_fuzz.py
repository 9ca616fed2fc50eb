"""The short, fixed-seed fuzzing budget of the test suite (the long campaign is
``benchmarks/fuzz.py``): mutated corpus and third-party programs, and programs made of
each dialect's statements by hypothesis, through the whole command line in every report
format and dialect. What must hold for each input is in ``harness.py``."""
from __future__ import annotations

import os

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from harness import (DIALECTS, EXTREME_NUMBERS, FORMATS, HOSTILE, REALWORLD, SCHEMAS, TOKENS, Runner, campaign, resident_mib,
                     seed_programs)

MUTATED_INPUTS = 90  # about 15 s on the build machine


@pytest.fixture(scope="module")
def runner(tmp_path_factory):
    if not (SCHEMAS / "sarif-schema-2.1.0.json").is_file():
        if os.environ.get("CI"):
            pytest.fail(f"the SARIF schema is missing: {SCHEMAS}")
        pytest.skip(f"no SARIF schema at {SCHEMAS}")
    return Runner(tmp_path_factory.mktemp("fuzz"), repeat_every=3)


def describe(failures) -> str:
    return "\n\n".join(f"{f.kind} with {' '.join(f.options)}: {f.detail[:1500]}\ninput: {f.data[:300]!r}" for f in failures[:3])


def test_mutated_programs_never_crash_hang_or_break_a_report(runner):
    if not REALWORLD.is_dir() and os.environ.get("CI"):
        pytest.fail(f"the third-party corpus is missing: {REALWORLD}")
    seeds = seed_programs()
    before = len(runner.tally.failures)
    tally = campaign(runner, seed=20261126, count=MUTATED_INPUTS, seeds=seeds)
    assert set(tally.by_format) == set(FORMATS)
    assert tally.failures[before:] == [], describe(tally.failures[before:])


def _program(dialect: str):
    statement = st.sampled_from(TOKENS[dialect])
    noise = st.sampled_from(HOSTILE + EXTREME_NUMBERS)
    line = st.one_of(statement, statement, st.tuples(statement, noise).map(" ".join), st.tuples(noise, statement).map("".join))
    ending = st.sampled_from(["\n", "\r\n", "\r"])
    return st.tuples(st.lists(line, min_size=1, max_size=25), ending).map(lambda parts: parts[1].join(parts[0]) + parts[1])


@pytest.mark.parametrize("dialect", sorted(TOKENS))
def test_programs_made_of_a_dialects_statements_never_crash(runner, dialect):
    @settings(max_examples=12, deadline=None, derandomize=True, database=None, suppress_health_check=list(HealthCheck))
    @given(text=_program(dialect), report_format=st.sampled_from(FORMATS), forced=st.sampled_from(DIALECTS))
    def check(text, report_format, forced):
        failure = runner.check(text.encode("utf-8", "surrogatepass"), {"iso": ".nc", "heidenhain": ".h", "sinumerik": ".mpf", "fagor": ".pim", "linuxcnc": ".ngc"}[dialect],
                               report_format, forced)
        assert failure is None, describe([failure])

    check()


def test_the_memory_check_sees_what_the_process_holds_now_not_its_peak():
    before = resident_mib()
    block = bytearray(256 << 20)
    block[::4096] = b"x" * len(block[::4096])  # touch every page so it is resident
    held = resident_mib()
    del block
    after = resident_mib()
    assert held - before > 200
    assert held - after > 200
