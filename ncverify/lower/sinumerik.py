"""Lowering of SINUMERIK 840D blocks to IR, and the SINUMERIK frontend.

Structured control flow is lowered to the IR's jumps and loops:

* ``IF c`` jumps, when ``c`` is false, to the synthetic label ``IF#<line>``; ``ELSE`` jumps
  to ``ELSE#<line>``. :meth:`SinumerikFrontend.label_offsets` matches ``IF``/``ELSE``/
  ``ENDIF`` over the whole program text (a pre-pass, cached) to find where each lands,
  and the landing blocks carry a :class:`StructureMark` label that the interpreter's
  confirmation accepts.
* ``WHILE``/``FOR``/``LOOP``/``REPEAT`` are ``LoopStart``/``LoopEnd`` with one loop id per
  kind: the interpreter's search for a loop's end counts nesting of the same id, so
  properly nested loops match without numbering them. ``FOR I=a TO b`` sets ``I=a-1``
  before its head and counts up right after it; ``UNTIL c`` stores ``c`` for the head of
  its ``REPEAT`` to test.
* ``CASE`` is a row of conditional jumps; ``GOTOF``/``GOTOB`` jump to a named label.

Cycles (``CYCLE81(...)``, ``POCKET1(...)``) become :class:`ir.CycleCall` with their
arguments named by position from ``dialects/sinumerik/cycles.toml`` (an omitted argument
is 0, seed L668-687); ``MCALL CYCLE8x(...)`` becomes a modal :class:`ir.CycleDefine`. Any
other name with or without arguments is a subprogram call (``PROC`` parameters are bound
by :meth:`SinumerikFrontend.proc_parameters`); ``MCALL NAME(...)`` calls it after every
later block that moves (:mod:`.modal_call`, see :meth:`SinumerikLowering._mcall`).
"""
from __future__ import annotations

import math
import re
from dataclasses import replace
from functools import cache

import numpy

from .. import ir
from ..context import Context, Stock, Tool, tool_value_problem
from ..cycle_models import CycleModel, load_cycle_table
from ..dialect import DialectSetup
from ..read.iso_runs import read_plain_run_at
from ..read.sinumerik import PATH_COMMANDS, Item, ReadBlock, read_line
from ..resources import data_dir, read_table
from ..source import Span, decode_line, letter_led, lines_holding
from . import modal_call
from .iso import FastMotionForm, fast_motion_block

WHILE_LOOP, FOR_LOOP, ENDLESS_LOOP, REPEAT_LOOP = 1, 2, 3, 4
UNTIL_FLAG = "_REPEAT_UNTIL_"
# A REPEAT of a section is a local call of its start label; the block that ends the section
# returns while $REPEAT_END names it (its label, or the REPEAT block itself for a section
# that runs up to the REPEAT), or, for that form, while an ENDLABEL comes first.
REPEAT_END = ir.Var("$REPEAT_END")
REPEAT_TO_ENDLABEL = ir.Var("$REPEAT_TO_ENDLABEL")
_REPEAT_STATE = {REPEAT_END.name: "", REPEAT_TO_ENDLABEL.name: 0.0}
_AXES = ("X", "Y", "Z", "A", "B", "C", "U", "V", "W")
_ARC_WORDS = ("I", "J", "K")
_INTERMEDIATE_WORDS = ("I1", "J1", "K1")
_DIRECTIONS = {"GOTOF": "forward", "GOTOB": "backward", "GOTO": "nearest", "GOTOC": "nearest"}
def _swivel(item: Item, span: Span) -> list[ir.Op]:
    """CYCLE800 tilts the working plane (not modelled: positions are unknown while it is
    on); ``CYCLE800()`` or all angles and shifts literally 0 switch it off (seed A L10846-10875)."""
    if item.name != "CYCLE800":
        return []
    numbers = item.args[4:13]
    neutral = all(arg is None or (type(arg) is float and arg == 0.0) for arg in numbers)
    return [ir.SetFrame(span, "swivel_off" if neutral else "swivel", what="CYCLE800 (swivelling the working plane)")]


# Kinematic transformations: while one is on, X/Y/Z are not the machine's linear axes (a
# face or a cylinder surface unrolled, an orientation) and positions mean something the
# rules do not model; TRAFOOF turns it off. The modal group "transformation" names it.
KINEMATIC_TRANSFORMATIONS = {"TRANSMIT": "TRANSMIT (face machining)", "TRACYL": "TRACYL (cylinder surface)",
                             "TRAORI": "TRAORI (tool orientation)", "TRAANG": "TRAANG (inclined axis)", "TRAFOOF": None}
_FRAME_COMPONENTS = {"TRANS": "translation", "ROT": "rotation", "SCALE": "scale", "MIRROR": "mirror"}
_AXIS_DATA_CODES = frozenset({"74", "75", "110", "111", "112", "58", "59", "25", "26"})
_STAGE_ORDER = ("feed", "tool", "speed", "spindle", "dwell", "modal", "offset", "motion", "call", "stop")
# The system variable holding the active cutting edge, the D number (840D programming
# knowledge, not in the references): D and M6 write it, rules read it from the state.
ACTIVE_EDGE = ir.Var(ir.ACTIVE_EDGE)
# Whether X is a diameter: the modal group "diameter" (840D programming knowledge; the
# references only use DIAMON in their turning examples). Rules that need it read it from
# the state; nothing moves differently.
DIAMETER_MODES = {"DIAMON": "diameter", "DIAMOF": "radius", "DIAM90": "diameter when absolute"}


class StructureMark:
    """The label of a block where an ``IF``/``ELSE`` lands (an ``ELSE`` or ``ENDIF`` line).
    The frontend's pre-pass has already chosen the line; the mark only confirms it."""

    __slots__ = ("kind",)

    def __init__(self, kind: str):
        self.kind = kind

    def __eq__(self, other) -> bool:
        return isinstance(other, str) and other.startswith(("IF#", "ELSE#"))

    def __hash__(self) -> int:
        return hash(self.kind)

    def __repr__(self) -> str:
        return self.kind


