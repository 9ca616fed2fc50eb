"""Rules of the Fagor 8060/8065 cycles (rules/fagor/*.md), from the hazards of the
reference's section 11 (seed = the canned-cycle manual, "seed Lnnnn").

Parameter alarms that are plain comparisons are constraints in the rule pages; this module
holds what needs the tool table, the machine state or the pattern runner's faults.
"""
from __future__ import annotations

from ..ir import cycle_code
from .. import frames, pocket, values
from ..check import Rule, hazard, rule, show
from ..diagnostics import Status
from .common import ReportsMissingContext, scaled_note
from .. import modelled



def _is_fagor(cycle: str) -> bool:
    return cycle.startswith("fagor.")


def _unmodelled_frame(state) -> bool:
    """Under a transformation that is not modelled (G72) the control knows where the tool
    is; only this analysis does not, so a position it lacks there is no finding."""
    return state.frame is frames.UNKNOWN


@rule("fagor.cycle-starts-spindle")
class CycleStartsSpindle(Rule):
    """A Fagor cycle starts a stopped spindle clockwise with the S in force (seed L582-583)."""
    judges_holes_before_moves = True

    def hole(self, hole, state):
        if not _is_fagor(hole.cycle) or state.spindle != "off" or not self.first_time(state, ("fagor.cycle-starts-spindle", hole.definition)):
            return
        code = cycle_code(hole.cycle)
        speed = state.spindle_speed
        if speed is None or speed == 0.0:
            self.report("fagor.cycle-starts-spindle", hole.span, f"{code} starts the stopped spindle clockwise (M03), but no spindle speed S is programmed: "
                        "the tool feeds into the part without turning")
        elif hole.model.tapping:
            self.report("fagor.cycle-starts-spindle", hole.span, f"{code} tapping starts the stopped spindle clockwise (M03) at S{show(speed)}: "
                        "a left-hand tap (M04) breaks; start the spindle in the tap's direction before the cycle")


@rule("fagor.unknown-start-plane")
class UnknownStartPlane(Rule):
    """Zi is where the tool is on the tool axis when the cycle is defined (seed L629, L871)."""
    judges_holes_before_moves = True

    def hole(self, hole, state):
        if not _is_fagor(hole.cycle) or hole.initial is not None or _unmodelled_frame(state) or not self.first_time(state, ("fagor.unknown-start-plane", hole.definition)):
            return
        default = "" if "Z" in hole.params else " and the reference plane defaults to it (no Z written)"
        self.report("fagor.unknown-start-plane", hole.definition or hole.span,
                    f"{cycle_code(hole.cycle)} is defined where the tool-axis position is not known (no {hole.drill_axis} move since the start, "
                    f"a tool change or a home search): the start plane Zi the G98 retract goes back to is unknown{default}")


@rule("fagor.pocket-incremental-depth")
class PocketIncrementalDepth(Rule):
    """G87/G88 in G91: the text measures I from Z, the manual's examples from Zi (H12)."""
    judges_holes_before_moves = True
    reads = modelled.AS_WRITTEN

    def hole(self, hole, state):
        cycle = state.cycle
        if hole.model.pocket not in ("rectangle", "circle") or cycle is None or not cycle.incremental or "I" in cycle.absolute:
            return
        depth, initial = hole.params.get("I"), cycle.initial
        if depth is None or initial is None or not self.first_time(state, ("fagor.pocket-incremental-depth", hole.definition)):
            return
        from_reference = hole.bottom
        from_start = values.add(initial, depth)
        verdict = self.checker.judge(hazard("!=", from_reference, from_start), state)
        self.checker.report_verdict("fagor.pocket-incremental-depth", hole.param_spans.get("I", hole.span),
                                    f"{cycle_code(hole.cycle)} in G91: I{show(depth)} gives the floor at {show(from_reference)} measured from the reference plane (the manual's text) "
                                    f"but at {show(from_start)} measured from the start plane (the manual's examples): program the floor in G90", verdict, state)


@rule("fagor.vc-absolute")
class CycleDataAbsolute(Rule):
    """V.C.x values are absolute coordinates whatever G90/G91 (seed L783-784)."""
    judges_holes_before_moves = True

    def hole(self, hole, state):
        cycle = state.cycle
        if cycle is None or not cycle.absolute or state.modal.get("distance") != "incremental":
            return
        if not self.first_time(state, ("fagor.vc-absolute", hole.definition)):
            return
        letters = " ".join(f"V.C.{letter}={show(hole.params.get(letter))}" for letter in sorted(cycle.absolute) if letter in hole.params)
        self.report("fagor.vc-absolute", hole.span, f"{cycle_code(hole.cycle)} machines in G91 with {letters} set through V.C: those are absolute coordinates "
                    "(from part zero), not distances like the G91 values written in the cycle block")


