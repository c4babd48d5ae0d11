"""Validation in a forked child: the same findings as in one process, and a dead child
costs nothing but time."""

from __future__ import annotations

import os

import pytest

from xodrlint.api import default_registry
from xodrlint.engine import Linter, LintOptions
from xodrlint.workers import background

from .conftest import REPO, SHARED_SCHEMAS, needs_shared


def test_a_task_runs_in_a_child_and_its_value_comes_back(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(background, "MIN_BYTES", 0)
    parent = os.getpid()
    pending = background.start(lambda: ("pid", os.getpid()), size=1)
    kind, pid = pending.result()
    assert kind == "pid" and pid != parent  # computed in the child


def test_a_dead_child_means_the_parent_does_the_work(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(background, "MIN_BYTES", 0)
    parent = os.getpid()

    def task() -> int:
        if os.getpid() != parent:
            os._exit(9)  # as a crash or an out-of-memory kill would end it
        return 42

    assert background.start(task, size=1).result() == 42


def test_small_documents_and_the_switch_keep_one_process(monkeypatch: pytest.MonkeyPatch) -> None:
    assert not background.can_fork(background.MIN_BYTES - 1)
    monkeypatch.setenv(background.ENV, "0")
    assert not background.can_fork(background.MIN_BYTES * 10)


@needs_shared
@pytest.mark.parametrize("name", ["broken.xodr", "two-findings.xodr", "clean.xodr"])
def test_forked_validation_gives_the_same_findings(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = REPO / "examples" / name
    linter = Linter(default_registry(), LintOptions(schema=SHARED_SCHEMAS))
    alone = linter.lint_path(path)
    monkeypatch.setattr(background, "MIN_BYTES", 0)
    forked = Linter(default_registry(), LintOptions(schema=SHARED_SCHEMAS)).lint_path(path)
    assert forked.findings == alone.findings
    assert forked.schema == alone.schema


def test_no_fork_while_other_threads_run() -> None:
    import threading

    assert background.can_fork(background.MIN_BYTES)
    release = threading.Event()
    other = threading.Thread(target=release.wait)
    other.start()
    try:
        assert not background.can_fork(background.MIN_BYTES)
    finally:
        release.set()
        other.join()