@cache
def tables() -> dict:
    folder = data_dir("dialects") / "sinumerik"
    return {"codes": read_table(folder / "codes.toml"), "cycles": load_cycle_table("sinumerik")}


def _code_key(value: float) -> str:
    if not math.isfinite(value):
        return str(value)  # in no table: an unknown code, never a crash
    return str(int(value)) if value == int(value) else f"{value:g}"


class SinumerikLowering:
    def __init__(self):
        loaded = tables()
        self.g = loaded["codes"]["g"]
        self.unsupported_g = loaded["codes"]["unsupported"]
        self.m = loaded["codes"]["m"]
        self.cycles = loaded["cycles"]
        self.uses_modal_call = False  # an MCALL of a subprogram anywhere: moves carry the modal call
        self.modal_call_arity = 0  # the most arguments any such MCALL passes
        self.uses_repeat = False  # a REPEAT/REPEATB of a section anywhere: labelled blocks may end one

    def lower(self, read: ReadBlock, path: str | None) -> list[ir.Block]:
        block = ir.Block(read.line, read.start + 1, read.end + 1, [], skippable=read.skip)
        block.label = read.label if read.label is not None or read.number is None else f"N{read.number}"  # GOTOF N100 lands on a block number
        block.comments = tuple((text, Span.on_line(read.line, start, end, path)) for text, start, end in read.comments)
        if read.header:
            block.program_start = read.header[0]
            return [block]
        if read.problem:
            problem = read.problem
            block.notes.append(ir.Note("core.syntax", problem.message, Span.on_line(read.line, problem.start, problem.end, path)))
            return [block]
        stages: dict[str, list] = {stage: [] for stage in _STAGE_ORDER}
        words: list[Item] = []
        blocks = [block]
        for item in read.items:
            span = Span.on_line(read.line, item.start, item.end, path)
            if item.kind == "word":
                words.append(item)
            elif item.kind == "else":
                block.ops.append(ir.Jump(span, f"ELSE#{read.line}"))
                landing = ir.Block(read.line, read.start + 1, read.end + 1, [], label=StructureMark("ELSE"))
                blocks.append(landing)
                block = landing
            elif item.kind == "endif":
                block.label = StructureMark("ENDIF")
            else:
                ops = self._statement(item, span, read, path, block)
                if item.kind in ("call", "mcall") and ops and isinstance(ops[-1], (ir.CycleCall, ir.CycleDefine)):
                    ops[-1].params["OTHER_WORDS"] = float(len(read.items) - 1)  # a cycle call must stand alone (seed L527)
                stages["call"].extend(ops)
        if words:
            supa = any(item.kind == "command" and item.name == "SUPA" for item in read.items)
            _call_repeat(words, stages["call"])
            self._words(words, stages, read, path, block, supa)
        for stage in _STAGE_ORDER:
            block.ops.extend(stages[stage])
        if self.uses_repeat and isinstance(read.label, str):
            block.ops.extend(_section_end(read.label, block.span))
        if self.uses_modal_call and modal_call.moves(block.ops) and not any(item.kind == "mcall" for item in read.items):
            positions = {str(index): str(index) for index in range(self.modal_call_arity)}
            block.ops.append(ir.ModalCallRun(block.span, "proc", positions))
        return blocks

    # ------------------------------------------------------------------ statements

    def _statement(self, item: Item, span: Span, read: ReadBlock, path, block: ir.Block) -> list[ir.Op]:
        kind = item.kind
        if kind == "assign":
            return [ir.Assign(span, item.extra, item.value)]
        if kind == "def":
            return [ir.Assign(span, ir.Var(name), value if value is not None else ("" if item.name in ("STRING", "CHAR") else 0.0))
                    for name, dimensions, value, _start in item.value if dimensions is None]
        if kind == "call":
            return [self._call(item, span, read, path)] + _swivel(item, span)
        if kind == "mcall":
            return self._mcall(item, span, read, path)
        if kind == "if":
            return [ir.Jump(span, f"IF#{read.line}", ir.Binary("EQ", item.condition, 0.0))]
        if kind == "goto":
            return [ir.Jump(span, _jump_target(item.value), item.condition, _DIRECTIONS[item.name], optional=item.name == "GOTOC")]
        if kind == "case":
            jumps = [ir.Jump(span, _jump_target(label), ir.Binary("EQ", item.value, value), "nearest") for value, label in item.args]
            if item.extra is not None:
                jumps.append(ir.Jump(span, _jump_target(item.extra), None, "nearest"))
            return jumps
        if kind == "while":
            return [ir.LoopStart(span, WHILE_LOOP, item.condition)]
        if kind == "endwhile":
            return [ir.LoopEnd(span, WHILE_LOOP)]
        if kind == "for":
            counter = ir.Var(item.name)
            return [ir.Assign(span, counter, ir.Binary("-", item.value, 1.0)),
                    ir.LoopStart(span, FOR_LOOP, ir.Binary("LE", ir.Binary("+", counter, 1.0), item.args[0])),
                    ir.Assign(span, counter, ir.Binary("+", counter, 1.0))]
        if kind == "endfor":
            return [ir.LoopEnd(span, FOR_LOOP)]
        if kind == "loop":
            return [ir.LoopStart(span, ENDLESS_LOOP, 1.0)]
        if kind == "endloop":
            return [ir.LoopEnd(span, ENDLESS_LOOP)]
        if kind == "repeat":
            flag = ir.Var(UNTIL_FLAG)
            return [ir.Assign(span, flag, 0.0), ir.LoopStart(span, REPEAT_LOOP, ir.Binary("EQ", flag, 0.0))]
        if kind == "until":
            return [ir.Assign(span, ir.Var(UNTIL_FLAG), item.condition), ir.LoopEnd(span, REPEAT_LOOP)]
        if kind == "ret":
            return [ir.Return(span)]
        if kind == "frame":
            return [self._frame(item, span)]
        if kind == "command" and item.name in KINEMATIC_TRANSFORMATIONS:
            return [ir.SetModal(span, "transformation", KINEMATIC_TRANSFORMATIONS[item.name])]
        if kind == "setal":
            return [ir.Alarm(span, item.value, "", "alarm {number} with SETAL")]
        if kind == "repeat_section":
            return _repeat_section(item, span, read.line)
        if kind == "unsupported":
            affects = () if item.name.startswith("a synchronised") or item.name.startswith("a curve") else ("position",)
            return [ir.Unsupported(span, item.name, affects + (("state",) if item.value else ()))]
        if kind == "command" and item.name in DIAMETER_MODES:
            return [ir.SetModal(span, "diameter", DIAMETER_MODES[item.name])]
        return []  # proc, msg, workpiece, other commands: no modelled effect

    def _call(self, item: Item, span: Span, read: ReadBlock, path) -> ir.Op:
        model = self.cycles.get(item.name)
        if model is not None:
            params, spans = self._cycle_arguments(item, model, read, path)
            return ir.CycleCall(span, f"sinumerik.{item.name}", params, spans)
        return ir.Call(span, "proc", item.name, 1.0, _positional_arguments(item))

    def _mcall(self, item: Item, span: Span, read: ReadBlock, path) -> list[ir.Op]:
        """``MCALL`` ends the modal call, a cycle's or a subprogram's; ``MCALL CYCLE8x(...)``
        makes the cycle modal; ``MCALL NAME(args)`` calls the subprogram NAME with the
        arguments (evaluated here) after every later block with a path motion, until
        ``MCALL`` or the next MCALL replaces it (seed A L4317-4364; not after the MCALL
        block itself, nor after the subprogram's own moves). A modally called
        subprogram must not contain an MCALL of its own (L4362-4364)."""
        ops: list[ir.Op] = [ir.CycleCancel(span)]
        if self.uses_modal_call:
            ops.append(ir.ModalCallOff(span))
            if item.name:
                ops.insert(0, ir.NoteInsideModalCall(span, _nested_modal_call(item.name, span)))
        if not item.name:
            return ops
        model = self.cycles.get(item.name)
        if model is None:
            return ops + [modal_call.switch_on(span, item.name, _positional_arguments(item), map(str, range(self.modal_call_arity)), 0.0)]
        params, spans = self._cycle_arguments(item, model, read, path)
        return ops + [ir.CycleDefine(span, f"sinumerik.{item.name}", params, spans)]

    @staticmethod
    def _cycle_arguments(item: Item, model: CycleModel, read: ReadBlock, path) -> tuple[dict, dict]:
        """Arguments named by position; omitted ones are 0 (seed L668-687). Extra
        arguments are kept as ``#13`` etc. for the rules (alarm 12340), and ``ARG_COUNT`` /
        ``ARG_OMITTED`` say how the list was written."""
        names = [argument[0] for argument in model.arguments]
        params: dict = {}
        spans: dict = {}
        omitted = []
        for index, arg in enumerate(item.args):
            name = names[index] if index < len(names) else f"#{index + 1}"
            params[name] = 0.0 if arg is None else arg
            if arg is None:
                omitted.append(name)
            start, end = item.arg_spans[index]
            spans[name] = Span.on_line(read.line, start, max(end, start + 1), path)
        for name in names[len(item.args):]:
            params[name] = 0.0
        params["ARG_COUNT"] = float(len(item.args))
        params["ARG_OMITTED"] = float(len(omitted))
        return params, spans

    @staticmethod
    def _frame(item: Item, span: Span) -> ir.Op:
        """TRANS/ROT/SCALE/MIRROR replace the programmable frame (reset without words), the
        A- forms append to it; ROTS/AROTS (solid angles) are not modelled."""
        base = item.name[1:] if item.name.startswith("A") else item.name
        component = _FRAME_COMPONENTS.get(base)
        words = {word.name: word.value for word in item.value}
        statement = " ".join([item.name] + [f"{word.name}{'=' if len(word.name) > 1 else ''}{word.value:g}" if type(word.value) is float else word.name
                                             for word in item.value])
        if component is None:
            return ir.SetFrame(span, "unknown", what=f"{statement} (a rotation by solid angles)")
        if not words and base == item.name:
            component = "reset"
        return ir.SetFrame(span, component, item.name != base, words, what=statement)

    # ------------------------------------------------------------------ address words

    def _words(self, words: list[Item], stages: dict, read: ReadBlock, path, block: ir.Block, supa: bool = False) -> None:
        targets: dict = {}
        incremental, absolute = set(), set()
        columns: dict = {}
        arc: dict = {}
        motion = None
        motion_span = None
        move_words: dict = {}
        machine_move, axis_data = supa, False  # SUPA: this block's axes in machine coordinates, like G153
        corner = None  # RND=/CHF=/CHR=: the corner at this move's end is cut off
        for item in words:
            span = Span.on_line(read.line, item.start, item.end, path)
            name, value = item.name, item.value
            if name in PATH_COMMANDS:
                motion, motion_span = PATH_COMMANDS[name], span
            elif name == "G":
                if type(value) is not float:
                    stages["modal"].append(ir.Unsupported(span, "a G code computed at run time", ("position",)))
                    continue
                motion_kind, machine = self._g_code(value, span, stages, block)
                axis_data = axis_data or _code_key(value) in _AXIS_DATA_CODES
                machine_move = machine_move or machine
                if motion_kind is not None:
                    motion, motion_span = motion_kind, span
            elif name == "M" or re.fullmatch(r"M\d", name):
                self._m_code(value, span, stages, block)
            elif name in _AXES:
                targets[name] = value
                columns[name] = (item.start, item.end)
                if item.mode == "IC":
                    incremental.add(name)
                elif item.mode == "AC":
                    absolute.add(name)
            elif name in _ARC_WORDS:
                arc[name] = value
                if item.mode == "AC":  # I=AC(..): the centre itself, not its distance from the start
                    absolute.add(name)
            elif name in _INTERMEDIATE_WORDS:  # CIP's intermediate point, read like the end point
                arc[name] = value
                if item.mode == "IC":
                    incremental.add(name)
                elif item.mode == "AC":
                    absolute.add(name)
            elif name == "CR":
                arc["R"] = value
            elif name in ("RND", "CHF", "CHR"):
                corner, move_words[name] = span, value  # the contour rules read them as the move's words
            elif name == "RNDM":
                stages["modal"].append(ir.CornerRounding(span, modal=not (type(value) is float and value == 0.0)))
                move_words[name] = value
            elif name == "F":
                stages["feed"].append(ir.SetFeed(span, value))
            elif name == "S" or re.fullmatch(r"S\d", name):
                stages["speed"].append(ir.SetSpindleSpeed(span, value))
            elif name == "LIMS":
                stages["speed"].append(ir.SetSpindleSpeed(span, value, clamp=True))
            elif name == "T":
                stages["tool"].append(ir.ToolSelect(span, value))
            elif name == "D":
                off = type(value) is float and value == 0.0
                stages["offset"].extend([ir.LengthOffset(span, "off" if off else "with_tool"), ir.Assign(span, ACTIVE_EDGE, value)])
            elif name in ("SPOS", "SPOSA"):
                stages["spindle"].append(ir.Spindle(span, "orient"))
            elif re.fullmatch(r"[XYZABC]\d", name) and _home_op(stages) is not None:
                _home_op(stages).axes += (name[0],)  # G74 X1=0: machine axis X1 to its reference point
            elif name in ("TURN", "AP", "RP", "ANG", "CIP") or re.fullmatch(r"[A-Z]\d", name):
                stages["motion"].append(ir.Unsupported(span, f"{name}= ({'polar or angle' if name in ('AP', 'RP', 'ANG') else 'extended'} programming)", ("position",)))
            else:
                move_words[name] = value
        dwell = next((op for op in stages["dwell"] if isinstance(op, ir.Dwell)), None)
        if dwell is not None:
            dwell.seconds = move_words.get("F")
            dwell.revolutions = move_words.get("S")
            stages["feed"] = [op for op in stages["feed"] if not isinstance(op, ir.SetFeed)]
            stages["speed"] = []
        if axis_data:  # G74/G75/G110-G112/G58/G59...: the axis words are data, not a move
            home = _home_op(stages)
            if home is not None:
                home.axes += tuple(targets)
            for op in stages["offset"]:
                if isinstance(op, ir.SetFrame):
                    op.values = dict(targets)  # G58/G59: the translation of the axes written
            return
        if machine_move:
            if targets:
                stages["motion"].append(ir.MachineMove(Span.on_line(read.line, read.start, read.end, path), targets))
            return
        if targets or arc or motion is not None:
            spans = [columns[name] for name in columns]
            if spans:
                start = min(first for first, _ in spans)
                end = max(last for _, last in spans)
                move_span = Span.on_line(read.line, start, end, path)
            else:
                move_span = motion_span or Span.on_line(read.line, read.start, read.end, path)
            if motion_span is not None:
                move_span = move_span.cover(motion_span)
            stages["motion"].append(ir.Move(move_span, motion, targets, arc or None, move_words, frozenset(incremental), columns, frozenset(absolute)))
            if corner is not None:
                stages["motion"].append(ir.CornerRounding(corner))

    def _g_code(self, value: float, span: Span, stages: dict, block: ir.Block) -> tuple[str | None, bool]:
        key = _code_key(value)
        entry = self.g.get(key)
        if entry is None:
            if key.isdigit() and 505 <= int(key) <= 599:  # the settable frames beyond G57
                stages["offset"].append(ir.WorkOffset(span, f"G{key}"))
                return None, False
            what = self.unsupported_g.get(key)
            if what is not None:
                stages["modal"].append(ir.Unsupported(span, what, ("position", "state")))
            if key == "291":
                block.notes.append(ir.Note("core.unsupported-code", "G291 switches the control to ISO dialect mode: the blocks up to G290 are read as "
                                           "SINUMERIK here, not as ISO; what they do is not verified", span))
            return None, False
        effect = entry["effect"]
        if effect == "move":
            return entry["kind"], False
        if effect == "modal":
            stages["modal"].append(ir.SetModal(span, entry["modal"], entry["value"]))
        elif effect == "comp":
            stages["modal"].append(ir.CutterComp(span, entry["side"]))
        elif effect == "work_offset":
            stages["offset"].append(ir.WorkOffset(span, f"G{key}"))
        elif effect == "frame_layer":
            stages["offset"].append(ir.SetFrame(span, "translation", layer=entry["layer"], what=f"G{key}"))
        elif effect == "dwell":
            stages["dwell"].append(ir.Dwell(span, None))
        elif effect == "machine_move":
            return None, True
        elif effect == "reference":
            stages["motion"].append(ir.Home(span))
        return None, False

    def _m_code(self, value, span: Span, stages: dict, block: ir.Block) -> None:
        if type(value) is not float:
            stages["stop"].append(ir.Unsupported(span, "an M code computed at run time", ("position",)))
            return
        entry = self.m.get(_code_key(value))
        if entry is None:
            return
        effect = entry["effect"]
        if effect == "stop":
            stages["stop"].append(ir.Stop(span, entry["kind"]))
        elif effect == "return":
            stages["stop"].append(ir.Return(span))
        elif effect in ("spindle", "coolant"):
            stage = "stop" if entry.get("output") == "after" else "spindle"  # the table's output timing (codes.toml)
            stages[stage].append((ir.Spindle if effect == "spindle" else ir.Coolant)(span, entry["state"]))
        elif effect == "tool_change":
            # The new tool's first cutting edge (D1) becomes active with the change (840D default).
            stages["tool"].extend([ir.ToolChange(span), ir.LengthOffset(span, "with_tool"), ir.Assign(span, ACTIVE_EDGE, 1.0)])


