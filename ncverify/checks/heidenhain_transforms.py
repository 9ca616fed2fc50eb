"""Klartext hazards of the coordinate transformations (reference A §9, H19, H36, H38). The
active transformations are the path's ``state.klartext.transforms``
(:mod:`ncverify.interpret.heidenhain.transforms`)."""
from __future__ import annotations

from .. import ir
from ..ir import cycle_code
from ..check import ARCS, Rule, rule
from .common import ReportsMissingContext

# Q214 of 202/204: 1 minus reference axis, 2 minus minor axis, 3 plus reference axis, 4 plus minor axis.
_DISENGAGE = {1.0: (0, "-"), 2.0: (1, "-"), 3.0: (0, "+"), 4.0: (1, "+")}
_DISENGAGING_CYCLES = ("heidenhain.202", "heidenhain.204")


def _active(state) -> dict:
    return dict(state.klartext.transforms)


@rule("heidenhain.scaling-factor")
class ArcUnderAxisScaling(Rule):
    """H38: under cycle 26 a circular arc needs one factor on both axes of its plane (seed
    L7976-7977). The factor ranges are constraints on the rule's page."""
    segment_kinds = ARCS

    handles_arcs = True  # each arc is judged as a segment while cycle 26 scales

    def segment(self, segment, state):
        if segment.arc is None:
            return
        scaling = _active(state).get(26)
        if scaling is None:
            return
        factors = dict(scaling[0])
        first, second, _normal = segment.arc.plane
        one, other = factors.get(first, 1.0), factors.get(second, 1.0)
        if type(one) is float and type(other) is float and one != other:
            self.report("heidenhain.scaling-factor", segment.span, f"cycle 26 scales {first} by {one:g} and {second} by {other:g}: a circular arc needs the same "
                        "factor on both axes of its plane (seed L7976-7977); scaled unequally it is no longer a circle")

    def motion_run(self, run, state):
        if run.arcs is not None and _active(state).get(26) is not None:
            for index in run.arc_indices():
                self.segment(run.segment(index), state)


@rule("heidenhain.disengage-mirror")
class DisengageUnderMirror(ReportsMissingContext):
    """H19: 202 and 204 move the tool off in the direction Q214 names, and that direction
    ignores a mirror image (seed L1880-1881, L2296-2297)."""

    def hole(self, hole, state):
        self._check(hole.cycle, hole.params, hole.param_spans, hole.span, state)

    def cycle_run(self, run, state):
        self._check(run.cycle, run.params, run.param_spans, run.span, state)

    def _check(self, cycle, params, spans, span, state):
        if cycle not in _DISENGAGING_CYCLES:
            return
        direction = _DISENGAGE.get(params.get("Q214"))
        mirrored = _active(state).get(8, ())
        if direction is None and mirrored and params.get("Q214") is not None and type(params["Q214"]) is not float:
            self.missing("heidenhain.disengage-mirror", spans.get("Q214", span), "the disengaging direction Q214 depends on a parameter that is not "
                         "known, so whether it points along a mirrored axis is not known")
        if direction is None or not mirrored:
            return
        axis = state.plane_axes[direction[0]]
        if axis not in mirrored or not self.first_time(state, ("disengage-mirror", span)):
            return
        self.report("heidenhain.disengage-mirror", spans.get("Q214", span), f"cycle {cycle_code(cycle)} disengages toward {direction[1]}{axis} "
                    f"(Q214={params['Q214']:g}) while cycle 8 mirrors {axis}: the disengaging direction is not mirrored, so on the mirrored part "
                    "the tool moves into the wall instead of away from it (seed L1880-1881, L2296-2297)")


@rule("heidenhain.rotation-cancels-compensation")
class RotationCancelsCompensation(Rule):
    """H36: cycle 10 cancels radius compensation (seed L7904); a contour move right after
    it that does not program RL/RR (or R0) again runs with the tool centre on the contour."""

    handles_arcs = True  # its run handler takes the first segment, arc or not

    def cycle_run(self, run, state):
        if run.cycle == "heidenhain.10" and state.comp_side in ("left", "right"):
            state.rule_state[("heidenhain", "rotation-cancelled")] = (run.span.line, "RL" if state.comp_side == "left" else "RR")

    def motion_run(self, run, state):
        if state.rule_state.get(("heidenhain", "rotation-cancelled")) is not None:
            self.segment(run.segment(0), state)  # only the first move after the rotation is judged

    def segment(self, segment, state):
        cancelled = state.rule_state.get(("heidenhain", "rotation-cancelled"))
        if cancelled is None or segment.role != "programmed":
            return
        state.rule_state[("heidenhain", "rotation-cancelled")] = None
        reprogrammed = any(isinstance(op, ir.CutterComp) for op in segment.block.ops)
        if segment.kind in ("feed", "arc") and not reprogrammed:
            line, side = cancelled
            self.report("heidenhain.rotation-cancels-compensation", segment.span, f"the rotation (cycle 10, line {line}) cancelled {side}: this contour move "
                        f"runs uncompensated, the tool centre on the contour, so the part is cut a tool radius too deep; program {side} again after the rotation (seed L7904)")


# The order the manual activates combined transformations in, and resets them the other way
# round (seed L8166-8178): datum shift, tilted working plane, rotation.
_CHAIN = {7: "the datum shift (cycle 7)", 19: "the tilted working plane (cycle 19)", 10: "the rotation (cycle 10)"}
_TILTED_BY_PLANE = ("heidenhain", "tilted-by-plane")  # whether the tilt in force came from the PLANE function


@rule("heidenhain.transform-reset-order")
class TransformResetOrder(Rule):
    """H35: with a tilted working plane, the transformations are reset in the reverse order
    of their definition: rotation, then the tilt, then the datum shift (seed L8166-8178).
    The activation order is the ``transforms`` change the frame lowering sends. The manual
    gives that order for cycle 19; a plane tilted with the PLANE function is not held to it
    (a CAM post resets the shift before PLANE RESET as a matter of course)."""

    def change(self, change, state):
        if change.what != "transforms":
            return
        tilted_by_plane = state.rule_state.get(_TILTED_BY_PLANE, False)
        tilt = dict(state.klartext.transforms).get(19)
        state.rule_state[_TILTED_BY_PLANE] = tilt is not None and "tilt" in dict(tilt)  # PLANE lowers to {"tilt": 1}, cycle 19 to its angles
        if tilted_by_plane:
            return
        before, after = change.old, change.new
        for reset in (number for number in before if number in _CHAIN and number not in after):
            later = [number for number in before[before.index(reset) + 1:] if number in _CHAIN and number in after]
            if later and 19 in (reset, *later):
                self.report("heidenhain.transform-reset-order", change.span, f"{_CHAIN[reset]} is reset while {_CHAIN[later[-1]]}, defined after it, "
                            "is still active: reset in the reverse order of the definitions (rotation, then the tilted plane, then the datum shift), "
                            "or the remaining transformation is taken in the wrong coordinate system (seed L8166-8178)")

