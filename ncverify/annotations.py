"""``ncverify:`` annotations in program comments: stock, tools, parameter ranges, and
suppressions. One grammar for every dialect, fixed because people write it by hand (extend
it, never change it); keywords are case-insensitive, lengths in the program's units::

    annotation := "ncverify:" ( stock | tool | assume | ignore )
    stock      := "stock" ( "box" "X"a":"b "Y"a":"b "Z"a":"b
                          | "cylinder" "D"d "Z"a":"b
                          | "polygon" point ("," point)+ "Z"a":"b )      point := "X"x "Y"y
    tool       := "tool" (number | '"'name'"') "radius" r { key value }
    assume     := "assume" chain { "and" chain }
    ignore     := "ignore" (rule-id | category) { "," (rule-id | category) }

An ``ignore`` in a comment on a line of its own applies to the next block; at the end of a
block, to that block.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy

from . import ir
from .context import TOOL_KEYS, Assumption, canonical_tool_type, Context, Stock, Tool, tool_value_problem
from .project import parse_assumption
from .source import ProgramSource, Span

_MARKERS = (b"ncverify", b"NCVERIFY", b"Ncverify", b"NCVerify", b"NcVerify")  # byte searches; case variants people write
_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)"
_RANGE = rf"({_NUMBER})\s*:\s*({_NUMBER})"
# pattern texts, compiled (and kept by ``re``) when an annotation first needs them: most
# programs have none or one kind, and compiling all at start-up cost 2 ms of every process
_BOX = rf"(?i)box\s+X\s*{_RANGE}\s+Y\s*{_RANGE}\s+Z\s*{_RANGE}\s*$"
_CYLINDER = rf"(?i)cylinder\s+D\s*({_NUMBER})\s+Z\s*{_RANGE}\s*$"
_POLYGON = rf"(?i)polygon\s+(.*?)\s+Z\s*{_RANGE}\s*$"
_POINT = rf"(?i)^\s*X\s*({_NUMBER})\s+Y\s*({_NUMBER})\s*$"
_TOOL = rf'(?i)tool\s+(?:(\d+)|"([^"]+)")\s+radius\s+({_NUMBER})((?:\s+[A-Za-z-]+\s+\S+)*)\s*$'
_NAME = r"[a-z][a-z0-9-]*(?:\.[a-z0-9-]+)?$"


@dataclass
class Annotations:
    """What a program's ``ncverify:`` comments say."""

    context: Context = field(default_factory=Context)
    suppressions: dict[int, set[str]] = field(default_factory=dict)  # line -> rule ids / categories
    notes: list[ir.Note] = field(default_factory=list)  # malformed annotations


def collect(source: ProgramSource, frontend) -> Annotations:
    """Every annotation in the program's comments, found by its marker."""
    found = Annotations()
    buffer = source.buffer
    seen_lines: set[int] = set()
    for marker in _markers(buffer):
        line_start = buffer.rfind(b"\n", 0, marker) + 1
        if line_start in seen_lines:
            continue
        seen_lines.add(line_start)
        line = source.line_number_at(line_start)
        blocks = frontend.blocks(_raw_line(buffer, line_start), line, None)
        own_line = not any(block.ops or block.label is not None for block in blocks)
        for block in blocks:
            for text, span in block.comments:
                marker_in_comment = re.search(r"(?i)ncverify\s*:", text)
                if marker_in_comment:
                    body = text[marker_in_comment.end():].strip()
                    target = _next_block_line(source, frontend, line_start) if own_line else line
                    _read(body, span, target, found)
    return found


def _markers(buffer) -> list[int]:
    """Where the markers are. Every case variant has a V, in either case, as its third
    byte: the Vs are found with numpy, in pieces of the file read in place (a V is rare in
    a program: two searches for the variants' tails cost three times as much), and the
    bytes around each are then told apart."""
    codes = numpy.frombuffer(buffer, dtype=numpy.uint8)
    found = []
    for start in range(0, len(codes), 1 << 18):
        piece = codes[start : start + (1 << 18)]
        vs = numpy.flatnonzero((piece | 0x20) == ord("v")) + start  # V and v, no other byte
        starts = vs[(codes.take(vs + 1, mode="clip") | 0x20) == ord("e")] - 2  # a V then an E: rarer still
        starts = starts[starts >= 0]
        around = codes.take(starts[:, None] + numpy.arange(8), mode="clip") | 0x20  # each V's marker-long bytes, in lower case
        found.extend(starts[(around == _LOWER_MARKER).all(axis=1)].tolist())
    return [start for start in found if bytes(buffer[start : start + 8]) in _MARKERS]


