"""Klartext contour, contour-train, OCM and cylinder-surface hazards (reference B §9).

The cycle runner hands each contour cycle's run over with the facts the rules need beside
its parameters (:class:`ncverify.trace.CycleFacts`): the contour it machines (``contour``:
cycle 14 or CONTOUR DEF and what each subprogram holds, see
:mod:`ncverify.interpret.heidenhain.contour`) and the machine state (``position`` at the
call, ``spindle``, the OCM ``boundary``, ``rougher_forgotten``). Parameter-only
hazards of these cycles are constraints in ``rules/heidenhain/*.md``.
"""
from __future__ import annotations

import math

from shapely.geometry import Point

from .. import values
from ..diagnostics import Severity
from ..check import hazard, rule, show
from .heidenhain import CycleRule, CycleRuleOfParts, spindle_tool

_SL = {21, 22, 23, 24}
_TRAINS = {25, 275, 276}
_CYLINDER = {27, 28, 29, 39}
_OCM = {272, 273, 274, 277}
_CORNER_DEGREES = 10.0  # arcs are walked in 5-degree chords: a sharper turn is a corner
_CONTOUR_DEF_LIMITS = {"subcontours": 9, "voids": 5}  # seed L14785-14797
_LABELS_MAX = 12  # subcontours in cycle 14 (seed L9195-9205)
_DECLARED_MAX = 128  # contours of a contour formula (seed L14355-14358)


def _label(subprogram) -> str:
    label = subprogram.label
    return f"LBL {label:g}" if type(label) is float else f'LBL "{label}"'


@rule("heidenhain.contour-subprogram")
class ContourSubprogram(CycleRule):
    """A3, A5, A6: what a contour subprogram may hold, how many a contour train takes, and
    how a trochoidal slot starts."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        use = facts.contour
        if use is None or (number not in _SL | _TRAINS | _CYLINDER | _OCM):
            return
        if use.how == "cycle 14" and len(use.labels) > _LABELS_MAX and self.first_time(state, ("label-count", use.span)):
            self.report("heidenhain.contour-subprogram", use.span or span, f"cycle 14 lists {len(use.labels)} contour labels; the control takes at most "
                        f"{_LABELS_MAX} (seed L9195-9205)")
        if number in _TRAINS and len(use.labels) > 1 and self.first_time(state, ("train-labels", span)):
            effect = "the control machines only the first and ignores the others" if number == 25 else "the control allows only one and stops with an error"
            self.report("heidenhain.contour-subprogram", use.span or span, f"cycle {number} works on one contour subprogram, but cycle 14 lists "
                        f"{len(use.labels)} labels: {effect} (seed L10012, L10222-10223, L10451-10452)")
        subprograms = use.subprograms[:1] if number in _TRAINS else use.subprograms
        for subprogram in subprograms:
            if self.first_time(state, ("contour-subprogram", number, subprogram.end)):
                for message, where in self._faults(number, subprogram):
                    self.report("heidenhain.contour-subprogram", where, message)

    @staticmethod
    def _faults(number: int, subprogram):
        name = _label(subprogram)
        for what, where in subprogram.forbidden:
            allowed = (what == "an APPR/DEP block" and (number in (25, 276) or (number == 275 and subprogram.first_is_approach))) or \
                      (what == "a tool-axis coordinate" and number == 276)
            if not allowed:
                yield f"{what} in the contour subprogram {name} of cycle {number}: a contour subprogram holds only the contour (seed L9058-9071)", where
        needed = {"X", "Y", "Z"} if number == 276 else {"X", "Y"}
        lacking = sorted(needed - subprogram.first_axes)
        if lacking:
            yield (f"the first block of contour subprogram {name} does not program {' and '.join(lacking)}: the control needs "
                   f"{', '.join(sorted(needed))} there to know where the contour starts (seed L9064, L10459-10461)"), subprogram.first_span
        if number == 275:
            yield from _slot_start(subprogram, name)


def _slot_start(subprogram, name: str):
    """275: a closed slot starts with an L block, away from a corner; an open one with APPR
    (seed L10160, L10181, L10225)."""
    if subprogram.first_is_approach:
        return
    if subprogram.closed is False:
        yield f"the open slot of cycle 275 in {name} must begin with an APPR block: the control plunges at the APPR start outside the material (seed L10181)", subprogram.first_span
        return
    if not subprogram.first_is_line:
        yield f"the closed slot of cycle 275 in {name} must begin with a straight L block (seed L10160)", subprogram.first_span
        return
    points = list(subprogram.contour.outline.exterior.coords) if subprogram.contour is not None else []
    if len(points) >= 4 and _turn_degrees(points[-2], points[0], points[1]) > _CORNER_DEGREES:
        x, y = points[0]
        yield (f"the closed slot of cycle 275 in {name} starts at X{x:g} Y{y:g}, a corner of the contour: the start point must lie on a "
               "side, not at a corner (seed L10160)"), subprogram.first_span


def _turn_degrees(before, at, after) -> float:
    incoming = math.atan2(at[1] - before[1], at[0] - before[0])
    outgoing = math.atan2(after[1] - at[1], after[0] - at[0])
    return abs(math.degrees((outgoing - incoming + math.pi) % (2 * math.pi) - math.pi))


@rule("heidenhain.contour-feed")
class ContourFeed(CycleRule):
    """A3 (part): feed rates and M functions in a contour subprogram, which describes only
    the geometry (seed L9071)."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        use = facts.contour
        if use is None:
            return
        for subprogram in use.subprograms:
            if subprogram.technology and self.first_time(state, ("contour-feed", subprogram.end)):
                what, where = subprogram.technology[0]
                # a feed rate there is ignored (no effect on the part: info); an M function that seems to switch something is a warning
                ignored = all(item.startswith("a feed rate") for item, _ in subprogram.technology)
                self.report("heidenhain.contour-feed", where, f"{what} in the contour subprogram {_label(subprogram)} of cycle {number}: the subprogram describes "
                            "only the contour, the cycle cuts at its own feeds and switches nothing there, so this does not do what it seems to (seed L9071)",
                            severity=Severity.INFO if ignored else None)


