"""The Python API: the engine without the CLI, for pipelines and notebooks.

``lint_file`` and ``lint_bytes`` lint one input; ``collect_inputs`` expands the paths
``xodrlint check`` takes (files, folders, globs). A pipeline (Dask, Spark, a CI matrix)
can call ``lint_file`` per file (the linter behind it is cached, so schemas compile once
per process); :func:`xodrlint.batch.lint_tasks` spreads many files over processes.
"""

from __future__ import annotations

import errno
import glob
import os
import stat
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from functools import lru_cache
from pathlib import Path
from typing import Final, NamedTuple

from xodrlint.engine import Linter, LintOptions
from xodrlint.findings import FileReport, Severity
from xodrlint.registry import Registry, load_registry

__all__ = ["LintOptions", "Linter", "collect_inputs", "lint_bytes", "lint_file"]

STDIN: Final = "-"
XODR_SUFFIX: Final = ".xodr"


@lru_cache(maxsize=1)
def default_registry() -> Registry:
    return load_registry()


@lru_cache(maxsize=8)
def _linter(
    select: tuple[str, ...],
    ignore: tuple[str, ...],
    schema: Path | None,
    rule_options: tuple[tuple[str, float], ...],
) -> Linter:
    options = LintOptions(
        select=select, ignore=ignore, schema=schema, rule_options=dict(rule_options)
    )
    return Linter(default_registry(), options)


def _linter_for(
    select: Sequence[str],
    ignore: Sequence[str],
    schema: str | os.PathLike[str] | None,
    rule_options: Mapping[str, float] | None,
) -> Linter:
    options = tuple(sorted((rule_options or {}).items()))
    return _linter(tuple(select), tuple(ignore), Path(schema) if schema else None, options)


def lint_file(
    path: str | os.PathLike[str],
    *,
    select: Sequence[str] = ("ALL",),
    ignore: Sequence[str] = (),
    schema: str | os.PathLike[str] | None = None,
    rule_options: Mapping[str, float] | None = None,
) -> FileReport:
    """Lint one file; a file that cannot be read gives a report with ``error`` set.

    ``rule_options`` sets rule options by name (``{"rail-min-width": 1.0}``).
    """
    linter = _linter_for(select, ignore, schema, rule_options)
    return linter.lint_path(Path(path))


def lint_bytes(
    data: bytes,
    path: str = "<bytes>",
    *,
    select: Sequence[str] = ("ALL",),
    ignore: Sequence[str] = (),
    schema: str | os.PathLike[str] | None = None,
    rule_options: Mapping[str, float] | None = None,
) -> FileReport:
    """Lint the contents of a file; ``path`` is only the name findings carry."""
    linter = _linter_for(select, ignore, schema, rule_options)
    return linter.lint_bytes(data, path)


class Input(NamedTuple):
    """One thing to lint: a file, standard input, or a path that cannot be linted."""

    display: str
    path: Path | None = None
    error: str | None = None
    is_stdin: bool = False


def collect_inputs(
    paths: Iterable[str], exclude: Callable[[Path], bool] | None = None
) -> Iterator[Input]:
    """Files as given, folders walked for ``*.xodr`` (sorted, symlinks not followed), and
    glob patterns (``maps/**/*.xodr``) expanded when no such path exists. ``exclude``
    drops files, found or given, that it matches."""
    for raw in paths:
        if raw == STDIN:
            yield Input(STDIN, is_stdin=True)
            continue
        for item in _expand(raw):
            if item.path is None or exclude is None or not exclude(item.path):
                yield item


def _expand(raw: str) -> Iterator[Input]:
    path = Path(raw)
    try:
        mode = path.stat().st_mode
    except OSError as error:
        if glob.has_magic(raw) and error.errno == errno.ENOENT:
            yield from _glob(raw)
        else:
            yield Input(raw, error=f"{raw}: {_reason(error)}")
        return
    if stat.S_ISDIR(mode):
        yield from _walk(path)
    else:
        yield Input(raw, path=path)


def _glob(pattern: str) -> Iterator[Input]:
    # glob.glob, not Path.glob: the pattern may be absolute, and ** must cross folders
    matched = sorted(glob.glob(pattern, recursive=True))  # noqa: PTH207
    if not matched:
        yield Input(pattern, error=f"{pattern}: no file matches")
    for name in matched:
        if Path(name).is_dir():
            yield from _walk(Path(name))
        else:
            yield Input(name, path=Path(name))


def _walk(folder: Path) -> Iterator[Input]:
    found: list[Path] = []
    for current, folders, files in os.walk(folder, followlinks=False):
        folders.sort()
        found.extend(Path(current, name) for name in files if name.lower().endswith(XODR_SUFFIX))
    for path in sorted(found):
        yield Input(path.as_posix(), path=path)


def _reason(error: OSError) -> str:
    reason = error.strerror or type(error).__name__
    return reason[:1].lower() + reason[1:]


def exit_code(reports: Sequence[FileReport], fail_on: Severity, exit_zero: bool) -> int:
    """0 clean, 1 findings at or above ``fail_on``, 2 unreadable input, 3 internal error."""
    if any(r.internal_errors for r in reports):
        return 3
    if any(r.error for r in reports):
        return 2
    if exit_zero:
        return 0
    failing = any(f.severity.rank >= fail_on.rank for r in reports for f in r.findings)
    return 1 if failing else 0