_LOWER_MARKER = numpy.frombuffer(b"ncverify", dtype=numpy.uint8)


def _raw_line(buffer, start: int) -> bytes:
    end = buffer.find(b"\n", start)
    return bytes(buffer[start : len(buffer) if end < 0 else end]).rstrip(b"\r")


def _next_block_line(source: ProgramSource, frontend, line_start: int) -> int:
    for number, _offset, _next, raw in source.lines_from(line_start):
        if number == source.line_number_at(line_start):
            continue
        if any(block.ops or block.label is not None for block in frontend.blocks(raw, number, None)):
            return number
    return source.line_number_at(line_start)


def _read(body: str, span: Span, target_line: int, found: Annotations) -> None:
    keyword, _, rest = body.partition(" ")
    keyword = keyword.lower()
    try:
        if keyword == "stock":
            found.context.stock = _stock(rest.strip(), span)
        elif keyword == "tool":
            tool = _tool(body, span)
            found.context.tools[tool.number if tool.number is not None else tool.name] = tool
        elif keyword == "assume":
            tree = parse_assumption(rest.strip())
            found.context.assumptions.append(Assumption(rest.strip(), tree, "annotation", span))
        elif keyword == "ignore":
            names = [name.strip().lower() for name in rest.split(",")]
            if not names or not all(re.match(_NAME, name) for name in names):
                raise ValueError("ignore takes rule ids or categories separated by commas")
            found.suppressions.setdefault(target_line, set()).update(names)
        else:
            raise ValueError(f"unknown annotation {keyword!r} (stock, tool, assume or ignore)")
    except (ValueError, SyntaxError) as error:
        message = error.msg if isinstance(error, SyntaxError) else str(error)
        found.notes.append(ir.Note("core.bad-annotation", f"cannot read this ncverify annotation: {message}", span))


def _stock(text: str, span: Span) -> Stock:
    if match := re.match(_BOX, text):
        numbers = [float(value) for value in match.groups()]
        return Stock.box(numbers[0:2], numbers[2:4], numbers[4:6], "annotation", span)
    if match := re.match(_CYLINDER, text):
        diameter, low, high = (float(value) for value in match.groups())
        return Stock.cylinder(diameter, (low, high), "annotation", span)
    if match := re.match(_POLYGON, text):
        points = []
        for part in match.group(1).split(","):
            point = re.match(_POINT, part)
            if not point:
                raise ValueError(f"a polygon point is written X<x> Y<y>, not {part.strip()!r}")
            points.append((float(point.group(1)), float(point.group(2))))
        if len(points) < 3:
            raise ValueError("a stock polygon needs at least three points")
        return Stock.polygon(points, (float(match.group(2)), float(match.group(3))), "annotation", span)
    raise ValueError("stock is: box X<a>:<b> Y<a>:<b> Z<a>:<b> | cylinder D<d> Z<a>:<b> | polygon X<x> Y<y>, ... Z<a>:<b>")


def _tool(text: str, span: Span) -> Tool:
    match = re.match(_TOOL, text)
    if not match:
        raise ValueError('tool is: tool <number or "name"> radius <r> [key value ...]')
    number, name, radius, extra = match.groups()
    tool = Tool(int(number) if number else None, name=name, radius=float(radius), origin="annotation")
    words = extra.split()
    for key, value in zip(words[::2], words[1::2]):
        key = key.lower().replace("-", "_")
        if key == "type":
            tool.type = canonical_tool_type(value)
        elif key in TOOL_KEYS:
            if problem := tool_value_problem(key, float(value)):
                raise ValueError(problem)
            setattr(tool, key, float(value))
        else:
            raise ValueError(f"unknown tool key {key!r} (accepted: type, {', '.join(k.replace('_', '-') for k in TOOL_KEYS)})")
    if problem := tool_value_problem("radius", tool.radius):
        raise ValueError(problem)
    if tool.radius <= 0:
        raise ValueError("the tool radius must be positive")
    return tool
