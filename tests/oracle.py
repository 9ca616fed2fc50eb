"""An independent concrete model of a machining program, for checking ncverify's verdicts.

Deliberately simple and written apart from ncverify's code (nothing of ncverify is
imported here). A generated program is a tree of steps (this module) that the writers in
``tests/oracle_programs.py`` turn into program text of each dialect; the model runs the
same tree itself for one value of the free parameter ``p``:

- positions are followed in machine coordinates: the program point goes through the frame
  (scaling, rotation, mirror image, then the local origin and the preset shift) to the
  workpiece, then the work offset to the machine;
- the tool is a cylinder of its radius around its axis (+Z), from the tip up its length;
  every rapid is sampled at many points and each sample is compared with the stock box
  (also in machine coordinates);
- every move, arcs along their circle, is sampled against the machine's travel.

A drilling cycle is a rapid over the hole at the clearance height, a rapid down to its R
point, a feed to the bottom and a retract up the hole it has just drilled (not judged: the
tool leaves through its own hole).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

SAMPLES = 200  # points per move
TOUCH = 1e-3  # how far into the stock a sample must reach to count as contact (mm)
# A witness of a violation may graze the stock at a corner, between two samples: it is
# reproduced with ten times the samples, and coming within NEAR of the stock counts.
NEAR = 0.05


@dataclass(frozen=True)
class Linear:
    """``constant + factor * p + per_pass * k`` (``k``: the pass of the enclosing loop, from 0)."""

    constant: float
    factor: float = 0.0
    per_pass: float = 0.0

    def at(self, parameter: float, counter: int = 0) -> float:
        return self.constant + self.factor * parameter + self.per_pass * counter


# --------------------------------------------------------------------------- the steps


@dataclass(frozen=True)
class Rapid:
    x: Linear
    y: Linear
    z: Linear


@dataclass(frozen=True)
class Feed:
    x: Linear
    y: Linear
    z: Linear


@dataclass(frozen=True)
class HalfCircle:
    """A feed half circle in the XY plane of the program: centre ``(i, j)`` from where the
    tool stands, ending on the opposite side."""

    i: float
    j: float
    clockwise: bool


@dataclass(frozen=True)
class Shift:
    """The local origin moves to (x, y) (G52, TRANS, datum shift cycle 7); it replaces the previous one."""

    x: float
    y: float


@dataclass(frozen=True)
class Preset:
    """The point where the tool stands becomes (x, y) of the program (G92)."""

    x: float
    y: float


@dataclass(frozen=True)
class Rotate:
    degrees: float  # about the program origin, counter-clockwise seen from +Z; 0 cancels


@dataclass(frozen=True)
class Scale:
    factor: float  # about the program origin; 1 cancels
    along_z: bool  # the tool axis scaled too (HEIDENHAIN cycle 11)


@dataclass(frozen=True)
class Mirror:
    on: bool  # X mirrored about the program origin


@dataclass(frozen=True)
class ToolChange:
    number: int


@dataclass(frozen=True)
class Drill:
    """Rapid up or down to ``clear`` where the tool stands, rapid over (x, y), rapid down to
    the R point ``r``, feed to ``bottom``, back up to ``clear``."""

    x: Linear
    y: Linear
    clear: float
    r: float
    bottom: float


@dataclass(frozen=True)
class Loop:
    count: int
    body: tuple


@dataclass(frozen=True)
class Call:
    name: str
    body: tuple


@dataclass(frozen=True)
class Tool:
    radius: float
    length: float


@dataclass(frozen=True)
class Case:
    stock: tuple  # ((x_low, x_high), (y_low, y_high), (z_low, z_high)), workpiece coordinates
    tools: dict  # number -> Tool; tool 1 is in the spindle at the start
    offset: tuple  # the work offset (G54): machine = workpiece + offset
    travel: tuple  # ((low, high) per axis), machine coordinates of the tool tip
    low: float  # the assumed range of the free parameter
    high: float
    steps: tuple  # the first a rapid, from where the program does not know


# --------------------------------------------------------------------------- the run


@dataclass
class _Frame:
    preset: tuple = (0.0, 0.0)
    local: tuple = (0.0, 0.0)
    degrees: float = 0.0
    factor: float = 1.0
    along_z: bool = False
    mirrored: bool = False

    def to_workpiece(self, point) -> tuple:
        x, y, z = point
        x, y = x * self.factor, y * self.factor
        if self.along_z:
            z *= self.factor
        cos, sin = math.cos(math.radians(self.degrees)), math.sin(math.radians(self.degrees))
        x, y = x * cos - y * sin, x * sin + y * cos
        if self.mirrored:
            x = -x
        return x + self.local[0] + self.preset[0], y + self.local[1] + self.preset[1], z

    def to_program(self, point) -> tuple:
        x, y, z = point
        x, y = x - self.local[0] - self.preset[0], y - self.local[1] - self.preset[1]
        if self.mirrored:
            x = -x
        cos, sin = math.cos(math.radians(self.degrees)), math.sin(math.radians(self.degrees))
        x, y = x * cos + y * sin, -x * sin + y * cos
        if self.along_z:
            z /= self.factor
        return x / self.factor, y / self.factor, z


@dataclass
class Move:
    """One move in machine coordinates, with the step that made it (its tag)."""

    tag: tuple
    kind: str  # "rapid", "feed", "arc", "retract"
    start: tuple
    end: tuple
    centre: tuple | None = None
    clockwise: bool = False
    tool: Tool | None = None


@dataclass
class _Run:
    case: Case
    parameter: float
    frame: _Frame = field(default_factory=_Frame)
    position: tuple | None = None  # workpiece
    tool: int = 1
    moves: list = field(default_factory=list)

    def machine(self, point) -> tuple:
        return tuple(a + b for a, b in zip(point, self.case.offset))

    def go(self, tag, kind, target, **more) -> None:
        """A move from where the tool stands; the first move, whose start is not known, is its end point alone."""
        start = target if self.position is None else self.position
        self.moves.append(Move(tag, kind, self.machine(start), self.machine(target), tool=self.case.tools[self.tool], **more))
        self.position = target

    def program_point(self, x: Linear, y: Linear, z: Linear, counter: int) -> tuple:
        return tuple(value.at(self.parameter, counter) for value in (x, y, z))

    def steps(self, steps: tuple, path: tuple, counter: int = 0) -> None:
        for index, step in enumerate(steps):
            self.step(step, (*path, index), counter)

    def step(self, step, tag: tuple, counter: int) -> None:
        if isinstance(step, (Rapid, Feed)):
            point = self.frame.to_workpiece(self.program_point(step.x, step.y, step.z, counter))
            self.go(tag, "rapid" if isinstance(step, Rapid) else "feed", point)
        elif isinstance(step, HalfCircle):
            x, y, z = self.frame.to_program(self.position)
            centre = self.frame.to_workpiece((x + step.i, y + step.j, z))
            clockwise = step.clockwise != self.frame.mirrored  # a mirror image turns the direction round
            self.go(tag, "arc", self.frame.to_workpiece((x + 2 * step.i, y + 2 * step.j, z)), centre=self.machine(centre), clockwise=clockwise)
        elif isinstance(step, Drill):
            self._drill(step, tag, counter)
        elif isinstance(step, Loop):
            for pass_ in range(step.count):
                self.steps(step.body, tag, pass_)
        elif isinstance(step, Call):
            self.steps(step.body, tag, counter)
        elif isinstance(step, ToolChange):
            self.tool = step.number
        else:
            self._frame(step)

    def _drill(self, step: Drill, tag: tuple, counter: int) -> None:
        x, y, _ = self.frame.to_program(self.position)
        self.go((*tag, "clear"), "rapid", self.frame.to_workpiece((x, y, step.clear)))
        over = (step.x.at(self.parameter, counter), step.y.at(self.parameter, counter))
        self.go((*tag, "over"), "rapid", self.frame.to_workpiece((*over, step.clear)))
        self.go((*tag, "down"), "rapid", self.frame.to_workpiece((*over, step.r)))
        self.go((*tag, "drill"), "feed", self.frame.to_workpiece((*over, step.bottom)))
        self.go((*tag, "retract"), "retract", self.frame.to_workpiece((*over, step.clear)))

    def _frame(self, step) -> None:
        if isinstance(step, Shift):
            self.frame.local = (step.x, step.y)
        elif isinstance(step, Preset):
            x, y, _ = self.position
            self.frame.preset = (x - self.frame.local[0] - step.x, y - self.frame.local[1] - step.y)
        elif isinstance(step, Rotate):
            self.frame.degrees = step.degrees
        elif isinstance(step, Scale):
            self.frame.factor, self.frame.along_z = step.factor, step.along_z
        elif isinstance(step, Mirror):
            self.frame.mirrored = step.on
        else:
            raise TypeError(step)


def run(case: Case, parameter: float) -> list[Move]:
    """Every move of the program for ``p = parameter``, in machine coordinates."""
    model = _Run(case, parameter)
    model.steps(case.steps, ())
    return model.moves


# --------------------------------------------------------------------------- the hazards


def touching(case: Case, parameter: float, near: bool = False) -> set[tuple]:
    """Tags of the rapids along which the tool reaches ``TOUCH`` into the stock (``near``:
    comes that near to it)."""
    touch, samples = (-NEAR, SAMPLES * 10) if near else (TOUCH, SAMPLES)
    stock = tuple((low + offset, high + offset) for (low, high), offset in zip(case.stock, case.offset))
    return {move.tag for move in run(case, parameter) if move.kind == "rapid" and _touches(stock, move, touch, samples)}


def _touches(stock, move: Move, touch: float, samples: int) -> bool:
    (x_low, x_high), (y_low, y_high), (z_low, z_high) = stock
    for x, y, z in _samples(move, samples):
        if z > z_high - touch or z + move.tool.length < z_low + touch:
            continue
        dx = max(x_low - x, 0.0, x - x_high)
        dy = max(y_low - y, 0.0, y - y_high)
        if math.hypot(dx, dy) < move.tool.radius - touch:
            return True
    return False


def outside_travel(case: Case, parameter: float, near: bool = False) -> set[tuple]:
    """Tags of the moves along which the tool tip leaves the travel by more than ``TOUCH``.
    A move that starts outside is the hazard of the move before it and is not judged again
    (the first move, its end point alone, is); ``near``: the moves that come within
    ``NEAR`` of the travel's end or start outside it."""
    margin, samples = (-NEAR, SAMPLES * 10) if near else (TOUCH, SAMPLES)

    def outside(point, margin) -> bool:
        return any(value < low - margin or value > high + margin for value, (low, high) in zip(point, case.travel))

    return {move.tag for move in run(case, parameter)
            if (near or move.start == move.end or not outside(move.start, -margin)) and any(outside(point, margin) for point in _samples(move, samples))}


def _samples(move: Move, samples: int = SAMPLES):
    """Points along a move: a straight line, or the arc about its centre."""
    if move.centre is None:
        for sample in range(samples + 1):
            share = sample / samples
            yield tuple(a + (b - a) * share for a, b in zip(move.start, move.end))
        return
    (cx, cy, _), (sx, sy, z) = move.centre, move.start
    radius, begin = math.hypot(sx - cx, sy - cy), math.atan2(sy - cy, sx - cx)
    end = math.atan2(move.end[1] - cy, move.end[0] - cx)
    sweep = (end - begin) % (2 * math.pi) or 2 * math.pi  # counter-clockwise
    if move.clockwise:
        sweep -= 2 * math.pi
    for sample in range(samples + 1):
        angle = begin + sweep * sample / samples
        yield cx + radius * math.cos(angle), cy + radius * math.sin(angle), z