def _call_repeat(words: list[Item], calls: list[ir.Op]) -> None:
    """``L10 P3``, ``NAME P=3``: the P word of a subprogram call is its repeat count
    (1-9999 on the control); it is taken out of the block's words."""
    call = next((op for op in calls if isinstance(op, ir.Call) and op.kind == "proc"), None)
    count = next((item for item in words if item.name == "P"), None)
    if call is None or count is None:
        return
    words.remove(count)
    call.repeat = count.value


def _repeat_section(item: Item, span: Span, line: int) -> list[ir.Op]:
    """``REPEAT A P=n`` (A up to the first ENDLABEL, else up to this block), ``REPEAT A B
    P=n`` (A to B) and ``REPEATB A P=n`` (the block A): the section runs n more times (once
    without P) as a local call of A, found backward first, then forward. No limit of n is
    stated, so only the loop bound ends a huge count. The section's end is saved and set
    around the call, so that a REPEAT inside a repeated section ends its own."""
    here = f"@REPEAT{line}"
    labels = item.value
    if item.name == "REPEATB":
        end, to_endlabel = labels[0], 0.0
    else:
        end, to_endlabel = (labels[1], 0.0) if len(labels) > 1 else (here, 1.0)
    saved_end, saved_flag = ir.Var(f"$REPEAT_END{here}"), ir.Var(f"$REPEAT_TO_ENDLABEL{here}")
    count = item.args[0] if item.args[0] is not None else 1.0
    return [ir.Conditional(span, ir.Binary("EQ", REPEAT_END, here), [ir.Return(span, local_only=True)]),
            ir.Assign(span, saved_end, REPEAT_END), ir.Assign(span, saved_flag, REPEAT_TO_ENDLABEL),
            ir.Assign(span, REPEAT_END, end), ir.Assign(span, REPEAT_TO_ENDLABEL, to_endlabel),
            ir.Call(span, "local", labels[0], count, most_repeats=None, direction="backward-first"),
            ir.Assign(span, REPEAT_END, saved_end), ir.Assign(span, REPEAT_TO_ENDLABEL, saved_flag)]


