"""Batch runs: many files over worker processes, each report handed on as soon as its
file is done (:func:`stream_tasks`) or all of them in input order (:func:`lint_tasks`).

Each worker builds its own :class:`~xodrlint.engine.linter.Linter` once (so each schema is
compiled once per worker, not once per file) and lints the files it is handed. A file
that kills its worker (a crash in a C library, an out-of-memory kill) is retried alone
in a fresh worker; if it kills that one too, it becomes an input error for that file and
the other files go on.
"""

from __future__ import annotations

import contextlib
import gc
import os
import sys
import time
from collections.abc import Callable, Generator, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Final, NamedTuple, Protocol, cast

from xodrlint.concurrency import background
from xodrlint.config.sizes import DEFAULT_MAX_FILE_SIZE
from xodrlint.engine.linter import ExternalIgnores, Linter, LintOptions
from xodrlint.engine.profiles import Linters
from xodrlint.findings import FileReport
from xodrlint.formatters.output import interactive
from xodrlint.inputs.collect import Input
from xodrlint.rules.registry import load_registry
from xodrlint.validation.sets import SchemaLoadError

if TYPE_CHECKING:
    from concurrent.futures import Future

#: Below this many files a pool costs more than it saves.
MIN_FILES_FOR_WORKERS: Final = 4
#: A progress bar is worth drawing from this many files on,
MIN_FILES_FOR_PROGRESS: Final = 2
#: once the batch has run this long (a shorter one would only flicker).
PROGRESS_AFTER_SECONDS: Final = 1.0


class Task(NamedTuple):
    """One file to lint: where it is, how reports name it, what is withheld from outside.

    A file by URL has ``url`` set: its worker reads it from there (through fsspec), at
    most ``max_file_size`` bytes, and ``path`` (the URL as a path) is never opened;
    ``size`` is the listing's, which schedules it without asking the store again.
    """

    path: Path
    display: str
    external: ExternalIgnores = ()
    url: str | None = None
    size: int | None = None
    max_file_size: int = DEFAULT_MAX_FILE_SIZE
    profile: int = 0
    """The configuration the file falls under (:mod:`xodrlint.config.resolver`): which of the
    run's linters lints it."""
    root: Path | None = None
    """The folder a walk found the file in (:attr:`~xodrlint.inputs.collect.Input.root`)."""


def task_of(
    item: Input,
    external: ExternalIgnores = (),
    max_file_size: int = DEFAULT_MAX_FILE_SIZE,
    profile: int = 0,
) -> Task:
    """The task that lints ``item`` (one that is :attr:`~xodrlint.inputs.collect.Input.lintable`)
    under ``profile``: a file, or an object by URL that its worker reads, at most
    ``max_file_size`` bytes."""
    if item.url is not None:
        return Task(
            Path(item.url),
            item.display,
            external,
            url=item.url,
            size=item.size,
            max_file_size=max_file_size,
            profile=profile,
        )
    if item.path is None:
        raise ValueError(f"{item.display}: not a file an engine lints")
    return Task(item.path, item.display, external, profile=profile, root=item.root)


LintTask = Callable[[Task], FileReport]

#: What an engine yields: each file's report with the index of its task, as files
#: complete (not in input order). The forked pool (:func:`stream_tasks`) and the Dask
#: engine (``runners/dask.py``) have this shape; :func:`in_order` puts one in order.
ReportStream = Iterator[tuple[int, FileReport]]


class Engine(Protocol):
    """What lints a run's tasks: the forked pool, Dask, or one process."""

    def __call__(self, tasks: Sequence[Task], /) -> ReportStream: ...


#: Whether batch runs fork their workers where they can (tests turn it off to run the
#: portable executor).
FORK_WORKERS = True

#: Each message to a worker carries this share of what is left per worker: large
#: messages while much is left (few round trips), single files at the end (no worker
#: waits long for another to finish its last message).
SHARE_PER_MESSAGE: Final = 4
#: and at most this many files: the parent holds a message's reports until the whole
#: message is back, and a streaming run writes none of them before, so an uncapped
#: first message (an eighth of a run's files) held an eighth of the reports and kept
#: the first lines waiting for it. A message costs the forked pool tens of
#: microseconds, 64 small maps tens of milliseconds.
MAX_FILES_PER_MESSAGE: Final = 64

# The linters workers use. Forked workers inherit the parent's (with every schema it has
# compiled so far); spawned ones build their own in the pool's initializer.
_WORKER: dict[str, Linters] = {}


def _start_worker(options: Sequence[LintOptions]) -> None:
    if "linters" not in _WORKER:
        _WORKER["linters"] = Linters(options, registry=load_registry())


def lint_in_worker(task: Task) -> FileReport:
    return lint_task(_WORKER["linters"][task.profile], task)


