"""The server's linting process: the editor's buffers are linted in a process of their own,
which the server can stop.

A lint in a thread of the server could not be stopped: Python's rule clock (``SIGALRM``)
fires only in a main thread, and a rule that runs away (a backtracking pattern from a
workspace's configuration) held a core and the interpreter's lock for ever, so that no
later file got diagnostics and the server had to be killed. Here the lint runs in the
worker's main thread, where each rule has its time limit (``rule-timeout``, an internal
error of that rule on that file); and a lint that does not end within the server's own
deadline (a rule that blocks the clock's signal, a stage in C that never returns) has
its process killed. The file then gets one diagnostic saying so, the next lint starts
a fresh process, and the server answers all the while.

Requests and answers are pickled over a pipe: a buffer's bytes and path in, the
:class:`~xodrlint.findings.FileReport` and the configuration's problem out. The worker
chooses each file's configuration itself (:class:`~xodrlint.server.folders.Folders`),
so it compiles schemas and keeps linters warm across lints, as the server did.
"""

from __future__ import annotations

import multiprocessing
import os
from multiprocessing.connection import Connection
from multiprocessing.process import BaseProcess
from pathlib import Path
from typing import Final, NamedTuple

from xodrlint.findings import FileReport
from xodrlint.server.folders import Folders

#: Seconds one lint may take, all stages and rules together, before its process is
#: stopped: far beyond a 20 MB map's few seconds, and a rule's own limit (60 s).
DEFAULT_DEADLINE: Final = 120.0


#: Seconds a linting process may take to start (import, load the rule packs).
STARTUP_SECONDS: Final = 60.0
#: What a linting process says once it can take requests.
READY: Final = "ready"


class Outcome(NamedTuple):
    """What a lint gave: its report, or why there is none (``failure``); and why the
    file's configuration could not be used as it is (``problem``), if it could not."""

    report: FileReport | None
    problem: str | None = None
    failure: str | None = None


class LintWorker:
    """One linting process, started on the first lint and again after one was stopped."""

    def __init__(self, *, trusted: bool = True, deadline: float = DEFAULT_DEADLINE) -> None:
        self.trusted = trusted
        self.deadline = deadline
        self._process: BaseProcess | None = None
        self._connection: Connection | None = None
        self._closed = False

    def lint(self, path: Path, data: bytes) -> Outcome:
        """Lint ``data`` as the file ``path``, within the deadline."""
        answer = self._ask(("lint", str(path), data), f"linting {path}")
        if isinstance(answer, Outcome):
            return answer
        return Outcome(None, failure=answer)

    def fix(self, path: Path, data: bytes) -> bytes | str:
        """``data`` with every safe fix made as ``check --fix`` makes them, within the
        deadline; or why not."""
        answer = self._ask(("fix", str(path), data), f"fixing {path}")
        if isinstance(answer, Outcome):
            if answer.report is not None and answer.report.fixed_source is not None:
                return answer.report.fixed_source
            return answer.failure or "no fix was made"
        return answer or "no fix was made"

    def forget(self) -> None:
        """A configuration file changed: the worker chooses every linter again."""
        if self._process is not None:
            self._ask(("forget",), "reloading the configuration")

    def close(self) -> None:
        """Stop the process for good (the server ends). Called from any thread, also while
        a lint waits on the process in another: the process is killed (it keeps nothing
        worth a word), that wait ends at once, and no lint starts another."""
        self._closed = True
        process = self._process
        if process is not None and process.is_alive():
            process.kill()
            process.join(timeout=5)

    def _ask(self, request: tuple[object, ...], what: str) -> Outcome | str | None:
        """The worker's answer to ``request``, or why there is none (a string)."""
        try:
            connection = self._started()
        except OSError as error:
            return f"{error}: {what} is left undone"
        try:
            connection.send(request)
            if not connection.poll(self.deadline):
                self._stop()
                return (
                    f"{what} took longer than {self.deadline:g} s and was stopped (a rule or a "
                    "stage that does not end); the next lint starts afresh"
                )
            answer: Outcome | None = connection.recv()
        except (EOFError, OSError):
            code = self._stop()
            return f"the linting process ended while {what} (exit code {code}); it is restarted"
        return answer

    def _started(self) -> Connection:
        if self._closed:
            raise OSError("the server is shutting down")
        if self._connection is not None:
            return self._connection
        # spawned, not forked: the server has threads (the event loop's, the lint pool's)
        context = multiprocessing.get_context("spawn")
        ours, theirs = context.Pipe()
        process = context.Process(
            target=serve_lints, args=(theirs, self.trusted), name="xodrlint-lint", daemon=True
        )
        process.start()
        theirs.close()
        self._process, self._connection = process, ours
        # the deadline is the lint's: a start-up (imports, the rule packs) on a busy
        # machine is not counted against it, though it has a limit of its own
        try:
            ready = ours.recv() if ours.poll(STARTUP_SECONDS) else None
        except (EOFError, OSError):  # it ended before it was ready
            ready = None
        if ready != READY:
            ended = not process.is_alive()
            code = self._stop()
            why = f"ended at start (exit code {code})" if ended else "did not start in time"
            raise OSError(f"the linting process {why}")
        return ours

    def _stop(self) -> int | None:
        """Kill the process; its exit code."""
        process, connection = self._process, self._connection
        self._process = self._connection = None
        if connection is not None:
            connection.close()
        if process is None:
            return None
        if process.is_alive():
            process.kill()
        process.join()
        return process.exitcode


def serve_lints(connection: Connection, trusted: bool) -> None:
    """The worker's loop: answer each request until ``stop`` or the server's end."""
    # the server's stdout is the protocol's channel: nothing of this process may reach it
    os.dup2(2, 1)
    from xodrlint.api import default_registry

    folders = Folders(default_registry(), trusted=trusted)
    connection.send(READY)
    while True:
        try:
            request = connection.recv()
        except (EOFError, OSError, KeyboardInterrupt):
            return
        kind = request[0]
        if kind == "stop":
            return
        if kind == "forget":
            folders.forget()
            connection.send(None)
            continue
        _, name, data = request
        if kind == "fix":
            connection.send(_fix(folders, Path(name), data))
            continue
        connection.send(_lint(folders, Path(name), data))


def _fix(folders: Folders, path: Path, data: bytes) -> Outcome:
    """The safe fixes of ``data`` made: the fixed bytes as the report's ``fixed_source``."""
    try:
        choice = folders.linter_for(path)
        if choice.excluded(path):
            return Outcome(FileReport(str(path), fixed_source=data), choice.problem)
        fixed, report = choice.linter.fixed_source(data, str(path), path)
    except Exception as error:  # as for a lint: said, not swallowed
        return Outcome(None, failure=f"cannot fix {path}: {error}")
    return Outcome(report._replace(fixed_source=fixed), choice.problem)


def _lint(folders: Folders, path: Path, data: bytes) -> Outcome:
    try:
        choice = folders.linter_for(path)
        if choice.excluded(path):
            return Outcome(FileReport(str(path)), choice.problem)
        report = choice.linter.lint_bytes(data, str(path), choice.external(path), location=path)
    except Exception as error:  # a schema that does not load, a bug: said, not swallowed
        return Outcome(None, failure=f"cannot lint {path}: {error}")
    return Outcome(report, choice.problem)
