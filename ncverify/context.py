"""What a verdict depends on besides the program: stock, tools, machine, parameter ranges.

Context comes from three places, and the first that says something wins: the program
itself (a dialect's stock or tool statements), ``ncverify:`` annotations in its comments
(:mod:`ncverify.annotations`), and the project file ``ncverify.toml``
(:mod:`ncverify.project`). A check whose context is missing answers ``unknown`` and says
which context it lacks; it never assumes "safe".
"""
from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field, fields, replace

import shapely
from shapely.geometry import Polygon

from .ir import ACTIVE_EDGE
from .source import Span, finditer_all, search_any

TOOL_TYPES = ("drill", "endmill", "ball", "bullnose", "chamfer", "spot", "tap", "threadmill", "boring", "reamer",
              "facemill", "slot", "turning", "grooving", "parting", "threading", "probe")
TOOL_KEYS = ("radius", "corner", "length", "cutting_length", "usable_length", "angle", "pitch", "nose_radius", "edge",
             "clearance_angle", "edge_position", "point_angle", "width", "holder_diameter", "holder_length")
# Common spellings of the tool types (hyphens, underscores and blanks are dropped first).
_TOOL_TYPE_SPELLINGS = {
    "facemill": ("face", "shellmill", "facingmill"), "endmill": ("flat", "flatendmill", "squareendmill", "mill", "cutter"),
    "ball": ("ballmill", "ballnose", "ballendmill", "ballnoseendmill"), "bullnose": ("torus", "radiusmill", "bullnoseendmill", "toroidal"),
    "spot": ("spotdrill", "centre", "center", "centredrill", "centerdrill", "ncspotdrill"), "chamfer": ("chamfermill", "countersink", "chamfertool"),
    "threadmill": ("threadmilling", "threadmiller"), "threading": ("thread", "threadturning", "threadingtool", "threadtool"),
    "grooving": ("groove", "groover", "groovingtool", "grooveturning"), "parting": ("part", "partingoff", "cutoff", "partoff"),
    "turning": ("turn", "turningtool", "lathe"), "boring": ("bore", "boringbar", "boringhead"), "reamer": ("ream", "reaming"),
    "slot": ("slotmill", "slotting", "keyseat", "slittingsaw", "saw"), "tap": ("tapping", "rigidtap"), "drill": ("twistdrill", "drilling"),
    "probe": ("touchprobe", "touchtrigger"),
}
_TOOL_TYPE_LOOKUP = {alias: canonical for canonical, aliases in _TOOL_TYPE_SPELLINGS.items() for alias in (canonical, *aliases)}


def canonical_tool_type(written: str) -> str:
    """The tool type a common spelling means (``face-mill`` -> facemill, ``groove`` ->
    grooving); ValueError listing the accepted ones for anything else."""
    key = "".join(character for character in written.lower() if character not in "-_ ")
    if key in _TOOL_TYPE_LOOKUP:
        return _TOOL_TYPE_LOOKUP[key]
    raise ValueError(f"unknown tool type {written!r} (accepted: {', '.join(TOOL_TYPES)}, and spellings such as face-mill, "
                     "end-mill, ball-nose, spot-drill, groove, thread, cut-off)")
# Keys whose value must lie in a range, not merely be positive: a turning tool's clearance
# angle ($TC_DP24, 0..90 degrees, 0 = the cycles do not monitor it; SINUMERIK reference B
# section 3, seed L14840-14850), its cutting-edge position ($TC_DP2, SL 1..9, L15650-15662), and
# a drill's point angle (HEIDENHAIN TOOL.T T-ANGLE, 0 = not entered).
TOOL_RANGES = {"clearance_angle": (0.0, 90.0), "edge_position": (1.0, 9.0), "point_angle": (0.0, 180.0)}


