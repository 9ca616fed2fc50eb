"""The rule registry: every rule id has exactly one implementation, and says where it is."""
from __future__ import annotations

import importlib
import inspect

import pytest

from ncverify import check
from ncverify.check import Rule, rule_definitions
from ncverify.rule_registry import REPORTED_BEFORE_THE_CHECKER, DuplicateRegistration, implementations, reporting_modules, rule, rule_classes

TABLE = implementations()


@pytest.mark.parametrize("rule_id", sorted(TABLE))
def test_each_entry_names_one_kind_of_logic(rule_id):
    """A class, or the modules that report it, never both; constraints only beside a class
    or alone."""
    entry = TABLE[rule_id]
    assert (entry.rule_class is not None) + entry.reported_before_the_checker + (entry.constraints and entry.rule_class is None) == 1, entry


@pytest.mark.parametrize("rule_id", sorted(rule_id for rule_id, entry in TABLE.items() if entry.rule_class))
def test_the_named_class_exists_and_handles_events(rule_id):
    entry = TABLE[rule_id]
    module, name = entry.rule_class.split(":")
    cls = getattr(importlib.import_module(module), name)
    handlers = ("segment", "motion_run", "hole", "cycle_run", "change", "finish")
    assert any(getattr(cls, handler) is not getattr(Rule, handler) for handler in handlers), f"{cls} is a placeholder"


@pytest.mark.parametrize("rule_id", sorted(REPORTED_BEFORE_THE_CHECKER))
def test_a_rule_reported_before_the_checker_is_reported_by_some_module(rule_id):
    modules = reporting_modules(rule_id)
    assert modules, f"no module before the checker reports {rule_id}"
    for module in modules:
        assert f'"{rule_id}"' in inspect.getsource(importlib.import_module(module))


def test_the_rules_own_modules_are_not_taken_for_reporters():
    assert "ncverify.checks.tools" not in reporting_modules("core.tool-number-range")
    assert reporting_modules("core.tool-number-range") == ()


@pytest.mark.parametrize("rule_id", sorted(TABLE))
def test_the_page_constraints_are_the_ones_the_registry_names(rule_id):
    assert TABLE[rule_id].constraints == bool(rule_definitions()[rule_id].constraints)


def test_a_rule_id_registered_by_two_classes_is_refused(monkeypatch):
    classes = list(rule_classes())
    monkeypatch.setattr(check, "_RULE_CLASSES", classes)
    rule("core.feed-missing")(type("SecondFeedMissing", (Rule,), {"segment": lambda self, segment, state: None}))
    with pytest.raises(DuplicateRegistration, match="core.feed-missing"):
        implementations()


def test_a_class_for_a_rule_the_interpreter_reports_is_refused(monkeypatch):
    classes = list(rule_classes())
    monkeypatch.setattr(check, "_RULE_CLASSES", classes)
    rule("core.syntax")(type("SyntaxAgain", (Rule,), {"segment": lambda self, segment, state: None}))
    with pytest.raises(DuplicateRegistration, match="core.syntax"):
        implementations()


def test_rules_where_names_the_implementation(capsys):
    from ncverify.cli import main

    assert main(["rules", "--where"]) == 0
    lines = {line.split()[0]: line for line in capsys.readouterr().out.splitlines()}
    assert lines["heidenhain.plunge-angle"].endswith("[ncverify.checks.heidenhain:PlungeAngle]")
    assert "ncverify.lower.iso" in lines["core.syntax"].rstrip("]").split("[reported by ")[1].split(", ")
    assert lines["core.single-peck"].endswith("[constraints in rules/core/single-peck.md]")
    assert set(lines) == set(rule_definitions())
