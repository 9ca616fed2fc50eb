"""ncverify findings as LSP diagnostics: severity by status, the rule page as the code's
description, and related information pointing at the block that caused the finding."""
from __future__ import annotations

import re
from bisect import bisect_left
from pathlib import Path

from lsprotocol import types

from ..api import FileResult
from ..check import rule_definitions
from ..diagnostics import Diagnostic, Severity, Status
from ..source import Span

SOURCE = "ncverify"

_VIOLATED_SEVERITY = {
    Severity.ERROR: types.DiagnosticSeverity.Error,
    Severity.WARNING: types.DiagnosticSeverity.Warning,
    Severity.INFO: types.DiagnosticSeverity.Information,
}

# Blocks a finding can be traced back to, per dialect: the cycle definition (for a finding
# at the block that runs the cycle) and the tool call (for a tool finding).
_CYCLE_DEFINITION = {
    "iso": r"\bG\s*0*(?:7[346]|8[1-9]|1[23])(?!\d)",
    "fagor": r"\bG\s*0*(?:8[1-9]|16[0-5]|21[0-2])(?!\d)",
    "heidenhain": r"\bCYCL\s+DEF\b",
    "sinumerik": r"\b(?:MCALL\s+)?(?:CYCLE\d+|POCKET\d|SLOT\d|LONGHOLE|HOLES\d)\s*\(",
}
_TOOL_CALL = {
    "iso": r"\bT\s*\d+",
    "fagor": r"\bT\s*\d+",
    "heidenhain": r"\bTOOL\s+CALL\b",
    "sinumerik": r"\bT\s*(?:=|\d)",
}
_CYCLE_CATEGORIES = {"cycle-parameter", "zero-depth", "retract-plane", "depth-sign"}
_TOOL_CATEGORIES = {"tool-missing", "tool-too-large"}


def rule_page_uri(rule: str) -> str | None:
    definition = rule_definitions().get(rule)
    return definition.path.resolve().as_uri() if definition else None


def to_range(span: Span) -> types.Range:
    return types.Range(
        start=types.Position(line=max(span.line - 1, 0), character=max(span.column - 1, 0)),
        end=types.Position(line=max(span.end_line - 1, 0), character=max(span.end_column - 1, 0)),
    )


def severity(diagnostic: Diagnostic) -> types.DiagnosticSeverity:
    """``unknown`` is information and ``proved`` a hint: neither is ever shown as an error."""
    if diagnostic.status is Status.UNKNOWN:
        return types.DiagnosticSeverity.Information
    if diagnostic.status is Status.PROVED:
        return types.DiagnosticSeverity.Hint
    return _VIOLATED_SEVERITY[diagnostic.severity]


def message(diagnostic: Diagnostic) -> str:
    text = diagnostic.message
    if diagnostic.status is Status.UNKNOWN:
        text = f"unknown: {text}" + (f" ({diagnostic.reason})" if diagnostic.reason else "")
    elif diagnostic.status is Status.PROVED:
        text = f"proved safe: {text}"
    if diagnostic.witness:
        text += " [witness: " + ", ".join(f"{name}={value:g}" for name, value in sorted(diagnostic.witness.items())) + "]"
    return text


class LineIndex:
    """The lines of a buffer, and the lines matching the patterns findings are traced to."""

    def __init__(self, text: str, dialect: str | None):
        self.lines = text.splitlines()
        self.dialect = dialect or "iso"
        self._found: dict[str, list[int]] = {}

    def last_before(self, pattern: str, line: int) -> int | None:
        """The last line at or before 1-based ``line`` matching ``pattern``."""
        matches = self._matches(pattern)
        position = bisect_left(matches, line + 1)
        return matches[position - 1] if position else None

    def first_mentioning(self, name: str) -> int | None:
        word = re.compile(rf"(?i)(?<![A-Z0-9_]){re.escape(name)}(?![A-Z0-9_])")
        for number, text in enumerate(self.lines, 1):
            if word.search(_code_part(text)):
                return number
        return None

    def _matches(self, pattern: str) -> list[int]:
        found = self._found.get(pattern)
        if found is None:
            compiled = re.compile(pattern, re.IGNORECASE)
            found = self._found[pattern] = [number for number, text in enumerate(self.lines, 1) if compiled.search(_code_part(text))]
        return found

    def line_range(self, line: int) -> types.Range:
        text = self.lines[line - 1] if 0 < line <= len(self.lines) else ""
        return types.Range(start=types.Position(line=line - 1, character=0), end=types.Position(line=line - 1, character=len(text)))


def _code_part(text: str) -> str:
    """A line without its comment (``;`` to the end, ``( )`` groups)."""
    return re.sub(r"\([^)]*\)?", "", text.split(";", 1)[0])


def to_diagnostics(result: FileResult, uri: str, index: LineIndex) -> list[types.Diagnostic]:
    return [_diagnostic(item, uri, index) for item in result.diagnostics]


def _diagnostic(item: Diagnostic, uri: str, index: LineIndex) -> types.Diagnostic:
    related: list[types.DiagnosticRelatedInformation] = []
    span = item.span
    if span.path:
        # A finding inside a called program: shown at the call, the callee's block related.
        call = index.first_mentioning(Path(span.path).stem) or index.first_mentioning(Path(span.path).stem.lstrip("Oo0")) or 1
        related.append(types.DiagnosticRelatedInformation(
            location=types.Location(uri=Path(span.path).resolve().as_uri(), range=to_range(span)),
            message=f"the finding, in the called program {Path(span.path).name}"))
        where = index.line_range(call)
    else:
        where = to_range(span)
        related.extend(_causes(item, uri, index))
    page = rule_page_uri(item.rule)
    return types.Diagnostic(
        range=where,
        message=message(item),
        severity=severity(item),
        code=item.rule,
        code_description=types.CodeDescription(href=page) if page else None,
        source=SOURCE,
        related_information=related or None,
        data={"rule": item.rule, "category": item.category, "status": item.status.value, "line": span.line},
    )


def _causes(item: Diagnostic, uri: str, index: LineIndex) -> list[types.DiagnosticRelatedInformation]:
    causes = []
    line = item.span.line
    if item.category in _CYCLE_CATEGORIES or "cycle" in item.rule:
        definition = index.last_before(_CYCLE_DEFINITION[index.dialect], line)
        if definition is not None and definition != line:
            causes.append(types.DiagnosticRelatedInformation(
                location=types.Location(uri=uri, range=index.line_range(definition)), message="the cycle definition in force here"))
    if item.category in _TOOL_CATEGORIES or "tool" in item.rule:
        tool = index.last_before(_TOOL_CALL[index.dialect], line)
        if tool is not None and tool != line:
            causes.append(types.DiagnosticRelatedInformation(
                location=types.Location(uri=uri, range=index.line_range(tool)), message="the tool call in force here"))
    return causes
