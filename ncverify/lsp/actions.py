"""Quick fixes for ncverify's diagnostics: an ``ncverify: ignore`` annotation at the line,
and the fixes whose text the finding itself states (the cancel word a modal cycle lacks,
a feed for a cutting move that has none)."""
from __future__ import annotations

import re

from lsprotocol import types

from .convert import SOURCE

_MISSING_CANCEL = re.compile(r"\(no (G80|MCALL|#MDOFF)\)")
_FEED = re.compile(r"(?i)(?<![A-Z_])F\s*=?\s*(\d+\.?\d*|\.\d+)(?![A-Z_])")


def code_actions(uri: str, lines: list[str], dialect: str | None, diagnostics: list[types.Diagnostic]) -> list[types.CodeAction]:
    found = []
    for diagnostic in diagnostics:
        if diagnostic.source != SOURCE or not diagnostic.code:
            continue
        line = diagnostic.range.start.line
        if not 0 <= line < len(lines):
            continue
        rule = str(diagnostic.code)
        found.append(_action(f"Suppress {rule} on this line (ncverify: ignore)", uri, diagnostic,
                             _suppression(lines[line], line, rule, dialect), preferred=False))
        if match := _MISSING_CANCEL.search(diagnostic.message):
            indent = re.match(r"\s*", lines[line]).group()
            position = types.Position(line=line, character=0)
            edit = types.TextEdit(range=types.Range(start=position, end=position), new_text=f"{indent}{match.group(1)}\n")
            found.append(_action(f"Insert {match.group(1)} before this block", uri, diagnostic, edit, preferred=True))
        if rule == "core.feed-missing" and (feed := _nearest_feed(lines, line)) is not None:
            value, where = feed
            end = len(_code(lines[line]).rstrip())
            position = types.Position(line=line, character=end)
            edit = types.TextEdit(range=types.Range(start=position, end=position), new_text=f" F{value}")
            found.append(_action(f"Add the feed F{value} programmed {where}", uri, diagnostic, edit, preferred=True))
    return found


def _action(title: str, uri: str, diagnostic: types.Diagnostic, edit: types.TextEdit, preferred: bool) -> types.CodeAction:
    return types.CodeAction(title=title, kind=types.CodeActionKind.QuickFix, diagnostics=[diagnostic],
                            edit=types.WorkspaceEdit(changes={uri: [edit]}), is_preferred=preferred)


def _code(text: str) -> str:
    """The part of a line before its trailing comment or Klartext continuation mark."""
    cut = len(text)
    for mark in (";", "(", "~"):
        position = text.find(mark)
        if position >= 0:
            cut = min(cut, position)
    return text[:cut]


def _suppression(text: str, line: int, rule: str, dialect: str | None) -> types.TextEdit:
    """An annotation at the end of the block: ISO and Fagor take it in parentheses, the
    others after a semicolon; a Klartext continuation mark ``~`` stays last."""
    if dialect in ("iso", "fagor", None):
        annotation = f"(ncverify: ignore {rule})"
        column = text.find(";") if ";" in text else len(text.rstrip())
        new_text = annotation if column == 0 else " " + annotation
    else:
        column = len(text.rstrip())
        if text.rstrip().endswith("~"):
            column -= 1
        new_text = f" ; ncverify: ignore {rule}"  # inside an existing comment it is still found by its marker
    position = types.Position(line=line, character=column)
    return types.TextEdit(range=types.Range(start=position, end=position), new_text=new_text)


def _nearest_feed(lines: list[str], line: int) -> tuple[str, str] | None:
    """A non-zero feed to give the move: the last one before it (the finding then means an F0
    in force), else the first one after it (the feed the program gives its cuts too late)."""
    for where, numbers in (("last", range(line - 1, -1, -1)), ("next", range(line + 1, len(lines)))):
        for index in numbers:
            feeds = [value for value in _FEED.findall(_code(lines[index])) if float(value) > 0]
            if feeds:
                return (feeds[-1] if where == "last" else feeds[0]), where
    return None
