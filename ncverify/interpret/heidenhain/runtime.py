"""What the Klartext operations that need the machine state do when the interpreter reaches them.

The lowering (:mod:`ncverify.lower.heidenhain`) turns constructs that need machine state
into IR operations (``ir.Pole``, ``ir.PoleArc``, ``ir.LabelCall``, ...) and the
statements no other dialect has into operations of their own type (``ir.DialectStatement``); :data:`OPERATIONS`
gives the interpreter the handler of each, which drives it through the public
:class:`~ncverify.interpret.runtime.Runtime`. Dialect state lives in the
path's :class:`~ncverify.interpret.heidenhain.state.KlartextState` (``state.klartext``),
replaced, never changed in place, so that forked paths keep their own.

Cycle motion (reference A §6.0, "generic hole-cycle kinematics"):

    dir = sign(Q201); Z_sc = Q203 - dir*Q200; Z_bottom = Q203 + Q201;
    Z_ret = Q203 - dir*max(Q200, Q204)

A CALL-active cycle's parameters are evaluated when its ``CYCL DEF`` runs (values frozen
at definition, seed L483-495) and kept until the next ``CYCL DEF``.
"""
from __future__ import annotations

import math
import re
from dataclasses import replace

import numpy

from ... import ir, values
from ...cycle_models import UNKNOWN_CYCLE, CycleModel
from . import special, transforms
from .common import (cycle_feed as _cycle_feed, levels, numbers as _numbers, offset_surface as _offset_surface,
                     plane as _plane, put as _put)
from .state import Definition
from ..arc_geometry import arc_by_centre, end_heading, tangent_arc, unplaced_arc
from ..control_flow import PathEnd
from ..cycles import grid
from ...trace import CycleFacts, CycleRun, Hole

_PLANES = {"xy": ("X", "Y", "Z"), "yz": ("Y", "Z", "X"), "zx": ("Z", "X", "Y")}
# DEF-active cycles (seed L666-688): they act when defined and are never called. 12 and 238
# are in that list too, but their own sections call them (reference B 4.6).
DEF_ACTIVE = frozenset({7, 8, 9, 10, 11, 13, 14, 19, 20, 26, 32, 220, 221, 224, 239, 247, 270, 271, 1271, 1272, 1273, 1278, 1281, 1282})
_SUBPROGRAM_END = re.compile(rb"(?m)^[ \t]*\d*[ \t]*LBL[ \t]*0(?![0-9.])")
_TRANSFORMS = frozenset({7, 8, 10, 11, 19, 26})
_HOLE_FAMILIES = frozenset({"drill", "tap", "thread"})


def batch_allowed(state) -> bool:
    """A batch of plain lines skips what each line's positioning step would do: nothing
    while no cycle waits on positions. Its arcs about a pole run in the working plane, so
    it must be the plane of ``CC X.. Y..``. (An ``R0`` line ends a batch under radius
    compensation: :attr:`ir.MoveBatch.compensation_off`.)"""
    return positioning_is_inert(state) and _plane(state)[:2] == ("X", "Y")


def after_batch(state, run: ir.MoveBatch) -> None:
    """Leave the Klartext state as the batch's lines leave it block by block: the last pole
    its ``CC`` lines set (:func:`_pole_run`), and the plane point its last move reached at
    feed (:func:`_positioned_run`)."""
    changes = {}
    if run.poles is not None:
        set_at = numpy.flatnonzero(~numpy.isnan(run.poles[:, 0]))
        if len(set_at):
            first, second = run.poles[set_at[-1]].tolist()
            changes.update(pole=dict(state.klartext.pole, X=first, Y=second), pole_axes=("X", "Y"))
    moves = numpy.flatnonzero(run.kinds >= 0)
    if len(moves):
        changes["fed_at"] = None if run.kinds[moves[-1]] == ir.MoveBatch.KINDS.index("rapid") else _plane_point(state)
    _put(state, **changes)


# --------------------------------------------------------------------------- contour geometry


def _pole_run(runner, op, block):
    params = runner.words(op.words, op.span)
    state = runner.state
    first, second, normal = _plane(state)
    pole = dict(state.klartext.pole)
    given = []
    for word, value in params.items():
        axis = word[-1]
        if word.startswith("I"):
            current = state.position.get(axis)
            pole[axis] = None if current is None else values.add(current, value)
        else:
            pole[axis] = value
        given.append(axis)
    if not given:
        pole[first], pole[second] = state.position.get(first), state.position.get(second)
        given = [first, second]
    _put(state, pole=pole, pole_axes=tuple(axis for axis in "XYZ" if axis in given) if len(given) == 2 else (first, second))
    return None


def _pole_plane(state):
    """The plane of the arcs about CC: the two axes CC was given in (CAM output writes
    ``CC Y.. Z..`` for arcs in YZ), else the working plane."""
    axes = state.klartext.pole_axes
    working = _plane(state)
    if not axes or set(axes) == set(working[:2]):
        return working
    for plane in _PLANES.values():
        if set(plane[:2]) == set(axes):
            return plane
    return working


def _targets(runner, params: dict, span) -> dict:
    """Absolute end coordinates of the axis words among ``params`` (``IX`` incremental)."""
    position = runner.state.position
    targets = {}
    for word, value in params.items():
        axis = word[-1]
        if len(word) > 2 or axis not in "XYZABCUVW" or word[:-1] not in ("", "I"):
            continue
        if word.startswith("I"):
            current = position.get(axis)
            targets[axis] = None if current is None else values.add(current, value)
        else:
            targets[axis] = value
    return targets


def _arc_run(runner, op, block):
    params = runner.words(op.words, op.span)
    state = runner.state
    first, second, normal = _pole_plane(state)
    pole = state.klartext.pole
    targets = _targets(runner, params, op.span)
    direction = "ccw" if params.get("DR", 1.0) > 0 else "cw"
    _emit_arc(runner, op, block, targets, (pole.get(first), pole.get(second)), (first, second, normal), direction)
    return None


def _emit_arc(runner, op, block, targets, centre, plane, direction) -> None:
    state = runner.state
    start = state.position
    state.move_to(targets)
    state.motion_seen = True
    first, second, _normal = plane
    s1, s2, e1, e2 = start.get(first), start.get(second), state.position.get(first), state.position.get(second)
    c1, c2 = centre
    if None in (s1, s2, e1, e2, c1, c2):
        arc = unplaced_arc(plane, direction)
    else:
        arc = arc_by_centre(direction, plane, c1, c2, s1, s2, e1, e2)
    runner.emit("arc", start, op.span, block, "programmed", None, arc, targets.keys())
    _put(state, fed_at=_plane_point(state))


def _plane_point(state):
    first, second, _normal = _plane(state)
    return state.position.get(first), state.position.get(second)