@rule("fagor.arc-positioning-in-cycle")
class ArcPositioning(Rule):
    """Positioning in a cycle zone uses the modal interpolation (seed L674-676, H33)."""
    judges_holes_before_moves = True

    def hole(self, hole, state):
        if not _is_fagor(hole.cycle) or state.modal.get("motion") not in ("arc_cw", "arc_ccw"):
            return
        if all(hole.position.get(axis) is state.position.get(axis) for axis in state.plane_axes[:2]):
            return  # machined where the tool is: no positioning move
        self.report("fagor.arc-positioning-in-cycle", hole.span, f"{cycle_code(hole.cycle)} positions to this hole in G0{2 if state.modal['motion'] == 'arc_cw' else 3} "
                    "(the interpolation in force): the move to the hole is an arc, not a straight line")


@rule("fagor.cycle-set-left-on")
class CycleSetLeftOn(Rule):
    """#LATHECY ON / #MILLCY ON switch the meaning of G81-G88 (seed L513-550, H28)."""

    def change(self, change, state):
        if change.what != "end":
            return
        for statement, cycles, on in (("LATHECY", "turning", state.fagor.lathe_cycles), ("MILLCY", "milling", state.fagor.mill_cycles)):
            if on:
                self.report("fagor.cycle-set-left-on", change.span, f"#{statement} ON is still in force at the program end: the next program's G81-G88 "
                            f"are {cycles} cycles unless it switches back (#{statement} OFF)")


@rule("fagor.pocket-tool-fit")
class PocketToolFit(ReportsMissingContext):
    """G87/G88/G210/G211: the tool against the pocket, bore or thread (seed L1386-1390,
    L1499-1503, L1599-1613; H13, H14, H20, H22). Sizes come from the cycle and the tool
    radius from the tool table; the largest tool that fits is reported."""
    judges_holes_before_moves = True
    reads = modelled.SCALED_SIZES

    def hole(self, hole, state):
        kind = hole.model.pocket or hole.model.thread_mill
        if kind not in ("rectangle", "circle", "bore", "internal") or not _is_fagor(hole.cycle):
            return
        if not self.first_time(state, ("fagor.pocket-tool-fit", hole.definition, id(hole.params.get("J")), hole.params.get("J"), state.tool_in_spindle)):
            return
        radius = self.spindle_tool_radius(state, hole.span, "fagor.pocket-tool-fit")
        if radius is None:
            return
        params = self.workpiece_sizes(hole.params, "JKCLQ", state, hole.span, "fagor.pocket-tool-fit")
        if params is None:
            return
        if not all(type(params.get(letter, 0.0)) is float for letter in "JKCLQM"):
            self._symbolic(hole, kind, params, radius, state)
            return
        problems = getattr(self, f"_{kind}")(params, radius)
        for letter, reason, largest in problems:
            fits = f"; the largest tool that fits has a radius of {largest:g}" if largest is not None else ""
            self.report("fagor.pocket-tool-fit", hole.param_spans.get(letter, hole.span),
                        f"{cycle_code(hole.cycle)} with tool T{show(state.tool_in_spindle)} (radius {radius:g}): {reason}{fits}{scaled_note(state)}")

    def _symbolic(self, hole, kind, params, radius, state) -> None:
        """Sizes that depend on free parameters: every condition of the concrete check as
        one hazard for the solver (``proved``, or ``violated`` with a witness)."""
        if type(params.get("M", 0.0)) is not float:
            self.report("fagor.pocket-tool-fit", hole.span, f"{cycle_code(hole.cycle)}: the corner type M is a computed value; the tool fit was not checked",
                        Status.UNKNOWN, "symbolic corner type")
            return
        misfit = _MISFITS[kind](params, radius)
        sizes = ", ".join(f"{letter}={show(params[letter])}" for letter in "JKLQC" if letter in params)
        self.checker.report_verdict("fagor.pocket-tool-fit", hole.param_spans.get("J", hole.span),
                                    f"{cycle_code(hole.cycle)}: tool T{show(state.tool_in_spindle)} (radius {radius:g}) does not fit the {_FEATURE_WORDS[kind]} "
                                    f"({sizes}){scaled_note(state)}: the control alarms", self.checker.judge(misfit, state), state)

    @staticmethod
    def _stepover(params, radius) -> list:
        stepover = params.get("C")
        if stepover is not None and stepover > 2 * radius:
            return [("C", f"the stepover C{stepover:g} is wider than the tool's diameter {2 * radius:g}: the control alarms", stepover / 2)]
        return []

    def _rectangle(self, params, radius) -> list:
        if "J" not in params or "K" not in params:
            return []
        length, width, allowance = 2 * abs(params["J"]), 2 * abs(params["K"]), params.get("L", 0.0)
        corner = params.get("Q", 0.0) if params.get("M") == 1.0 else 0.0
        problems = self._stepover(params, radius)
        for fit, what in ((pocket.rectangle_fit(length, width, corner, radius, strict=True), f"pocket {length:g} x {width:g}"),
                          (pocket.rectangle_fit(length - 2 * allowance, width - 2 * allowance, 0.0, radius, strict=True),
                           f"the roughing area inside the allowance L{allowance:g}")):
            if not fit.fits:
                problems.append(("J", f"{fit.reason} ({what})", fit.largest_radius))
                break
        return problems

    def _circle(self, params, radius) -> list:
        if "J" not in params:
            return []
        allowance = params.get("L", 0.0)
        problems = self._stepover(params, radius)
        fit = pocket.circle_fit(2 * (abs(params["J"]) - allowance), radius, strict=True)
        if not fit.fits:
            problems.append(("J", f"{fit.reason} (radius J{abs(params['J']):g} less the allowance L{allowance:g})", fit.largest_radius))
        return problems

    @staticmethod
    def _bore(params, radius) -> list:
        if "J" not in params:
            return []
        diameter, predrilled = abs(params["J"]), params.get("K", 0.0)
        fit = pocket.circle_fit(diameter, radius, strict=True)
        problems = []
        if not fit.fits:
            problems.append(("J", f"{fit.reason}: the control alarms (the tool radius must be below half the hole diameter J)", fit.largest_radius))
        if radius < (diameter - predrilled) / 4:
            problems.append(("J", f"the tool radius is below (J - K) / 4 = {(diameter - predrilled) / 4:g}: the helix leaves a core standing in the middle "
                             "of the hole and the control alarms", None))
        return problems

    @staticmethod
    def _internal(params, radius) -> list:
        if "J" not in params or "K" not in params:
            return []
        room = abs(params["J"]) - 2 * abs(params["K"])
        fit = pocket.circle_fit(room, radius, strict=True)
        if fit.fits:
            return []
        return [("J", f"{fit.reason} left inside the thread's root (J{abs(params['J']):g} less twice the thread depth K{abs(params['K']):g}): "
                 "the tool cannot enter the pre-drilled hole", fit.largest_radius)]


