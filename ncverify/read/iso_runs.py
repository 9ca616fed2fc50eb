"""Array reader for streaks of plain ISO blocks (``N G0/G1 X Y Z F``, and where the caller
asks, the arcs ``G2/G3`` with centre offsets ``I J K`` or a radius ``R``), the bulk of CAM
output. A chunk of text is classified byte by byte with a lookup table; words, numbers and
lines are found with numpy, and numbers are parsed exactly: the digits make an integer
mantissa below 2**53 that is divided by an exact power of ten, which IEEE division rounds
correctly, so every value equals what ``float(text)`` gives.

The first line that is not plain ends the run (the per-block reader takes it from there),
so what is read here is exactly what the per-block reader would read.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache

import numpy

from ..trace import any_in_row

LETTERS = b"NGXYZFIJKR"  # columns of the table, in this order
ARC_WORDS = slice(6, 10)  # the columns of I, J, K and R
_STRAIGHT_LETTERS = b"NGXYZF"
_OTHER, _LETTER, _DIGIT, _DOT, _SIGN, _BLANK, _NEWLINE = range(7)
_NEWLINE_BYTE = ord("\n")


def _byte_classes(letters: bytes):
    classes = numpy.zeros(256, dtype=numpy.int8)
    classes[list(letters)] = _LETTER
    classes[list(b"0123456789")] = _DIGIT
    classes[ord(".")] = _DOT
    classes[list(b"+-")] = _SIGN
    classes[list(b" \t\r")] = _BLANK
    classes[ord("\n")] = _NEWLINE
    return classes


_BYTE_CLASS = {False: _byte_classes(_STRAIGHT_LETTERS), True: _byte_classes(LETTERS)}  # by whether arcs are read
_COLUMN = numpy.zeros(256, dtype=numpy.int64)
_COLUMN[list(LETTERS)] = numpy.arange(len(LETTERS))
_G, _X, _F, _I, _R = (LETTERS.index(letter) for letter in b"GXFIR")
_POWERS_OF_TEN = 10.0 ** numpy.arange(23)
_MAX_DIGITS = 15  # mantissas stay below 2**53
_INTEGER_POWERS_OF_TEN = 10 ** numpy.arange(_MAX_DIGITS, dtype=numpy.int64)
_MOTION_CODES = {False: (0.0, 1.0), True: (0.0, 1.0, 2.0, 3.0)}
_FIRST_CHUNK = 1 << 14  # bytes read first; CAM streaks between arcs are short
_MINIMUM_LINES = 16  # a shorter streak is left to the per-block path
_LARGEST_CHUNK = 1 << 18  # larger arrays are mapped afresh for every chunk (a tenth of the run's time)


@dataclass(slots=True)
class PlainRun:
    """``table[line, column]``: the number of letter ``LETTERS[column]`` on each line (NaN
    when absent), without the arc words' columns when no line has one; ``pointless``
    marks numbers written without a decimal point."""

    table: numpy.ndarray
    pointless: numpy.ndarray
    line_starts: numpy.ndarray  # offsets relative to the chunk
    length: int  # bytes read
    worded: numpy.ndarray  # lines holding at least one word (the others are no block)

    @property
    def arc_words(self) -> numpy.ndarray | None:
        """The ``I J K R`` columns, None when no line has one."""
        return self.table[:, ARC_WORDS] if self.table.shape[1] > ARC_WORDS.start else None

    @property
    def blocks(self) -> int:
        return int(numpy.count_nonzero(self.worded))

    @staticmethod
    def joined(pieces: list[PlainRun]) -> PlainRun:
        """Runs read one after the other as one run (the arc words' columns kept when any
        piece has them)."""
        if len(pieces) == 1:
            return pieces[0]
        width = max(piece.table.shape[1] for piece in pieces)
        starts = numpy.cumsum([0] + [piece.length for piece in pieces[:-1]])
        return PlainRun(  # stacked column by column, as each piece's table is laid out
            numpy.hstack([_widened(piece.table, width, numpy.nan).T for piece in pieces]).T,
            numpy.hstack([_widened(piece.pointless, width, False).T for piece in pieces]).T,
            numpy.concatenate([piece.line_starts + start for piece, start in zip(pieces, starts)]),
            sum(piece.length for piece in pieces),
            numpy.concatenate([piece.worded for piece in pieces]))


def _widened(array, width: int, fill):
    if array.shape[1] == width:
        return array
    return numpy.hstack([array, numpy.full((array.shape[0], width - array.shape[1]), fill, dtype=array.dtype)])


class _Chunk:
    """The byte positions of one chunk, found once."""

    def __init__(self, chunk: bytes, arcs: bool):
        self.codes = numpy.frombuffer(chunk, dtype=numpy.uint8)
        self.classes = _BYTE_CLASS[arcs].take(self.codes)  # take: twice as fast as indexing
        is_letter = self.classes == _LETTER
        is_newline = self.classes == _NEWLINE
        self.letters = numpy.flatnonzero(is_letter)
        self.newlines = numpy.flatnonzero(is_newline)
        self.digits = numpy.flatnonzero(self.classes == _DIGIT)
        self.dots = numpy.flatnonzero(self.classes == _DOT)
        self.signs = numpy.flatnonzero(self.classes == _SIGN)
        # For every byte: how many letters are at or before it (the index of the word it
        # belongs to, plus one).
        self.letters_up_to = numpy.cumsum(is_letter, dtype=numpy.int32)
        self.digit_owner = self.owner_of(self.digits)
        self.dot_owner = self.owner_of(self.dots)
        # digits after each letter, up to the next letter ([0]: before the first one)
        self.digit_counts = numpy.bincount(self.digit_owner + 1, minlength=len(self.letters) + 1)
        # the line and the table column of every letter (the words of a line are counted
        # at its newline: cheaper than numbering the lines of every byte)
        self.words_per_line = numpy.diff(self.letters_up_to.take(self.newlines), prepend=0, append=len(self.letters))
        self.letter_lines = numpy.repeat(numpy.arange(len(self.words_per_line), dtype=numpy.int32), self.words_per_line)
        self.letter_columns = _COLUMN.take(self.codes.take(self.letters))

    def owner_of(self, positions):
        """The index of the word each position belongs to (-1 before the first letter)."""
        return self.letters_up_to.take(positions) - 1

    def line_start_at(self, position: int) -> int:
        """The start of the line that holds ``position`` (the chunk's length stays itself)."""
        if position >= len(self.codes):
            return len(self.codes)
        before = self.newlines[: numpy.searchsorted(self.newlines, position)]
        return int(before[-1]) + 1 if before.size else 0

    def lines_before(self, stop: int) -> int:
        """How many lines start before ``stop`` (a line start or the chunk's length)."""
        count = int(numpy.searchsorted(self.newlines, stop))
        return count + (0 if stop == 0 or self.codes[stop - 1] == _NEWLINE_BYTE else 1)

    def first_bad_position(self) -> int:
        """The first byte that breaks the form of a word: a character outside it, a letter
        not followed directly by its number, a number not directly after a letter, a sign
        inside a number, a number with two points, no digit or too many digits. (A letter
        twice in a line is found on the table, see :func:`_first_odd_line`.)"""
        classes, letters = self.classes, self.letters
        numeric = (classes >= _DIGIT) & (classes <= _SIGN)
        bad = [_first_true(classes == _OTHER),
               _first_true(numeric[:1]),
               _first_true(numeric[1:] & ~(numeric[:-1] | (classes[:-1] == _LETTER))) + 1]  # after a blank or a line end
        follows = classes.take(letters + 1, mode="clip")  # the last byte a letter: clipped onto itself, no number
        bad.append(letters[(follows < _DIGIT) | (follows > _SIGN)][:1])
        signs = self.signs
        bad.append(signs[classes[numpy.maximum(signs - 1, 0)] != _LETTER][:1])
        bad.append(self.dots[1:][self.dot_owner[1:] == self.dot_owner[:-1]][:1])
        if len(letters):
            digit_counts = self.digit_counts[1:]
            bad.append(letters[(digit_counts == 0) | (digit_counts > _MAX_DIGITS)][:1])
        found = [int(position[0]) for position in bad if len(position)]
        return min(found) if found else len(self.codes)

    def numbers(self, stop: int):
        """The number after each letter before ``stop``, and whether it has a point."""
        letters = self.letters[: numpy.searchsorted(self.letters, stop)]  # positions are in order: the kept ones lead
        digits = numpy.searchsorted(self.digits, stop)
        dots = numpy.searchsorted(self.dots, stop)
        signs = self.signs[: numpy.searchsorted(self.signs, stop)]
        minus = signs[self.codes.take(signs) == ord("-")]
        per_number = self.digit_counts[1 : len(letters) + 1].copy()
        if len(per_number):  # digits past stop that the last word owns (a number without its letter on the next line)
            per_number[-1] -= int(per_number.sum()) - digits
        values, has_point = parse_numbers(self.codes, self.digits[:digits], self.digit_owner[:digits], self.dots[:dots], self.dot_owner[:dots],
                                          self.owner_of(minus), len(letters), digits_follow_point=True, per_number=per_number)
        return letters, values, has_point


def _first_true(mask):
    """The index of the first true entry of a boolean array, as an array of one, or none
    (``argmax`` stops at it, where ``flatnonzero`` reads to the end)."""
    first = int(mask.argmax()) if len(mask) else 0
    return numpy.arange(first, first + 1) if len(mask) and mask[first] else numpy.zeros(0, dtype=numpy.int64)


def parse_numbers(codes, digits, digit_owner, dots, dot_owner, minus_owner, count: int, digits_follow_point: bool = False, per_number=None):
    """The values of ``count`` numbers given by where their characters are: the digits and
    decimal points (in text order) with the number each belongs to, and the numbers that
    carry a minus sign. Returns the values and whether each was written with a point.
    A number's digits are consecutive among ``digits``: its mantissa is their sum weighted
    by powers of ten, and its decimals are its digits that follow its point. With
    ``digits_follow_point`` (ISO words: only digits come after a point) they are the bytes
    from the point to the number's last digit, found without searching for the point among
    the digits (a third of the time of this function); a number without that form is on a
    line the caller does not take. ``per_number``: each number's count of digits, when
    the caller has it."""
    if per_number is None:
        per_number = numpy.bincount(digit_owner, minlength=count)
    ends = numpy.cumsum(per_number)  # one past each number's last digit
    rank = (ends - 1).take(digit_owner)
    rank -= numpy.arange(len(digits))  # digits after this one in its number
    if len(digits) and per_number.max() <= _MAX_DIGITS:
        # in integers, as a running total: a mantissa is the difference of two totals, exact
        # even where the total wraps past 2**63 (it is below 2**53); numpy's reduceat, which
        # sums number by number, took three times as long
        totals = numpy.concatenate(([0], numpy.cumsum((codes.take(digits) - 48) * _INTEGER_POWERS_OF_TEN.take(rank))))
        mantissa = (totals.take(ends) - totals.take(ends - per_number)).astype(numpy.float64)
    else:
        mantissa = numpy.zeros(count)
        written = per_number > 0
        if len(digits):
            mantissa[written] = numpy.add.reduceat((codes.take(digits) - 48) * _POWERS_OF_TEN.take(rank), (ends - per_number)[written])
    decimals = numpy.zeros(count, dtype=numpy.int64)
    if digits_follow_point:
        last_digit = digits.take(numpy.maximum(ends.take(dot_owner) - 1, 0)) if len(digits) else dots
        decimals[dot_owner] = numpy.maximum(last_digit - dots, 0)
    else:
        decimals[dot_owner] = ends[dot_owner] - numpy.searchsorted(digits, dots)
    has_point = numpy.zeros(count, dtype=bool)
    has_point[dot_owner] = True
    values = mantissa / _POWERS_OF_TEN[decimals]
    values[minus_owner] *= -1.0
    return values, has_point


def read_plain_run(chunk: bytes, minimum_lines: int = _MINIMUM_LINES, stop_at_small_integers: bool = False, arcs: bool = False) -> PlainRun | None:
    """Read the plain lines at the start of ``chunk`` (whole lines only); None when
    fewer than ``minimum_lines``. With ``stop_at_small_integers`` (a control that reads
    integers in least input increments) the run also ends before a coordinate like ``Z5``,
    which the per-block path reports as a decimal-point trap. With ``arcs`` the lines may
    also be arcs, as the per-block fast lowering takes them (see :func:`_first_odd_line`).
    The lines up to the first byte out of form are put in the table, which then tells
    the first line whose words do not go together."""
    if len(chunk) < minimum_lines * 4:
        return None
    if minimum_lines and _lines_in_form(arcs, minimum_lines).match(chunk) is None:
        return None  # a byte out of form in the first lines: the run is too short, told without the arrays
    found = _Chunk(chunk, arcs)
    stop = found.line_start_at(found.first_bad_position())
    letters, values, has_point = found.numbers(stop)
    line_count = found.lines_before(stop)
    if line_count < minimum_lines:
        return None
    rows, columns = found.letter_lines[: len(letters)], found.letter_columns[: len(letters)]  # the kept letters lead
    width = len(LETTERS) if (columns >= _I).any() else len(_STRAIGHT_LETTERS)  # no arc words: no room for them
    # column by column in memory (a column's words, such as one axis, are read together);
    # flat indices: a third of the time of indexing by (rows, columns)
    cells = columns * line_count + rows
    table = numpy.full(width * line_count, numpy.nan)
    table[cells] = values
    table = table.reshape(width, line_count).T
    pointless = numpy.zeros(width * line_count, dtype=bool)
    pointless[cells] = ~has_point
    pointless = pointless.reshape(width, line_count).T
    odd = _first_odd_line(table, pointless, found.words_per_line[:line_count], stop_at_small_integers, arcs)
    if odd < line_count:
        if odd < minimum_lines:
            return None
        line_count, stop = odd, int(found.newlines[odd - 1]) + 1 if odd else 0
        table, pointless = table[:odd], pointless[:odd]
    line_starts = numpy.concatenate(([0], found.newlines[: line_count - 1] + 1)) if line_count else numpy.zeros(0, dtype=numpy.int64)
    return PlainRun(table, pointless, line_starts, stop, found.words_per_line[:line_count] > 0)


@lru_cache(maxsize=4)
def _lines_in_form(arcs: bool, count: int) -> re.Pattern:
    """``count`` whole lines of nothing but the bytes a plain run's words are made of, any
    motion code among those the run takes (a G word of another value, such as G81 or G40,
    ends the run). A streak cut short by a tool change, a comment or a cycle fails this in
    microseconds, where the arrays of :class:`_Chunk` take a quarter of a millisecond to
    tell. A line that passes may still be refused by them (one letter twice)."""
    letters = (LETTERS if arcs else _STRAIGHT_LETTERS).replace(b"G", b"")
    motion = rb"G[+-]?0*[0-3]?(?:\.0*)?(?![0-9.])" if arcs else rb"G[+-]?0*[01]?(?:\.0*)?(?![0-9.])"
    line = rb"(?:[" + letters + rb"0-9.+\- \t\r]|" + motion + rb")*+(?:\n|\Z)"  # possessive: no line end inside; the text's last may have none
    return re.compile(rb"(?:" + line + rb"){" + str(count).encode() + rb"}")


def _first_odd_line(table, pointless, words, small_integers_are_increments: bool, arcs: bool) -> int:
    """The first line whose words the per-block fast lowering leaves to the general one
    (the table's length when none): one letter twice (fewer cells filled than ``words``, the
    line's letters); a motion code other than G0/G1 (and G2/G3 with ``arcs``); counted in
    increments, a coordinate without a point from 1 to 999; a radius with centre offsets,
    centre or radius words on a G0/G1 line, or (counted in increments) one without a point."""
    odd = numpy.count_nonzero(~numpy.isnan(table), axis=1) < words  # a number is never NaN
    motion = table[:, _G]
    odd_motion = ~numpy.isnan(motion)
    for code in _MOTION_CODES[arcs]:  # cheaper than numpy.isin, which sorts
        odd_motion &= motion != code
    odd |= odd_motion
    if small_integers_are_increments:
        magnitude = numpy.abs(table[:, _X : _F])
        odd |= any_in_row(pointless[:, _X : _F] & (magnitude >= 1) & (magnitude < 1000))
    if table.shape[1] > _I:
        arc_words = ~numpy.isnan(table[:, _I:])
        centre, radius = any_in_row(arc_words[:, : _R - _I]), arc_words[:, _R - _I]
        odd |= (centre & radius) | ((centre | radius) & (motion < 2.0))
        if small_integers_are_increments:
            odd |= any_in_row(arc_words & pointless[:, _I:])
    first = numpy.flatnonzero(odd)
    return int(first[0]) if first.size else len(table)


def read_plain_run_at(buffer, offset: int, limit: int, stop_at_small_integers: bool = False, arcs: bool = False,
                      radius_word: bytes = b"R", first_chunk: int = _FIRST_CHUNK, largest_chunk: int = _LARGEST_CHUNK) -> PlainRun | None:
    """The plain run from ``offset`` of ``buffer`` on (whole lines, at most ``limit``
    bytes). It is read in chunks that start small and grow fourfold up to
    ``largest_chunk``, each from where the run so far ends, while the run fills them: the
    arrays cost what the run is long, so a streak of ten lines between two arcs does not
    pay for classifying a whole ``limit`` of text, no byte is classified twice, and the
    arrays of one chunk stay small enough to be reused rather than mapped afresh. Whether
    a line is plain depends on that line alone, so the pieces make the run one read of all
    the text would make; the first chunk decides whether the streak is long enough.
    ``radius_word``: how the language writes an arc's radius (SINUMERIK ``CR=``; there a
    bare R is a parameter and ends the run)."""
    size = first_chunk
    pieces: list[PlainRun] = []
    start = offset
    while True:
        end = min(len(buffer), offset + limit, start + size)
        chunk = bytes(buffer[start:end])
        if end < len(buffer):
            chunk = chunk[: chunk.rfind(b"\n") + 1]
        if radius_word != b"R":
            chunk = _radius_words_as_r(chunk, radius_word)
        piece = read_plain_run(chunk, minimum_lines=0 if pieces else _MINIMUM_LINES, stop_at_small_integers=stop_at_small_integers, arcs=arcs)
        if piece is None:
            return None
        if piece.length:
            pieces.append(piece)
            start += piece.length
        if piece.length < len(chunk) or end >= len(buffer) or end >= offset + limit:
            return PlainRun.joined(pieces)
        size = min(size * 4, largest_chunk) if chunk else size * 4  # no whole line in it yet: look further


def _radius_words_as_r(chunk: bytes, radius_word: bytes) -> bytes:
    """``chunk`` with each ``radius_word`` written as ``R`` at its end (blanks before it, so
    every byte keeps its place) and every other R made a byte outside the form."""
    padding = b" " * (len(radius_word) - 1)
    return chunk.replace(b"R", b"?").replace(radius_word.replace(b"R", b"?"), padding + b"R")