@dataclass(frozen=True)
class Stock:
    """The blank. ``box``: x, y, z ranges; ``polygon``: a shapely polygon in XY between two
    Z levels (with a ``diameter``: a round blank, :meth:`round_blank`); ``cylinder``: a bar of
    ``diameter`` along Z (lathe, X is a diameter)."""

    kind: str
    z_range: tuple[float, float]
    x_range: tuple[float, float] | None = None
    y_range: tuple[float, float] | None = None
    outline: Polygon | None = None
    diameter: float | None = None
    origin: str = "project file"  # where it was defined: program, annotation, project file
    span: Span | None = None

    @property
    def top(self) -> float:
        return self.z_range[1]

    @classmethod
    def box(cls, x, y, z, origin="project file", span=None) -> "Stock":
        return cls("box", _ordered(z), _ordered(x), _ordered(y), origin=origin, span=span)

    @classmethod
    def polygon(cls, points, z, origin="project file", span=None) -> "Stock":
        if not all(math.isfinite(float(value)) for point in points for value in point):
            raise ValueError("a stock polygon point is not a finite number")
        outline = Polygon(points)
        if not outline.is_valid or outline.area <= 0:
            raise ValueError("the stock polygon is not a simple closed outline with an area")
        shapely.prepare(outline)
        return cls("polygon", _ordered(z), outline=outline, origin=origin, span=span)

    @classmethod
    def round_blank(cls, radius: float, z, origin="project file", span=None) -> "Stock":
        """A round blank standing along Z about the workpiece origin (Klartext ``BLK FORM
        CYLINDER Z``; X and Y are coordinates, not a lathe's diameter): the polygon of
        ``_ROUND_SIDES`` sides around the circle, which holds it whole (proofs against it
        hold for the circle) and reaches past it by less than 0.004 % of the radius."""
        if not radius > 0 or not math.isfinite(radius):
            raise ValueError("the blank's radius must be a positive finite number")
        outer = radius / math.cos(math.pi / _ROUND_SIDES)
        corners = [(outer * math.cos(2 * math.pi * (k + 0.5) / _ROUND_SIDES), outer * math.sin(2 * math.pi * (k + 0.5) / _ROUND_SIDES)) for k in range(_ROUND_SIDES)]
        return replace(cls.polygon(corners, z, origin, span), diameter=2.0 * radius)

    @classmethod
    def cylinder(cls, diameter, z, origin="project file", span=None) -> "Stock":
        if not diameter > 0 or not math.isfinite(diameter):
            raise ValueError("the stock diameter must be a positive finite number")
        return cls("cylinder", _ordered(z), diameter=float(diameter), origin=origin, span=span)

    def describe(self) -> str:
        if self.kind == "box":
            return f"box X{self.x_range[0]:g}..{self.x_range[1]:g} Y{self.y_range[0]:g}..{self.y_range[1]:g} Z{self.z_range[0]:g}..{self.z_range[1]:g}"
        if self.kind == "cylinder":
            return f"bar D{self.diameter:g} Z{self.z_range[0]:g}..{self.z_range[1]:g}"
        if self.diameter is not None:
            return f"round blank D{self.diameter:g} about Z Z{self.z_range[0]:g}..{self.z_range[1]:g}"
        return f"polygon stock Z{self.z_range[0]:g}..{self.z_range[1]:g}"


_ROUND_SIDES = 360


def _ordered(pair) -> tuple[float, float]:
    low, high = (float(value) for value in pair)
    if not (math.isfinite(low) and math.isfinite(high)):
        raise ValueError(f"the range {low:g}..{high:g} is not made of finite numbers")
    if low > high:
        low, high = high, low
    if low == high:
        raise ValueError(f"the range {low:g}..{high:g} is empty")
    return low, high


