"""The schema of the cycle tables, ``dialects/<dialect>/cycles.toml``.

Every key a cycle model or one of its parameters may have is a field below, with what it
means; :func:`load_cycle_table` reads a table into :class:`CycleModel` objects and refuses
a key that is not one of them, naming the file, the cycle and the keys it accepts, so that
a misspelt key is an error when the table is loaded instead of a fact silently not applied.
Code reads a model's facts as attributes; a cycle the tables do not have is
:data:`UNKNOWN_CYCLE`, every fact at its default.
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields
from functools import cache

from .resources import data_dir, read_table


@dataclass(frozen=True)
class ParameterSpec:
    """One parameter of a cycle (``params`` of the ISO, Klartext and Fagor tables)."""

    meaning: str
    kind: str  # length (scaled like an axis word) | time | count | feed | angle | code
    required: bool = False
    modal: bool = False  # ISO: kept for the later holes of a modal cycle
    allowed: list | None = None  # the only values the control takes
    default: float | None = None  # Fagor: the value of an omitted parameter
    unit: str | None = None  # Klartext: as the manual gives them
    reference: str | None = None  # Klartext: absolute | incremental
    range: list | None = None  # Klartext: the input range the manual prints
    tolerance: bool = False  # Klartext OCM: the value may be a toleranced text


@dataclass(frozen=True)
class CycleModel:
    """One cycle of a dialect's table; see ``dialects/README.md`` for the motion keys."""

    name: str
    seed: str | None = None  # the manual lines the model comes from
    machine: str | None = None  # mill | lathe: the machine type the cycle belongs to
    params: dict[str, ParameterSpec] = field(default_factory=dict)
    arguments: list | tuple = ()  # SINUMERIK: [name, type] by position
    # hole motion (ISO, Fagor)
    infeed: str | None = None
    bottom: list | tuple = ()
    retract: str | None = None
    shape: str | None = None
    two_blocks: bool = False
    first_block: list | tuple = ()
    drill_axis: str | None = None
    r_incremental: bool = False
    tapping: bool = False
    thread: bool = False
    spindle_before: str | None = None
    depth: str | None = None
    # Klartext
    family: str | None = None
    activity: str | None = None  # def | call
    ends_elsewhere: bool = False
    start_end: list | tuple = ()  # start and end point in the tool axis, in place of Q203 and Q201
    requires: list | tuple = ()
    compatible: list | tuple = ()
    spindle_by_cycle: bool = False
    # SINUMERIK
    affects: list | tuple = ()
    contours: dict = field(default_factory=dict)
    needs_offset: bool = False
    needs_tool: bool = False
    spindle_after: str | None = None
    spindle_during: str | None = None
    tapping_cycle: bool = False
    text_length: int | None = None
    text_specials: str | None = None
    called_after_motion: bool = False  # set by the lowering, not in the table: MCALL calls the cycle after each move
    # Fagor
    approach: str | None = None
    axis_word_moves: bool = False
    fresh_data: bool = False
    levels: str | None = None
    motion_codes_keep_cycle: bool = False
    passes: str | None = None
    pattern: str | None = None
    pocket: str | None = None
    positions_in_motion_mode: bool = False
    repeat_letter: str | None = None
    runs_at_definition: bool = False
    starts_spindle: bool = False
    thread_mill: str | None = None
    zero_repeat_moves: bool = False
    # LinuxCNC
    rises_to_r: bool = False  # a tool below R rises to it before positioning
    retract_to_higher: bool = False  # G98 returns straight out to the higher of the initial level and R
    feeds_out_to_r: bool = False  # leaves the hole at feed to R only, then rapids to the G98 level (rs274's G85)


UNKNOWN_CYCLE = CycleModel(name="")  # the model of a cycle the tables do not have
CYCLE_KEYS = frozenset(item.name for item in fields(CycleModel)) - {"called_after_motion"}
PARAMETER_KEYS = frozenset(item.name for item in fields(ParameterSpec))


class CycleTableError(ValueError):
    pass


@cache
def load_cycle_table(dialect: str) -> dict[str, CycleModel]:
    """The cycle models of ``dialects/<dialect>/cycles.toml`` by cycle id, read once per
    process (the Klartext setup asks for them for every file); the models are frozen and
    nobody adds to the table."""
    return typed_cycle_table(read_cycle_table(dialect))


def read_cycle_table(dialect: str) -> dict[str, dict]:
    """The tables of ``dialects/<dialect>/cycles.toml`` as written, by cycle id, each checked
    against :class:`CycleModel` and its parameters against :class:`ParameterSpec` (for a
    dialect that overlays one table on another before typing them)."""
    path = data_dir("dialects") / dialect / "cycles.toml"
    models = read_table(path)["cycle"]
    for cycle, model in models.items():
        check_cycle_model(f"dialects/{dialect}/cycles.toml", cycle, model)
    return models


def typed_cycle_table(models: dict[str, dict]) -> dict[str, CycleModel]:
    """Checked tables (:func:`read_cycle_table`) as :class:`CycleModel` objects."""
    return {cycle: CycleModel(**{**model, "params": {name: ParameterSpec(**spec) for name, spec in model.get("params", {}).items()}})
            for cycle, model in models.items()}


def check_cycle_model(where: str, cycle: str, model: dict) -> None:
    """Raise :class:`CycleTableError` for a key the schema does not know."""
    unknown = sorted(set(model) - CYCLE_KEYS)
    if unknown:
        raise CycleTableError(f"{where}: cycle {cycle}: unknown key {', '.join(unknown)}; accepted keys: {', '.join(sorted(CYCLE_KEYS))}")
    if "name" not in model:
        raise CycleTableError(f"{where}: cycle {cycle}: no name")
    for parameter, spec in (model.get("params") or {}).items():
        unknown = sorted(set(spec) - PARAMETER_KEYS)
        if unknown:
            raise CycleTableError(f"{where}: cycle {cycle}: parameter {parameter}: unknown key {', '.join(unknown)}; "
                                  f"accepted keys: {', '.join(sorted(PARAMETER_KEYS))}")