def _section_end(label: str, span: Span) -> list[ir.Op]:
    """What a labelled block does at its end while a REPEAT runs: return where the section
    ends here."""
    ends = [ir.Conditional(span, ir.Binary("EQ", REPEAT_END, label), [ir.Return(span, local_only=True)])]
    if label == "ENDLABEL":
        ends.append(ir.Conditional(span, ir.Binary("EQ", REPEAT_TO_ENDLABEL, 1.0), [ir.Return(span, local_only=True)]))
    return ends


def _positional_arguments(item: Item) -> dict:
    """A subprogram call's arguments by position ("0", "1"...); an omitted one is 0."""
    return {str(index): (0.0 if arg is None else arg) for index, arg in enumerate(item.args)}


def _nested_modal_call(name: str, span: Span) -> ir.Note:
    """The finding of an ``MCALL name`` block that runs inside the modally called subprogram."""
    message = (f"MCALL {name} inside the subprogram that MCALL calls modally: modal calls cannot nest "
               "(seed A L4362-4364); the control refuses it")
    return ir.Note("sinumerik.nested-mcall", message, span)


# ---------------------------------------------------------------------- frontend

_PLAIN_MOTION = re.compile(rb"[ \t]*+(?:(?:[NGXYZFIJK]|CR=)[ \t]*+[+-]?+(?>\d+\.?\d*|\.\d+)[ \t]*+)++")  # possessive: see iso._FAST_LINE
# Plain motion lines lowered without the reader, as the general lowering would (N is a block
# number, a label only as N<number>; I/J/K and the radius CR= are arc data only, outside the
# move's span; R is a parameter).
_FAST_WORD = rb"(?:[GXYZABCFIJK]|CR=)[+-]?(?:\d+\.?\d*|\.\d+)"
_FAST_LINE = re.compile(rb"[ \t]*(?:N\d+[ \t]+)?" + _FAST_WORD + rb"(?:[ \t]+" + _FAST_WORD + rb")*[ \t]*")  # N first, words apart
_FAST_FORM = FastMotionForm(frozenset(_AXES), number_label=lambda digits: f"N{int(digits)}", arc_letters=frozenset((*_ARC_WORDS, "R")),
                            arc_words_in_span=False, line=_FAST_LINE)
