"""``xodrlint check``: settings, inputs, linting (in workers for many files), baseline,
report. The CLI hands over a :class:`CheckRequest` and gets an exit code back."""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

from xodrlint import __version__
from xodrlint.api import (
    STDIN,
    Input,
    default_registry,
    exit_code,
)
from xodrlint.baseline import BaselineError
from xodrlint.cli.inputs import InputsError, check_stdin, collect, in_shard, parse_shard, show_files
from xodrlint.cli.notes import run_notes, say_notes
from xodrlint.cli.reports import (
    ExtraReport,
    OutputRefused,
    check_outputs,
    check_statistics_format,
    parse_reports,
    report_renderer,
    statistics_renderer,
    write_baseline,
    write_reports,
)
from xodrlint.cli.scheduler import SchedulerUsageError, check_scheduler, scheduler_engine
from xodrlint.cli.stream import (
    Source,
    Streamed,
    StreamingRefused,
    check_streamable,
    run_stream,
    stream_inputs,
)
from xodrlint.config import (
    COMMAND_LINE,
    DEFAULT_RULE_TIMEOUT,
    MAX_FOUND_RULE_TIMEOUT,
    ConfigError,
    Settings,
    find_config,
    parse_size,
    read_config,
    settings_from,
)
from xodrlint.engine import Linter, LintOptions, SelectorError, select_rules
from xodrlint.findings import NO_ENTRIES, FileReport, RunResult
from xodrlint.formatters import (
    Formatter,
    available,
    carries_notes,
    get_formatter,
    streaming,
    warnings_of,
)
from xodrlint.messages import one_line
from xodrlint.output import STDOUT, error_line
from xodrlint.registry import Registry
from xodrlint.rule_options import (
    OptionError,
    command_line_options,
    declared_options,
    resolve_rule_options,
)
from xodrlint.validation.sets import SCHEMA_PATH_ENV, SchemaFinder, SchemaLoadError
from xodrlint.workers.batch import Engine, default_jobs, in_order, stream_tasks

if TYPE_CHECKING:
    from collections import Counter


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
    show_suppressed: bool = False
    sarif_max_results: int | None = None
    statistics: bool = False
    reports: tuple[str, ...] = ()
    """``--report FORMAT=PATH`` entries: more reports of the same run, each to a file."""
    verbose: bool = False
    color: str | None = None
    """``--color``: one of :data:`~xodrlint.output.COLOR_CHOICES`; ``None`` is "auto"."""
    max_file_size: str | None = None
    rule_timeout: float | None = None
    shard: str | None = None
    """``--shard K/N``: lint only the K-th of N parts of the inputs."""


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
        skipped: list[str] = []
        found = find_config(Path(first), skipped)
        for reason in skipped:
            error_line(one_line(f"warning: {reason}"))
    settings = settings_from(
        found,
        overrides or {},
        rule_options=declared_options(registry),
        known_codes=registry.by_code,
    )
    if found is not None and config is None:
        settings = _limited(settings, found.path)
    return settings


def _limited(settings: Settings, found: Path) -> Settings:
    """``settings`` with the rule time limit on, where a configuration found in a folder
    turned it off (0) or set it past :data:`~xodrlint.config.MAX_FOUND_RULE_TIMEOUT`: the
    limit is what stops a runaway rule (a pattern of that very file), and only the user's
    own command line (``--rule-timeout``, or ``--config``) may lift it."""
    timeout = settings.rule_timeout
    if 0 < timeout <= MAX_FOUND_RULE_TIMEOUT or settings.source_of("rule-timeout") != str(found):
        return settings
    kept = DEFAULT_RULE_TIMEOUT if timeout == 0 else MAX_FOUND_RULE_TIMEOUT
    asked = "0 (no limit)" if timeout == 0 else f"{timeout:g}"
    error_line(
        one_line(
            f"warning: {found}: rule-timeout = {asked} is taken only from the command line "
            f"or --config; rules keep a {kept:g} s limit"
        )
    )
    sources = {**settings.sources, "rule-timeout": f"{found}, limited to {kept:g} s"}
    return replace(settings, rule_timeout=kept, sources=sources)


def _overrides(request: CheckRequest) -> dict[str, object]:
    return {
        "select": request.select,
        "extend-select": request.extend_select,
        "ignore": request.ignore,
        "fail-on": request.fail_on,
        "schema": request.schema,
        "output-format": request.output_format,
        "sarif-max-results": request.sarif_max_results,
        "exclude": request.exclude,
        "respect-gitignore": request.respect_gitignore,
        "warn-unused-suppressions": request.warn_unused_suppressions,
        "all-versions": request.all_versions,
        "max-file-size": _max_file_size(request.max_file_size),
        "rule-timeout": request.rule_timeout,
    }


