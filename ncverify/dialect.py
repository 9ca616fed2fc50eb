"""What a dialect hands the pipeline: its frontend and the tables the interpreter runs with.

Every dialect family has one lowering module, ``ncverify.lower.<dialect>``, with a function
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
``batch_allowed(state) -> bool`` (optional)
    Whether a batch may run now, for a dialect whose plain blocks also change state of its
    own (Klartext: an M89 cycle runs at every position); without it, whenever the
    interpreter's own conditions hold.
``programs(buffer) -> [(name, offset)]``, ``is_subprogram(buffer, start, end)``,
``tape_marks(buffer)``, ``program_name(number_or_name) -> str``
    Where programs start in a file, which are subprograms, and how a called program is
    named (the name a subprogram library looks for).
``label_offsets(buffer, label)``, ``describe_label(label) -> str``
    Offsets of lines that may carry a label (the interpreter confirms each by reading it),
    and the label as the dialect writes it, for messages.
``variable_scope(name) -> "local" | "global"``, ``system_variable(name, state)``
    Which parameters a call gets fresh copies of, and the values of the system variables the
    machine state can answer (None: not a system variable, or one we cannot know).
``program_context(source) -> Context`` (optional)
    What the program itself declares about its context (stock, tools), found before it runs.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass, field

from .context import Context


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


def setup_for(dialect: str, settings, detection, project: Context) -> DialectSetup | None:
    """The dialect's setup, or None when no lowering module exists for it yet."""
    try:
        module = importlib.import_module(f"ncverify.lower.{dialect}")
    except ModuleNotFoundError as error:
        if error.name != f"ncverify.lower.{dialect}":
            raise
        return None
    return module.setup(settings, detection, project)


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
