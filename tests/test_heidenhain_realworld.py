"""ncverify on real, third-party Klartext programs (``shared/corpus-realworld/heidenhain``).

The files are not part of this repository; the module is skipped where the corpus is not
present. Every file must be read without a ``core.syntax`` finding; the findings each file
must give are reviewed in ``realworld_expectations.toml``.

How long each file takes is measured by ``benchmarks/realworld.py``, not here: a time limit
fails on a loaded machine for reasons that are not the program's.
"""
from __future__ import annotations

from pathlib import Path

import pytest

from ncverify import Settings, check_file

HEIDENHAIN = Path(__file__).resolve().parents[2] / "shared" / "corpus-realworld" / "heidenhain"

if not HEIDENHAIN.is_dir():
    pytest.skip(f"third-party corpus not present at {HEIDENHAIN}", allow_module_level=True)


FILES = sorted(path for path in HEIDENHAIN.iterdir() if path.is_file())


@pytest.mark.parametrize("path", FILES, ids=[path.name for path in FILES])
def test_file_is_klartext_read_without_a_syntax_finding(path):
    result = check_file(path, Settings())
    assert result.dialect == "heidenhain"
    syntax = [(d.span.line, d.span.column, d.message) for d in result.diagnostics if d.rule == "core.syntax" and d.span.path is None]
    assert not syntax