@rule("heidenhain.contour-compensation")
class ContourCompensation(CycleRule):
    """A1, A4: cycle-14 subcontours of SL cycles need RL or RR (pocket or island comes from
    it); with cycle 270 or CONTOUR DEF the subprograms must have none."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        use = facts.contour
        if use is None:
            return
        governed = "CONTOUR DEF" if use.how == "CONTOUR DEF" else ("cycle 270" if number in (25, 276) and "Q391" in params else None)
        for subprogram in use.subprograms[:1] if number in _TRAINS else use.subprograms:
            if not self.first_time(state, ("contour-compensation", number, subprogram.end)):
                continue
            written = [(side, where) for side, where in subprogram.sides if side in ("left", "right")]
            if governed is not None and written:
                self.report("heidenhain.contour-compensation", written[0][1], f"RL/RR in contour subprogram {_label(subprogram)} used with {governed}: "
                            f"{'P/I in CONTOUR DEF' if governed == 'CONTOUR DEF' else 'Q391 of cycle 270'} gives the side, the subprogram must have none (seed L9924, L14801-14803)")
            elif governed is None and number in _SL and not written:
                self.report("heidenhain.contour-compensation", subprogram.first_span, f"contour subprogram {_label(subprogram)} of cycle {number} has no RL or RR: "
                            "the SL cycles tell a pocket from an island by the compensation and the direction, so with R0 the control may machine the "
                            "complement (seed L9063-9066)")


@rule("heidenhain.contour-overlap-start")
class ContourOverlapStart(CycleRule):
    """A2: where superimposed subcontours start decides union, difference or intersection
    (seed L9254-9320): the first pocket must start outside the pockets and islands it
    overlaps (else only the common area is machined), an island inside a pocket."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        use = facts.contour
        if use is None or number not in _SL or use.how != "cycle 14":
            return
        found = [subprogram.contour for subprogram in use.subprograms]
        if len(found) < 2 or not self.first_time(state, ("overlap", use.span)):
            return
        if any(contour is None or contour.pocket is None for contour in found):
            self.missing("heidenhain.contour-overlap-start", use.span, "a subcontour of cycle 14 could not be resolved (free Q parameters, CT or FK "
                         "elements, or an R0 subcontour), so whether the superimposed subcontours start where they must is not known")
            return
        names = [_label(subprogram) for subprogram in use.subprograms]
        for index, message in _overlap_faults(found, names):
            self.report("heidenhain.contour-overlap-start", use.subprograms[index].first_span, f"{message} (seed L9254-9320)")