def _lift_run(runner, op, block):
    """``L Z.. FMAX`` alone. Straight up from where the tool got to at feed, its own body
    already fills the column above the tip: reported as a move out of the cut (the stock
    model is not updated by cutting, so the rapid would read as a crash)."""
    params = runner.words(op.words, op.span)
    state = runner.state
    targets = _targets(runner, params, op.span)
    current, target = state.position.get("Z"), targets.get("Z")
    rising = type(current) is float and type(target) is float and target > current
    in_place = all(targets[axis] == state.position.get(axis) for axis in ("X", "Y") if axis in targets)
    fed_here = state.klartext.fed_at == _plane_point(state) and None not in _plane_point(state)
    state.modal["motion"] = "rapid"
    state.motion_seen = True
    role = "out-of-hole" if rising and fed_here and in_place else "programmed"
    start = state.position
    state.move_to(targets)
    runner.emit("rapid", start, op.span, block, role)
    return None


def _tangent_run(runner, op, block):
    """CT: an arc that leaves the previous contour element tangentially. Its centre follows
    from that element's direction at its end; when the direction is not known exactly the
    arc has no centre, and what it sweeps is unknown (never judged by its chord)."""
    params = runner.words(op.words, op.span)
    state = runner.state
    plane = _pole_plane(state)
    first, second, _normal = plane
    heading = end_heading(state.last_segment, state.position, plane)
    start = state.position
    targets = _targets(runner, params, op.span)
    state.move_to(targets)
    state.motion_seen = True
    end = state.position
    if start.get(_normal) != end.get(_normal):
        arc = unplaced_arc(plane)  # a tangential helix: not modelled
    else:
        arc = tangent_arc(plane, heading, (start.get(first), start.get(second)), (end.get(first), end.get(second)))
    runner.emit("arc", start, op.span, block, "programmed", None, arc, targets.keys())
    _put(state, fed_at=_plane_point(state))
    return None


def _polar_run(runner, op, block):
    """LP / CP: a point given by radius PR and angle PA about the pole CC."""
    params = runner.words(op.words, op.span)
    state = runner.state
    first, second, normal = _pole_plane(state)
    pole = state.klartext.pole
    c1, c2 = pole.get(first), pole.get(second)
    s1, s2 = state.position.get(first), state.position.get(second)
    end = _polar_end(params, c1, c2, s1, s2)
    targets = {first: end[0], second: end[1]} if end else {first: None, second: None}
    for word in (normal, "I" + normal):
        if word in params:
            targets.update(_targets(runner, {word: params[word]}, op.span))
    kind = op.kind
    if kind == "arc":
        turn = params.get("DR")
        if turn is None:
            turn = params.get("IPA", 1.0) if type(params.get("IPA", 1.0)) is float else 1.0
        _emit_arc(runner, op, block, targets, (c1, c2), (first, second, normal), "ccw" if turn > 0 else "cw")
        return None
    start = state.position
    state.move_to(targets)
    state.motion_seen = True
    runner.emit("rapid" if kind == "rapid" else "feed", start, op.span, block)
    return None


def _polar_end(params, c1, c2, s1, s2):
    if type(c1) is not float or type(c2) is not float:
        return None
    if type(s1) is float and type(s2) is float:
        radius = math.hypot(s1 - c1, s2 - c2)
        angle = math.degrees(math.atan2(s2 - c2, s1 - c1))
    else:
        radius = angle = None  # an absolute PR and PA need no start point
    if "PR" in params:
        radius = params["PR"]
    elif "IPR" in params and radius is not None:
        radius = values.add(radius, params["IPR"])
    if "PA" in params:
        angle = params["PA"]
    elif "IPA" in params and angle is not None:
        angle = values.add(angle, params["IPA"])
    if type(radius) is not float or type(angle) is not float:
        return None
    return c1 + radius * math.cos(math.radians(angle)), c2 + radius * math.sin(math.radians(angle))


def _retract_run(runner, op, block):
    """M140 MB: retract along the tool axis, by MB or to the travel limit (MB MAX)."""
    amount = runner.words({"MB": op.amount}, op.span).get("MB")
    state = runner.state
    axis = _plane(state)[2]
    if amount == "MAX":
        state.park((axis,))  # up to the software limit: the top of the travel, unknown in workpiece coordinates
        return None
    if type(amount) is str or amount is None:
        state.move_to({axis: None})
        return None
    current = state.position.get(axis)
    runner.move_to({axis: None if current is None else values.add(current, amount)}, op.span, block, "retract", None)
    return None


def _tool_delta_run(runner, op, block):
    _put(runner.state, radius_delta=runner.evaluate(op.radius, op.span), length_delta=runner.evaluate(op.length, op.span))
    return None


def _tool_feed_run(runner, op, block):
    feed = runner.words({"F": op.feed}, op.span)
    if "F" in feed:
        _put(runner.state, tool_feed=feed["F"])
    return None


# --------------------------------------------------------------------------- program flow


def _label_call_run(runner, op, block):
    """CALL LBL n [REP r]: a label before the call with no LBL 0 between them repeats the
    program section r more times (seed L8265-8273); otherwise the subprogram runs (r + 1
    times) and returns at its LBL 0."""
    params = runner.words({"label": op.label, "REP": op.repeat}, op.span)
    state = runner.state
    label = params.get("label")
    repeat = params.get("REP", 0.0)
    if type(label) not in (float, str):
        runner.unsupported(op.span, "a label call whose label depends on a free parameter")
        raise PathEnd
    if type(repeat) is not float:
        runner.unsupported(op.span, "a REP count that depends on a free parameter")
        raise PathEnd
    target = runner.find_label(label, op.span)
    here = runner.current_offset
    if (target.source is runner.current_source and target.offset < here and not _returns_between(runner, target, here)
            and not _inside_subprogram(state, target)):
        repeats = state.klartext.label_repeats
        done = repeats.get(here, 0)
        if done < repeat:
            _put(state, label_repeats={**repeats, here: done + 1})
            runner.count_jump(target, op.span, f"the repeat of {runner.frontend.describe_label(label)}")
            return target
        _put(state, label_repeats={**repeats, here: 0})
        return None
    call = ir.Call(op.span, "local", label, repeat + 1.0)
    return runner.call_subprogram(call, block)


def _inside_subprogram(state, target) -> bool:
    """Is the label's own subprogram running (a call to it from inside is recursion, which
    the control refuses, not a section repeat)?"""
    return any(frame.kind == "local" and frame.source is target.source and frame.start == target.offset for frame in state.call_stack)


def _returns_between(runner, target, end: int) -> bool:
    """Is there an LBL 0 between a label and the call (the label starts a subprogram)?"""
    text = bytes(runner.current_source.buffer[target.offset:end]).upper()
    return _SUBPROGRAM_END.search(text) is not None


# --------------------------------------------------------------------------- cycles


_CYCLE_Q = re.compile(r"Q(?:[2-9]\d\d|[1-9]\d{3,})")  # Q200 on: the cycles' own parameters (the SL cycles' Q1-Q20 are judged apart)


def _defined_cycle(state):
    """The CALL-active cycle as a call runs it: its Q parameters are the control's global Q
    parameters, which CYCL DEF wrote and the program may have written again since."""
    definition = state.klartext.cycle
    if definition is None:
        return None
    variables = state.global_variables
    current = {name: variables.get(name, value) if _CYCLE_Q.fullmatch(name) else value for name, value in definition.params.items()}
    if all(current[name] is value for name, value in definition.params.items()):
        return definition
    return replace(definition, params=current)


