"""Run a Fagor program and keep what the interpreter reports: holes, segments, faults,
notes. Tests read the trace when a finding alone cannot show where the tool went."""
from __future__ import annotations

import textwrap
from dataclasses import dataclass, field

from ncverify import Settings
from ncverify.context import Context
from ncverify.detect import Detection
from ncverify.dialect import setup_for
from ncverify.interpret import Interpreter
from ncverify.library import SubprogramLibrary
from ncverify.source import ProgramSource


@dataclass
class Trace:
    holes: list = field(default_factory=list)
    segments: list = field(default_factory=list)
    faults: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    runs: list = field(default_factory=list)
    states: list = field(default_factory=list)
    context: dict = field(default_factory=dict)  # what the checker would hold (the cycle runner reads "tools")

    def hole(self, hole, state):
        self.holes.append(hole)

    def segment(self, segment, state):
        self.segments.append(segment)

    def motion_run(self, run, state):
        self.segments.extend(run.segment(index) for index in range(len(run)))

    def cycle_run(self, run, state):
        self.runs.append(run)

    def change(self, change, state):
        if change.what == "end":
            self.states.append(state)

    def fault(self, fault):
        self.faults.append(fault)

    def note(self, note):
        self.notes.append(note)

    @property
    def points(self) -> list[tuple]:
        """Each hole's (X, Y, R point, bottom)."""
        return [(hole.position.get("X"), hole.position.get("Y"), hole.r_point, hole.bottom) for hole in self.holes]

    def rules(self) -> list[str]:
        return [item.rule for item in self.faults + self.notes]


def trace(program: str, machine: str = "mill", tools: dict | None = None) -> Trace:
    source = ProgramSource.from_text(textwrap.dedent(program).lstrip("\n"), "t.pim")
    settings = Settings(machine=machine)
    dialect = setup_for("fagor", settings, Detection("fagor", 1.0), Context())
    observer = Trace(context={"tools": tools or {}})
    interpreter = Interpreter(source, dialect.frontend, observer, settings, power_on=dialect.power_on, cycle_models=dialect.cycle_models,
                              twins=dialect.twins, machine=dialect.machine, increment=0.0, feed_increment=0.0,
                              library=SubprogramLibrary([], settings.extensions))
    interpreter.run()
    return observer
