"""The README promises things a test can hold it to."""
from __future__ import annotations

import sys
from pathlib import Path

from ncverify import check_file
from ncverify.check import rule_definitions
from ncverify.cli import main

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
_TABLE_HEAD = "| rule | category | severity | summary |\n|---|---|---|---|\n"
_TABLE_END = "\n## Architecture"


def rules_table() -> str:
    """The README's rule table, from the rule definitions (sorted by category, then id)."""
    definitions = sorted(rule_definitions().values(), key=lambda definition: (definition.category, definition.id))
    return "".join(f"| `{d.id}` | {d.category} | {d.severity.value} | {_cell(d.summary)} |\n" for d in definitions)


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def test_the_readme_lists_every_rule():
    """Regenerate the table with ``python tests/test_readme.py --write``."""
    start = README.index(_TABLE_HEAD) + len(_TABLE_HEAD)
    assert README[start : README.index(_TABLE_END, start)].strip() == rules_table().strip()


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


if __name__ == "__main__" and "--write" in sys.argv:
    start = README.index(_TABLE_HEAD) + len(_TABLE_HEAD)
    (ROOT / "README.md").write_text(README[:start] + rules_table() + README[README.index(_TABLE_END, start):], encoding="utf-8")
