"""Faults for the Dask tests, planted in the worker processes through worker plugins (a
worker imports this module by name: the tests' folder is on its path, as on theirs)."""

from __future__ import annotations

import os
import signal
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from distributed import WorkerPlugin

from xodrlint.engine.linter import ExternalIgnores, Linter
from xodrlint.findings import FileReport

#: The keys of the engine's tasks (see xodrlint.runners.dask._run).
LINT_KEY = "xodrlint-lint-"

LintPath = Callable[[Linter, Path, str | None, ExternalIgnores], FileReport]


class KillOnce(WorkerPlugin):
    """Kills its worker (as the out-of-memory killer would) when it starts its
    ``after + 1``-th lint task, once in the whole cluster: the first worker to create
    ``marker`` dies, later ones find it there."""

    def __init__(self, marker: str, after: int = 1) -> None:
        self.marker = marker
        self.after = after
        self.started = 0

    def transition(self, key: Any, start: str, finish: str, **kwargs: Any) -> None:
        if finish != "executing" or not str(key).startswith(LINT_KEY):
            return
        self.started += 1
        if self.started <= self.after:
            return
        try:
            os.close(os.open(self.marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        except FileExistsError:
            return
        os.kill(os.getpid(), signal.SIGKILL)


class PatchedLintPath(WorkerPlugin):
    """Replaces ``Linter.lint_path`` in the worker while registered."""

    def setup(self, worker: object) -> None:
        self.original: LintPath = Linter.lint_path
        original = self.original
        wrap = self.wrap

        def lint_path(
            linter: Linter,
            path: Path,
            display: str | None = None,
            external: ExternalIgnores = (),
            *,
            root: Path | None = None,
        ) -> FileReport:
            wrap(path)
            return original(linter, path, display, external, root=root)

        Linter.lint_path = lint_path  # type: ignore[method-assign, assignment]

    def teardown(self, worker: object) -> None:
        Linter.lint_path = self.original  # type: ignore[method-assign, assignment]

    def wrap(self, path: Path) -> None:
        raise NotImplementedError


class FailOn(PatchedLintPath):
    """The linter itself fails on files whose name holds ``word``: it raises (a bug in
    the engine), or kills its worker (a crash in a C library) with ``kill``."""

    def __init__(self, word: str, *, kill: bool = False) -> None:
        self.word = word
        self.kill = kill

    def wrap(self, path: Path) -> None:
        if self.word in path.name:
            if self.kill:
                os._exit(70)
            raise RuntimeError("simulated failure")


class Slow(PatchedLintPath):
    """Each file takes ``seconds`` longer: a run long enough to interrupt."""

    def __init__(self, seconds: float) -> None:
        self.seconds = seconds

    def wrap(self, path: Path) -> None:
        time.sleep(self.seconds)


class CountLinters(WorkerPlugin):
    """Counts the linters built in the worker while registered (``linters_built``)."""

    def setup(self, worker: object) -> None:
        self.original = Linter.__init__
        original = self.original
        counted = self

        def counting_init(linter: Linter, *args: Any, **kwargs: Any) -> None:
            counted.built += 1
            original(linter, *args, **kwargs)

        self.built = 0
        Linter.__init__ = counting_init  # type: ignore[method-assign, assignment]

    def teardown(self, worker: object) -> None:
        Linter.__init__ = self.original  # type: ignore[method-assign]


def linters_built(dask_worker: Any) -> int:
    """Run on a worker (``client.run``): the linters built there since counting began."""
    plugin = dask_worker.plugins["count-linters"]
    return int(plugin.built)


class BrokenLinterPlugin(WorkerPlugin):
    """Stands in for the engine's plugin on workers whose xodrlint cannot build a linter
    (not installed there, or another version)."""

    def __init__(self, options: object, rules: object = ()) -> None:
        self.options = options

    def setup(self, worker: object) -> None:
        raise ModuleNotFoundError("No module named 'xodrlint.runners.dask'")
