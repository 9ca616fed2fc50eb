"""Reviewed expectations for every HEIDENHAIN, SINUMERIK, Fanuc-style and LinuxCNC program of the
third-party corpus (``../shared/corpus-realworld``), checked as a new user would: no project
file, no options.

``realworld_expectations.toml`` lists each ``violated`` error and warning with whether it is
a real problem on the named control and the reason, and the files that must give none. A
new finding fails until someone reads it and either adds it with its reason or removes the
false alarm in ncverify; a finding that goes away fails until the list is brought up to date,
so a real problem cannot be lost silently. The precision figure of the README is the share of
``real = true`` entries; the last test keeps it from falling.
"""
from __future__ import annotations

import tomllib
from collections import defaultdict
from pathlib import Path

import pytest

from ncverify import Settings, check_file
from ncverify.diagnostics import Severity, Status

REALWORLD = Path(__file__).resolve().parents[2] / "shared" / "corpus-realworld"
FOLDERS = ("heidenhain", "sinumerik", "fanuc", "linuxcnc")
PRECISION_FOLDERS = ("heidenhain/", "sinumerik/", "fanuc/")  # the README's figure; LinuxCNC is reviewed, not counted
EXPECTATIONS = tomllib.loads((Path(__file__).parent / "realworld_expectations.toml").read_text(encoding="utf-8"))
PRECISION_FLOOR = 0.90  # the bar; measured 62 of 64 at the last review (see the README, "Precision on real programs")

if not all((REALWORLD / folder).is_dir() for folder in FOLDERS):
    pytest.skip(f"third-party corpus not present at {REALWORLD}", allow_module_level=True)

FILES = sorted(f"{folder}/{path.name}" for folder in FOLDERS for path in (REALWORLD / folder).iterdir()
               if path.is_file() and path.suffix.lower() not in (".md", ".tsv"))
EXPECTED: dict[str, set] = defaultdict(set)
for entry in EXPECTATIONS["finding"]:
    EXPECTED[entry["file"]].add((entry["rule"], entry["line"]))


def reported(name: str) -> set:
    result = check_file(REALWORLD / name, Settings())
    return {(d.rule, d.span.line) for d in result.diagnostics
            if d.status is Status.VIOLATED and d.severity in (Severity.ERROR, Severity.WARNING)}


def test_every_file_has_a_reviewed_expectation():
    listed = set(EXPECTATIONS["passing"]) | set(EXPECTED)
    assert sorted(set(FILES) - listed) == []
    assert sorted(listed - set(FILES)) == []
    assert not set(EXPECTATIONS["passing"]) & set(EXPECTED)


def test_every_finding_has_a_verdict_and_a_reason():
    for entry in EXPECTATIONS["finding"]:
        assert isinstance(entry["real"], bool) and len(entry["reason"]) > 20, entry


@pytest.mark.parametrize("name", FILES)
def test_file_gives_exactly_its_reviewed_findings(name):
    assert reported(name) == EXPECTED.get(name, set())


def test_precision_does_not_fall():
    findings = [entry for entry in EXPECTATIONS["finding"] if entry["file"].startswith(PRECISION_FOLDERS)]
    real = sum(1 for entry in findings if entry["real"])
    assert real / len(findings) >= PRECISION_FLOOR
