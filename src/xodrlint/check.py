"""``xodrlint check``: settings, inputs, linting (in workers for many files), baseline,
report. The CLI hands over a :class:`CheckRequest` and gets an exit code back."""

from __future__ import annotations

import json
import os
import sys
from collections import Counter
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Final, TextIO

from xodrlint import __version__
from xodrlint.api import STDIN, Input, collect_inputs, default_registry, exit_code
from xodrlint.baseline import BaselineError
from xodrlint.batch import Task, default_jobs, lint_tasks
from xodrlint.config import (
    COMMAND_LINE,
    ConfigError,
    Settings,
    any_match,
    find_config,
    read_config,
    settings_from,
)
from xodrlint.engine import (
    Linter,
    LintOptions,
    OptionError,
    SelectorError,
    resolve_rule_options,
    select_rules,
)
from xodrlint.findings import FileReport, RunResult
from xodrlint.formatters import Formatter, available, get_formatter
from xodrlint.output import STDOUT, error_line, write_output
from xodrlint.registry import Registry
from xodrlint.schemas import SCHEMA_PATH_ENV, Origin, SchemaLoadError
from xodrlint.suppress import UNUSED_META

FULL_VALIDATION_NOTE: Final = (
    "only railroad elements were validated (built-in schema); for full OpenDRIVE "
    f"validation run 'xodrlint schemas fetch', or point {SCHEMA_PATH_ENV} or --schema at "
    "the official ASAM schemas"
)


@dataclass(frozen=True)
class CheckRequest:
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
    rule_options: Mapping[str, float] = field(default_factory=dict)
    config: Path | None = None
    isolated: bool = False
    exclude: tuple[str, ...] | None = None
    jobs: int | None = None
    baseline: Path | None = None
    write_baseline: Path | None = None
    warn_unused_suppressions: bool | None = None
    show_suppressed: bool = False
    statistics: bool = False


class UsageError(ValueError):
    """A request that cannot run: exit 2 with this one line."""


def resolve_settings(
    registry: Registry,
    paths: tuple[str, ...],
    *,
    config: Path | None = None,
    isolated: bool = False,
    overrides: Mapping[str, object] | None = None,
) -> Settings:
    """The effective settings: the config file that governs the first path (or ``config``),
    under the command line's ``overrides``."""
    if isolated:
        found = None
    elif config is not None:
        found = read_config(config)
    else:
        first = next((p for p in paths if p != STDIN), ".")
        found = find_config(Path(first))
    minimums = {
        option.name: option.minimum for rule in registry.rules for option in rule.meta.options
    }
    return settings_from(
        found,
        overrides or {},
        option_minimums=minimums,
        known_codes=registry.by_code,
    )


def _overrides(request: CheckRequest) -> dict[str, object]:
    return {
        "select": request.select,
        "extend-select": request.extend_select,
        "ignore": request.ignore,
        "fail-on": request.fail_on,
        "schema": request.schema,
        "output-format": request.output_format,
        "exclude": request.exclude,
        "warn-unused-suppressions": request.warn_unused_suppressions,
        **request.rule_options,
    }


def run_check(request: CheckRequest) -> int:
    registry = default_registry()
    for warning in registry.warnings:
        error_line(f"warning: {warning}")
    try:
        settings, linter = prepare_linter(registry, request)
        formatter = _formatter(settings.output_format, request)
        inputs = list(collect_inputs(request.paths, _excluder(settings)))
        _check_output_target("--output", request.output, inputs)
        if request.write_baseline is not None:
            _check_output_target("--write-baseline", str(request.write_baseline), inputs)
        recorded = None
        if request.baseline is not None:
            from xodrlint.baseline import load_baseline

            recorded = load_baseline(request.baseline)
    except (ConfigError, SelectorError, OptionError, UsageError, BaselineError) as error:
        error_line(str(error))
        return 2
    try:
        reports = _lint(linter, settings, inputs, request)
    except SchemaLoadError as error:
        error_line(str(error))
        return 2
    root = str(Path.cwd())
    for report in reports:
        if report.error:
            error_line(report.error)
        for crash in report.internal_errors:
            error_line(f"internal error: {crash}")
    if request.write_baseline is not None:  # every current finding, the baseline's too
        return _write_baseline(request.write_baseline, reports, root)
    if recorded is not None:
        from xodrlint.baseline import apply_baseline

        reports = apply_baseline(reports, recorded, root, keep=request.show_suppressed)
    metas = registry.metas + ((UNUSED_META,) if settings.warn_unused_suppressions else ())
    result = RunResult(tuple(reports), metas, __version__, notes=run_notes(reports), root=root)
    try:
        if request.statistics:
            write_output(request.output, lambda stream: _statistics(result, stream))
        else:
            write_output(request.output, lambda stream: formatter.render(result, stream))
    except OSError as error:
        error_line(f"--output {request.output}: cannot write: {error.strerror or error}")
        return 2
    return exit_code(reports, settings.fail_on, request.exit_zero)


