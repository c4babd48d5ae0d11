"""Batch runs: worker processes, input order, a crashing worker, globs, excludes, statistics."""

from __future__ import annotations

import gc
import json
import os
import pickle
import shutil
import threading
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from tests.conftest import REPO
from xodrlint.api import default_registry
from xodrlint.cli import app
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import FileReport
from xodrlint.runners import batch
from xodrlint.runners.batch import (
    MAX_FILES_PER_MESSAGE,
    SHARE_PER_MESSAGE,
    Task,
    lint_in_worker,
    lint_tasks,
    schedule,
)

CASES = sorted(REPO.glob("rules/[A-Z]*/*.xodr"))[:60]


def run(*args: str | Path) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


def _copy_cases(target: Path) -> Path:
    for index, case in enumerate(CASES):
        folder = target / f"group{index % 3}"
        folder.mkdir(parents=True, exist_ok=True)
        shutil.copy(case, folder / f"{index:03}-{case.parent.name}-{case.name}")
    return target


@pytest.fixture(params=["forked", "executor"])
def pool_kind(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> str:
    """Both ways of running workers: forked by xodrlint, or the portable executor."""
    monkeypatch.setattr(batch, "FORK_WORKERS", request.param == "forked")
    return str(request.param)


def test_output_is_identical_whatever_the_number_of_jobs(tmp_path: Path, pool_kind: str) -> None:
    maps = _copy_cases(tmp_path / "maps")
    one = run("check", "-f", "json", "-j", "1", maps)
    two = run("check", "-f", "json", "-j", "2", maps)
    assert one.exit_code == two.exit_code == 1
    assert one.stdout == two.stdout
    assert len(json.loads(one.stdout)["files"]) == len(CASES)
    # the workers' findings carry the column of their element's start tag too
    placed = [f for f in json.loads(two.stdout)["findings"] if f["xpath"] != "/"]
    assert placed and all(isinstance(f["column"], int) for f in placed)
    assert one.stderr == two.stderr == ""  # no progress bar when stderr is not a terminal


def crash_on_marked_files(task: Task) -> FileReport:
    """A worker that dies (as a segfault in a C library would) on files named *crash*."""
    if "crash" in task.display:
        os._exit(70)
    return lint_in_worker(task)


def test_a_file_that_kills_its_worker_is_an_error_and_the_rest_go_on(
    tmp_path: Path, pool_kind: str
) -> None:
    paths = []
    for index in range(8):
        name = "crash.xodr" if index == 3 else f"map{index}.xodr"
        shutil.copy(REPO / "examples" / "broken.xodr", tmp_path / name)
        paths.append(tmp_path / name)
    linter = Linter(default_registry(), LintOptions())
    tasks = [Task(path, path.name) for path in paths]
    reports = lint_tasks(linter, tasks, 2, worker=crash_on_marked_files)
    assert [r.path for r in reports] == [p.name for p in paths]
    assert reports[3].error == "crash.xodr: the worker linting it crashed"
    assert all(len(r.findings) == 6 and r.error is None for i, r in enumerate(reports) if i != 3)


def test_globs_and_excludes(tmp_path: Path) -> None:
    maps = _copy_cases(tmp_path / "maps")
    pattern = f"{maps}/**/*-PT00*.xodr"
    everything = json.loads(run("check", "-f", "json", pattern).stdout)["files"]
    assert everything and all("-PT00" in Path(f["path"]).name for f in everything)
    assert all(f["error"] is None for f in everything)
    kept = json.loads(run("check", "-f", "json", pattern, "--exclude", "group1/").stdout)["files"]
    assert kept and all("/group1/" not in f["path"] for f in kept)
    assert len(kept) < len(everything)
    nothing = run("check", f"{maps}/**/*.nomatch")
    assert nothing.exit_code == 2 and "no file matches" in nothing.stderr


def test_statistics_counts_per_rule() -> None:
    out = run("check", "--statistics", REPO / "examples" / "broken.xodr").stdout
    assert out.splitlines() == [
        "     3  XS006  [error]   schema-violation",
        "     1  RL003  [error]   rail-lane-too-narrow",
        "     1  ST004  [error]   segment-s-out-of-range",
        "     1  SW006  [warning] side-track-not-at-end",
    ]


class _Terminal:
    def isatty(self) -> bool:
        return True

    def write(self, text: str) -> int:
        return len(text)

    def flush(self) -> None:
        pass


def test_progress_bar_only_on_a_terminal_and_for_a_batch(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import sys

    from xodrlint.runners.batch import MIN_FILES_FOR_PROGRESS, _Progress

    monkeypatch.delenv("CI", raising=False)
    monkeypatch.delenv("TERM", raising=False)
    assert _Progress(MIN_FILES_FOR_PROGRESS, enabled=True)._bar is None  # stderr is a pipe
    monkeypatch.setattr(sys, "stderr", _Terminal())
    assert _Progress(MIN_FILES_FOR_PROGRESS, enabled=True)._bar is not None
    assert _Progress(MIN_FILES_FOR_PROGRESS - 1, enabled=True)._bar is None
    assert _Progress(MIN_FILES_FOR_PROGRESS, enabled=False)._bar is None


def test_workers_start_with_the_parents_objects_frozen(monkeypatch: pytest.MonkeyPatch) -> None:
    # a worker's collector would otherwise walk, and copy, every page it inherited
    tasks = [Task(REPO / "examples" / "clean.xodr", f"clean-{n}") for n in range(6)]
    linter = Linter(default_registry(), LintOptions())
    reports = lint_tasks(linter, tasks, 2, worker=_counting_worker)
    assert [r.path for r in reports] == [t.display for t in tasks]
    assert all(int(r.error or 0) > 0 for r in reports)
    assert gc.get_freeze_count() == 0  # the parent's collector is whole again


def _counting_worker(task: Task) -> FileReport:
    # runs in a forked worker: report how many objects it inherited frozen
    return FileReport(task.display, error=str(gc.get_freeze_count()))


def test_reports_and_options_cross_process_boundaries() -> None:
    # workers send reports back and spawned workers get the options: all must pickle,
    # defaults included
    for value in (FileReport("a.xodr", error="gone"), LintOptions()):
        assert pickle.loads(pickle.dumps(value)) == value


def test_workers_get_the_largest_files_first_in_shrinking_messages() -> None:
    indexes = list(range(10, 210))
    sizes = [1000 + (i * 37) % 500 for i in range(200)]
    sizes[150] = 10**8  # a city map late in the input
    chunks = schedule(indexes, sizes, 2)
    assert sorted(i for chunk in chunks for i in chunk) == indexes  # each file once
    assert chunks[0][0] == 160  # the city map is handed out first
    handed_out = [sizes[i - 10] for chunk in chunks for i in chunk]
    assert handed_out == sorted(handed_out, reverse=True)
    lengths = [len(chunk) for chunk in chunks]
    assert lengths == sorted(lengths, reverse=True)
    assert lengths[0] == 200 // (2 * SHARE_PER_MESSAGE)
    assert lengths[-4:] == [1, 1, 1, 1]  # the last files go out one by one


def test_no_message_holds_more_than_its_share_of_files() -> None:
    # a parent holds a message's reports until it is whole, and a streaming run writes
    # nothing of it before: the first message of a large run must not be huge
    chunks = schedule(range(100_000), [1000] * 100_000, 2)
    assert max(len(chunk) for chunk in chunks) == MAX_FILES_PER_MESSAGE
    assert sorted(i for chunk in chunks for i in chunk) == list(range(100_000))
    lengths = [len(chunk) for chunk in schedule(range(40), [1] * 40, 1, most=3)]
    assert lengths[:3] == [3, 3, 3] and lengths[-4:] == [1, 1, 1, 1] and sum(lengths) == 40


def test_equal_sizes_keep_input_order_and_one_file_is_one_message() -> None:
    assert schedule([4, 5, 6], [7, 7, 7], 4) == [[4], [5], [6]]
    assert schedule([], [], 2) == []


def test_a_process_running_threads_gets_fresh_workers_not_forks(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from xodrlint.concurrency import forkpool

    def no_fork(*_: object) -> list[int]:
        raise AssertionError("forked a process that runs threads")

    monkeypatch.setattr(forkpool, "stream_pieces", no_fork)
    paths = []
    for index in range(6):
        paths.append(tmp_path / f"map{index}.xodr")
        shutil.copy(REPO / "examples" / "broken.xodr", paths[-1])
    release = threading.Event()
    other = threading.Thread(target=release.wait)
    other.start()
    try:
        linter = Linter(default_registry(), LintOptions())
        reports = lint_tasks(linter, [Task(p, p.name) for p in paths], 2)
    finally:
        release.set()
        other.join()
    assert [len(r.findings) for r in reports] == [6] * 6


def test_batch_workers_keep_their_work_in_one_thread(monkeypatch: pytest.MonkeyPatch) -> None:
    # every core already lints a file of its own: a validation thread per file only adds
    # switches (-j 2 on 200 small maps: 0.30 s with threads, 0.27 s without)
    from xodrlint.concurrency import background
    from xodrlint.runners import batch

    monkeypatch.setenv(background.ENV, "1")  # restored afterwards
    seen: list[bool] = []

    def worker(task: object) -> FileReport:
        seen.append(background.threads_allowed())
        return FileReport("x")

    batch._lint_chunk(worker, [object(), object()])  # type: ignore[list-item]
    assert seen == [False, False]


@pytest.mark.parametrize("jobs", [1, 2])
def test_a_file_that_breaks_the_linter_is_its_internal_error_and_the_rest_go_on(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, jobs: int
) -> None:
    real = Linter.lint_path

    def failing(linter: Linter, path: Path, *args: object, **named: object) -> FileReport:
        if path.name == "crash.xodr":
            raise RuntimeError("simulated failure")
        return real(linter, path, *args, **named)  # type: ignore[arg-type]

    if jobs > 1 and not batch._can_fork_workers():
        pytest.skip("this process runs threads (a Dask test's): its workers are not forks of it")
    monkeypatch.setattr(Linter, "lint_path", failing)
    paths = []
    for index in range(6):
        name = "crash.xodr" if index == 2 else f"map{index}.xodr"
        shutil.copy(REPO / "examples" / "broken.xodr", tmp_path / name)
        paths.append(tmp_path / name)
    tasks = [Task(path, path.name) for path in paths]
    reports = lint_tasks(Linter(default_registry(), LintOptions()), tasks, jobs)
    assert reports[2] == FileReport(
        "crash.xodr",
        internal_errors=("linting crash.xodr failed: RuntimeError('simulated failure')",),
    )
    assert all(len(r.findings) == 6 for i, r in enumerate(reports) if i != 2)
