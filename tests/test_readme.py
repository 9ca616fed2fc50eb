"""The README promises things a test can hold it to."""
from __future__ import annotations

from pathlib import Path

from ncverify import check_file
from ncverify.check import rule_definitions
from ncverify.cli import main

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_the_readme_lists_every_rule():
    missing = [rule_id for rule_id in rule_definitions() if f"`{rule_id}`" not in README]
    assert not missing


def test_the_quick_start_example_is_bundled_and_has_its_five_findings(capsys):
    example = ROOT / "corpus" / "iso" / "quickstart-bracket.nc"
    assert f"ncverify check {example.relative_to(ROOT).as_posix()}" in README
    assert main(["check", str(example)]) == 1
    assert "5 planted" in README.replace("\n", " ").replace("five planted", "5 planted")
    assert len([d for d in check_file(example).diagnostics if d.status.value == "violated"]) == 5


def test_ci_runs_the_readme_test_command():
    command = 'pip install ".[test]" && python -m pytest'
    assert command in README
    assert command in (ROOT / ".ci" / "run").read_text(encoding="utf-8")
