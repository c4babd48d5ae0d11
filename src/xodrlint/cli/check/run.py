"""``xodrlint check``: settings, inputs, linting (in workers for many files), baseline,
report. The CLI hands over a :class:`CheckRequest` and gets an exit code back."""

from __future__ import annotations

import glob
import os
import time
from array import array
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

from xodrlint import __version__
from xodrlint.api import default_registry, exit_code
from xodrlint.cli.check.fixes import show_diffs, write_document
from xodrlint.cli.check.inputs import (
    InputsError,
    check_stdin,
    collect,
    in_shard,
    parse_shard,
    show_files,
)
from xodrlint.cli.check.notes import run_notes, say_notes
from xodrlint.cli.check.reports import (
    ExtraReport,
    OutputRefused,
    check_outputs,
    check_statistics_format,
    checkout_root,
    parse_reports,
    report_renderer,
    statistics_renderer,
    withheld_line,
    write_baseline,
    write_reports,
)
from xodrlint.cli.check.request import CheckRequest, UsageError
from xodrlint.cli.check.scheduler import SchedulerUsageError, check_scheduler, scheduler_engine
from xodrlint.cli.check.stream import (
    Source,
    Streamed,
    StreamingRefused,
    check_streamable,
    run_stream,
    stream_inputs,
)
from xodrlint.config.resolver import Resolver
from xodrlint.config.settings import ConfigError, Settings
from xodrlint.config.sizes import parse_size
from xodrlint.engine.baseline import BaselineError
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.engine.profiles import Linters
from xodrlint.findings import FileReport, RunResult
from xodrlint.formatters import (
    Formatter,
    available,
    carries_notes,
    get_formatter,
    says_withheld,
    shows_fixes,
    streaming,
    warnings_of,
)
from xodrlint.formatters.output import STDERR, STDOUT, error_line
from xodrlint.inputs.collect import STDIN, Input
from xodrlint.inputs.remote import is_url
from xodrlint.messages import one_line
from xodrlint.rules.options import (
    OptionError,
    command_line_options,
    resolve_rule_options,
)
from xodrlint.rules.registry import Registry
from xodrlint.rules.selection import SelectorError
from xodrlint.runners.batch import Engine, default_jobs, in_order, stream_tasks
from xodrlint.validation.sets import SCHEMA_PATH_ENV, SchemaFinder, SchemaLoadError

if TYPE_CHECKING:
    from xodrlint.engine.baseline import Baseline


def resolve_settings(
    registry: Registry,
    paths: tuple[str, ...],
    *,
    config: Path | None = None,
    isolated: bool = False,
    overrides: Mapping[str, object] | None = None,
) -> Settings:
    """The effective settings of the first of ``paths`` (a file or a folder; none: the
    working folder), under the command line's ``overrides``: what ``xodrlint config``
    shows, and what a check lints that path with."""
    first = next((p for p in paths if p != STDIN), None)
    resolver = Resolver(
        registry,
        overrides,
        config=config,
        isolated=isolated,
        folders=run_folders(paths),
        warn=_warn,
        check=False,
    )
    if first is None:
        return resolver.run
    path = Path(first)
    return resolver.settings[resolver.profile_of(path, folder=path.is_dir())]


def _warn(message: str) -> None:
    error_line(one_line(message))


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
        "xsd-scope": request.xsd_scope,
        "max-file-size": _max_file_size(request.max_file_size),
        "rule-timeout": request.rule_timeout,
        "fix": request.fix,
        "diff": request.diff or None,
        "unsafe-fixes": request.unsafe_fixes,
        "fixable": request.fixable,
        "unfixable": request.unfixable,
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
    linters: Linters
    formatter: Formatter
    extra: list[tuple[ExtraReport, Formatter]]
    inputs: list[Input]
    baseline: Baseline | None
    resolver: Resolver
    profiles: Sequence[int]
    """Each input's profile (its configuration's), by input."""


def _source_shown(request: CheckRequest, output_format: str) -> None:
    """Warn where ``--show-source`` shows nothing: only the text format's full report
    prints the lines."""
    if not request.show_source:
        return
    if request.statistics or output_format != "text":
        where = "--statistics" if request.statistics else f"-f {output_format}"
        error_line(f"warning: --show-source shows nothing with {where} (only -f text shows lines)")
    elif request.quiet:
        error_line("warning: --show-source shows nothing with -q (which prints findings only)")