_PROGRAM_HEADER = re.compile(rb"(?mi)^[ \t]*%_N_(\w+?)_(MPF|SPF)\b")
_PROC = re.compile(rb"(?mi)^[ \t]*(?:N\d+[ \t]*)?PROC[ \t]+(\w+)")
# Scans of the whole text: each line pattern with a keyword every line it matches holds
# (:func:`~ncverify.source.lines_holding`).
_PROGRAM_END = (letter_led(rb"M0?(?:2|30)"), re.compile(rb"(?mi)^[^;\n]*\bM0?(?:2|30)\b(?![ \t]*=)"))
_MODAL_CALL = (letter_led(rb"MCALL"), re.compile(rb"(?mi)^[^;\n]*\bMCALL[ \t]+(\w+)[^\n]*"))
_REPEAT_SECTION = (letter_led(rb"REPEAT"), re.compile(rb"(?mi)^[^;\n]*\bREPEATB?[ \t]+[A-Z_]"))
_SUBPROGRAM_END = re.compile(rb"(?mi)^[^;\n]*\b(?:M17|RET)\b(?![ \t]*=)")
_STRUCTURE_LINE = re.compile(r"^\s*(?:/\d?\s*)?(?:N\d+\s*)?(?:[A-Za-z_]\w*\s*:(?!=)\s*)?(IF|ELSE|ENDIF)\b(.*)$", re.IGNORECASE)


_READINGS_KEPT = 4096  # different line texts whose readings are kept at once


_FRAME_TABLES = ("$P_UIFR", "$P_UBFR", "$P_CHBFR", "$P_NCBFR")  # settable frames (G54...) and base frames, by number
# programmable tool length offsets (TOFFL, TOFF[Z], TOFFR), an axis's offset from a
# synchronized action and the external work offset: in force where they are written
_OFFSETS_IN_FORCE = re.compile(r"(?:TOFF[LR]?|\$AA_OFF|\$AA_ETRANS|DL)(?:\[|$)")  # a name alone, or indexed


