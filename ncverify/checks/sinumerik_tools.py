"""SINUMERIK 840D rules on the cutting edge in use: its clearance angle against a CYCLE95
contour (alarm 61604), its cutting-edge position at CYCLE94/96 (61608), the edge CYCLE73
needs (61989), and the threading tool's flank angle against the infeed angle of CYCLE97/98.

The tool data are those of the active edge (``$TC_DP..[t,d]`` in the program; ``ncverify:
tool`` annotations and ``[tools.N]`` describe D1); the active edge is the ``$P_TOOL`` variable
that D words and M6 write (:mod:`ncverify.lower.sinumerik`). Reference ``sinumerik-840d-b.md`` sections 3, 6.0,
6.3, 6.5, 9 and 11.2; ``sinumerik-840d-a.md`` section 6.24.
"""
from __future__ import annotations

import math
from typing import NamedTuple

from .. import ir
from ..check import rule, show
from ..frames import Frame
from ..context import active_tool_number
from .common import ReportsMissingContext
from .. import modelled


def active_edge(state):
    """The active D number, or None when the program has not set it on this path."""
    edge = state.global_variables.get(ir.ACTIVE_EDGE)
    return edge if type(edge) is float else None


class _EdgeRule(ReportsMissingContext):
    """A rule that needs the data of the active cutting edge."""
    reads = modelled.AS_WRITTEN

    def edge_tool(self, state):
        """``(data of the active edge, None)`` when they are known, else ``(None, why not)``.
        Annotations and the project file describe edge D1; ``$TC_DP..[t,d]`` any edge."""
        number = active_tool_number(state, self.checker.context.lathe)
        if number is None:
            return None, "which tool is active is not known"
        edge = active_edge(state)
        if edge is None:
            return None, "no D number is programmed on this path"
        tool = self.checker.context.tools.numbered(number)
        if tool is None:
            return None, f"tool T{show(number)} is not defined ($TC_DP.. in the program, an ncverify: tool annotation or [tools.{show(number)}])"
        data = tool.edge_data(edge)
        if data is None:
            return None, f"the data of edge D{show(edge)} of T{show(number)} are not in the program ($TC_DP..[{show(number)},{show(edge)}])"
        return data, None

    def edge_data(self, rule_id: str, span, state, what: str):
        """The active edge's data, or None after saying once (``what`` names the datum the
        rule needs) why they are not known."""
        tool, why = self.edge_tool(state)
        if tool is None:
            self.missing(rule_id, span, f"the {what} of the active tool is not known: {why}")
        return tool

    def edge_value(self, rule_id: str, span, state, field: str):
        """``(active edge, its value of field)``; the value is None after saying once where
        it would come from."""
        what, parameter = _EDGE_FIELDS[field]
        tool = self.edge_data(rule_id, span, state, what)
        if tool is None:
            return None, None
        value = getattr(tool, field)
        if value is None:
            self.missing(rule_id, span, f"the {what} of {_edge_name(tool, state)} is not known ($TC_DP{parameter}{_edge_index(tool, state)}, "
                         f"{field.replace('_', '-')} in an ncverify: tool annotation, or [tools.{tool.number}] {field})")
        return tool, value


# the edge data a rule may need: what a machinist calls it, and its $TC_DP parameter number
_EDGE_FIELDS = {"clearance_angle": ("clearance angle", 24), "edge_position": ("cutting-edge position", 2)}


def _edge_name(tool, state) -> str:
    return f"T{tool.number} D{show(active_edge(state))}"


def _edge_index(tool, state) -> str:
    return f"[{tool.number},{show(active_edge(state))}]"


# --------------------------------------------------------------------------- CYCLE95: the clearance angle (61604)

