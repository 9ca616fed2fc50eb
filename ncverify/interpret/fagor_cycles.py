"""How Fagor 8060/8065 cycles move: the planes of the hole cycles and the points of the
multiple-machining patterns G160-G165 (seed 000_a3a484fdafe81829.txt, "seed Lnnnn").

Both plug into the shared cycle runner (:mod:`ncverify.interpret.cycles`): the hole cycles keep the
shared motion model (rapid to the R point, feed to the bottom, retract per G98/G99) with
Fagor's planes; a pattern runs the active cycle's hole at each of its points, so every hole
rule (rapid into the stock, depth, retract) sees the pattern's holes.
"""
from __future__ import annotations

import math

from ..ir import cycle_code
from .. import values
from .cycles import DialectCycles, grid
from ..trace import CycleRun

_SKIP_LETTERS = "PQRSTUV"


def run_turning_cycle(runner, op, block, model, params):
    """A G81-G88 that is a turning cycle here (lathe software, or ``#LATHECY ON``; seed
    L513-550): it replaces any milling cycle, and where it leaves the tool is not known."""
    code = f"G{params.get('G', 0.0):g}"
    runner.cancel_cycle()
    runner.fault("fagor.turning-cycle", op.span, f"{code} is a turning cycle here (lathe software, or #LATHECY ON on a mill): the milling-cycles "
                  "manual does not define the turning cycles, so this block and the moves that depend on it are not verified",
                  "unknown", "turning cycles are not in the Fagor milling-cycles manual")
    runner.state.move_to(dict.fromkeys(runner.state.position))
    return None


# ---------------------------------------------------------------------- hole cycles


def parameter(cycle, data: dict, letter: str):
    """A parameter's value, or its default from the cycle table."""
    value = data.get(letter)
    if value is None:
        value = cycle.model.params[letter].default if letter in cycle.model.params else None
    return value


def hole_levels(runner, cycle, data: dict):
    """``(r_point, bottom[, reference, entry])``: the reference plane Z is absolute in G90 and from the start
    plane in G91 (Zi when not written, seed L867-871); I is absolute in G90 and from Z in
    G91 (seed L873-876); G83's bottom is Z + J*I (seed L1044-1050). V.C.x values are
    absolute (seed L783-784). The R point is where the cycle's rapid approach ends; pockets
    and thread mills, which approach the surface, leave back up to the reference plane
    before any G98 retract (seed L1411, L1530, L1659, L1758, L1899). A thread milled with a
    negative pitch B runs from the thread end up: the tool rapids down the pre-drilled hole
    to the entry height there (seed L1697, L1744, L1885), taken as the thread end I. The
    surface lies D from the reference plane toward the part: along ``#TOOL AX [Z-]``
    (``cycle.up`` = -1, the reference's sigma) the part is on the + side and the offsets flip."""
    incremental = cycle.incremental
    reference = reference_plane(cycle, data)
    if reference is None:
        return None, None
    depth = data.get("I")
    if cycle.model.depth == "pecks":
        count = data.get("J")
        bottom = None if depth is None or count is None else values.add(reference, values.mul(count, depth))
    elif depth is None:
        bottom = None
    elif incremental and "I" not in cycle.absolute:
        bottom = values.add(reference, depth)
    else:
        bottom = depth
    approach = cycle.model.approach
    if approach is None:
        return reference, bottom
    surface = values.sub(reference, values.mul(cycle.up, parameter(cycle, data, "D") or 0.0))
    pitch = data.get("B")
    upward = cycle.model.thread_mill and not (type(pitch) is float and pitch >= 0)
    return (values.add(surface, cycle.up) if approach == "surface_plus_1" else surface), bottom, reference, bottom if upward else None


