"""Line numbers of a program's offsets: counted on the buffer in place, an mmap as much as
bytes, they are the line ends before the offset plus one. Scans of the whole text for the
lines that match a pattern find what the pattern finds."""
from __future__ import annotations

import mmap
import re

from hypothesis import given, settings
from hypothesis import strategies as st

from ncverify.lower.fagor import _DOLLAR, _PERCENT, _STRUCTURE, _SUBROUTINE_HEADER
from ncverify.lower.sinumerik import _MODAL_CALL, _PROGRAM_END, _REPEAT_SECTION
from ncverify.lower.heidenhain import _TOOL_CALL_NUMBER, _TOOL_CALL_UNSURE
from ncverify.lower.iso import _TOOL_WORD, IsoFrontend
from ncverify.lower.linuxcnc import _FANUC_PROGRAM, _LETTER_O, _OWORD_CALL, _SUB, LinuxcncFrontend
from ncverify.source import ProgramSource, finditer_all, lines_holding, search_any

_TEXT = st.lists(st.sampled_from([b"G1 X1.\n", b"\n", b"M30", b"(a\r\nb)\n", b"N10 G0 Z5.\r\n", b"x" * 300]), max_size=40).map(b"".join)


@settings(max_examples=200, deadline=None)
@given(text=_TEXT, cut=st.floats(0, 1))
def test_a_line_number_counts_the_line_ends_before_its_offset(text, cut):
    offset = int(len(text) * cut)
    assert ProgramSource.from_bytes(text, "t.nc").line_number_at(offset) == text[:offset].count(b"\n") + 1


def test_line_numbers_in_a_long_mapped_file(tmp_path):
    """Counted in pieces across a file of a few MiB, from wherever a number is known."""
    lines = [f"G1 X{index}. Y{index % 7}.\n".encode() for index in range(300_000)]
    path = tmp_path / "long.nc"
    path.write_bytes(b"".join(lines))
    source = ProgramSource.open(path)
    assert isinstance(source.buffer, mmap.mmap)
    ends = [0]
    for line in lines:
        ends.append(ends[-1] + len(line))
    for index in (299_999, 1, 150_000, 200_001, 0):
        assert source.line_number_at(ends[index]) == index + 1
    assert source.line_number_at(len(source)) == len(lines) + 1


# Lines as SINUMERIK, Fagor and LinuxCNC programs write the words their whole-text scans look
# for: in code, after a comment's semicolon, twice in a line, in lower case, in longer names.
_SCANNED_LINE = st.lists(st.sampled_from([b"N10 ", b"MCALL CYCLE81", b"mcall sub1", b"; MCALL X", b"M30", b"m2", b"M300", b"M02 ",
                                          b"REPEAT LBL1 P2", b"REPEATB A", b"R1=2 ", b"G0 X1", b"$IF [P1 EQ 1]", b"$ENDIF", b"$ifx",
                                          b"/ $ELSE", b"%L SUB1", b"% l x.y", b"%", b"\t", b"\r", b"o100 sub", b"O<name> SUB", b"O 12",
                                          b"(o1 sub)", b"O1", b"o2 call", b"o100 subx", b"/ N5 O7 sub"]), max_size=5).map(b"".join)
_SCANNED_TEXT = st.lists(_SCANNED_LINE, max_size=12).map(b"\n".join)
_SCANS = (_MODAL_CALL, _PROGRAM_END, _REPEAT_SECTION, (_DOLLAR, _STRUCTURE), (_PERCENT, _SUBROUTINE_HEADER), (_LETTER_O, _SUB),
          (_LETTER_O, _FANUC_PROGRAM))


@settings(max_examples=300, deadline=None)
@given(text=_SCANNED_TEXT, cut=st.tuples(st.floats(0, 1), st.floats(0, 1)))
def test_a_scan_of_the_lines_holding_a_keyword_finds_what_the_line_pattern_finds_everywhere(text, cut):
    """:func:`lines_holding` tries a pattern anchored at line starts on the lines that hold
    its keyword only: the same matches as the pattern's own scan, between any two offsets."""
    start, end = sorted(int(len(text) * fraction) for fraction in cut)
    for keyword, pattern in _SCANS:
        assert [m.span() for m in lines_holding(text, keyword, pattern, start, end)] == [m.span() for m in pattern.finditer(text, start, end)]
        assert [m.span() for m in lines_holding(text, keyword, pattern)] == [m.span() for m in pattern.finditer(text)]


# The tool scans as one pattern each, as they were written before they were made letter-led
# (tried at every byte): the letter-led scans must find what these find.
_ISO_UNSURE = rb"(?<![A-Za-z_#<])[Tt]\s*[-+#\[<]|(?<![A-Za-z])[Mm]\s*0*(?:98|198)(?!\d)|(?<![A-Za-z])[Gg]\s*0*(?:10|65|66)(?!\d)"
_TOOL_SCANS = (  # (letter-led patterns, the one pattern, finds numbers)
    (_TOOL_WORD, re.compile(rb"(?<![A-Za-z_#<])[Tt]\s*(\d+)"), True),
    (IsoFrontend.tool_unsure, re.compile(_ISO_UNSURE), False),
    (LinuxcncFrontend.tool_unsure, re.compile(_ISO_UNSURE + rb"|(?<![A-Za-z])[Mm]\s*0*61(?!\d)"), False),
    (_TOOL_CALL_NUMBER, re.compile(rb"TOOL\s+CALL\s+(\d+)", re.IGNORECASE), True),
    (_OWORD_CALL, re.compile(rb"[Oo]\s*(<[^>]*>|\d+)\s*call", re.IGNORECASE), True),
    (_TOOL_CALL_UNSURE, re.compile(rb"TOOL\s+CALL\s+[\"'Qq]|(?:CALL|SEL)\s+PGM|PGM\s+CALL|\bFN\s*(?:17|26|27|28)\b|TAB(?:OPEN|WRITE)", re.IGNORECASE), False),
)
_TOOL_TEXT = st.lists(st.sampled_from([b"T", b"t", b"M", b"m", b"G", b"g", b"1", b"0", b"6", b"98", b"198", b"10", b"65", b"61", b" ", b"\n", b"#",
                                       b"[", b"<", b"_", b"-", b"x", b"Q", b"'", b"TOOL", b"tool", b"CALL", b"call", b"PGM", b"Sel", b"FN",
                                       b"fn", b"17", b"26", b"TAB", b"open", b"WRITE", b"\"", b"O", b"o", b"<a>", b"CALL "]), max_size=30).map(b"".join)


@settings(max_examples=500, deadline=None)
@given(text=_TOOL_TEXT)
def test_the_letter_led_tool_scans_find_what_one_pattern_finds(text):
    for letter_led, one_pattern, numbers in _TOOL_SCANS:
        assert search_any(text, letter_led) == (one_pattern.search(text) is not None)
        if numbers:
            found = sorted((match.start(), match.group(1)) for match in finditer_all(text, letter_led))
            assert found == [(match.start(), match.group(1)) for match in one_pattern.finditer(text)]