def lint_task(linter: Linter, task: Task) -> FileReport:
    """``task``'s report, wherever it runs (this process, a forked worker, a Dask worker):
    a local file, or an object by URL, read here (the client only listed it).

    A file that makes the linter itself fail (not one rule: the engine keeps those to
    the rule) is that file's internal error, and the other files go on; a schema set
    that cannot be compiled is the run's error and ends it.
    """
    try:
        if task.url is not None:
            return linter.lint_url(task.url, task.display, task.external, task.max_file_size)
        return linter.lint_path(task.path, task.display, task.external, root=task.root)
    except SchemaLoadError:
        raise
    except Exception as error:
        return FileReport(
            task.display, internal_errors=(f"linting {task.display} failed: {error!r}",)
        )


def _lint_chunk(worker: LintTask, chunk: Sequence[Task]) -> list[FileReport]:
    # in a worker process, beside others that keep every core busy: validating each
    # file in a thread of its own would only add switches (this process's setting only)
    os.environ[background.ENV] = "0"
    return [worker(task) for task in chunk]


def uses_workers(jobs: int, files: int) -> bool:
    """Whether :func:`stream_tasks` (and so :func:`lint_tasks`) lints ``files`` files in
    worker processes."""
    return jobs > 1 and files >= MIN_FILES_FOR_WORKERS


def default_jobs() -> int:
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1)


def lint_tasks(
    linter: Linter | Linters,
    tasks: Sequence[Task],
    jobs: int,
    *,
    progress: bool = False,
    worker: LintTask = lint_in_worker,
) -> list[FileReport]:
    """Reports for ``tasks``, in their order; ``jobs`` > 1 lints in worker processes."""
    return in_order(stream_tasks(linter, tasks, jobs, progress=progress, worker=worker), len(tasks))


def in_order(stream: ReportStream, count: int) -> list[FileReport]:
    """The reports of a stream over ``count`` tasks, in the tasks' order."""
    reports: list[FileReport | None] = [None] * count
    for index, report in stream:
        reports[index] = report
    missing = [index for index, report in enumerate(reports) if report is None]
    if missing:  # an engine that loses a file is a bug, never a shorter report
        raise RuntimeError(f"the engine gave no report for task {missing[0]} of {count}")
    return cast("list[FileReport]", reports)


def stream_tasks(
    linter: Linter | Linters,
    tasks: Sequence[Task],
    jobs: int,
    *,
    progress: bool = False,
    worker: LintTask = lint_in_worker,
) -> Generator[tuple[int, FileReport], None, None]:
    """Each task's report with its index in ``tasks``, as soon as it is done: one by one
    in their order in this process, a message's worth at a time (largest files first)
    from worker processes when ``jobs`` > 1. Each task is linted by the linter of its
    profile (one ``linter`` serves a run of one profile)."""
    linters = linter if isinstance(linter, Linters) else Linters.of(linter)
    if not uses_workers(jobs, len(tasks)):
        with _Progress(len(tasks), enabled=progress) as bar:
            for index, task in enumerate(tasks):
                yield index, lint_task(linters[task.profile], task)
                bar.advance()
        return
    # Compile the first file's schema here, once: forked workers inherit it. An object
    # by URL is read by its worker only (the client lists, never reads).
    if tasks[0].url is None:
        linters[tasks[0].profile].warm_up(tasks[0].path)
    _WORKER["linters"] = linters
    everything = range(len(tasks))
    options = linters.options
    # The collector of a forked worker walks every object it inherited, and touching one
    # copies its memory page: frozen, the parent's objects stay shared while the pool runs.
    gc.freeze()
    try:
        pending = yield from _stream_pool(options, tasks, everything, jobs, worker, progress)
    finally:
        gc.unfreeze()
    for index in pending:  # each file of a chunk that broke a pool gets a worker alone
        alone = yield from _stream_pool(options, tasks, [index], 1, worker, False)
        if alone:
            task = tasks[index]
            yield (
                index,
                FileReport(task.display, error=f"{task.display}: the worker linting it crashed"),
            )


def _stream_pool(
    options: Sequence[LintOptions],
    tasks: Sequence[Task],
    indexes: Sequence[int],
    jobs: int,
    worker: LintTask,
    progress: bool,
) -> Generator[tuple[int, FileReport], None, list[int]]:
    """Lint ``indexes`` in worker processes, yielding each report as its message comes
    back; returns the indexes whose worker died."""
    chunks = schedule(indexes, [task_size(tasks[i]) for i in indexes], jobs)

    def lint_chunk(number: int) -> list[FileReport]:
        return _lint_chunk(worker, [tasks[i] for i in chunks[number]])

    with _Progress(len(indexes), enabled=progress) as bar:
        if _can_fork_workers():
            # imported here: a single-file run (a pre-commit hook) never starts workers
            from xodrlint.concurrency.forkpool import stream_pieces

            messages = stream_pieces(len(chunks), lint_chunk, jobs)
        else:
            messages = _stream_executor(options, chunks, tasks, jobs, worker)
        with contextlib.closing(messages):
            broken = yield from _reports_of(messages, chunks, bar)
    return [index for number in broken for index in chunks[number]]


