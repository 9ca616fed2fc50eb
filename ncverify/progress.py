"""The progress bar of a batch on a terminal: files done, blocks per second, files failing
so far. It appears only once a batch has run for a few seconds, and never when standard
error is not a terminal (logs and pipes stay clean)."""
from __future__ import annotations

import time

from .diagnostics import Severity, Status

SHOW_AFTER_S = 2.0


class BatchProgress:
    def __init__(self, total: int, console=None, show_after_s: float = SHOW_AFTER_S):
        if console is None and total > 1:  # one file never shows the bar: no console (rich costs 40 ms to import)
            from rich.console import Console

            console = Console(stderr=True)
        self.console = console
        self.enabled = total > 1 and console.is_terminal
        self.total = total
        self.show_after_s = show_after_s
        self.started = time.monotonic()
        self.done = self.blocks = self.failing = 0
        self._bar = None
        self._task = None

    def advance(self, outcome) -> None:
        self.done += 1
        if outcome.result is not None:
            self.blocks += outcome.result.blocks
        if outcome.error is not None or _fails(outcome.result):
            self.failing += 1
        if not self.enabled:
            return
        elapsed = time.monotonic() - self.started
        if self._bar is None and elapsed >= self.show_after_s and self.done < self.total:
            self._start()
        if self._bar is not None:
            rate = self.blocks / elapsed if elapsed > 0 else 0.0
            self._bar.update(self._task, completed=self.done, rate=f"{rate:,.0f} blocks/s", failing=self.failing)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.stop()
            self._bar = None

    def _start(self) -> None:
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

        self._bar = Progress(TextColumn("checking"), BarColumn(), MofNCompleteColumn(), TextColumn("files"),
                             TextColumn("{task.fields[rate]}"), TextColumn("[red]{task.fields[failing]} failing"),
                             TimeElapsedColumn(), TimeRemainingColumn(), console=self.console, transient=True)
        self._task = self._bar.add_task("check", total=self.total, rate="", failing=0)
        self._bar.start()


def _fails(result) -> bool:
    """A violated error or warning: what a reader of the bar calls failing."""
    return result is not None and any(d.status is Status.VIOLATED and d.severity is not Severity.INFO for d in result.diagnostics)
