"""Where every rule is implemented: one entry per rule id.

A rule's *definition* (id, category, severity, page) is its page in ``rules/``. Its
*implementation* is exactly one of:

- a rule class in ``ncverify/checks/`` registered with :func:`rule` (its page may add
  parameter constraints the class does not repeat);
- parameter constraints only, written in its page (``[[constraint]]``);
- a finding the reader, lowering or interpreter reports itself (a syntax error, a jump to
  a missing label, a cycle called with no cycle defined): :data:`REPORTED_BY` names the
  modules that report it.

:func:`implementations` joins the three into one table; a rule id registered twice is an
error when the table is built, and a test holds pages and table to each other.
"""
from __future__ import annotations

from dataclasses import dataclass

_RULE_CLASSES: list[type] = []


def rule(*ids: str):
    """Register a rule class reporting the given rule ids."""

    def register(cls):
        cls.ids = ids
        _RULE_CLASSES.append(cls)
        return cls

    return register


def rule_classes() -> list[type]:
    """Every registered rule class, in registration order (the order events reach them)."""
    from . import checks  # noqa: F401  (importing the package registers the classes)

    return _RULE_CLASSES


# Findings reported by the stages before the checker, as notes of the reader/lowering or
# faults of the interpreter, with the modules that report them.
REPORTED_BY: dict[str, tuple[str, ...]] = {
    "core.arithmetic-domain": ("ncverify.interpret",),
    "core.bad-annotation": ("ncverify.annotations",),
    "core.bare-g": ("ncverify.lower.iso",),
    "core.call-depth": ("ncverify.control_flow",),
    "core.decimal-point": ("ncverify.lower.iso",),
    "core.dialect-unsupported": ("ncverify.api",),
    "core.duplicate-address": ("ncverify.lower.iso", "ncverify.lower.fagor"),
    "core.duplicate-label": ("ncverify.control_flow",),
    "core.label-not-found": ("ncverify.control_flow",),
    "core.loop-bound": ("ncverify.interpret", "ncverify.control_flow"),
    "core.m99-in-main": ("ncverify.control_flow",),
    "core.macro-alarm": ("ncverify.interpret",),
    "core.path-limit": ("ncverify.control_flow",),
    "core.program-end-missing": ("ncverify.control_flow",),
    "core.program-not-found": ("ncverify.control_flow",),
    "core.repeat-count-range": ("ncverify.cycles", "ncverify.control_flow"),
    "core.same-group-codes": ("ncverify.lower.iso",),
    "core.shape-order": ("ncverify.cycles",),
    "core.syntax": ("ncverify.lower.iso", "ncverify.lower.heidenhain", "ncverify.lower.sinumerik", "ncverify.lower.fagor",
                    "ncverify.control_flow"),
    "core.too-many-m-codes": ("ncverify.lower.iso",),
    "core.undefined-variable": ("ncverify.interpret",),
    "core.unknown-code": ("ncverify.lower.iso",),
    "core.unsupported-code": ("ncverify.interpret", "ncverify.frames", "ncverify.lower.iso", "ncverify.lower.heidenhain",
                              "ncverify.lower.heidenhain_run", "ncverify.lower.heidenhain_frames", "ncverify.lower.heidenhain_special",
                              "ncverify.lower.sinumerik", "ncverify.lower.sinumerik_cycles", "ncverify.lower.fagor",
                              "ncverify.lower.fagor_cycles"),
    "fagor.cycle-data-without-cycle": ("ncverify.lower.fagor",),
    "fagor.pattern-parameters": ("ncverify.lower.fagor_cycles",),
    "fagor.pattern-skip-list": ("ncverify.lower.fagor_cycles",),
    "fagor.pattern-without-cycle": ("ncverify.lower.fagor_cycles",),
    "fagor.repeat-without-motion": ("ncverify.lower.fagor",),
    "fagor.turning-cycle": ("ncverify.lower.fagor_cycles",),
    "heidenhain.call-pos-axes": ("ncverify.lower.heidenhain_run",),
    "heidenhain.call-without-cycle": ("ncverify.lower.heidenhain_run", "ncverify.lower.heidenhain_special"),
    "heidenhain.call-without-tool": ("ncverify.lower.heidenhain_run",),
    "heidenhain.cycle-with-compensation": ("ncverify.lower.heidenhain_run",),
    "heidenhain.mirror-tool-axis": ("ncverify.lower.heidenhain_run",),
    "heidenhain.pattern-surface": ("ncverify.lower.heidenhain_run",),
    "heidenhain.pattern-tool-axis": ("ncverify.lower.heidenhain_run",),
    "heidenhain.position-after-cycle": ("ncverify.lower.heidenhain_run",),
    "heidenhain.program-name-mismatch": ("ncverify.lower.heidenhain",),
    "heidenhain.sl-prerequisites": ("ncverify.lower.heidenhain_run",),
    "sinumerik.nested-mcall": ("ncverify.lower.sinumerik",),
}


@dataclass(frozen=True)
class Implementation:
    """How one rule is implemented: a rule class (``module:Class``), constraints in its
    page, modules that report it, or a class plus constraints in its page."""

    rule_id: str
    rule_class: str | None = None
    constraints: bool = False
    reported_by: tuple[str, ...] = ()

    @property
    def where(self) -> str:
        """Where to read the rule's logic, as ``ncverify rules --where`` prints it."""
        parts = [self.rule_class] if self.rule_class else []
        if self.reported_by:
            parts.append("reported by " + ", ".join(self.reported_by))
        if self.constraints:
            parts.append(f"constraints in rules/{self.rule_id.replace('.', '/', 1)}.md")
        return " + ".join(parts)


class DuplicateRegistration(ValueError):
    pass


def implementations() -> dict[str, Implementation]:
    """Every implemented rule id with its one implementation."""
    from .check import rule_definitions

    classes: dict[str, str] = {}
    for cls in rule_classes():
        for rule_id in cls.ids:
            name = f"{cls.__module__}:{cls.__qualname__}"
            if rule_id in classes:
                raise DuplicateRegistration(f"rule {rule_id} is registered by {classes[rule_id]} and by {name}")
            classes[rule_id] = name
    for rule_id in REPORTED_BY.keys() & classes.keys():
        raise DuplicateRegistration(f"rule {rule_id} is registered by {classes[rule_id]} and as reported by {', '.join(REPORTED_BY[rule_id])}")
    constrained = {definition.id for definition in rule_definitions().values() if definition.constraints}
    table = {}
    for rule_id in sorted(classes.keys() | constrained | REPORTED_BY.keys()):
        table[rule_id] = Implementation(rule_id, classes.get(rule_id), rule_id in constrained, REPORTED_BY.get(rule_id, ()))
    return table