def around_the_stud(runner, cycle, span, block, levels) -> None:
    """G212 (seed L1879-1901, reference §6.11 and H22), from the rapid over the stud's
    centre: rapid to the reference plane; out to the entry point |J|/2 + R + E from the
    centre at the start angle Q (R the tool radius); down to the entry height (the surface,
    or the thread end when a negative B cuts upward). Without E the tool goes down over the
    centre first and then out to the entry point (step 5, the 3-axis rapid). The thread is
    drawn as a feed along the tool axis at the entry point (the helix's reach along the
    axis, not its circle around the stud); then a rapid up to the reference plane, G98 to
    the start plane, and over the centre again. The radial passes (A, L) repeat these
    rapids: one is drawn. Without the tool radius the passes are not placed and not judged."""
    surface, bottom, reference, upward_entry = levels
    state = runner.state
    axis = runner.drill_axis(cycle.model)
    first, second, _normal = state.plane_axes
    centre = {first: state.position.get(first), second: state.position.get(second)}
    runner.move_to({axis: reference}, span, block, "approach", cycle.cycle)
    point = _entry_point(runner, cycle, centre)
    if point is not None:
        start, end = (surface, bottom) if upward_entry is None else (upward_entry, surface)
        if "E" in cycle.params:
            runner.move_to(point, span, block, "to-thread", cycle.cycle)
            runner.move_to({axis: start}, span, block, "to-thread" if upward_entry is None else "beside-stud", cycle.cycle)
        else:
            runner.move_to({axis: start}, span, block, "over-stud", cycle.cycle)
            runner.move_to(point, span, block, "to-thread", cycle.cycle)
        runner.move_to({axis: end}, span, block, "infeed", cycle.cycle, "feed")
        runner.move_to({axis: reference}, span, block, "out-of-hole", cycle.cycle)
    runner.retract(cycle, span, block)
    runner.move_to(centre, span, block, "retract", cycle.cycle)


def _entry_point(runner, cycle, centre: dict) -> dict | None:
    """Where G212 enters the thread, or None (with an ``unknown`` finding) when the tool
    radius or the start angle is not known."""
    if None in centre.values():
        return None  # the hole's position is not known (fagor.hole-at-unknown-position)
    data = cycle.params
    radius = _tool_radius(runner)
    angle = parameter(cycle, data, "Q")
    code = cycle_code(cycle.cycle)
    if radius is None or type(angle) is not float:
        missing = "the start angle Q is computed" if radius is not None else "the tool radius is not in the tool table"
        runner.fault("core.rapid-into-stock", cycle.param_spans.get("J", cycle.definition), f"{code} runs around the stud at |J|/2 + tool radius + E "
                             f"from its centre, but {missing}: the rapids to the thread and back were not checked", "unknown", missing)
        return None
    distance = values.add(values.mul(values.absolute(data["J"]), 0.5), values.add(radius, data.get("E", 0.0)))
    radians = math.radians(angle)
    directions = (round(math.cos(radians), 12), round(math.sin(radians), 12))  # Q90 is straight along the ordinate, not 6e-17 off it
    return {axis: values.add(centre[axis], values.mul(distance, direction)) for axis, direction in zip(centre, directions)}


def _tool_radius(runner) -> float | None:
    """The radius of the tool in the spindle from the tool table."""
    tool = runner.tool_in_spindle()
    return None if tool is None else tool.radius


def reference_plane(cycle, data: dict):
    written = data.get("Z")
    if written is None:
        return cycle.initial
    if cycle.incremental and "Z" not in cycle.absolute:
        return None if cycle.initial is None else values.add(cycle.initial, written)
    return written


# ---------------------------------------------------------------------- multiple machining


class PatternError(Exception):
    """A pattern the control refuses (the message says why)."""


class PatternTooLarge(Exception):
    """A pattern of more points than may be expanded (``args[0]``: how many)."""


def run_pattern(runner, op, block, model, params):
    state = runner.state
    code = cycle_code(op.cycle)
    runner.report_cycle(CycleRun(op.cycle, model, op.span, block, dict(params), dict(op.param_spans)))
    cycle = state.cycle
    if cycle is None:
        runner.fault("fagor.pattern-without-cycle", op.span, f"{code} repeats the active canned cycle, but no cycle is active here "
                      "(G80, a new plane, #TOOL AX, G74 or M30 cancelled it, or none was defined): the control alarms")
        return None
    first, second, _normal = state.plane_axes
    start = (state.position.get(first), state.position.get(second))
    if not all(type(value) is float for value in params.values()):
        return _unplaced(runner, op, code, state)  # a computed count or step: nothing to check it against
    concrete = all(type(value) is float for value in start)
    try:
        count, points = pattern_points(model.pattern, params, start if concrete else (0.0, 0.0), runner.loop_bound)
    except PatternError as error:
        runner.fault("fagor.pattern-parameters", op.span, f"{code}: {error}: the control alarms")
        return None
    except PatternTooLarge as error:
        runner.within_loop_bound(error.args[0], op.span, code)
        state.move_to({first: None, second: None})
        return None
    skipped = _skip_list(code, params, count, op, runner)
    if not concrete:
        return _unplaced(runner, op, code, state)
    motion = state.modal.get("motion")
    state.modal["motion"] = "rapid" if params.get("C", 0.0) == 0.0 else "linear"  # G160-G162: always G00 (seed L2007)
    for number, (abscissa, ordinate) in enumerate(points, start=2):
        if number not in skipped:
            runner.make_hole(cycle, op.span, block, {first: abscissa, second: ordinate})
    state.modal["motion"] = motion
    return None


