"""Stage 5, report: findings as text and JSON (the contract, ``version: 1``); SARIF and
GitLab Code Quality are in ``sarif.py``."""
from __future__ import annotations

import json
from pathlib import Path

from .api import FileResult
from .diagnostics import Severity, Status
from .source import normalise


def summary(results: list[FileResult], errors: list[str]) -> dict:
    diagnostics = [d for result in results for d in result.diagnostics]
    return {
        "files": len(results),
        "checked": sum(1 for result in results if result.skipped is None and result.dialect is not None),
        "skipped": sum(1 for result in results if result.skipped is not None),
        "unreadable": len(errors),
        "error": sum(1 for d in diagnostics if d.severity is Severity.ERROR and d.status is Status.VIOLATED),
        "warning": sum(1 for d in diagnostics if d.severity is Severity.WARNING and d.status is Status.VIOLATED),
        "info": sum(1 for d in diagnostics if d.severity is Severity.INFO and d.status is Status.VIOLATED),
        "unknown": sum(1 for d in diagnostics if d.status is Status.UNKNOWN),
        "proved": sum(1 for d in diagnostics if d.status is Status.PROVED),
        "blocks": sum(result.blocks for result in results),
    }


def to_json(results: list[FileResult], errors: list[str]) -> dict:
    document = {"version": 1, "files": [result.to_json() for result in results], "summary": summary(results, errors)}
    if errors:
        document["errors"] = list(errors)
    return document


def render_json(results: list[FileResult], errors: list[str]) -> str:
    return json.dumps(to_json(results, errors), indent=2, ensure_ascii=False)


# --------------------------------------------------------------------------- text


class _Quoter:
    """Quotes source lines for the text report, reading each file once."""

    def __init__(self):
        self._lines: dict[str, list[str]] = {}

    def line(self, path: str, number: int) -> str:
        lines = self._lines.get(path)
        if lines is None:
            try:
                raw = Path(path).read_bytes() if Path(path).is_file() else b""
            except OSError:
                raw = b""
            lines = normalise(raw).decode("utf-8", errors="replace").split("\n") if len(raw) < 50_000_000 else []
            self._lines[path] = lines
        return lines[number - 1] if 0 < number <= len(lines) else ""


def render_text(results: list[FileResult], errors: list[str], texts: dict[str, str] | None = None,
                show_proved: bool = False) -> str:
    """One line per finding, with ``unknown`` where the severity stands; ``proved`` verdicts
    only with ``show_proved``; the context a run lacked said once; then the summary, the
    files that failed and the rules that fired most."""
    quoter = _Quoter()
    out: list[str] = []
    gaps_by_file: dict[str, dict[str, str]] = {}
    for result in results:
        if result.skipped:
            out.append(f"{result.path}: note: skipped: {result.skipped}")
            continue
        gaps = {d.rule: d.reason or d.message for d in result.diagnostics if _is_context_gap(d)}
        if gaps:
            gaps_by_file[result.path] = gaps
        for d in result.diagnostics:
            if _is_context_gap(d) or (d.status is Status.PROVED and not show_proved):
                continue
            out += _finding_lines(result, d, quoter, texts)
        for rule_id, count in sorted(result.truncated.items()):
            out.append(f"{result.path}: note: {count} more {rule_id} findings not shown")
        if result.air_cutting:
            shares = ", ".join(f"{tool} {air / feed:.0%} of {feed:.0f} mm" for tool, (feed, air) in sorted(result.air_cutting.items()) if feed > 0)
            out.append(f"{result.path}: note: feed moves that cut only air, per tool: {shares}")
    out += _context_gap_lines(gaps_by_file, len([r for r in results if not r.skipped]))
    for error in errors:
        out.append(f"error: {error}")
    totals = summary(results, errors)
    out.append(
        f"{totals['checked']} file(s) checked, {totals['skipped']} skipped: {totals['error']} error(s), {totals['warning']} warning(s), "
        f"{totals['info']} note(s), {totals['unknown']} unknown, {totals['proved']} proved"
    )
    out += _failures(results)
    return "\n".join(out)