def _define_run(runner, op: ir.CycleDefine, block):
    """CYCL DEF: a DEF-active cycle acts now, the others become the cycle the next call runs."""
    params = runner.words(op.params, op.span)
    state = runner.state
    number = int(ir.cycle_code(op.cycle))
    cycle_model = runner.cycle_model(op.cycle)
    defaults = state.klartext.global_defaults
    for name, value in list(params.items()):
        if value == "PREDEF":
            if name in defaults:
                params[name] = defaults[name]  # the GLOBAL DEF value (seed L854-881)
            else:
                runner.fault("core.unsupported-code", op.param_spans.get(name, op.span), f"{name} is PREDEF but no GLOBAL DEF before it gives the value: "
                              "the control's stored default is not known here", "unknown", "PREDEF without GLOBAL DEF")
    unreadable = _read_tolerances(params, cycle_model)
    if number in DEF_ACTIVE:
        return _def_active(runner, op, block, number, params, cycle_model, CycleFacts(bad_tolerances=unreadable))
    definition = Definition(number, params, dict(op.param_spans), op.span, cycle_model)
    _put(state, cycle=definition)
    _put(state, m89=False)
    for name, value in params.items():  # its Q parameters are the control's own: the call reads them as they are then
        if _CYCLE_Q.fullmatch(name):
            state.global_variables[name] = value
    if cycle_model is UNKNOWN_CYCLE:
        runner.fault("core.unsupported-code", op.span, f"cycle {number} is read but not modelled; checks that depend on its motion answer unknown",
                      "unknown", f"cycle {number}")
    return None


def _read_tolerances(params: dict, cycle_model: CycleModel) -> tuple:
    """A toleranced dimension written as text (``Q218="10H7"``) becomes the size the control
    machines; the (parameter, text) the control cannot read are returned for the rules (only
    the OCM shapes take such texts, and they act when defined)."""
    from .tolerance import toleranced

    unreadable = []
    for name, spec in cycle_model.params.items():
        text = params.get(name)
        if spec.tolerance and isinstance(text, str) and text not in ("PREDEF", "AUTO", "FMAX"):
            size = toleranced(text)
            if size is None:
                unreadable.append((name, text))
                del params[name]
            else:
                params[name] = size
    return tuple(unreadable)


def _def_active(runner, op, block, number, params, cycle_model, facts: CycleFacts):
    state = runner.state
    runner.report_cycle(CycleRun(f"heidenhain.{number}", cycle_model, op.span, block, _numbers(params), dict(op.param_spans), facts=facts))
    if number in (220, 221):
        size = _pattern_size(number, params)
        points = _pattern_points(number, params) if size is not None and runner.within_loop_bound(size, op.span, f"cycle {number}") else None
        if points is None:
            if size is None:
                runner.fault("core.unsupported-code", op.span, f"cycle {number}'s points depend on free parameters; the holes are not placed", "unknown", f"cycle {number}")
            state.move_to(dict.fromkeys(_plane(state)[:2]))
            return None
        return _run_at_points(runner, op, block, points, pattern=params)
    if number == 247:
        transforms.reset(runner, transforms.RESET_BY_DATUM_SETTING)  # seed L8221-8223
        runner.unfollowed("cycle 247 activated another preset: where the part lies in it is not known")
        return None
    if number == 20:
        _put(state, sl_data=(_numbers(params), dict(op.param_spans), op.span))
        return None
    if number == 14:
        _put(state, sl_labels=tuple(value for key, value in sorted(params.items()) if key.startswith("L")))
        _put(state, contour_source=("cycle 14", op.span, None, None))
        return None
    if number == 270:  # the contour train data of 25 and 276 (seed L9908-9974)
        _put(state, train_data=(_numbers(params), dict(op.param_spans)))
        return None
    if number in (9, 32, 13, 239):
        return None
    if number == 224:
        return special.datamatrix(runner, op, block)
    if number in (271, 1271, 1272, 1273, 1278):  # OCM data, with a standard shape (reference B 6.21)
        _put(state, ocm=(number, _numbers(params), dict(op.param_spans)))
        _put(state, ocm_boundary=None)  # a shape cancels the boundary before it (seed L12143-12145)
        return None
    if number in (1281, 1282):
        _put(state, ocm_boundary=number)
        return None
    if number in _TRANSFORMS:
        if params:  # without words it is the header of the old-style sub-blocks (CYCL DEF 7.0 DATUM SHIFT)
            _transform(runner, op, number, params)
        return None
    runner.fault("core.unsupported-code", op.span, f"cycle {number} is read but not modelled; checks that depend on it answer unknown", "unknown", f"cycle {number}")
    return None


def _old_cycle_run(runner, op, block, params):
    """Old-style two-part cycles ``CYCL DEF 7.0`` / ``7.1 X+60``, the old fixed cycles 1-5
    and 18 (their data arrive in sub-blocks and join the definition); the data blocks of a
    DEF-active one (9.1 DWELL, 32.1 T) go to the rules as they come."""
    state = runner.state
    number, sub = op.number, op.sub
    cycle_model = runner.cycle_model(f"heidenhain.{number}")
    if sub == 0:
        _put(state, old_cycle=(number, {}))
        if number not in DEF_ACTIVE:
            _put(state, cycle=Definition(number, {}, {}, op.span, cycle_model))
            _put(state, m89=False)
        return None
    if number not in DEF_ACTIVE:
        definition = state.klartext.cycle
        if definition is not None and definition.number == number:
            program = op.program if op.program is not None else definition.program
            _put(state, cycle=replace(definition, params={**definition.params, **params}, spans={**definition.spans, **op.param_spans}, program=program))
        return None
    runner.report_cycle(CycleRun(f"heidenhain.{number}", cycle_model, op.span, block, _numbers(params), dict(op.param_spans)))
    if number == 14:
        labels = tuple(params[key] for key in sorted((key for key in params if key.startswith("L")), key=lambda key: int(key[1:])))
        _put(state, sl_labels=labels)
        _put(state, sl_kinds=None)
        _put(state, contour_source=("cycle 14", op.span, None, None))
    elif number in _TRANSFORMS:
        _transform(runner, op, number, params)
    return None


def _transform(runner, op, number, params) -> None:
    """Datum shift, mirror, rotation, scaling, working plane: the frame from program to
    BLK FORM coordinates (:mod:`ncverify.interpret.heidenhain.transforms`)."""
    state = runner.state
    transforms.transform(runner, op, number, params)
    if number == 10:
        state.comp_side = "off"  # cycle 10 cancels radius compensation (seed L7904)
    tool_axis = _plane(state)[2]
    if number == 8 and (tool_axis in params or "I" + tool_axis in params):
        runner.fault("heidenhain.mirror-tool-axis", op.span, f"cycle 8 mirrors the tool axis {tool_axis}: the spindle axis may not be mirrored (seed L7869-7870)")