def _unplaced(runner, op, code: str, state) -> None:
    """A pattern computed from values not known here: unknown, and the tool is lost."""
    runner.fault("core.unsupported-code", op.span, f"{code} with computed values: its points are not placed; the holes after it are not checked",
                 "unknown", "pattern with symbolic values")
    first, second, _normal = state.plane_axes
    state.move_to({first: None, second: None})


def pattern_points(pattern: str, params: dict, start: tuple[float, float], most: float = math.inf) -> tuple[int, list[tuple[float, float]]]:
    """The point count and the points after the first (which the definition machined);
    :class:`PatternTooLarge` before a list of more than ``most`` points is made."""
    if pattern == "line":
        count, step = _side(params, "X", "I", "K", "the line", most)
        direction = _unit(params.get("A", 0.0))
        return count, [_along(start, direction, step * k) for k in range(1, count)]
    if pattern in ("parallelogram", "grid"):
        count_a, step_a = _side(params, "X", "I", "K", "the first side", most)
        count_b, step_b = _side(params, "Y", "J", "D", "the second side", most)
        _within(count_a * count_b, most)
        angle = params.get("A", 0.0)
        first_side, second_side = _unit(angle), _unit(angle + params.get("B", 90.0))
        nodes = _grid_order(count_a, count_b) if pattern == "grid" else _outline_order(count_a, count_b)
        points = [_along(_along(start, first_side, step_a * i), second_side, step_b * j) for i, j in nodes]
        return len(points), points[1:]
    return _circular(pattern, params, start, most)


def _within(count, most: float) -> None:
    if isinstance(count, (int, float)) and not count <= most:  # NaN too
        raise PatternTooLarge(count)


def _side(params, length_letter, step_letter, count_letter, what, most) -> tuple[int, float]:
    """Exactly two of length, step and count (seed L1986, L2081, L2161)."""
    given = [letter for letter in (length_letter, step_letter, count_letter) if letter in params]
    if len(given) != 2:
        raise PatternError(f"{what} needs exactly two of {length_letter}, {step_letter} and {count_letter} ({', '.join(given) or 'none'} given)")
    length, step, count = params.get(length_letter), params.get(step_letter), params.get(count_letter)
    if count is None:
        if step == 0:
            raise PatternError(f"the step {step_letter}0 is zero")
        exact = abs(length / step)
        _within(exact + 1, most)
        if abs(exact - round(exact)) > 1e-6:
            raise PatternError(f"{length_letter}{length:g} is not a whole number of steps {step_letter}{step:g} ({exact:g})")
        return int(round(exact)) + 1, step
    _within(count, most)
    if not math.isfinite(count) or count != int(count) or count < 1:
        raise PatternError(f"the number of points {count_letter}{count:g} is not a whole number of at least 1")
    if step is None:
        step = length / (count - 1) if count > 1 else 0.0
    return int(count), step


def _unit(degrees: float) -> tuple[float, float]:
    radians = math.radians(degrees)
    return math.cos(radians), math.sin(radians)


def _along(point, direction, distance):
    return point[0] + direction[0] * distance, point[1] + direction[1] * distance


def _grid_order(count_a: int, count_b: int) -> list[tuple[int, int]]:
    """Row by row, each row back the other way (zig-zag; the manual's figure is missing:
    uncertain)."""
    return [(i if j % 2 == 0 else count_a - 1 - i, j) for i, j in grid(count_a, count_b)]


def _outline_order(count_a: int, count_b: int) -> list[tuple[int, int]]:
    """Around the outline, first side first (the figure is missing: uncertain)."""
    if count_a < 2 or count_b < 2:
        return _grid_order(count_a, count_b)
    nodes = [(i, 0) for i in range(count_a)]
    nodes += [(count_a - 1, j) for j in range(1, count_b)]
    nodes += [(i, count_b - 1) for i in range(count_a - 2, -1, -1)]
    nodes += [(0, j) for j in range(count_b - 2, 0, -1)]
    return nodes


