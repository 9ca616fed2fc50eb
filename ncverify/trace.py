"""What the interpreter reports as it runs, and what rules read: the interpreted trace.

Rules never see program text. They see motion segments (programmed ones and the ones a
cycle makes), holes made by canned cycles, state changes, faults the interpreter itself
detects (a jump to a missing label, a domain error), and the machine state at that moment.
Events stream: nothing here is kept after the rules have looked at it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from . import ir
from .cycle_models import CycleModel
from .source import Span
from .values import Value


@dataclass(slots=True)
class Arc:
    """Geometry of a circular segment in its plane: ``centre`` on the plane's two axes."""

    direction: str  # cw / ccw
    plane: tuple[str, str, str]  # first axis, second axis, normal axis
    centre: tuple[Value, Value] | None
    start_radius: Value | None
    end_radius: Value | None
    radius_word: Value | None = None  # the R word, when the arc was given by radius
    chord: Value | None = None  # start-to-end distance in the plane (R form)
    # Squared distances, exact polynomials when the points depend on free parameters:
    start_radius_sq: Value | None = None
    end_radius_sq: Value | None = None
    chord_sq: Value | None = None


@dataclass(slots=True)
class Segment:
    """One straight or circular move. Positions are in the program's work coordinates;
    an axis whose position is unknown (before the first absolute move, after a reference
    return) is ``None``. ``role`` says where it came from: ``programmed``, ``reference``, or a
    cycle's ``approach`` / ``infeed`` / ``out-of-hole`` (back up the hole just made) /
    ``retract`` / ``between-holes`` / ``through-bore`` (G87 down a pre-bored hole) /
    ``contour`` / ``shift``."""

    kind: str  # rapid, feed, arc, thread
    start: dict[str, Value | None]
    end: dict[str, Value | None]
    span: Span
    block: ir.Block
    role: str = "programmed"
    cycle: str | None = None
    arc: Arc | None = None


RUN_AXES = ("X", "Y", "Z")  # the columns of a run made of moves the block path gathered (and a gathered move's first fields)
ROTARY_AXES = frozenset("ABC")  # a rotary table's or a swivelling head's axes


@dataclass(slots=True)
class MotionRun:
    """Many segments at once (a batch of plain blocks): ``points[0]`` is where the run
    starts, ``points[k + 1]`` where segment ``k`` ends, NaN where unknown; ``kinds[k]`` is 0
    for rapid, 1 for feed, 2 for a clockwise and 3 for a counter-clockwise arc; ``feeds[k]``
    the feed in force (NaN: none); ``written[k]`` which axes segment ``k``'s block wrote.
    ``arcs`` (None when there is no arc) holds the arcs' plane, centres and radius words
    (:class:`ncverify.interpret.interpreter.BatchArcs`). ``span(k)`` and ``segment(k)``
    build the per-segment objects on demand (an arc's with the same Arc the block path
    makes), for reports and for rules without a run handler. A part of a run (:meth:`part`)
    knows the whole run and where in it it starts. ``cycle_moves``: the moves are a canned
    cycle's (each segment carries its role and cycle), not the program's own."""

    axes: tuple[str, ...]
    points: object
    kinds: object
    feeds: object
    written: object
    span: object  # Callable[[int], Span]
    segment: object  # Callable[[int], Segment]
    arcs: object = None
    state_at: object = None  # Callable[[Segment, int], None]: the state as the block path has it at a segment
    whole: "MotionRun | None" = None  # the run this one is a part of (None: it is whole)
    first: int = 0  # where in the whole run it starts
    cycle_moves: bool = False

    def __len__(self) -> int:
        return len(self.kinds)

    def arc_indices(self) -> list[int]:
        return (self.kinds >= ARC_CW).nonzero()[0].tolist()

    def pieces(self):
        """``(start, stop, straight)``: the run in order, cut into stretches of straight
        segments and single arcs."""
        start = 0
        for index in self.arc_indices():
            if index > start:
                yield start, index, True
            yield index, index + 1, False
            start = index + 1
        if start < len(self.kinds):
            yield start, len(self.kinds), True

    def part(self, start: int, stop: int) -> "MotionRun":
        """Straight segments ``start`` to ``stop`` (not included) as a run of their own."""
        whole = self.whole or self
        first = self.first + start
        return MotionRun(self.axes, self.points[start : stop + 1], self.kinds[start:stop], self.feeds[start:stop], self.written[start:stop],
                         lambda index: whole.span(first + index), lambda index: whole.segment(first + index), None, None, whole, first, self.cycle_moves)


