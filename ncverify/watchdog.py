"""Every file's analysis under a budget, and a failure of the analysis as its own outcome.

A file whose analysis runs past its wall-clock budget (``--file-timeout``) or its memory
budget (``--file-memory``), or ends in an exception inside ncverify, is reported as *not
checked* with the reason, and the batch goes on with the next file. The caller (the CLI,
or a pool of worker processes) turns such a result into exit code 2: a crash must never
read as "the program has findings" (1) or as "nothing found" (0).

:func:`check_within_budget` checks one file; a worker process calls it once per file after
:func:`memory_cap` has capped the process once.
"""
from __future__ import annotations

import resource
import signal
import threading
import traceback
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from .api import FileResult, InputError, check_file
from .project import ConfigError
from .settings import Settings

INTERNAL_ERROR = "internal error"


@dataclass(frozen=True)
class Budget:
    """The time and memory one file's analysis may take."""

    seconds: float = Settings.file_timeout_s  # wall clock per file
    memory_bytes: int = Settings.file_memory_bytes  # data memory of the process while it checks the file

    @classmethod
    def of(cls, settings: Settings) -> "Budget":
        return cls(settings.file_timeout_s, settings.file_memory_bytes)


class _OverTime(BaseException):
    """Raised by the timer inside whatever the analysis is doing. A BaseException, so that
    no ``except Exception`` on the way swallows it."""


def check_within_budget(path: str | Path, settings: Settings, budget: Budget) -> FileResult:
    """``check_file`` under ``budget``. Raises only what ``check_file`` documents for
    unusable input (:class:`InputError`, :class:`ConfigError`); any other failure is a
    result marked not checked (:func:`is_not_checked`)."""
    return run_within_budget(str(path), lambda: check_file(path, settings), budget)


def run_within_budget(name: str, check: Callable[[], FileResult], budget: Budget) -> FileResult:
    """Run ``check`` (one file's analysis, ``name`` for the report) under ``budget``."""
    try:
        with _deadline(budget.seconds):
            return check()
    except (InputError, ConfigError):
        raise
    except _OverTime:
        return not_checked(name, f"the analysis ran past its budget of {budget.seconds:g} s (--file-timeout); nothing in this file was verified")
    except MemoryError:
        return not_checked(name, f"the analysis ran past its memory budget of {budget.memory_bytes >> 20:,} MiB (--file-memory); nothing in this file was verified")
    except Exception as error:  # noqa: BLE001 - every failure (RecursionError too) becomes this file's outcome
        return not_checked(name, f"{INTERNAL_ERROR}: {type(error).__name__}: {error}{_where(error)} (please report it); nothing in this file was verified")


def not_checked(name: str, reason: str) -> FileResult:
    return FileResult(name, None, 0.0, skipped=reason, failed=True)


def is_not_checked(result: FileResult) -> bool:
    """Did the analysis itself fail (internal error, budget) rather than decline the file?"""
    return result.failed


def _where(error: BaseException) -> str:
    frames = traceback.extract_tb(error.__traceback__)
    if not frames:
        return ""
    last = frames[-1]
    return f" at {Path(last.filename).name}:{last.lineno}"


@contextmanager
def _deadline(seconds: float | None):
    """Raise :class:`_OverTime` in this thread after ``seconds``. Timers need the main
    thread (signals); elsewhere (an editor's worker thread) the analysis runs unbounded."""
    if not seconds or threading.current_thread() is not threading.main_thread():
        yield
        return

    def expire(_signal, _frame):
        raise _OverTime

    previous = signal.signal(signal.SIGALRM, expire)
    # then again every second: a raise that lands in a destructor (Z3's __del__) is dropped
    signal.setitimer(signal.ITIMER_REAL, seconds, 1.0)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@contextmanager
def memory_cap(budget: Budget):
    """Cap the process's data memory at the budget while the block runs (files are checked
    one at a time per process, so this is the budget of the file being checked). An
    allocation past it raises ``MemoryError`` in the analysis, which reports the file."""
    soft, hard = resource.getrlimit(resource.RLIMIT_DATA)
    cap = budget.memory_bytes if hard == resource.RLIM_INFINITY else min(budget.memory_bytes, hard)
    resource.setrlimit(resource.RLIMIT_DATA, (cap, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_DATA, (soft, hard))
