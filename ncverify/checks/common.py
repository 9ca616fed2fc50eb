"""Helpers the rule modules of every dialect share: the one place a rule says which context
it lacked, and the tool radius lookup the milling rules use. Helpers of one dialect's
rules are public in that dialect's first module (``checks.heidenhain``: ``CycleRule``,
``cycle_number``, ``spindle_tool``; ``checks.sinumerik``: ``cycle_name``,
``is_sinumerik``, ...; ``checks.sinumerik_tools``: ``active_edge``); no rule module
imports another's private names."""
from __future__ import annotations

from .. import frames, values
from ..check import Rule
from ..diagnostics import Status

# Why a cycle's sizes are not known on the workpiece
UNEVEN_SCALE = ("the working plane is scaled unevenly, or by a transformation that is not modelled: "
                "the sizes the cycle cuts on the workpiece are not known")


def plane_scale(state) -> float | None:
    """The factor the active frame scales lengths in the working plane by: 1 with no frame,
    a shift, a rotation or a mirror image; None when the plane's axes are scaled by
    different factors or the frame is not known."""
    frame = frames.program_to_workpiece(state)
    if frame is None:
        return 1.0
    similar = frame.plane_similarity(state.plane_axes)
    return None if similar is None else similar[0]


_DIAMETER_MODES = {"diameter": True, "radius": False}
UNKNOWN_DIAMETER_MODE = ("whether the lathe's X is a diameter or a radius is not known (SINUMERIK: no DIAMON or DIAMOF yet, "
                         "or DIAM90, which reads radii in incremental blocks)")


def lathe_x_is_diameter(state) -> bool | None:
    """Whether a lathe program's X is a diameter: the mode in force (SINUMERIK DIAMON /
    DIAMOF, LinuxCNC G7 / G8); without one, a diameter, as on the ISO family's lathes. None
    when it is not known: SINUMERIK before DIAMON or DIAMOF (machine data decides), and
    DIAM90, which reads diameters in absolute blocks and radii in incremental ones."""
    mode = state.modal.get("diameter")
    return True if mode is None else _DIAMETER_MODES.get(mode)


def scaled_note(state) -> str:
    """What a finding on a cycle's size adds when a scale factor made it: "" without one."""
    factor = plane_scale(state)
    return "" if factor in (1.0, None) else f" (the sizes as scaled by the factor {factor:g} in force)"


class ReportsMissingContext(Rule):
    """Says once per file, where it first needed it, which context was missing."""

    def __init__(self, checker):
        super().__init__(checker)
        self._said: set = set()  # (rule, what) said already: rules live as long as one file's check

    def missing(self, rule_id: str, span, what: str) -> None:
        key = (rule_id, what)
        if key in self._said:
            return
        self._said.add(key)
        self.report(rule_id, span, f"not checked: {what}", Status.UNKNOWN, what)

    def spindle_tool_radius(self, state, span, rule_id: str) -> float | None:
        """The radius of the tool in the spindle from the tool table, or None after saying
        once what is missing (the whole table, or this tool's radius)."""
        tools = self.checker.context.tools
        tool = tools.in_spindle(state)
        if tool is None or tool.radius is None:
            self.missing(rule_id, span, tools.missing(state, "radius"))
            return None
        return tool.radius

    def workpiece_sizes(self, params: dict, names, state, span, rule_id: str) -> dict | None:
        """``params`` with the lengths ``names`` as the control cuts them: the control scales
        a cycle's sizes with every position (SINUMERIK SCALE/ASCALE, Klartext cycles 11 and
        26), never the tool, so the tool must fit the scaled size. None (unknown, said once)
        when the plane is scaled unevenly or the frame is not known."""
        factor = plane_scale(state)
        if factor is None:
            self.missing(rule_id, span, UNEVEN_SCALE)
            return None
        if factor == 1.0:
            return params
        return {**params, **{name: values.mul(params[name], factor) for name in names if params.get(name) is not None and not isinstance(params[name], str)}}
