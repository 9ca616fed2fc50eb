"""ncverify on real, third-party SINUMERIK programs (``shared/corpus-realworld/sinumerik``).

The files are not part of this repository; the module is skipped where the corpus is not
present. Every file must be detected as SINUMERIK from its text, checked without a crash, and
read without a ``core.syntax`` finding unless the file really is broken
(``KNOWN_BROKEN``). ``REVIEWED_ERRORS`` holds every violated error finding, each read at the
last triage; a new one fails until it is read and either added with its reason or fixed as
a false alarm. The warnings read at the same triage are listed in ``REVIEWED_WARNINGS``.

How long each file takes is measured by ``benchmarks/realworld.py``, not here: a time limit
fails on a loaded machine for reasons that are not the program's.
"""
from __future__ import annotations

from pathlib import Path

import pytest

from ncverify import Settings, check_file

SINUMERIK = Path(__file__).resolve().parents[2] / "shared" / "corpus-realworld" / "sinumerik"

if not SINUMERIK.is_dir():
    pytest.skip(f"third-party corpus not present at {SINUMERIK}", allow_module_level=True)


KNOWN_BROKEN = {
    "004_deathaxe-SYNTAX_CHECK.SPF": "a syntax-highlighter test file: the lines it marks '; syntax error' (G5[10]=, M5[10]=, "
                                     "'M 5', T10[2]=, T\"10\", S1[1]=, R10[5]=) are not SINUMERIK",
    "005_deretvir-chiron-code.txt": "'TURNVL //L': '//' is not a SINUMERIK comment or operator (Chiron macro text)",
}

FILES = sorted(path for path in SINUMERIK.iterdir() if path.is_file())


@pytest.mark.parametrize("path", FILES, ids=[path.name for path in FILES])
def test_file_is_detected_checked_and_reads_unless_broken(path):
    result = check_file(path, Settings())
    assert result.dialect == "sinumerik", result.dialect
    syntax = [d for d in result.diagnostics if d.rule == "core.syntax" and d.span.path is None]
    if path.name in KNOWN_BROKEN:
        assert syntax, f"listed as broken ({KNOWN_BROKEN[path.name]}) but no syntax finding"
    else:
        assert not syntax, [(d.span.line, d.span.column, d.message) for d in syntax]


def test_known_lists_name_existing_files():
    names = {path.name for path in FILES}
    assert set(KNOWN_BROKEN) <= names