def _max_file_size(given: str | None) -> int | None:
    if given is None:
        return None
    try:
        return parse_size(given)
    except TypeError as expected:
        raise UsageError(f"--max-file-size {given}: expected {expected}") from None


class _Plan(NamedTuple):
    """A check ready to lint: everything refused before linting has been."""

    settings: Settings
    linter: Linter
    formatter: Formatter
    extra: list[tuple[ExtraReport, Formatter]]
    inputs: list[Input]
    recorded: Counter[str] | None


def run_check(request: CheckRequest, formatter: Formatter | None = None) -> int:
    """Run a check; ``formatter`` replaces the one the output format names (``qc``)."""
    registry = default_registry()
    for warning in registry.warnings:
        error_line(f"warning: {warning}")
    try:
        plan = _plan(registry, request, formatter)
    except (
        ConfigError,
        SelectorError,
        OptionError,
        UsageError,
        BaselineError,
        OutputRefused,
        InputsError,
        StreamingRefused,
        SchedulerUsageError,
    ) as error:
        error_line(str(error))
        return 2
    if isinstance(plan, int):  # --show-files
        return plan
    settings, linter, formatter, _, inputs, recorded = plan
    if request.verbose:
        from xodrlint.cli.verbose import describe_run

        readable = sum(1 for item in inputs if item.error is None)
        codes = (rule.code for rule in linter.rules)
        describe_run(settings, codes, readable, _jobs(request), request.scheduler)
    source = _source(linter, settings, inputs, request)
    streamed = None if request.write_baseline else streaming(formatter)
    try:
        if streamed is not None:
            return run_stream(source, streamed, Streamed.of(request, recorded))
        started = time.perf_counter()
        reports = in_order(stream_inputs(source), len(inputs))
    except (SchemaLoadError, SchedulerUsageError) as error:
        error_line(str(error))
        return 2
    if request.verbose:
        from xodrlint.cli.verbose import describe_end, describe_file

        for report in reports:
            describe_file(report)
        linted = sum(1 for report in reports if report.error is None)
        describe_end(linted, time.perf_counter() - started)
    return _report(registry, request, plan, reports)


def _plan(registry: Registry, request: CheckRequest, formatter: Formatter | None) -> _Plan | int:
    """What the check lints and writes, each refused before linting when it cannot be
    (raising the errors :func:`run_check` makes one line of); ``--show-files`` is done
    here, and its exit code returned."""
    settings, linter = prepare_linter(registry, request)
    formatter = formatter or _formatter(settings.output_format, request, settings)
    extra = [
        (report, _formatter(report.format, request, settings, report.flag))
        for report in parse_reports(request.reports)
    ]
    if request.statistics:
        check_statistics_format(settings.output_format)
    if not request.write_baseline and streaming(formatter) is not None:
        check_streamable(settings.output_format, (report for report, _ in extra))
    check_stdin(request.paths, request.stdin_filename)
    check_scheduler(request.scheduler, request.scheduler_timeout, request.jobs)
    shard = parse_shard(request.shard) if request.shard is not None else None
    inputs = collect(request.paths, settings)
    if shard is not None:
        inputs = in_shard(inputs, shard, request.stdin_filename)
    if request.show_files:
        return show_files(inputs, request.stdin_filename)
    read_only = (item.path for item in inputs if item.path is not None)
    check_outputs(
        request.output,
        extra,
        request.write_baseline,
        read_only,
        settings.config_file,
        request.baseline,
    )
    recorded = None
    if request.baseline is not None:
        from xodrlint.baseline import load_baseline

        recorded = load_baseline(request.baseline)
    return _Plan(settings, linter, formatter, extra, inputs, recorded)