def _global_def_run(runner, op, block, params):
    state = runner.state
    merged = dict(state.klartext.global_defaults)
    merged.update(params)
    _put(state, global_defaults=merged)
    return None


def _contour_def_run(runner, op, block, params):
    """CONTOUR DEF names each subcontour's kind: P pocket, I island, V void (machined as an
    island), each with an optional DEPTH (``D<n>``). It also makes the control forget the
    radius of the last roughing tool (seed L11284-11286)."""
    order = sorted((key for key in params if key[0] in "PIV"), key=lambda key: int(key[1:]))
    state = runner.state
    _put(state, sl_labels=tuple(params[key] for key in order))
    _put(state, sl_kinds=tuple(key[0] == "P" for key in order))
    depths = tuple(params.get(f"D{key[1:]}") for key in order)
    _put(state, contour_source=("CONTOUR DEF", op.span, tuple(key[0] for key in order), depths))
    _put(state, roughed_since_contour_def=False)
    return None


def _select_contour_run(runner, op, block, params):
    """SEL CONTOUR: a contour the SL and OCM cycles may use, from a program not read here;
    like CONTOUR DEF it makes the control forget the last roughing tool (seed L11284-11286)."""
    state = runner.state
    _put(state, sl_labels=())
    _put(state, sl_kinds=None)
    _put(state, contour_source=("SEL CONTOUR", op.span, None, None))
    _put(state, roughed_since_contour_def=False)
    return None


def _declare_contour_run(runner, op, block, params):
    """DECLARE CONTOUR of a contour-definition program goes to the rules with whether each
    declaration so far had a DEPTH (all or none must, seed L14464-14465) and the Q1-Q20 the
    program has set, which the SL cycles also use (seed L9360-9361)."""
    state = runner.state
    declared = state.klartext.declared_depths + ("DEPTH" in params,)
    _put(state, declared_depths=declared)
    runner.report_cycle(CycleRun("heidenhain.declare-contour", UNKNOWN_CYCLE, op.span, block, {},
                                 facts=CycleFacts(declared_depths=declared, own_q=_own_reserved(state))))
    return None


def _trans_run(runner, op, block, params):
    what = params.pop("what", "DATUM")
    number = {"DATUM": 7, "MIRROR": 8, "ROTATION": 10, "SCALE": 11, "PLANE": 19}.get(what, 7)
    if params.pop("reset", None) is not None or what == "RESET":
        transforms.reset(runner, {number}, op.span)
        return None
    _transform(runner, op, number, params)
    return None


def _pattern_run(runner, op, block, params):
    tool_axis = _plane(runner.state)[2]
    if tool_axis != "Z":
        runner.fault("heidenhain.pattern-tool-axis", op.span, f"PATTERN DEF with the tool axis {tool_axis}: the pattern computes X and Y only, "
                             "so its points are not where they are meant to be in this working plane (seed L1079-1085)")
    forms = {}
    for key, value in params.items():
        index, word = key.split(":", 1)
        forms.setdefault(int(index), {})[word] = value
    points = []
    if not runner.within_loop_bound(sum(_pattern_form_size(form) for form in forms.values()), op.span, "PATTERN DEF"):
        forms = {}
        points = None
    for index in sorted(forms):
        found = _pattern_form_points(forms[index], points)
        if found is None:
            points = None
            break
        points.extend(found)
    _put(runner.state, pattern=None if points is None else tuple(points))
    return None


def _pattern_form_size(form: dict) -> float:
    """At most how many points one PATTERN DEF element has (0 when a count is not a number:
    then the element is not expanded anyway)."""
    counts = [form.get(key, 1.0) for key in ("NUM", "NUMX", "NUMY")]
    return math.prod(max(count, 1.0) for count in counts) if all(type(count) is float for count in counts) else 0.0


def _pattern_form_points(form: dict, earlier: list):
    """The X, Y (and surface Z) of one PATTERN DEF element (reference A §4.5); the caller
    bounds their number with :func:`_pattern_form_size` first."""
    kind = form.get("form")
    words = {key: value for key, value in form.items() if key != "form"}
    if not all(type(value) is float and math.isfinite(value) for value in words.values()):
        return None
    z = words.get("Z", 0.0)
    if kind == "POS":
        last = earlier[-1] if earlier else (0.0, 0.0, 0.0)
        x = words["X"] if "X" in words else last[0] + words.get("IX", 0.0)
        y = words["Y"] if "Y" in words else last[1] + words.get("IY", 0.0)
        return [(x, y, words.get("Z", last[2] + words.get("IZ", 0.0) if "IZ" in words else z))]
    x0, y0 = words.get("X", 0.0), words.get("Y", 0.0)
    rotation = math.radians(words.get("ROT", 0.0))
    if kind == "ROW":
        return [_rotated(x0, y0, index * words.get("D", 0.0), 0.0, rotation, z) for index in range(int(words.get("NUM", 0)))]
    if kind in ("PAT", "FRAME"):
        columns, rows = int(words.get("NUMX", 0)), int(words.get("NUMY", 0))
        return [_rotated(x0, y0, column * words.get("DX", 0.0), row * words.get("DY", 0.0), rotation, z) for column, row in grid(columns, rows)
                if kind == "PAT" or not (0 < row < rows - 1 and 0 < column < columns - 1)]
    if kind in ("CIRC", "PITCHCIRC"):
        count = int(words.get("NUM", 0))
        radius = words.get("D", 0.0) / 2.0
        step = words.get("STEP", 360.0 / count if count else 0.0) if kind == "PITCHCIRC" else (360.0 / count if count else 0.0)
        start = words.get("START", 0.0)
        return [(x0 + radius * math.cos(math.radians(start + index * step)), y0 + radius * math.sin(math.radians(start + index * step)), z)
                for index in range(count)]
    return None


def _rotated(x0, y0, dx, dy, angle, z):
    return (x0 + dx * math.cos(angle) - dy * math.sin(angle), y0 + dx * math.sin(angle) + dy * math.cos(angle), z)


def _pattern_size(number: int, params: dict) -> float | None:
    """How many points cycle 220 (Q241) or 221 (Q242 x Q243) has; None when not numbers."""
    counts = [params.get(name) for name in (("Q241",) if number == 220 else ("Q242", "Q243"))]
    return math.prod(max(count, 0.0) for count in counts) if all(type(count) is float for count in counts) else None


