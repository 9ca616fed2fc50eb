"""Klartext coordinate transformations (reference A §8): cycles 7, 8, 10, 11, 26, 19 and 247
and ``TRANS``, as one :class:`ncverify.frames.Frame`.

The active transformations are kept per cycle number in the path's dialect state
``state.klartext.transforms`` (a sorted tuple of ``(number, data)``, empty when none is
active); every change rebuilds the frame and hands it to the interpreter. How they combine
(my reading, tested in tests/test_frames.py):

- Cycle 7 (seed L7746-7836): absolute values are the datum relative to the preset,
  incremental ones (``IX``) relative to the last shifted datum. Each sub-block sets its
  own axis; an axis a new definition does not program keeps its shift (the status display
  shows the shift per axis; "reset: program X=0, Y=0 ...", L7764-7767). ``7.1 #n`` takes
  row n of a datum table this analysis does not have: the shift is unknown.
- Rotation (10, L7890-7899), mirror image (8, L7847-7850) and scaling (11, L7936-7937)
  act about the shifted datum; cycle 26 about its own centre CCX/CCY/CCZ in that system
  (L7972-7974). A programmed point is scaled (26, then 11), rotated, mirrored, then
  shifted: the datum shift is applied first when the control builds its system (L8161-8178),
  so it is the outermost map. Mirroring after rotating makes a mirrored program's angles
  turn the other way, as on the control's display.
- Cycle 11 scales all three axes, so cycle dimensions scale too: the cycles compute in
  program coordinates and their motion is mapped (Q200, Q201, Q203 all scaled). The
  tool-fit rules scale the sizes they read from the parameters (pocket sides, radii, slot
  widths) by the frame's factor in the working plane, and answer unknown where the plane
  is scaled unevenly (cycle 26 with two factors).
- Cycle 19 with any angle other than 0, and PLANE, tilt the working plane, which is not
  modelled: the frame is unknown until cycle 19 with all angles 0 or PLANE RESET.
- Cycle 247 (L8221-8223) resets shift, mirror image, rotation and both scalings (not 19).
- Neutral values reset a cycle: shift 0 on every axis, no mirrored axis, ROT 0, SCL 1,
  factor 1 on every axis.
"""
from __future__ import annotations

from dataclasses import replace

from ... import frames, values

_NEUTRAL_FACTOR = 1.0
RESET_BY_DATUM_SETTING = frozenset({7, 8, 10, 11, 26})  # cycle 247: all but the tilted plane
_XYZ = frozenset(frames.AXES)


def transform(runner, op, number: int, params: dict) -> None:
    """One transformation cycle (or a sub-block of one, or TRANS) runs."""
    state = runner.state
    active = dict(state.klartext.transforms)
    data = _component(runner, op, number, params, active.get(number), state.plane_axes)
    if data is None:
        active.pop(number, None)
    else:
        active[number] = data
    if number == 19 and data is not None:
        runner.fault("core.unsupported-code", op.span, "tilting the working plane (cycle 19, PLANE) is not modelled: positions after it are unknown "
                      "until it is reset (cycle 19 with all angles 0, PLANE RESET)", "unknown", "tilted working plane")
    set_transforms(runner, active, op.span)


def reset(runner, numbers, span=None) -> None:
    """The transformations of cycles ``numbers`` end (TRANS ... RESET at ``span``; cycle 247,
    which sets a new datum, with no span: it is no reset in an order)."""
    active = dict(runner.state.klartext.transforms)
    set_transforms(runner, {number: data for number, data in active.items() if number not in numbers}, span)


def set_transforms(runner, active: dict, span=None) -> None:
    """Make ``active`` the transformations in force. The order they were activated in is
    kept beside them; a change of it at ``span`` goes to the rules as a ``transforms``
    change (old and new order), which is how the reset order (seed L8166-8178) is judged."""
    state = runner.state
    before = state.klartext.transform_order
    order = tuple(number for number in before if number in active) + tuple(sorted(number for number in active if number not in before))
    state.klartext = replace(state.klartext, transforms=tuple(sorted(active.items())), transform_order=order)
    runner.set_frame(frame_of(active))
    if span is not None and order != before:
        runner.change("transforms", span, None, before, order)


def frame_of(active: dict) -> frames.Frame:
    """The frame the active cycles make (order: see the module's docstring)."""
    if 19 in active:
        return frames.UNKNOWN
    frame = frames.translation(dict(active.get(7, ())))
    if 8 in active:
        frame = frames.compose(frame, frames.mirror(active[8]))
    if 10 in active:
        plane, angle = active[10]
        frame = frames.compose(frame, frames.rotation(plane, angle))
    if 11 in active:
        frame = frames.compose(frame, frames.scaling(dict.fromkeys(frames.AXES, active[11])))
    if 26 in active:
        factors, centre = active[26]
        frame = frames.compose(frame, frames.scaling(dict(factors), dict(centre)))
    return frame


def _component(runner, op, number: int, params: dict, old, plane):
    """What cycle ``number`` holds after this definition (None: neutral, reset)."""
    if number == 7:
        return _shift(runner, op, params, dict(old or ()))
    if number == 8:
        return tuple(sorted(axis for axis in params if axis in _XYZ)) or None
    if number == 10:
        return _rotation(params, old, plane)
    if number == 11:
        factor = params.get("SCL", _NEUTRAL_FACTOR)
        return None if _is(factor, _NEUTRAL_FACTOR) else factor
    if number == 26:
        return _axis_scaling(params, old)
    if number == 19:
        return None if all(_is(value, 0.0) for name, value in params.items() if type(value) is not str) else tuple(sorted(params.items()))
    return None


def _shift(runner, op, params: dict, shift: dict):
    if "#" in params or "TABLINE" in params:  # CYCL DEF 7.1 #5, TRANS DATUM TABLE TABLINE 5
        row = params.get("#", params.get("TABLINE"))
        shown = f"{row:g}" if type(row) is float else "(a Q parameter)"
        runner.fault("core.unsupported-code", op.span, f"datum shift from row {shown} of a datum table: the table is not known here "
                      "(SEL TABLE names it on the control), so positions after it are unknown", "unknown", "datum table not known")
        return tuple((axis, None) for axis in frames.AXES)
    for word, value in params.items():
        axis = word[-1]
        if axis not in _XYZ or word not in (axis, "I" + axis):
            continue
        if word.startswith("I"):
            known = shift.get(axis, 0.0)
            value = None if known is None else values.add(known, value)
        shift[axis] = value
    shift = {axis: value for axis, value in shift.items() if not _is(value, 0.0)}
    return tuple(sorted(shift.items())) or None


def _rotation(params: dict, old, plane):
    if "ROT" in params:
        angle = params["ROT"]
    elif "IROT" in params:
        angle = values.add(old[1] if old else 0.0, params["IROT"])
    else:
        return None  # TRANS ROTATION RESET
    return None if _is(angle, 0.0) else (plane, angle)


def _axis_scaling(params: dict, old):
    factors, centre = (dict(part) for part in old) if old else ({}, {})
    for word, value in params.items():
        if word in _XYZ:
            factors[word] = value
        elif word.startswith("CC") and word[2:] in _XYZ:
            centre[word[2:]] = value
    factors = {axis: factor for axis, factor in factors.items() if not _is(factor, _NEUTRAL_FACTOR)}
    return (tuple(sorted(factors.items())), tuple(sorted(centre.items()))) if factors else None


def _is(value, number: float) -> bool:
    return type(value) is float and value == number