class UndercutEntry(NamedTuple):
    """A contour element that may dive into an undercut in the machining direction, with its
    angle to the machining axis in degrees: at least ``flattest`` somewhere on the element
    (0 when it need not enter at all), at most ``steepest`` anywhere on it, over the readings
    of X that may hold (a radius, a diameter, or both when the mode is not known)."""

    start: tuple[float, float]
    end: tuple[float, float]
    span: object
    flattest: float
    steepest: float
    arc: bool = False


def undercut_entries(points, kind: float, plane: tuple[str, str, str], arcs: dict | None = None,
                     diameter: bool | None = None) -> list[UndercutEntry]:
    """The elements of a CYCLE95 contour (``points``: the plane points in order, with the
    block reaching each; ``arcs``: the blocks that are arcs, by span, with their radius or
    None; ``diameter``: whether X is a diameter, None when not known) that enter an undercut: they advance in the machining direction, from the first
    contour point to the last along the machining axis, and go deeper along the infeed axis
    (reference B section 6.3, VARI table L16166-16208: longitudinal machining runs along the
    first plane axis with the infeed along the second, face machining the other way round;
    external machining feeds in towards minus, internal towards plus). An element whose chord
    turns back against the machining direction is an overhang, not an entry."""
    along = 0 if int(kind) % 100 % 2 == 1 else 1
    across = 1 - along
    inward = 1.0 if (int(kind) % 100 - 1) % 4 >= 2 else -1.0
    if points[-1][0][along] == points[0][0][along]:
        return []
    direction = math.copysign(1.0, points[-1][0][along] - points[0][0][along])
    modes = (False, True) if diameter is None else (diameter,)
    readings = [[(0.5 if plane[index] == "X" and as_diameter else 1.0) for index in (along, across)] for as_diameter in modes]
    entries = []
    for (start, _), (end, span) in zip(points, points[1:]):
        advance, depth = (end[along] - start[along]) * direction, (end[across] - start[across]) * inward
        if advance < -1e-9:
            continue
        is_arc = arcs is not None and span in arcs
        chords = [(advance * scale_along, depth * scale_across) for scale_along, scale_across in readings]
        if is_arc:
            # A reading in which the chord is longer than the diameter is no arc at all: the program means the other one.
            radius = arcs[span]
            possible = [chord for chord in chords if radius is None or math.hypot(*chord) <= 2 * radius + 1e-9] or chords
            flattest = min(_angle(chord) for chord in possible) if depth > 1e-9 else 0.0
            steepest = max(_arc_steepest(chord, radius) for chord in possible)
        elif depth > 1e-9:
            flattest, steepest = min(map(_angle, chords)), max(map(_angle, chords))
        else:
            continue
        if steepest > 1e-6:  # a quarter arc rising from a level element starts level
            entries.append(UndercutEntry(start, end, span, flattest, steepest, is_arc))
    return entries


def _angle(chord: tuple[float, float]) -> float:
    """The angle in degrees of an (advance, depth) direction to the machining axis."""
    return math.degrees(math.atan2(chord[1], chord[0]))


def _arc_steepest(chord: tuple[float, float], radius) -> float:
    """The steepest an arc of ``radius`` (None: unknown) over ``chord`` can dive: its tangent
    turns at most half the swept angle away from the chord's direction."""
    if radius is None:
        return 90.0
    half_swept = math.degrees(math.asin(min(1.0, math.hypot(*chord) / (2 * radius))))
    return min(90.0, _angle(chord) + half_swept)