def _stepover_misfit(params, radius):
    """The stepover C wider than the tool's diameter (no C: the control's own 3/4 of it)."""
    stepover = params.get("C")
    return False if stepover is None else hazard(">", stepover, 2 * radius)


def _rectangle_misfit(params, radius):
    length, width = values.mul(values.absolute(params["J"]), 2.0), values.mul(values.absolute(params["K"]), 2.0)
    allowance = values.mul(params.get("L", 0.0), 2.0)
    corner = params.get("Q", 0.0) if params.get("M") == 1.0 else 0.0
    whole = pocket.rectangle_misfit(length, width, corner, radius, strict=True)
    roughed = pocket.rectangle_misfit(values.sub(length, allowance), values.sub(width, allowance), 0.0, radius, strict=True)
    return pocket.either(_stepover_misfit(params, radius), pocket.either(whole, roughed))


def _circle_misfit(params, radius):
    room = values.mul(values.sub(values.absolute(params["J"]), params.get("L", 0.0)), 2.0)
    return pocket.either(_stepover_misfit(params, radius), pocket.circle_misfit(room, radius, strict=True))


def _bore_misfit(params, radius):
    diameter = values.absolute(params["J"])
    core = hazard("<", radius, values.mul(values.sub(diameter, params.get("K", 0.0)), 0.25))
    return pocket.either(pocket.circle_misfit(diameter, radius, strict=True), core)


def _internal_misfit(params, radius):
    room = values.sub(values.absolute(params["J"]), values.mul(values.absolute(params["K"]), 2.0))
    return pocket.circle_misfit(room, radius, strict=True)


# The conditions of PocketToolFit's concrete checks, for sizes that depend on free parameters
_MISFITS = {"rectangle": _rectangle_misfit, "circle": _circle_misfit, "bore": _bore_misfit, "internal": _internal_misfit}
_FEATURE_WORDS = {"rectangle": "rectangular pocket", "circle": "circular pocket", "bore": "bore", "internal": "thread's pre-drilled hole"}


