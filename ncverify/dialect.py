"""The dialects ncverify knows, and what a dialect hands the pipeline: its frontend and the
tables the interpreter runs with.

:data:`DIALECTS` is the one list of dialects: the command line's ``--dialect`` and
``--machine`` choices, the project file's validation and detection's signatures all follow
it. Every dialect family has one lowering module (``DialectInfo.lowering``) with a function
``setup(settings, detection, project) -> DialectSetup``. The pipeline (``api.py``) finds it
by the detected dialect's name; a dialect without such a module is recognised but reported
as not checked. Nothing else in the pipeline knows which dialect it runs.

The frontend is the object the interpreter asks about text. Its methods:

``blocks(raw, line, path) -> list[ir.Block]``
    The blocks of one logical line. ``raw`` is the line's bytes; when the dialect continues
    blocks over several lines (see ``continues``) it is the lines joined by ``b"\\n"`` and
    ``line`` is the first one's number.
``continues(raw) -> bool`` (optional)
    Does the block on this line go on in the next line (Klartext ``~``)? Without this
    method every line is one logical line.
``is_plain(raw)`` / ``plain_run(buffer, offset, line)``
    The batch fast path for plain motion; a dialect without one answers False / None.
``programs(buffer) -> [(name, offset)]``, ``is_subprogram(buffer, start, end)``,
``tape_marks(buffer)``, ``program_name(number_or_name) -> str``
    Where programs start in a file, which are subprograms, and how a called program is
    named (the name a subprogram library looks for).
``label_offsets(buffer, label)``, ``describe_label(label) -> str``
    Offsets of lines that may carry a label (the interpreter confirms each by reading it),
    and the label as the dialect writes it, for messages.
``variable_scope(name) -> "local" | "global"``, ``system_variable(name, state)`` (optional)
    Which parameters a call gets fresh copies of, and the values of the system variables the
    machine state can answer (None: not a system variable, or one we cannot know).
``program_context(source) -> Context`` (optional)
    What the program itself declares about its context (stock, tools), found before it runs.
``program_extent(buffer, start) -> int`` (optional)
    Where the program starting at ``start`` ends, for a dialect whose subprograms nest inside
    the main code (LinuxCNC ``sub``/``endsub``); without it a program runs to the next header.
``unset_is_vacant(name) -> bool`` (optional)
    Whether a local parameter never set reads as vacant even outside a call (LinuxCNC's named
    parameters); without it such a parameter is free.

A dialect whose operations need run-time code of their own names its run-time module
(``DialectInfo.runtime``, in ``ncverify/interpret/``); :func:`setup_for` hands it to the
interpreter as ``DialectSetup.runtime``. The lowering never imports it. Its optional hooks:

``batch_allowed(state) -> bool``
    Whether a batch may run now, for a dialect whose plain blocks also change state of its
    own (Klartext: an M89 cycle runs at every position); without it, whenever the
    interpreter's own conditions hold.
``after_batch(state, run) -> None``
    Leave the dialect's own state as the batch's lines leave it block by block (Klartext:
    the pole its ``CC`` lines set, the point last reached at feed).
``OPERATIONS: dict``
    The handlers of IR operations the dialect lowers to and the shared interpreter leaves to
    it, by operation type: ``run(runtime, op, block)`` with the
    :class:`~ncverify.interpret.runtime.Runtime` of the path.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from functools import cache

from .context import Context
from .resources import data_dir, read_table


@dataclass(frozen=True)
class DialectInfo:
    """One dialect family: its id (the ``--dialect`` value), the name it is shown by, the
    file extensions its programs usually have, the module that lowers it, and the machine
    types it runs on. Its tables are ``dialects/<id>/*.toml``."""

    id: str
    name: str
    extensions: tuple[str, ...]
    lowering: str
    machines: tuple[str, ...] = ("mill",)
    profiles_table: str | None = None  # dialects/<id>/<file> whose tables are the profiles (ISO)
    runtime: str | None = None  # the module of its run-time hooks, if it has any
    # radius compensation offsets the tool by the radius of its own tool data (Klartext RL/RR:
    # the called tool's R and DR; SINUMERIK G41/G42: the active edge's), not by an offset
    # register's value on the machine (ISO and Fagor D, LinuxCNC's D naming another tool)
    offset_is_tool_radius: bool = False

    def profiles(self) -> list[str]:
        """The profiles a ``--profile`` may name, sorted; none for a dialect without them."""
        if self.profiles_table is None:
            return []
        return list(_profile_names(self.id, self.profiles_table))


@cache  # the command line asks for them each time it builds its parser
def _profile_names(dialect: str, table: str) -> tuple[str, ...]:
    return tuple(sorted(read_table(data_dir("dialects") / dialect / table)))


DIALECTS: dict[str, DialectInfo] = {info.id: info for info in (
    DialectInfo("iso", "ISO family (Mitsubishi E60/M60, Fanuc-style, Haas)", (".nc", ".ngc", ".cnc", ".tap", ".eia", ".iso"),
                "ncverify.lower.iso", ("mill", "lathe"), "profiles.toml"),
    DialectInfo("heidenhain", "HEIDENHAIN TNC 620 Klartext", (".h", ".i"), "ncverify.lower.heidenhain",
                runtime="ncverify.interpret.heidenhain.runtime", offset_is_tool_radius=True),
    DialectInfo("sinumerik", "SINUMERIK 840D", (".mpf", ".spf"), "ncverify.lower.sinumerik", ("mill", "lathe"), offset_is_tool_radius=True),
    DialectInfo("fagor", "Fagor 8060/8065", (".pim", ".pit"), "ncverify.lower.fagor", runtime="ncverify.interpret.fagor"),
    DialectInfo("linuxcnc", "LinuxCNC (RS274NGC)", (".ngc",), "ncverify.lower.linuxcnc", ("mill", "lathe")),
)}
MACHINES = tuple(dict.fromkeys(machine for info in DIALECTS.values() for machine in info.machines))


@dataclass
class DialectSetup:
    """A dialect's frontend and tables for one run."""

    frontend: object
    power_on: dict
    cycle_models: dict
    profile: str | None = None
    machine: str = "mill"
    twins: dict = field(default_factory=dict)  # incremental twin letters (lathe U = incremental X)
    increment: float | None = None  # least input increment of an integer length word (0: whole units; None: no such notion)
    feed_increment: float = 0.0
    limits: dict = field(default_factory=dict)  # dialect limits the rules read (register ranges)
    runtime: object = None  # the dialect's run-time hooks (DialectInfo.runtime), set by setup_for
    arc_tolerance: object = None  # context.ArcTolerance: the control's own arc check, where stated
    lengths_by_set_up: bool = False  # a missing length offset matters only where the tool table holds lengths (LinuxCNC)


def setup_for(dialect: str, settings, detection, project: Context) -> DialectSetup | None:
    """The dialect's setup, or None when no lowering module exists for it yet."""
    info = DIALECTS.get(dialect)
    if info is None:
        return None
    setup = importlib.import_module(info.lowering).setup(settings, detection, project)
    if info.runtime is not None:
        setup.runtime = importlib.import_module(info.runtime)
    return setup


def logical_lines(source, offset: int, frontend):
    """``source.lines_from(offset)``, with the lines of a block the dialect continues over
    several lines (``frontend.continues``) joined by ``b"\\n"`` into one item."""
    lines = source.lines_from(offset)
    continues = getattr(frontend, "continues", None)
    if continues is None:
        return lines
    return _joined(lines, continues)


def _joined(lines, continues):
    for line_number, offset, next_offset, raw in lines:
        parts = [raw]
        while continues(parts[-1]):
            following = next(lines, None)
            if following is None:
                break
            parts.append(following[3])
            next_offset = following[2]
        yield line_number, offset, next_offset, b"\n".join(parts) if len(parts) > 1 else raw