@rule("sinumerik.clearance-angle")
class ClearanceAngle(_EdgeRule):
    """CYCLE95 checks every undercut element against the clearance angle of the active edge
    (``$TC_DP24``, 0-90 degrees, 0 = not monitored) and stops with alarm 61604 when the tool
    would damage the contour (reference B section 6.0, C15 and section 9 item 17, seed
    L14840-14888, L16440-16462, L19971-19978): an element entering an undercut at a steeper
    angle to the machining axis than the clearance angle. Judged on the contour's end points:
    an arc's chord is as steep as the arc at some point of it, so a steep chord is a steep
    element; a contour with arcs and no steep chord is unknown (a tangent inside an arc may
    dip more steeply). Roundings and chamfers lie between the angles of their neighbours."""

    def cycle_run(self, run, state):
        facts = run.params.get("CONTOUR") if run.cycle == "sinumerik.CYCLE95" else None
        kind = run.params.get("VARI")
        if facts is None or not facts.found or type(kind) is not float or not 1 <= kind % 100 <= 12:
            return
        if not facts.points:
            self.missing("sinumerik.clearance-angle", run.param_spans.get("NPP", run.span),
                         f"the points of the CYCLE95 contour \"{facts.name}\" are not all known numbers: its undercuts are not judged against the clearance angle")
            return
        entries = undercut_entries(facts.points, kind, state.plane_axes, facts.arcs, _x_is_diameter(state, facts))
        if not entries:
            return
        if state.frame is not None and state.frame.linear != Frame().linear:
            self.missing("sinumerik.clearance-angle", run.span,
                         "a rotation, scale or mirror frame is active: the cycle's clearance-angle monitoring does not take it into account (seed B L14880-14884)")
            return
        tool, angle = self.edge_value("sinumerik.clearance-angle", run.span, state, "clearance_angle")
        if angle is not None and angle > 0:
            self._judge(facts, entries, tool, state)

    def _judge(self, facts, entries, tool, state):
        angle = tool.clearance_angle
        first, second, _normal = state.plane_axes
        for entry in entries:
            where = (f"CYCLE95 contour \"{facts.name}\": the {'arc' if entry.arc else 'element'} from {first}{entry.start[0]:g} {second}{entry.start[1]:g} "
                     f"to {first}{entry.end[0]:g} {second}{entry.end[1]:g}")
            if entry.flattest > angle:
                self.report("sinumerik.clearance-angle", entry.span,
                            f"{where} enters an undercut at {_angles(entry)}, steeper than the clearance angle {angle:g} of {_edge_name(tool, state)}: "
                            "would raise alarm 61604 \"active tool violates programmed contour\"; use a tool with a larger clearance angle or change the contour")
                return
            if entry.steepest > angle:
                why = "the arc's tangents are bounded, not computed" if entry.arc else "whether X is a diameter is not known (no DIAMON or DIAMOF before the call)"
                self.missing("sinumerik.clearance-angle", entry.span,
                             f"{where} may enter an undercut at up to {entry.steepest:.1f} degrees, against the clearance angle {angle:g}: {why}")


def _x_is_diameter(state, facts) -> bool | None:
    """Whether the contour's X values are diameters: DIAMON or DIAMOF in force at the call
    and not changed inside the contour; None when not known (DIAM90 included)."""
    modes = {state.modal.get("diameter"), *facts.diameter_modes}
    return {"diameter": True, "radius": False}.get(modes.pop()) if len(modes) == 1 else None


def _angles(entry: UndercutEntry) -> str:
    if entry.arc:
        return f"{entry.flattest:.1f} degrees or more somewhere"
    if entry.flattest == entry.steepest:
        return f"{entry.flattest:.1f} degrees"
    return f"{entry.flattest:.1f} to {entry.steepest:.1f} degrees (X read as a diameter or as a radius)"


# --------------------------------------------------------------------------- CYCLE94/96: the cutting-edge position (61608)

