"""ncverify on real, third-party Klartext programs (``shared/corpus-realworld/heidenhain``).

The files are not part of this repository; the module is skipped where the corpus is not
present. Every file must be read without a ``core.syntax`` finding; the findings each file
must give are reviewed in ``realworld_expectations.toml``.
"""
from __future__ import annotations

import time
from pathlib import Path

import pytest

from ncverify import Settings, check_file

HEIDENHAIN = Path(__file__).resolve().parents[2] / "shared" / "corpus-realworld" / "heidenhain"

if not HEIDENHAIN.is_dir():
    pytest.skip(f"third-party corpus not present at {HEIDENHAIN}", allow_module_level=True)

TIME_LIMIT_SECONDS = 10.0

FILES = sorted(path for path in HEIDENHAIN.iterdir() if path.is_file())


def _run(path: Path):
    started = time.perf_counter()
    result = check_file(path, Settings())
    return result, time.perf_counter() - started


@pytest.mark.parametrize("path", FILES, ids=[path.name for path in FILES])
def test_file_is_klartext_read_quickly_without_a_syntax_finding(path):
    result, elapsed = _run(path)
    assert result.dialect == "heidenhain"
    assert elapsed < TIME_LIMIT_SECONDS, f"took {elapsed:.1f} s"
    syntax = [(d.span.line, d.span.column, d.message) for d in result.diagnostics if d.rule == "core.syntax" and d.span.path is None]
    assert not syntax
