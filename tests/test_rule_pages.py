"""Every rule page is a contract: its Example triggers the rule, its fix does not."""
from __future__ import annotations

import pytest

from pathlib import Path

from ncverify import Settings, check_text
from ncverify.project import load_project_text
from ncverify.diagnostics import Status
from ncverify.check import rule_definitions
from ncverify.rule_registry import implementations

DEFINITIONS = sorted(rule_definitions().values(), key=lambda definition: definition.id)


def _run(definition, title):
    program = definition.example(title)
    assert program.strip(), f"{definition.id}: the page has no program under '{title}'"
    dialect = None if definition.dialect == "auto" else definition.dialect
    settings = Settings(dialect=dialect, **definition.example_settings)
    project = load_project_text(definition.example_project, Path("ncverify.toml")) if definition.example_project else None
    return check_text(program, f"{definition.id}.nc", settings, project)


@pytest.mark.parametrize("definition", DEFINITIONS, ids=lambda d: d.id)
def test_example_triggers_the_rule(definition):
    result = _run(definition, "Example")
    reported = {d.rule for d in result.diagnostics if d.status is not Status.PROVED}
    assert definition.id in reported, [(d.rule, d.span.line, d.status.value, d.message) for d in result.diagnostics]


@pytest.mark.parametrize("definition", DEFINITIONS, ids=lambda d: d.id)
def test_fixed_example_does_not_trigger_the_rule(definition):
    """The fix removes the violation; an ``unknown`` for missing context may remain."""
    result = _run(definition, "Use instead")
    violated = {d.rule for d in result.diagnostics if d.status is Status.VIOLATED}
    assert definition.id not in violated, [(d.rule, d.span.line, d.message) for d in result.diagnostics]


@pytest.mark.parametrize("definition", DEFINITIONS, ids=lambda d: d.id)
def test_page_has_every_section(definition):
    for title in ("What it checks", "Why it matters", "Example", "Use instead"):
        assert definition.section(title), f"{definition.id}: missing section '{title}'"


@pytest.mark.parametrize("definition", [d for d in DEFINITIONS if d.constraints], ids=lambda d: d.id)
def test_every_constraint_condition_parses(definition):
    """Conditions are parsed when a check first evaluates them; every one must parse."""
    for constraint in definition.constraints:
        assert constraint.tree.body is not None


def test_every_page_has_an_implementation_and_every_implementation_a_page():
    assert set(implementations()) == set(rule_definitions())