def _circular(pattern, params, start, most):
    centre = (start[0] + params.get("X", 0.0), start[1] + params.get("Y", 0.0))
    radius = math.hypot(start[0] - centre[0], start[1] - centre[1])
    if radius == 0:
        raise PatternError("X and Y put the centre on the start point (radius 0)")
    first_angle = math.degrees(math.atan2(start[1] - centre[1], start[0] - centre[0]))
    if pattern == "chord":
        return 2, [_on_circle(centre, radius, _chord_end(params, first_angle, radius))]
    if ("I" in params) == ("K" in params):
        raise PatternError("give exactly one of I (angular step) and K (number of points)")
    total = 360.0 if pattern == "circle" else params.get("B")
    if total is None:
        raise PatternError("the arc's total angle B is missing")
    if "I" in params:
        step = params["I"]
        if step == 0:
            raise PatternError("the angular step I0 is zero")
        exact = abs(total / step)
        _within(exact + 1, most)
        if abs(exact - round(exact)) > 1e-6:
            raise PatternError(f"the angular step I{step:g} does not divide {'360' if pattern == 'circle' else f'B{total:g}'} into whole steps ({exact:g})")
        count = int(round(exact)) + (0 if pattern == "circle" else 1)
    else:
        count = params["K"]
        _within(count, most)
        if not math.isfinite(count) or count != int(count) or count < 1:
            raise PatternError(f"the number of points K{count:g} is not a whole number of at least 1")
        count = int(count)
        step = 360.0 / count if pattern == "circle" else (total / (count - 1) if count > 1 else 0.0)
    return count, [_on_circle(centre, radius, first_angle + step * k) for k in range(1, count)]


def _chord_end(params, first_angle, radius) -> float:
    if ("A" in params) == ("I" in params):
        raise PatternError("give exactly one of A (angle of the chord's bisector) and I (chord length)")
    if "A" in params:
        return 2 * params["A"] - first_angle
    chord = params["I"]
    if abs(chord) > 2 * radius:
        raise PatternError(f"the chord I{chord:g} is longer than the circle's diameter {2 * radius:g}")
    return first_angle + math.copysign(math.degrees(2 * math.asin(abs(chord) / (2 * radius))), chord)


def _on_circle(centre, radius, degrees):
    radians = math.radians(degrees)
    return centre[0] + radius * math.cos(radians), centre[1] + radius * math.sin(radians)


# ---------------------------------------------------------------------- skip lists


def skip_range(value: float) -> tuple[int, int]:
    """``P7`` -> (7, 7); ``Q10.013`` -> (10, 13); ``Q10.13`` -> (10, 130): the fraction is
    always three digits (seed L1995-1996)."""
    first = int(value)
    last = int(round((value - first) * 1000))
    return first, last if last else first


def _skip_list(code, params, count, op, runner) -> set[int]:
    skipped: set[int] = set()
    previous_last, previous_letter = 0, None
    for letter in _SKIP_LETTERS:
        value = params.get(letter)
        if value is None:
            continue
        span = op.param_spans.get(letter, op.span)
        if type(value) is not float or value < 1:
            runner.fault("fagor.pattern-skip-list", span, f"{code} {letter}: points to skip must be given as point numbers n or n.mmm")
            continue
        first, last = skip_range(value)
        shown = f"{letter}{value:g}"
        if last < first:
            runner.fault("fagor.pattern-skip-list", span, f"{code} {shown} skips points {first} to {last}: the range runs backwards "
                          "(the end always has three digits: Q10.13 means 10 to 130, write Q10.013 for 10 to 13)")
        elif first <= previous_last:
            runner.fault("fagor.pattern-skip-list", span, f"{code} {shown} starts at point {first}, not after the points of {previous_letter} (up to {previous_last}): "
                          "P, Q, R, S, T, U, V must name increasing points; the control alarms")
        elif last > count:
            runner.fault("fagor.pattern-skip-list", span, f"{code} {shown} skips points {first} to {last}, but the pattern has only {count} points"
                          + (" (the end always has three digits: this reads as 10 to 130, not 10 to 13)" if last >= 100 and last % 10 == 0 else ""))
        skipped.update(range(first, last + 1))
        previous_last, previous_letter = max(previous_last, last), letter
    return skipped


CYCLES = DialectCycles(shapes={"fagor_pattern": run_pattern, "fagor_turning": run_turning_cycle},
                       levels={"fagor": hole_levels}, passes={"fagor_stud": around_the_stud})
