"""Where every rule is implemented: one entry per rule id.

A rule's *definition* (id, category, severity, page) is its page in ``rules/``. Its
*implementation* is exactly one of:

- a rule class in ``ncverify/checks/`` registered with :func:`ncverify.check.rule` (its page may add
  parameter constraints the class does not repeat);
- parameter constraints only, written in its page (``[[constraint]]``);
- a finding the reader, lowering or interpreter reports itself (a syntax error, a jump to
  a missing label, a cycle called with no cycle defined): it is listed in
  :data:`REPORTED_BEFORE_THE_CHECKER`, and :func:`reporting_modules` finds the modules
  that report it.

:func:`implementations` joins the three into one table; a rule id registered twice is an
error when the table is built, and a test holds pages and table to each other.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from pathlib import Path

from . import checks  # noqa: F401  (importing the package registers the rule classes)
from .check import rule_classes, rule, rule_definitions  # noqa: F401  (re-exported)


# Findings the stages before the checker report themselves, as notes of the reader or
# lowering and faults of the interpreter; :func:`reporting_modules` finds where.
REPORTED_BEFORE_THE_CHECKER: frozenset[str] = frozenset({
    "core.arithmetic-domain", "core.bad-annotation", "core.bare-g", "core.call-depth", "core.decimal-point",
    "core.dialect-unsupported", "core.duplicate-address", "core.duplicate-label", "core.label-not-found",
    "core.loop-bound", "core.m99-in-main", "core.macro-alarm", "core.path-limit", "core.program-end-missing",
    "core.program-not-found", "core.repeat-count-range", "core.same-group-codes", "core.shape-order",
    "core.syntax", "core.too-many-m-codes", "core.undefined-variable", "core.unknown-code",
    "core.unsupported-code", "fagor.cycle-data-without-cycle", "fagor.pattern-parameters",
    "fagor.pattern-skip-list", "fagor.pattern-without-cycle", "fagor.repeat-without-motion",
    "fagor.turning-cycle", "heidenhain.call-pos-axes", "heidenhain.call-without-cycle",
    "heidenhain.call-without-tool", "heidenhain.cycle-with-compensation", "heidenhain.mirror-tool-axis",
    "heidenhain.pattern-surface", "heidenhain.pattern-tool-axis", "heidenhain.position-after-cycle",
    "heidenhain.program-name-mismatch", "heidenhain.sl-prerequisites", "linuxcnc.oword-structure",
    "linuxcnc.unknown-code", "sinumerik.nested-mcall",
})


@cache
def _sources() -> dict[str, str]:
    package = Path(__file__).parent
    sources = {}
    for path in sorted(package.rglob("*.py")):
        relative = path.relative_to(package)
        if relative.parts[0] == "checks" or relative.name in ("check.py", "rule_registry.py"):
            continue
        module = ".".join(("ncverify",) + relative.with_suffix("").parts).removesuffix(".__init__")
        sources[module] = path.read_text(encoding="utf-8")
    return sources


def reporting_modules(rule_id: str) -> tuple[str, ...]:
    """The modules before the checker whose code names ``rule_id``: where it is reported."""
    return tuple(module for module, text in _sources().items() if f'"{rule_id}"' in text)


@dataclass(frozen=True)
class Implementation:
    """How one rule is implemented: a rule class (``module:Class``), constraints in its
    page, modules that report it, or a class plus constraints in its page."""

    rule_id: str
    rule_class: str | None = None
    constraints: bool = False
    reported_before_the_checker: bool = False

    @property
    def reported_by(self) -> tuple[str, ...]:
        """The modules that report it, for a rule the stages before the checker report."""
        return reporting_modules(self.rule_id) if self.reported_before_the_checker else ()

    @property
    def where(self) -> str:
        """Where to read the rule's logic, as ``ncverify rules --where`` prints it."""
        parts = [self.rule_class] if self.rule_class else []
        if self.reported_before_the_checker:
            parts.append("reported by " + (", ".join(self.reported_by) or "no module (a defect)"))
        if self.constraints:
            parts.append(f"constraints in rules/{self.rule_id.replace('.', '/', 1)}.md")
        return " + ".join(parts)


class DuplicateRegistration(ValueError):
    pass


def implementations() -> dict[str, Implementation]:
    """Every implemented rule id with its one implementation."""
    classes: dict[str, str] = {}
    for cls in rule_classes():
        for rule_id in cls.ids:
            name = f"{cls.__module__}:{cls.__qualname__}"
            if rule_id in classes:
                raise DuplicateRegistration(f"rule {rule_id} is registered by {classes[rule_id]} and by {name}")
            classes[rule_id] = name
    for rule_id in REPORTED_BEFORE_THE_CHECKER & classes.keys():
        raise DuplicateRegistration(f"rule {rule_id} is registered by {classes[rule_id]} and as reported before the checker")
    constrained = {definition.id for definition in rule_definitions().values() if definition.constraints}
    table = {}
    for rule_id in sorted(classes.keys() | constrained | REPORTED_BEFORE_THE_CHECKER):
        reported = rule_id in REPORTED_BEFORE_THE_CHECKER
        table[rule_id] = Implementation(rule_id, classes.get(rule_id), rule_id in constrained, reported)
    return table