class SinumerikFrontend:
    # A subprogram ends with M17 or RET (cycles manual L8555, L14068, L16610). Neither the
    # manual nor the reference says what the 840D does when a subprogram's text ends without
    # one (no alarm is listed, no implicit return described): that end is unknown, not a fault.
    subprogram_end = "M17/RET"
    subprogram_text_end = "unknown"

    def __init__(self, lowering: SinumerikLowering):
        self.lowering = lowering
        self._structures: dict = {}
        self._proc_cache: dict = {}
        self._readings: dict[str, ReadBlock] = {}  # line text -> its reading (see _read)

    def blocks(self, raw: bytes, line: int, path: str | None) -> list[ir.Block]:
        if not self.lowering.uses_modal_call and _FAST_LINE.fullmatch(raw):  # with MCALL, a move also carries the call
            block = fast_motion_block(raw, line, path, _FAST_FORM)
            if block is not None:
                return [block]
        return self.lowering.lower(self._read(decode_line(raw), line), path)

    def _read(self, text: str, line: int) -> ReadBlock:
        """:func:`read_line`, remembered by text: a post writes the same lines again and again
        (``CYCLE81(15, 0, 2, -5)`` at every hole, ``M6``, ``G0 Z50``). A reading depends on the
        text alone but for its line number, its items give columns, not spans, and the
        lowering only reads them."""
        reading = self._readings.get(text)
        if reading is None:
            if len(self._readings) >= _READINGS_KEPT:
                self._readings.clear()
            reading = self._readings[text] = read_line(text, line)
        return reading if reading.line == line else replace(reading, line=line)

    def is_plain(self, raw: bytes) -> bool:
        """Could this line be part of a :class:`ir.MoveBatch`? (``N.. G0-G3 X Y Z I J K
        CR= F`` with literal numbers, as in ISO: CAM output is the same in both languages.
        Not while a subprogram may be called modally: its moves carry the call.)"""
        return not self.lowering.uses_modal_call and _PLAIN_MOTION.fullmatch(raw) is not None

    def plain_run(self, buffer, offset: int, line: int, limit: int = 1 << 20):
        """The plain blocks from ``offset`` on, arcs among them (the radius as ``CR=``),
        read as arrays by the ISO run reader; a SINUMERIK number is always in mm or inch (no
        least-increment scaling)."""
        if self.lowering.uses_modal_call:
            return None
        run = read_plain_run_at(buffer, offset, limit, arcs=True, radius_word=b"CR=")
        if run is None:
            return None
        table = run.table
        motion = table[:, 1]
        kinds = numpy.where(numpy.isnan(motion), -1, motion).astype(numpy.int8)
        unscaled = numpy.zeros((len(kinds), 3), dtype=bool)
        return ir.MoveBatch(offset, offset + run.length, line, run.line_starts + offset, kinds, ("X", "Y", "Z"), table[:, 2:5],
                          unscaled, table[:, 5], numpy.zeros(len(kinds), dtype=bool), run.blocks, run.arc_words, run.worded)

    def programs(self, buffer) -> list[tuple[str, int]]:
        """Programs named by ``%_N_NAME_MPF/SPF`` headers; a file without one that starts
        with ``PROC NAME`` is that subprogram, and one that ends with M17/RET and never with
        M2/M30 is a subprogram stored on its own."""
        self._find_modal_calls(buffer)
        if _first_line(buffer, _REPEAT_SECTION) is not None:
            self.lowering.uses_repeat = True
        found = [(match.group(1).decode().upper(), match.start()) for match in _PROGRAM_HEADER.finditer(buffer)]
        if found:
            return found
        head = _first_code_line(buffer)
        proc = _PROC.match(buffer, head) if head is not None else None
        if proc:
            return [(proc.group(1).decode().upper(), 0)]
        if _first_line(buffer, _PROGRAM_END) is None and _SUBPROGRAM_END.search(buffer) is not None:
            return [("(SUBPROGRAM)", 0)]
        return []

    def _find_modal_calls(self, buffer) -> None:
        """Whether the text has an MCALL of a subprogram (not of a cycle), and how many
        arguments the longest passes: every moving block then carries the modal call."""
        for match in lines_holding(buffer, *_MODAL_CALL):
            if match.group(1).decode().upper() in self.lowering.cycles:
                continue
            self.lowering.uses_modal_call = True
            line = buffer[match.start() : match.end()]
            for item in read_line(decode_line(line), 1).items:
                if item.kind == "mcall":
                    self.lowering.modal_call_arity = max(self.lowering.modal_call_arity, len(item.args))

    @staticmethod
    def stored_as_subprogram(name: str) -> bool:
        """A file stored as ``NAME.SPF`` (a Sub Program File, manual glossary L20593) is a
        subprogram: it is called by a main program (L21560), never run as one."""
        return name.lower().endswith(".spf")

    def is_subprogram(self, buffer, start: int, end: int) -> bool:
        header = _PROGRAM_HEADER.match(buffer, start)
        if header is not None:
            return header.group(2).upper() == b"SPF"
        head = _first_code_line(buffer[start:end])
        if head is not None and _PROC.match(buffer, start + head):
            return True
        return _first_line(buffer, _PROGRAM_END, start, end) is None

    def tape_marks(self, buffer) -> list[int]:
        return []

    def program_name(self, name) -> str:
        return name.upper() if isinstance(name, str) else f"{name:g}"

    def describe_label(self, label) -> str:
        if isinstance(label, str) and "#" in label:
            kind, line = label.split("#")
            return f"the {'ELSE/ENDIF' if kind == 'IF' else 'ENDIF'} matching the {kind} in line {line}"
        return f"label {label}"

    def variable_scope(self, name: str) -> str:
        """R parameters and system variables ($...) are global; DEF variables and PROC
        parameters belong to the program that defines them."""
        return "global" if name[:1] in ("R", "$") and (name[:1] == "$" or name[1:].split("[")[0].isdigit()) else "local"

    def system_variable(self, name: str, state):
        """System constants are values (``$PI``); machine data and the rest are the
        machine's, read as inputs (unknown without an ``assume``), never set to 0 freely."""
        constant = _SYSTEM_CONSTANTS.get(name.upper())
        return constant if constant is not None else _REPEAT_STATE.get(name)

    @staticmethod
    def machine_data(name: str) -> tuple[str, bool] | None:
        """What writing system variable ``name`` changes that the model does not follow (see
        :meth:`~ncverify.interpret.Interpreter.unfollowed`): a frame or an offset in force
        (``$P_PFRAME``, ``$P_IFRAME``..., ``TOFFL``, ``TOFF[Z]``, ``$AA_OFF``, ``$AA_ETRANS``,
        the address ``DL``) whenever written; the settable and base frame tables and the tool
        data (``$TC_``) once the program moves, as a program defines its tools and offsets
        with them at its start; None for any other variable."""
        upper = name.upper()
        if upper.startswith("$TC_"):
            return "tool data", False
        if _OFFSETS_IN_FORCE.match(upper):  # DL=n: additive (sum and setup) offsets the program does not give
            return "an offset in force", True
        if upper.startswith(_FRAME_TABLES):
            return "a work offset (settable or base frame)", False
        if upper.startswith("$P_") and "FRAME" in upper:
            return "the frame in force", True
        return None

    def label_offsets(self, buffer, label):
        if isinstance(label, str) and "#" in label:
            offset = self._structure(buffer).get(label)
            return [] if offset is None else [offset]
        text = str(label).upper()
        if re.fullmatch(r"N\d+", text):  # GOTOF N100: a block number, not a label named N100
            text = text[1:]
        if text.replace(".", "").isdigit():
            pattern = re.compile(rb"(?mi)^[ \t]*(?:/\d?[ \t]*)?N0*" + str(int(float(text))).encode() + rb"(?![0-9.])")
        else:
            pattern = re.compile(rb"(?mi)^[ \t]*(?:/\d?[ \t]*)?(?:N\d+[ \t]*)?" + re.escape(text.encode()) + rb"[ \t]*(?::|\xef\xbc\x9a)")
        return [match.start() for match in pattern.finditer(buffer)]

    def _structure(self, buffer) -> dict:
        """Where each IF and ELSE lands: a pass over the text matching IF/ELSE/ENDIF."""
        key = (id(buffer), len(buffer))
        found = self._structures.get(key)
        if found is not None:
            return found
        found = {}
        stack: list[list] = []
        offset = 0
        for number, raw in enumerate(bytes(buffer).split(b"\n"), start=1):
            if b"IF" in raw.upper() or b"ELSE" in raw.upper():
                text = decode_line(raw).split(";")[0]
                match = _STRUCTURE_LINE.match(text)
                if match:
                    keyword = match.group(1).upper()
                    if keyword == "IF" and not re.search(r"\bGOTO[FBC]?\b", match.group(2), re.IGNORECASE):
                        stack.append([number, None])
                    elif keyword == "ELSE" and stack:
                        found[f"IF#{stack[-1][0]}"] = offset
                        stack[-1][1] = number
                    elif keyword == "ENDIF" and stack:
                        opener, else_line = stack.pop()
                        found.setdefault(f"IF#{opener}", offset)
                        if else_line is not None:
                            found[f"ELSE#{else_line}"] = offset
            offset += len(raw) + 1
        self._structures[key] = found
        return found

    def proc_parameters(self, buffer, start: int) -> list[tuple[str, bool]]:
        """``(name, by_reference)`` of the PROC that opens the program at ``start``."""
        key = (id(buffer), start)
        if key not in self._proc_cache:
            self._proc_cache[key] = _proc_parameters(buffer, start)
        return self._proc_cache[key]

    def program_context(self, source) -> Context:
        return program_context(bytes(source.buffer))