@rule("fagor.g86-back-off")
class G86BackOffDirection(Rule):
    """The page's constraints catch a missing Q and a back-off that is ignored or zero. With
    A0/A1, Q and a back-off D/E, which way the tool moves depends on the machine's spindle
    orientation reference and on how the bar is clamped: the manual warns twice that a
    wrong orientation drives the tool into the wall (seed L1265-1273, reference H18). That
    is answered unknown, once per cycle definition (each definition backs off its own way)."""
    judges_holes_before_moves = True

    def hole(self, hole, state):
        params = hole.params
        mode, angle = params.get("A"), params.get("Q")
        if hole.cycle != "fagor.G86" or mode is None or (type(mode) is float and mode not in (0.0, 1.0)) or angle is None:
            return  # a computed A may be A0 or A1: its direction is as unknown
        back_off = " ".join(f"{letter}{show(params[letter])}" for letter in "DE" if not (type(params.get(letter, 0.0)) is float and params.get(letter, 0.0) == 0.0))
        if not back_off or not self.first_time(state, ("fagor.g86-back-off", hole.definition)):
            return
        moment = "before it leaves (A0) or enters (A1) the bore" if type(mode) is not float else "before it leaves the bore" if mode == 0.0 else "before it enters the bore"
        self.report("fagor.g86-back-off", hole.param_spans.get("Q", hole.definition or hole.span),
                    f"G86 A{show(mode)} orients the spindle at Q{show(angle)} and backs the tool off by {back_off} {moment}: whether that moves the edge "
                    "away from the wall or into it depends on the machine's spindle orientation reference and on how the boring bar is clamped, "
                    "which ncverify does not know; check the direction at the machine (a wrong orientation drives the tool into the wall)",
                    Status.UNKNOWN, "the spindle orientation reference and the bar's edge are not known")


@rule("fagor.hole-at-unknown-position")
class HoleAtUnknownPosition(Rule):
    """The block that defines a cycle machines where the tool is (seed L613-615; H2)."""
    judges_holes_before_moves = True

    def hole(self, hole, state):
        if not _is_fagor(hole.cycle):
            return
        first, second, _ = state.plane_axes
        if hole.position.get(first) is not None and hole.position.get(second) is not None or _unmodelled_frame(state):
            return
        if self.first_time(state, ("fagor.hole-at-unknown-position", hole.definition)):
            self.report("fagor.hole-at-unknown-position", hole.span,
                        f"{cycle_code(hole.cycle)} machines at a {first}{second} position that is not known here (no {first}/{second} move since the start, a tool change, "
                        "a home search or an unmodelled statement): the defining block drills wherever the tool happens to be")


@rule("fagor.rigid-tapping-encoder")
class RigidTappingEncoder(ReportsMissingContext):
    """G84 R1 is rigid tapping, which needs a motor-driven spindle with an encoder (seed
    L1090, L1132-1135; H19); ``[machine] spindle_encoder`` says whether the machine has one."""
    judges_holes_before_moves = True
    reads = modelled.AS_WRITTEN

    def hole(self, hole, state):
        rigid = hole.params.get("R")
        if not _is_fagor(hole.cycle) or not hole.model.tapping or not (rigid == 1.0 if type(rigid) is float else isinstance(rigid, values.Sym)):
            return  # a computed R may be R1
        span = hole.param_spans.get("R", hole.span)
        encoder = self.checker.context.machine.spindle_encoder
        if encoder is None:
            self.missing("fagor.rigid-tapping-encoder", span, "whether the spindle has an encoder is not known ([machine] spindle_encoder in ncverify.toml)")
        elif not encoder and self.first_time(state, ("fagor.rigid-tapping-encoder", hole.definition)):
            self.checker.report_verdict("fagor.rigid-tapping-encoder", span, "G84 R1 is rigid tapping, which needs a motor-driven spindle with an encoder, and this "
                                        "machine has none ([machine] spindle_encoder = false): the feed cannot follow the spindle and the tap strips the thread "
                                        "or breaks; tap with R0 in a floating holder", self.checker.judge(hazard("==", rigid, 1.0), state), state)


class _PastTheStock(ReportsMissingContext):
    """Rules that judge how far a hole reaches along its tool axis against the stock's far
    face: its bottom for a tool coming down Z, and for a box stock its face on any axis,
    either way (``hole.up``). Without the stock, or its extent along that axis, the rule
    answers unknown once per file."""
    reads = modelled.GEOMETRY

    rule_id = ""

    def far_face(self, hole):
        """``(coordinate of the far face, "<" or ">" for "beyond it", the axis)``, or None."""
        stock = self.checker.context.stock
        if stock is None:
            self.missing(self.rule_id, hole.span, "no stock defined (annotation 'ncverify: stock ...' or [stock] in ncverify.toml)")
            return None
        extent = {"Z": stock.z_range, "X": stock.x_range, "Y": stock.y_range}.get(hole.drill_axis)
        if extent is None:
            self.missing(self.rule_id, hole.span, f"the stock's extent along {hole.drill_axis} is not known (only a box stock gives it)")
            return None
        return (extent[0], "<", hole.drill_axis) if hole.up > 0 else (extent[1], ">", hole.drill_axis)


