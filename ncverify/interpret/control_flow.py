"""Control flow of the interpreter: branches, jumps, loops, labels, programs, calls and returns.

Control flow follows the program: jumps, loops and calls are resolved through the dialect
front end by byte offset, so straight-line code streams and memory does not grow with it.
A branch whose condition depends on free parameters forks the path (up to
``Settings.max_paths``); every loop, jump chain and call nest is bounded, and hitting a
bound is a finding, never a hang. After every path has run, the lines none of them reached
are read for their syntax findings.

:class:`ControlFlow` is a mixin of :class:`~ncverify.interpret.Interpreter`: its methods
are the handlers of the control-flow operations and use the interpreter's state,
expression evaluation and reporting.
"""
from __future__ import annotations

from dataclasses import dataclass

from .. import ir, values
from ..dialect import logical_lines
from ..source import ProgramSource, Span
from ..solver import z3
from ..trace import Fault
from ..values import VACANT, Condition

# Fanuc argument specification I: G65 letters to local variables.
_ARGUMENT_VARIABLES = {
    "A": 1, "B": 2, "C": 3, "I": 4, "J": 5, "K": 6, "D": 7, "E": 8, "F": 9, "H": 11, "M": 13,
    "Q": 17, "R": 18, "S": 19, "T": 20, "U": 21, "V": 22, "W": 23, "X": 24, "Y": 25, "Z": 26,
}


class PathEnd(Exception):
    """The current path stops (program end, alarm, bound hit)."""


@dataclass(slots=True)
class Position:
    """Where execution is: a line's offset in a source and the block / op inside it."""

    source: ProgramSource
    offset: int
    block_index: int = 0
    op_index: int = 0


@dataclass(slots=True)
class CallFrame:
    """A subprogram or macro call on the stack."""

    kind: str  # main, subprogram, macro, local
    program: str
    source: ProgramSource
    start: int  # offset of the program's first line
    return_to: Position | None
    repeats_left: int = 0
    local_variables: dict | None = None  # a macro's own #1-#33; None shares the caller's
    called_at: Span | None = None  # the calling block, for findings in another file


@dataclass(slots=True)
class LoopFrame:
    loop_id: int
    head: Position
    iterations: int = 0