def _overlap_faults(found, names):
    first = found[0]
    pockets = [contour.outline for contour in found if contour.pocket]
    for index, other in enumerate(found[1:], 1):
        overlapping = first.outline.intersects(other.outline) and not first.outline.touches(other.outline)
        if first.pocket and overlapping and other.outline.contains(Point(first.start)):
            if other.pocket:
                yield 0, (f"pocket {names[0]} starts inside pocket {names[index]}: the control machines only the area the two share (intersection), "
                          "not both; start the first pocket outside the second for the union")
            else:
                yield 0, f"pocket {names[0]} starts inside island {names[index]}: for pocket-minus-island the pocket must start outside the island"
        touched = [outline for outline in pockets if outline.intersects(other.outline)]
        if not other.pocket and touched and not any(outline.contains(Point(other.start)) for outline in touched):
            yield index, f"island {names[index]} starts outside the pockets it overlaps: for pocket-minus-island the island must start inside the pocket"


@rule("heidenhain.contour-def")
class ContourDefinition(CycleRule):
    """A7-A9: CONTOUR DEF limits, subcontour depths against the cycle depth, and the kinds
    Q569 of cycle 271 demands; a shape island with no boundary."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        use = facts.contour
        self._declared(facts.declared_depths, span, state)
        if number in _OCM and facts.shape in (1271.0, 1272.0, 1273.0, 1278.0):
            self._shape_island(number, params, spans, span, state, facts.boundary)
        if use is None or use.how != "CONTOUR DEF" or not self.first_time(state, ("contour-def", use.span)):
            return
        kinds = use.kinds or ()
        subcontours, voids = sum(kind in "PI" for kind in kinds), kinds.count("V")
        for what, count in (("subcontours", subcontours), ("voids", voids)):
            if count > _CONTOUR_DEF_LIMITS[what]:
                self.report("heidenhain.contour-def", use.span, f"CONTOUR DEF names {count} {what}; the control accepts at most {_CONTOUR_DEF_LIMITS[what]} (seed L14785-14797)")
        depth_name = "Q1" if number in _SL else "Q201"
        self._depths(use, params.get(depth_name), depth_name, state)
        if number in _OCM:
            self._open_boundary(use, params.get("Q569"), spans.get("Q569", span))

    def _declared(self, declared, span, state):
        """DECLARE CONTOUR: at most 128 contours, and a DEPTH on all or none (seed L14355-14358, L14464-14465)."""
        if not declared:
            return
        if len(set(declared)) > 1 and self.first_time(state, ("declared-depths",)):
            with_depth = "this one has a DEPTH and an earlier one none" if declared[-1] else "an earlier one has a DEPTH and this one none"
            self.report("heidenhain.contour-def", span, f"DECLARE CONTOUR: {with_depth}; when one contour has its own depth, every one must have one "
                        "(DEPTH0 is allowed) (seed L14464-14465)")
        if len(declared) == _DECLARED_MAX + 1:
            self.report("heidenhain.contour-def", span, f"more than {_DECLARED_MAX} DECLARE CONTOUR in one contour-definition program (seed L14355-14358)")

    def _depths(self, use, depth, depth_name: str, state):
        """Every subcontour's DEPTH is at most the cycle depth, which is that of the first
        subcontour (seed L10972-10977, L14874-14879)."""
        if depth is None:
            return
        for index, given in enumerate(use.depths or ()):
            if given is None:
                continue
            verdict = self.checker.judge(hazard(">", values.absolute(given), values.absolute(depth)), state)
            self.checker.report_verdict("heidenhain.contour-def", use.span, f"CONTOUR DEF gives subcontour {index + 1} the DEPTH {show(given)}, deeper than the cycle depth "
                                        f"{depth_name}={show(depth)}: no subcontour may be deeper than the first; program the deepest pocket first", verdict, state)

    def _open_boundary(self, use, boundary, where):
        """Q569 = 1: the first contour is an open boundary and the others islands; 2: a
        boundary block and the others pockets (seed L11168-11175)."""
        wanted = {1.0: ("I", "islands"), 2.0: ("P", "pockets")}.get(boundary)
        if wanted is None:
            return
        wrong = [index + 1 for index, kind in enumerate(use.kinds[1:], 1) if kind != wanted[0]]
        if wrong:
            self.report("heidenhain.contour-def", use.span, f"cycle 271 has Q569={show(boundary)}, so every subcontour after the first must be one of the {wanted[1]}, "
                        f"but subcontour {', '.join(map(str, wrong))} is not: the control rejects the contour (seed L11168-11175)")

    def _shape_island(self, number, params, spans, span, state, boundary):
        if params.get("Q650") == 1.0 and boundary is None and self.first_time(state, ("shape-island", span)):
            self.report("heidenhain.contour-def", spans.get("Q650", span), f"cycle {number} machines an island shape (Q650=1) with no boundary cycle "
                        "1281 or 1282 after the shape: the control needs the boundary to know what to clear around the island (seed L12200-12205)")


@rule("heidenhain.below-clearance-height")
class BelowClearanceHeight(CycleRule):
    """H16: cycle 276 stops with an error when the tool is below the clearance height Q7 at
    the call (seed L10444-10446)."""
    reads = frozenset()  # compares positions as the program writes them with the blank: no active state is read

    def judge_cycle(self, number, params, spans, span, state, facts):
        height, position = params.get("Q7"), facts.position
        if number != 276 or height is None or position is None:
            return
        axis = state.plane_axes[2]
        level = position.get(axis)
        if level is None:
            self.missing("heidenhain.below-clearance-height", span, "the tool-axis position at the call of cycle 276 is not known")
            return
        verdict = self.checker.judge(hazard("<", level, height), state)
        self.checker.report_verdict("heidenhain.below-clearance-height", span, f"cycle 276 is called with the tool at {axis}{show(level)}, below its clearance "
                                    f"height Q7={show(height)}: the control stops with an error", verdict, state)


@rule("heidenhain.cylinder-clearance")
class CylinderClearance(CycleRule):
    """H19: the set-up clearance Q6 of a cylinder-surface cycle must exceed the tool radius."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        clearance = params.get("Q6")
        if number not in _CYLINDER or clearance is None or not self.first_time(state, ("cylinder-clearance", span)):
            return
        tool = spindle_tool(self, state, span, "heidenhain.cylinder-clearance", "radius")
        if tool is None:
            return
        verdict = self.checker.judge(hazard("<=", clearance, tool.radius), state)
        self.checker.report_verdict("heidenhain.cylinder-clearance", spans.get("Q6", span), f"cycle {number}: set-up clearance Q6={show(clearance)} is not greater than the radius "
                                    f"R={tool.radius:g} of tool T{show(state.tool_in_spindle)}: the tool swings round the cylinder that close to the surface (seed L13651)", verdict, state)