def _pattern_points(number: int, params: dict):
    """Cycle 220 (polar) / 221 (Cartesian) pattern points (reference B); the caller bounds
    their number with :func:`_pattern_size` first."""
    if number == 220:
        names = ("Q216", "Q217", "Q244", "Q245", "Q246", "Q247", "Q241")
        found = [params.get(name) for name in names]
        if any(type(value) is not float for value in found):
            return None
        x0, y0, diameter, start, end, step, count = found
        count = int(max(count, 0.0))
        if step == 0.0 and count > 1:
            span = end - start
            step = span / count if abs(span) >= 360.0 else span / (count - 1)
        return [(x0 + diameter / 2 * math.cos(math.radians(start + index * step)), y0 + diameter / 2 * math.sin(math.radians(start + index * step)), 0.0)
                for index in range(count)]
    names = ("Q225", "Q226", "Q237", "Q238", "Q242", "Q243")
    found = [params.get(name) for name in names]
    if any(type(value) is not float for value in found):
        return None
    x0, y0, dx, dy, columns, rows = found
    rotation = math.radians(params.get("Q224", 0.0) if type(params.get("Q224", 0.0)) is float else 0.0)
    return [_rotated(x0, y0, column * dx, row * dy, rotation, 0.0) for column, row in grid(columns, rows)]


def _call_run(runner, op, block, params):
    """CYCL CALL / CYCL CALL PAT / CYCL CALL POS / M99 / M89 (seed L692-791)."""
    state = runner.state
    how = params.get("how", "CALL")
    definition = _defined_cycle(state)
    if how in ("M89", "M99"):
        _put(state, m89=how == "M89")
    if definition is None:
        runner.fault("heidenhain.call-without-cycle", op.span, f"{_call_words(how)} with no machining cycle defined before it: the control stops with an error "
                      "(define the cycle with CYCL DEF first)")
        return None
    if state.tool_in_spindle is None and state.call_stack[0].kind == "main":
        runner.fault("heidenhain.call-without-tool", op.span, f"{_call_words(how)} runs cycle {definition.number} before any TOOL CALL: the control needs a "
                      "called tool to run a cycle (seed L655-664)")
    if how == "PAT":
        points = state.klartext.pattern
        if points is None:
            runner.fault("core.unsupported-code", op.span, "CYCL CALL PAT without a PATTERN DEF whose points are known (a point table?) is not modelled",
                          "unknown", "CYCL CALL PAT")
            state.move_to(dict.fromkeys(state.position))
            return None
        return _run_at_points(runner, op, block, list(points), params.get("F"))
    if how == "POS":
        missing = [axis for axis in "XYZ" if axis not in params and "I" + axis not in params]
        if missing:
            runner.fault("heidenhain.call-pos-axes", op.span, f"CYCL CALL POS without {', '.join(missing)}: all three coordinates must be programmed (seed L710-737)")
        targets = _targets(runner, params, op.span)
        axis = _plane(state)[2]
        runner.move_to({a: v for a, v in targets.items() if a != axis}, op.span, block, "between-holes", f"heidenhain.{definition.number}")
        return run_cycle(runner, op, block, definition, shift=targets.get(axis))
    return run_cycle(runner, op, block, definition)


def _positioned_run(runner, op, block):
    """After M89 every positioning block runs the cycle, until M99 or a new CYCL DEF
    (seed L742-752). Its words are numbers the lowering wrote: nothing to evaluate."""
    params = op.params
    state = runner.state
    _put(state, fed_at=_plane_point(state) if params.get("fed") else None)
    ended = state.klartext.ended_elsewhere
    if ended is not None and params.get("plane"):
        _put(state, ended_elsewhere=None)
        if params.get("relative") or params.get("plane") < 2:
            runner.fault("heidenhain.position-after-cycle", op.span, f"cycle {ended} leaves the tool at the clearance height but not over its start point: "
                                 "the first positioning after it must give both plane axes absolute; an incremental or single-axis move goes somewhere else (seed L5930-5940)")
    if not state.klartext.m89:
        return None
    definition = _defined_cycle(state)
    if definition is None:
        return None
    return run_cycle(runner, op, block, definition)


def positioning_is_inert(state) -> bool:
    """Does a positioning line do nothing beyond moving and noting the point it reached at
    feed (no M89 cycle to run at each position, no cycle end to check)? Then plain lines
    may run as a batch (:func:`batch_allowed`)."""
    return not state.klartext.m89 and state.klartext.ended_elsewhere is None


def _call_words(how: str) -> str:
    return {"CALL": "CYCL CALL", "PAT": "CYCL CALL PAT", "POS": "CYCL CALL POS"}.get(how, how)


def _run_at_points(runner, op, block, points, feed=None, pattern: dict | None = None):
    """The cycle at every point of a pattern. PATTERN DEF with CYCL CALL PAT: between
    points at the 2nd set-up clearance or the height at the call, whichever is higher (seed
    L1147-1149). Cycles 220/221 (``pattern`` = their parameters): their Q200, Q203, Q204
    replace the machining cycle's for this and every later call, and with Q301 = 0 the
    tool moves between points at the set-up clearance only (reference B H34, H17)."""
    state = runner.state
    definition = _defined_cycle(state)
    if definition is None:
        runner.fault("heidenhain.call-without-cycle", op.span, "a pattern runs with no machining cycle defined before it: the control stops with an error")
        return None
    if pattern is not None:
        overrides = {name: pattern[name] for name in ("Q200", "Q203", "Q204") if name in pattern}
        definition = replace(definition, params={**definition.params, **overrides})
        _put(state, cycle=definition)
    low = pattern is not None and pattern.get("Q301") == 0.0 and "Q200" in definition.params
    first, second_axis, axis = _plane(state)
    name = f"heidenhain.{definition.number}"
    for index, (x, y, z) in enumerate(points):
        level = state.position.get(axis)
        runner.move_to({first: x, second_axis: y}, op.span, block, "between-holes", name, "rapid" if feed in (None, "FMAX") else "feed")
        here = definition
        if low and index < len(points) - 1:
            here = replace(definition, params={**definition.params, "Q204": definition.params["Q200"]})
        surface = here.params.get("Q203")
        if z and type(surface) is float and surface != 0.0 and pattern is None:
            runner.fault("heidenhain.pattern-surface", op.span, f"pattern point X{x:g} Y{y:g} gives the surface Z{z:g} and cycle {definition.number} has "
                                 f"Q203={surface:g}: the two add up, the surface is offset twice (seed L1168-1169)")
        run_cycle(runner, op, block, here, surface_offset=z if z else None)
        if pattern is None and level is not None and state.position.get(axis) is not None and _higher(level, state.position[axis]):
            runner.move_to({axis: level}, op.span, block, "retract", name)
    return None


def _higher(a, b) -> bool:
    return type(a) is float and type(b) is float and a > b


