"""Batch runs: many files over worker processes, reports in input order whatever the count.

Each worker builds its own :class:`~xodrlint.engine.Linter` once (so each schema is
compiled once per worker, not once per file) and lints the files it is handed. A file
that kills its worker (a crash in a C library, an out-of-memory kill) is retried alone
in a fresh worker; if it kills that one too, it becomes an input error for that file and
the other files go on.
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Callable, Sequence
from concurrent.futures import Future, ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path
from typing import Final

from xodrlint.engine import ExternalIgnores, Linter, LintOptions
from xodrlint.findings import FileReport
from xodrlint.registry import load_registry

#: Below this many files a pool costs more than it saves.
MIN_FILES_FOR_WORKERS: Final = 4
#: A progress bar is worth drawing from this many files on.
MIN_FILES_FOR_PROGRESS: Final = 20


@dataclass(frozen=True, slots=True)
class Task:
    """One file to lint: where it is, how reports name it, what is withheld from outside."""

    path: Path
    display: str
    external: ExternalIgnores = ()


LintTask = Callable[[Task], FileReport]

# One linter per worker process, built by the pool's initializer: the schemas it compiles
# are what makes a worker worth keeping between files. Only worker processes fill it.
_WORKER: dict[str, Linter] = {}


def _start_worker(options: LintOptions) -> None:
    _WORKER["linter"] = Linter(load_registry(), options)


def lint_in_worker(task: Task) -> FileReport:
    return _WORKER["linter"].lint_path(task.path, task.display, task.external)


def default_jobs() -> int:
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1)


def lint_tasks(
    linter: Linter,
    tasks: Sequence[Task],
    jobs: int,
    *,
    progress: bool = False,
    worker: LintTask = lint_in_worker,
) -> list[FileReport]:
    """Reports for ``tasks``, in their order; ``jobs`` > 1 lints in worker processes."""
    if jobs <= 1 or len(tasks) < MIN_FILES_FOR_WORKERS:
        done = []
        with _Progress(len(tasks), enabled=progress) as bar:
            for task in tasks:
                done.append(linter.lint_path(task.path, task.display, task.external))
                bar.advance()
        return done
    reports: dict[int, FileReport] = {}
    pending = _run_pool(linter.options, tasks, range(len(tasks)), jobs, worker, reports, progress)
    for index in pending:  # each file that broke a pool gets a worker of its own
        alone = _run_pool(linter.options, tasks, [index], 1, worker, reports, False)
        if alone:
            task = tasks[index]
            reports[index] = FileReport(
                task.display, error=f"{task.display}: the worker linting it crashed"
            )
    return [reports[index] for index in range(len(tasks))]


def _run_pool(
    options: LintOptions,
    tasks: Sequence[Task],
    indexes: Sequence[int],
    jobs: int,
    worker: LintTask,
    reports: dict[int, FileReport],
    progress: bool,
) -> list[int]:
    """Lint ``indexes`` in a pool; the indexes whose worker died are returned."""
    with ProcessPoolExecutor(
        max_workers=jobs, initializer=_start_worker, initargs=(options,)
    ) as pool:
        futures: dict[Future[FileReport], int] = {
            pool.submit(worker, tasks[index]): index for index in indexes
        }
        with _Progress(len(futures), enabled=progress) as bar:
            for future in as_completed(futures):
                with contextlib.suppress(BrokenProcessPool):  # the caller retries those
                    reports[futures[future]] = future.result()
                bar.advance()
    return [index for index in indexes if index not in reports]


class _Progress:
    """A rich progress bar on stderr, only when stderr is a terminal and the run is long."""

    def __init__(self, total: int, *, enabled: bool) -> None:
        self._bar = None
        if enabled and total >= MIN_FILES_FOR_PROGRESS and sys.stderr.isatty():
            from rich.console import Console
            from rich.progress import Progress

            self._bar = Progress(console=Console(stderr=True), transient=True)
            self._task = self._bar.add_task("linting", total=total)

    def __enter__(self) -> _Progress:
        if self._bar is not None:
            self._bar.start()
        return self

    def __exit__(self, *_: object) -> None:
        if self._bar is not None:
            self._bar.stop()

    def advance(self) -> None:
        if self._bar is not None:
            self._bar.advance(self._task)
