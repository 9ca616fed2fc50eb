"""Helpers for the verdict tests: put parameter values into a program's TEXT.

A witness is checked the way a machinist would check it: write the values into the program
as literal numbers and run the concrete program. ``#n`` directly after an address letter
(``Z#1``) becomes ``Z-5.``; anywhere else in an expression (``[#3+10.]``) it becomes
``[-5.]``. Comments are left alone, so ``ncverify: assume`` annotations stay as written (they
then constrain a parameter nobody reads, which changes nothing).
"""
from __future__ import annotations

import re

from ncverify.diagnostics import Status

_COMMENT = re.compile(r"\([^)]*\)|;.*$", re.MULTILINE)
_READ = re.compile(r"([A-Za-z]?)#(\d+)(?!\d)")
_ASSUME_LINE = re.compile(r"ncverify\s*:\s*assume\s+([^)]*)", re.IGNORECASE)
_RANGE = re.compile(r"([-+]?[\d.]+)\s*<=\s*(#\d+)\s*<=\s*([-+]?[\d.]+)")


def literal(value: float) -> str:
    """``-5.``, ``0.5``, ``-1.000001``: a literal that reads back as the same float."""
    text = repr(float(value))
    if "e" in text or "E" in text:
        text = format(float(value), ".20f")
    text = text.rstrip("0") if "." in text else text + "."
    if text == "-0.":
        text = "0."
    assert float(text) == float(value), (value, text)
    return text


def substitute(text: str, values: dict[str, float]) -> str:
    """The program with every read of a parameter in ``values`` replaced by its value."""

    def code(part: str) -> str:
        def replace(match: re.Match) -> str:
            name = "#" + match.group(2)
            if name not in values:
                return match.group(0)
            letter = match.group(1)
            number = literal(values[name])
            return letter + number if letter else "[" + number + "]"

        return _READ.sub(replace, part)

    pieces, last = [], 0
    for comment in _COMMENT.finditer(text):
        pieces.append(code(text[last : comment.start()]))
        pieces.append(comment.group(0))
        last = comment.end()
    pieces.append(code(text[last:]))
    return "".join(pieces)


def parameters_only(witness: dict[str, float]) -> dict[str, float]:
    """The witness values of program parameters (``#n``)."""
    return {name: value for name, value in witness.items() if re.fullmatch(r"#\d+", name)}


def assumed_ranges(text: str) -> dict[str, tuple[float, float]]:
    """``-20 <= #1 <= -2`` ranges stated by ``ncverify: assume`` annotations in the text."""
    ranges = {}
    for body in _ASSUME_LINE.findall(text):
        for low, name, high in _RANGE.findall(body):
            ranges[name] = (float(low), float(high))
    return ranges


def violated(result, rule: str | None = None, line: int | None = None) -> list:
    return [d for d in result.diagnostics if d.status is Status.VIOLATED
            and (rule is None or d.rule == rule) and (line is None or d.span.line == line)]


def with_status(result, status: Status, rule: str | None = None) -> list:
    return [d for d in result.diagnostics if d.status is status and (rule is None or d.rule == rule)]