def _profile(resolver: Resolver, item: Input, stdin_filename: str | None) -> int:
    """The profile ``item`` is linted under: a local file's nearest configuration's,
    standard input's by ``--stdin-filename``, the working folder's for standard input
    without one and for an object by URL."""
    if item.is_stdin and stdin_filename:
        return resolver.profile_of(Path(stdin_filename))
    if item.is_stdin or item.url is not None:
        return resolver.working_profile()
    if item.path is not None and item.error is None:
        return resolver.profile_of(item.path)
    return 0


def run_check(request: CheckRequest, formatter: Formatter | None = None) -> int:
    """Run a check; ``formatter`` replaces the one the output format names (``qc``)."""
    registry = default_registry()
    for warning in registry.warnings:
        error_line(f"warning: {warning}")
    try:
        ready = _ready(registry, request, formatter)
        inputs = _inputs(request, ready.resolver)
        if request.show_files:
            return show_files(inputs, request.stdin_filename)
        plan = _plan(registry, request, ready, inputs)
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
    if request.verbose:
        from xodrlint.cli.check.verbose import describe_run

        readable = sum(1 for item in inputs if item.error is None)
        codes = (rule.code for rule in plan.linters[0].rules)
        describe_run(plan.settings, codes, readable, _jobs(request), request.scheduler)
    source = _source(plan, request)
    # a fixing run writes documents or diffs beside its report: it keeps every report
    fixing = bool(plan.settings.fix_mode) or any(s.fix for s in plan.resolver.settings)
    streamed = None if request.write_baseline or fixing else streaming(plan.formatter)
    try:
        if streamed is not None:
            return run_stream(source, streamed, Streamed.of(request, plan.baseline))
        started = time.perf_counter()
        reports = in_order(stream_inputs(source), len(inputs))
    except (SchemaLoadError, SchedulerUsageError) as error:
        error_line(str(error))
        return 2
    if request.verbose:
        from xodrlint.cli.check.verbose import describe_end, describe_file

        for report in reports:
            describe_file(report)
        linted = sum(1 for report in reports if report.error is None)
        describe_end(linted, time.perf_counter() - started)
    return _report(registry, request, plan, reports)


class _Ready(NamedTuple):
    """A check whose settings and outputs passed: what it writes with, before its inputs
    are collected."""

    resolver: Resolver
    formatter: Formatter
    extra: list[tuple[ExtraReport, Formatter]]


def _ready(registry: Registry, request: CheckRequest, formatter: Formatter | None) -> _Ready:
    """The settings and formats of a check, each refused before any input is collected
    (raising the errors :func:`run_check` makes one line of)."""
    resolver = prepare_resolver(registry, request)
    settings = resolver.run
    formatter = formatter or _formatter(settings.output_format, request, settings)
    extra = [
        (report, _formatter(report.format, request, settings, report.flag))
        for report in parse_reports(request.reports)
    ]
    if request.statistics:
        check_statistics_format(settings.output_format)
    _source_shown(request, settings.output_format)
    if not request.write_baseline and streaming(formatter) is not None:
        check_streamable(settings.output_format, (report for report, _ in extra))
    check_stdin(request.paths, request.stdin_filename)
    check_scheduler(request.scheduler, request.scheduler_timeout, request.jobs)
    _check_fixing(request, settings)
    return _Ready(resolver, formatter, extra)


def _check_fixing(request: CheckRequest, settings: Settings) -> None:
    """Refuse what ``--fix`` and ``--diff`` cannot do: write an object back to its store,
    run on a cluster (whose workers would write), record a baseline. Checked with the
    run's settings before any input is listed, and again with each file's configuration
    (a folder's may say ``fix = true``) before any is linted."""
    mode = settings.fix_mode
    if not mode:
        return
    flag = "--diff" if mode == "diff" else "--fix"
    url = next((path for path in request.paths if is_url(path)), None)
    if url is not None:
        raise UsageError(f"{flag}: cannot fix an object by URL in place ({one_line(url)})")
    if request.scheduler is not None:
        raise UsageError(f"{flag} runs on this machine: it does not go with --scheduler")
    if request.write_baseline is not None:
        raise UsageError(f"{flag} does not go with --write-baseline")
    if mode == "diff":
        # the diff is the report: another one asked for would silently not be written
        for given, option in (
            (request.output, "--output"),
            (request.reports, "--report"),
            (request.output_format not in (None, "text"), "--output-format"),
            (request.statistics, "--statistics"),
        ):
            if given:
                raise UsageError(f"--diff prints a diff: it does not go with {option}")


