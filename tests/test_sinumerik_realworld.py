"""ncverify on real, third-party SINUMERIK programs (``shared/corpus-realworld/sinumerik``).

The files are not part of this repository; the module is skipped where the corpus is not
present. Every file must be detected as SINUMERIK from its text, checked without a crash in
bounded time, and read without a ``core.syntax`` finding unless the file really is broken
(``KNOWN_BROKEN``). ``REVIEWED_ERRORS`` holds every violated error finding, each read at the
last triage; a new one fails until it is read and either added with its reason or fixed as
a false alarm. The warnings read at the same triage are listed in ``REVIEWED_WARNINGS``.
"""
from __future__ import annotations

import time
from pathlib import Path

import pytest

from ncverify import Settings, check_file

SINUMERIK = Path(__file__).resolve().parents[2] / "shared" / "corpus-realworld" / "sinumerik"

if not SINUMERIK.is_dir():
    pytest.skip(f"third-party corpus not present at {SINUMERIK}", allow_module_level=True)

TIME_LIMIT_SECONDS = 10.0

KNOWN_BROKEN = {
    "004_deathaxe-SYNTAX_CHECK.SPF": "a syntax-highlighter test file: the lines it marks '; syntax error' (G5[10]=, M5[10]=, "
                                     "'M 5', T10[2]=, T\"10\", S1[1]=, R10[5]=) are not SINUMERIK",
    "005_deretvir-chiron-code.txt": "'TURNVL //L': '//' is not a SINUMERIK comment or operator (Chiron macro text)",
}

# (rule, line) -> why it is true. Findings on a variable the file never sets (a GUD or a PROC
# parameter) are true in the sense the checker means: nothing in the file rules the bad value
# out; an 'ncverify: assume' annotation states the caller's range and removes them.
REVIEWED_ERRORS = {
    "004_deathaxe-SYNTAX_CHECK.SPF": {("core.arc-geometry", line) for line in range(144, 151)},  # 'X100Y10' under G2/G3 with no CR/I/J
    "009_nadjimre418-AL600.SPF": {("core.feed-missing", 15)},  # G1 F=RABHOD: RABHOD is a GUD the file never sets
    "013_nadjimre-MS100.SPF": {("core.feed-missing", 11)},  # G1 ... F=brz_mer: the PROC parameter is not checked against 0
    "038_pdubovikov-KANAVKA_SFERA.spf": {("core.arithmetic-domain", 8), ("core.arithmetic-domain", 9)},  # R10/R5, /R4: radius and angle parameters divided unchecked
}

REVIEWED_WARNINGS = {
    "001_deathaxe-example.mpf": {("core.macro-alarm", 5)},  # SETAL(66021) when VELO < 0: the program's own alarm
    "002_deathaxe-syntax_test_isocall.spf": {("core.program-end-missing", 69)},  # a test file with no M17/RET
    "003_deathaxe-syntax_test_synact.spf": {("core.program-end-missing", 130)},  # a test file with no M17/RET
    "005_deretvir-chiron-code.txt": {("core.program-end-missing", 7)},  # a fragment, no end
    "008_nadjimre418-AL000.SPF": {("core.macro-alarm", 21)},  # SETAL(65017) on a branch
    "009_nadjimre418-AL600.SPF": {("core.feed-plausibility", 15)},  # F=RABHOD may be below 1 mm/min
    "013_nadjimre-MS100.SPF": {("core.feed-plausibility", 11)},  # F=brz_mer may be below 1 mm/min
    "016_nadjimre-_PROBE_CALIBRATION.SPF": {("core.macro-alarm", 27)},  # SETAL(65110) on a branch
    "019_nadjimre-SASA.MPF": {("core.program-end-missing", 45)},  # HMI-generated main program with no M30/M17
    "020_nadjimre418-SH000.SPF": {("core.macro-alarm", 10)},  # SETAL(65017) on a branch
    "033_pdubovikov-123.mpf": {("core.spindle-off-cutting", 414), ("core.spindle-off-cutting", 457)},  # M5 M00 (tool change by hand), then G1 with no M3
    "034_pdubovikov-case_test.mpf": {("core.program-end-missing", 5)},  # a CASE test with no M30
    "036_pdubovikov-CYCLE82.SPF": {("core.macro-alarm", 35)},  # a CYCLE82 rewrite raising 61101 itself
    "037_pdubovikov-HOLES1.SPF": {("core.macro-alarm", 30)},  # a HOLES1 rewrite raising 61103 itself
    "040_pdubovikov-repeat_test.mpf": {("core.spindle-off-cutting", 5)},  # G1 with no M3 in a REPEAT test
}

FILES = sorted(path for path in SINUMERIK.iterdir() if path.is_file())


def _run(path: Path):
    started = time.perf_counter()
    result = check_file(path, Settings())
    return result, time.perf_counter() - started


def _findings(result, errors: bool) -> set:
    return {(d.rule, d.span.line) for d in result.diagnostics
            if (d.severity.value == "error") == errors and d.status.value == "violated" and d.span.path is None}


@pytest.mark.parametrize("path", FILES, ids=[path.name for path in FILES])
def test_file_is_detected_checked_quickly_and_reads_unless_broken(path):
    result, elapsed = _run(path)
    assert result.dialect == "sinumerik", result.dialect
    assert elapsed < TIME_LIMIT_SECONDS, f"took {elapsed:.1f} s"
    syntax = [d for d in result.diagnostics if d.rule == "core.syntax" and d.span.path is None]
    if path.name in KNOWN_BROKEN:
        assert syntax, f"listed as broken ({KNOWN_BROKEN[path.name]}) but no syntax finding"
    else:
        assert not syntax, [(d.span.line, d.span.column, d.message) for d in syntax]


@pytest.mark.parametrize("path", FILES, ids=[path.name for path in FILES])
def test_every_finding_is_a_reviewed_true_one(path):
    result, _ = _run(path)
    errors = {(rule, line) for rule, line in _findings(result, True) if rule != "core.syntax" or path.name not in KNOWN_BROKEN}
    assert errors == REVIEWED_ERRORS.get(path.name, set())
    assert _findings(result, False) == REVIEWED_WARNINGS.get(path.name, set())


def test_known_lists_name_existing_files():
    names = {path.name for path in FILES}
    assert set(KNOWN_BROKEN) | set(REVIEWED_ERRORS) | set(REVIEWED_WARNINGS) <= names
