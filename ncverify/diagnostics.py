"""The finding a rule reports, in the shape of the JSON contract (``version: 1``)."""
from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

from .source import Span


class Severity(str, Enum):
    INFO = "info"
    WARNING = "warning"
    ERROR = "error"

    @property
    def rank(self) -> int:
        return _RANK[self]


_RANK = {Severity.INFO: 0, Severity.WARNING: 1, Severity.ERROR: 2}


class Status(str, Enum):
    VIOLATED = "violated"
    PROVED = "proved"
    UNKNOWN = "unknown"


CATEGORIES = frozenset(
    {
        "syntax",
        "depth-sign",
        "zero-depth",
        "retract-plane",
        "rapid-into-stock",
        "tool-too-large",
        "tool-missing",
        "spindle",
        "feed",
        "cutter-comp",
        "travel-limit",
        "cycle-parameter",
        "modal-state",
        "control-flow",
        "arithmetic",
        "unsupported",
    }
)


@dataclass(slots=True)
class Diagnostic:
    """A finding: a rule's verdict at a place, with its message."""

    rule: str
    category: str
    severity: Severity
    span: Span
    message: str
    status: Status = Status.VIOLATED
    reason: str | None = None
    witness: dict[str, float] = field(default_factory=dict)
    related: Span | None = None  # the call in the checked file that led to a finding in another file

    def sort_key(self):
        return (self.span.path or "", self.span.line, self.span.column, self.rule)

    def to_json(self) -> dict:
        entry = {"rule": self.rule, "category": self.category, "severity": self.severity.value}
        if self.span.path:
            entry["path"] = self.span.path
        entry.update(
            line=self.span.line,
            column=self.span.column,
            end_line=self.span.end_line,
            end_column=self.span.end_column,
            message=self.message,
            status=self.status.value,
        )
        if self.reason:
            entry["reason"] = self.reason
        if self.witness:
            entry["witness"] = dict(self.witness)
        if self.related is not None:
            entry["related"] = [{"path": self.related.path, "line": self.related.line, "column": self.related.column,
                                 "message": "called from here"} if self.related.path else
                                {"line": self.related.line, "column": self.related.column, "message": "called from here"}]
        return entry


@dataclass(slots=True)
class Suppressed:
    """A finding an ``ignore`` annotation left out of the report."""

    rule: str
    line: int
    by: str

    def to_json(self) -> dict:
        return {"rule": self.rule, "line": self.line, "by": self.by}