@rule("heidenhain.cylinder-radius")
class CylinderRadius(CycleRule):
    """H19: Q16 should be the radius of the BLK FORM CYLINDER the depth is measured from."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        radius = params.get("Q16")
        stock = self.checker.context.stock
        if number not in _CYLINDER or radius is None or not self.first_time(state, ("cylinder-radius", span)):
            return
        if stock is None or stock.diameter is None:
            self.missing("heidenhain.cylinder-radius", span, "no BLK FORM CYLINDER to compare the cylinder radius Q16 with")
            return
        blank = stock.diameter / 2.0
        verdict = self.checker.judge(hazard(">", values.absolute(values.sub(radius, blank)), 1e-6), state)
        self.checker.report_verdict("heidenhain.cylinder-radius", spans.get("Q16", span), f"cycle {number}: cylinder radius Q16={show(radius)} differs from the radius "
                                    f"{blank:g} of the BLK FORM CYLINDER: depth and set-up clearance are measured from Q16, so the tool "
                                    f"{'starts inside the material' if type(radius) is float and radius < blank else 'cuts short of the depth'}", verdict, state)


@rule("heidenhain.cylinder-spindle")
class CylinderSpindle(CycleRule):
    """H30: 28, 29 and 39 must be called with the spindle running (seed L13641-13642)."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        if number in (28, 29, 39) and facts.spindle == "off" and self.first_time(state, ("cylinder-spindle", span)):
            self.report("heidenhain.cylinder-spindle", span, f"cycle {number} is called with the spindle stopped: the cycle plunges and mills at once, "
                        "a standing tool collides (the control says so only if the machine parameter displaySpindleErr is set)")


