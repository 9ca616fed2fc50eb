"""Batches over program libraries: many files checked in worker processes (or on a Dask
cluster), with a content-keyed result cache, the outcomes returned in input order.

:func:`check_path` is the unit of work: one file in, a :class:`FileOutcome` out. It runs
in the calling process, in a worker process or on a Dask worker alike, which is what keeps
the results of ``--jobs 1``, ``--jobs N`` and ``--dask`` identical.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Iterator

from .api import FileResult, InputError
from .cache import ResultCache, folder_for
from .dependencies import ReadLog, recording
from .library import shared_indexes
from .project import ConfigError
from .pool import WorkerFailure, run_in_workers
from .settings import Settings
from .watchdog import Budget, check_within_budget, is_not_checked


@dataclass
class FileOutcome:
    """One input's outcome: a result, or ``error`` (the file could not be checked: exit 2)."""

    path: str
    explicit: bool = False  # named on the command line, not found in a folder
    result: FileResult | None = None
    error: str | None = None
    log: ReadLog = field(default_factory=ReadLog)  # what the check read, for the cache
    cached: bool = False
    text: str | None = None  # the program's text when it came from standard input
    project_file_error: bool = False  # ``error`` is a broken project file: the whole run stops (exit 2)

    def to_json(self) -> dict:
        """The JSON report's file entry, or ``{"path", "error"}``."""
        return self.result.to_json() if self.result is not None else {"path": self.path, "error": self.error}


def check_path(task: tuple[Path, Settings]) -> FileOutcome:
    """Check one file; a file that cannot be read is an outcome with ``error``."""
    path, settings = task
    with recording() as log, shared_indexes():
        try:
            result = check_within_budget(path, settings, Budget.of(settings))
        except InputError as error:
            return FileOutcome(str(path), error=str(error), log=log)
        except ConfigError as error:
            return FileOutcome(str(path), error=str(error), log=log, project_file_error=True)
    return FileOutcome(str(path), result=result, log=log)


def default_jobs() -> int:
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


Dispatch = Callable[[list[tuple[Path, Settings]]], Iterator[tuple[int, object]]]


def local_dispatch(jobs: int, timeout: float | None = None) -> Dispatch:
    """Tasks in this process (one job, or one task), else in ``jobs`` worker processes."""

    def dispatch(tasks):
        if jobs <= 1 or len(tasks) <= 1:
            return ((index, check_path(task)) for index, task in enumerate(tasks))
        return run_in_workers(check_path, tasks, jobs, timeout)

    return dispatch


def run_batch(inputs: Iterable[tuple[Path, bool]], settings: Settings, dispatch: Dispatch, use_cache: bool = True,
              on_outcome: Callable[[FileOutcome], None] | None = None) -> list[FileOutcome]:
    """Check every ``(path, explicit)`` input; return the outcomes in input order and hand
    each to ``on_outcome`` as soon as it is known (cache hits first)."""
    inputs = list(inputs)
    outcomes: list[FileOutcome | None] = [None] * len(inputs)
    caches: dict[int, tuple[ResultCache, str]] = {}
    missing: list[int] = []
    for index, (path, explicit) in enumerate(inputs):
        with shared_indexes():
            cached = _lookup(path, settings) if use_cache else None
        if cached is not None:
            caches[index] = cached[:2]
            if cached[2] is not None:
                outcomes[index] = FileOutcome(str(path), explicit, cached[2], cached=True)
                _announce(outcomes[index], on_outcome)
                continue
        missing.append(index)
    tasks = [(inputs[index][0], settings) for index in missing]
    for position, value in dispatch(tasks):
        index = missing[position]
        path, explicit = inputs[index]
        outcome = _outcome(value, path)
        outcome.explicit = explicit
        outcomes[index] = outcome
        if index in caches and outcome.result is not None and not is_not_checked(outcome.result):
            cache, key = caches[index]
            cache.store(key, outcome.result, outcome.log)
        _announce(outcome, on_outcome)
    return outcomes


def _lookup(path: Path, settings: Settings) -> tuple[ResultCache, str, FileResult | None] | None:
    if not path.is_file():
        return None  # a FIFO or other special file: reading it to hash it could block forever (the check skips it)
    try:
        cache = ResultCache(folder_for(path, settings))
    except ConfigError:  # the check reports it
        return None
    key = cache.key(path, settings)
    if key is None:
        return None
    return cache, key, cache.load(key, settings)


def _outcome(value, path: Path) -> FileOutcome:
    if isinstance(value, FileOutcome):
        return value
    reason = value.reason if isinstance(value, WorkerFailure) else str(value)
    return FileOutcome(str(path), error=f"{path}: not checked: {reason}")


def _announce(outcome: FileOutcome, on_outcome) -> None:
    if on_outcome is not None:
        on_outcome(outcome)
