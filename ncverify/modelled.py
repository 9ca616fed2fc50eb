"""What a proof reads: the kinds of machine state a ``proved`` verdict can depend on.

Every rule class declares ``reads``, the kinds of state its proofs account for: those it
models (the stock rule maps each position through the frame, so translations, rotations,
scalings and mirror images are read), and those its verdict cannot depend on (a cycle
parameter compared with another as the program writes them). Whenever a kind it does not
read is active on the path, :meth:`ncverify.check.Checker.report_verdict` turns its
``proved`` into ``unknown`` and names the state; violations stand (they were shown for
concrete values and replayed).
"""
from __future__ import annotations

import numpy

from . import frames
from .context import compensated
from .material import length_problem, radius_problem, tool_axis_problem

TRANSLATION = "translation"
ROTATION = "rotation"
SCALING = "scaling"
MIRROR = "mirror image"
UNMODELLED_FRAME = "unmodelled frame"
TOOL_AXIS = "tool axis"
KINEMATICS = "kinematic transformation"
DIAMETER = "diameter programming"
RADIUS_COMPENSATION = "radius compensation"
TOOL_LENGTH = "tool length"  # the tip is not held at the programmed point (material.length_problem)
TOOL_RADIUS = "radius offset"  # compensation runs by another radius than the tool's (material.radius_problem)
UNFOLLOWED = "data changed by the program"  # a work offset or tool data written, the units switched (MachineState.unfollowed)
KINDS = (TRANSLATION, ROTATION, SCALING, MIRROR, UNMODELLED_FRAME, TOOL_AXIS, KINEMATICS, DIAMETER, RADIUS_COMPENSATION, TOOL_LENGTH, TOOL_RADIUS, UNFOLLOWED)

# Positions judged in workpiece coordinates, through the one program-to-workpiece map
# (not under radius compensation: the tool then runs beside the programmed positions).
GEOMETRY = frozenset({TRANSLATION, ROTATION, SCALING, MIRROR})
# Program values compared among themselves or with the tool table, as the program writes
# them: where the part lies, how it is turned or mirrored, along which axis the tool
# stands, how far beside the path it runs and how far the tip is from the programmed point
# leave them as they are; a scaling (sizes), a kinematic transformation, diameter
# programming (what a value means) or data the program changed (units, tool sizes) do not.
AS_WRITTEN = frozenset({TRANSLATION, ROTATION, MIRROR, UNMODELLED_FRAME, TOOL_AXIS, RADIUS_COMPENSATION, TOOL_LENGTH})
# Cycle sizes compared with the tool as the control cuts them: the written size times the
# factor that scales the working plane (``common.ReportsMissingContext.workpiece_sizes``; uneven: unknown).
SCALED_SIZES = AS_WRITTEN | {SCALING}
# Positions judged in workpiece coordinates, with a lathe's X read as a diameter or a
# radius by the mode in force (``common.lathe_x_is_diameter``; not known: unknown).
GEOMETRY_AND_DIAMETER = GEOMETRY | {DIAMETER}
EVERY = frozenset(KINDS)


def active(state, context) -> dict[str, str]:
    """The kinds of state in force on the path (plain milling along +Z in an unshifted
    system, with the loaded tool's own length offset, has none), each with the words that
    say so (``context``: the checker's, for the tool table and the machine)."""
    found = _frame_kinds(frames.program_to_workpiece(state))
    problem = tool_axis_problem(state)
    if problem is not None:
        found[TOOL_AXIS] = problem
    transformation = state.modal.get("transformation")
    if transformation:
        found[KINEMATICS] = f"the kinematic transformation {transformation} is on"
    if state.modal.get("diameter") in ("diameter", "diameter when absolute"):
        found[DIAMETER] = "X is programmed as a diameter"
    if compensated(state):
        found[RADIUS_COMPENSATION] = "radius compensation is on: the tool runs beside the programmed path, which the geometric checks do not work out"
    length = length_problem(context, state)
    if length is not None:
        found[TOOL_LENGTH] = length
    radius = radius_problem(context, state)
    if radius is not None:
        found[TOOL_RADIUS] = radius
    if state.unfollowed is not None:
        found[UNFOLLOWED] = state.unfollowed
    return found


def _frame_kinds(frame) -> dict[str, str]:
    if frame is None or frame.is_identity:
        return {}
    if any(entry is None for row in frame.linear for entry in row):
        return {UNMODELLED_FRAME: "a tilted or otherwise unmodelled coordinate system is active"}
    found = {}
    if not all(type(value) is float and value == 0.0 for value in frame.offset):
        found[TRANSLATION] = "a datum shift is active"
    linear = numpy.array(frame.linear, dtype=float)
    lengths = numpy.linalg.norm(linear, axis=0)
    if not numpy.allclose(lengths, 1.0):
        found[SCALING] = "a scaling is active"
    if numpy.linalg.det(linear) < 0:
        found[MIRROR] = "a mirror image is active"
    turned = linear / numpy.where(lengths == 0.0, 1.0, lengths)
    # a rotation leaves entries off the diagonal, or (by 180 degrees) turns two axes round
    if not numpy.allclose(turned, numpy.diag(numpy.diag(turned))) or (numpy.diag(turned) < 0).sum() >= 2:
        found[ROTATION] = "a rotation is active"
    return found


def unread(state, reads: frozenset, context) -> str | None:
    """Why a proof that reads ``reads`` does not hold here, or None."""
    missing = [why for kind, why in active(state, context).items() if kind not in reads]
    return "; ".join(missing) if missing else None
