"""The motion of the SINUMERIK standard cycles, run as shapes of the shared cycle runner (:mod:`ncverify.interpret.cycles`).

Drilling cycles CYCLE81-89/840 make one hole at the current position on the shared hole
model (seed A L1934-2146): rapid to ``SP = RFP + s*SDIS``, infeed to the depth, retract, rapid
to ``RTP``, where ``s`` is the sign of ``RTP - RFP`` and the depth is ``RFP - s*DPR`` when DPR is
programmed, else ``DP``. Under ``MCALL`` the interpreter calls the same shape after every
positioning move. HOLES1/HOLES2/CYCLE801 move with G0 from position to position and run the
modal cycle at each (seed A L4476-4970). Pockets, slots, spigots, thread milling and engraving
approach their feature at RTP, rapid to RFP + SDIS, plunge to the depth and retract to RTP
(``_FEATURES``); the machining inside the feature is not modelled. The other milling cycles
leave the tool at their retract level, unknown in the plane; turning cycles leave it
unknown. Contours named by a cycle are read, not run (``read_contour_section``).
"""
from __future__ import annotations

import math
from typing import NamedTuple

from .. import values
from .cycles import DialectCycles, grid
from ..cycle_models import CycleModel
from ..trace import CycleRun, Hole
from ..values import VACANT

_CHECKED_LEVELS = ("RTP", "RFP", "SDIS", "DP", "DPR")


def levels(params: dict, absolute_depth_only: bool = False):
    """``(s, SP, DEPTH)`` from RTP, RFP, SDIS, DP, DPR (None where undecidable).
    ``s`` = +1 when the retract plane lies on the positive side of the reference plane."""
    rtp, rfp = _get(params, "RTP"), _get(params, "RFP")
    sdis, dp = _get(params, "SDIS"), _get(params, "DP")
    dpr = 0.0 if absolute_depth_only else _get(params, "DPR")
    side = direction(rtp, rfp)
    if side is None and type(rtp) is float and rtp == rfp and dpr == 0.0 and type(dp) is float:
        side = 1.0 if dp < rfp else -1.0
    if side is None:
        return None, None, None
    start = values.add(rfp, values.mul(side, values.absolute(sdis)))
    if dpr == 0.0:
        depth = dp
    else:
        depth = values.sub(rfp, values.mul(side, values.absolute(dpr)))
    return side, start, depth


def direction(rtp, rfp) -> float | None:
    difference = values.sub(rtp, rfp)
    low, high = values.interval(difference)
    if low > 0:
        return 1.0
    if high < 0:
        return -1.0
    return None


def _get(params: dict, name: str):
    """A parameter by its name with or without the leading underscore of the newer cycles."""
    for key in (name, f"_{name}"):
        value = params.get(key)
        if value is not None and value is not VACANT and not isinstance(value, str):
            return value
    return 0.0


def _report_run(runner, op, block, model, params):
    runner.report_cycle(CycleRun(op.cycle, model, op.span, block, params, dict(op.param_spans)))


