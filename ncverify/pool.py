"""Worker processes for batches: one task at a time per worker, so that a worker that
crashes or overruns its time can be blamed on exactly one file and replaced while the
batch goes on.

``concurrent.futures`` cannot do this: a crashed worker breaks the whole executor, and a
running task cannot be stopped. Here each worker has its own pipe; the parent waits on the
pipes and the process sentinels together.
"""
from __future__ import annotations

import time
from collections import deque
from dataclasses import dataclass
from typing import Callable, Iterable, Iterator


@dataclass(frozen=True)
class WorkerFailure:
    """A task that produced no value: its worker died, overran ``timeout`` or raised."""

    reason: str


def run_in_workers(function: Callable, tasks: Iterable, jobs: int, timeout: float | None = None) -> Iterator[tuple[int, object]]:
    """Yield ``(index, function(task))`` for every task, in the order they finish, computed
    in ``jobs`` worker processes; a task whose worker fails yields a :class:`WorkerFailure`.
    ``function`` must be importable by name (it is sent to spawned processes)."""
    import multiprocessing  # here: a run of one file never starts a worker, and this import costs 30 ms
    from multiprocessing.connection import wait

    pending = deque(enumerate(tasks))
    context = multiprocessing.get_context("spawn")
    idle: list[_Worker] = []
    busy: dict[_Worker, int] = {}
    try:
        while pending or busy:
            while pending and len(idle) + len(busy) < jobs:
                idle.append(_Worker(context, function))
            while pending and idle:
                worker = idle.pop()
                index, task = pending.popleft()
                worker.send(index, task)
                busy[worker] = index
            wait([w.connection for w in busy] + [w.process.sentinel for w in busy], timeout=_next_deadline(busy, timeout))
            for worker, index in list(busy.items()):
                outcome = worker.collect(timeout)
                if outcome is None:
                    continue
                del busy[worker]
                yield index, outcome
                if isinstance(outcome, WorkerFailure) and not worker.process.is_alive():
                    worker.close()
                else:
                    idle.append(worker)
    finally:
        for worker in idle + list(busy):
            worker.close()


def _next_deadline(busy: dict, timeout: float | None) -> float | None:
    started = [worker.started for worker in busy if worker.started is not None]
    if timeout is None or not started:
        return None if timeout is None else 0.5
    return max(0.0, min(started) + timeout - time.monotonic()) + 0.01


class _Worker:
    def __init__(self, context, function: Callable):
        self.connection, child = context.Pipe()
        self.process = context.Process(target=_serve, args=(child, function), daemon=True)
        self.process.start()
        child.close()
        self.started: float | None = None

    def send(self, index: int, task) -> None:
        self.started = None  # set when the worker says it began: starting a process is not the task's time
        self.connection.send((index, task))

    def collect(self, timeout: float | None):
        """The finished task's value, a failure, or None while it is still running."""
        while self.connection.poll():
            try:
                kind, value = self.connection.recv()
            except (EOFError, OSError):
                return self._died()
            if kind == "started":
                self.started = time.monotonic()
                continue
            return value if kind == "value" else WorkerFailure(value)
        if not self.process.is_alive():
            return self._died()
        if timeout is not None and self.started is not None and time.monotonic() - self.started > timeout:
            self.process.kill()
            self.process.join()
            return WorkerFailure(f"no result within {timeout:g} s; the worker was stopped")
        return None

    def _died(self) -> WorkerFailure:
        self.process.join()
        return WorkerFailure(f"the worker process stopped unexpectedly (exit code {self.process.exitcode})")

    def close(self) -> None:
        if self.process.is_alive():
            try:
                self.connection.send(None)
            except OSError:
                pass
            self.process.join(timeout=2)
            if self.process.is_alive():
                self.process.kill()
                self.process.join()
        self.connection.close()


def _serve(connection, function: Callable) -> None:
    """A worker's loop: tasks in, values out, until the parent sends None."""
    while True:
        try:
            message = connection.recv()
        except (EOFError, KeyboardInterrupt):
            return
        if message is None:
            return
        index, task = message
        connection.send(("started", index))
        try:
            reply = ("value", function(task))
        except Exception as error:  # the batch goes on; the file is reported as not checked
            reply = ("failure", f"internal error: {type(error).__name__}: {error}")
        connection.send(reply)
