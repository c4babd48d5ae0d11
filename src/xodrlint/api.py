"""The Python API: the engine without the CLI, for pipelines and notebooks.

``lint_file`` and ``lint_bytes`` lint one input; ``collect_inputs`` expands the paths
``xodrlint check`` takes (files, folders, globs; :mod:`xodrlint.inputs.collect`). A
pipeline (Dask, Spark, a CI matrix) can call ``lint_file`` per file (the linter behind it
is cached, so schemas compile once per process); :func:`xodrlint.runners.batch.lint_tasks`
spreads many files over processes.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Mapping, Sequence
from functools import lru_cache
from pathlib import Path

from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import FileReport, Severity
from xodrlint.inputs.collect import collect_inputs
from xodrlint.inputs.remote import is_url
from xodrlint.rules.registry import Registry, load_registry

__all__ = ["LintOptions", "Linter", "collect_inputs", "lint_bytes", "lint_file"]


@lru_cache(maxsize=1)
def default_registry() -> Registry:
    return load_registry()


@lru_cache(maxsize=8)
def _linter(
    select: tuple[str, ...],
    ignore: tuple[str, ...],
    schema: Path | None,
    rule_options: tuple[tuple[str, float | str], ...],
    all_versions: bool = False,
) -> Linter:
    options = LintOptions(
        select=select,
        ignore=ignore,
        schema=schema,
        rule_options=dict(rule_options),
        all_versions=all_versions,
    )
    return Linter(_api_registry(), options)


@lru_cache(maxsize=1)
def _api_registry() -> Registry:
    """The registry ``lint_file`` and ``lint_bytes`` lint with: a pack it refused is one
    ``RuntimeWarning`` a process, where the command line prints its warning line."""
    registry = default_registry()
    for message in registry.warnings:
        warnings.warn(f"xodrlint: {message}", RuntimeWarning, stacklevel=5)
    return registry


def _linter_for(
    select: Sequence[str],
    ignore: Sequence[str],
    schema: str | os.PathLike[str] | None,
    rule_options: Mapping[str, float | str] | None,
    all_versions: bool,
) -> Linter:
    options = tuple(sorted((rule_options or {}).items()))
    where = Path(schema) if schema else None
    return _linter(tuple(select), tuple(ignore), where, options, all_versions)


def lint_file(
    path: str | os.PathLike[str],
    *,
    select: Sequence[str] = ("ALL",),
    ignore: Sequence[str] = (),
    schema: str | os.PathLike[str] | None = None,
    rule_options: Mapping[str, float | str] | None = None,
    all_versions: bool = False,
) -> FileReport:
    """Lint one file; a file that cannot be read gives a report with ``error`` set.

    ``path`` may be a URL that fsspec reads (``s3://bucket/maps/a.xodr``; the ``cloud``
    extra). ``rule_options`` sets rule options by name (``{"rail-min-width": 1.0}``).
    ``all_versions`` applies every rule whatever version the file declares (RL001 and
    RL002 apply from OpenDRIVE 1.7 on; the report's ``rules_not_applied`` names those
    that did not judge the file).
    """
    linter = _linter_for(select, ignore, schema, rule_options, all_versions)
    if isinstance(path, str) and is_url(path):
        return linter.lint_url(path)
    return linter.lint_path(Path(path))


def lint_bytes(
    data: bytes,
    path: str = "<bytes>",
    *,
    select: Sequence[str] = ("ALL",),
    ignore: Sequence[str] = (),
    schema: str | os.PathLike[str] | None = None,
    rule_options: Mapping[str, float | str] | None = None,
    all_versions: bool = False,
    location: str | os.PathLike[str] | None = None,
) -> FileReport:
    """Lint the contents of a file; ``path`` is only the name findings carry (the
    keywords as :func:`lint_file`'s). ``location`` is the file the bytes stand for: the
    document's ``include`` elements are read from its folder (without it, each is an
    XS007 finding)."""
    linter = _linter_for(select, ignore, schema, rule_options, all_versions)
    where = Path(location) if location is not None else None
    return linter.lint_bytes(data, path, location=where)


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