def drill(runner, op, block, model, params):
    """One hole at the current position (CYCLE81-89, CYCLE840)."""
    _report_run(runner, op, block, model, params)
    state = runner.state
    axis = state.plane_axes[2]
    side, start, depth = levels(params)
    rtp = _get(params, "RTP")
    name = op.cycle
    if side is None or depth is None:
        runner.fault("core.unsupported-code", op.span, f"{name.split('.')[-1]}: the drilling direction cannot be told from RTP and RFP here; the hole is not analysed",
                             "unknown", "RTP and RFP depend on free parameters")
        state.move_to({axis: None})
        return None
    position = dict(state.position)
    if side > 0:
        definition = state.cycle.definition if state.cycle is not None else op.span
        spans = {"Z": op.param_spans.get("DP", op.span), "R": op.param_spans.get("RFP", op.span)}
        spans.update(op.param_spans)
        runner.report_hole(Hole(name, model, op.span, block, axis, position, rtp, start, depth, dict(params), spans, (), definition))
    tapping = model.tapping_cycle and params.get("ENC") != 1.0  # G331/G33: the feed follows the pitch
    cut = "thread" if tapping else "feed"
    programmed_feed, inherited = state.feed, state.feed_inherited
    feed_in, feed_out = params.get("FFR"), params.get("RFF")
    if type(feed_in) is float and feed_in > 0:
        state.feed = feed_in  # CYCLE85 feeds with its own FFR
    elif tapping:
        state.feed = tapping_feed(params, state)
        state.feed_inherited = state.feed is None or inherited
    _set_spindle(runner, op, block, _spindle_code(params, model.spindle_during))
    runner.move_to({axis: start}, op.span, block, "approach", name)
    runner.move_to({axis: depth}, op.span, block, "infeed", name, cut)
    if model.retract == "feed":
        if type(feed_out) is float and feed_out > 0:
            state.feed = feed_out
        runner.move_to({axis: start}, op.span, block, "out-of-hole", name, cut)
        runner.move_to({axis: rtp}, op.span, block, "retract", name)
    else:
        runner.move_to({axis: rtp}, op.span, block, "out-of-hole", name)
    state.feed, state.feed_inherited = programmed_feed, inherited
    after = model.spindle_after
    if after == "off" or (after and params.get("SDR", 3.0) != 0.0):
        _set_spindle(runner, op, block, "off" if after == "off" else _spindle_code(params, after))
    return None


_SPINDLE_CODES = {3.0: "cw", 4.0: "ccw", 5.0: "off"}


def _spindle_code(params: dict, name: str | None) -> str | None:
    """The spindle state a direction parameter (3, 4, 5) selects, or None."""
    return _SPINDLE_CODES.get(params.get(name)) if name else None


def _set_spindle(runner, op, block, new: str | None) -> None:
    """A cycle switches the spindle: the state changes and the rules see the change."""
    state = runner.state
    if new is not None and state.spindle != new:
        old, state.spindle = state.spindle, new
        runner.change("spindle", op.span, block, old, new)


# ISO metric coarse pitches by thread size, for MPIT (reference A section 6.4, marked as background).
COARSE_PITCH = {3: 0.5, 4: 0.7, 5: 0.8, 6: 1.0, 8: 1.25, 10: 1.5, 12: 1.75, 14: 2.0, 16: 2.0, 18: 2.5, 20: 2.5, 22: 2.5,
                24: 3.0, 27: 3.0, 30: 3.5, 33: 3.5, 36: 4.0, 39: 4.0, 42: 4.5, 45: 4.5, 48: 5.0}


def tapping_feed(params: dict, state):
    """The feed a tapping cycle runs at: pitch (PIT, or MPIT's coarse pitch) x speed (SST,
    or the programmed speed); None when it cannot be told."""
    pitch = params.get("PIT")
    if type(pitch) is not float or pitch == 0.0:
        size = params.get("MPIT")
        pitch = COARSE_PITCH.get(int(abs(size))) if type(size) is float and size == int(size) else None
    speed = params.get("SST")
    if type(speed) is not float or speed == 0.0:
        speed = state.spindle_speed
    if pitch is None or type(speed) is not float:
        return None
    return abs(pitch) * speed


def pattern(runner, op, block, model, params):
    """HOLES1 / HOLES2 / CYCLE801: G0 from position to position, the modal cycle at each."""
    _report_run(runner, op, block, model, params)
    state = runner.state
    name = op.cycle.split(".")[-1]
    count = pattern_size(name, params)
    positions = pattern_positions(name, params) if count is not None and runner.within_loop_bound(count, op.span, name) else None
    if positions is None:
        if count is None:
            runner.fault("core.unsupported-code", op.span, f"{name}: the positions depend on free parameters; the pattern is not analysed",
                          "unknown", "pattern parameters depend on free parameters")
        first, second, _ = state.plane_axes
        state.move_to({first: None, second: None})
        return None
    modal = state.cycle
    first, second, _ = state.plane_axes
    for abscissa, ordinate in positions:
        runner.move_to({first: abscissa, second: ordinate}, op.span, block, "between-holes", op.cycle)
        if modal is not None:
            run = modal_shape(modal.model)
            if run is not None:
                call = type(op)(op.span, modal.cycle, {}, dict(modal.param_spans))
                run(runner, call, block, modal.model, dict(modal.params))
    return None