def run_cycle(runner, op, block, definition: Definition, shift=None, surface_offset=None):
    model = definition.model
    family = model.family
    state = runner.state
    if state.comp_side in ("left", "right"):
        runner.fault("heidenhain.cycle-with-compensation", op.span, f"cycle {definition.number} is called while radius compensation "
                      f"{'RL' if state.comp_side == 'left' else 'RR'} is on: position to the cycle's start point with R0 (seed L1629)")
    if family in _HOLE_FAMILIES:
        return _hole(runner, op, block, definition, shift, surface_offset)
    if family == "back_bore":
        return _back_bore(runner, op, block, definition, shift, surface_offset)
    if family in ("pocket", "stud", "slot", "face"):
        return _pocket(runner, op, block, definition, shift, surface_offset)
    if family == "contour" and definition.number in (21, 22, 23, 24):
        return _sl_cycle(runner, op, block, definition)
    if family == "contour_train":
        return _contour_train(runner, op, block, definition)
    if family == "cylinder":
        return _cylinder_cycle(runner, op, block, definition)
    if family == "ocm":
        return _ocm_cycle(runner, op, block, definition)
    special = _SPECIAL_FAMILIES.get(family)
    if special is not None:
        return special(runner, op, block, definition, shift, surface_offset)
    if family == "old":  # the old fixed cycles start and end at the position of the call
        runner.report_cycle(CycleRun(f"heidenhain.{definition.number}", model, op.span, block, _numbers(definition.params), dict(definition.spans)))
        return None
    runner.report_cycle(CycleRun(f"heidenhain.{definition.number}", model, op.span, block, _numbers(definition.params), dict(definition.spans)))
    runner.fault("core.unsupported-code", op.span, f"the motion of cycle {definition.number} is not modelled; checks that depend on it answer unknown",
                  "unknown", f"cycle {definition.number}")
    state.move_to(dict.fromkeys(state.position))
    return None


def _surface_and_depth(params: dict, start: str, end: str) -> None:
    """A cycle that gives its start and end point in the tool axis (233: Q227 and Q386, seed
    L7112-7528) has the surface Q203 at the start and the depth Q201 from start to end; the
    depth is unknown unless both are numbers."""
    params.pop("Q201", None)
    if type(params.get(start)) is float and type(params.get(end)) is float:
        params.update(Q203=params[start], Q201=params[end] - params[start])


def _depth_name(definition: Definition) -> str:
    return definition.model.depth or "Q201"


def _hole(runner, op, block, definition, shift, surface_offset):
    state = runner.state
    axis = _plane(state)[2]
    params = dict(definition.params)
    _offset_surface(params, shift, surface_offset)
    name = f"heidenhain.{definition.number}"
    model = definition.model
    required = [q for q, spec in model.params.items() if spec.required]
    missing = tuple(q for q in required if q not in params)
    found = levels(params, _depth_name(definition))
    set_up, bottom, retract = (found[:3] if found else (None, None, None))
    predrilled = _predrilled(state, set_up) or _taps_an_earlier_hole(state, model)
    hole = Hole(name, model, op.span, block, axis, dict(state.position), retract, None if predrilled else set_up, bottom, _numbers(params),
                dict(definition.spans), missing, definition.span)
    runner.report_hole(hole)
    depth = params.get(_depth_name(definition))
    if missing or depth == 0.0:
        return None  # the control alarms, or skips a cycle of depth 0 (seed L1630-1631)
    if found is None:
        state.move_to({axis: None})  # levels not known (PREDEF, a keyword): the cycle runs, to heights not known here
        return None
    deepened = _deepened_start(params, set_up, found[3])
    deepened_predrilled = deepened is not None and _predrilled(state, deepened)
    _remember_hole(state, bottom)
    runner.move_to({axis: set_up}, op.span, block, "into-hole" if predrilled else "approach", name)
    if deepened is not None:
        _to_deepened_start(runner, op, block, deepened, params.get("Q253"), deepened_predrilled, name)
    spindle = state.spindle
    if model.spindle_by_cycle and spindle == "off":
        state.spindle = "cw"  # rigid tapping runs the spindle itself; it stays stopped after (seed L3915-3917)
    with _cycle_feed(state, params):
        runner.move_to({axis: bottom}, op.span, block, "infeed", name, "feed")
        out_kind = "feed" if model.retract == "feed" else "rapid"
        runner.move_to({axis: set_up}, op.span, block, "out-of-hole", name, out_kind)
    state.spindle = spindle
    runner.move_to({axis: retract}, op.span, block, "out-of-hole", name)  # on up the same axis
    return None


def _deepened_start(params, set_up, direction):
    """205 and 241 with a deepened starting point Q379 start drilling at the set-up clearance
    above Q203 - Q379 (the retracts still go to Q203 + Q200); None without one."""
    deepening = params.get("Q379")
    if type(deepening) is not float or deepening <= 0.0:
        return None
    return values.add(set_up, values.mul(direction, deepening))


def _to_deepened_start(runner, op, block, level, feed, predrilled: bool, name) -> None:
    """Down to the deepened starting point at Q253, FMAX allowed: into solid material unless
    a hole is already there (reference A H30, seed L2438-2441, L2651-2656)."""
    axis = _plane(runner.state)[2]
    if feed == "FMAX":
        runner.move_to({axis: level}, op.span, block, "into-hole" if predrilled else "approach", name)
        return
    with _cycle_feed(runner.state, {"Q206": feed}):
        runner.move_to({axis: level}, op.span, block, "infeed", name, "feed")


def _back_bore(runner, op, block, definition, shift, surface_offset):
    """Cycle 204 (seed L2267-2291): FMAX to Q203 + Q200, down the pre-bored hole at Q253
    until the cutting edge is Q200 below the underside (the bar's tip Q252 lower still),
    counterbore up to the underside + Q249 at Q254, back out and up to the clearance."""
    state = runner.state
    params = dict(definition.params)
    _offset_surface(params, shift, surface_offset)
    name = f"heidenhain.{definition.number}"
    runner.report_cycle(CycleRun(name, definition.model, op.span, block, _numbers(params), dict(definition.spans)))
    axis = _plane(state)[2]
    found = [params.get(q) for q in ("Q203", "Q200", "Q250", "Q252", "Q249")]
    if any(type(value) is not float for value in found):
        state.move_to({axis: None})
        return None
    surface, clearance, thickness, edge, counterbore = found
    second = params.get("Q204", 0.0)
    underside = surface - thickness
    runner.move_to({axis: surface + clearance}, op.span, block, "approach", name)
    runner.move_to({axis: underside - clearance - edge}, op.span, block, "through-bore", name)
    with _cycle_feed(state, {"Q206": params.get("Q254")}):
        runner.move_to({axis: underside + counterbore - edge}, op.span, block, "infeed", name, "feed")
    runner.move_to({axis: underside - clearance - edge}, op.span, block, "out-of-hole", name)
    runner.move_to({axis: surface + max(clearance, second if type(second) is float else 0.0)}, op.span, block, "out-of-hole", name)
    return None