@dataclass
class Tool:
    """A tool as the project file or an annotation describes it."""

    number: int | None
    name: str | None = None
    type: str | None = None
    radius: float | None = None
    corner: float | None = None
    length: float | None = None
    cutting_length: float | None = None
    usable_length: float | None = None
    angle: float | None = None
    pitch: float | None = None
    nose_radius: float | None = None
    edge: float | None = None
    clearance_angle: float | None = None  # degrees, the turning tool's clearance angle (TOOL_RANGES)
    edge_position: float | None = None  # the turning tool's cutting-edge position SL (TOOL_RANGES)
    point_angle: float | None = None  # degrees, a drill's point angle (TOOL.T T-ANGLE); 0: not entered
    width: float | None = None  # a grooving or parting tool's cutting width
    holder_diameter: float | None = None  # the holder's diameter, from holder_length (or usable_length) above the tip upward
    holder_length: float | None = None  # how far the holder reaches down from the spindle gauge line (at ``length`` above the tip)
    origin: str = "project file"
    edges: dict = field(default_factory=dict)  # SINUMERIK: the data of cutting edges D2, D3... by D number (the fields above: D1)

    def edge_data(self, edge: float) -> "Tool | None":
        """The data of cutting edge D``edge`` (this tool's own values are edge D1's), or None
        when that edge is not described."""
        return self if edge == 1.0 else self.edges.get(int(edge))

    def filled_from(self, base: "Tool") -> "Tool":
        """This tool, with ``base``'s values where this one says nothing."""
        missing = {item.name: getattr(base, item.name) for item in fields(self) if getattr(self, item.name) is None}
        return replace(self, **missing)


def tool_value_problem(key: str, value: float) -> str | None:
    """Why ``value`` cannot be the tool's ``key`` (not finite, or outside its range in
    TOOL_RANGES), or None."""
    if not math.isfinite(value):
        return f"{key.replace('_', '-')} must be a finite number, got {value:g}"
    low, high = TOOL_RANGES.get(key, (None, None))
    if low is not None and not low <= value <= high:
        return f"{key.replace('_', '-')} must lie in {low:g}..{high:g}, got {value:g}"
    return None


NO_TOOL_TABLE = "no tool table ([tools.N] in ncverify.toml, 'ncverify: tool' annotations, or TOOL.T beside a Klartext program)"


def tools_called_in(buffer, call, unsure) -> frozenset[int] | None:
    """The tool numbers the text ``buffer`` can load: every number the patterns ``call``
    find (their first group), and no other. None, any tool, where that cannot be told from
    the text: one of the patterns ``unsure`` finds a tool called by a computed number, a
    call of another program (whose tools are not in this text) or a write to the tool
    table, or no tool is called at all (the program cuts with the one in the spindle). A
    number in a comment is counted too, which can only add a tool. (Both are sequences of
    patterns, as :func:`~ncverify.source.letter_led` makes them for a fast scan.)"""
    if search_any(buffer, unsure):
        return None
    called = set()
    for found in finditer_all(buffer, call):
        number = found.group(1)
        if len(number) > 15:  # no tool of the table (and past what int() takes from text of thousands of digits)
            return None
        called.add(int(number))
    return frozenset(called) or None


class ToolTable(Mapping[int, Tool]):
    """The tools by number, and the one place where a computed T number becomes a tool.

    Reads the machine state only through ``state.tool_in_spindle``, so that it sits below
    the interpreter as well as the rules."""

    def __init__(self, tools: Mapping[int, Tool] | None = None):
        self._tools = dict(tools or {})

    def __getitem__(self, number: int) -> Tool:
        return self._tools[number]

    def __iter__(self) -> Iterator[int]:
        return iter(self._tools)

    def __len__(self) -> int:
        return len(self._tools)

    def numbered(self, number) -> Tool | None:
        """The tool a T (or H, D) number the program computed names: None when the number is
        not known (absent, symbolic) or the table has no such tool."""
        return self._tools.get(int(number)) if type(number) is float else None

    def in_spindle(self, state) -> Tool | None:
        """The tool in the spindle on this path, or None when it is not known or not in the table."""
        return self.numbered(state.tool_in_spindle)

    def missing(self, state, what: str | None = None) -> str:
        """What keeps a rule from reading the tool in the spindle (or its ``what``, a
        :class:`Tool` field) from the table: the one wording every rule gives."""
        number = state.tool_in_spindle
        if not self._tools:
            return NO_TOOL_TABLE
        if type(number) is not float:
            return "the tool in the spindle is not known"
        if self.numbered(number) is None:
            return f"tool T{number:g} is not in the tool table"
        return f"tool T{number:g} has no {(what or 'entry').replace('_', ' ')} in the tool table"


