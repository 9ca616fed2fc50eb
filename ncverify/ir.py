"""The dialect-neutral intermediate representation every reader lowers to.

A program is a stream of :class:`Block` objects, one per source block, each holding the
operations that block commands, **in the order the control executes them** (feed mode,
feed, spindle speed, tool, spindle, coolant, plane, units, compensation, cycles, distance
mode, work offset, motion, stops, as LinuxCNC and the ISO manuals order a block). The
interpreter runs blocks one by one; control flow (jumps, loops, calls) names its target and
the interpreter resolves it through the reader, so straight-line code is never held whole.

Values inside operations are :data:`Expr` trees, not numbers: a word may read a parameter
the program computes at run time. Expressions are evaluated by the interpreter against
the machine state; literal numbers are plain ``float`` for speed.

Operations (all carry the ``span`` of the words they came from):

==================  =====================================================================
``SetModal``        a modal group changes: plane, units, distance, feed mode, path mode,
                    cycle return level, spindle speed mode, arc centre mode
``Move``            motion: ``kind`` is rapid / linear / arc_cw / arc_ccw / thread, or
                    ``None`` for "the modal motion" (ISO blocks that only carry axis words;
                    with a canned cycle modal this drills a hole). ``targets`` maps axis
                    letters to values as written (absolute or incremental per the modal
                    distance mode, unless listed in ``incremental``); ``arc`` carries
                    centre offsets or a radius; ``words`` the other address words of the
                    block (R, Q, P, L, K, comma words) that a modal cycle consumes
``Dwell``           a pause, in seconds or spindle revolutions
``CutterComp``      radius compensation left / right / auto / off, with its register
``LengthOffset``    tool length offset plus / minus / off, with its register
``WorkOffset``      selects a work coordinate system (G54.., or a numbered one)
``CoordinateShift`` sets a coordinate shift without motion (G92, G52, datum shifts)
``SetFrame``        a programmable coordinate transformation (SINUMERIK TRANS/ROT/SCALE/
                    MIRROR and their A- forms, G58/G59): ``component`` translation /
                    rotation / scale / mirror / reset / unknown (a transformation not
                    modelled: positions after it are unknown) / swivel and swivel_off (a
                    tilted plane, kept apart from the programmable frame: unknown while
                    on); ``additive`` appends it in
                    the current system instead of replacing the frame; ``values`` per axis
                    (rotation: ``RPL`` or the plane's normal axis, in degrees); ``layer`` ``coarse`` /
                    ``fine`` for the axial G58 / G59 translations. Klartext cycles 7-26
                    and TRANS set the same frame from their runner (:mod:`ncverify.frames`)
``ReferenceReturn`` returns to a machine reference point through an intermediate point
``MachineMove``     a one-shot move in machine coordinates (G53)
``Home``            axes go to the machine's reference point by a search or approach with no
                    intermediate point (SINUMERIK G74, Fagor G74): ``axes`` empty for all
``SetFeed``         feed rate word
``SetSpindleSpeed`` spindle speed word (or a speed clamp)
``Spindle``         spindle start cw / ccw, stop, orient (``apart``: reported without the block's moves)
``Coolant``         coolant on (flood, mist, through-tool) / off
``ToolSelect``      a tool number is selected (T word); ``offset`` for lathe T0101 forms
``ToolChange``      the selected tool goes into the spindle (M06)
``CycleDefine``     a modal canned cycle becomes active with its data (G81, CYCL DEF ..)
``CycleCancel``     the modal canned cycle ends (G80)
``CycleCall``       a one-shot cycle runs now (lathe G70-G79, G12/G13)
``Assign``          a parameter is assigned
``Jump``            go to a label / sequence number, optionally under a condition
``LoopStart``       ``WHILE [cond] DO m``: a loop head with an id
``LoopEnd``         ``END m``: back to the matching loop head
``Conditional``     ``IF [cond] THEN ops``
``Call``            subprogram / macro call with repeat count and arguments
``Return``          end of a subprogram, optionally to a sequence number
``Stop``            program stop, optional stop, program end
``Alarm``           the program raises an alarm on purpose (#3000)
``ProgramEnd``      the end of a program file (Klartext END PGM): ends the main program,
                    returns from a called one
``LabelCall``       a call of a label that repeats a program section when the label lies
                    before it, else runs the label as a subprogram (Klartext CALL LBL REP)
``ToolLength``      the control applies the tool's length by itself at a tool change
                    (Klartext TOOL CALL): no register written, no G43 to forget
``ToolFeed``        the feed a tool call gives (Klartext TOOL CALL F: FAUTO reads it)
``ToolDelta``       the oversize a tool call adds to the table's radius (Klartext TOOL CALL DR)
``Approach``        a contour approach or departure (APPR / DEP); its move follows as its own op
``Pole``            the pole of polar coordinates and arcs about it (Klartext CC, G111);
                    ``words`` the axis words as written, ``I``-prefixed when incremental
``PoleArc``         an arc about the pole to an end point (Klartext C); ``DR`` the direction
``TangentArc``      an arc tangent to the previous element (Klartext CT)
``PolarMove``       a move to a point given by radius and angle about the pole (LP, CP);
                    ``kind`` rapid / linear / arc
``Lift``            a rapid along the tool axis alone (Klartext ``L Z.. FMAX``): straight up
                    from where the tool was fed it leaves the cut
``Retract``         retract along the tool axis by an amount, or to the travel limit (M140 MB)
``MFunction``       an M function with no effect on the modelled machine that rules watch
                    (M94) or that changes the feed mode (M136 / M137)
``DialectStatement`` a statement of one dialect with no counterpart in the others (Klartext
                    CYCL DEF, TRANS, PATTERN DEF, ...), run by the dialect's run-time module;
                    ``params`` as written, ``param_spans`` where each is written
``Deferred``        a block whose codes are computed (``G#3``): resolved at run time
``MoveBatch``       (not an op) a batch of consecutive plain blocks - feed word, motion
                    code, literal axis words - that the interpreter runs at once
``Unsupported``     a construct that reads fine but is not modelled; checks that depend
                    on what it does answer ``unknown``
==================  =====================================================================
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any, Callable, Union

from .source import Span

# --------------------------------------------------------------------------- expressions


@dataclass(frozen=True, slots=True)
class Var:
    """A parameter reference. ``name`` is a str ("#1", "Q5") or an Expr for indirect
    references (``#[#1+1]``), resolved to a name by the interpreter."""

    name: "str | Expr"
    span: Span | None = None
    prefix: str = "#"  # of an indirect reference's name: "#", "Q", "R", "P"


@lru_cache(maxsize=512)
def cycle_code(cycle: str) -> str:
    """The control's own code of a cycle id ``<dialect>.<code>``: ``CYCLE81`` of
    ``sinumerik.CYCLE81``, ``G81`` of ``iso.G81``, ``200`` of ``heidenhain.200`` (kept per
    id: rules ask it of every hole)."""
    return cycle.rsplit(".", 1)[-1]


# The SINUMERIK cutting edge in use (D word, M6), written by the lowering, read by the tool rules.
ACTIVE_EDGE = "$P_TOOL"


@dataclass(frozen=True, slots=True)
class Unary:
    """A sign applied to an operand."""

    op: str  # "-" or "+"
    operand: "Expr"


@dataclass(frozen=True, slots=True)
class Binary:
    """An arithmetic, logical or comparison operation on two operands."""

    op: str  # + - * / MOD AND OR XOR EQ NE GT GE LT LE
    left: "Expr"
    right: "Expr"


@dataclass(frozen=True, slots=True)
class Func:
    """A function of the dialect applied to its arguments."""

    name: str  # SIN COS TAN ASIN ACOS ATAN ATAN2 SQRT ABS ROUND FIX FUP LN EXP ...
    args: tuple["Expr", ...]
    span: Span | None = None


@dataclass(frozen=True, slots=True)
class IncrementCount:
    """A number written without a decimal point, in least input increments: its length
    depends on the units in force when it runs (``X1000`` = 1 mm in G21, 0.1 in in G20),
    so the interpreter scales it. ``kind`` is ``length`` or ``feed``."""

    count: float
    kind: str = "length"


@dataclass(frozen=True, slots=True)
class MachineValue:
    """A value the machine holds that no program can name as a variable (the FAUTO feed of
    the tool call, whether a hole cycle is modal, the result of a function that reads the
    machine): ``read(state)`` gives it on the path where the expression is evaluated.
    ``what`` says which value it is, for reading the IR."""

    what: str
    read: Callable[[Any], Any]


Expr = Union[float, str, Var, Unary, Binary, Func, IncrementCount, MachineValue]  # str: a name (a label, a program)


# --------------------------------------------------------------------------- operations


@dataclass(slots=True)
class Op:
    """An operation a block commands; ``span`` is where its words are written."""

    span: Span


@dataclass(slots=True)
class SetModal(Op):
    """A modal group takes a new value."""

    group: str  # plane, units, distance, feed_mode, path_mode, cycle_return, spindle_mode, arc_distance
    value: str


@dataclass(slots=True)
class Move(Op):
    """Motion to ``targets`` (see the table above for ``kind``, ``arc`` and ``words``)."""

    kind: str | None  # rapid, linear, arc_cw, arc_ccw, thread; None = modal motion
    targets: dict[str, Expr]
    arc: dict[str, Expr] | None = None  # I/J/K centre offsets or {"R": radius}
    words: dict[str, Expr] = field(default_factory=dict)
    incremental: frozenset[str] = frozenset()  # axes written incrementally (U/W forms, IX..)
    word_columns: dict[str, tuple[int, int]] = field(default_factory=dict)  # 0-based, in span's line
    absolute: frozenset[str] = frozenset()  # axes, and arc centre letters, written absolutely whatever the modal mode (SINUMERIK X=AC(..), I=AC(..))

    def word_span(self, letter: str) -> Span:
        """Where a word of this move is written (built on demand: moves are many)."""
        columns = self.word_columns.get(letter)
        if columns is None:
            return self.span
        return Span(self.span.line, columns[0] + 1, self.span.line, columns[1] + 1, self.span.path)

    def word_spans(self) -> dict[str, Span]:
        return {letter: self.word_span(letter) for letter in self.word_columns}


@dataclass(slots=True)
class Dwell(Op):
    """A pause, in seconds or in spindle revolutions."""

    seconds: Expr | None
    revolutions: Expr | None = None


@dataclass(slots=True)
class CutterComp(Op):
    """Tool radius compensation to one side, automatic or off."""

    side: str  # left, right, auto, off
    register: Expr | None = None
    only_if_changed: bool = False  # writing the side already in force does nothing (Klartext R0/RL/RR)


@dataclass(slots=True)
class CornerRounding(Op):
    """A rounding or chamfer of the corner the contour turns at the end of the move before
    (ISO ``,R``/``,C``, SINUMERIK ``RND``/``CHF``/``CHR``, Klartext ``RND``/``CHF``): the tool
    cuts the corner off, between the move before and the move after. ``modal``: SINUMERIK
    ``RNDM`` rounds every corner from here on (True) or no more (False); None: this corner."""

    modal: bool | None = None


@dataclass(slots=True)
class LengthOffset(Op):
    """Tool length compensation on (plus or minus) or off."""

    mode: str  # plus, minus, off; with_tool: the tool's own length (SINUMERIK: its active edge's), no H register and no Z move (Fagor, SINUMERIK D)
    register: Expr | None = None


@dataclass(slots=True)
class WorkOffset(Op):
    """A work coordinate system is selected."""

    name: str  # "G54", "G54.1 P3", "G55" ...


@dataclass(slots=True)
class CoordinateShift(Op):
    """A shift of the coordinate system, made without motion."""

    kind: str  # set_position (G92), local (G52), data (G10)
    values: dict[str, Expr]
    words: dict[str, Expr] = field(default_factory=dict)


@dataclass(slots=True)
class SetFrame(Op):
    """A programmable coordinate transformation (see the table above)."""

    component: str  # translation, rotation, scale, mirror, reset, unknown, swivel, swivel_off
    additive: bool = False
    values: dict[str, Expr] = field(default_factory=dict)
    layer: str | None = None  # coarse (G58) / fine (G59): replaces that part of the translation per axis
    what: str = ""  # the statement, for messages
    group: str | None = None  # an ISO-style statement's modal group: its cancel ends only its own group's transformation


@dataclass(slots=True)
class ReferenceReturn(Op):
    """A return to a machine reference point, through ``via``."""

    which: str  # "home" (G28), "secondary" (G30), "from_reference" (G29), "check" (G27), "stored" (LinuxCNC G28/G30: parameters' position)
    via: dict[str, Expr]
    words: dict[str, Expr] = field(default_factory=dict)
    incremental: frozenset[str] = frozenset()  # axes of ``via`` written incrementally (U/W)


@dataclass(slots=True)
class MachineMove(Op):
    """A move in machine coordinates, for this block only."""

    targets: dict[str, Expr]
    zero_is_reference: bool = True  # machine zero is the reference point (ISO G53, SINUMERIK G53/SUPA), not HEIDENHAIN M91/M92


@dataclass(slots=True)
class Home(Op):
    """Axes go to the machine reference point with no intermediate point."""

    axes: tuple[str, ...] = ()  # empty: every axis


@dataclass(slots=True)
class SetFeed(Op):
    """A feed rate word."""

    value: Expr


@dataclass(slots=True)
class SetSpindleSpeed(Op):
    """A spindle speed word, or a limit on the speed (``clamp``)."""

    value: Expr
    clamp: bool = False


@dataclass(slots=True)
class Spindle(Op):
    """The spindle starts, stops or orients."""

    state: str  # cw, ccw, off, orient
    apart: bool = False  # the change is reported without the block's moves (Klartext: M3/M4 act before them, M5 after)


@dataclass(slots=True)
class Coolant(Op):
    """Coolant on in one of its forms, or off."""

    state: str  # flood, mist, through, off


@dataclass(slots=True)
class ToolSelect(Op):
    """A tool number is selected; it goes into the spindle at the next tool change."""

    number: Expr
    offset: Expr | None = None  # lathe Tttoo: the offset register selected with the tool


@dataclass(slots=True)
class ToolChange(Op):
    """The selected tool goes into the spindle."""


@dataclass(slots=True)
class CycleDefine(Op):
    """A modal canned cycle becomes active with its parameters."""

    cycle: str  # a cycle model id, e.g. "iso.G81"
    params: dict[str, Expr]
    param_spans: dict[str, Span] = field(default_factory=dict)
    up: float = 1.0  # +1: the tool enters going - along the drilling axis (from above); -1: from the - side (Fagor #TOOL AX [Z-])


@dataclass(slots=True)
class CycleCancel(Op):
    """The modal canned cycle ends."""

    plane_change_to: str | None = None  # Fagor G17-G19: the cycle ends only if this plane is a new one


@dataclass(slots=True)
class CycleCall(Op):
    """A cycle that runs once, now, with its parameters."""

    cycle: str
    params: dict[str, Expr]
    param_spans: dict[str, Span] = field(default_factory=dict)


@dataclass(slots=True)
class Assign(Op):
    """A variable is given a value."""

    target: Var
    value: Expr


@dataclass(slots=True)
class Jump(Op):
    """The program goes on at a label or sequence number, if ``condition`` holds."""

    target: Expr  # a sequence number / label
    condition: Expr | None = None
    direction: str | None = None  # forward / backward / nearest: search only that way (SINUMERIK GOTOF/GOTOB/GOTO)
    optional: bool = False  # a missing target is no alarm: the program goes on with the next block (SINUMERIK GOTOC)


@dataclass(slots=True)
class LoopStart(Op):
    """The head of a loop: its body runs while ``condition`` holds."""

    loop_id: int
    condition: Expr


@dataclass(slots=True)
class LoopEnd(Op):
    """The end of a loop's body: back to the head of the same ``loop_id``."""

    loop_id: int


@dataclass(slots=True)
class Conditional(Op):
    """Operations that run only when ``condition`` holds."""

    condition: Expr
    then: list[Op]


@dataclass(slots=True)
class Call(Op):
    """A call of a subprogram or macro, repeated ``repeat`` times, with its arguments."""

    kind: str  # subprogram (M98), local (M97: by sequence number), macro (G65)
    program: Expr
    repeat: Expr = 1.0
    arguments: dict[str, Expr] = field(default_factory=dict)
    start_label: Expr | None = None  # M98 H: start at a sequence number
    most_repeats: float | None = 9999.0  # the control's limit on the repeat count (None: none is known)
    direction: str | None = None  # a local call by label: where to search it (see Jump; "backward-first": before, else after)


@dataclass(slots=True)
class ModalCallOn(Op):
    """Make ``program`` the modal call (Fagor ``#MCALL``, SINUMERIK ``MCALL NAME(...)``): it
    runs after every later block that moves (:class:`ModalCallRun`) until
    :class:`ModalCallOff` or the next ``ModalCallOn``. ``arguments`` (by key) are evaluated
    here, when the call is switched on."""

    program: Expr
    arguments: dict[str, Expr] = field(default_factory=dict)


@dataclass(slots=True)
class ModalCallOff(Op):
    """The modal call ends."""


@dataclass(slots=True)
class ModalCallRun(Op):
    """After a block that moves: call the modal program, if a modal call is on and that
    program is not running now, as a :class:`Call` of ``kind`` whose argument ``name`` is
    the argument stored under ``parameters[name]`` (vacant when the call stored none)."""

    kind: str
    parameters: dict[str, str]


@dataclass(slots=True)
class NoteInsideModalCall(Op):
    """Report ``note`` when the block runs inside the modally called program (an MCALL
    there: modal calls cannot nest)."""

    note: "Note"


@dataclass(slots=True)
class Return(Op):
    """The end of a subprogram: back to the caller (or to a label of it)."""

    to_label: Expr | None = None
    local_only: bool = False  # ends a call by label (Klartext LBL 0); outside one it does nothing


@dataclass(slots=True)
class Stop(Op):
    """A program stop, an optional stop or the program's end."""

    kind: str  # stop (M00), optional (M01), end (M02/M30)
    resets: tuple = ()  # the states a program end puts back, where the control does that ("cycle", "cutter_comp")


@dataclass(slots=True)
class Alarm(Op):
    """The program raises an alarm on purpose."""

    number: Expr
    message: str
    statement: str = "macro alarm #3000={number}"  # how the program raised it, for messages


@dataclass(slots=True)
class ProgramEnd(Op):
    """The end of a program file: the main program ends, a called one returns."""


@dataclass(slots=True)
class LabelCall(Op):
    """A call of a label: repeats a section before it, else runs it as a subprogram."""

    label: Expr
    repeat: Expr = 0.0  # the section runs this many more times


@dataclass(slots=True)
class ToolLength(Op):
    """The control applies the tool's length by itself (a Klartext tool call)."""

    on: bool
    tool: Expr | None = None


@dataclass(slots=True)
class ToolFeed(Op):
    """The feed a tool call gives (what FAUTO reads)."""

    feed: Expr


@dataclass(slots=True)
class ToolDelta(Op):
    """The oversizes a tool call adds to the tool table's radius and length."""

    radius: Expr
    length: Expr = 0.0


@dataclass(slots=True)
class Approach(Op):
    """A contour approach or departure; its move follows as an operation of its own."""


@dataclass(slots=True)
class Pole(Op):
    """The pole of polar coordinates and of arcs about it."""

    words: dict[str, Expr]  # "X" / "IX": absolute / incremental; none: the pole is where the tool is


@dataclass(slots=True)
class PoleArc(Op):
    """An arc about the pole to an end point."""

    words: dict[str, Expr]  # end point words, and DR: +1 counterclockwise, -1 clockwise, 0 not written


@dataclass(slots=True)
class TangentArc(Op):
    """An arc tangent to the element before it."""

    words: dict[str, Expr]


@dataclass(slots=True)
class PolarMove(Op):
    """A move to a point given by radius and angle about the pole."""

    kind: str  # rapid, linear, arc
    words: dict[str, Expr]  # PR / IPR radius, PA / IPA angle, DR, tool-axis words


@dataclass(slots=True)
class Lift(Op):
    """A rapid along the tool axis alone."""

    words: dict[str, Expr]


@dataclass(slots=True)
class Retract(Op):
    """A retraction along the tool axis by an amount, or to the travel limit."""

    amount: Expr  # a length, or "MAX" / "FMAX": to the travel limit


@dataclass(slots=True)
class MFunction(Op):
    """An M function that changes nothing the machine model holds but that rules watch."""

    number: float


@dataclass(slots=True)
class DialectStatement(Op):
    """A statement only one dialect has, with its words by name. Its type says which (the
    Klartext ones below); the dialect's run-time module has a handler for each type."""

    params: dict[str, Expr] = field(default_factory=dict)
    param_spans: dict[str, Span] = field(default_factory=dict)


@dataclass(slots=True)
class CallActiveCycle(DialectStatement):
    """Klartext ``CYCL CALL`` (word ``how``: CALL, PAT or POS, with the POS target), ``M99``,
    ``M89``: run the CALL-active cycle."""


@dataclass(slots=True)
class PositioningBlock(DialectStatement):
    """A Klartext block that positions, where an ``M89`` cycle runs: words ``fed`` (1: at
    feed), ``plane`` (how many plane axes it moves) and ``relative`` (1: incremental)."""


@dataclass(slots=True)
class OldCycle(DialectStatement):
    """Klartext old-style cycle sub-block ``CYCL DEF 7.0 DATUM SHIFT`` / ``7.1 X+60``: its
    words, the cycle's ``number`` and the ``sub``-block; ``program`` is the program of
    ``12.1 PGM``."""

    number: int = 0
    sub: int = 0
    program: str | None = None


@dataclass(slots=True)
class Transformation(DialectStatement):
    """Klartext ``TRANS DATUM/MIRROR/ROTATION/SCALE/RESET`` and ``PLANE`` (word ``what``)."""


@dataclass(slots=True)
class PatternDef(DialectStatement):
    """Klartext ``PATTERN DEF``: words ``<n>:form`` and ``<n>:<word>`` per pattern."""


@dataclass(slots=True)
class GlobalDef(DialectStatement):
    """Klartext ``GLOBAL DEF``: the values PREDEF parameters take."""


@dataclass(slots=True)
class SelectPattern(DialectStatement):
    """Klartext ``SEL PATTERN``: word ``table``, the point table ``CYCL CALL PAT`` runs on."""


@dataclass(slots=True)
class SelectContour(DialectStatement):
    """Klartext ``SEL CONTOUR``: the contour is described in another program."""


@dataclass(slots=True)
class DeclareContour(DialectStatement):
    """Klartext ``DECLARE CONTOUR`` of a contour-definition program (word ``DEPTH``)."""


@dataclass(slots=True)
class ContourDef(DialectStatement):
    """Klartext ``CONTOUR DEF``: pockets ``P<n>``, islands ``I<n>``, voids ``V<n>`` by label, depths ``D<n>``."""


@dataclass(slots=True)
class ToolAxis(Op):
    """Fagor ``#TOOL AX [Z-]``: the axis the tool points along ("?" for one the cycles are
    not modelled for: X2, U...) and its direction."""

    axis: str
    direction: str  # "+" or "-"


@dataclass(slots=True)
class CycleSet(Op):
    """Fagor ``#LATHECY ON``/``OFF`` (``turning``) and ``#MILLCY ON``/``OFF``: whether
    G81-G88 are turning or milling cycles."""

    turning: bool
    on: bool


@dataclass(slots=True)
class RepeatEnd(Op):
    """Fagor ``(RPT N10, N20)``: while the blocks run, the one labelled ``label`` (N20)
    returns; ``None`` once the repeat is over."""

    label: Expr | None


@dataclass(slots=True)
class DialectDeferred(Op):
    """A block whose meaning depends on the dialect's state where it runs (a Fagor cycle
    block: the plane, ``#TOOL AX`` and the cycle set): the dialect's run-time code calls
    ``resolve`` with that state for the real ops and notes."""

    resolve: object  # Callable[..., tuple[list[Op], list[Note]]], its arguments the dialect's


@dataclass(slots=True)
class Deferred(Op):
    """A block whose meaning depends on a value known only at run time (``G#3``, ``M#5``):
    the interpreter evaluates ``exprs`` and calls ``resolve(values)`` for the real ops, or
    treats the block as unsupported when a value is symbolic."""

    exprs: tuple
    resolve: object  # Callable[[tuple[float, ...]], tuple[list[Op], list[Note]]]


@dataclass(slots=True)
class Unsupported(Op):
    """A construct that reads fine but is not modelled: checks that depend on it answer ``unknown``."""

    what: str
    affects: tuple[str, ...] = ()  # "position": where the tool is; "state": offsets, frames or tool data (MachineState.unfollowed)


@dataclass(slots=True)
class MoveBatch:
    """Consecutive plain blocks read in one go: each row is ``[SetFeed] Move(kind, targets)``
    with literal numbers. Straight-line CAM code is millions of such blocks; reading and
    running them as arrays is what makes the checker fast. ``kinds`` is -1 for "modal",
    else an index into ``KINDS``; missing words are NaN; ``scaled`` marks numbers written
    without a decimal point (least input increments). ``arc_words``: the ``I J K R`` of
    each row (NaN when absent), None when the reader took no arcs; ``worded``: which rows
    hold a word (None: all of them).

    What a dialect's rows do besides (None: no row does it): ``centres_absolute``, the
    ``I J K`` are the centre itself, not its offset from the start (Klartext ``C`` about the
    pole); ``keeps_motion``, rows that leave the motion mode as it was (a Klartext pole and
    the arcs about it); ``compensation_off``, rows that end radius compensation (Klartext
    ``R0``: a batch under compensation stops before them); ``poles``, the pole a row sets
    (NaN where it sets none), which the dialect's runtime keeps after the batch."""

    KINDS = ("rapid", "linear", "arc_cw", "arc_ccw")

    source_offset: int
    end_offset: int
    first_line: int
    line_offsets: object  # numpy int64 (rows,)
    kinds: object  # numpy int8 (rows,)
    axes: tuple[str, ...]
    values: object  # numpy float64 (rows, len(axes))
    scaled: object  # numpy bool (rows, len(axes))
    feeds: object  # numpy float64 (rows,)
    feed_scaled: object  # numpy bool (rows,)
    blocks: int = 0  # rows that hold at least one word (empty lines are not blocks)
    arc_words: object = None  # numpy float64 (rows, 4)
    worded: object = None  # numpy bool (rows,)
    centres_absolute: bool = False
    keeps_motion: object = None  # numpy bool (rows,)
    compensation_off: object = None  # numpy bool (rows,)
    poles: object = None  # numpy float64 (rows, 2)

    @property
    def rows(self) -> int:
        return len(self.kinds)

    def head(self, rows: int) -> "MoveBatch":
        """The batch's first ``rows`` rows."""
        worded = None if self.worded is None else self.worded[:rows]
        blocks = rows if worded is None else int(worded.sum())
        end = int(self.line_offsets[rows]) if rows < self.rows else self.end_offset

        def first(rows_of):
            return None if rows_of is None else rows_of[:rows]

        return MoveBatch(self.source_offset, end, self.first_line, self.line_offsets[:rows], self.kinds[:rows], self.axes,
                         self.values[:rows], self.scaled[:rows], self.feeds[:rows], self.feed_scaled[:rows], blocks, first(self.arc_words),
                         worded, self.centres_absolute, first(self.keeps_motion), first(self.compensation_off), first(self.poles))


# --------------------------------------------------------------------------- blocks


@dataclass(slots=True)
class Note:
    """A finding the reader or lowering makes about a block's text (a syntax error, an
    unknown code, two codes of one group): a rule id from ``rules/`` and a message."""

    rule: str
    message: str
    span: Span
    status: str = "violated"  # or "unknown": what the block asks of a rule was not checked
    reason: str | None = None


@dataclass(slots=True)
class Block:
    """One source block: its line, label, the operations it commands, and enough of its
    text position to quote it. ``program`` is the program number / name it belongs to."""

    line: int
    start_column: int  # 1-based
    end_column: int  # exclusive
    ops: list[Op]
    label: float | None = None  # N number
    skippable: bool = False  # '/' block delete
    comments: tuple[tuple[str, Span], ...] = ()
    program_start: str | None = None  # this block starts program O1234
    tape_mark: bool = False  # a '%' line: the start or the end of the tape
    notes: list[Note] = field(default_factory=list)

    @property
    def span(self) -> Span:
        return Span(self.line, self.start_column, self.line, self.end_column)