def _sl_cycle(runner, op, block, definition):
    """SL cycles 21-24: the contour of cycle 14 / CONTOUR DEF, the data of cycle 20. The
    cycle moves to set-up clearance Q5 + Q6, machines to Q5 + Q1 and leaves the tool at the
    clearance height Q7 with its plane position unknown (posAfterContPocket, reference B
    §4.5); the contour's region goes to the rules as ``CycleFacts.region``."""
    from .contour import contours, region
    state = runner.state
    name = f"heidenhain.{definition.number}"
    labels = state.klartext.sl_labels
    data = state.klartext.sl_data
    contour = labels or (state.klartext.contour_source or ("",))[0] == "SEL CONTOUR"
    if not contour or data is None:
        missing = " and ".join(what for what, have in (("a contour (cycle 14 or CONTOUR DEF)", contour), ("contour data (cycle 20)", data)) if not have)
        runner.fault("heidenhain.sl-prerequisites", op.span, f"cycle {definition.number} is called without {missing} defined before it: the control stops with an error (seed L9532-9535)")
        state.move_to(dict.fromkeys(state.position))
        return None
    params = dict(data[0])
    params.update(_numbers(definition.params))
    spans = dict(data[1])
    spans.update(definition.spans)
    use = _contour_use(runner, op)
    found = contours(use.subprograms, labels)
    kinds = state.klartext.sl_kinds
    if found is not None and kinds is not None:
        found = [replace(contour, pocket=pocket) for contour, pocket in zip(found, kinds)]
    area = region(found, by_start_points=use.how == "cycle 14") if found else None
    facts = CycleFacts(region=area, contour=use, own_q=_own_reserved(state), last_rougher=state.klartext.sl_rougher)
    runner.report_cycle(CycleRun(name, definition.model, op.span, block, params, spans, facts=facts))
    if definition.number == 22:
        _put(state, sl_rougher=state.tool_in_spindle)  # what Q438 = -1 of cycle 24 refers to (seed L9818-9840)
    first, second, axis = _plane(state)
    surface, clearance, depth, height = (params.get(q) for q in ("Q5", "Q6", "Q1", "Q7"))
    if any(type(value) is not float for value in (surface, clearance, depth, height)):
        state.move_to(dict.fromkeys(state.position))
        return None
    direction = 1.0 if depth > 0 else -1.0
    state.move_to({first: None, second: None})  # the plunge point is where the control computes it
    runner.move_to({axis: surface - direction * clearance}, op.span, block, "approach", name)
    with _cycle_feed(state, {"Q206": params.get("Q11", params.get("Q12"))}):
        runner.move_to({axis: surface + depth}, op.span, block, "infeed", name, "feed")
    runner.move_to({axis: height}, op.span, block, "out-of-hole", name)
    _put(state, ended_elsewhere=definition.number)  # posAfterContPocket may leave the tool anywhere (reference B §4.5)
    return None


def _ocm_cycle(runner, op, block, definition):
    """OCM 272-274: the data of 271 or of a standard shape 1271-1278; set-up clearance
    Q203 + Q200, floor Q203 + Q201, clearance height Q260 (absolute) at the end, the plane
    position then unknown. The shape's number goes to the rules as ``CycleFacts.shape``."""
    state = runner.state
    name = f"heidenhain.{definition.number}"
    data = state.klartext.ocm
    if data is None:
        runner.fault("heidenhain.sl-prerequisites", op.span, f"cycle {definition.number} is called without OCM data (cycle 271 or a shape 1271-1278) defined before it: "
                      "the control stops with an error (seed L11211-11215)")
        state.move_to(dict.fromkeys(state.position))
        return None
    shape, values_, spans_ = data
    params = dict(values_)
    params.update(_numbers(definition.params))
    spans = dict(spans_)
    spans.update(definition.spans)
    facts = CycleFacts(shape=float(shape), contour=_contour_use(runner, op) if shape == 271 else None, boundary=state.klartext.ocm_boundary,
                       rougher_forgotten=state.klartext.roughed_since_contour_def is False)
    runner.report_cycle(CycleRun(name, definition.model, op.span, block, params, spans, facts=facts))
    if definition.number == 272:
        _put(state, roughed_since_contour_def=True)
    first, second, axis = _plane(state)
    surface, clearance, depth, height = (params.get(q) for q in ("Q203", "Q200", _depth_name(definition), "Q260"))
    state.move_to({first: None, second: None})
    if any(type(value) is not float for value in (surface, clearance, depth, height)):
        state.move_to({axis: None})
        return None
    runner.move_to({axis: surface + clearance}, op.span, block, "approach", name)
    with _cycle_feed(state, {"Q207": params.get("Q207", params.get("Q385"))}):  # 273/274 finish at Q385
        runner.move_to({axis: surface + depth}, op.span, block, "infeed", name, "feed")
    runner.move_to({axis: height}, op.span, block, "out-of-hole", name)
    _put(state, ended_elsewhere=definition.number)
    return None


def _contour_use(runner, op):
    """The contour a cycle machines, as cycle 14 or CONTOUR DEF left it, with what its
    subprograms hold; None when neither was defined."""
    from .contour import ContourUse, subprograms

    state = runner.state
    labels = state.klartext.sl_labels or ()
    how, span, kinds, depths = state.klartext.contour_source or ("cycle 14", op.span, None, None)
    if not labels and how != "SEL CONTOUR":
        return None
    return ContourUse(how, span, tuple(labels), kinds, depths, tuple(subprograms(runner, labels, op.span)))


def _own_reserved(state) -> tuple:
    """Q1-Q20 the program has set itself: the SL and cylinder cycles keep their parameters
    there (seed L9360-9361)."""
    return tuple(name for name in (f"Q{number}" for number in range(1, 21)) if name in state.global_variables)


def _missing_contour(runner, op, definition, seed: str) -> bool:
    """Report a contour cycle called with no cycle 14 before it (reference B H33)."""
    if runner.state.klartext.sl_labels:
        return False
    runner.fault("heidenhain.sl-prerequisites", op.span, f"cycle {definition.number} is called without a contour (cycle 14) defined before it: "
                         f"the control stops with an error ({seed})")
    runner.state.move_to(dict.fromkeys(runner.state.position))
    return True


def _contour_train(runner, op, block, definition):
    """25 CONTOUR TRAIN, 275 TROCHOIDAL SLOT, 276 THREE-D CONT. TRAIN on the single
    subprogram of cycle 14 (reference B 6.11-6.13). The start point follows from the contour
    and is not placed here. 25: down to Q5 + Q1, up to the clearance height Q7; 275: the
    levels of a pocket (Q203, Q200, Q201, Q204); 276: the heights come from the subprogram's
    Z values, only the final clearance height Q7 is known. Depth 0 skips 25 and 275 (seed
    L10020-10021, L10220-10221). All three end away from their start (seed L10002-10009)."""
    state = runner.state
    number = definition.number
    if _missing_contour(runner, op, definition, "seed L10019, L10217-10218, L10453-10455"):
        return None
    data, data_spans = state.klartext.train_data if number in (25, 276) else ({}, {})  # cycle 270 (275 takes none)
    params = {**data, **_numbers(definition.params)}
    spans = {**data_spans, **definition.spans}
    name = f"heidenhain.{number}"
    facts = CycleFacts(contour=_contour_use(runner, op), position=dict(state.position), own_q=_own_reserved(state) if number != 275 else ())
    runner.report_cycle(CycleRun(name, definition.model, op.span, block, params, spans, facts=facts))
    first, second, axis = _plane(state)
    depth = params.get(_depth_name(definition))
    if depth == 0.0 and number != 276:
        return None
    state.move_to({first: None, second: None})
    if number == 275:
        found = levels(params)
        if found is None:
            state.move_to({axis: None})
            return None
        set_up, bottom, retract, _direction = found
        runner.move_to({axis: set_up}, op.span, block, "approach", name)
        with _cycle_feed(state, params):
            runner.move_to({axis: bottom}, op.span, block, "infeed", name, "feed")
        runner.move_to({axis: retract}, op.span, block, "out-of-hole", name)
    else:
        surface, height = params.get("Q5"), params.get("Q7")
        if number == 25 and type(surface) is float and type(depth) is float:
            with _cycle_feed(state, {"Q206": params.get("Q11")}):
                runner.move_to({axis: surface + depth}, op.span, block, "infeed", name, "feed")
        else:
            state.move_to({axis: None})
        if type(height) is not float:
            state.move_to({axis: None})
            return None
        runner.move_to({axis: height}, op.span, block, "out-of-hole", name)
    _put(state, ended_elsewhere=number)
    return None