@dataclass
class Machine:
    """What the project file says of the machine."""

    kind: str | None = None  # mill / lathe
    travel: dict[str, tuple[float, float]] = field(default_factory=dict)  # machine coordinates
    work_offsets: dict[str, tuple[float, ...]] = field(default_factory=dict)  # "G54" -> (x, y, z)
    max_spindle: float | None = None
    max_feed: float | None = None
    lathe_x: str | None = None  # lathe: are X travel and work offsets a "diameter" or a "radius"?
    spindle_encoder: bool | None = None  # a motor-driven spindle with an encoder, which rigid tapping needs
    one_workpiece: frozenset[str] = frozenset()  # work offsets that all hold the one blank the stock describes
    start: dict[str, float] | None = None  # where the tool starts, in workpiece coordinates ({}: unknown; None: the default)
    remaps: frozenset[str] | None = None  # LinuxCNC: the G codes the configuration remaps (None: not declared)


def start_position(machine: Machine, stock: "Stock | None") -> dict[str, float]:
    """Where the tool stands when the program starts and after a reference return or a full
    retract, in workpiece coordinates: ``[machine] start`` when given, else above the top of
    the stock by its own height (the other axes unknown), else nowhere known."""
    if machine.start is not None:
        return dict(machine.start)
    if stock is None:
        return {}
    low, high = stock.z_range
    return {"Z": high + (high - low)}


def describe_start(machine: Machine, stock: "Stock | None") -> str | None:
    """The start position as the report's assumptions state it."""
    start = start_position(machine, stock)
    if not start:
        return None
    where = " ".join(f"{axis}{value:g}" for axis, value in sorted(start.items()))
    origin = "[machine] start" if machine.start is not None else "the default: above the stock top by its height, other axes unknown"
    return f"the tool starts at {where}, and reference returns and full retracts take it back there ({origin})"


@dataclass
class Assumption:
    """A constraint on free parameters (``-20 <= #1 <= -2``), as text and as bounds."""

    text: str
    tree: object  # ast.Expression over parameter names
    origin: str = "project file"
    span: Span | None = None


@dataclass
class Context:
    """What a check may assume beyond the program: the project file and the annotations."""

    stock: Stock | None = None
    tools: dict[int, Tool] = field(default_factory=dict)
    machine: Machine = field(default_factory=Machine)
    assumptions: list[Assumption] = field(default_factory=list)
    settings: dict = field(default_factory=dict)  # [settings] of the project file
    disabled: set[str] = field(default_factory=set)  # [rules] disable
    severity: dict[str, str] = field(default_factory=dict)  # [rules] severity
    source: str | None = None  # the project file, when one was read

    def layered_over(self, base: "Context") -> "Context":
        """This context's definitions, with ``base`` filling what this one lacks, down to
        a tool's single values (annotations over the project file; the program over both)."""
        tools = dict(base.tools)
        tools.update({key: tool.filled_from(base.tools[key]) if key in base.tools else tool for key, tool in self.tools.items()})
        machine = Machine(
            self.machine.kind or base.machine.kind,
            {**base.machine.travel, **self.machine.travel},
            {**base.machine.work_offsets, **self.machine.work_offsets},
            self.machine.max_spindle if self.machine.max_spindle is not None else base.machine.max_spindle,
            self.machine.max_feed if self.machine.max_feed is not None else base.machine.max_feed,
            self.machine.lathe_x or base.machine.lathe_x,
            self.machine.spindle_encoder if self.machine.spindle_encoder is not None else base.machine.spindle_encoder,
            self.machine.one_workpiece or base.machine.one_workpiece,
            self.machine.start if self.machine.start is not None else base.machine.start,
            self.machine.remaps if self.machine.remaps is not None else base.machine.remaps,
        )
        return Context(
            self.stock or base.stock, tools, machine, base.assumptions + self.assumptions,
            {**base.settings, **self.settings}, base.disabled | self.disabled, {**base.severity, **self.severity},
            self.source or base.source,
        )


