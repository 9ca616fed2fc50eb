"""An independent concrete model of the rapid-into-stock hazard, for checking ncverify's proofs.

Deliberately simple and written apart from ncverify's code (nothing of ncverify is
imported here): a generated program is a list of steps the model runs itself for one
value of the free parameter, in workpiece coordinates; the tool is a cylinder of a radius
around its axis from the tip up its length, sampled at many points along every rapid, and
the stock a box. The generator writes the same steps as program text in each dialect.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

SAMPLES = 400  # points per move
TOUCH = 1e-3  # how far into the stock a sample must reach to count as contact (mm)


@dataclass(frozen=True)
class Linear:
    """``constant + factor * parameter``."""

    constant: float
    factor: float = 0.0

    def at(self, parameter: float) -> float:
        return self.constant + self.factor * parameter


@dataclass(frozen=True)
class Shift:
    """The program origin moves to (x, y) of the workpiece (G52, TRANS, datum shift 7)."""

    x: float
    y: float


@dataclass(frozen=True)
class Rapid:
    x: Linear
    y: Linear
    z: Linear


@dataclass(frozen=True)
class Case:
    stock: tuple  # ((x_low, x_high), (y_low, y_high), (z_low, z_high))
    radius: float
    length: float
    low: float  # the assumed range of the free parameter
    high: float
    steps: tuple  # Shift and Rapid steps, after a first rapid to a safe point


def touching_steps(case: Case, parameter: float, touch: float = TOUCH) -> set[int]:
    """Indexes of the rapid steps along which the tool reaches ``touch`` into the stock (a
    negative ``touch``: comes that near to it). The first rapid, whose start is unknown to
    a program, is not judged."""
    shift, position, touching = (0.0, 0.0), None, set()
    for index, step in enumerate(case.steps):
        if isinstance(step, Shift):
            shift = (step.x, step.y)
            continue
        target = (step.x.at(parameter) + shift[0], step.y.at(parameter) + shift[1], step.z.at(parameter))
        if position is not None and _touches(case, position, target, touch):
            touching.add(index)
        position = target
    return touching


def _touches(case: Case, start, end, touch: float) -> bool:
    (x_low, x_high), (y_low, y_high), (z_low, z_high) = case.stock
    for sample in range(SAMPLES + 1):
        share = sample / SAMPLES
        x, y, z = (a + (b - a) * share for a, b in zip(start, end))
        if z > z_high - touch or z + case.length < z_low + touch:
            continue
        dx = max(x_low - x, 0.0, x - x_high)
        dy = max(y_low - y, 0.0, y - y_high)
        if math.hypot(dx, dy) < case.radius - touch:
            return True
    return False
