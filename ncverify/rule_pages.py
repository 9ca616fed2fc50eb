"""Rule definitions: the pages in ``rules/`` (id, category, default severity, page,
parameter constraints) read into :class:`RuleDefinition` objects.

Below the stages: the checker runs them, the project file and the command line check rule
ids against them.
"""
from __future__ import annotations

import ast
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from functools import cache, cached_property
from pathlib import Path

from .diagnostics import CATEGORIES, Severity
from .resources import data_dir, parse_table


@dataclass(frozen=True)
class Constraint:
    """A condition on a cycle's parameters as written, from a rule page."""

    cycles: tuple[str, ...]
    when: str
    message: str

    @cached_property
    def tree(self) -> ast.Expression:
        """``when`` parsed, on first use: a check meets few of the constrained cycles, and
        parsing all the pages' conditions took a hundredth of a small check's time."""
        return ast.parse(self.when, mode="eval")


@dataclass(frozen=True)
class RuleDefinition:
    """A rule as its page in ``rules/`` defines it."""

    id: str
    category: str
    severity: Severity
    summary: str
    page: str
    path: Path
    dialect: str = "iso"
    example_settings: dict = field(default_factory=dict)
    example_project: str = ""  # ncverify.toml text the examples run with
    once_per_file: bool = False  # report only the first finding of the file
    constraints: tuple[Constraint, ...] = ()

    def section(self, title: str) -> str:
        """The text of one ``## title`` section of the page."""
        marker = f"## {title}"
        if marker not in self.page:
            return ""
        text = self.page.split(marker, 1)[1]
        return text.split("\n## ", 1)[0].strip()

    def example(self, title: str) -> str:
        """The program in the ```nc fence of a section."""
        text = self.section(title)
        if "```" not in text:
            return ""
        body = text.split("```", 2)[1]
        return body.split("\n", 1)[1] if "\n" in body else ""


class RuleFileError(ValueError):
    pass


def parse_rule_file(path: Path) -> RuleDefinition:
    text = path.read_text(encoding="utf-8")
    if not text.startswith("+++"):
        raise RuleFileError(f"{path}: a rule file starts with a +++ TOML front matter block")
    try:
        _, front, page = text.split("+++", 2)
        meta = parse_table(front)
    except ValueError as error:  # a TOMLDecodeError too
        raise RuleFileError(f"{path}: {error}") from error
    expected = f"{path.parent.name}.{path.stem}"
    if meta.get("id") != expected:
        raise RuleFileError(f"{path}: id {meta.get('id')!r} does not match the file's place ({expected!r})")
    if meta.get("category") not in CATEGORIES:
        raise RuleFileError(f"{path}: category {meta.get('category')!r} is not in the contract's list")
    constraints = tuple(
        Constraint(tuple(item["cycles"]), item["when"], item["message"])
        for item in meta.get("constraint", [])
    )
    return RuleDefinition(
        id=meta["id"], category=meta["category"], severity=Severity(meta["severity"]), summary=meta["summary"],
        page=page.strip(), path=path, dialect=meta.get("dialect", "iso"),
        example_settings=meta.get("example_settings", {}), example_project=meta.get("example_project", ""), once_per_file=meta.get("once_per_file", False), constraints=constraints,
    )


class RuleBook(Mapping):
    """Every rule's definition by id (a page's id is its place: ``category-folder.stem``),
    each page parsed when it is first looked up. A check reads the pages of the rules it
    reports and of the rules with constraints, not all two hundred (parsing every page's
    TOML is a tenth of a small check's time)."""

    def __init__(self, paths: list[Path]):
        self._paths = {f"{path.parent.name}.{path.stem}": path for path in paths}
        self._parsed: dict[str, RuleDefinition] = {}
        self._constrained: list[RuleDefinition] | None = None

    def __getitem__(self, rule_id: str) -> RuleDefinition:
        definition = self._parsed.get(rule_id)
        if definition is None:
            definition = self._parsed[rule_id] = parse_rule_file(self._paths[rule_id])
        return definition

    def __contains__(self, rule_id) -> bool:
        return rule_id in self._paths

    def __iter__(self) -> Iterator[str]:
        return iter(self._paths)

    def __len__(self) -> int:
        return len(self._paths)

    def constrained(self) -> list[RuleDefinition]:
        """The definitions with parameter constraints, in id order (found once: the pages
        are the package's). Only pages that name a constraint at all are parsed."""
        if self._constrained is None:
            # bytes: a third of the time of decoding each page, and UTF-8 holds an ASCII word only as itself
            candidates = (rule_id for rule_id, path in self._paths.items() if b"constraint" in path.read_bytes())
            self._constrained = [definition for definition in map(self.__getitem__, candidates) if definition.constraints]
        return self._constrained


@cache
def rule_definitions() -> RuleBook:
    return RuleBook(sorted(data_dir("rules").glob("*/*.md")))


def explain_text(rule_id: str) -> str | None:
    """The page ``ncverify explain`` prints (Markdown), or ``None`` for an unknown rule."""
    definition = rule_definitions().get(rule_id)
    if definition is None:
        return None
    header = f"{definition.id}  [{definition.category}, {definition.severity.value}]\n{definition.summary}\n"
    return header + "\n" + definition.page