@dataclass(frozen=True)
class RegisterLimits:
    """The largest tool number and offset registers the control takes (the dialect's tables)."""

    tool_number_max: float = math.inf
    h_register_max: float = math.inf
    d_register_max: float = math.inf


@dataclass(frozen=True)
class ArcTolerance:
    """How far an arc's end radius may differ from its start radius before the control
    refuses the arc: refused when off by more than the absolute tolerance of the program's
    units (``metric`` in mm, ``inch`` in inches: the control keeps one per unit, not one
    converted) and more than ``relative`` times the start radius (LinuxCNC)."""

    metric: float
    inch: float
    relative: float = 0.0


@dataclass(frozen=True)
class RuleContext:
    """What the rules may assume besides the trace: the program's stock, tools and machine
    (after layering program, annotations and project file), the control's register limits,
    how rapids move, and the control's own words for messages."""

    machine: Machine = field(default_factory=Machine)  # ``kind``: the machine type this run settled on
    stock: Stock | None = None
    tools: ToolTable = field(default_factory=ToolTable)
    limits: RegisterLimits = field(default_factory=RegisterLimits)
    rapid_path: str = "straight"
    wording: Mapping[str, str] = field(default_factory=dict)
    arc_tolerance: "ArcTolerance | None" = None  # the control's own, where the dialect states it
    lengths_by_set_up: bool = False  # see DialectSetup.lengths_by_set_up
    dialect: str | None = None  # the program's dialect: rules of other dialects are not asked (None: every rule is)
    tools_called: frozenset[int] | None = None  # the tool numbers the program's text can call; None: any of the table's

    @property
    def lathe(self) -> bool:
        return self.machine.kind == "lathe"


def radius_delta(state):
    """The radius delta the active tool call adds to the tool table's radius (Klartext
    ``TOOL CALL .. DR``): 0.0 where none is programmed; a symbolic value when it depends
    on a free parameter (rules then answer unknown)."""
    return state.klartext.radius_delta


def active_tool_number(state, lathe: bool):
    """The tool that cuts: the one M6 loaded; on a lathe the T word changes the turret at
    once (the part B examples call the turning cycles after ``T3 D1`` with no M6), so there
    the selected tool, unless an M6 loaded another one (then it depends on the machine)."""
    mounted, selected = state.tool_in_spindle, state.tool_selected
    if not lathe or selected is None or selected == mounted:
        return mounted if type(mounted) is float else None
    return selected if mounted is None and type(selected) is float else None


def compensated(state) -> bool:
    """Is radius compensation on (G41/G42, RL/RR), or in a state that is not known? The
    tool then runs beside the programmed path by an offset the program alone does not fix."""
    return state.comp_side != "off"


def off_path(state) -> bool:
    """Does each cut leave its programmed path by an amount the program does not fix:
    radius compensation, or SINUMERIK ``RNDM`` rounding every corner?"""
    return compensated(state) or state.corners_rounded


def active_edge(state):
    """The active SINUMERIK cutting edge (1.0 where no D word set one; a symbolic value
    when it depends on a free parameter)."""
    return state.global_variables.get(ACTIVE_EDGE, 1.0)