def _inputs(request: CheckRequest, resolver: Resolver) -> list[Input]:
    """What the check lints: the paths' files after the settings' exclusions, the part
    ``--shard`` takes."""
    shard = parse_shard(request.shard) if request.shard is not None else None
    inputs = collect(request.paths, resolver.run, resolver, request.stdin_filename)
    if shard is not None:
        inputs = in_shard(inputs, shard, request.stdin_filename)
    return inputs


def _plan(registry: Registry, request: CheckRequest, ready: _Ready, inputs: list[Input]) -> _Plan:
    """What the check lints and writes, each refused before linting when it cannot be
    (raising the errors :func:`run_check` makes one line of)."""
    resolver = ready.resolver
    # every file's configuration read (and refused) before any is linted
    profiles = array("q", (_profile(resolver, item, request.stdin_filename) for item in inputs))
    for each in resolver.settings:
        _check_fixing(request, each)
    read_only = (item.path for item in inputs if item.path is not None)
    check_outputs(
        request.output,
        ready.extra,
        request.write_baseline,
        read_only,
        (each.config_file for each in resolver.settings if each.config_file is not None),
        request.baseline,
    )
    baseline = None
    if request.baseline is not None:
        from xodrlint.engine.baseline import load_baseline

        baseline = load_baseline(request.baseline)
    options = resolver.options
    if request.diff or any(shows_fixes(f) for f in (ready.formatter, *(f for _, f in ready.extra))):
        options = [each._replace(place_fixes=True) for each in options]
    first = _kept_linter(registry, options[0], request.keep_alive)
    linters = Linters(options, first=first)
    linters.built()  # each profile's rules and options refused here, not in a worker
    return _Plan(
        settings=resolver.run,
        linters=linters,
        formatter=ready.formatter,
        extra=ready.extra,
        inputs=inputs,
        baseline=baseline,
        resolver=resolver,
        profiles=profiles,
    )


def _report(
    registry: Registry, request: CheckRequest, plan: _Plan, reports: list[FileReport]
) -> int:
    """Write the reports of a run that kept them all: its report or statistics and every
    ``--report`` file, or the baseline; returns the exit code."""
    settings, formatter, baseline = plan.settings, plan.formatter, plan.baseline
    for report in reports:
        if report.error:
            error_line(one_line(report.error))  # it names the file: escaped
        for crash in report.internal_errors:
            error_line(f"internal error: {crash}")
    if request.write_baseline is not None:  # every current finding, the baseline's too
        return write_baseline(request.write_baseline, reports)
    if settings.diff:
        return show_diffs(reports)
    fixed_document = next((r.fixed_source for r in reports if r.fixed_source is not None), None)
    withheld = 0
    if baseline is not None:
        from xodrlint.engine.baseline import apply_baseline

        unmatched = baseline.unmatched(r.path for r in reports if r.error is None)
        if unmatched is not None:
            error_line(f"warning: {one_line(unmatched)}")
        reports, withheld = apply_baseline(reports, baseline, keep=request.show_suppressed)
    result = RunResult(
        tuple(reports),
        registry.metas,
        __version__,
        notes=run_notes(reports, registry.metas),
        root=checkout_root(),
        selected=_selected(plan.linters),
        baseline=None if baseline is None else baseline.path.name,
        withheld=withheld,
    )
    main = (
        statistics_renderer(settings.output_format, result)
        if request.statistics
        else report_renderer(formatter, result)
    )
    output = request.output
    if fixed_document is not None:
        # standard output carries the fixed document, as ruff's --fix on stdin does; the
        # report goes to standard error unless -o names a file
        if not write_document(fixed_document):
            return 2
        output = STDERR if output in (None, STDOUT) else output
    written = [("--output " + str(request.output), output, main)]
    written += [(report.flag, report.path, report_renderer(f, result)) for report, f in plan.extra]
    if not write_reports(written):
        return 2
    if baseline is not None and (request.statistics or not says_withheld(formatter)):
        error_line(withheld_line(baseline.path.name, withheld))
    if request.statistics or not carries_notes(formatter):
        # counts, or a report of findings only (concise, GitLab's, JUnit, XQAR): what was
        # not checked goes to stderr, after them (where both reach one log, as in
        # pre-commit's)
        say_notes(result.notes)
    _left_out(formatter, plan.extra)
    # each file fails the run by its own configuration's fail-on; the run's code is the
    # largest of the files' (3 before 2 before 1 before 0)
    return max(
        (
            exit_code((report,), plan.resolver.settings[profile].fail_on, request.exit_zero)
            for report, profile in zip(reports, plan.profiles, strict=True)
        ),
        default=0,
    )


