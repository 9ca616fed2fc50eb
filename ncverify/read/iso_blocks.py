"""What the ISO family's reader hands back: blocks of words and macro statements, and the
syntax problem of a block it cannot read. Kept apart from :mod:`ncverify.read.iso` so that
its grammar path (:mod:`ncverify.read.iso_grammar`, loaded only when a block needs it)
builds them without importing the reader back."""
from __future__ import annotations

from dataclasses import dataclass, field

from .. import ir


@dataclass(slots=True)
class Word:
    """An address word. ``value`` is a float for a literal number (as written, not yet
    scaled by the least input increment) or an expression; ``None`` for a bare address."""

    letter: str  # "G", "X", ... or ",R" for a comma word
    value: "float | ir.Expr | None"
    has_point: bool
    start: int  # 0-based columns in the line, end exclusive
    end: int


@dataclass(slots=True)
class Statement:
    """A macro statement: ``assign``, ``if_goto``, ``if_then``, ``while``, ``end``, ``goto``."""

    kind: str
    start: int
    end: int
    target: "ir.Var | None" = None
    value: "ir.Expr | None" = None
    condition: "ir.Expr | None" = None
    number: int | None = None  # the m of DO m / END m


@dataclass(slots=True)
class SyntaxProblem:
    message: str
    start: int
    end: int


@dataclass(slots=True)
class ReadBlock:
    line: int
    start: int  # 0-based, end exclusive, in the decoded line
    end: int
    items: list  # Word | Statement, in source order
    comments: list = field(default_factory=list)  # (text, start, end)
    skip: bool = False
    problem: SyntaxProblem | None = None
    percent: bool = False  # a '%' tape mark line
    directive: str | None = None  # a simulator / editor directive line ($Inches, #region)
