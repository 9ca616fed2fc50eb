"""The ISO run reader with arcs: every line it takes is one the per-block fast lowering
takes too, with the same numbers, and it stops before a line that lowering leaves to the
general one."""
from __future__ import annotations

import math
import re

import numpy
import pytest

from hypothesis import given, settings
from hypothesis import strategies as st

from ncverify import ir
from ncverify.lower.iso import FastMotionForm, fast_motion_block
from ncverify.read.iso_runs import LETTERS, read_plain_run, read_plain_run_at

_FORM = FastMotionForm(frozenset("XYZ"))
_NUMBER = st.one_of(
    st.floats(-999, 999, allow_nan=False).map(lambda value: f"{value:.4f}"),
    st.integers(-9999, 9999).map(str),
    st.integers(-9, 9).map(lambda value: f"{value}."),
)
_WORD = st.tuples(st.sampled_from("XYZIJKRF"), _NUMBER).map("".join)
_LINE = st.tuples(
    st.one_of(st.none(), st.sampled_from(["G0", "G1", "G2", "G3", "G02", "G03"])),
    st.lists(_WORD, max_size=5),
).map(lambda parts: " ".join(([parts[0]] if parts[0] else []) + parts[1]))
# Lines no run may take: a number without its letter (alone or first), a letter without
# its number, a sign or a point out of place, a letter twice, a comment, an M code.
_ODD_LINE = st.sampled_from(["5", ".5", "-3", "  12.5", "7 X1.", "X", "G1 X", "X1.5.2", "X-1-2", "X1. X2.", "G1 X1. (c)", "M3", "+", "G1 Y-.5-"])
_ANY_LINE = st.one_of(_LINE, _LINE, _LINE, _ODD_LINE, st.just(""))


def _words_of(block: ir.Block) -> dict:
    """The letters and values the fast lowering read from a line."""
    words = {}
    for op in block.ops:
        if isinstance(op, ir.SetFeed):
            words["F"] = op.value
        elif isinstance(op, ir.Move):
            words.update(op.targets)
            words.update(op.arc or {})
    return words


@settings(max_examples=300, deadline=None)
@given(lines=st.lists(_ANY_LINE, min_size=1, max_size=30))
def test_every_line_of_a_run_is_lowered_alike_by_the_fast_path(lines):
    text = "".join(line + "\n" for line in lines).encode()
    run = read_plain_run(text, minimum_lines=1, arcs=True)
    taken = 0 if run is None else len(run.line_starts)
    for row in range(taken):
        if not run.worded[row]:
            assert not lines[row].strip()  # a blank line: no block
            continue
        block = fast_motion_block(lines[row].encode(), row + 1, None, _FORM)
        assert block is not None, lines[row]
        table = {chr(LETTERS[column]): value for column, value in enumerate(run.table[row].tolist()) if not math.isnan(value)}
        table.pop("N", None)
        table.pop("G", None)
        assert table == _words_of(block)
    if taken < len(lines) and run is not None:
        odd = lines[taken]
        letters = {word[0] for word in odd.split()}
        arc_words = letters & set("IJKR")
        straight = odd.split()[0] in ("G0", "G1") if odd else False
        # the run ended at a line the fast lowering leaves to the general one, or one that
        # repeats a letter
        assert (fast_motion_block(odd.encode(), 1, None, _FORM) is None or "R" in arc_words and arc_words - {"R"}
                or (arc_words and straight) or len(odd.split()) != len({word[0] for word in odd.split()}))


def test_a_radius_with_centre_offsets_ends_the_run():
    text = b"".join([b"G1 X1. Y1.\n"] * 20 + [b"G2 X2. Y2. I1. R1.\n"] + [b"G1 X3.\n"] * 20)
    run = read_plain_run(text, arcs=True)
    assert len(run.line_starts) == 20


def test_centre_words_on_a_straight_move_end_the_run():
    text = b"".join([b"G3 X1. Y1. I0.5 J0.5\n"] * 20 + [b"G1 X2. Y2. I1.\n"])
    run = read_plain_run(text, arcs=True)
    assert len(run.line_starts) == 20


def test_centre_words_without_a_point_end_the_run_where_integers_are_increments():
    text = b"".join([b"G2 X1. Y1. I1. J0.\n"] * 20 + [b"G2 X1. Y1. I1 J0.\n"])
    assert len(read_plain_run(text, arcs=True, stop_at_small_integers=True).line_starts) == 20
    assert len(read_plain_run(text, arcs=True).line_starts) == 21


def _read_from_the_start(buffer, offset: int, limit: int, first_chunk: int, **options):
    """The run read as it was before pieces: each larger chunk read again from ``offset``."""
    size = min(first_chunk, limit)
    while True:
        end = min(len(buffer), offset + size)
        chunk = bytes(buffer[offset:end])
        if end < len(buffer):
            chunk = chunk[: chunk.rfind(b"\n") + 1]
        run = read_plain_run(chunk, **options)
        if run is None or run.length < len(chunk) or end >= len(buffer) or size >= limit:
            return run
        size = min(size * 4, limit)


@settings(max_examples=300, deadline=None)
@given(lines=st.lists(st.one_of(_LINE, _LINE, _LINE, _LINE, _ANY_LINE), min_size=1, max_size=120), offset_line=st.integers(0, 5),
       first_chunk=st.integers(40, 400), largest=st.integers(0, 4), limit=st.integers(100, 6000), last_newline=st.booleans(), arcs=st.booleans(),
       increments=st.booleans())