@rule("sinumerik.edge-position")
class EdgePosition(_EdgeRule):
    """CYCLE94 and CYCLE96 with ``_VARI=0`` take the undercut position from the cutting-edge
    position of the active edge (``$TC_DP2``) and accept only SL 1-4: SL 5-9 raises alarm
    61608 (reference B sections 6.2, 6.4 and 11.2, seed L15650-15662, L19994-19999)."""

    def cycle_run(self, run, state):
        if run.cycle not in ("sinumerik.CYCLE94", "sinumerik.CYCLE96") or run.params.get("_VARI", 0.0) != 0.0:
            return
        name = ir.cycle_code(run.cycle)
        tool, position = self.edge_value("sinumerik.edge-position", run.span, state, "edge_position")
        if position is not None and position >= 5:
            self.report("sinumerik.edge-position", run.param_spans.get("_VARI", run.span),
                        f"{name} with _VARI=0 takes the undercut position from the cutting-edge position, and the active edge {_edge_name(tool, state)} has SL {position:g}: "
                        "only SL 1 to 4 are allowed: would raise alarm 61608 \"wrong cutting-edge position programmed\"; program the position in _VARI (1-4) or use another edge")


# --------------------------------------------------------------------------- CYCLE73: edge D1 (61989)

@rule("sinumerik.pocket-edge")
class PocketEdge(ReportsMissingContext):
    """CYCLE73 computes its paths with the offsets of edge D1 and allows no other edge (no
    spare-tool strategy): another D raises alarm 61989 (reference A sections 6.24 and 9 item
    39, seed L9530-9620, L10703-10775)."""
    reads = modelled.AS_WRITTEN

    def cycle_run(self, run, state):
        if run.cycle != "sinumerik.CYCLE73":
            return
        edge = active_edge(state)
        if edge is None:
            self.missing("sinumerik.pocket-edge", run.span, "the active cutting edge (D number) at CYCLE73 is not known on this path")
        elif edge != 1.0:
            self.report("sinumerik.pocket-edge", run.span,
                        f"CYCLE73 with edge D{show(edge)} active: the pocket cycle works only with D1: would raise alarm 61989 \"D1 not programmed as active edge\"; program D1 before the call")


# --------------------------------------------------------------------------- CYCLE97/98: the infeed angle against the flank angle

_METRIC_FLANK_ANGLE = 60.0  # an ISO metric thread (MPIT), reference B section 9 item 35


@rule("sinumerik.thread-infeed-angle")
class ThreadInfeedAngle(_EdgeRule):
    """CYCLE97 and CYCLE98 infeed along a flank at IANG, which may be at most half the flank
    angle of the threading tool (reference B sections 6.5 and 9 item 35, seed L17147-17171):
    the tool's ``angle`` (an ``ncverify: tool`` annotation or ``[tools.N]``), or 60 degrees for
    a metric thread given by MPIT when the tool's angle is not known."""

    def cycle_run(self, run, state):
        infeed = run.params.get("IANG") if run.cycle in ("sinumerik.CYCLE97", "sinumerik.CYCLE98") else None
        if type(infeed) is not float or infeed == 0.0:
            return
        name = ir.cycle_code(run.cycle)
        flank, whose = self._flank_angle(run, state)
        if flank is None:
            return
        if abs(infeed) > flank / 2 + 1e-9:
            self.report("sinumerik.thread-infeed-angle", run.param_spans.get("IANG", run.span),
                        f"{name}: infeed angle IANG={show(infeed)} is more than half the flank angle {flank:g} of {whose}: "
                        f"the tool cuts into the thread's flank (no alarm); at most {flank / 2:g}")

    def _flank_angle(self, run, state):
        """The flank angle and what it belongs to, or (None, None) when it is not known (said once)."""
        size = run.params.get("MPIT")
        metric = run.cycle == "sinumerik.CYCLE97" and type(size) is float and size != 0.0
        tool = self.edge_tool(state)[0] if metric else self.edge_data("sinumerik.thread-infeed-angle", run.span, state, "flank angle")
        if tool is not None and tool.angle is not None:
            return tool.angle, f"tool T{tool.number}"
        if metric:
            return _METRIC_FLANK_ANGLE, f"the metric thread M{size:g}"
        if tool is not None:
            self.missing("sinumerik.thread-infeed-angle", run.span,
                         f"the flank angle of threading tool T{tool.number} is not known (angle in an ncverify: tool annotation or [tools.{tool.number}])")
        return None, None