def _first_line(buffer, scan: tuple, start: int = 0, end: int | None = None):
    """The first match of a whole-text scan (keyword, line pattern), or None."""
    return next(lines_holding(buffer, *scan, start, end), None)


def _first_code_line(buffer) -> int | None:
    offset = 0
    for raw in bytes(buffer[:65536]).split(b"\n"):
        text = raw.strip()
        if text and not text.startswith((b";", b"%")):
            return offset
        offset += len(raw) + 1
    return None


def _proc_parameters(buffer, start: int) -> list[tuple[str, bool]]:
    end = min(len(buffer), start + 65536)
    offset = start
    for raw in bytes(buffer[start:end]).split(b"\n")[:50]:
        read = read_line(decode_line(raw), 1)
        for item in read.items:
            if item.kind == "proc":
                return [(name, by_reference) for _type, name, by_reference in item.value]
        if read.items and not any(item.kind in ("command", "msg") for item in read.items):
            return []
        offset += len(raw) + 1
    return []


# ---------------------------------------------------------------------- context from the program

_WORKPIECE = re.compile(r"^\s*(?:N\d+\s*)?WORKPIECE\s*\((.*)\)", re.IGNORECASE)
_TOOL_ASSIGNMENT = r"\$TC_DP(\d+)\s*\[\s*(\d+)\s*,\s*(\d+)\s*\]\s*=\s*([-+]?(?:\d+\.?\d*|\.\d+))\s*"
# A block of tool-data assignments only, several to a block as in seed B L19033-19034; the
# comment may start with the full-width semicolon of the OCR'd manuals.
_TOOL_DATA_BLOCK = re.compile(rf"^\s*(?:N\d+\s*)?(?:{_TOOL_ASSIGNMENT})+(?:[;\uff1b].*)?$", re.IGNORECASE)
_TOOL_DATA = re.compile(_TOOL_ASSIGNMENT, re.IGNORECASE)
# Tool type codes (seed B L81, A section 3.1): 1xx mills, 2xx drills, 5xx turning tools.
_TOOL_TYPES = {1: "endmill", 2: "drill", 5: "turning"}
_SYSTEM_CONSTANTS = {"$PI": math.pi}


