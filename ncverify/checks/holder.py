"""The holder and the shank against the stock as cut so far (``core.holder-collision``).

A feed move cuts with the tool's flutes only: what lies above the cutting length (the
shank) and above the usable length or the holder's lower end (the holder) does not cut.
Before the model of the cut stock (:mod:`.material`) sweeps a feed move (one this rule
hands it, or one of a batch it cuts), it asks this rule which parts of the tool in the
spindle are known, tests each as a flat-bottomed cylinder at its height above the tip
against the material the moves before left, and calls :meth:`HolderCollision.collides`
where that material surely is.
"""
from __future__ import annotations

from ..check import CUTTING, Rule, rule, show
from ..workpiece import Cutter


def _where(point) -> str:
    return " ".join(f"{axis}{show(float(value))}" for axis, value in zip("XYZ", point))


@rule("core.holder-collision")
class HolderCollision(Rule):
    judges_cycle_runs = True
    segment_kinds = CUTTING  # the material model judges a feed move's holder
    def __init__(self, checker):
        super().__init__(checker)
        checker.material.holder_rule = self
        self._parts_of: dict[tuple, tuple] = {}  # a tool's sizes -> its parts

    def segment(self, segment, state):
        self.checker.material.holder(segment, state)

    handles_arcs = True

    def motion_run(self, run, state):
        """The material model judges a batch's feed moves and arcs as it cuts them, each
        against what the moves before it left (it calls :meth:`parts` and :meth:`collides`)."""

    def parts(self, state) -> tuple[tuple[float, Cutter, str], ...]:
        """(height above the tip, shape, name) of each non-cutting part of the tool in the
        spindle that the tool table describes; none for a tool it does not. The same parts
        each time for the same sizes: the material model asks before every feed move."""
        tool = self.checker.context.tools.in_spindle(state)
        if tool is None or not tool.radius:
            return ()
        sizes = (tool.radius, tool.cutting_length, tool.usable_length, tool.holder_diameter, tool.length, tool.holder_length)
        parts = self._parts_of.get(sizes)
        if parts is None:
            parts = self._parts_of[sizes] = _parts(tool)
        return parts

    def collides(self, span, start, end, part: str, point, state) -> None:
        self.report("core.holder-collision", span, f"feed move from {_where(start)} to {_where(end)} of tool T{show(state.tool_in_spindle)}: "
                    f"{part} meets material left by the cuts so far near {_where(point)}: it does not cut, and rubs or crashes there")


def _parts(tool) -> tuple[tuple[float, Cutter, str], ...]:
    """(height above the tip, shape, name) of each non-cutting part the tool table gives for ``tool``."""
    parts = []
    if tool.cutting_length:
        parts.append((tool.cutting_length, Cutter(tool.radius), f"the shank above the cutting length {tool.cutting_length:g} mm"))
    if tool.usable_length and (not tool.cutting_length or tool.usable_length > tool.cutting_length):
        parts.append((tool.usable_length, Cutter(tool.radius), f"the tool above its usable length {tool.usable_length:g} mm"))
    holder_low = _holder_low(tool)
    if tool.holder_diameter and holder_low is not None:
        parts.append((holder_low, Cutter(tool.holder_diameter / 2.0), f"the holder (D{tool.holder_diameter:g}, from {holder_low:g} mm above the tip)"))
    return tuple(parts)


def _holder_low(tool) -> float | None:
    """How far above the tip the holder begins: the usable length, else the tool length
    less the holder's length; None when neither is known."""
    if tool.usable_length:
        return tool.usable_length
    if tool.length and tool.holder_length and tool.length > tool.holder_length:
        return tool.length - tool.holder_length
    return None
