"""The public interface a dialect's run-time code drives the interpreter through.

Every cycle, and every Klartext operation that needs the machine state, runs when the
interpreter reaches it, through a few small public methods of a :class:`Runtime` (the shape
of LinuxCNC's rs274ngc canned cycles, which move only through ``cycle_feed`` and
``cycle_traverse``): move the tool, report what the rules should see, transfer control,
read and write variables. The runners a dialect declares in its
:class:`~ncverify.interpret.cycles.DialectCycles`, and the handlers of the IR operations its
run-time module lists in ``OPERATIONS``, receive the
:class:`~ncverify.interpret.cycles.CycleRunner`, which is a :class:`Runtime`; they never
reach into the interpreter's private methods.
"""
from __future__ import annotations

from .. import ir
from ..cycle_models import UNKNOWN_CYCLE, CycleModel
from ..trace import Segment
from ..values import VACANT


def moved_to(start: dict, targets: dict) -> tuple[dict | None, list]:
    """Where a move to ``targets`` from ``start`` ends (a new dict: positions are
    copy-on-write) and the axes it moves, leaving out None values and axes that hold that
    very value already; (None, []) when no axis moves."""
    end = None
    moved = []
    for axis, value in targets.items():
        if value is not None and start.get(axis) is not value:
            if end is None:
                end = dict(start)
            end[axis] = value
            moved.append(axis)
    return end, moved