def program_context(buffer: bytes) -> Context:
    """The blank from ``WORKPIECE(...)`` and the tools from ``$TC_DP`` assignments."""
    context = Context()
    tools: dict[int, dict[int, dict]] = {}  # tool -> edge -> offset parameter -> value
    for number, raw in _lines_naming(buffer, _CONTEXT_WORDS):
        upper = raw.upper()
        if b"WORKPIECE" in upper:
            stock = _workpiece(decode_line(raw).split(";")[0], number)
            if stock is not None and context.stock is None:
                context.stock = stock
        elif b"$TC_DP" in upper and _TOOL_DATA_BLOCK.match(text := decode_line(raw)):
            for match in _TOOL_DATA.finditer(text):
                parameter, tool, edge, value = match.groups()
                if math.isfinite(float(value)):  # a value beyond any range leaves the parameter unknown
                    tools.setdefault(int(tool), {}).setdefault(int(edge), {})[int(parameter)] = float(value)
    for number, edges in tools.items():
        context.tools[number] = _tool(number, edges.get(1, {}))
        context.tools[number].edges = {edge: _tool(number, data) for edge, data in edges.items() if edge != 1}
    return context


_CONTEXT_WORDS = (*letter_led(rb"WORKPIECE"), re.compile(rb"\$(?i:TC_DP)"))  # each begins with a plain byte (see letter_led)
_WHOLE_LINE = re.compile(rb"[^\n]*")


def _lines_naming(buffer: bytes, keywords: tuple):
    """(line number, text) of the lines holding any of ``keywords``, in order: a long
    program's other lines are not split off one by one."""
    number, counted = 1, 0
    for line in lines_holding(buffer, keywords, _WHOLE_LINE):
        number += buffer.count(b"\n", counted, line.start())
        counted = line.start()
        yield number, line.group()


def _tool(number: int, data: dict) -> Tool:
    """Tool ``number`` from one edge's offset parameters: P1 type, P2 cutting-edge position,
    P3 length, P6 radius, P24 clearance angle (reference B section 3). A value outside its
    range (``TOOL_RANGES``) is left unknown, and so are the radius and the length when
    another parameter of the edge holds a value."""
    def checked(key, parameter):
        value = data.get(parameter)
        return None if value is None or tool_value_problem(key, value) else value

    unread = any(value != 0.0 for parameter, value in data.items() if parameter not in _READ_EDGE_PARAMETERS)  # wear, more lengths...
    return Tool(number, type=_TOOL_TYPES.get(int(data.get(1, 0)) // 100), radius=None if unread else data.get(6), length=None if unread else data.get(3),
                clearance_angle=checked("clearance_angle", 24), edge_position=checked("edge_position", 2), origin="program ($TC_DP)")


# The edge parameters read (type, edge position, length 1, radius, clearance angle); any other
# one set to a value (lengths 2 and 3, wear such as $TC_DP12 and $TC_DP15, base dimensions) adds
# to the radius or the length in ways not modelled, which are then not known.
_READ_EDGE_PARAMETERS = frozenset({1, 2, 3, 6, 24})


def _workpiece(text: str, line: int) -> Stock | None:
    """``WORKPIECE(,"",,"RECTANGLE",0,ZA,ZI,ZB,L,W)``, ``"BOX"`` with two corners
    X0,Y0,X1,Y1, ``"CYLINDER"`` with a diameter (ShopMill/ShopTurn blank layout, †: the
    references do not define it). ZI below ZA is the absolute bottom; a positive ZI is a
    depth below ZA."""
    match = _WORKPIECE.match(normalize_quotes(text))
    if match is None:
        return None
    args = [arg.strip().strip('"').upper() for arg in match.group(1).split(",")]
    numbers = []
    for arg in args[4:]:
        try:
            numbers.append(float(arg) if arg else 0.0)
        except ValueError:
            return None
    if len(args) < 4 or len(numbers) < 4:
        return None
    kind = args[3]
    top, bottom = numbers[1], numbers[2]
    if bottom > top:
        bottom = top - bottom
    span = Span(line, 1, line, len(text) + 1)
    try:
        if kind == "RECTANGLE" and len(numbers) >= 6:
            length, width = numbers[4], numbers[5]
            return Stock.box((-length / 2, length / 2), (-width / 2, width / 2), (bottom, top), "program (WORKPIECE)", span)
        if kind == "BOX" and len(numbers) >= 8:
            return Stock.box((numbers[4], numbers[6]), (numbers[5], numbers[7]), (bottom, top), "program (WORKPIECE)", span)
        if kind == "CYLINDER" and len(numbers) >= 5:
            return Stock.cylinder(numbers[4], (bottom, top), "program (WORKPIECE)", span)
    except ValueError:
        return None
    return None


def normalize_quotes(text: str) -> str:
    return text.replace("“", '"').replace("”", '"').replace("„", '"').replace("（", "(").replace("）", ")").replace("，", ",")


def setup(settings, detection, project) -> DialectSetup:
    loaded = tables()
    machine = settings.machine or project.machine.kind or detection.machine or "mill"
    power_on = dict(loaded["codes"]["power_on"])
    if machine == "lathe":
        power_on.update(loaded["codes"]["power_on_lathe"])
    models = {f"sinumerik.{name}": replace(model, called_after_motion=True) for name, model in loaded["cycles"].items()}
    limits = {"d_register_max": 32000.0, "h_register_max": 32000.0, "tool_number_max": 32000.0}
    return DialectSetup(SinumerikFrontend(SinumerikLowering()), power_on, models, None, machine, {}, None, 0.0, limits)


def _home_op(stages: dict) -> ir.Home | None:
    """The block's G74 reference point approach, if it has one."""
    return next((op for op in stages["motion"] if isinstance(op, ir.Home)), None)


def _jump_target(label):
    """A jump's target as the blocks carry it: a label by name, a block number as ``N100``
    (written ``N100`` or ``100``)."""
    if isinstance(label, str) and re.fullmatch(r"N?\d+", label):
        return f"N{int(label.lstrip('N'))}"
    return label