_PATTERN_PARAMETERS = {"HOLES1": ("SPCA", "SPCO", "STA1", "FDIS", "DBH", "NUM"), "HOLES2": ("CPA", "CPO", "RAD", "STA1", "INDA", "NUM"),
                       "CYCLE801": ("_SPCA", "_SPCO", "_STA", "_DIS1", "_DIS2", "_NUM1", "_NUM2")}


def _pattern_numbers(cycle: str, params: dict) -> list | None:
    """The pattern's parameters in order (an omitted one is 0), or None when one is not a number."""
    found = [params.get(name, 0.0) for name in _PATTERN_PARAMETERS[cycle]]
    return found if all(type(value) is float for value in found) else None


def pattern_size(cycle: str, params: dict) -> float | None:
    """How many positions a pattern cycle has (NUM, or _NUM1 x _NUM2), or None when its
    parameters are not numbers."""
    found = _pattern_numbers(cycle, params)
    return None if found is None else math.prod(max(count, 0.0) for count in found[5:])


def pattern_positions(cycle: str, params: dict):
    """The plane positions of a pattern cycle, or None when a value is not a number (the
    caller bounds their count with :func:`pattern_size` first)."""
    found = _pattern_numbers(cycle, params)
    if found is None:
        return None
    if cycle == "HOLES1":
        x, y, angle, first, step, count = found
        cos, sin = math.cos(math.radians(angle)), math.sin(math.radians(angle))
        return [(x + (first + k * step) * cos, y + (first + k * step) * sin) for k in range(int(max(count, 0.0)))]
    if cycle == "HOLES2":
        x, y, radius, start, increment, count = found
        count = int(max(count, 0.0))
        increment = increment or (360.0 / count if count else 0.0)
        return [(x + radius * math.cos(math.radians(start + k * increment)), y + radius * math.sin(math.radians(start + k * increment)))
                for k in range(count)]
    x, y, angle, column, row, columns, rows = found
    cos, sin = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    return [(x + i * column * cos - j * row * sin, y + i * column * sin + j * row * cos) for i, j in grid(columns, rows)]


def one_shot(runner, op, block, model, params):
    """A milling, turning or swivel cycle: reported for the parameter rules. Milling cycles
    with a modelled approach run it (``_FEATURES``); the others leave the tool at their
    retract level on the infeed axis, unknown in the plane; turning and swivel cycles leave
    the position unknown."""
    for key, where in model.contours.items():
        facts = _named_contour(runner, op, params, where)
        if facts is not None:
            params = {**params, key: facts}
    _report_run(runner, op, block, model, params)
    state = runner.state
    first, second, axis = state.plane_axes
    features = _FEATURES.get(op.cycle.split(".")[-1])
    if features is not None and _feature_motion(runner, op, block, params, features(params, state)):
        return None
    if model.shape == "sinumerik_mill":
        level = _end_level(op.cycle, params)
        state.move_to({first: None, second: None, axis: level if type(level) is float else None})
    elif model.shape == "sinumerik_turn" or "position" in model.affects:
        state.move_to(dict.fromkeys(state.position))
    return None


def _end_level(cycle: str, params: dict):
    """Where a milling cycle leaves the tool on the infeed axis: RTP, except CYCLE72 whose
    _VARI hundreds digit retracts to RTP (0), to RFP + SDIS (1), by SDIS above the last
    level (2) or not at all (3); the last level keeps the bottom allowance when roughing
    (seed A L8386-8388, L8300-8306)."""
    rtp = _get(params, "RTP")
    kind = _get(params, "VARI")
    if cycle != "sinumerik.CYCLE72" or type(kind) is not float or kind // 100 % 10 == 0:
        return rtp
    side, start, depth = levels(params)
    if side is None:
        return None
    if kind // 100 % 10 == 1:
        return start
    allowance = _get(params, "FALD") if kind % 10 == 1 else 0.0
    bottom = values.add(depth, values.mul(side, values.absolute(allowance)))
    return values.add(bottom, values.mul(side, values.absolute(_get(params, "SDIS")))) if kind // 100 % 10 == 2 else bottom


