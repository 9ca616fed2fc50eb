"""Array reader for streaks of plain HEIDENHAIN Klartext contour lines, the bulk of CAM
output, with literal numbers:

- ``[n] L [X..] [Y..] [Z..] [R0] [F..|FMAX]`` (at least one axis, in that order);
- ``[n] CR [X..] [Y..] R.. DR± [F..]``, an arc by its radius (at least one axis);
- ``[n] CC X.. Y..``, the pole, and ``[n] C [X..] [Y..] DR± [F..]``, an arc about it
  (at least one axis; only after a ``CC`` of the same streak, so its centre is known here).

A regular expression finds how far the streak goes (in C, no Python per line); the
numbers are then read with numpy as :mod:`ncverify.read.iso_runs` reads them, exactly as
``float(text)`` would.

A line with anything else ends the streak and runs block by block (lowered by the
per-line fast path or the general one): an incremental axis, an M function, a Q parameter,
RL/RR, a tangential arc, a comment, a number with more than 9 + 6 digits. So does
``L .. Z.. FMAX``, which the lowering runs as a lift out of the cut rather than as a plain
rapid.

The last line of a streak is left to the per-block path too: besides the position and the
feed, a plain line leaves one more fact behind (whether the tool got to its plane point at
feed, which a following ``L Z.. FMAX`` lift reads), and that line sets it as block by block
would.

What the lines leave besides the moves, the batch carries for the interpreter and the
dialect's runtime (:class:`ir.MoveBatch`): the ``R0`` lines (they end radius compensation,
so a batch under it stops there), the poles, and the arcs about them, which leave the
motion mode alone.
"""
from __future__ import annotations

import re

import numpy

from .. import ir
from .iso_runs import parse_numbers

_UNSIGNED = rb"(?:\d{1,9}+(?:\.\d{0,6}+|,\d{1,6}+)?+|\.\d{1,6}+)"  # 12  12.5  12,5  12.  .5 (not 12, nor ,5)
_NUMBER = rb"[+-]?+" + _UNSIGNED
_FEED_WORD = rb"(?:[ \t]++F" + _UNSIGNED + rb")?+"
_PLANE_WORDS = rb"(?:[ \t]++X" + _NUMBER + rb")?+(?:[ \t]++Y" + _NUMBER + rb")?+"
_DIRECTION = rb"[ \t]++DR[+-]"
_COMMANDS = (
    rb"L(?=[ \t]+[XYZ])" + _PLANE_WORDS + rb"(?:[ \t]++Z" + _NUMBER + rb")?+(?:[ \t]++R0)?+(?:[ \t]++F(?:MAX|" + _UNSIGNED + rb"))?+",
    rb"CR(?=[ \t]+[XY])" + _PLANE_WORDS + rb"[ \t]++R(?!0(?![0-9.,]))" + _NUMBER + _DIRECTION + _FEED_WORD,  # a bare R0 is no radius
    rb"CC[ \t]++X" + _NUMBER + rb"[ \t]++Y" + _NUMBER,
    rb"C(?=[ \t]+[XY])" + _PLANE_WORDS + _DIRECTION + _FEED_WORD,
)
_LINE = rb"[ \t]*+(?:\d++[ \t]++)?+(?:" + rb"|".join(_COMMANDS) + rb")[ \t\r]*+"
_PLAIN_LINE = re.compile(_LINE)
_STREAK = re.compile(rb"(?:" + _LINE + rb"\n)*+")
_X, _Y, _Z, _F, _R = range(5)  # columns of the table
_COLUMN = numpy.full(256, -1, dtype=numpy.int64)
_COLUMN[list(b"XYZFR")] = numpy.arange(5)
_NUMBER_START = numpy.zeros(256, dtype=bool)
_NUMBER_START[list(b"0123456789+-.")] = True
_SEPARATOR = numpy.zeros(256, dtype=bool)
_SEPARATOR[list(b" \t\r\n")] = True
_LETTER = numpy.zeros(256, dtype=bool)
_LETTER[ord("A") : ord("Z") + 1] = True
_RAPID, _FEED, _CW, _CCW = (ir.MoveBatch.KINDS.index(kind) for kind in ("rapid", "linear", "arc_cw", "arc_ccw"))
_STRAIGHT, _BY_RADIUS, _POLE, _ABOUT_POLE = range(4)  # L, CR, CC, C (the poles and the arcs about them last)


def is_plain_line(raw: bytes) -> bool:
    """Could this line be part of a run (see the module's docstring for the form)?"""
    return _PLAIN_LINE.fullmatch(raw) is not None


