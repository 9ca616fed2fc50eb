"""The Klartext state of one path: what the control remembers between blocks beyond the
dialect-neutral machine state (the CALL-active cycle, the circle centre, the SL and OCM
contour data, the active coordinate transformations, ...).

It is a frozen value in :attr:`MachineState.klartext
<ncverify.interpret.interpreter.MachineState.klartext>`: a change replaces it
(:func:`dataclasses.replace`), so a forked path never sees its twin's changes.
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields

from ...cycle_models import CycleModel


class DrilledHoles:
    """The holes a path has drilled, as ``(x, y, bottom)`` in order, found by their plane
    point without a scan: a CAM program drills thousands, and looking through all of them
    at each new hole took time growing with the square of their number.

    A value like the rest of :class:`KlartextState`: :meth:`adding` gives a new one and this
    one goes on seeing only its own holes. Versions share one append-only log; a version
    that is no longer the log's newest (a forked path adding its own hole) copies its part
    of the log first."""

    __slots__ = ("_log", "_count")

    def __init__(self, log: _HoleLog | None = None, count: int = 0):
        self._log = log if log is not None else _HoleLog()
        self._count = count

    def __len__(self) -> int:
        return self._count

    def __iter__(self):
        return iter(self._log.holes[: self._count])

    def __eq__(self, other) -> bool:
        return isinstance(other, DrilledHoles) and list(self) == list(other)


    def adding(self, x, y, bottom) -> DrilledHoles:
        log = self._log
        if len(log.holes) != self._count:
            log = _HoleLog(log.holes[: self._count])
        log.append((x, y, bottom))
        return DrilledHoles(log, self._count + 1)

    def bottoms_at(self, x, y) -> list:
        """The bottoms of the holes drilled at the plane point (x, y), compared with ``==``."""
        log, count = self._log, self._count
        found = [log.holes[index][2] for index in log.by_point.get(_point_key(x, y), ()) if index < count]
        found.extend(log.holes[index][2] for index in log.others if index < count and log.holes[index][0] == x and log.holes[index][1] == y)
        return found


class _HoleLog:
    """Holes in the order drilled, indexed by their point where it is two plain numbers
    (``others``: the rest, symbolic coordinates, compared one by one)."""

    __slots__ = ("holes", "by_point", "others")

    def __init__(self, holes=()):
        self.holes, self.by_point, self.others = [], {}, []
        for hole in holes:
            self.append(hole)

    def append(self, hole: tuple) -> None:
        key = _point_key(hole[0], hole[1])
        if key is None:
            self.others.append(len(self.holes))
        else:
            self.by_point.setdefault(key, []).append(len(self.holes))
        self.holes.append(hole)


def _point_key(x, y):
    """A dictionary key that finds exactly the points ``==`` finds: two floats that are
    numbers (a NaN equals nothing, itself included); None for anything else."""
    if type(x) is float and type(y) is float and x == x and y == y:
        return (x, y)
    return None


@dataclass(frozen=True)
class Definition:
    """A CALL-active cycle as its CYCL DEF left it."""

    number: int
    params: dict
    spans: dict
    span: object
    model: CycleModel
    program: str | None = None  # the program cycle 12 calls (12.1 PGM)


@dataclass(frozen=True)
class KlartextState:
    cycle: Definition | None = None  # the CALL-active cycle CYCL CALL, M99 and M89 run
    m89: bool | None = None  # that cycle runs after every positioning block (M89)
    old_cycle: tuple | None = None  # (number, params) of an old-style cycle being defined block by block
    global_defaults: dict = field(default_factory=dict)  # GLOBAL DEF values PREDEF reads
    tool_feed: object = None  # the feed of the last TOOL CALL (FAUTO)
    radius_delta: object = 0.0  # the DR of the last TOOL CALL, on top of the table's R + DR
    length_delta: object = 0.0  # its DL, on top of the table's L + DL: the tip stands DL from the programmed point
    pole: dict = field(default_factory=dict)  # the circle centre CC per axis
    pole_axes: tuple | None = None  # the two axes CC was given in
    fed_at: tuple | None = None  # the plane point the last feed move ended at
    pattern: tuple | None = None  # points of PATTERN DEF or SEL PATTERN (None: not known)
    ended_elsewhere: int | None = None  # the cycle that left the tool away from its start point
    drilled: DrilledHoles = field(default_factory=DrilledHoles)  # the holes drilled so far
    feed_per_revolution: bool | None = None  # M136 is on
    label_repeats: dict = field(default_factory=dict)  # CALL LBL .. REP: repeats done, by the call's offset
    # SL contours (cycle 14, CONTOUR DEF, SEL CONTOUR) and contour trains
    sl_data: tuple | None = None  # (params, spans, span) of cycle 20
    sl_labels: tuple | None = None  # the contour subprograms' labels
    sl_kinds: tuple | None = None  # per label: a pocket (True) or an island (CONTOUR DEF P/I)
    contour_source: tuple | None = None  # (how, span, kinds, depths) of the contour's definition
    declared_depths: tuple = ()  # per DECLARE CONTOUR: was a DEPTH given
    sl_rougher: object = None  # the tool that roughed the last SL contour
    roughed_since_contour_def: bool | None = None  # an OCM rougher ran since CONTOUR DEF / SEL CONTOUR
    train_data: tuple = ({}, {})  # (params, spans) of cycle 270
    ocm: tuple | None = None  # (number, params, spans) of cycle 271 or an OCM shape
    ocm_boundary: int | None = None  # the OCM boundary shape
    # coordinate transformations (:mod:`.transforms`)
    transforms: tuple = ()  # sorted (number, data) of the active transformations
    transform_order: tuple = ()  # their numbers in the order they were defined

    def changed(self, changes: dict) -> KlartextState:
        """A copy with ``changes``: :func:`dataclasses.replace` without its detour through
        ``__init__``, as the path makes one on nearly every block (where the feed moves ended)."""
        if not changes.keys() <= _FIELD_NAMES:
            raise TypeError(f"not a field of KlartextState: {', '.join(sorted(changes.keys() - _FIELD_NAMES))}")
        twin = object.__new__(KlartextState)
        twin.__dict__.update(self.__dict__, **changes)
        return twin


_FIELD_NAMES = frozenset(item.name for item in fields(KlartextState))
