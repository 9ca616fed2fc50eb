"""Program text as the checker sees it: a byte buffer read line by line from any offset.

Programs are read as bytes so that the interpreter can jump (GOTO, M98, WHILE) by byte
offset without keeping decoded lines in memory; straight-line code is streamed. Columns
are counted in characters of the decoded line, 1-based, end exclusive, as the JSON
contract says.
"""
from __future__ import annotations

import heapq
import mmap
import re
from pathlib import Path
from typing import NamedTuple

import numpy

from .dependencies import note_file


class Span(NamedTuple):
    """A 1-based source range; ``end_column`` is exclusive. ``path`` is set only when the
    span lies in another file than the one being checked (a subprogram file). A tuple,
    because millions are made on the hot path."""

    line: int
    column: int
    end_line: int
    end_column: int
    path: str | None = None

    @classmethod
    def on_line(cls, line: int, start: int, end: int, path: str | None = None) -> "Span":
        """Span of characters ``start:end`` (0-based, end exclusive) of one line."""
        return cls(line, start + 1, line, end + 1, path)

    def cover(self, other: "Span") -> "Span":
        """The smallest span holding both (same file assumed)."""
        first = min((self.line, self.column), (other.line, other.column))
        last = max((self.end_line, self.end_column), (other.end_line, other.end_column))
        return Span(first[0], first[1], last[0], last[1], self.path)


def decode_line(raw: bytes) -> str:
    """Decode one line; programs are UTF-8 or a legacy 8-bit code page, comments may be
    Chinese. Undecodable bytes become U+FFFD so that columns stay meaningful."""
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("utf-8", errors="replace")


_UTF8_BOM = b"\xef\xbb\xbf"
_UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")
_LONE_CR = re.compile(rb"\r(?!\n)")


def normalise(buffer: bytes | mmap.mmap) -> bytes | mmap.mmap:
    """The bytes every reader sees: a UTF-8 byte-order mark dropped, UTF-16 with a
    byte-order mark re-encoded as UTF-8, lone-CR and mixed line ends turned into LF, and
    tabs into spaces (one character for one, so columns do not move). CRLF is left as it
    is (every reader strips the CR), so the usual file is not copied."""
    head = bytes(buffer[:3])
    if head.startswith(_UTF16_BOMS):
        buffer = bytes(buffer).decode("utf-16", errors="replace").encode("utf-8")
    elif head == _UTF8_BOM:
        buffer = bytes(buffer[3:])
    if buffer.find(b"\r") >= 0 and _LONE_CR.search(buffer):
        buffer = _LONE_CR.sub(b"\n", bytes(buffer).replace(b"\r\n", b"\n"))
    if buffer.find(b"\t") >= 0:
        buffer = bytes(buffer).replace(b"\t", b" ")
    return buffer


def find_all(buffer, needles: tuple[bytes, ...], start: int = 0):
    """Offsets of every occurrence of any of ``needles``, in order. Byte searches run at
    memchr speed, where a regex with a character class would test every position."""
    found = []
    for needle in needles:
        position = buffer.find(needle, start)
        while position >= 0:
            found.append(position)
            position = buffer.find(needle, position + 1)
    return sorted(set(found))


def line_start(buffer, offset: int) -> int:
    return buffer.rfind(b"\n", 0, offset) + 1


def lines_holding(buffer, keyword, line_pattern: re.Pattern, start: int = 0, end: int | None = None):
    """The matches of ``line_pattern``, a pattern anchored at line starts (``(?m)^...``, one
    match a line at most, none across a line end), as its ``finditer`` over ``buffer[start:end]``
    gives them, tried only on the lines that hold ``keyword``, which every matching line holds.
    A pattern such as ``^[^;\\n]*\\bMCALL`` backtracks along every line of the text, where a
    search for its keyword alone runs several times faster: on a long program the scan took
    a tenth of the check. ``keyword``: a pattern, or several (:func:`letter_led`'s), any of
    which the line holds."""
    end = len(buffer) if end is None else end
    keywords = keyword if isinstance(keyword, tuple) else (keyword,)
    tried = -1
    for found in heapq.merge(*(pattern.finditer(buffer, start, end) for pattern in keywords), key=_start):
        begin = max(line_start(buffer, found.start()), start)
        if begin == tried:
            continue  # the keyword twice in one line
        tried = begin
        match = line_pattern.match(buffer, begin, end)
        if match is not None:
            yield match