@rule("fagor.thread-mill-overshoot")
class ThreadMillOvershoot(_PastTheStock):
    """G211/G212 leave the thread on a tangential helix that runs past the thread end I
    along the tool axis (seed L1782-1803, L1922-1939; H21). The manual gives no length; one
    pitch |B| is taken as the overshoot. Past the stock's far face the tool runs into the
    table or the fixture."""
    judges_holes_before_moves = True

    rule_id = "fagor.thread-mill-overshoot"

    def hole(self, hole, state):
        pitch = hole.params.get("B")
        if not hole.model.thread_mill or hole.bottom is None or pitch is None or not self.first_time(state, (self.rule_id, hole.definition)):
            return
        face = self.far_face(hole)
        if face is None:
            return
        limit, beyond, axis = face
        reach = values.sub(hole.bottom, values.mul(hole.up, values.absolute(pitch)))
        verdict = self.checker.judge(hazard(beyond, reach, limit), state)
        self.checker.report_verdict(self.rule_id, hole.param_spans.get("I", hole.span),
                                    f"{cycle_code(hole.cycle)} ends the thread at {axis}{show(hole.bottom)}, but its helical exit runs on past it by up to one pitch "
                                    f"(B{show(values.absolute(pitch))}) to about {axis}{show(reach)}, past the stock's far face {axis}{limit:g}: "
                                    "the tool reaches the table or the fixture behind the part", verdict, state)


@rule("fagor.g83-depth")
class DeepDrillingDepth(_PastTheStock):
    """G83's I is one peck and J the number of pecks (seed L1044-1050; H4): a depth of J
    pecks that ends more than a peck past the stock's far face was meant as a total depth."""
    judges_holes_before_moves = True

    rule_id = "fagor.g83-depth"

    def hole(self, hole, state):
        if hole.model.depth != "pecks" or hole.bottom is None:
            return
        peck, count = hole.params.get("I"), hole.params.get("J")
        if peck is None or count is None or not self.first_time(state, (self.rule_id, hole.definition)):
            return
        face = self.far_face(hole)
        if face is None:
            return
        limit, beyond, axis = face
        verdict = self.checker.judge(hazard(beyond, values.add(hole.bottom, values.mul(hole.up, values.absolute(peck))), limit), state)
        self.checker.report_verdict(self.rule_id, hole.param_spans.get("J", hole.param_spans.get("I", hole.span)),
                                    f"G83 drills J{show(count)} pecks of I{show(peck)}: the bottom is {axis}{show(hole.bottom)}, more than a peck past the stock's "
                                    f"far face {axis}{limit:g}; I is one peck, not the depth (the depth is J x I from the reference plane)", verdict, state)


@rule("fagor.bore-milling-no-floor")
class BoreMillingNoFloor(_PastTheStock):
    """G210 with a negative pitch B makes no bottom pass (seed L1615-1619; H20): meant for
    through holes. A hole that ends before the stock's far face is blind."""
    judges_holes_before_moves = True

    rule_id = "fagor.bore-milling-no-floor"

    def hole(self, hole, state):
        pitch = hole.params.get("B")
        if hole.model.pocket != "bore" or not isinstance(pitch, (float, values.Sym)) or (type(pitch) is float and pitch >= 0) or hole.bottom is None:
            return  # a computed B is judged: it may be negative
        if not self.first_time(state, (self.rule_id, hole.definition)):
            return
        face = self.far_face(hole)
        if face is None:
            return
        limit, beyond, axis = face
        short = ">" if beyond == "<" else "<"
        verdict = self.checker.judge(values.logical("AND", hazard("<", pitch, 0.0), hazard(short, hole.bottom, limit)), state)
        self.checker.report_verdict(self.rule_id, hole.param_spans.get("B", hole.span),
                                    f"G210 with a negative pitch B{show(pitch)} makes no bottom pass (it is meant for through holes), but the hole ends at "
                                    f"{axis}{show(hole.bottom)}, short of the stock's far face {axis}{limit:g}: the floor of this blind hole is left as the "
                                    "helix ramps it, not flat; program B positive", verdict, state)