class Features(NamedTuple):
    """Where a milling cycle works: the plane points it plunges at (None: a start point the
    cycle computes itself), where the tool ends in the plane (None: unknown), whether it
    plunges with G0, and whether RFP + SDIS lies inside a bore made before (internal threads
    milled bottom up)."""

    points: list
    end: tuple | None
    g0_insertion: bool = False
    in_bore: bool = False


def _feature_motion(runner, op, block, params, features: Features) -> bool:
    """Each feature point: G0 to it at RTP, G0 to RFP + SDIS, the plunge to the depth (at
    the depth feed FFD, or G0 for a G0 insertion), (the machining inside the feature), G0
    back to RTP. At a point of None the moves run along the infeed axis only and the plane
    position is unknown. The tool ends at RTP above ``features.end``. False when a level is
    not a number."""
    state = runner.state
    first, second, axis = state.plane_axes
    side, start, depth = levels(params)
    rtp = _get(params, "RTP")
    known = [value for point in features.points if point is not None for value in point]
    if side is None or any(type(value) is not float for value in (start, depth, rtp, *known)):
        return False
    name = op.cycle
    programmed_feed = state.feed
    plunge_feed = _get(params, "FFD")
    for point in features.points:
        if point is None:
            runner.move_to({axis: rtp}, op.span, block, "approach", name)
            state.move_to({first: None, second: None})
        else:
            runner.move_to({first: point[0], second: point[1], axis: rtp}, op.span, block, "approach", name)
        runner.move_to({axis: start}, op.span, block, "into-hole" if features.in_bore else "approach", name)
        if type(plunge_feed) is float and plunge_feed > 0:
            state.feed = plunge_feed  # the depth feed is a parameter of the cycle
        runner.move_to({axis: depth}, op.span, block, "infeed", name, "rapid" if features.g0_insertion else "feed")
        state.feed = programmed_feed
        runner.move_to({axis: rtp}, op.span, block, "out-of-hole", name)
    if features.end is None:
        state.move_to({first: None, second: None})
    else:
        runner.move_to({first: features.end[0], second: features.end[1]}, op.span, block, "retract", name)
    return True


def _centre(first: str, second: str, g0_insertion: bool = False):
    """A feature at one centre given by two parameters, where the tool also ends;
    ``g0_insertion``: the cycle's VARI tens digit 0 plunges with G0."""
    def features(params, state):
        centre = (params.get(first), params.get(second))
        return Features([centre], centre, g0_insertion and _inserts_with_g0(params))
    return features


def _inserts_with_g0(params) -> bool:
    """The tens digit 0 of VARI/_VARI: vertical insertion with G0 (SLOT1 A L5973, POCKET3/4 L7327)."""
    kind = _get(params, "VARI")
    return type(kind) is float and kind // 10 % 10 == 0


def _rectangular_pocket(params, state):
    """POCKET3 plunges at the pocket centre: _PA/_PO, or with _ZSD[2]=1 the corner they
    give plus half of the signed _LENG/_WID along _STA (seed A L7228-7240). Unknown when the
    program does not set _ZSD[2]."""
    corner = state.global_variables.get("_ZSD[2]", state.local_variables.get("_ZSD[2]"))
    x, y, length, width, angle = (params.get(name, 0.0) for name in ("_PA", "_PO", "_LENG", "_WID", "_STA"))
    if corner == 0.0:
        centre = (x, y)
    elif corner == 1.0 and all(type(value) is float for value in (x, y, length, width, angle)):
        cos, sin = math.cos(math.radians(angle)), math.sin(math.radians(angle))
        centre = (x + length / 2 * cos - width / 2 * sin, y + length / 2 * sin + width / 2 * cos)
    else:
        centre = None
    return Features([centre], centre, _inserts_with_g0(params))