class Runtime:
    """What a cycle or dialect operation may do to the machine and the trace."""

    def __init__(self, interpreter):
        self._interp = interpreter

    # ------------------------------------------------------------------ machine state

    @property
    def state(self):
        """The path's :class:`~ncverify.interpret.interpreter.MachineState` (forks with the path)."""
        return self._interp.state

    def cycle_model(self, cycle: str) -> CycleModel:
        """The model of a cycle id from the dialect's tables (:data:`UNKNOWN_CYCLE` when there is none)."""
        return self._interp.cycle_models.get(cycle, UNKNOWN_CYCLE)

    def tool_in_spindle(self):
        """The tool-table entry of the tool in the spindle, or None when the tool or its
        entry is not known."""
        return self._interp.tools.in_spindle(self.state)

    # ------------------------------------------------------------------ motion

    def move_to(self, targets: dict, span, block, role: str, cycle: str | None, kind: str = "rapid") -> None:
        """Move the axes of ``targets`` (None values and axes already there are left out) and
        report the segment as ``kind`` (``rapid`` or ``feed``) in its ``role`` of ``cycle``."""
        interpreter = self._interp
        state = interpreter.state
        start = state.position
        end, moved = moved_to(start, targets)
        if end is None:
            return
        # what MachineState.move_to and emit() do, three calls less (a hole makes five moves)
        state.position = end
        if state.parked or state.left_start:
            state.leave_start(moved)
        segment = state.last_segment = Segment(kind, start, end, span, block, role, cycle)
        if cycle is None or not interpreter._gather_segment(segment, moved, state.modal.get("motion"), hole=True):
            interpreter.observer.segment(segment, state)

    def move_through(self, steps: list, span, block, cycle: str) -> None:
        """The moves of ``steps``, each ``(targets, role, kind)`` as :meth:`move_to` takes
        it, one after the other: a hole's, judged with the moves next to them where they may
        be (the conditions asked once for all of them)."""
        if not self._interp._gather_hole_moves(steps, span, block, cycle):
            for targets, role, kind in steps:
                self.move_to(targets, span, block, role, cycle, kind)

    def rapid_to(self, targets: dict, span, block, role: str, cycle: str | None) -> None:
        """A rapid traverse to ``targets`` (see :meth:`move_to`)."""
        self.move_to(targets, span, block, role, cycle, "rapid")

    def feed_to(self, targets: dict, span, block, role: str, cycle: str | None) -> None:
        """A feed move to ``targets`` (see :meth:`move_to`)."""
        self.move_to(targets, span, block, role, cycle, "feed")

    def emit(self, kind: str, start: dict, span, block, role: str = "programmed", cycle: str | None = None, arc=None, written=None) -> None:
        """Report the move from ``start`` to the current position (an arc with its
        :class:`~ncverify.trace.Arc`) to every motion rule. ``written``, the axes the block
        wrote, marks a programmed contour element that leaves the motion mode alone and
        changes no other state a rule reads: it may reach the rules with the moves next to
        it, as one run."""
        self._interp._emit(kind, start, span, block, role, cycle, arc, written)

    # ------------------------------------------------------------------ what the rules see

    @property
    def loop_bound(self) -> int:
        """How often one loop may run (``--loop-bound``): also the most holes one pattern may make."""
        return self._interp.settings.loop_bound

    def within_loop_bound(self, count, span, what: str) -> bool:
        """Whether a pattern or repeat of ``count`` holes (points, positions) stays within
        the loop bound, as the iterations of a loop must. One past it (or not a number) is
        not expanded, which would take time and memory without end: the finding
        ``core.loop-bound`` says so, and the caller leaves its points unknown."""
        bound = self.loop_bound
        if count <= bound:
            return True
        self.fault("core.loop-bound", span, f"{what} makes {count:,.0f} holes, more than the loop bound of {bound:,}: they are not placed and "
                   "none of them is checked", "unknown", f"loop bound {bound} reached")
        return False

    def fault(self, rule: str, span, message: str, status: str = "violated", reason: str | None = None) -> None:
        """A finding of ``rule`` at ``span``."""
        self._interp._fault(rule, span, message, status, reason)

    def unfollowed(self, why: str, before_moves: bool = False) -> None:
        """The program changed state the model does not follow
        (:meth:`~ncverify.interpret.Interpreter.unfollowed`)."""
        self._interp.unfollowed(why, before_moves)

    def unsupported(self, span, what: str) -> None:
        """A construct read but not modelled here: what depends on it answers unknown."""
        self._interp._unsupported_here(span, what)

    def note(self, note: ir.Note) -> None:
        """A finding the lowering wrote for the case that the path reaches it."""
        self._interp.observer.note(note)

    def change(self, what: str, span, block, old=None, new=None) -> None:
        """A state change the rules watch (``spindle``, ``transforms``, ...)."""
        self._interp._change(what, span, block, old, new)

    def report_cycle(self, run) -> None:
        """A :class:`~ncverify.trace.CycleRun`: the cycle runs here with these parameters."""
        self._interp.observer.cycle_run(run, self.state)

    def report_hole(self, hole) -> None:
        """A :class:`~ncverify.trace.Hole`, before the segments that make it."""
        self._interp.observer.hole(hole, self.state)

    # ------------------------------------------------------------------ operations and control flow

    def execute(self, op: ir.Op, block):
        """Run one IR operation as if the program had it in ``block`` (a spindle or
        compensation change a dialect operation makes); returns what its handler returns."""
        return self._interp._handlers[type(op)](op, block)

    def run_lowered(self, ops: list, notes: list, block):
        """Run the ops of a block whose lowering waited for the state where it runs (and
        report its notes); returns where execution goes next, None for the next op."""
        return self._interp.run_lowered(ops, notes, block)

    def cancel_cycle(self) -> None:
        """The modal canned cycle ends (its data goes with it)."""
        self._interp._cancel_cycle()

    def set_frame(self, frame) -> None:
        """Make ``frame`` (:class:`ncverify.frames.Frame`) the program-to-workpiece map."""
        self._interp.set_frame(frame)

    def call_subprogram(self, op: ir.Call, block):
        """Call a subprogram or label: returns the position where execution continues."""
        return self._interp._call(op, block)

    def return_from(self, op: ir.Return, block):
        """Return from the running subprogram (or end the main program)."""
        return self._interp._return(op, block)

    def end_program(self, span, block, how: str):
        """The program ends here (``how``: the change reported); the path stops."""
        return self._interp._program_end(span, block, how)

    def find_label(self, label, span):
        """The position of the block carrying ``label`` (a finding when there is none)."""
        return self._interp.find_label(label, span)

    def find_program(self, name, span):
        """``(source, offset)`` of a program by name, in the file or on the search path, or None."""
        return self._interp._find_program(name, span)

    def count_jump(self, target, span, what: str) -> None:
        """Count one more jump back to ``target``: past the loop bound the path stops."""
        self._interp._count_jump(target, span, lambda: what)

    @property
    def frontend(self):
        """The dialect's frontend: blocks of a line, label offsets, label descriptions."""
        return self._interp.frontend

    @property
    def main_source(self):
        """The program the analysis started from."""
        return self._interp.source

    @property
    def current_source(self):
        """The program the current block is in."""
        return self._interp._line_source

    @property
    def current_offset(self) -> int:
        """The byte offset of the current block's line in :attr:`current_source`."""
        return self._interp._line_offset

    # ------------------------------------------------------------------ values

    def value(self, expr, span=None):
        """An expression's value (a vacant variable reads as 0, with a finding where the
        control would compute with it)."""
        return self._interp.value(expr, span)

    def words(self, exprs: dict, span=None) -> dict:
        """The values of written words by name (:meth:`value` of each), vacant ones left out."""
        evaluated = {}
        for name, expr in exprs.items():
            value = self._interp.value(expr, span)
            if value is not VACANT:
                evaluated[name] = value
        return evaluated

    def evaluate(self, expr, span=None):
        """An expression's value, vacant kept as :data:`ncverify.values.VACANT`."""
        return self._interp.evaluate(expr, span)

    def read_variable(self, var: ir.Var, span=None):
        return self._interp.read_variable(var, span)

    def write_variable(self, var: ir.Var, value, span=None) -> None:
        self._interp.write_variable(var, value, span)