def _finding_lines(result: FileResult, d, quoter: _Quoter, texts: dict[str, str] | None) -> list[str]:
    path = d.span.path or result.path
    label = d.severity.value if d.status is Status.VIOLATED else d.status.value
    reason = f" [{d.reason}]" if d.status is Status.UNKNOWN and d.reason else ""
    witness = "" if not d.witness else " (for example " + ", ".join(f"{name}={value:g}" for name, value in sorted(d.witness.items())) + ")"
    called = f" (called from {d.related.path or result.path}:{d.related.line})" if d.related is not None else ""
    lines = [f"{path}:{d.span.line}:{d.span.column}: {label} {d.rule}: {d.message}{witness}{reason}{called}"]
    source_line = texts[path].splitlines()[d.span.line - 1] if texts and path in texts and d.span.line <= len(texts[path].splitlines()) else quoter.line(path, d.span.line)
    if source_line.strip():
        lines.append(f"    {d.span.line:>5} | {source_line.rstrip()}")
        if d.span.end_line == d.span.line and d.span.end_column > d.span.column:
            lines.append("          | " + " " * (d.span.column - 1) + "^" * (d.span.end_column - d.span.column))
    return lines


# What each kind of missing context needs in ncverify.toml: (word in the reason, section, line).
_CONTEXT_SNIPPETS = [
    ("stock", "[stock]", "box = { x = [0, 120], y = [0, 80], z = [-25, 0] }"),
    ("tool table", "[tools.1]", "radius = 5.0\nlength = 60"),
    ("travel", "[machine]", "travel = { x = [-400, 400], y = [-250, 250], z = [-300, 0] }\nwork_offsets = { G54 = [-300, -200, -250] }"),
    ("max_feed", "[machine]", "max_feed = 10000"),
    ("max_spindle", "[machine]", "max_spindle = 12000"),
]


def _context_gap_lines(gaps_by_file: dict[str, dict[str, str]], checked: int) -> list[str]:
    """The "not checked for want of context" note, once for the run: each check with the
    number of files it could not judge, then the one ncverify.toml snippet that supplies
    all of it."""
    if not gaps_by_file:
        return []
    counts: dict[tuple[str, str], int] = {}
    for gaps in gaps_by_file.values():
        for rule, reason in gaps.items():
            counts[(rule, reason)] = counts.get((rule, reason), 0) + 1
    listed = "; ".join(f"{rule} ({reason}){'' if count == checked else f' in {count} file(s)'}" for (rule, reason), count in counts.items())
    everywhere = " in every file" if all(count == checked for count in counts.values()) else ""
    lines = [f"note: not checked for want of context{everywhere}: {listed}"]
    reasons = " ".join(reason for _, reason in counts).lower()
    sections: dict[str, list[str]] = {}
    for word, section, body in _CONTEXT_SNIPPETS:
        if word in reasons:
            sections.setdefault(section, []).extend(body.splitlines())
    if sections:
        lines.append("note: an ncverify.toml beside the programs supplies it, for example:")
        lines += ["    " + line for section, body in sections.items() for line in (section, *body)]
    return lines


def _failures(results: list[FileResult], most: int = 5) -> list[str]:
    """The files with errors or warnings, and the rules that fired most, for the end of the report."""
    failed = [(result.path, result.count(Severity.ERROR), result.count(Severity.WARNING)) for result in results]
    failed = [entry for entry in failed if entry[1] or entry[2]]
    if not failed:
        return []
    lines = [f"files with findings ({len(failed)}):"] + [f"    {path}: {errors} error(s), {warnings} warning(s)" for path, errors, warnings in failed]
    fired: dict[str, int] = {}
    for result in results:
        for d in result.diagnostics:
            if d.status is Status.VIOLATED and d.severity is not Severity.INFO:
                fired[d.rule] = fired.get(d.rule, 0) + 1
    ranked = sorted(fired.items(), key=lambda item: (-item[1], item[0]))[:most]
    lines.append("rules that fired most: " + ", ".join(f"{rule} ({count})" for rule, count in ranked))
    return lines


def _is_context_gap(diagnostic) -> bool:
    """An ``unknown`` that only says which context (stock, travel, tools) was missing."""
    return diagnostic.status is Status.UNKNOWN and diagnostic.message.startswith("not checked: ")