def _slots_on_a_circle(params, state):
    """SLOT2's slots start on the circle RAD at STA1 + k*INDA (INDA 0: 360/NUM; seed A
    L6182-6310); the tool ends at RTP above the last one, at a point the cycle computes."""
    count, increment = params.get("NUM"), params.get("INDA", 0.0)
    names = ("CPA", "CPO", "RAD", "STA1")
    if type(count) is not float or not 1 <= count <= 1000 or type(increment) is not float or any(type(params.get(n, 0.0)) is not float for n in names):
        return Features([None], None)
    x, y, radius, angle = (params.get(name, 0.0) for name in names)
    step = increment or 360.0 / count
    points = [(x + radius * math.cos(math.radians(angle + k * step)), y + radius * math.sin(math.radians(angle + k * step))) for k in range(int(count))]
    return Features(points, None)


def _computed_start(inserts_with_g0: bool):
    """A feature whose start point the cycle computes (SLOT1, LONGHOLE: where on the slot the
    reference puts RAD is not recoverable; spigots start outside the blank; external threads
    on the outer diameter): the moves along the infeed axis only."""
    return lambda params, state: Features([None], None, inserts_with_g0 and _inserts_with_g0(params))


def _thread(params, state):
    """CYCLE90: an internal thread (TYPTH 0) starts and ends at the centre CPA/CPO at RTP and
    reaches RFP + SDIS inside its bore (below the surface when milled bottom up); an external
    one starts on the outer diameter (seed A L5203-5296)."""
    if params.get("TYPTH", 0.0) != 0.0:
        return _computed_start(False)(params, state)
    return _centre("CPA", "CPO")(params, state)._replace(in_bore=True)


# Seed A: POCKET1 L6575-6600, POCKET2 L6892, POCKET3 L7058-7106, POCKET4 L7636, SLOT1 L5836-5860,
# SLOT2 L6182-6310, LONGHOLE L5553-5580, CYCLE76 L8655-8700, CYCLE77 L8898-9137, CYCLE90 L5203-5287,
# CYCLE60 L14330-14345 (each character: G0 to RFP + SDIS, one plunge at _FFD; its start point
# depends on the font).
_FEATURES = {"POCKET1": _centre("CPA", "CPO"), "POCKET2": _centre("CPA", "CPO"), "POCKET3": _rectangular_pocket,
             "POCKET4": _centre("_PA", "_PO", g0_insertion=True),
             "SLOT1": _computed_start(True), "SLOT2": _slots_on_a_circle, "LONGHOLE": _computed_start(False),
             "CYCLE76": _computed_start(False), "CYCLE77": _computed_start(False), "CYCLE90": _thread,
             "CYCLE60": _computed_start(False)}


def modal_shape(model: CycleModel):
    return _SHAPES.get(model.shape)


_SHAPES = {"sinumerik_drill": drill, "sinumerik_pattern": pattern, "sinumerik_mill": one_shot,
           "sinumerik_turn": one_shot, "sinumerik_other": one_shot}
CYCLES = DialectCycles(shapes=_SHAPES)


# --------------------------------------------------------------------------- CYCLE95 contour

_CONTOUR_BLOCK_LIMIT = 5000
_NOT_IN_CONTOUR = {"thread": "a thread block", "arc_through": "a CIP arc", "arc_tangent": "a CT arc"}  # alarm 10930 inside a CYCLE95 contour


