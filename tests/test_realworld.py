"""ncverify on real, third-party Fanuc-style programs (``shared/corpus-realworld/fanuc``).

The files are not part of this repository (see the corpus README and MANIFEST.tsv for
their sources and licences); the module is skipped where the corpus is not present.

Every file must be checked without a crash and without a ``core.syntax``
finding in the file itself, unless the file really is broken (``KNOWN_BROKEN``). Findings
in other files the program calls (found in the same folder) belong to those files and are
tested with them.

The findings each file must give, with the reason each is real or not, are reviewed in
``realworld_expectations.toml`` (``test_realworld_expectations.py``).

How long each file takes is measured by ``benchmarks/realworld.py``, not here: a time limit
fails on a loaded machine for reasons that are not the program's.
"""
from __future__ import annotations

from pathlib import Path

import pytest

from ncverify import Settings, check_file

REALWORLD = Path(__file__).resolve().parents[2] / "shared" / "corpus-realworld"
FANUC = REALWORLD / "fanuc"

if not FANUC.is_dir():
    pytest.skip(f"third-party corpus not present at {REALWORLD}", allow_module_level=True)


# Files that are not valid Fanuc-style ISO as they stand: their syntax findings are true.
KNOWN_BROKEN = {
    "018_donpayne-example_prg-cncsimulator.cnc": "CNCSimulator Pro G12 words 'SA0 AS36 RA1.18' (line 61) that no ISO control reads",
    "023_donpayne-lathe_jaws_o4001.cnc": "stray '5' after the ';' end of block on line 6: '(5/10/2023);5'",
    "024_haas-lathe-jaws-o4002.cnc": "stray '5' after the ';' end of block on line 6",
    "025_donpayne-turners_cube_o3001.cnc": "'M98 P3002 L;' - the repeat count L has no value (line 31)",
    "048_fanuc0i-main-o2-g65-calls.nc": "'#1=#1-#11:' - ':' typed for ';' at the end of line 15",
}

# Files that fail the syntax test only because ncverify misreads valid text: file -> why (strict xfail).
# Empty at the last triage; the ones found earlier (':(' comment lines, '$Inches'/'#region' simulator
# directives, '; free text' trailing comments) are read correctly now.
SYNTAX_FALSE_ALARMS: dict[str, str] = {}

FILES = sorted(path for path in FANUC.iterdir() if path.is_file())


def _file_params():
    for path in FILES:
        reason = SYNTAX_FALSE_ALARMS.get(path.name)
        marks = [pytest.mark.xfail(strict=True, reason=f"ncverify false alarm: {reason}")] if reason else []
        yield pytest.param(path, id=path.name, marks=marks)


@pytest.mark.parametrize("path", list(_file_params()))
def test_file_is_checked_and_reads_unless_broken(path):
    result = check_file(path, Settings())
    assert result.skipped is None, f"not checked: {result.skipped}"
    syntax = [d for d in result.diagnostics if d.rule == "core.syntax" and d.span.path in (None, str(path))]
    if path.name in KNOWN_BROKEN:
        assert syntax, f"listed as broken ({KNOWN_BROKEN[path.name]}) but no syntax finding: remove it from KNOWN_BROKEN"
    else:
        assert not syntax, [(d.span.line, d.span.column, d.message) for d in syntax]


def test_known_lists_name_existing_files():
    names = {path.name for path in FILES}
    assert set(KNOWN_BROKEN) <= names
    assert set(SYNTAX_FALSE_ALARMS) <= names
    assert not set(SYNTAX_FALSE_ALARMS) & set(KNOWN_BROKEN)
