"""The Klartext special cycles when the interpreter reaches them (reference B 6.3, 6.30-6.38):
224 DataMatrix pattern, 225 engraving, 232 face milling, 18 thread cutting, 12 program call,
238/239 (the machine moves its axes itself), the points of a point table (``SEL PATTERN``),
and the M functions rules watch (M94, M136/M137).

What these cycles do in the working plane (the cells of a code, the strokes of a text, the
passes of a face) is not traced: the plane position becomes unknown, and the tool-axis
moves, which the rapid and stock rules need, are made here.
"""
from __future__ import annotations

import re
from pathlib import Path

from ... import ir
from . import common
from ...dependencies import note_file
from ...trace import CycleRun

# One printed character of an engraving text: an escape (%% %ae %time08 %count9 \\ \t) or a
# plain character (reference B 6.34).
_CHARACTER = re.compile(r"%(?:%|[A-Za-z]+\d*)|\\.|.", re.S)


def engraved_characters(text: str) -> int:
    """Characters of the longest line of an engraving text (``\\n`` starts a new line)."""
    return max(len(_CHARACTER.findall(line)) for line in text.split("\\n"))


def _observe(runner, op, block, definition, params, extra: dict | None = None) -> None:
    numbers = common.numbers(params)
    numbers.update(extra or {})
    runner.report_cycle(CycleRun(f"heidenhain.{definition.number}", definition.model, op.span, block, numbers, dict(definition.spans)))


def datamatrix(runner, op, block) -> None:
    """Cycle 224 runs the last machining cycle at every dark cell of the code of QS501. Which
    cells are dark is not computed, so the holes are not placed and the tool ends somewhere
    on the code at the 2nd set-up clearance (seed L8675-8702)."""
    state = runner.state
    if state.klartext.cycle is None:
        runner.fault("heidenhain.call-without-cycle", op.span, "cycle 224 runs the last machining cycle at the cells of its code, but no machining cycle is defined before it")
    runner.fault("core.unsupported-code", op.span, "cycle 224's cells come from the DataMatrix code of its text, which is not computed: the holes it machines "
                  "are not placed and the position after it is unknown", "unknown", "cycle 224")
    state.move_to(dict.fromkeys(state.position))


def engrave(runner, op, block, definition, shift, surface_offset) -> None:
    """Cycle 225: up to the 2nd set-up clearance when the tool is below it, over the first
    character (not computed: the plane position becomes unknown), in to Q203 + Q201, out to
    Q203 + Q200 after each character, and to the 2nd set-up clearance at the end. Depth 0:
    not executed."""
    state = runner.state
    params = dict(definition.params)
    common.offset_surface(params, shift, surface_offset)
    text = params.get("QS500")
    _observe(runner, op, block, definition, params, {"text_characters": float(engraved_characters(text))} if isinstance(text, str) else None)
    found = common.levels(params)
    if params.get("Q201") == 0.0:
        return None
    first, second, axis = common.plane(state)
    if found is None:
        state.move_to(dict.fromkeys(state.position))
        return None
    set_up, bottom, retract, _direction = found
    name = f"heidenhain.{definition.number}"
    here = state.position.get(axis)
    if here is None or (type(here) is float and type(retract) is float and here < retract):
        runner.move_to({axis: retract}, op.span, block, "retract", name)
    state.move_to({first: None, second: None})
    runner.move_to({axis: set_up}, op.span, block, "approach", name)
    with common.cycle_feed(state, params):
        runner.move_to({axis: bottom}, op.span, block, "infeed", name, "feed")
    runner.move_to({axis: set_up}, op.span, block, "out-of-hole", name)
    runner.move_to({axis: retract}, op.span, block, "retract", name)
    return None


def face_milling(runner, op, block, definition, shift, surface_offset) -> None:
    """Cycle 232: to the 2nd set-up clearance Q227 + Q204 (up first when lower), to the
    start point R + Q357 before the surface edge (where the rule on the blank judges it),
    down at Q253, the passes at Q207 down to Q386, FMAX up to the 2nd set-up clearance.
    Q227 = Q386: not run; Q227 < Q386: the control stops with an error (L15655-15659)."""
    state = runner.state
    params = dict(definition.params)
    _observe(runner, op, block, definition, params)
    first, second, axis = common.plane(state)
    start, end = params.get("Q227"), params.get("Q386")
    clearance, second_clearance = params.get("Q200", 0.0), params.get("Q204", 0.0)
    if type(start) is float and type(end) is float and start <= end:
        return None
    if any(type(value) is not float for value in (start, end, clearance, second_clearance)):
        state.move_to(dict.fromkeys(state.position))
        return None
    name = f"heidenhain.{definition.number}"
    safe = start + max(clearance, second_clearance)
    here = state.position.get(axis)
    if here is None or (type(here) is float and here < safe):
        runner.move_to({axis: safe}, op.span, block, "retract", name)
    state.move_to({first: None, second: None})
    runner.move_to({axis: safe}, op.span, block, "approach", name)
    feed = params.get("Q253")
    with common.cycle_feed(state, {"Q206": feed if type(feed) is float else params.get("Q207")}):
        runner.move_to({axis: end}, op.span, block, "infeed", name, "rapid" if feed == "FMAX" else "feed")
    runner.move_to({axis: safe}, op.span, block, "out-of-hole", name)
    return None