class ContourFacts:
    """What a contour a cycle names looks like (CYCLE95: reference B section 6.3, rules C2-C13
    and alarm 61607; CYCLE74/75/950: closed contours): the problems found, as ``(alarm, text,
    span)``, the plane points in order with the blocks that reach them (None when a point is
    not a number), the rectangle they span, the motion of the first plane block and the
    block that ends the contour with a rounding or chamfer."""

    def __init__(self, name: str):
        self.name = name
        self.found = False
        self.problems: list[tuple[str, str, object]] = []
        self.points: list[tuple[tuple[float, float], object]] | None = None
        self.box: tuple[float, float, float, float] | None = None
        self.plane_blocks = 0
        self.first_motion: str | None = None
        self.rounded_end = None  # the span of a last plane block carrying RND/CHF/CHR
        self.open_start = None  # the first plane block, when it gives only one of the two plane coordinates
        self.compensation: list = []  # the spans of G40/G41/G42 inside the contour
        self.arcs: dict = {}  # the G2/G3 blocks moving in the plane, by span, with their radius CR (None: not a positive number)
        self.roundings: list = []  # the spans of the plane blocks carrying RND/CHF/CHR
        self.diameter_modes: set = set()  # DIAMON/DIAMOF/DIAM90 set inside the contour (the "diameter" modes)
        self.frames: list = []  # the spans of frame statements inside the contour
        self.section_lines: tuple[int, int] | None = None  # a "START:END" section of the calling program

    def straight(self) -> bool:
        """Whether the contour is its points joined by straight lines (no arc, rounding or chamfer)."""
        return not self.arcs and not self.roundings

    def closed(self) -> bool | None:
        """Whether the last point is the first (None when the points are not known)."""
        if not self.points:
            return None
        return math.dist(self.points[0][0], self.points[-1][0]) < 1e-6


def _named_contour(runner, op, params: dict, where: dict) -> ContourFacts | None:
    """The contour a cycle's string parameters name (``contours`` in cycles.toml): one
    ``name`` ("PROGRAM" or "START:END"), or a ``program`` with ``start`` and ``end`` labels or
    block numbers, any of them empty. None when nothing is named."""
    def text(key):
        value = params.get(where.get(key, ""))
        return value.strip() if isinstance(value, str) else ""

    if "name" in where:
        return read_contour(runner, op, text("name")) if text("name") else None
    program, start, end = text("program"), text("start"), text("end")
    if not (program or start or end):
        return None
    shown = program + (f" {start}..{end}" if start or end else "")
    return read_contour_section(runner, op, program or None, _label(start) or None, _label(end) or None, shown.strip())


def _label(text: str) -> str:
    """A label, or a block number written ``N400`` as the number the frontend looks for."""
    return text[1:] if len(text) > 1 and text[0] in "Nn" and text[1:].isdigit() else text


def read_contour(runner, op, name: str) -> ContourFacts:
    """Read (not run) the contour of CYCLE95/CYCLE72: a program ``"NAME"`` or a section
    ``"START:END"`` of the calling program."""
    if ":" in name and not name.startswith("/"):
        start_label, end_label = (part.strip() for part in name.split(":", 1))
        return read_contour_section(runner, op, None, start_label, end_label, name)
    return read_contour_section(runner, op, name, None, None, name)


def read_contour_section(runner, op, program: str | None, start_label: str | None, end_label: str | None, shown: str) -> ContourFacts:
    """Read the contour in ``program`` (None: the calling program) from ``start_label`` to
    ``end_label`` (None: the whole program). Not found, or labels that are not there exactly
    once in that order, leave ``found`` False."""
    facts = ContourFacts(shown)
    if program:
        found = runner.find_program(program.upper(), op.span) if not program.startswith("/") else None
        if found is None:
            return facts
        source, start = found
    elif start_label and end_label:
        source, start = runner.current_source, 0
    else:
        return facts
    if start_label and end_label:
        starts = list(runner.frontend.label_offsets(source.buffer, start_label.upper()))
        ends = list(runner.frontend.label_offsets(source.buffer, end_label.upper()))
        if len(starts) != 1 or len(ends) != 1 or ends[0] < starts[0]:
            return facts
        lines = ((number, raw) for number, offset, _next, raw in source.lines_from(starts[0]) if offset <= ends[0])
        if source is runner.main_source:
            facts.section_lines = (source.line_number_at(starts[0]), source.line_number_at(ends[0]))
    else:
        lines = ((number, raw) for number, _offset, _next, raw in source.lines_from(start))
    facts.found = True
    path = None if source is runner.main_source else source.name
    _walk_contour(runner, facts, lines, path, runner.state.plane_axes)
    return facts