def _cylinder_cycle(runner, op, block, definition):
    """27/28/29/39 machine the contour of cycle 14 on the unrolled surface of a rotary axis
    (reference B 6.27). Their parameters and the machine state at the call are checked; the
    path on the cylinder is not modelled, so where they leave the tool is unknown."""
    state = runner.state
    number = definition.number
    if _missing_contour(runner, op, definition, "seed L13576-13600"):
        return None
    params = _numbers(definition.params)
    facts = CycleFacts(contour=_contour_use(runner, op), spindle=state.spindle, own_q=_own_reserved(state))
    runner.report_cycle(CycleRun(f"heidenhain.{number}", definition.model, op.span, block, params, dict(definition.spans), facts=facts))
    if params.get("Q1") == 0.0:
        return None  # depth 0: the control skips the cycle (seed L13649-13650)
    runner.fault("core.unsupported-code", op.span, f"cycle {number} machines on the unrolled surface of the rotary axis, which is not modelled: "
                  "where it leaves the tool is unknown, so the moves after it are not checked until the program positions every axis again",
                  "unknown", f"cycle {number} (cylinder surface)")
    state.move_to(dict.fromkeys(state.position))
    if number == 28:
        _put(state, ended_elsewhere=number)  # the slot ends at the opposite wall (seed L13776-13785)
    return None


def _predrilled(state, level) -> bool:
    """Was a hole drilled here before, at least down to ``level``? The stock model has no
    holes: the approach into it is then reported as not checked, not as a crash."""
    point = _plane_point(state)
    if type(level) is not float or None in point:
        return False
    return any(type(bottom) is float and bottom <= level for bottom in state.klartext.drilled.bottoms_at(*point))


def _taps_an_earlier_hole(state, model) -> bool:
    """A tap needs a hole. Tapping where this program has drilled nothing taps one that an
    earlier operation made, and the blank (the raw part) does not show it: the way down to
    the set-up clearance is a hole bored before, as for a drilled one."""
    point = _plane_point(state)
    if model.family != "tap" or None in point:
        return False
    return not state.klartext.drilled.bottoms_at(*point)


def _remember_hole(state, bottom) -> None:
    drilled = state.klartext.drilled
    point = _plane_point(state)
    if None not in point and len(drilled) < 10_000:
        _put(state, drilled=drilled.adding(point[0], point[1], bottom))


def _pocket(runner, op, block, definition, shift, surface_offset):
    """Pockets, studs, slots and face milling: the levels are those of a hole (the cutting
    paths in the plane are not traced); the cycle ends at the 2nd set-up clearance, over
    the centre for pockets and elsewhere for studs and for slots that start at an end."""
    state = runner.state
    params = dict(definition.params)
    _offset_surface(params, shift, surface_offset)
    model = definition.model
    name = f"heidenhain.{definition.number}"
    runner.report_cycle(CycleRun(name, model, op.span, block, _numbers(params), dict(definition.spans)))
    axis = _plane(state)[2]
    if model.start_end:
        _surface_and_depth(params, *model.start_end)
    found = levels(params, _depth_name(definition))
    depth = params.get(_depth_name(definition))
    if depth == 0.0:
        return None  # the control skips the cycle (233: Q227 = Q386, seed L7302-7303)
    if found is None:
        state.move_to(dict.fromkeys(state.position))  # where the cycle leaves the tool is not known
        return None
    set_up, bottom, retract, _direction = found
    first, second, _normal = _plane(state)
    if model.family == "stud":
        state.move_to({first: None, second: None})  # studs start beside the stud, where Q437 / Q224 put the tool
    runner.move_to({axis: set_up}, op.span, block, "approach", name)
    with _cycle_feed(state, params):
        runner.move_to({axis: bottom}, op.span, block, "infeed", name, "feed")
        runner.move_to({axis: set_up}, op.span, block, "out-of-hole", name, "feed")
    runner.move_to({axis: retract}, op.span, block, "retract", name)
    if model.ends_elsewhere or (model.family == "slot" and params.get("Q367", 0.0) != 0.0):
        state.move_to({first: None, second: None})
        _put(state, ended_elsewhere=definition.number)
    return None


def _statement_run(runner, op: ir.DialectStatement, block):
    """A Klartext statement no other dialect has, with its words' values."""
    return _STATEMENTS[type(op)](runner, op, block, runner.words(op.params, op.span))


_STATEMENTS = {
    ir.OldCycle: _old_cycle_run, ir.Transformation: _trans_run, ir.PatternDef: _pattern_run, ir.CallActiveCycle: _call_run,
    ir.SelectPattern: special.select_pattern_run, ir.ContourDef: _contour_def_run,
    ir.GlobalDef: _global_def_run, ir.SelectContour: _select_contour_run, ir.DeclareContour: _declare_contour_run,
}
# The handlers of the operations this dialect lowers to and the shared interpreter leaves
# to it: ``run(runner, op, block)`` with the path's :class:`~ncverify.interpret.runtime.Runtime`.
OPERATIONS = {
    ir.Pole: _pole_run, ir.PoleArc: _arc_run, ir.TangentArc: _tangent_run, ir.PolarMove: _polar_run,
    ir.Lift: _lift_run, ir.PositioningBlock: _positioned_run, ir.Retract: _retract_run, ir.ToolFeed: _tool_feed_run, ir.ToolDelta: _tool_delta_run, ir.LabelCall: _label_call_run,
    ir.MFunction: special.m_function_run, ir.CycleDefine: _define_run, **dict.fromkeys(_STATEMENTS, _statement_run),
}
# Operations that change no state a rule reads while the predicate holds: moves gathered into
# a run (Interpreter._gather) stay gathered across them.
# CC changes only the pole, which no rule reads; the arcs C and CT report their move as one
# that may join the run (Runtime.emit with the axes written), or hand the run on first.
INERT_BETWEEN_MOVES = {ir.PositioningBlock: positioning_is_inert, **dict.fromkeys((ir.Pole, ir.PoleArc, ir.TangentArc), lambda _state: True)}
_SPECIAL_FAMILIES = {"engrave": special.engrave, "face232": special.face_milling,
                     "thread_cut": special.thread_cutting, "machine_moving": special.machine_moving,
                     "pgm_call": special.program_call}