def test_a_run_read_in_pieces_is_the_run_read_in_one(lines, offset_line, first_chunk, largest, limit, last_newline, arcs, increments):
    buffer = ("\n".join(lines) + ("\n" if last_newline else "")).encode()
    offset = sum(len(line) + 1 for line in lines[:offset_line]) if offset_line < len(lines) else 0
    options = {"arcs": arcs, "stop_at_small_integers": increments}
    pieces = read_plain_run_at(buffer, offset, limit, first_chunk=first_chunk, largest_chunk=first_chunk * 4 ** largest, **options)
    whole = _read_from_the_start(buffer, offset, limit, first_chunk, **options)
    assert (pieces is None) == (whole is None)
    if whole is not None:
        assert pieces.length == whole.length
        assert numpy.array_equal(pieces.table, whole.table, equal_nan=True)
        assert numpy.array_equal(pieces.pointless, whole.pointless)
        assert numpy.array_equal(pieces.line_starts, whole.line_starts)
        assert numpy.array_equal(pieces.worded, whole.worded)


def test_a_number_without_its_letter_ends_the_run_before_its_line():
    """It once joined the number of the line before (Y1. and a line "5" read as Y1.5)."""
    text = b"G1 X1. Y1.\n" * 20 + b"5\n" + b"G1 X2. Y2.\n" * 20
    run = read_plain_run(text)
    assert len(run.line_starts) == 20 and run.table[19].tolist()[3] == 1.0


@settings(max_examples=200, deadline=None)
@given(numbers=st.lists(st.tuples(st.integers(0, 10**15 - 1), st.integers(0, 14), st.booleans()), min_size=16, max_size=60))
def test_numbers_of_up_to_fifteen_digits_read_as_float_reads_them(numbers):
    """Each mantissa is the difference of two running totals of whole numbers: exact."""
    texts = []
    for mantissa, decimals, negative in numbers:
        digits = str(mantissa).rjust(decimals + 1, "0")
        texts.append(("-" if negative else "") + (digits[: len(digits) - decimals] + "." + digits[len(digits) - decimals :] if decimals else digits + "."))
    run = read_plain_run("".join(f"G1 X{text}\n" for text in texts).encode())
    assert run.table[:, LETTERS.index(b"X")].tolist() == [float(text) for text in texts]


def test_running_totals_past_two_to_the_63_still_give_each_number():
    """Ten thousand fifteen-digit numbers add up to more than an int64 holds."""
    run = read_plain_run(b"G1 X999999999999.999 Y-99999999999999.9\n" * 10_000)
    assert len(run.line_starts) == 10_000
    assert set(run.table[:, LETTERS.index(b"X")].tolist()) == {999999999999.999}
    assert set(run.table[:, LETTERS.index(b"Y")].tolist()) == {-99999999999999.9}


_OTHER_CODE_LINE = st.sampled_from(["G81 X1. Y2.", "G98 G81 X5. Y5. Z-5. R1. F150.", "G40 G1 X-10.", "G17", "G4 X1.", "G10 X1.", "G1.5 X1.", "G-1 X1.", "G01 X1.", "G3.0 X1. I1."])


@settings(max_examples=400, deadline=None)
@given(lines=st.lists(st.one_of(_LINE, _LINE, _LINE, _ANY_LINE, _OTHER_CODE_LINE), min_size=0, max_size=40), minimum=st.integers(1, 20),
       arcs=st.booleans(), last_newline=st.booleans())
def test_the_quick_look_at_the_first_lines_never_changes_what_the_reader_answers(lines, minimum, arcs, last_newline):
    """Before its arrays, the reader looks at the first lines with a pattern (a failed attempt
    then costs microseconds, not a quarter of a millisecond): whatever that pattern refuses,
    the arrays refuse as well."""
    from ncverify.read import iso_runs

    chunk = ("\n".join(lines) + ("\n" if last_newline else "")).encode()
    quick = read_plain_run(chunk, minimum_lines=minimum, arcs=arcs)
    with pytest.MonkeyPatch.context() as patched:
        patched.setattr(iso_runs, "_lines_in_form", lambda arcs, count: re.compile(rb""))  # lets every chunk through
        full = read_plain_run(chunk, minimum_lines=minimum, arcs=arcs)
    assert (quick is None) == (full is None)
    if full is not None:
        assert quick.length == full.length and numpy.array_equal(quick.table, full.table, equal_nan=True)


_G_WORD = st.sampled_from(["G0", "G00", "G1", "G01", "G1.", "G1.0", "G-0", "G+1", "G.0", "G0.", "G003", "G2", "G03", "G3.00",
                           "G10", "G80", "G98", "G-1", "G2.5", "G.5", "G4", "G90", "G17", "G 1", "G -1"])
_G_LINE = st.tuples(st.lists(_G_WORD, min_size=1, max_size=2), st.lists(_WORD, max_size=4)).map(lambda parts: " ".join(parts[0] + parts[1]))


@settings(max_examples=400, deadline=None)
@given(line=_G_LINE)
def test_the_plain_form_refuses_no_line_the_fast_lowering_takes(line):
    """The plain form lets G through only with a motion code of 0-3, however written: a
    line it refuses goes to the general lowering, so the fast one must have no block for it."""
    from ncverify.lower.iso import _CANONICAL, _FAST_LINE, lower_fast_motion

    raw = line.encode()
    if _FAST_LINE.fullmatch(raw) is None and _CANONICAL.fullmatch(raw) is None:
        assert lower_fast_motion(raw, 1, None, _FORM) is None