ARC_CW, ARC_CCW = 2, 3  # MotionRun kind codes of arcs


def any_in_row(mask):
    """``mask.any(axis=1)`` of a boolean array of at least one column, one column at a
    time: numpy's reduction along rows of two to four entries (a run's axes, its arc words)
    costs over ten times more."""
    rows = mask[:, 0].copy()
    for column in range(1, mask.shape[1]):
        rows |= mask[:, column]
    return rows


@dataclass(slots=True)
class Hole:
    """A hole a canned cycle makes, with its levels resolved along the drilling axis."""

    cycle: str
    model: CycleModel
    span: Span
    block: ir.Block
    drill_axis: str
    position: dict[str, Value | None]
    initial: Value | None
    r_point: Value | None
    bottom: Value | None
    params: dict[str, Value]
    param_spans: dict[str, Span] = field(default_factory=dict)
    missing: tuple[str, ...] = ()
    definition: Span | None = None  # the block that made the cycle modal
    repeat: float = 1.0  # the block's repeat count (L, or K on a lathe); each repeat is its own Hole
    up: float = 1.0  # +1: the tool comes from the + side of the drilling axis (the usual); -1: from the - side (Fagor #TOOL AX [Z-])


@dataclass(frozen=True, slots=True)
class CycleFacts:
    """What the rules of a cycle run read beside the program's parameters, where the run
    knows it (the Klartext contour, OCM and cylinder cycles); None or empty where it does not."""

    contour: object = None  # the contour the cycle machines (ncverify.interpret.heidenhain.contour.ContourUse)
    region: object = None  # the area that contour encloses (its pockets less its islands)
    own_q: tuple | None = None  # the Q1-Q20 the program set itself, which the SL cycles overwrite
    last_rougher: Value | None = None  # the tool of the last cycle 22 (what Q438 = -1 of cycle 24 names)
    declared_depths: tuple | None = None  # DECLARE CONTOUR: whether each declaration so far had a DEPTH
    shape: float | None = None  # OCM 272-274: the cycle whose data they machine (271, 1271-1278)
    boundary: float | None = None  # OCM: the boundary cycle since the shape, if any
    rougher_forgotten: bool | None = None  # OCM: no 272 roughing since the contour was defined
    position: dict | None = None  # where the tool stands when the cycle is called
    spindle: str | None = None  # the spindle when the cycle is called
    bad_tolerances: tuple = ()  # (parameter, text) of toleranced sizes the control cannot read


NO_FACTS = CycleFacts()


@dataclass(slots=True)
class CycleRun:
    """A one-shot cycle (lathe G70-G76, G12/G13) with its resolved parameters."""

    cycle: str
    model: CycleModel
    span: Span
    block: ir.Block
    params: dict[str, Value]
    param_spans: dict[str, Span] = field(default_factory=dict)
    first_block: bool = False
    facts: CycleFacts = NO_FACTS


@dataclass(slots=True)
class Fault:
    """A finding the interpreter makes itself (missing label, domain error, bound hit)."""

    rule: str
    span: Span
    message: str
    status: str = "violated"
    reason: str | None = None
    severity: str | None = None  # instead of the rule's own (a guard exit is info)


@dataclass(slots=True)
class Change:
    """A state change rules watch: ``what`` is ``tool_change``, ``cutter_comp``,
    ``length_offset``, ``units``, ``spindle``, ``stop``, ``end``, ``call``, ``thread`` (a G33
    block's other words, evaluated, in ``new``: Q start angle, E lead), ``feed_mode`` /
    ``spindle_mode`` / ``path_mode`` (a G94/G95, G96/G97 or G61-G64 code ran: ``old`` and
    ``new`` values), ``set_position`` (G92/G50 with axis words, evaluated, in ``new``),
    ``data_setting`` (G10: axis words in ``old``, the other words in ``new``), ``transforms``
    (Klartext: the coordinate transformations active, in the order they were defined, before
    and after), ``m_function`` (an M function rules watch, its number in ``new``),
    ``corner_rounding`` (the contour's corner at the tool's position is rounded or chamfered)...
    ``words`` holds other words of the block a rule needs, evaluated (G30 ``P``)."""

    what: str
    span: Span
    block: ir.Block | None
    old: object = None
    new: object = None
    register: Value | None = None
    words: dict | None = None
