"""Array reader for streaks of plain HEIDENHAIN Klartext straight lines, the bulk of CAM
output: ``[n] L [X..] [Y..] [Z..] [R0] [F..|FMAX]`` with literal numbers (at least one
axis, in that order). A regular expression finds how far the streak goes (in C, no Python
per line); the numbers are then read with numpy as :mod:`ncverify.read.iso_runs` reads
them, exactly as ``float(text)`` would.

A line with anything else ends the streak and runs block by block (lowered by the
per-line fast path or the general one): an incremental axis, an M function, a Q parameter,
RL/RR, a comment, a number with more than 9 + 6 digits. So does ``L .. Z.. FMAX``, which
the lowering runs as a lift out of the cut rather than as a plain rapid.

The last line of a streak is left to the per-block path too: besides the position and the
feed, a plain line leaves one more fact behind (whether the tool got to its plane point at
feed, which a following ``L Z.. FMAX`` lift reads), and that line sets it as block by block
would.
"""
from __future__ import annotations

import re

import numpy

from .. import ir
from .iso_runs import parse_numbers

_UNSIGNED = rb"(?:\d{1,9}+(?:\.\d{0,6}+|,\d{1,6}+)?+|\.\d{1,6}+)"  # 12  12.5  12,5  12.  .5 (not 12, nor ,5)
_NUMBER = rb"[+-]?+" + _UNSIGNED
_LINE = (rb"[ \t]*+(?:\d++[ \t]++)?+L(?=[ \t]+[XYZ])(?:[ \t]++X" + _NUMBER + rb")?+(?:[ \t]++Y" + _NUMBER + rb")?+(?:[ \t]++Z"
         + _NUMBER + rb")?+(?:[ \t]++R0)?+(?:[ \t]++F(?:MAX|" + _UNSIGNED + rb"))?+[ \t\r]*+")
_PLAIN_LINE = re.compile(_LINE)
_STREAK = re.compile(rb"(?:" + _LINE + rb"\n)*+")
_COLUMN = numpy.full(256, -1, dtype=numpy.int64)  # X, Y, Z, F: columns of the table
_COLUMN[list(b"XYZF")] = numpy.arange(4)
_NUMBER_START = numpy.zeros(256, dtype=bool)
_NUMBER_START[list(b"0123456789+-.")] = True
_SEPARATOR = numpy.zeros(256, dtype=bool)
_SEPARATOR[list(b" \t\r\n")] = True
_RAPID, _FEED = ir.MoveBatch.KINDS.index("rapid"), ir.MoveBatch.KINDS.index("linear")


def is_plain_line(raw: bytes) -> bool:
    """Could this line be part of a run (see the module's docstring for the form)?"""
    return _PLAIN_LINE.fullmatch(raw) is not None


def read_plain_run(buffer, offset: int, line: int, limit: int = 1 << 20, minimum_lines: int = 16) -> ir.MoveBatch | None:
    """The plain lines from ``offset`` on (at most ``limit`` bytes) as one
    :class:`ir.MoveBatch`, its last line left out; None when fewer than ``minimum_lines``."""
    chunk = bytes(buffer[offset : min(len(buffer), offset + limit)])
    codes = numpy.frombuffer(chunk, dtype=numpy.uint8, count=_STREAK.match(chunk).end())
    newlines = numpy.flatnonzero(codes == ord("\n"))
    if len(newlines) <= minimum_lines:
        return None
    table = _words(codes, newlines)
    kinds = numpy.full(len(newlines), _FEED, dtype=numpy.int8)
    rapids = numpy.flatnonzero((codes[:-1] == ord("F")) & (codes[1:] == ord("M")))
    kinds[numpy.searchsorted(newlines, rapids)] = _RAPID
    lifts = numpy.flatnonzero((kinds == _RAPID) & ~numpy.isnan(table[:, 2]))  # FMAX with a Z word
    rows = (int(lifts[0]) if len(lifts) else len(newlines)) - 1
    if rows < minimum_lines:
        return None
    line_starts = numpy.concatenate(([0], newlines[: rows - 1] + 1))
    length = int(newlines[rows - 1]) + 1
    unscaled = numpy.zeros((rows, 3), dtype=bool)
    return ir.MoveBatch(offset, offset + length, line, line_starts + offset, kinds[:rows], ("X", "Y", "Z"), table[:rows, :3], unscaled,
                      table[:rows, 3], numpy.zeros(rows, dtype=bool), rows)


def _words(codes, newlines):
    """``table[line, column]``: the X, Y, Z and F numbers of each line (NaN when absent).
    A word is one of those letters directly followed by its number (the X of FMAX is not);
    the block number and the 0 of R0 belong to no word."""
    following = numpy.append(codes[1:], ord("\n"))
    is_word_letter = (_COLUMN[codes] >= 0) & _NUMBER_START[following]
    letters = numpy.flatnonzero(is_word_letter)
    word_at = numpy.cumsum(is_word_letter, dtype=numpy.int64) - 1
    token_at = numpy.cumsum(_SEPARATOR[codes], dtype=numpy.int64)

    def of_a_word(positions):
        """The positions that are part of a word's number (in its letter's token), and the word of each."""
        owner = word_at[positions]
        inside = (owner >= 0) & (token_at[positions] == token_at[letters[numpy.maximum(owner, 0)]])
        return positions[inside], owner[inside]

    digits, digit_owner = of_a_word(numpy.flatnonzero((codes >= ord("0")) & (codes <= ord("9"))))
    dots, dot_owner = of_a_word(numpy.flatnonzero((codes == ord(".")) | (codes == ord(","))))
    minus_owner = of_a_word(numpy.flatnonzero(codes == ord("-")))[1]
    values, _has_point = parse_numbers(codes, digits, digit_owner, dots, dot_owner, minus_owner, len(letters))
    table = numpy.full((len(newlines), 4), numpy.nan)
    table[numpy.searchsorted(newlines, letters), _COLUMN[codes[letters]]] = values
    return table
