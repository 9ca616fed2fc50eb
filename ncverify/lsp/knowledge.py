"""What the dialect tables say about the word under the cursor: G/M codes, cycles and
cycle parameters (hover), and the names of positional cycle arguments (inlay hints)."""
from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache

from ..resources import data_dir, read_table
from ..tables import code_key, iso_table

_UNITS = {"length": "mm (inch under inch input)", "feed": "mm/min", "time": "s", "angle": "degrees", "count": "a count", "code": "a code"}
_SINUMERIK_MEANINGS = {"move": "motion", "modal": "modal setting", "comp": "radius compensation", "work_offset": "work offset",
                       "machine_move": "move in machine coordinates", "dwell": "dwell", "reference": "reference point approach",
                       "frame_layer": "programmable frame"}


@cache
def _table(family: str, name: str) -> dict:
    return read_table(data_dir("dialects") / family / name)


@dataclass(frozen=True)
class Argument:
    """One positional argument of a cycle call: its index, its 0-based columns, its text."""

    index: int
    start: int
    end: int
    text: str


@dataclass(frozen=True)
class CycleCall:
    name: str
    start: int  # column of the name
    end: int
    arguments: tuple[Argument, ...]


_CALL = re.compile(r"(?i)\b([A-Z_][A-Z0-9_]*)\s*\(")


def sinumerik_cycles() -> dict[str, dict]:
    return _table("sinumerik", "cycles.toml")["cycle"]


def cycle_calls(line: str) -> list[CycleCall]:
    """The standard-cycle calls of one SINUMERIK line with their positional arguments."""
    calls = []
    code = line.split(";", 1)[0]
    for match in _CALL.finditer(code):
        name = match.group(1).upper()
        if name not in sinumerik_cycles():
            continue
        calls.append(CycleCall(name, match.start(1), match.end(1), tuple(_arguments(code, match.end()))))
    return calls


def _arguments(code: str, position: int) -> list[Argument]:
    """Split the argument list that starts at ``position`` at its top-level commas."""
    arguments, depth, quoted, start = [], 0, False, position
    for index in range(position, len(code) + 1):
        char = code[index] if index < len(code) else ")"
        if char == '"':
            quoted = not quoted
        elif quoted:
            continue
        elif char in "([":
            depth += 1
        elif char in ")]" and depth:
            depth -= 1
        elif char in ",)":
            raw = code[start:index]
            stripped = raw.strip()
            offset = start + (len(raw) - len(raw.lstrip()))
            arguments.append(Argument(len(arguments), offset, offset + len(stripped), stripped))
            start = index + 1
            if char == ")":
                break
    return arguments


def parameter_names(cycle: str) -> list[tuple[str, str]]:
    return [tuple(item) for item in sinumerik_cycles().get(cycle, {}).get("arguments", [])]


# --------------------------------------------------------------------------- hover

def hover_markdown(dialect: str | None, profile: str | None, machine: str | None, lines: list[str], line: int, character: int) -> str | None:
    """Markdown describing what is at 0-based ``line``/``character``, or ``None``. ``lines``
    may keep their line ends."""
    if not 0 <= line < len(lines):
        return None
    text = lines[line].rstrip("\r\n")
    dialect = dialect or "iso"
    if dialect == "sinumerik":
        found = _sinumerik_argument(text, character)
        if found:
            return found
    if dialect == "heidenhain":
        return _heidenhain(lines, line, character)
    word = _word_at(text, character)
    if word is None:
        return None
    letter, number = word
    if letter in "GM":
        return _code(dialect, profile, machine, letter, number)
    if dialect in ("iso", "fagor"):
        return _cycle_letter(dialect, profile, machine, text, letter)
    return None


def _word_at(text: str, character: int) -> tuple[str, str] | None:
    for match in re.finditer(r"(?i)\b([A-Z])\s*([-+]?\d*\.?\d+)", text.split(";", 1)[0]):
        if match.start() <= character <= match.end():
            return match.group(1).upper(), match.group(2)
    return None


def _code(dialect: str, profile: str | None, machine: str | None, letter: str, number: str) -> str | None:
    try:
        key = code_key(float(number))
    except ValueError:
        return None
    if dialect == "iso":
        table = iso_table(profile or "mitsubishi-e60", machine or "mill")
        entry = (table.g if letter == "G" else table.m).get(key)
        where = f"ISO, profile {table.profile}, {table.machine}"
    elif dialect == "fagor":
        entry = _table("fagor", "mill.toml")[letter.lower()].get(key)
        where = "Fagor 8060/8065 mill"
    else:
        entry = _table("sinumerik", "codes.toml").get(letter.lower(), {}).get(key)
        unsupported = _table("sinumerik", "codes.toml").get("unsupported", {}).get(key) if letter == "G" else None
        if unsupported:
            return f"**{letter}{key}**: {unsupported}, not modelled by ncverify (what depends on it is unknown)"
        where = "SINUMERIK 840D"
    if not entry:
        return f"**{letter}{key}**: not in the {where.split(',')[0]} code table of ncverify"
    meaning = entry.get("meaning") or _SINUMERIK_MEANINGS.get(entry.get("effect", ""), entry.get("effect", ""))
    details = [f"group {entry['group']}"] if "group" in entry else []
    details += [f"{name} {entry[name]}" for name in ("kind", "value", "side", "mode") if name in entry]
    cycle = entry.get("cycle")
    text = f"**{letter}{key}**: {meaning}" + (f" ({', '.join(details)})" if details else "") + f"  \n_{where}_"
    if cycle:
        text += "\n\n" + _parameter_table(_cycle_table(dialect).get(cycle, {}).get("params", {}))
    return text