def _start(match: re.Match) -> int:
    return match.start()


def letter_led(*words: bytes) -> tuple[re.Pattern, ...]:
    """The patterns ``words``, each starting with a letter and matched in either case, made
    for a scan of the whole text: each becomes two patterns that start with its letter as
    a plain byte, upper and lower case, the rest matched in either case. Python's ``re``
    finds a pattern's literal first byte by a byte search and tries the rest only there; a
    pattern that starts with a class, an alternation or a lookbehind, or any under
    IGNORECASE, is tried at every byte: on a CAM program of 200,000 lines a third of a
    second a scan, where these take a few milliseconds. A lookbehind goes after the
    letter and takes it in (``T(?<![A-Z]T)``)."""
    return tuple(re.compile(re.escape(case) + b"(?i:" + word[1:] + b")") for word in words for case in (word[:1].upper(), word[:1].lower()))


def search_any(buffer, patterns) -> bool:
    """Does any of ``patterns`` occur in ``buffer``?"""
    return any(pattern.search(buffer) is not None for pattern in patterns)


def finditer_all(buffer, patterns):
    """Every match of each of ``patterns`` in ``buffer``, pattern after pattern."""
    for pattern in patterns:
        yield from pattern.finditer(buffer)


def _count_newlines(buffer, start: int, end: int) -> int:
    """Line ends between the offsets, counted on the buffer in place (a slice of an mmap
    is a copy: faulting its fresh pages in cost six times the count), in pieces whose
    scratch arrays the allocator keeps."""
    codes = numpy.frombuffer(buffer, dtype=numpy.uint8)
    count = 0
    while start < end:
        stop = min(start + (1 << 18), end)
        count += int(numpy.count_nonzero(codes[start:stop] == _NEWLINE))
        start = stop
    return count


_NEWLINE = ord("\n")


class ProgramSource:
    """One program file's bytes, addressed by byte offset.

    ``buffer`` is an mmap for files on disk and bytes for text handed in by the API or
    stdin, so a long file is never copied into Python objects whole.
    """

    def __init__(self, buffer: bytes | mmap.mmap, name: str, path: Path | None = None):
        self.buffer = normalise(buffer)
        self.name = name
        self.path = path
        self._line_cache: dict[int, int] = {0: 1}

    @classmethod
    def from_text(cls, text: str, name: str = "<text>") -> "ProgramSource":
        return cls(text.encode("utf-8"), name)

    @classmethod
    def from_bytes(cls, data: bytes, name: str) -> "ProgramSource":
        return cls(data, name)

    @classmethod
    def open(cls, path: Path) -> "ProgramSource":
        note_file(path)
        with path.open("rb") as handle:
            size = path.stat().st_size
            if size == 0:
                return cls(b"", str(path), path)
            buffer = mmap.mmap(handle.fileno(), 0, access=mmap.ACCESS_READ)
        return cls(buffer, str(path), path)

    def __len__(self) -> int:
        return len(self.buffer)

    def line_number_at(self, offset: int) -> int:
        """1-based line number of the line starting at ``offset``, counted from the
        nearest offset already known below it (memoised)."""
        cached = self._line_cache.get(offset)
        if cached is None:
            known = max((start for start in self._line_cache if start <= offset), default=0)
            cached = self._line_cache.get(known, 1) + _count_newlines(self.buffer, known, offset)
            if len(self._line_cache) < 10_000:
                self._line_cache[offset] = cached
        return cached

    def lines_from(self, offset: int = 0, line_number: int | None = None):
        """Yield ``(line_number, start_offset, next_offset, raw_bytes)`` from ``offset`` on.

        Line ends are LF or CRLF (``normalise`` turned lone CRs into LF); the yielded
        bytes exclude them.
        """
        buffer = self.buffer
        size = len(buffer)
        number = self.line_number_at(offset) if line_number is None else line_number
        find = buffer.find
        while offset < size:
            newline = find(b"\n", offset)
            end = size if newline < 0 else newline
            raw = buffer[offset:end]
            next_offset = end + 1
            if raw.endswith(b"\r"):
                raw = raw[:-1]
            yield number, offset, next_offset, raw
            number += 1
            offset = next_offset

    def head(self, size: int = 65536) -> str:
        return decode_line(bytes(self.buffer[:size]))