def _walk_contour(runner, facts: ContourFacts, lines, path, plane) -> None:
    first, second, _normal = plane
    position: dict = {}
    incremental = False
    motion = None
    points: list = []
    exact = True
    for count, (number, raw) in enumerate(lines):
        if count > _CONTOUR_BLOCK_LIMIT:
            break
        for block in runner.frontend.blocks(raw, number, path):
            if count and block.program_start:
                return _close(facts, points, exact)
            for op in block.ops:
                kind = type(op).__name__
                if kind in ("Return", "Stop"):
                    return _close(facts, points, exact)
                if kind == "SetModal" and op.group == "plane":
                    facts.problems.append(("10931", "a plane selection (G17/G18/G19) inside the contour", op.span))
                elif kind == "SetModal" and op.group == "distance":
                    incremental = op.value == "incremental"
                elif kind == "SetModal" and op.group == "diameter":
                    facts.diameter_modes.add(op.value)
                elif kind == "CutterComp":
                    facts.compensation.append(op.span)
                    if op.side in ("left", "right"):
                        facts.problems.append(("10931", "G41/G42 inside the contour", op.span))
                elif kind == "SetFrame" or (kind in ("CoordinateShift", "Unsupported") and "frame" in getattr(op, "what", "frame")):
                    facts.frames.append(op.span)
                    facts.problems.append(("10931", "a frame inside the contour", op.span))
                elif kind == "Move":
                    motion = op.kind or motion
                    in_plane = {axis: value for axis, value in op.targets.items() if axis in (first, second)}
                    if not in_plane:
                        continue
                    if op.kind in _NOT_IN_CONTOUR:
                        facts.problems.append(("10930", f"{_NOT_IN_CONTOUR[op.kind]} (only G0/G1/G2/G3 lines and arcs are allowed)", op.span))
                    if facts.plane_blocks == 0:
                        facts.first_motion = motion
                        facts.open_start = op.span if len(in_plane) < 2 else None
                        if op.kind is None:
                            facts.problems.append(("15800", "the first block moving in the plane has no G0/G1/G2/G3", op.span))
                    radius = _literal((op.arc or {}).get("R"))
                    if type(radius) is float and radius < 0:
                        facts.problems.append(("10931", f"an arc of more than 180 degrees (CR={radius:g})", op.span))
                    facts.plane_blocks += 1
                    facts.rounded_end = op.span if any(word in op.words for word in ("RND", "CHF", "CHR")) else None
                    if facts.rounded_end is not None:
                        facts.roundings.append(op.span)
                    if motion in ("arc_cw", "arc_ccw"):
                        facts.arcs[op.span] = radius if type(radius) is float and radius > 0 else None
                    for axis, value in in_plane.items():
                        value = _literal(value)
                        if type(value) is not float:
                            exact = False
                            continue
                        if incremental or axis in op.incremental:
                            position[axis] = None if position.get(axis) is None else position[axis] + value
                        else:
                            position[axis] = value
                    if position.get(first) is None or position.get(second) is None:
                        exact = exact and facts.plane_blocks > 1
                    else:
                        points.append(((position[first], position[second]), op.span))
    return _close(facts, points, exact)


def _literal(value):
    """A number written with a sign (``CR=-5`` reads as minus 5), else the value as is."""
    if type(value).__name__ == "Unary" and type(value.operand) is float:
        return -value.operand if value.op == "-" else value.operand
    return value


def _close(facts: ContourFacts, points, exact: bool) -> None:
    if facts.plane_blocks < 3:
        facts.problems.append(("10933", f"only {facts.plane_blocks} blocks move in the plane (at least 3 are needed)", None))
    if points and exact:
        facts.points = points
        firsts, seconds = [point[0][0] for point in points], [point[0][1] for point in points]
        facts.box = (min(firsts), max(firsts), min(seconds), max(seconds))
