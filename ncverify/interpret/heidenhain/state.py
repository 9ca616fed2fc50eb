"""The Klartext state of one path: what the control remembers between blocks beyond the
dialect-neutral machine state (the CALL-active cycle, the circle centre, the SL and OCM
contour data, the active coordinate transformations, ...).

It is a frozen value in :attr:`MachineState.klartext
<ncverify.interpret.interpreter.MachineState.klartext>`: a change replaces it
(:func:`dataclasses.replace`), so a forked path never sees its twin's changes.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ...cycle_models import CycleModel


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
    pole: dict = field(default_factory=dict)  # the circle centre CC per axis
    pole_axes: tuple | None = None  # the two axes CC was given in
    fed_at: tuple | None = None  # the plane point the last feed move ended at
    pattern: tuple | None = None  # points of PATTERN DEF or SEL PATTERN (None: not known)
    ended_elsewhere: int | None = None  # the cycle that left the tool away from its start point
    drilled: tuple = ()  # (x, y, bottom) of the holes drilled so far
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