@rule("heidenhain.slot-width")
class SlotWidth(CycleRule):
    """C27, C28: the trochoidal slot 275 needs a width between the tool diameter and twice
    it; the cylinder slot 28 a width of at least the tool diameter plus both allowances."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        if number not in (275, 28) or not self.first_time(state, ("slot-width", span)):
            return
        name = "Q219" if number == 275 else "Q20"
        width = params.get(name)
        if width is None:
            return
        tool = spindle_tool(self, state, span, "heidenhain.slot-width", "radius")
        if tool is None:
            return
        diameter, where = 2.0 * tool.radius, spans.get(name, span)
        allowance = params.get("Q3", 0.0) if number == 28 else 0.0
        room = values.sub(width, values.mul(2.0, allowance))
        verdict = self.checker.judge(hazard("<", room, diameter - 1e-9), state)
        self.checker.report_verdict("heidenhain.slot-width", where, f"cycle {number}: slot width {name}={show(width)}"
                                    f"{f' less twice the allowance Q3={show(allowance)}' if number == 28 else ''} is narrower than the diameter "
                                    f"{diameter:g} of tool T{show(state.tool_in_spindle)}: the walls are cut oversize (seed L10241-10245, L13722-13735)", verdict, state)
        if number == 275 and params.get("Q215", 0.0) != 2.0:
            verdict = self.checker.judge(hazard(">", width, 2.0 * diameter), state)
            self.checker.report_verdict("heidenhain.slot-width", where, f"cycle 275: slot width Q219={show(width)} is more than twice the diameter {diameter:g} "
                                        f"of tool T{show(state.tool_in_spindle)}: trochoidal roughing cannot clear it (seed L10241-10245)", verdict, state)


@rule("heidenhain.ocm-tool-corner")
class OcmToolCorner(CycleRule):
    """C26: 272 and 273 compute their paths without the tool's corner radius R2."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        if number not in (272, 273) or not self.first_time(state, ("ocm-tool-corner", span)):
            return
        tool = self.checker.context.tools.in_spindle(state)
        if tool is None:
            self.missing("heidenhain.ocm-tool-corner", span, self.checker.context.tools.missing(state))
        elif tool.corner:
            self.report("heidenhain.ocm-tool-corner", span, f"cycle {number} with tool T{show(state.tool_in_spindle)} whose corner radius R2={tool.corner:g}: "
                        "OCM ignores R2, so material is left on the floor along the walls and the next tool meets it (seed L11266-11273, L11761-11767)")


@rule("heidenhain.rougher-forgotten")
class RougherForgotten(CycleRule):
    """H37: CONTOUR DEF makes the control forget the last roughing tool; Q438 = -1 then
    means 'no roughing before' (seed L11284-11286)."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        if number in (273, 274, 277) and params.get("Q438") == -1.0 and facts.rougher_forgotten and self.first_time(state, ("rougher", span)):
            self.report("heidenhain.rougher-forgotten", spans.get("Q438", span), f"cycle {number} with Q438=-1 (the last roughing tool) after a CONTOUR DEF "
                        "and no OCM roughing since: CONTOUR DEF resets the remembered roughing tool, so the control assumes nothing was roughed and "
                        "the finishing tool takes the full material; give the roughing tool's number in Q438")


@rule("heidenhain.sl-q-parameters")
class SlQParameters(CycleRule):
    """H36: the SL and cylinder cycles keep their parameters in Q1-Q20 (seed L9360-9361)."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        own = facts.own_q
        if own and self.first_time(state, ("sl-q-parameters",)):
            user = f"calls SL cycle {number}" if number is not None else "declares SL contours (DECLARE CONTOUR)"
            self.report("heidenhain.sl-q-parameters", span, f"the program sets {', '.join(own)} itself and {user}: the SL and cylinder cycles "
                        "keep their parameters in Q1-Q20, so a cycle definition overwrites the program's values and the program's assignments change the "
                        "cycle's data; use Q parameters above 20 (or QL) for the program's own values")


