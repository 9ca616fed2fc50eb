"""Running ``ncverify check`` on an editor's buffer, away from the server's event loop.

Each analysis runs in a worker process: the server keeps answering hover and other requests
while a long program is checked, and an analysis made stale by a newer version of the
document is stopped by ending its worker, not left to finish.
"""
from __future__ import annotations

import asyncio
import multiprocessing
import os
import traceback
from dataclasses import dataclass
from pathlib import Path

from ..api import FileResult, check_source, detect_dialect, project_for
from ..detect import Detection
from ..project import ConfigError
from ..settings import Settings
from ..source import ProgramSource

@dataclass(frozen=True)
class EditorSettings:
    """What the editor may set (``initializationOptions`` and the ``ncverify`` section of
    ``workspace/configuration``); ``None`` leaves the project file or the default in force."""

    dialect: str | None = None
    profile: str | None = None
    machine: str | None = None
    config: str | None = None
    disabled_rules: tuple[str, ...] = ()
    solver_timeout_s: float | None = None
    subprogram_path: tuple[str, ...] = ()
    debounce_ms: int = 30

    @classmethod
    def from_json(cls, data) -> "EditorSettings":
        """Read the editor's JSON leniently: unknown keys and values of the wrong type are
        ignored (a bad value in an editor's settings must not stop the server)."""
        if not isinstance(data, dict):
            return cls()
        data = data.get("ncverify", data) if isinstance(data.get("ncverify"), dict) else data

        def text(key, allowed=None):
            value = data.get(key)
            if isinstance(value, str) and value and (allowed is None or value in allowed):
                return value
            return None

        def texts(key):
            value = data.get(key)
            return tuple(item for item in value if isinstance(item, str)) if isinstance(value, list) else ()

        timeout = data.get("solverTimeout")
        debounce = data.get("debounceMs")
        return cls(
            dialect=text("dialect", {"iso", "heidenhain", "sinumerik", "fagor"}),
            profile=text("profile"),
            machine=text("machine", {"mill", "lathe"}),
            config=text("projectFile"),
            disabled_rules=texts("disabledRules"),
            solver_timeout_s=float(timeout) if isinstance(timeout, (int, float)) and timeout > 0 else None,
            subprogram_path=texts("subprogramPath"),
            debounce_ms=int(debounce) if isinstance(debounce, int) and 0 <= debounce <= 5000 else 30,
        )

    def settings(self) -> Settings:
        """The check's settings: what the editor states wins over the project file, which
        wins over the defaults (the editor's values are marked explicit, like CLI flags)."""
        values = {
            "dialect": self.dialect, "profile": self.profile, "machine": self.machine,
            "config": Path(self.config) if self.config else None,
            "disabled_rules": frozenset(self.disabled_rules),
            "subprogram_path": tuple(Path(folder) for folder in self.subprogram_path),
        }
        if self.solver_timeout_s is not None:
            values["solver_timeout_s"] = self.solver_timeout_s
        explicit = {"dialect", "profile", "machine"} & {key for key, value in values.items() if value is not None}
        if self.solver_timeout_s is not None:
            explicit.add("solver_timeout_s")
        if self.subprogram_path:
            explicit.add("subprogram_path")
        return Settings(**values, explicit=frozenset(explicit), record_values=True)


def analyse(text: str, path: Path | None, name: str, settings: Settings,
            detection: Detection | None = None) -> tuple[FileResult | None, str | None, Detection | None]:
    """Check one buffer as ``ncverify check`` checks the file: same settings, same project
    file. ``detection``: the dialect settled when the document was opened or saved (detection
    reads the first 64 KiB and costs more than checking a few thousand lines, so it is not
    repeated on every keystroke). Returns the result or a problem, and the detection used."""
    try:
        source = ProgramSource(text.encode("utf-8", errors="replace"), name, path)
        detection = detection or detect_dialect(source, settings)
        project = project_for(path, settings)
        return check_source(source, settings, project, detection), None, detection
    except ConfigError as error:
        return None, f"ncverify: error in the project file: {error}", detection
    except RecursionError:
        return None, "ncverify: the program nests too deeply to be analysed", detection
    except Exception as error:  # noqa: BLE001 - an editor session must survive an internal error
        return None, "ncverify: internal error while checking: " + "".join(traceback.format_exception_only(error)).strip(), detection


class Worker:
    """A warm child process that checks one buffer at a time. Started with ``spawn``: a
    forked copy of the server could inherit a lock held by one of its threads."""

    def __init__(self):
        context = multiprocessing.get_context("spawn")
        self.connection, child_end = context.Pipe()
        self.process = context.Process(target=_serve_jobs, args=(child_end,), daemon=True)
        self.process.start()
        child_end.close()

    def ask(self, job: tuple):
        """The answer to one job; ``None`` when the worker was ended meanwhile."""
        try:
            self.connection.send(job)
            return self.connection.recv()
        except (EOFError, OSError):
            self.connection.close()  # only this thread uses the connection while a job runs
            return None

    def end(self) -> None:
        """Stop the process; a thread blocked in :meth:`ask` then sees the pipe break."""
        if self.process.is_alive():
            self.process.kill()


class Runner:
    """Runs analyses in workers, at most one per document at a time: a newer version of a
    document ends the worker still checking the older one, and a fresh worker is kept warm."""

    def __init__(self):
        self._idle: list[Worker] = []
        self._busy: dict[str, Worker] = {}

    def warm_up(self) -> None:
        if not self._idle:
            self._idle.append(Worker())

    async def run(self, key: str, text: str, path: Path | None, name: str, settings: Settings, detection: Detection | None = None):
        self.cancel(key)
        worker = self._idle.pop() if self._idle else Worker()
        self._busy[key] = worker
        answer = await asyncio.get_running_loop().run_in_executor(None, worker.ask, (text, path, name, settings, detection))
        if self._busy.get(key) is worker:
            del self._busy[key]
            if answer is not None and len(self._idle) < 2:
                self._idle.append(worker)
                return answer
            worker.end()
            worker.connection.close()
        return answer

    def cancel(self, key: str) -> None:
        worker = self._busy.pop(key, None)
        if worker is not None:
            worker.end()
            self.warm_up()

    def cancel_all(self) -> None:
        for worker in [*self._busy.values(), *self._idle]:
            worker.end()
        for worker in self._idle:
            worker.connection.close()
        self._busy.clear()
        self._idle.clear()


def _serve_jobs(connection) -> None:
    """The worker's loop. Its stdout is the editor's channel, so anything printed by
    mistake goes to stderr instead."""
    os.dup2(2, 1)
    while True:
        try:
            job = connection.recv()
        except (EOFError, OSError, KeyboardInterrupt):
            return
        connection.send(analyse(*job))