def _report(
    registry: Registry, request: CheckRequest, plan: _Plan, reports: list[FileReport]
) -> int:
    """Write the reports of a run that kept them all: its report or statistics and every
    ``--report`` file, or the baseline; returns the exit code."""
    settings, linter, formatter, extra, _, recorded = plan
    root = str(Path.cwd())
    for report in reports:
        if report.error:
            error_line(one_line(report.error))  # it names the file: escaped
        for crash in report.internal_errors:
            error_line(f"internal error: {crash}")
    if request.write_baseline is not None:  # every current finding, the baseline's too
        return write_baseline(request.write_baseline, reports, root)
    if recorded is not None:
        from xodrlint.baseline import apply_baseline

        reports = apply_baseline(reports, recorded, root, keep=request.show_suppressed)
    result = RunResult(
        tuple(reports),
        registry.metas,
        __version__,
        notes=run_notes(reports, registry.metas),
        root=root,
        selected=tuple(rule.code for rule in linter.rules),
    )
    main = (
        statistics_renderer(settings.output_format, result)
        if request.statistics
        else report_renderer(formatter, result)
    )
    written = [("--output " + str(request.output), request.output, main)]
    written += [(report.flag, report.path, report_renderer(f, result)) for report, f in extra]
    if not write_reports(written):
        return 2
    if request.statistics or not carries_notes(formatter):
        # counts, or a report of findings only (concise, GitLab's, JUnit, XQAR): what was
        # not checked goes to stderr, after them (where both reach one log, as in
        # pre-commit's)
        say_notes(result.notes)
    _left_out(formatter, extra)
    return exit_code(reports, settings.fail_on, request.exit_zero)


def _left_out(formatter: Formatter, extra: list[tuple[ExtraReport, Formatter]]) -> None:
    """Say on stderr what each report written left out (SARIF's result limit); a line
    about a ``--report`` file names it."""
    for warning in warnings_of(formatter):
        error_line(f"warning: {warning}")
    for report, other in extra:
        for warning in warnings_of(other):
            error_line(f"warning: {report.flag}: {warning}")


def prepare_linter(registry: Registry, request: CheckRequest) -> tuple[Settings, Linter]:
    """The effective settings of ``request`` and a linter that applies them (``map`` lints
    with exactly what ``check`` would). Raises the errors ``run_check`` reports as usage
    errors: :class:`ConfigError`, :class:`SelectorError`, :class:`OptionError`,
    :class:`UsageError`."""
    given = command_line_options(registry, request.rule_options)
    resolve_rule_options(registry, given)  # names and values the command line got
    settings = resolve_settings(
        registry,
        request.paths,
        config=request.config,
        isolated=request.isolated,
        overrides={**_overrides(request), **given},
    )
    return settings, _linter(registry, settings, request)


def _linter(registry: Registry, settings: Settings, request: CheckRequest) -> Linter:
    if settings.schema is not None and not settings.schema.exists():
        source = settings.source_of("schema")
        if source == COMMAND_LINE:
            raise UsageError(f"--schema {settings.schema}: no such file or folder")
        raise UsageError(f"schema {settings.schema} (from {source}): no such file or folder")
    for path in SchemaFinder().environment_paths():
        # a typo would fall back to the built-in schema: CI would lose full validation
        if not path.exists():
            raise UsageError(f"{SCHEMA_PATH_ENV} names {path}: no such file or folder")
    for _, selectors in settings.per_file_ignores:
        select_rules(registry, selectors, ())  # an entry that names no rule is an error
    options = LintOptions.of(
        settings, keep_source=request.show_source, keep_suppressed=request.show_suppressed
    )
    # The command line exits without cleanup (cli.main): it never frees the last tree,
    # nor the linter holding it, which outlives the run in this slot (one linter at most,
    # for a process that runs many checks).
    linter = Linter(registry, options, keep_last_document=True)
    _LAST_LINTER[:] = [linter]
    return linter


_LAST_LINTER: list[Linter] = []


def _formatter(
    name: str, request: CheckRequest, settings: Settings, flag: str | None = None
) -> Formatter:
    # styles are for a terminal or a log (--color, FORCE_COLOR); a file is for reading
    # later: plain, as ruff writes its --output-file
    to_file = flag is not None or request.output not in (None, STDOUT)
    try:
        return get_formatter(
            name,
            show_source=request.show_source,
            quiet=request.quiet,
            color="never" if to_file else request.color,
            sarif_max_results=settings.sarif_max_results,
        )
    except KeyError:
        where = f"{flag}: " if flag else ""
        raise UsageError(
            f"{where}unknown output format '{name}' (choose from {', '.join(available())})"
        ) from None


def _source(
    linter: Linter, settings: Settings, inputs: list[Input], request: CheckRequest
) -> Source:
    jobs = _jobs(request)
    engine: Engine = scheduler_engine(linter.options, request) or (
        lambda tasks: stream_tasks(linter, tasks, jobs, progress=True)
    )
    return Source(linter, settings, inputs, engine, request.stdin_filename)


def _jobs(request: CheckRequest) -> int:
    return request.jobs if request.jobs is not None else default_jobs()