def prepare_linter(registry: Registry, request: CheckRequest) -> tuple[Settings, Linter]:
    """The effective settings of ``request`` and a linter that applies them (``map`` lints
    with exactly what ``check`` would). Raises the errors ``run_check`` reports as usage
    errors: :class:`ConfigError`, :class:`SelectorError`, :class:`OptionError`,
    :class:`UsageError`."""
    resolve_rule_options(registry, request.rule_options)  # names the command line got
    settings = resolve_settings(
        registry,
        request.paths,
        config=request.config,
        isolated=request.isolated,
        overrides=_overrides(request),
    )
    return settings, _linter(registry, settings, request)


def _linter(registry: Registry, settings: Settings, request: CheckRequest) -> Linter:
    if settings.schema is not None and not settings.schema.exists():
        flag = "--schema" if settings.source_of("schema") == COMMAND_LINE else "schema"
        raise UsageError(f"{flag} {settings.schema}: no such file or folder")
    for _, selectors in settings.per_file_ignores:
        select_rules(registry, selectors, ())  # an entry that names no rule is an error
    options = LintOptions(
        select=settings.selected,
        ignore=settings.ignore,
        severity=settings.severity,
        schema=settings.schema,
        schema_origin=Origin.OPTION,
        keep_source=request.show_source,
        rule_options=settings.rule_options,
        keep_suppressed=request.show_suppressed,
        warn_unused_suppressions=settings.warn_unused_suppressions,
    )
    return Linter(registry, options)


def _formatter(name: str, request: CheckRequest) -> Formatter:
    try:
        return get_formatter(name, show_source=request.show_source, quiet=request.quiet)
    except KeyError:
        raise UsageError(
            f"unknown output format '{name}' (choose from {', '.join(available())})"
        ) from None


def _excluder(settings: Settings) -> Callable[[Path], bool] | None:
    if not settings.exclude:
        return None
    return lambda path: any_match(settings.exclude, path, settings.base)


def _lint(
    linter: Linter, settings: Settings, inputs: list[Input], request: CheckRequest
) -> list[FileReport]:
    stdin = sys.stdin.buffer.read() if any(i.is_stdin for i in inputs) else None
    tasks = [
        Task(item.path, item.display, _per_file_ignores(settings, item.path))
        for item in inputs
        if item.path is not None and item.error is None
    ]
    jobs = request.jobs if request.jobs is not None else default_jobs()
    linted = iter(lint_tasks(linter, tasks, jobs, progress=True))
    reports = []
    for item in inputs:
        if item.error is not None:
            reports.append(FileReport(item.display, error=item.error))
        elif item.is_stdin:
            name = request.stdin_filename or STDIN
            external = _per_file_ignores(settings, Path(name)) if request.stdin_filename else ()
            reports.append(linter.lint_bytes(stdin or b"", name, external))
        else:
            reports.append(next(linted))
    return reports


def _per_file_ignores(settings: Settings, path: Path) -> tuple[tuple[str, str], ...]:
    where = f"per-file-ignores in {settings.config_file or 'the command line'}"
    return tuple(
        (selector, f"{where} ({glob})")
        for glob, selectors in settings.per_file_ignores
        if any_match([glob], path, settings.base)
        for selector in selectors
    )


def _check_output_target(flag: str, output: str | None, inputs: list[Input]) -> None:
    """Refuse an output that cannot take what is written there, before any linting."""
    if output in (None, STDOUT):
        return
    target = Path(output)
    real = os.path.realpath(target)
    if any(item.path is not None and os.path.realpath(item.path) == real for item in inputs):
        raise UsageError(f"{flag} {output}: is one of the inputs; refusing to overwrite it")
    if target.is_dir():
        raise UsageError(f"{flag} {output}: is a folder")
    if not target.parent.is_dir():
        raise UsageError(f"{flag} {output}: its folder {target.parent} does not exist")


def run_notes(reports: list[FileReport]) -> tuple[str, ...]:
    return (FULL_VALIDATION_NOTE,) if any(r.schema_builtin for r in reports) else ()


def _write_baseline(path: Path, reports: list[FileReport], root: str) -> int:
    from xodrlint.baseline import baseline_document

    document = baseline_document(reports, root)
    try:
        write_output(str(path), lambda stream: _dump(document, stream))
    except OSError as error:
        error_line(f"--write-baseline {path}: cannot write: {error.strerror or error}")
        return 2
    count = sum(len(r.findings) for r in reports)
    print(f"xodrlint: recorded {count} findings in {path}", file=sys.stderr)
    return 2 if any(r.error for r in reports) else 0


def _dump(document: object, stream: TextIO) -> None:
    json.dump(document, stream, indent=2, ensure_ascii=False)
    stream.write("\n")


def _statistics(result: RunResult, stream: TextIO) -> None:
    """Counts per rule, most frequent first (``--statistics``)."""
    counts = Counter(finding.code for finding in result.findings)
    names = {meta.code: meta for meta in result.rules}
    for code, count in sorted(counts.items(), key=lambda item: (-item[1], item[0])):
        meta = names.get(code)
        severity = f"[{meta.severity}]" if meta else ""
        stream.write(f"{count:>6}  {code}  {severity:<9} {meta.name if meta else ''}\n")
