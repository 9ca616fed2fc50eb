"""ncverify on real, third-party Fanuc-style programs (``shared/corpus-realworld/fanuc``).

The files are not part of this repository (see the corpus README and MANIFEST.tsv for
their sources and licences); the module is skipped where the corpus is not present.

Every file must be checked without a crash, in bounded time, and without a ``core.syntax``
finding in the file itself, unless the file really is broken (``KNOWN_BROKEN``). Findings
in other files the program calls (found in the same folder) belong to those files and are
tested with them.

``REVIEWED_ERRORS`` holds every error-severity finding on these files, each read and judged
a true defect; any other error finding fails until it is read and either added there with
its reason or fixed in ncverify as a false alarm.
"""
from __future__ import annotations

import time
from pathlib import Path

import pytest

from ncverify import Settings, check_file

REALWORLD = Path(__file__).resolve().parents[2] / "shared" / "corpus-realworld"
FANUC = REALWORLD / "fanuc"

if not FANUC.is_dir():
    pytest.skip(f"third-party corpus not present at {REALWORLD}", allow_module_level=True)

TIME_LIMIT_SECONDS = 10.0

# Files that are not valid Fanuc-style ISO as they stand: their syntax findings are true.
KNOWN_BROKEN = {
    "018_donpayne-example_prg-cncsimulator.cnc": "CNCSimulator Pro G12 words 'SA0 AS36 RA1.18' (line 61) that no ISO control reads",
    "023_donpayne-lathe_jaws_o4001.cnc": "stray '5' after the ';' end of block on line 6: '(5/10/2023);5'",
    "024_haas-lathe-jaws-o4002.cnc": "stray '5' after the ';' end of block on line 6",
    "025_donpayne-turners_cube_o3001.cnc": "'M98 P3002 L;' - the repeat count L has no value (line 31)",
    "038_millmaster-pro-rail-hole.nc": "MillMaster Pro dialect: '//' line comments and '/text' after M00, not ISO",
    "039_millmaster-pro-carriage-slot.nc": "MillMaster Pro dialect: '//' line comments, not ISO",
    "048_fanuc0i-main-o2-g65-calls.nc": "'#1=#1-#11:' - ':' typed for ';' at the end of line 15",
}

# Files that fail the syntax test only because ncverify misreads valid text: file -> why (strict xfail).
# Empty at the last triage; the ones found earlier (':(' comment lines, '$Inches'/'#region' simulator
# directives, '; free text' trailing comments) are read correctly now.
SYNTAX_FALSE_ALARMS: dict[str, str] = {}

# Every error finding on these files, read and judged a TRUE defect at the last triage
# (file -> {(rule, line)}; findings in the file itself, syntax findings of KNOWN_BROKEN files
# excluded). A new error finding fails the test until someone reads it: a true defect is
# added here with its reason, a false alarm is fixed in ncverify.
REVIEWED_ERRORS = {
    "004_haas-lathe-snowman-o58215.nc": {("core.label-not-found", 15)},  # G71 P45 Q58: there is no N58 (MANIFEST)
    "012_haas-4x3block-o78244.nc": {("core.cycle-missing-parameter", line) for line in (114, 124, 153, 174)},  # G82/G83 without R
    "018_donpayne-example_prg-cncsimulator.cnc": {("core.duplicate-address", 61)},  # CNCSimulator 'SA0 AS36 RA1.18' words
    "023_donpayne-lathe_jaws_o4001.cnc": {("core.cycle-missing-parameter", 120)},  # G73 without its peck depth Q
    "028_haas-mill-hp3-o1001.nc": {("core.cycle-missing-parameter", 53), ("core.cycle-missing-parameter", 68)},  # G81 without R
    "031_haas-lathe-weld-pin-o2007.nc": {("core.label-not-found", 49)},  # G70 P30 Q40: no N30/N40 (the G71 used P10 Q20)
    "033_fadal-ppg.nc": {("core.arc-geometry", 32)},  # 'G91 X-1.' still under G3 with no I/J/R: an alarm
    "040_fanuc-macro-o130001-inner-measure.nc": {("core.program-not-found", 163), ("core.program-not-found", 168)},  # O910002 absent
    "046_fanuc-college-project-g68-corner-r.nc": {("core.comp-on-arc", 49), ("core.comp-on-arc", 54)},  # G42/G41 started on G02/G03
    "052_fanuc0i-macro-o3003-spiral-holes.nc": {("core.label-not-found", 8)},  # IF..GOTO1, only N2 exists (MANIFEST)
}

FILES = sorted(path for path in FANUC.iterdir() if path.is_file())


def _run(path: Path):
    started = time.perf_counter()
    result = check_file(path, Settings())
    return result, time.perf_counter() - started


def _file_params():
    for path in FILES:
        reason = SYNTAX_FALSE_ALARMS.get(path.name)
        marks = [pytest.mark.xfail(strict=True, reason=f"ncverify false alarm: {reason}")] if reason else []
        yield pytest.param(path, id=path.name, marks=marks)


@pytest.mark.parametrize("path", list(_file_params()))
def test_file_is_checked_quickly_and_reads_unless_broken(path):
    result, elapsed = _run(path)
    assert result.skipped is None, f"not checked: {result.skipped}"
    assert elapsed < TIME_LIMIT_SECONDS, f"took {elapsed:.1f} s"
    syntax = [d for d in result.diagnostics if d.rule == "core.syntax" and d.span.path in (None, str(path))]
    if path.name in KNOWN_BROKEN:
        assert syntax, f"listed as broken ({KNOWN_BROKEN[path.name]}) but no syntax finding: remove it from KNOWN_BROKEN"
    else:
        assert not syntax, [(d.span.line, d.span.column, d.message) for d in syntax]


def test_known_lists_name_existing_files():
    names = {path.name for path in FILES}
    assert set(KNOWN_BROKEN) <= names
    assert set(REVIEWED_ERRORS) <= names
    assert set(SYNTAX_FALSE_ALARMS) <= names
    assert not set(SYNTAX_FALSE_ALARMS) & set(KNOWN_BROKEN)


@pytest.mark.parametrize("path", FILES, ids=[path.name for path in FILES])
def test_every_error_finding_is_a_reviewed_true_defect(path):
    result, _ = _run(path)
    errors = {(d.rule, d.span.line) for d in result.diagnostics
              if d.severity.value == "error" and d.status.value == "violated" and d.span.path is None}
    if path.name in KNOWN_BROKEN:
        errors = {(rule, line) for rule, line in errors if rule != "core.syntax"}
    assert errors == REVIEWED_ERRORS.get(path.name, set())