def read_plain_run(buffer, offset: int, line: int, limit: int = 1 << 20, minimum_lines: int = 16) -> ir.MoveBatch | None:
    """The plain lines from ``offset`` on (at most ``limit`` bytes) as one
    :class:`ir.MoveBatch`, its last line left out; None when fewer than ``minimum_lines``."""
    streak = _STREAK.match(buffer, offset, min(len(buffer), offset + limit)).end()  # found in the text itself: only the streak is copied
    codes = numpy.frombuffer(bytes(buffer[offset:streak]), dtype=numpy.uint8)
    newlines = numpy.flatnonzero(codes == ord("\n"))
    if len(newlines) <= minimum_lines:
        return None
    starts = numpy.concatenate(([0], newlines[:-1] + 1))
    commands = _commands(codes, starts)
    table = _words(codes, newlines)
    kinds = _kinds(codes, newlines, commands)
    lifts = numpy.flatnonzero((kinds == _RAPID) & ~numpy.isnan(table[:, _Z]))  # FMAX with a Z word
    about_pole = commands == _ABOUT_POLE
    orphans = numpy.flatnonzero(about_pole & (numpy.cumsum(commands == _POLE) == 0))  # about a pole set before the streak
    rows = min(int(lifts[0]) if len(lifts) else len(newlines), int(orphans[0]) if len(orphans) else len(newlines)) - 1
    if rows < minimum_lines:
        return None
    length = int(newlines[rows - 1]) + 1
    table, kinds, commands, about_pole = table[:rows], kinds[:rows], commands[:rows], about_pole[:rows]
    poles = numpy.where((commands == _POLE)[:, None], table[:, :2], numpy.nan)
    arc_words = None
    if (kinds >= _CW).any():
        arc_words = numpy.full((rows, 4), numpy.nan)  # I J K R
        arc_words[about_pole, :2] = _forward_filled(poles)[about_pole]
        by_radius = commands == _BY_RADIUS
        arc_words[by_radius, 3] = table[by_radius, _R]
    values = numpy.where((commands == _POLE)[:, None], numpy.nan, table[:, :3])  # a pole is no move
    return ir.MoveBatch(offset, offset + length, line, starts[:rows] + offset, kinds, ("X", "Y", "Z"), values,
                        numpy.zeros((rows, 3), dtype=bool), table[:, _F], numpy.zeros(rows, dtype=bool), rows, arc_words,
                        centres_absolute=True, keeps_motion=_where_any(commands >= _POLE),
                        compensation_off=_where_any((commands == _STRAIGHT) & ~numpy.isnan(table[:, _R])),
                        poles=poles if (commands == _POLE).any() else None)


def _where_any(rows):
    """The rows of a mask, None when it holds none (the batch then does nothing for it)."""
    return rows if rows.any() else None


def _commands(codes, starts):
    """Each line's command (``_STRAIGHT``, ``_BY_RADIUS``, ``_POLE``, ``_ABOUT_POLE``), told
    by its first letter and the byte after it (C alone is followed by a blank)."""
    letters = numpy.flatnonzero(_LETTER[codes])
    first = letters[numpy.searchsorted(letters, starts)]  # every line has its command
    second = codes[first + 1]  # a command is never a line's last byte
    circle = codes[first] == ord("C")
    return numpy.where(~circle, _STRAIGHT, numpy.where(second == ord("R"), _BY_RADIUS, numpy.where(second == ord("C"), _POLE, _ABOUT_POLE))).astype(numpy.int8)


def _kinds(codes, newlines, commands):
    """Each line's kind: FMAX a rapid, DR- and DR+ the arcs, the rest a feed move; -1 for a
    pole, which moves nothing."""
    kinds = numpy.full(len(newlines), _FEED, dtype=numpy.int8)
    rapids = numpy.flatnonzero((codes[:-1] == ord("F")) & (codes[1:] == ord("M")))
    kinds[numpy.searchsorted(newlines, rapids)] = _RAPID
    turns = numpy.flatnonzero((codes[:-2] == ord("D")) & (codes[1:-1] == ord("R")))
    kinds[numpy.searchsorted(newlines, turns)] = numpy.where(codes[turns + 2] == ord("-"), _CW, _CCW)
    kinds[commands == _POLE] = -1
    return kinds


def _forward_filled(rows):
    """Each row of ``rows`` replaced by the last row at or before it that is not NaN (the
    first row stays as it is)."""
    written = ~numpy.isnan(rows[:, 0])
    return rows[numpy.maximum.accumulate(numpy.where(written, numpy.arange(len(rows)), 0))]


def _words(codes, newlines):
    """``table[line, column]``: the X, Y, Z, F and R numbers of each line (NaN when absent).
    A word is one of those letters after a blank, directly followed by its number (the X of
    FMAX and the R of DR- are not); the block number belongs to no word. R is a circle's
    radius, or the 0 of R0."""
    following = numpy.append(codes[1:], ord("\n"))
    preceding = numpy.insert(codes[:-1], 0, ord("\n"))
    is_word_letter = (_COLUMN[codes] >= 0) & _NUMBER_START[following] & _SEPARATOR[preceding]
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
    table = numpy.full((len(newlines), 5), numpy.nan)
    table[numpy.searchsorted(newlines, letters), _COLUMN[codes[letters]]] = values
    return table