def _cycle_table(dialect: str) -> dict:
    return _table("iso" if dialect == "iso" else dialect, "cycles.toml")["cycle"]


def _parameter_table(params: dict) -> str:
    if not params:
        return ""
    rows = ["| word | meaning | unit |", "|---|---|---|"]
    for name, info in params.items():
        rows.append(f"| {name} | {info.get('meaning', '')}{' (required)' if info.get('required') else ''} | {_UNITS.get(info.get('kind', ''), '')} |")
    return "\n".join(rows)


def _parameter(name: str, info: dict, cycle: str) -> str:
    parts = [f"**{name}** of {cycle}: {info.get('meaning', '')}"]
    if info.get("kind") in _UNITS:
        parts.append(f"unit: {_UNITS[info['kind']]}")
    if "range" in info:
        parts.append(f"range: {info['range']}")
    if "default" in info:
        parts.append(f"default: {info['default']:g}")
    if "allowed" in info:
        parts.append("allowed: " + ", ".join(f"{value:g}" for value in info["allowed"]))
    if info.get("required"):
        parts.append("required")
    return "  \n".join(parts)


def _cycle_letter(dialect: str, profile: str | None, machine: str | None, text: str, letter: str) -> str | None:
    """A letter word in a block that defines a canned cycle: the cycle's parameter."""
    code = text.split(";", 1)[0]
    cycles = [int(found) for found in re.findall(r"(?i)\bG\s*0*(\d+)(?!\.)", code)]
    table = iso_table(profile or "mitsubishi-e60", machine or "mill").g if dialect == "iso" else _table("fagor", "mill.toml")["g"]
    for number in reversed(cycles):
        entry = table.get(str(number), {})
        cycle = entry.get("cycle")
        params = _cycle_table(dialect).get(cycle, {}).get("params", {}) if cycle else {}
        if dialect == "fagor" and letter not in params and "Z" in params and letter in "XYZ":
            letter = "Z"  # the tool-axis word is the reference plane
        if letter in params:
            return _parameter(letter, params[letter], f"G{number} ({entry.get('meaning', '')})")
    return None


def _sinumerik_argument(text: str, character: int) -> str | None:
    for call in cycle_calls(text):
        cycle = sinumerik_cycles()[call.name]
        if call.start <= character <= call.end:
            names = ", ".join(name for name, _ in parameter_names(call.name))
            return f"**{call.name}**: {cycle.get('name', '')}  \nparameters: {names}"
        for argument in call.arguments:
            if argument.start <= character <= max(argument.end, argument.start + 1):
                names = parameter_names(call.name)
                if argument.index >= len(names):
                    return f"argument {argument.index + 1} of {call.name}: more than the {len(names)} the cycle defines (alarm 12340)"
                name, kind = names[argument.index]
                return f"**{name}** ({kind}): argument {argument.index + 1} of {call.name} ({cycle.get('name', '')})"
    return None


_CYCL_DEF = re.compile(r"(?i)\bCYCL\s+DEF\s+(\d+)")
_Q_WORD = re.compile(r"(?i)\bQ(\d+)\s*=")


def _heidenhain(lines: list[str], line: int, character: int) -> str | None:
    text = lines[line].rstrip("\r\n")
    definition = _CYCL_DEF.search(text)
    if definition and definition.start() <= character <= definition.end() + 40:
        cycle = _cycle_table("heidenhain").get(f"heidenhain.{definition.group(1)}")
        if cycle:
            return f"**cycle {definition.group(1)} {cycle.get('name', '')}**\n\n" + _parameter_table(cycle.get("params", {}))
    for match in _Q_WORD.finditer(text):
        if match.start() <= character <= match.end():
            number = _cycle_in_force(lines, line)
            if number is None:
                return None
            info = _cycle_table("heidenhain").get(f"heidenhain.{number}", {}).get("params", {}).get(f"Q{match.group(1)}")
            return _parameter(f"Q{match.group(1)}", info, f"cycle {number}") if info else None
    return None


def _cycle_in_force(lines: list[str], line: int) -> str | None:
    """The cycle a ``Q2xx=`` line belongs to: the CYCL DEF this block continues."""
    for index in range(line, max(line - 60, -1), -1):
        found = _CYCL_DEF.search(lines[index])
        if found:
            return found.group(1)
        if index < line and not lines[index].lstrip().lstrip("0123456789 ").startswith(("Q", "~")):
            return None
    return None
