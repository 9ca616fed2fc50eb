"""Helpers the rule modules of every dialect share: the one place a rule says which context
it lacked, and the tool radius lookup the milling rules use. Helpers of one dialect's
rules are public in that dialect's first module (``checks.heidenhain``: ``CycleRule``,
``cycle_number``, ``spindle_tool``; ``checks.sinumerik``: ``cycle_name``,
``is_sinumerik``, ...; ``checks.sinumerik_tools``: ``active_edge``); no rule module
imports another's private names."""
from __future__ import annotations

from ..check import Rule
from ..diagnostics import Status


class ReportsMissingContext(Rule):
    """Says once per file, where it first needed it, which context was missing."""

    def missing(self, rule_id: str, span, what: str) -> None:
        said = self.__dict__.setdefault("_said", set())  # rules live as long as one file's check
        if (rule_id, what) in said:
            return
        said.add((rule_id, what))
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