def _reports_of(
    messages: Generator[tuple[int, list[FileReport]], None, list[int]],
    chunks: list[list[int]],
    bar: _Progress,
) -> Generator[tuple[int, FileReport], None, list[int]]:
    """Each message's reports as ``(task index, report)``; returns the broken messages."""
    while True:
        try:
            number, done = next(messages)
        except StopIteration as finished:
            broken: list[int] = finished.value
            return broken
        bar.advance(len(done))
        yield from zip(chunks[number], done, strict=True)


def _can_fork_workers() -> bool:
    # A fork copies only the thread that calls it, with every lock the others hold at
    # that moment: a process running threads (an application calling the API from one)
    # gets fresh workers from the executor instead.
    return FORK_WORKERS and hasattr(os, "fork") and background.single_threaded()


def _stream_executor(
    options: Sequence[LintOptions],
    chunks: list[list[int]],
    tasks: Sequence[Task],
    jobs: int,
    worker: LintTask,
) -> Generator[tuple[int, list[FileReport]], None, list[int]]:
    """Where workers cannot be forked (Windows, a process with threads): fresh workers,
    each building its own linter. Yields ``(message number, reports)`` as messages come
    back; returns the messages whose pool broke."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool

    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("forkserver" if "forkserver" in methods else "spawn")
    with ProcessPoolExecutor(
        max_workers=jobs, mp_context=context, initializer=_start_worker, initargs=(options,)
    ) as pool:
        futures: dict[Future[list[FileReport]], int] = {
            pool.submit(_lint_chunk, worker, [tasks[i] for i in chunk]): number
            for number, chunk in enumerate(chunks)
        }
        broken = []
        try:
            for future in as_completed(futures):
                try:
                    done = future.result()
                except BrokenProcessPool:  # the caller retries those files one by one
                    broken.append(futures[future])
                    continue
                yield futures[future], done
        finally:  # a caller that stops early leaves no file queued behind it
            for future in futures:
                future.cancel()
    return broken


def schedule(
    indexes: Sequence[int],
    sizes: Sequence[int],
    jobs: int,
    *,
    most: int = MAX_FILES_PER_MESSAGE,
) -> list[list[int]]:
    """``indexes`` in messages for ``jobs`` workers: the largest files first, in messages
    that shrink as the work left does (guided self-scheduling), of at most ``most`` files.

    Largest first, because the last file handed out bounds how long the other workers
    wait: a folder of small maps with one city map at the end would otherwise leave one
    worker linting the city alone.
    """
    order = sorted(range(len(indexes)), key=lambda k: (-sizes[k], k))
    chunks = []
    start = 0
    while start < len(order):
        left = len(order) - start
        size = min(most, max(1, left // (jobs * SHARE_PER_MESSAGE)))
        chunks.append([indexes[k] for k in order[start : start + size]])
        start += size
    return chunks


def task_size(task: Task) -> int:
    """The bytes of ``task``'s file, to schedule the largest first: an object's from its
    listing (no request to the store), a local file's from a ``stat``."""
    if task.url is not None:
        return task.size or 0
    try:
        return task.path.stat().st_size
    except OSError:  # gone since it was found: its worker reports that
        return 0


def progress_wanted() -> bool:
    """Whether stderr is a person's terminal: never a pipe, a file or a CI job's log
    (some CI runners give jobs a terminal, and a bar redrawn there fills the log)."""
    return interactive(sys.stderr) and not os.environ.get("CI")


class _Progress:
    """A rich progress bar on stderr, only on a person's terminal and once the batch has
    run for :data:`PROGRESS_AFTER_SECONDS`.

    It is drawn from a file done on: its refresh thread then starts after the workers
    are forked (a thread's locks, copied by a fork, could be held forever).
    """

    def __init__(self, total: int, *, enabled: bool) -> None:
        self._bar = None
        self._started = False
        self._created = time.monotonic()
        self._done = 0
        if enabled and total >= MIN_FILES_FOR_PROGRESS and progress_wanted():
            from rich.console import Console
            from rich.progress import Progress

            self._bar = Progress(console=Console(stderr=True), transient=True)
            self._task = self._bar.add_task("linting", total=total)

    def __enter__(self) -> _Progress:
        return self

    def __exit__(self, *_: object) -> None:
        if self._bar is not None and self._started:
            self._bar.stop()

    def advance(self, count: int = 1) -> None:
        if self._bar is None:
            return
        self._done += count
        if not self._started:
            if time.monotonic() - self._created < PROGRESS_AFTER_SECONDS:
                return
            self._bar.start()
            self._started = True
            self._bar.update(self._task, completed=self._done)
        else:
            self._bar.advance(self._task, count)
