"""Where things are in a program: programs, subprograms, labels, sequence numbers, tool
calls and cycle definitions (document symbols), the jumps and calls that name them (go to
definition, references) and the ranges an editor can fold (subprograms, loops).

Read from the text line by line with each dialect's forms, so it works on a program that
does not run, while the user is typing it.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from lsprotocol import types


@dataclass(frozen=True)
class Place:
    line: int  # 0-based
    start: int
    end: int

    def range(self) -> types.Range:
        return types.Range(start=types.Position(line=self.line, character=self.start), end=types.Position(line=self.line, character=self.end))


@dataclass
class Symbol:
    name: str
    kind: types.SymbolKind
    place: Place
    last_line: int  # where the symbol's body ends (its own line for a single block)


@dataclass
class Outline:
    definitions: dict[str, list[Place]] = field(default_factory=dict)
    references: dict[str, list[Place]] = field(default_factory=dict)
    symbols: list[Symbol] = field(default_factory=list)
    folds: list[tuple[int, int]] = field(default_factory=list)

    def define(self, key: str, place: Place) -> None:
        self.definitions.setdefault(key, []).append(place)

    def refer(self, key: str, place: Place) -> None:
        self.references.setdefault(key, []).append(place)

    def key_at(self, line: int, character: int) -> str | None:
        for table in (self.references, self.definitions):
            for key, places in table.items():
                if any(p.line == line and p.start <= character <= p.end for p in places):
                    return key
        return None


def _blank_comments(text: str) -> str:
    """The line with its comments replaced by spaces, so that columns stay where they are."""
    code = re.sub(r"\((?!\s*RPT\b)[^)]*\)?", lambda m: " " * len(m.group()), text)  # Fagor's (RPT ..) is code
    semicolon = code.find(";")
    return code if semicolon < 0 else code[:semicolon] + " " * (len(code) - semicolon)


def outline(lines: list[str], dialect: str | None) -> Outline:
    reader = {"heidenhain": _heidenhain, "sinumerik": _sinumerik, "fagor": _fagor}.get(dialect or "iso", _iso)
    found = Outline()
    reader([_blank_comments(line) for line in lines], found)
    return found


def _place(line: int, match: re.Match, group: int = 0) -> Place:
    return Place(line, match.start(group), match.end(group))


def _number_key(prefix: str, digits: str) -> str:
    return f"{prefix}{int(float(digits))}"


def _close_blocks(found: Outline, openers: list, line: int, kinds: set[str]) -> None:
    """Fold from the innermost open block of one of ``kinds`` to ``line``."""
    for index in range(len(openers) - 1, -1, -1):
        kind, start = openers[index]
        if kind in kinds:
            del openers[index:]
            if line > start:
                found.folds.append((start, line))
            return


def _end_program(found: Outline, program: Symbol | None, line: int) -> None:
    if program is not None:
        program.last_line = line
        if line > program.place.line:
            found.folds.append((program.place.line, line))


# --------------------------------------------------------------------------- ISO and Fagor

_N = re.compile(r"(?i)^\s*/?\s*N\s*(\d+)")
_O = re.compile(r"(?i)^\s*%?\s*(?:N\d+\s*)?O\s*(\d+)")
_GOTO = re.compile(r"(?i)\bGOTO\s*(\d+)")
_CALL_PROGRAM = re.compile(r"(?i)\b(?:M\s*98|G\s*65|G\s*66)\b[^P]*?P\s*(\d+)")
_CALL_LOCAL = re.compile(r"(?i)\b(?:M\s*97|M\s*99)\b[^P]*?P\s*(\d+)")
_SHAPE = re.compile(r"(?i)\b([PQ])\s*(\d+)")
_SHAPE_CYCLE = re.compile(r"(?i)\bG\s*7[0-3](?!\d)")
_WHILE = re.compile(r"(?i)\bDO\s*(\d+)")
_END = re.compile(r"(?i)\bEND\s*(\d+)")
_TOOL = re.compile(r"(?i)\bT\s*(\d+)")
_TOOL_CHANGE = re.compile(r"(?i)\bM\s*0*6(?!\d)")
_ISO_CYCLE = re.compile(r"(?i)\bG\s*0*(7[346]|8[1-9])(?![\d.])")
_PROGRAM_END = re.compile(r"(?i)\bM\s*(?:0*2|30|99)(?!\d)")


def _iso(lines: list[str], found: Outline) -> None:
    program: Symbol | None = None
    loops: list = []
    for number, code in enumerate(lines):
        if match := _O.match(code):
            _end_program(found, program, number - 1)
            program = Symbol(f"O{int(match.group(1))}", types.SymbolKind.Module, _place(number, match), number)
            found.symbols.append(program)
            found.define(_number_key("O", match.group(1)), _place(number, match))
        _sequence_and_tools(number, code, found, _ISO_CYCLE)
        for match in _GOTO.finditer(code):
            found.refer(_number_key("N", match.group(1)), _place(number, match))
        for match in _CALL_PROGRAM.finditer(code):
            found.refer(_number_key("O", match.group(1)), _place(number, match))
        for match in _CALL_LOCAL.finditer(code):
            found.refer(_number_key("N", match.group(1)), _place(number, match))
        if _SHAPE_CYCLE.search(code):
            for match in _SHAPE.finditer(code):
                found.refer(_number_key("N", match.group(2)), _place(number, match))
        for match in _WHILE.finditer(code):
            loops.append((f"DO{match.group(1)}", number))
        for match in _END.finditer(code):
            _close_blocks(found, loops, number, {f"DO{match.group(1)}"})
        if program is not None and _PROGRAM_END.search(code):
            _end_program(found, program, number)
            program = None


def _sequence_and_tools(number: int, code: str, found: Outline, cycle: re.Pattern) -> None:
    if match := _N.match(code):
        found.define(_number_key("N", match.group(1)), _place(number, match))
        found.symbols.append(Symbol(f"N{int(match.group(1))}", types.SymbolKind.Key, _place(number, match), number))
    if _TOOL_CHANGE.search(code) and (match := _TOOL.search(code)):
        found.symbols.append(Symbol(f"tool T{int(match.group(1))}", types.SymbolKind.Object, _place(number, match), number))
    if match := cycle.search(code):
        found.symbols.append(Symbol(f"cycle G{match.group(1)}", types.SymbolKind.Function, _place(number, match), number))


_FAGOR_SUB = re.compile(r"(?i)^\s*%L\s+([A-Z0-9_]+)")
_FAGOR_CALL = re.compile(r"(?i)#(?:P?CALL|MCALL|LOCAL)\s+\"?([A-Z0-9_.]+)")
_FAGOR_GOTO = re.compile(r"(?i)\$GOTO\s+N\s*(\d+)")
_FAGOR_RPT = re.compile(r"(?i)\$?RPT\s+N\s*(\d+)\s*,\s*N\s*(\d+)")
_FAGOR_OPEN = re.compile(r"(?i)\$(IF|WHILE|FOR|DO|SWITCH)\b")
_FAGOR_CLOSE = re.compile(r"(?i)\$(ENDIF|ENDWHILE|ENDFOR|ENDDO|ENDSWITCH)\b")
_FAGOR_CYCLE = re.compile(r"(?i)\bG\s*0*(8[1-9]|16[0-5]|21[0-2])(?![\d.])")
_FAGOR_PAIRS = {"ENDIF": "IF", "ENDWHILE": "WHILE", "ENDFOR": "FOR", "ENDDO": "DO", "ENDSWITCH": "SWITCH"}
_FAGOR_RETURN = re.compile(r"(?i)\bM\s*(?:0*2|30|17|29)(?!\d)|\$RET\b")


def _fagor(lines: list[str], found: Outline) -> None:
    program: Symbol | None = None
    blocks: list = []
    for number, code in enumerate(lines):
        if match := _FAGOR_SUB.match(code):
            _end_program(found, program, number - 1)
            program = Symbol(match.group(1), types.SymbolKind.Function, _place(number, match, 1), number)
            found.symbols.append(program)
            found.define(f"PGM:{match.group(1).upper()}", _place(number, match, 1))
        _sequence_and_tools(number, code, found, _FAGOR_CYCLE)
        for match in _FAGOR_CALL.finditer(code):
            found.refer(f"PGM:{match.group(1).upper()}", _place(number, match, 1))
        for match in _FAGOR_GOTO.finditer(code):
            found.refer(_number_key("N", match.group(1)), _place(number, match))
        for match in _FAGOR_RPT.finditer(code):
            found.refer(_number_key("N", match.group(1)), _place(number, match))
            found.refer(_number_key("N", match.group(2)), _place(number, match))
        for match in _FAGOR_OPEN.finditer(code):
            blocks.append((match.group(1).upper(), number))
        for match in _FAGOR_CLOSE.finditer(code):
            _close_blocks(found, blocks, number, {_FAGOR_PAIRS[match.group(1).upper()]})
        if program is not None and _FAGOR_RETURN.search(code):
            _end_program(found, program, number)
            program = None


# --------------------------------------------------------------------------- HEIDENHAIN

_BEGIN_PGM = re.compile(r"(?i)\bBEGIN\s+PGM\s+([^\s]+)")
_END_PGM = re.compile(r"(?i)\bEND\s+PGM\b")
_LBL = re.compile(r"(?i)(?<!CALL )(?<!GOTO )\bLBL\s+(\"[^\"]*\"|\d+)")
_CALL_LBL = re.compile(r"(?i)\b(?:CALL|GOTO)\s+LBL\s+(\"[^\"]*\"|\d+)")
_CALL_PGM = re.compile(r"(?i)\bCALL\s+PGM\s+([^\s;]+)")
_TOOL_CALL = re.compile(r"(?i)\bTOOL\s+CALL\s+(\"[^\"]*\"|\d+)")
_CYCLE_DEF = re.compile(r"(?i)\bCYCL\s+DEF\s+([\d.]+(?:\s+[A-Z][A-Z\s-]*)?)")


def _label_key(text: str) -> str:
    return "LBL:" + text.strip('"').upper()


def _program_key(text: str) -> str:
    name = text.strip('"').replace("\\", "/").rsplit("/", 1)[-1]
    return "PGM:" + name.rsplit(".", 1)[0].upper()


def _heidenhain(lines: list[str], found: Outline) -> None:
    program: Symbol | None = None
    label: Symbol | None = None
    for number, code in enumerate(lines):
        if match := _BEGIN_PGM.search(code):
            program = Symbol(match.group(1), types.SymbolKind.Module, _place(number, match, 1), number)
            found.symbols.append(program)
            found.define(_program_key(match.group(1)), _place(number, match, 1))
        for match in _CALL_LBL.finditer(code):
            found.refer(_label_key(match.group(1)), _place(number, match, 1))
        for match in _LBL.finditer(code):
            if _CALL_LBL.search(code[max(match.start() - 10, 0):match.end()]):
                continue
            if label is not None:
                _end_program(found, label, number - 1 if match.group(1) != "0" else number)
                label = None
            if match.group(1) != "0":
                label = Symbol(f"LBL {match.group(1)}", types.SymbolKind.Function, _place(number, match, 1), number)
                found.symbols.append(label)
                found.define(_label_key(match.group(1)), _place(number, match, 1))
        for match in _CALL_PGM.finditer(code):
            found.refer(_program_key(match.group(1)), _place(number, match, 1))
        if match := _TOOL_CALL.search(code):
            found.symbols.append(Symbol(f"TOOL CALL {match.group(1)}", types.SymbolKind.Object, _place(number, match), number))
        if match := _CYCLE_DEF.search(code):
            found.symbols.append(Symbol(f"CYCL DEF {match.group(1).strip()}", types.SymbolKind.Function, _place(number, match), number))
        if _END_PGM.search(code):
            _end_program(found, label, number - 1)
            label = None
            _end_program(found, program, number)
            program = None


# --------------------------------------------------------------------------- SINUMERIK

_SIN_LABEL = re.compile(r"(?i)^\s*(?:N\d+\s+)?([A-Z_][A-Z0-9_]*):(?!=)")
_SIN_GOTO = re.compile(r"(?i)\bGOTO[FBC]?\s+([A-Z_][A-Z0-9_]*)")
_SIN_PROC = re.compile(r"(?i)\bPROC\s+([A-Z_][A-Z0-9_]*)")
_SIN_CALL = re.compile(r"(?i)^\s*(?:N\d+\s+)?(?:MCALL\s+|CALL\s+)?\"?([A-Z_][A-Z0-9_]*)\"?\s*(?:\(|$|;)")
_SIN_OPEN = re.compile(r"(?i)^\s*(?:N\d+\s+)?(IF|WHILE|FOR|REPEAT|LOOP|CASE)\b")
_SIN_CLOSE = re.compile(r"(?i)^\s*(?:N\d+\s+)?(ENDIF|ENDWHILE|ENDFOR|UNTIL|ENDLOOP|ENDCASE)\b")
_SIN_PAIRS = {"ENDIF": "IF", "ENDWHILE": "WHILE", "ENDFOR": "FOR", "UNTIL": "REPEAT", "ENDLOOP": "LOOP", "ENDCASE": "CASE"}
_SIN_TOOL = re.compile(r"(?i)\bT\s*=?\s*(\"[^\"]*\"|\d+)")
_SIN_KEYWORDS = {"IF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "FOR", "ENDFOR", "REPEAT", "UNTIL", "LOOP", "ENDLOOP", "CASE",
                 "ENDCASE", "RET", "M17", "M30", "M2", "DEF", "PROC", "MCALL", "STOPRE", "G0", "G1", "G40", "G90", "G91",
                 "G17", "G18", "G19", "G54", "G500", "M3", "M4", "M5", "M6", "M8", "M9", "DIAMON", "DIAMOF", "TRANS", "ROT",
                 "SCALE", "MIRROR", "CYCLE800", "WORKPIECE", "ENDPROC", "GOTOF", "GOTOB", "GOTO"}


def _sinumerik(lines: list[str], found: Outline) -> None:
    from .knowledge import cycle_calls

    blocks: list = []
    for number, code in enumerate(lines):
        if match := _SIN_PROC.search(code):
            found.symbols.append(Symbol(match.group(1), types.SymbolKind.Function, _place(number, match, 1), len(lines) - 1))
            found.define(f"PGM:{match.group(1).upper()}", _place(number, match, 1))
        if match := _SIN_LABEL.match(code):
            found.define(f"LBL:{match.group(1).upper()}", _place(number, match, 1))
            found.symbols.append(Symbol(match.group(1), types.SymbolKind.Key, _place(number, match, 1), number))
        for match in _SIN_GOTO.finditer(code):
            found.refer(f"LBL:{match.group(1).upper()}", _place(number, match, 1))
        match = _SIN_CALL.match(code)
        if match and match.group(1).upper() not in _SIN_KEYWORDS and not cycle_calls(code) and not re.fullmatch(r"(?i)[A-Z]\d*", match.group(1)):
            found.refer(f"PGM:{match.group(1).upper()}", _place(number, match, 1))
        for call in cycle_calls(code):
            found.symbols.append(Symbol(call.name, types.SymbolKind.Function, Place(number, call.start, call.end), number))
        if match := _SIN_TOOL.search(code):
            found.symbols.append(Symbol(f"tool T{match.group(1)}", types.SymbolKind.Object, _place(number, match), number))
        if match := _SIN_OPEN.match(code):
            blocks.append((match.group(1).upper(), number))
        if match := _SIN_CLOSE.match(code):
            _close_blocks(found, blocks, number, {_SIN_PAIRS[match.group(1).upper()]})