class _SideFinishingRadius(CycleRule):
    """C20: for 24 the finishing allowance plus the finishing tool's radius must stay below
    the roughing allowance Q3 plus the rougher's radius (seed L9833-9834); Q438 names the
    rougher (-1: the tool of the last 22, 0: none)."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        side, finish_allowance = params.get("Q3"), params.get("Q14")
        if number != 24 or side is None or finish_allowance is None or not self.first_time(state, ("side-finishing-radius", span)):
            return
        finisher = spindle_tool(self, state, span, "heidenhain.sl-allowance", "radius")
        rougher = self._rougher_radius(params, span, facts.last_rougher)
        if finisher is None or rougher is None:
            return
        finishing, roughing = values.add(finish_allowance, finisher.radius), values.add(side, rougher)
        verdict = self.checker.judge(hazard(">=", finishing, roughing), state)
        self.checker.report_verdict("heidenhain.sl-allowance", spans.get("Q14", span), f"cycle 24: allowance Q14={show(finish_allowance)} plus the finishing tool's radius "
                                    f"{finisher.radius:g} is not below the roughing allowance Q3={show(side)} plus the rougher's radius {rougher:g}: the finisher has no "
                                    "room beside what the roughing left (seed L9833-9834)", verdict, state)

    def _rougher_radius(self, params, span, last_rougher):
        reference = params.get("Q438", -1.0)
        number = last_rougher if reference == -1.0 else reference
        if reference == 0.0:
            return 0.0
        tool = self.checker.context.tools.numbered(number)
        if tool is None or tool.radius is None:
            self.missing("heidenhain.sl-allowance", span, "the radius of the roughing tool cycle 24 refers to (Q438, or the tool of the last cycle 22) is not known")
            return None
        return tool.radius


class _ContourMillingAllowance(CycleRule):
    """C20, C24: side finishing of a contour that is a single island mills along it; the
    roughing allowance (Q3 of 20, Q368 of 271) must then exceed Q14 plus the tool radius
    (seed L9836-9840, L11863-11868)."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        name = {24: "Q3", 274: "Q368"}.get(number)
        side, finish_allowance = params.get(name), params.get("Q14")
        if name is None or side is None or finish_allowance is None or not _single_island(facts.contour):
            return
        if not self.first_time(state, ("contour-milling", span)):
            return
        tool = spindle_tool(self, state, span, "heidenhain.sl-allowance", "radius")
        if tool is None:
            return
        needed = values.add(finish_allowance, tool.radius)
        verdict = self.checker.judge(hazard("<=", side, needed), state)
        self.checker.report_verdict("heidenhain.sl-allowance", spans.get(name, span), f"cycle {number} mills along a single island: its side allowance {name}={show(side)} "
                                    f"must exceed Q14={show(finish_allowance)} plus the tool radius {tool.radius:g} = {show(needed)} (seed L9836-9840, L11863-11868)", verdict, state)


@rule("heidenhain.sl-allowance")
class SlAllowance(CycleRuleOfParts):
    """The allowances of side finishing 24 and 274 against the tools' radii (the page adds
    the parameter-only constraints)."""

    parts = (_SideFinishingRadius, _ContourMillingAllowance)


def _single_island(use) -> bool:
    if use is None or len(use.subprograms) != 1:
        return False
    if use.how == "CONTOUR DEF":
        return use.kinds == ("I",)
    contour = use.subprograms[0].contour
    return contour is not None and contour.pocket is False


@rule("heidenhain.pilot-drill")
class PilotDrill(CycleRule):
    """C31: cycle 21 places its plunge holes for the rougher Q13; a drill wider than that
    rougher may not fit where the rougher does (seed L9483-9490)."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        rougher = params.get("Q13")
        if number != 21 or type(rougher) is not float or rougher == 0.0 or not self.first_time(state, ("pilot-drill", span)):
            return
        drill = spindle_tool(self, state, span, "heidenhain.pilot-drill", "radius")
        roughing = self.checker.context.tools.numbered(rougher)
        if drill is None:
            return
        if roughing is None or roughing.radius is None:
            self.missing("heidenhain.pilot-drill", span, f"rough-out tool T{rougher:g} of Q13 is not in the tool table")
            return
        if drill.radius > roughing.radius:
            self.report("heidenhain.pilot-drill", spans.get("Q13", span), f"cycle 21 drills with T{show(state.tool_in_spindle)} (R={drill.radius:g}) the plunge holes "
                        f"for rough-out tool T{rougher:g} (R={roughing.radius:g}): the holes are placed where the smaller rougher fits, so the larger drill "
                        "cuts into the contour's walls in narrow places")


@rule("heidenhain.tolerance")
class ToleranceText(CycleRule):
    """A10: a toleranced dimension of an OCM shape that is none of the forms the control reads."""

    def judge_cycle(self, number, params, spans, span, state, facts):
        for name, text in facts.bad_tolerances:
            where = spans.get(name, span)
            if self.first_time(state, ("tolerance", where)):
                self.report("heidenhain.tolerance", where, f"cycle {number}: {name}=\"{text}\" is not a tolerance the control reads (10+0.01-0.015, an ISO 286 fit "
                            "such as 10H7, or an ISO 2768 class such as 10m; H is a hole, h a shaft): machining stops with an error (seed L12155-12190)")