class ControlFlow:
    """Where execution goes next; mixed into :class:`~ncverify.interpret.Interpreter`."""

    # ------------------------------------------------------------------ where execution is

    def _next_position(self) -> Position:
        return self._current_position(self._op_index + 1)

    def _current_position(self, op_index: int) -> Position:
        return Position(self._line_source, self._line_offset, self._block_index, op_index)

    def _path_name(self, source: ProgramSource) -> str | None:
        """The file name spans carry for ``source``: None for the program being checked."""
        return None if source is self.source else source.name

    # ------------------------------------------------------------------ branching

    def _decide(self, condition, span, resume_false) -> bool:
        """Decide a branch. A symbolic condition forks: this path takes ``True`` (and its
        path condition records it), a copy takes ``False`` from ``resume_false()`` (a
        callable, since finding that position can mean reading ahead)."""
        if type(condition) is bool:
            return condition
        if self.paths_started + len(self._forks) >= self.settings.max_paths:
            self._fault("core.path-limit", span, f"the branch depends on {', '.join(sorted(_condition_parameters(condition)))}; "
                        f"more than {self.settings.max_paths} paths: this branch was not explored both ways", "unknown",
                        "path budget exhausted (max_paths)")
            raise PathEnd
        self._hand_on_gathered()  # the moves before the branch belong to both paths: judged once, before the copy
        twin = self.state.fork()
        twin.path_condition.append(values.negate(condition))
        self._forks.append((twin, resume_false()))
        self.state.path_condition.append(condition)
        return True

    def _conditional(self, op: ir.Conditional, block):
        condition = self.condition(op.condition, op.span)
        if self._decide(condition, op.span, self._next_position):
            for inner in op.then:
                transfer = self._handlers[type(inner)](inner, block)
                if transfer is not None:
                    return transfer
        return None

    # ------------------------------------------------------------------ jumps and loops

    def _jump(self, op: ir.Jump, block):
        if op.condition is not None:
            condition = self.condition(op.condition, op.span)
            if not self._decide(condition, op.span, self._next_position):
                return None
        target = op.target if type(op.target) is str else self.evaluate(op.target, op.span)  # a label as written is its own value
        if type(target) not in (float, str):
            self._unsupported_here(op.span, "a jump whose target depends on a free parameter")
            raise PathEnd
        if op.optional and not self.label_exists(target):
            return None  # GOTOC: no alarm, the next block runs
        position = self.find_label(target, op.span, direction=op.direction, branch=True)
        self._count_jump(position, op.span, lambda: f"the jump to {self.frontend.describe_label(target)}")
        return position

    def _count_jump(self, position: Position, span, what) -> None:
        """Count one more jump to ``position``: past the loop bound the path stops, with a
        finding naming the jump by ``what()`` (worked out only then)."""
        key = (id(position.source), position.offset, position.block_index)
        counts = self.state.jump_counts
        count = counts[key] = counts.get(key, 0) + 1
        if count > self.settings.loop_bound:
            self._fault("core.loop-bound", span, f"{what()} was taken {self.settings.loop_bound:,} times without the loop ending; the rest of this path is not analysed",
                        "unknown", f"loop bound {self.settings.loop_bound} reached")
            raise PathEnd

    def _loop_start(self, op: ir.LoopStart, block):
        condition = self.condition(op.condition, op.span)
        head = self._current_position(self._op_index)
        state = self.state
        frame = next((loop for loop in state.loops if loop.loop_id == op.loop_id and loop.head == head), None)
        if self._decide(condition, op.span, lambda: self._find_loop_end(op.loop_id, op.span)):
            if frame is None:
                state.loops.append(LoopFrame(op.loop_id, head))
            return None
        return self._exit_loop(op, frame)

    def _exit_loop(self, op: ir.LoopStart, frame):
        if frame is not None:
            self.state.loops.remove(frame)
        return self._find_loop_end(op.loop_id, op.span)

    def _loop_end(self, op: ir.LoopEnd, block):
        state = self.state
        for frame in reversed(state.loops):
            if frame.loop_id == op.loop_id:
                frame.iterations += 1
                if frame.iterations >= self.settings.loop_bound:
                    self._fault("core.loop-bound", op.span, f"the loop that ends here ran {self.settings.loop_bound:,} times without its condition becoming false; "
                                "the rest of this path is not analysed", "unknown", f"loop bound {self.settings.loop_bound} reached")
                    raise PathEnd
                return frame.head
        self._fault("core.label-not-found", op.span, f"END{op.loop_id} has no matching WHILE ... DO{op.loop_id} before it")
        return None

    def _find_loop_end(self, loop_id: int, span) -> Position:
        source = self._line_source
        depth = 0
        path = self._path_name(source)
        start_offset, start_block = self._line_offset, self._block_index + 1
        for line_number, offset, _next, raw in logical_lines(source, start_offset, self.frontend):
            blocks = self.frontend.blocks(raw, line_number, path)
            for index in range(start_block if offset == start_offset else 0, len(blocks)):
                for op in blocks[index].ops:
                    if isinstance(op, ir.LoopStart) and op.loop_id == loop_id:
                        depth += 1
                    elif isinstance(op, ir.LoopEnd) and op.loop_id == loop_id:
                        if depth == 0:
                            return Position(source, offset, index + 1)
                        depth -= 1
        self._fault("core.label-not-found", span, f"DO{loop_id} has no matching END{loop_id}: the control alarms when the loop ends")
        raise PathEnd

    # ------------------------------------------------------------------ programs and labels

    def _main_program(self) -> tuple[str, int, bool]:
        """The program to run: the first one that is not a subprogram (M99 and no M02/M30);
        when every program in the file is a subprogram, the first, run as a called program
        whose feed and spindle come from a caller we cannot see."""
        programs = self._program_index(self.source)
        if not programs:
            stored_as_subprogram = getattr(self.frontend, "stored_as_subprogram", None)
            return "main", 0, stored_as_subprogram is not None and stored_as_subprogram(self.source.name)
        buffer = self.source.buffer
        offsets = sorted(programs.values()) + [len(buffer)]
        names = sorted(programs, key=programs.get)
        for name in names:
            start = programs[name]
            end = offsets[offsets.index(start) + 1]
            if not self.frontend.is_subprogram(buffer, start, end):
                return name, (0 if start == offsets[0] else start), False
        return names[0], 0, True

    def _program_index(self, source: ProgramSource) -> dict[str, int]:
        key = id(source)
        if key not in self.programs:
            index: dict[str, int] = {}
            for name, offset in self.frontend.programs(source.buffer):
                index.setdefault(name, offset)
            self.programs[key] = index
        return self.programs[key]

    def _is_first_program(self, source: ProgramSource, offset: int) -> bool:
        programs = self._program_index(source)
        return bool(programs) and min(programs.values()) == offset

    def _program_bounds(self, source: ProgramSource, start: int) -> tuple[int, int]:
        """The program that begins at ``start`` runs to the next program header; a main
        program read from the top of the file owns the first header too."""
        extent = getattr(self.frontend, "program_extent", None)
        if extent is not None:  # programs that nest in the main code (LinuxCNC subroutines)
            return start, extent(source.buffer, start)
        offsets = sorted(self._program_index(source).values())
        own_header = offsets[0] if offsets and start <= offsets[0] else start
        later = [offset for offset in offsets if offset > own_header]
        return start, (later[0] if later else len(source))

    def _find_program(self, number: float | str, span) -> tuple[ProgramSource, int] | None:
        name = self.frontend.program_name(number)
        for source in (self._line_source, self.source):
            offset = self._program_index(source).get(name)
            if offset is not None:
                return source, offset
        if self.library is not None:
            found = self.library.find(name)
            if found is not None:
                source = found
                offset = self._program_index(source).get(name, 0)
                return source, offset
        return None

    def label_exists(self, label) -> bool:
        """Does the running program carry ``label`` anywhere?"""
        frame = self.state.call_stack[-1]
        key = (id(frame.source), frame.program, label)
        if key not in self.label_cache:
            self.label_cache[key] = self._scan_label(frame.source, frame, label)
        return bool(self.label_cache[key])

    def find_label(self, label: float, span, source: ProgramSource | None = None, frame: CallFrame | None = None,
                   direction: str | None = None, branch: bool = False) -> Position:
        """The block carrying ``label``. ``direction`` ``forward`` / ``backward`` searches
        only that way from the current block and takes the nearest (SINUMERIK GOTOF/GOTOB,
        where a label may repeat); ``nearest`` tries forward, then backward (GOTO);
        ``backward-first`` backward, then forward (SINUMERIK REPEAT). Without a direction a
        repeated number is a finding; for a ``branch`` (GOTO) only where the landing is
        doubtful (``_landing_doubtful``)."""
        frame = frame or self.state.call_stack[-1]
        source = source or frame.source
        current = self._line_offset if source is self._line_source else -1
        landing_key = (id(source), frame.program, label, current, direction, branch)
        landing = self.landing_cache.get(landing_key)
        if landing is not None:
            return landing  # this jump was taken before from here, without a finding (a loop's jump back)
        key = (id(source), frame.program, label)
        found = self.label_cache.get(key)
        if found is None:
            found = self._scan_label(source, frame, label)
            self.label_cache[key] = found
        if not found:
            self._fault("core.label-not-found", span, f"label {self.frontend.describe_label(label)} is not in program {frame.program}: the control alarms here")
            raise PathEnd
        after = [position for position in found if position.offset > current]
        if direction is not None:
            before = [position for position in found if position.offset < current]
            nearest = {"forward": after[:1], "backward": before[-1:], "backward-first": before[-1:] or after[:1]}.get(direction, after[:1] or before[-1:])
            if not nearest:
                self._fault("core.label-not-found", span, f"{self.frontend.describe_label(label)} is not {'after' if direction == 'forward' else 'before'} this block in {frame.program}: the control alarms here")
                raise PathEnd
            self.landing_cache[landing_key] = nearest[0]
            return nearest[0]
        if len(found) > 1 and (not branch or self._landing_doubtful(source, current, found, after)):
            self.observer.fault(Fault("core.duplicate-label", span, f"{self.frontend.describe_label(label)} appears {len(found)} times in {frame.program}; the jump goes to the first one after the current block"))
        else:
            self.landing_cache[landing_key] = (after or found)[0]
        return (after or found)[0]

    def _landing_doubtful(self, source: ProgramSource, current: int, found: list[Position], after: list[Position]) -> bool:
        """A GOTO to a number that several blocks carry lands on the nearest copy after it,
        else on the first from the top: that is deterministic, and macros reuse numbers on
        purpose as local forward labels. It is doubtful only where a copy it does not land on
        is the plausible target: it wraps to the top past a nearer copy behind it (a loop
        meant to close on that one), or a copy stands behind it and the landing is the block
        that runs next anyway (a jump that skips nothing: a loop head taken by a later copy)."""
        before = [position for position in found if position.offset < current]
        if not after:
            return len(before) > 1
        return bool(before) and self._runs_next(source, current, after[0])

    def _runs_next(self, source: ProgramSource, current: int, landing: Position) -> bool:
        """Is ``landing`` the first block after the line at ``current`` (only empty or comment
        lines between)?"""
        line_end = source.buffer.find(b"\n", current)
        if line_end < 0 or landing.block_index:
            return False
        path = self._path_name(source)
        first_line = source.line_number_at(line_end + 1)
        between = bytes(source.buffer[line_end + 1 : landing.offset]).splitlines()
        return not any(block.ops or block.label is not None
                       for number, raw in enumerate(between, first_line)
                       for block in self.frontend.blocks(raw.rstrip(b"\r"), number, path))

    def _scan_label(self, source: ProgramSource, frame: CallFrame, label: float) -> list[Position]:
        start, end = self._program_bounds(source, frame.start)
        path = self._path_name(source)
        found = []
        for offset in self.frontend.label_offsets(source.buffer, label):
            if not start <= offset < end:
                continue
            line_number = source.line_number_at(offset)
            newline = source.buffer.find(b"\n", offset)
            raw = bytes(source.buffer[offset : len(source.buffer) if newline < 0 else newline]).rstrip(b"\r")
            for index, block in enumerate(self.frontend.blocks(raw, line_number, path)):
                if block.label == label:
                    found.append(Position(source, offset, index))
        return found

    # ------------------------------------------------------------------ calls and returns

    def _call(self, op: ir.Call, block):
        state = self.state
        repeat = self.evaluate(op.repeat, op.span)
        repeat = 1 if repeat is VACANT else repeat
        if type(repeat) is not float:
            self._unsupported_here(op.span, "a call whose repeat count depends on a free parameter")
            raise PathEnd
        if op.most_repeats is not None and not 0 <= repeat <= op.most_repeats:
            self._fault("core.repeat-count-range", op.span, f"repeat count L{repeat:g} is outside 0-{op.most_repeats:g}")
        if repeat < 1:
            return None
        if op.kind == "local":
            return self._local_call(op, block, int(repeat))
        program = self.evaluate(op.program, op.span)
        if not (type(program) is str or (type(program) is float and program >= 0)):
            self._fault("core.program-not-found", op.span, "the call names no program number (P missing)")
            return None
        found = self._find_program(program, op.span)
        if found is None:
            self._program_not_here(program, op.span)
            return None
        source, start = found
        if len(state.call_stack) > self.settings.call_depth:
            self._fault("core.call-depth", op.span, f"calls nest deeper than {self.settings.call_depth} levels (recursion through {self.frontend.program_name(program)}?): the control alarms")
            raise PathEnd
        local_variables = None
        if op.kind == "macro":
            local_variables = self._macro_arguments(op)
        elif op.kind == "proc":
            local_variables = self._proc_arguments(op, source, start)
        frame = CallFrame(op.kind, self.frontend.program_name(program), source, start, self._next_position(), int(repeat) - 1,
                          called_at=op.span)
        if local_variables is not None:
            frame.local_variables = state.local_variables
            state.local_variables = local_variables
        state.call_stack.append(frame)
        self._change("call", op.span, block, None, frame.program)
        entry = Position(source, start)
        if op.start_label is not None:
            label = self.evaluate(op.start_label, op.span)
            if type(label) is float:
                return self.find_label(label, op.span, source, frame)
        return entry

    def call_site(self) -> Span | None:
        """Where the main file called into another file, on the current path (the outermost
        such call): a finding in the called file is reported with it."""
        for frame in self.state.call_stack:
            if frame.source is not self.source and frame.called_at is not None:
                return frame.called_at
        return None

    def _program_not_here(self, program, span) -> None:
        """A called program this run cannot read: it may be stored on the control (a CALL
        PGM TNC:\\..., a G65 P9xxx macro library, an OEM cycle), so what it does is
        ``unknown``, never an alarm; where the search path holds several files with that
        program they are named. Afterwards position, feed and spindle are what it left."""
        name = self.frontend.program_name(program)
        candidates = self.library.candidates(name) if self.library is not None else []
        if len(candidates) > 1:
            files = ", ".join(path.name for path in candidates)
            self._fault("core.program-not-found", span, f"program {name} called here is in several files of the search path ({files}): which one the control holds is not known, so it is not analysed",
                        "unknown", f"{len(candidates)} candidates for {name}; name the folder that holds this program's subprograms with --subprogram-path or [settings] subprogram_path")
        else:
            self._fault("core.program-not-found", span, f"program {name} called here is not available here: what it does is not analysed",
                        "unknown", "it may be stored on the control; give its folder with --subprogram-path")
        state = self.state
        state.move_to(dict.fromkeys(state.position))
        state.feed_inherited, state.spindle = True, "inherited"  # it may set feed and spindle
        self.unfollowed(f"program {name} was not analysed: it may have written an offset or tool data (probing and tool-setting macros do)", before_moves=True)

    def _macro_arguments(self, op: ir.Call) -> dict:
        arguments = {}
        for letter, expr in op.arguments.items():
            number = _ARGUMENT_VARIABLES.get(letter)
            if number is None and len(letter) < 2:
                self._fault("core.syntax", op.span, f"address {letter} cannot pass a G65 argument")
                continue
            value = self.evaluate(expr, op.span)
            if value is not VACANT:
                arguments[f"#{number}" if number is not None else letter] = value  # a variable name as is (Fagor #PCALL P0-P25)
        return arguments

    def _proc_arguments(self, op: ir.Call, source: ProgramSource, start: int) -> dict:
        """A call by name with positional arguments (SINUMERIK ``NAME(a, b)``): the called
        program's own variables start as its formal parameters (``frontend.proc_parameters``);
        an omitted argument is 0. A parameter passed by reference (``VAR``) writes back to the
        caller's variable, which is not followed."""
        arguments = {}
        for index, (name, by_reference) in enumerate(self.frontend.proc_parameters(source.buffer, start)):
            value = self.evaluate(op.arguments.get(str(index), 0.0), op.span)
            arguments[name] = 0.0 if value is VACANT else value
            if by_reference:
                self.unfollowed(f"{op.program} takes {name} by reference (VAR): what it writes back to the caller's variable is not followed", before_moves=True)
        return arguments

    def _local_call(self, op: ir.Call, block, repeat: int):
        label = self.evaluate(op.program, op.span)
        if type(label) not in (float, str):
            self._fault("core.label-not-found", op.span, "the call names no label (M97 without P?)")
            return None
        current = self.state.call_stack[-1]
        target = self.find_label(label, op.span, direction=op.direction)
        if len(self.state.call_stack) > self.settings.call_depth:
            self._fault("core.call-depth", op.span, f"calls nest deeper than {self.settings.call_depth} levels (recursion through "
                        f"{self.frontend.describe_label(label)}?): the control alarms")
            raise PathEnd
        frame = CallFrame("local", current.program, current.source, current.start, self._next_position(), repeat - 1)
        frame.local_variables = None
        self.state.call_stack.append(frame)
        frame.start = target.offset
        return target

    def _return(self, op: ir.Return, block):
        state = self.state
        frame = state.call_stack[-1]
        if op.local_only and frame.kind != "local":
            return None
        if frame.kind == "called":
            self._program_end(op.span, block, "return")
        if frame.kind == "main":
            self._fault("core.m99-in-main", op.span, "M99 in the main program restarts it from the top: it repeats without end (bar feeder loop?)")
            self._program_end(op.span, block, "m99")
        if frame.repeats_left > 0:
            frame.repeats_left -= 1
            self._count_jump(Position(frame.source, frame.start), op.span, lambda: f"the repeat of {frame.program}")
            return Position(frame.source, frame.start)
        state.call_stack.pop()
        if frame.local_variables is not None:
            state.local_variables = frame.local_variables
        self._change("return", op.span, block, frame.program, None)
        if op.to_label is not None:
            label = self.evaluate(op.to_label, op.span)
            if type(label) is float:
                return self.find_label(label, op.span)
        return frame.return_to

    # ------------------------------------------------------------------ program ends

    def _stop(self, op: ir.Stop, block):
        self._change("stop", op.span, block, None, op.kind)
        if op.kind == "end":
            self._reset_at_end(op.resets)
            self._program_end(op.span, block, "end")
        return None

    def _reset_at_end(self, resets: tuple) -> None:
        """What the control's program end puts back before the next program (LinuxCNC's M2
        and M30: the motion mode to G1, so no canned cycle, and cutter compensation off)."""
        if "cycle" in resets:
            self._cancel_cycle()
        if "cutter_comp" in resets:
            self.state.comp_side, self.state.comp_register = "off", None

    def _program_file_end(self, op: ir.ProgramEnd, block):
        """The end of a program file (Klartext END PGM) ends the main program like M30 and
        returns from a called one."""
        call_stack = self.state.call_stack
        while call_stack[-1].kind == "local" and len(call_stack) > 1:
            call_stack.pop()  # a subprogram without a return that runs into the end of its file ends with it
        if call_stack[-1].kind in ("main", "called"):
            self._program_end(op.span, block, "end")
        return self._return(ir.Return(op.span), block)

    def _program_end(self, span, block, how: str):
        self._change("end", span, block, None, how)
        raise PathEnd

    def _end_of_text(self, source: ProgramSource):
        resume = self._ran_off_the_end(source)
        if resume is not None:
            return resume
        raise PathEnd

    def _ran_off_the_end(self, source: ProgramSource) -> Position | None:
        """Report a program whose text ends without its end code; where the control's
        behaviour there is not known, continue at the caller (see :meth:`_unended_subprogram`)."""
        frame = self.state.call_stack[-1]
        last_line = max(source.line_number_at(len(source)) - (1 if source.buffer[-1:] == b"\n" else 0), 1) if len(source) else 1
        span = Span(last_line, 1, last_line, 1, self._path_name(source))
        text_end_ends = getattr(self.frontend, "text_end_ends_program", None)
        if frame.kind == "main" and text_end_ends is not None and text_end_ends(bytes(source.buffer)):
            self._change("end", span, None, None, "eof")
            return None
        if self._subprogram_end_unknown(frame):
            return self._unended_subprogram(frame, span, "ends")
        program, end_code = _unended(frame, self.frontend)
        self._fault("core.program-end-missing", span, f"{program} ends without {end_code}: the control stops at the end of the text with the spindle and coolant as they are")
        self._change("end", span, None, None, "eof")
        return None

    def _program_ran_into_next(self, block: ir.Block, frame: CallFrame) -> Position:
        if self._subprogram_end_unknown(frame):
            resume = self._unended_subprogram(frame, block.span, f"runs into program {block.program_start}")
            if resume is not None:
                return resume
            raise PathEnd
        program, end_code = _unended(frame, self.frontend)
        self._fault("core.program-end-missing", block.span, f"{program} runs into program {block.program_start} without {end_code}")
        self._change("end", block.span, block, None, "eof")
        raise PathEnd

    def _subprogram_end_unknown(self, frame: CallFrame) -> bool:
        return frame.kind != "main" and getattr(self.frontend, "subprogram_text_end", "violated") == "unknown"

    def _unended_subprogram(self, frame: CallFrame, span: Span, how: str) -> Position | None:
        """A subprogram whose text ends without its return, on a control whose manual does not
        say what happens there: ``unknown``; a caller in the check goes on after the call (what
        follows is checked as if the control returned), a file checked alone ends there."""
        program, end_code = _unended(frame, self.frontend)
        self._fault("core.program-end-missing", span, f"{program} {how} without {end_code}", status="unknown",
                    reason=f"the manual does not say what the control does at the end of a subprogram without {end_code}; end it with {end_code.replace('/', ' or ')}")
        if frame.return_to is None:
            self._change("end", span, None, None, "eof")
            return None
        return self._return(ir.Return(span), None)

    def _closes_tape(self, source: ProgramSource, offset: int) -> bool:
        marks = self._tape_marks(source)
        return offset in marks and marks.index(offset) % 2 == 1

    # ------------------------------------------------------------------ tape marks and unread text

    def _tape_marks(self, source: ProgramSource) -> list[int]:
        key = ("tape", id(source))
        if key not in self.programs:
            self.programs[key] = self.frontend.tape_marks(source.buffer)
        return self.programs[key]

    def _off_tape(self, source: ProgramSource) -> list[tuple[int, int]]:
        """Text after a closing '%' and before the next opening one: no control reads it."""
        marks = self._tape_marks(source)
        closings = marks[1::2]
        openings = marks[2::2] + [len(source)]
        return [(closing, opening) for closing, opening in zip(closings, openings)]

    def _sweep_unvisited(self) -> None:
        """Read the lines no path reached, for their syntax findings only."""
        by_source: dict[int, tuple[ProgramSource, list]] = {}
        for source, start, end in self.visited:
            by_source.setdefault(id(source), (source, []))[1].append((start, end))
        by_source.setdefault(id(self.source), (self.source, []))
        for source, ranges in by_source.values():
            path = self._path_name(source)
            for start, end in _gaps(sorted(ranges + self._off_tape(source)), len(source)):
                for line_number, offset, _next, raw in logical_lines(source, start, self.frontend):
                    if offset >= end:
                        break
                    for block in self.frontend.blocks(raw, line_number, path):
                        for note in block.notes:
                            self.observer.note(note)


def _unended(frame: CallFrame, frontend) -> tuple[str, str]:
    """How a message names the program of ``frame``, and the code that should end it."""
    program = frame.program if frame.program != "main" else "the program"
    return program, "M02/M30" if frame.kind == "main" else getattr(frontend, "subprogram_end", "M99")


def _gaps(ranges: list[tuple[int, int]], size: int):
    position = 0
    for start, end in ranges:
        if start > position:
            yield position, start
        position = max(position, end)
    if position < size:
        yield position, size


def _condition_parameters(condition: Condition) -> set[str]:
    found = set()
    seen = set()  # a term shares its sub-terms: walked as a tree, a loop's sums take exponential time

    def walk(term):
        if term.get_id() in seen:
            return
        seen.add(term.get_id())
        if z3.is_const(term) and term.decl().kind() == z3.Z3_OP_UNINTERPRETED:
            found.add(values.readable(str(term)))
        for child in term.children():
            walk(child)

    walk(condition.term)
    return found or {"a free parameter"}
