"""How deep and how long an expression the readers take.

The readers descend recursively into brackets, and the interpreter evaluates the tree they
build recursively, so both are bounded well below Python's recursion limit. No control
takes expressions near these bounds (Fanuc nests 5 levels, SINUMERIK and Klartext a few
more); a program beyond them gets a syntax finding on its block instead of a traceback.
"""
from __future__ import annotations

MAX_NESTING = 32  # brackets, unary signs and function calls inside one another
MAX_TERMS = 200  # numbers, parameters and sub-expressions in one block


def nesting_message(depth: int) -> str:
    return f"an expression nested more than {depth} levels deep: no control accepts that"


def terms_message(terms: int) -> str:
    return f"an expression of more than {terms} terms is too long for a control's block buffer"
