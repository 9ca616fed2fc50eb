"""Reports for CI services: SARIF 2.1.0 as GitHub code scanning reads it, and GitLab's Code
Quality report (a CodeClimate JSON array).

Both need a fingerprint that stays the same while a program is edited elsewhere or its
blocks are renumbered: the hash of the rule id and the finding's line with its sequence
number, block-skip slash and spacing taken out, followed by the occurrence of that pair
in the file (two identical lines with the same finding stay apart).
"""
from __future__ import annotations

import hashlib
import json
import os
import re
from pathlib import Path
from urllib.parse import quote

from . import __version__
from .api import FileResult
from .check import rule_definitions
from .diagnostics import Severity, Status
from .report import _Quoter

_SARIF_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}
_GITLAB_SEVERITY = {Severity.ERROR: "major", Severity.WARNING: "minor", Severity.INFO: "info"}
SARIF_SCHEMA = "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json"
SOURCE_ROOT = "SRCROOT"
# A leading block number (N10, Klartext's bare 10, SINUMERIK's N10 after a skip level /1).
_BLOCK_NUMBER = re.compile(r"^\s*(?:/\d?\s*)?(?:N\s*\d+\s*|\d+\s+(?=[A-Z*;]))?", re.IGNORECASE)


def normalized_line(text: str) -> str:
    """A line as the fingerprint sees it: no block number, no skip slash, no spacing, upper case."""
    return re.sub(r"\s+", "", _BLOCK_NUMBER.sub("", text, count=1)).upper()


class Fingerprints:
    """Stable per-finding fingerprints; reads each file once."""

    def __init__(self):
        self._quoter = _Quoter()
        self._seen: dict[tuple, int] = {}

    def line_hash(self, path: str, rule: str, line: int) -> str:
        """``hash:occurrence`` in the form of code scanning's ``primaryLocationLineHash``."""
        content = normalized_line(self._quoter.line(path, line))
        digest = hashlib.sha256(f"{rule}\0{content}".encode()).hexdigest()[:16]
        key = (path, digest)
        self._seen[key] = self._seen.get(key, 0) + 1
        return f"{digest}:{self._seen[key]}"


def _relative_uri(path: str) -> tuple[str, str | None]:
    """The path as a URI relative to the working directory (with the base id), or an
    absolute file URI when the file lies outside it."""
    absolute = Path(path).resolve()
    try:
        return quote(absolute.relative_to(Path.cwd().resolve()).as_posix()), SOURCE_ROOT
    except ValueError:
        return absolute.as_uri(), None


def _location(path: str, span, text: str | None = None) -> dict:
    uri, base = _relative_uri(path)
    artifact = {"uri": uri, "uriBaseId": base} if base else {"uri": uri}
    location = {"physicalLocation": {"artifactLocation": artifact, "region": {
        "startLine": span.line, "startColumn": span.column, "endLine": span.end_line, "endColumn": max(span.end_column, span.column)}}}
    if text:
        location["message"] = {"text": text}
    return location


def render_sarif(results: list[FileResult], errors: list[str], include_proved: bool = False, category: str = "ncverify") -> str:
    """``proved`` verdicts are left out unless ``include_proved``: code scanning turns
    every result into an alert."""
    definitions = rule_definitions()
    shown = [(result, d) for result in results for d in result.diagnostics if include_proved or d.status is not Status.PROVED]
    used = sorted({d.rule for _, d in shown})
    index = {rule_id: position for position, rule_id in enumerate(used)}
    fingerprints = Fingerprints()
    run = {
        "tool": {"driver": {"name": "ncverify", "version": __version__, "semanticVersion": __version__,
                            "informationUri": "https://github.com/ncverify/ncverify",
                            "rules": [_sarif_rule(definitions[rule_id]) for rule_id in used]}},
        "automationDetails": {"id": category.rstrip("/") + "/"},
        "originalUriBaseIds": {SOURCE_ROOT: {"uri": Path.cwd().resolve().as_uri() + "/"}},
        "columnKind": "unicodeCodePoints",
        "results": [_sarif_result(result, d, index, fingerprints) for result, d in shown],
        "invocations": [{
            "executionSuccessful": not errors,
            "toolExecutionNotifications": [{"level": "error", "message": {"text": error}} for error in errors],
        }],
    }
    return json.dumps({"$schema": SARIF_SCHEMA, "version": "2.1.0", "runs": [run]}, indent=2, ensure_ascii=False)


def _sarif_rule(definition) -> dict:
    return {
        "id": definition.id,
        "name": "".join(part.capitalize() for part in re.split(r"[.\-]", definition.id)),
        "shortDescription": {"text": definition.summary},
        "fullDescription": {"text": definition.section("What it checks") or definition.summary},
        "help": {"text": definition.page, "markdown": definition.page},
        "defaultConfiguration": {"level": _SARIF_LEVEL[definition.severity]},
        "properties": {"category": definition.category, "tags": ["cnc", definition.category, definition.id.split(".")[0]],
                       "precision": "very-high", "problem.severity": _problem_severity(definition.severity)},
    }


def _problem_severity(severity: Severity) -> str:
    return {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "recommendation"}[severity]


def _sarif_result(result: FileResult, d, index: dict, fingerprints: Fingerprints) -> dict:
    path = d.span.path or result.path
    entry = {
        "ruleId": d.rule,
        "ruleIndex": index[d.rule],
        "level": _SARIF_LEVEL[d.severity],
        "message": {"text": d.message},
        "locations": [_location(path, d.span)],
        "partialFingerprints": {"primaryLocationLineHash": fingerprints.line_hash(path, d.rule, d.span.line)},
        "properties": {"category": d.category, "status": d.status.value},
    }
    if d.related is not None:
        entry["relatedLocations"] = [dict(_location(d.related.path or result.path, d.related, "called from here"), id=1)]
    if d.status is Status.PROVED:
        entry["kind"] = "pass"
        entry["level"] = "none"
    elif d.status is Status.UNKNOWN:
        entry["kind"] = "review"
        entry["level"] = "none"  # SARIF: a result that is not a failure has level none
    if d.reason:
        entry["properties"]["reason"] = d.reason
    if d.witness:
        entry["properties"]["witness"] = dict(d.witness)
    return entry


# --------------------------------------------------------------------------- GitLab Code Quality


def render_gitlab(results: list[FileResult]) -> str:
    """Violated findings only: GitLab shows every entry as an issue of the merge request."""
    fingerprints = Fingerprints()
    issues = []
    for result in results:
        for d in result.diagnostics:
            if d.status is not Status.VIOLATED:
                continue
            path = d.span.path or result.path
            line_hash = fingerprints.line_hash(path, d.rule, d.span.line)
            relative = os.path.relpath(Path(path).resolve(), Path.cwd().resolve()).replace(os.sep, "/")
            issues.append({
                "description": f"{d.rule}: {d.message}",
                "check_name": d.rule,
                "fingerprint": hashlib.md5(f"{relative}\0{d.rule}\0{line_hash}".encode()).hexdigest(),
                "severity": _GITLAB_SEVERITY[d.severity],
                "location": {"path": relative, "lines": {"begin": d.span.line}},
                "categories": ["Bug Risk"],
                "type": "issue",
                "engine_name": "ncverify",
            })
    return json.dumps(issues, indent=2, ensure_ascii=False)
