"""What ``xodrlint check`` (and ``map``, ``qc``, ``config``) was asked: the request the
commands build and the modules of a check read, apart from all of them so that none
imports another for it."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import NamedTuple

from xodrlint.findings import NO_ENTRIES


class CheckRequest(NamedTuple):
    """What the command line asked for; ``None`` means "not given" (the config decides)."""

    paths: tuple[str, ...]
    output_format: str | None = None
    output: str | None = None
    select: tuple[str, ...] | None = None
    extend_select: tuple[str, ...] | None = None
    ignore: tuple[str, ...] | None = None
    fail_on: str | None = None
    exit_zero: bool = False
    schema: Path | None = None
    quiet: bool = False
    show_source: bool = False
    stdin_filename: str | None = None
    rule_options: Mapping[str, float | str] = NO_ENTRIES
    """Rule options by name: a flag's number, or ``--rule-option NAME=VALUE``'s text,
    which :func:`prepare_linter` reads as the option takes it."""
    config: Path | None = None
    isolated: bool = False
    exclude: tuple[str, ...] | None = None
    respect_gitignore: bool | None = None
    show_files: bool = False
    jobs: int | None = None
    scheduler: str | None = None  # a Dask scheduler's address, or "local"
    scheduler_timeout: float | None = None
    baseline: Path | None = None
    write_baseline: Path | None = None
    warn_unused_suppressions: bool | None = None
    all_versions: bool | None = None
    """``--all-versions``: every rule judges every file, whatever version it declares."""
    xsd_scope: str | None = None
    """``--xsd-scope``: ``all`` or ``railroad`` (which schema errors are listed)."""
    show_suppressed: bool = False
    fix: bool | None = None
    unsafe_fixes: bool | None = None
    diff: bool = False
    fixable: tuple[str, ...] | None = None
    unfixable: tuple[str, ...] | None = None
    sarif_max_results: int | None = None
    statistics: bool = False
    reports: tuple[str, ...] = ()
    """``--report FORMAT=PATH`` entries: more reports of the same run, each to a file."""
    verbose: bool = False
    color: str | None = None
    """``--color``: one of :data:`~xodrlint.formatters.output.COLOR_CHOICES`; ``None`` is "auto"."""
    keep_alive: list[object] | None = None
    """Where the run leaves what it need not free: the entry point's list, which lives
    until the process exits without tearing down (:mod:`xodrlint.cli.entry`). The last
    map's tree and the linter holding it go there, so freeing them costs no run (tens
    of milliseconds on a 20 MB map); ``None`` (the API, tests) frees them with the run."""
    max_file_size: str | None = None
    rule_timeout: float | None = None
    shard: str | None = None
    """``--shard K/N``: lint only the K-th of N parts of the inputs."""


class UsageError(ValueError):
    """A request that cannot run: exit 2 with this one line."""
