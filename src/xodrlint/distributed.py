"""Lint on a Dask cluster from Python, for pipelines that already run one.

- :func:`lint_paths` lints what ``xodrlint check`` would (files, folders, globs) on the
  workers of a :class:`distributed.Client`, with one warm linter per worker, and yields
  each file's :class:`~xodrlint.findings.FileReport` as it completes.
- :func:`lint_partition` lints a partition of paths where it runs: for
  ``dask.bag.from_sequence(paths).map_partitions(lint_partition)``.
- :func:`lint_frame` does the same for a partition of a dataframe of paths, one row per
  finding: for ``ddf.map_partitions(lint_frame, meta=findings_meta())``.

This module needs Dask (``pip install 'xodrlint[dask]'``); ``import xodrlint`` does not
import it. Spark and Ray pipelines call :func:`xodrlint.lint_bytes` in their own
partitions instead (``docs/distributed.md`` shows how).
"""

from __future__ import annotations

import contextlib
import os
import pickle
import threading
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

from distributed import Client

from xodrlint.api import collect_inputs
from xodrlint.config.sizes import DEFAULT_MAX_FILE_SIZE
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import FileReport
from xodrlint.inputs.globs import any_match, glob_matches
from xodrlint.inputs.remote import is_url
from xodrlint.rules.registry import load_registry
from xodrlint.runners.batch import Task, lint_task, task_of
from xodrlint.runners.dask import DEFAULT_RETRIES, lint_on_cluster

if TYPE_CHECKING:
    import pandas as pd

__all__ = [
    "FINDING_COLUMNS",
    "LintOptions",
    "findings_meta",
    "lint_frame",
    "lint_partition",
    "lint_paths",
]

#: The columns of :func:`lint_frame`'s rows and their pandas types; ``error`` is set on
#: the row of a file that could not be linted (the other columns are then empty).
FINDING_COLUMNS: Final = {
    "path": "string",
    "line": "Int64",
    "column": "Int64",
    "code": "string",
    "severity": "string",
    "message": "string",
    "uid": "string",
    "xpath": "string",
    "error": "string",
}
#: Linters a process keeps for :func:`lint_partition`, one per set of options.
KEPT_LINTERS: Final = 4


def lint_paths(
    client: Client,
    paths: Iterable[str],
    *,
    options: LintOptions | None = None,
    exclude: Sequence[str] = (),
    respect_gitignore: bool = True,
    max_file_size: int = DEFAULT_MAX_FILE_SIZE,
    ordered: bool = False,
    retries: int = DEFAULT_RETRIES,
) -> Iterator[FileReport]:
    """Lint ``paths`` (files, folders searched for ``*.xodr``, glob patterns) on the
    workers of ``client``, as ``xodrlint check --scheduler`` does.

    Each report carries its file's path as ``collect_inputs`` spells it (``report.path``),
    not its position: reports come as files complete, or in input order with ``ordered``
    (a report then waits for those before it). A path that cannot be linted (missing, no
    match, too large) is a report with ``error`` set, never an exception; ``exclude``
    holds glob patterns of files to leave out, as ``--exclude`` does.

    The paths are read by the workers: they must see the same files at the same paths.
    A URL (``s3://bucket/maps/**/*.xodr``) is listed here and each object read by the
    worker that lints it, through fsspec (``exclude`` then matches the path in the
    bucket). Close the iterator (or run it to its end) to release the run's work on the
    cluster.
    """
    folder = Path.cwd()
    found = collect_inputs(
        paths,
        (lambda path: any_match(exclude, path, folder)) if exclude else None,
        max_file_size,
        respect_gitignore=respect_gitignore,
        exclude_url=(lambda part: any(glob_matches(g, part) for g in exclude)) if exclude else None,
    )
    inputs = [item for item in found if item.skipped is None and not item.is_stdin]
    tasks = [task_of(item, max_file_size=max_file_size) for item in inputs if item.lintable]
    where = [number for number, item in enumerate(inputs) if item.lintable]
    done: dict[int, FileReport] = {
        number: FileReport(item.display, error=item.error)
        for number, item in enumerate(inputs)
        if not item.lintable
    }
    if not ordered:
        yield from done.values()
        done.clear()
    following = 0
    run = lint_on_cluster(client, options or LintOptions(), tasks, retries=retries)
    with contextlib.closing(run):
        for index, report in run:
            if not ordered:
                yield report
                continue
            done[where[index]] = report
            while following in done:  # the reports before it are all out
                yield done.pop(following)
                following += 1
    yield from (done[number] for number in sorted(done))


_LINTERS: dict[bytes, tuple[Linter, threading.Lock]] = {}
_LINTERS_LOCK = threading.Lock()


def _linter(options: LintOptions) -> tuple[Linter, threading.Lock]:
    """This process's linter for ``options`` (schemas compiled once per process, not per
    partition), and the lock its callers take turns with."""
    key = pickle.dumps(options)  # the options hold mappings: no hash of their own
    with _LINTERS_LOCK:
        found = _LINTERS.get(key)
        if found is None:
            while len(_LINTERS) >= KEPT_LINTERS:
                _LINTERS.pop(next(iter(_LINTERS)))
            found = _LINTERS[key] = (Linter(load_registry(), options), threading.Lock())
    return found


def lint_partition(
    paths: Iterable[str | os.PathLike[str]], options: LintOptions | None = None
) -> list[FileReport]:
    """The reports of ``paths``, in their order, linted in this process (a Dask worker,
    for a bag's ``map_partitions``). Each path is a file's, or an object's URL (read
    here): folders and globs are :func:`lint_paths`'s. A file that cannot be read is a
    report with ``error`` set."""
    linter, lock = _linter(options or LintOptions())
    with lock:
        return [lint_task(linter, _task(os.fspath(path))) for path in paths]


def _task(name: str) -> Task:
    return Task(Path(name), name, url=name if is_url(name) else None)


def findings_meta() -> pd.DataFrame:
    """An empty frame with :data:`FINDING_COLUMNS`: ``meta`` for ``map_partitions``."""
    import pandas as pd

    return pd.DataFrame({name: pd.Series(dtype=kind) for name, kind in FINDING_COLUMNS.items()})


def lint_frame(
    frame: pd.DataFrame, column: str = "path", options: LintOptions | None = None
) -> pd.DataFrame:
    """One row per finding of the files ``frame[column]`` names, and one row with
    ``error`` set per file that could not be linted or whose lint failed (an internal
    error), in the order of ``frame``; columns :data:`FINDING_COLUMNS`."""
    import pandas as pd

    rows: list[tuple[Any, ...]] = []
    for report in lint_partition(frame[column].tolist(), options):
        rows.extend(
            (f.path, f.line, f.column, f.code, str(f.severity), f.message, f.uid, f.xpath, None)
            for f in report.findings
        )
        problems = ([report.error] if report.error else []) + list(report.internal_errors)
        rows.extend((report.path, *[None] * 7, problem) for problem in problems)
    found = pd.DataFrame(rows, columns=list(FINDING_COLUMNS), dtype=object)
    return found.astype(FINDING_COLUMNS)
