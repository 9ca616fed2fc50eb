"""Reader for the ISO family (Fanuc-style, Mitsubishi E60/M60, Haas): text to blocks of words.

A line holds one or more blocks (``;`` ends a block); ``( )`` comments may sit anywhere
between words. Most CAM output is plain words (``N120 G1 X10.5 Y-3 F800``): those blocks
take a regex fast path and never build a lark tree. Everything else - macro statements,
expressions, comma words, a bare ``G``, block skip - goes through the lark grammar in
``dialects/iso/block.lark``. Both paths produce the same :class:`ReadBlock`, which a
property test checks.
"""
from __future__ import annotations

import re

from .iso_blocks import ReadBlock, Statement, SyntaxProblem, Word  # noqa: F401  (re-exported: what this reader hands back)


_UPPER = str.maketrans("abcdefghijklmnopqrstuvwxyz", "ABCDEFGHIJKLMNOPQRSTUVWXYZ")
_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)"
_PLAIN_CODE = re.compile(rf"[ \t]*(?:[A-Z][ \t]*{_NUMBER}[ \t]*)*")
_PLAIN_WORD = re.compile(rf"([A-Z])[ \t]*({_NUMBER})")
_COMMENT = re.compile(r"\([^)]*\)")
# Macro output to a port (Fanuc macro B, Haas): DPRNT[..] / BPRNT[..] print, POPEN / PCLOS open and close the port
_OUTPUT_STATEMENT = re.compile(r"[ \t]*(?:(N[ \t]*\d+)[ \t]*)?(?:[DB]PRNT[ \t]*\[[^\n]*\]|POPEN|PCLOS)[ \t]*")
# A line of a CNC simulator's or editor's own ($Inches, $AddRegPart, #region): not G-code.
_DIRECTIVE = re.compile(r"\$[A-Z]|#[A-Z]")
# After ';' (end of block), prose rather than words is a comment (Mastercam, Mach3 posts):
# a lower-case letter, or a word of several letters that is no macro keyword.
_FREE_TEXT = re.compile(r"[^;(]*[a-z]|\s*(?!(?:IF|GOTO|WHILE|WH|END|DO|THEN)(?![A-Za-z]))[A-Za-z]{2,}")


def read_line(text: str, line: int, force_grammar: bool = False) -> list[ReadBlock]:
    """Read one decoded line into its blocks."""
    code = text.translate(_UPPER)
    stripped = code.strip()
    if not stripped:
        return []
    if _DIRECTIVE.match(stripped):
        start = code.index(stripped[0])
        return [ReadBlock(line, start, start + len(stripped), [], directive=text.strip())]
    if stripped.startswith("%"):
        start = code.index("%")
        rest = code[start + 1 :]
        blocks = [ReadBlock(line, start, start + 1, [], percent=True)]
        if rest.strip():
            blocks += read_line(" " * (start + 1) + text[start + 1 :], line, force_grammar)
        return blocks
    if "(" not in code and ";" not in code and ")" not in code:
        return [_read_block(code, text, line, 0, len(code), (), force_grammar)]
    return _read_segments(code, text, line, force_grammar)


def _read_segments(code: str, text: str, line: int, force_grammar: bool) -> list[ReadBlock]:
    """Split a line at ';' outside comments and collect its comments."""
    blocks = []
    comments: list = []
    segment_start = 0
    position = 0
    length = len(code)
    while position < length:
        char = code[position]
        if char == "(":
            close = code.find(")", position + 1)
            if close < 0:
                block = _read_block(code, text, line, segment_start, position, comments, force_grammar)
                block.end = length
                block.problem = block.problem or SyntaxProblem(
                    "comment is not closed: '(' has no ')' before the end of the line", position, length
                )
                blocks.append(block)
                return blocks
            comments.append((text[position + 1 : close], position, close + 1))
            position = close + 1
            continue
        if char == ")":
            block = _read_block(code, text, line, segment_start, length, comments, force_grammar)
            block.problem = block.problem or SyntaxProblem("')' without an opening '('", position, position + 1)
            blocks.append(block)
            return blocks
        if char == ";":
            if code[segment_start:position].strip() or comments:
                blocks.append(_read_block(code, text, line, segment_start, position, comments, force_grammar))
            comments = []
            segment_start = position + 1
            if _FREE_TEXT.match(text, segment_start):
                blocks.append(ReadBlock(line, position, length, [], [(text[segment_start:].strip(), position, length)]))
                return blocks
        position += 1
    if code[segment_start:].strip() or comments:
        blocks.append(_read_block(code, text, line, segment_start, length, comments, force_grammar))
    return blocks


def _read_block(code, text, line, start, end, comments, force_grammar) -> ReadBlock:
    segment = code[start:end]
    if comments:
        for _, comment_start, comment_end in comments:
            if start <= comment_start < end:
                offset = comment_start - start
                segment = segment[:offset] + " " * (comment_end - comment_start) + segment[offset + comment_end - comment_start :]
    content = segment.strip()
    first = start + (len(segment) - len(segment.lstrip()))
    last = start + len(segment.rstrip())
    if not content:
        first, last = (comments[0][1], comments[-1][2]) if comments else (start, end)
    block = ReadBlock(line, first, last, [], list(comments))
    output = _OUTPUT_STATEMENT.fullmatch(segment)
    if output is not None:  # macro output (DPRNT, BPRNT, POPEN, PCLOS): data to a port, no machine state
        if output.group(1) is not None:
            block.items = [Word("N", float(output.group(1)[1:]), False, start + output.start(1), start + output.end(1))]
        return block
    if not force_grammar and _PLAIN_CODE.fullmatch(segment):
        block.items = [
            Word(match.group(1), float(match.group(2)), "." in match.group(2), match.start() + start, match.end() + start)
            for match in _PLAIN_WORD.finditer(segment)
        ]
        return block
    from .iso_grammar import parse_with_grammar  # lark costs 60 ms to import: only programs that need it pay

    parse_with_grammar(block, segment, start)
    return block