def thread_cutting(runner, op, block, definition, shift, surface_offset) -> None:
    """Cycle 18: from where the tool is, DEPTH deeper at S x PITCH, with no approach or
    departure of its own; the spindle is stopped at the thread end and left as it was
    before the cycle (seed L15959-16039)."""
    state = runner.state
    params = dict(definition.params)
    _observe(runner, op, block, definition, params, {"spindle_running": 1.0 if state.spindle in ("cw", "ccw") else 0.0})
    axis = common.plane(state)[2]
    depth, pitch = params.get("DEPTH"), params.get("PITCH")
    here = state.position.get(axis)
    if depth == 0.0 or pitch == 0.0:
        return None
    if type(here) is not float or type(depth) is not float:
        state.move_to({axis: None})
        return None
    name = f"heidenhain.{definition.number}"
    spindle, saved = state.spindle, state.feed
    state.spindle = "cw"  # the cycle runs the spindle itself
    if pitch is not None and not isinstance(pitch, str):
        state.feed = common.pitch_feed(state, pitch)
    runner.move_to({axis: here + depth}, op.span, block, "infeed", name, "feed")
    state.spindle, state.feed = spindle, saved
    return None


def program_call(runner, op, block, definition, shift, surface_offset):
    """Cycle 12 runs the program of 12.1 at each call, like CALL PGM: its Q parameters are
    the caller's (seed L14990-14991). At the points of a pattern the call is not followed."""
    program = definition.program
    single = isinstance(op, ir.PositioningBlock) or (isinstance(op, ir.CallActiveCycle) and op.params.get("how") != "PAT")
    if not isinstance(program, str) or not single:
        runner.fault("core.unsupported-code", op.span, "cycle 12 at the points of a pattern, or without a program name, is not followed: "
                      "what the called program does is not analysed", "unknown", "cycle 12")
        runner.state.move_to(dict.fromkeys(runner.state.position))
        return None
    return runner.call_subprogram(ir.Call(op.span, "subprogram", program), block)


def machine_moving(runner, op, block, definition, shift, surface_offset) -> None:
    """Cycle 238 moves the machine's axes at rapid along paths the machine builder set
    (seed L15836-15851): where the tool is after it is not known."""
    state = runner.state
    _observe(runner, op, block, definition, dict(definition.params))
    state.move_to(dict.fromkeys(state.position))
    return None


def point_table(runner, op, name: str):
    """The points of a point table (``SEL PATTERN "HOLES.PNT"``) from the file beside the
    program: the columns named in its ``NR X Y Z ...`` header, faded points (FADE Y) left
    out; None when the file is not there (reference A 4.5)."""
    here = op.span.path or runner.main_source.path
    candidate = (Path(here).parent if here else Path(".")) / re.split(r"[\\/:]", name)[-1]
    if not candidate.is_file():
        return None
    note_file(candidate)
    columns, points = None, []
    for line in candidate.read_text(encoding="utf-8", errors="replace").splitlines():
        fields = line.split()
        if fields and fields[0].upper() == "NR":
            columns = [field.upper() for field in fields]
            continue
        if columns is None or not fields or not fields[0].isdigit():
            continue
        row = dict(zip(columns, fields))
        if row.get("FADE", "").upper() == "Y":
            continue
        try:
            points.append(tuple(float(row.get(axis, "0").replace(",", ".")) for axis in ("X", "Y", "Z")))
        except ValueError:
            return None
    return points


def select_pattern_run(runner, op, block, params):
    """``SEL PATTERN``: the points of the table become the pattern of CYCL CALL PAT; a table
    that is not beside the program leaves them unknown, and says so."""
    name = params.get("table")
    points = point_table(runner, op, name) if isinstance(name, str) else None
    if points is None:
        runner.fault("core.unsupported-code", op.span, f"point table {name} is not beside the program: the points CYCL CALL PAT machines are unknown",
                             "unknown", "point table")
    common.put(runner.state, pattern=None if points is None else tuple(points))
    return None


def m_function_run(runner, op, block):
    """M136 / M137 switch the feed per spindle revolution on and off (kept for the boring
    cycle); every watched M function reaches the rules as an ``m_function`` change."""
    number = op.number
    if number in (136.0, 137.0):
        common.put(runner.state, feed_per_revolution=number == 136.0)
        runner.state.modal["feed_mode"] = "per_revolution" if number == 136.0 else "per_minute"  # what the feed rules read
    runner.change("m_function", op.span, block, None, number)
    return None
