"""ncverify on real, third-party Klartext programs (``shared/corpus-realworld/heidenhain``).

The files are not part of this repository; the module is skipped where the corpus is not
present. Every file must be read without a ``core.syntax`` finding, and every error
finding on it must be one that was read and judged a true defect (``REVIEWED_ERRORS``).
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

# Programs these files call with CALL PGM are not in the corpus (they live on the machine:
# TNC:\REF, TNC:\Z19, the 90H7 macros ...): the call cannot be followed, which is what
# the finding says.
_CALLED_ELSEWHERE = {
    "003_drunsinn-3170_de.h": (22,),
    "007_drunsinn-9030_de.h": (62, 91),
    "013_janforys-CHWYT-125.h": (15, 16, 65, 66, 84, 97, 98),
    "014_janforys-DENKO-OTW-BOKI.H": (2, 3, 105, 106),
    "024_janforys-P-ZBIORCZY.H": (12, 14, 16, 18, 20, 22, 24, 26),
    "025_janforys-SONDA-6H7.H": (39,),
    "028_jstjst-Plan-Beispiel.h": (23,),
}

REVIEWED_ERRORS = {name: {("core.program-not-found", line) for line in lines} for name, lines in _CALLED_ELSEWHERE.items()}
REVIEWED_ERRORS.update({
    # BEGIN PGM YL-05 ... END PGM 100: the program was renamed at one end only.
    "002_digiliner-YL-05.h": {("heidenhain.program-name-mismatch", 463)},
    # CALL LBL 3 six times, but the program has only LBL 1 and LBL 0: the control stops.
    "008_drunsinn-BewegBlv.h": {("core.label-not-found", 120)},
    # Q1951 = INT(Q1950 / Q1810 + 0.99999999) is 0 when Q1804 = Q1805 (a zero depth, which the
    # input checks in blocks 8-27 let through), and block 31 divides by it.
    "027_jstjst-Plan.h": {("core.arithmetic-domain", 39)},
})

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


def test_reviewed_lists_name_existing_files():
    assert set(REVIEWED_ERRORS) <= {path.name for path in FILES}


@pytest.mark.parametrize("path", FILES, ids=[path.name for path in FILES])
def test_every_error_finding_is_a_reviewed_true_defect(path):
    result, _ = _run(path)
    errors = {(d.rule, d.span.line) for d in result.diagnostics
              if d.severity.value == "error" and d.status.value == "violated" and d.span.path is None}
    assert errors == REVIEWED_ERRORS.get(path.name, set())