def _selected(linters: Linters) -> tuple[str, ...]:
    """The codes of the rules the run applied to some file, in the registry's order."""
    if len(linters) == 1:
        return tuple(rule.code for rule in linters[0].rules)
    codes = {rule.code for linter in linters.built() for rule in linter.rules}
    return tuple(code for code in linters[0].registry.by_code if code in codes)


def _left_out(formatter: Formatter, extra: list[tuple[ExtraReport, Formatter]]) -> None:
    """Say on stderr what each report written left out (SARIF's result limit); a line
    about a ``--report`` file names it."""
    for warning in warnings_of(formatter):
        error_line(f"warning: {warning}")
    for report, other in extra:
        for warning in warnings_of(other):
            error_line(f"warning: {report.flag}: {warning}")


def prepare_resolver(registry: Registry, request: CheckRequest) -> Resolver:
    """The configuration of each file of ``request`` and the run's own (profile 0).
    Raises the errors ``run_check`` reports as usage errors: :class:`ConfigError`,
    :class:`SelectorError`, :class:`OptionError`, :class:`UsageError`."""
    given = command_line_options(registry, request.rule_options)
    resolve_rule_options(registry, given)  # names and values the command line got
    for path in SchemaFinder().environment_paths():
        # a typo would fall back to the built-in schema: CI would lose full validation
        if not path.exists():
            raise UsageError(f"{SCHEMA_PATH_ENV} names {path}: no such file or folder")
    return Resolver(
        registry,
        {**_overrides(request), **given},
        config=request.config,
        isolated=request.isolated,
        folders=run_folders(request.paths, request.stdin_filename),
        warn=_warn,
        keep_source=request.show_source,
        keep_suppressed=request.show_suppressed,
    )


def run_folders(paths: Sequence[str], stdin_filename: str | None = None) -> list[Path]:
    """The folders of the local paths a run lints (a file's, a folder itself, a glob's up
    to its first wildcard, standard input's at ``--stdin-filename``), absolute and
    normalised: the deepest folder holding them all gives the run's own settings, so the
    order of the paths never matters and one path's run is governed by that path's
    configuration."""
    folders = []
    for path in (*paths, *((stdin_filename,) if stdin_filename else ())):
        if path == STDIN or is_url(path):
            continue
        # '..' taken away as written, without following links, as the paths are reported
        local = Path(os.path.abspath(_before_wildcards(path)))  # noqa: PTH100
        folders.append(local if local.is_dir() else local.parent)
    return folders


def _before_wildcards(path: str) -> str:
    if not glob.has_magic(path) or os.path.lexists(path):  # a name with '[' in it
        return path
    parts = Path(path).parts
    plain = next(i for i, part in enumerate(parts) if glob.has_magic(part))
    return str(Path(*parts[:plain])) if plain else "."


def prepare_linter(registry: Registry, request: CheckRequest) -> tuple[Settings, Linter]:
    """The settings and a linter for the first path of ``request`` (``map`` lints its
    file with exactly what ``check`` would). Raises as :func:`prepare_resolver`."""
    resolver = prepare_resolver(registry, request)
    first = next((p for p in request.paths if p != STDIN), None)
    profile = resolver.profile_of(Path(first)) if first is not None else 0
    linter = _kept_linter(registry, resolver.options[profile], request.keep_alive)
    return resolver.settings[profile], linter


def _kept_linter(
    registry: Registry, options: LintOptions, keep_alive: list[object] | None
) -> Linter:
    """A linter that keeps its last document (``map`` draws it); left in ``keep_alive``
    (see :attr:`CheckRequest.keep_alive`) when the caller has one."""
    linter = Linter(registry, options, keep_last_document=True)
    if keep_alive is not None:
        keep_alive.append(linter)
    return linter


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
            unsafe_fixes=settings.unsafe_fixes,
        )
    except KeyError:
        where = f"{flag}: " if flag else ""
        raise UsageError(
            f"{where}unknown output format '{name}' (choose from {', '.join(available())})"
        ) from None


def _source(plan: _Plan, request: CheckRequest) -> Source:
    jobs = _jobs(request)
    linters = plan.linters
    engine: Engine = scheduler_engine(linters.options, request) or (
        lambda tasks: stream_tasks(linters, tasks, jobs, progress=True)
    )
    return Source(
        linters,
        plan.settings,
        plan.inputs,
        engine,
        request.stdin_filename,
        plan.resolver,
        plan.profiles,
    )


def _jobs(request: CheckRequest) -> int:
    return request.jobs if request.jobs is not None else default_jobs()
