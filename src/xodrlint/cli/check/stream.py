"""``xodrlint check``'s reports as files are done: every input's report from an engine
(:data:`~xodrlint.runners.batch.ReportStream`), and the run of a streaming format
(``jsonl``), which writes and flushes each file's lines as it completes and keeps no
report after that, so its memory stays flat however many files it lints.

What needs every report at once cannot stream, and is refused before linting (exit 2):
``--statistics`` (refused by the formats that hold it), and ``--report`` files, which a
run in another format writes beside a ``jsonl`` one (``-f sarif --report jsonl=FILE``).
``--write-baseline`` writes no report, so the format does not matter to it.
"""

from __future__ import annotations

import contextlib
import sys
import time
from array import array
from collections import deque
from collections.abc import Generator, Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple, TextIO, cast, overload

from xodrlint.api import exit_code
from xodrlint.cli.check.inputs import read_stdin
from xodrlint.cli.check.notes import NotApplied, hidden_note, run_notes, say_notes
from xodrlint.cli.check.reports import withheld_line
from xodrlint.config.settings import Settings
from xodrlint.engine.linter import Linter
from xodrlint.engine.profiles import Linters
from xodrlint.findings import FileReport, RuleMeta, Severity
from xodrlint.formatters import StreamingFormatter
from xodrlint.formatters.output import STDOUT, error_line, release, write_output
from xodrlint.inputs.collect import STDIN, Input
from xodrlint.inputs.files import os_reason
from xodrlint.inputs.remote import url_path
from xodrlint.messages import one_line
from xodrlint.runners.batch import Engine, Task, task_of

if TYPE_CHECKING:
    from xodrlint.cli.check.reports import ExtraReport
    from xodrlint.cli.check.request import CheckRequest
    from xodrlint.config.resolver import Resolver
    from xodrlint.engine.baseline import Baseline


class Source(NamedTuple):
    """What a run lints and how: the inputs in order, the linters and the run's settings,
    the engine for the files, and the name reported for standard input.

    A run whose files fall under several configurations has the ``resolver`` that found
    them and each input's profile in ``profiles``; without them every input is linted
    under ``settings`` by ``linter``."""

    linter: Linter | Linters
    settings: Settings
    inputs: Sequence[Input]
    engine: Engine
    stdin_filename: str | None = None
    resolver: Resolver | None = None
    profiles: Sequence[int] = ()

    def settings_of(self, index: int) -> Settings:
        """The settings input ``index`` is linted under."""
        if self.resolver is None or not self.profiles:
            return self.settings
        return self.resolver.settings[self.profiles[index]]

    def profile_of(self, index: int) -> int:
        return self.profiles[index] if self.profiles else 0

    @property
    def linters(self) -> Linters:
        linter = self.linter
        return linter if isinstance(linter, Linters) else Linters.of(linter)


def stream_inputs(source: Source) -> Generator[tuple[int, FileReport], None, None]:
    """Each input's report with its index in ``source.inputs``, as soon as it is known:
    the files as the engine completes them, and each input it does not lint (a path that
    cannot be read, standard input) just before the first file after it, so an engine
    that completes files in their order (one process) gives the inputs' order."""
    inputs, settings = source.inputs, source.settings
    reading = any(item.is_stdin for item in inputs)
    stdin, unreadable = read_stdin(settings.max_file_size) if reading else (b"", None)
    tasks = _Tasks(source)
    others = deque(i for i, item in enumerate(inputs) if not _is_file(item))
    linters = source.linters

    def other(index: int) -> FileReport:
        item = inputs[index]
        if item.error is not None:
            return FileReport(item.display, error=item.error)
        name = source.stdin_filename or STDIN
        if unreadable is not None:
            return FileReport(name, error=unreadable)
        named = source.stdin_filename is not None
        external = source.settings_of(index).ignored_in(Path(name)) if named else ()
        # standard input named by --stdin-filename reads its includes from there
        location = Path(name) if named else None
        return linters[source.profile_of(index)].lint_bytes(
            stdin, name, external, location=location
        )

    completed = source.engine(tasks)
    try:
        for number, report in completed:
            position = tasks.position(number)
            while others and others[0] < position:
                index = others.popleft()
                yield index, other(index)
            yield position, report
    finally:  # a caller that stops early stops the engine's workers now, not when collected
        close = getattr(completed, "close", None)
        if close is not None:
            close()
    while others:
        index = others.popleft()
        yield index, other(index)


def _is_file(item: Input) -> bool:
    return item.lintable


class _Tasks(Sequence[Task]):
    """The inputs that are files as the engine's tasks, each made when the engine asks
    for it: a run holds its inputs once (8 bytes a file more here), not a second list of
    tasks beside them."""

    def __init__(self, source: Source) -> None:
        self._source = source
        inputs = source.inputs
        self._positions = array("q", (i for i, item in enumerate(inputs) if _is_file(item)))

    def position(self, number: int) -> int:
        """The index among the inputs of task ``number``."""
        return self._positions[number]

    def __len__(self) -> int:
        return len(self._positions)

    @overload
    def __getitem__(self, number: int) -> Task: ...

    @overload
    def __getitem__(self, number: slice) -> list[Task]: ...

    def __getitem__(self, number: int | slice) -> Task | list[Task]:
        if isinstance(number, slice):
            return [self[i] for i in range(len(self))[number]]
        source = self._source
        index = self._positions[number]
        item = source.inputs[index]
        # an object by URL is read by its worker (this process only listed it); its
        # per-file-ignores match the path in its bucket
        where = url_path(item.url) if item.url is not None else cast("Path", item.path)
        external = source.settings_of(index).ignored_in(where)
        return task_of(item, external, source.settings.max_file_size, source.profile_of(index))


class StreamingRefused(ValueError):
    """A request a streaming run cannot serve: exit 2 with this one line, before linting."""


def check_streamable(name: str, extra: Iterable[ExtraReport]) -> None:
    """Refuse ``--report`` files beside the streaming format ``name``: every other format
    needs every report at once, which a streaming run does not keep."""
    for report in extra:
        raise StreamingRefused(
            f"{report.flag}: -f {name} writes findings as files are done and keeps no "
            f"reports to write another from (for both from one run: -f {report.format} "
            f"--report {name}=FILE)"
        )


class Streamed(NamedTuple):
    """A streaming run's settings beside its source: where its output goes, what it
    withholds (the baseline) and what it says on stderr."""

    output: str | None
    baseline: Baseline | None = None
    keep_suppressed: bool = False
    exit_zero: bool = False
    verbose: bool = False

    @classmethod
    def of(cls, request: CheckRequest, baseline: Baseline | None) -> Streamed:
        """What ``request`` asks of a streaming run, ``baseline`` the one it applies."""
        return cls(
            request.output,
            baseline,
            keep_suppressed=request.show_suppressed,
            exit_zero=request.exit_zero,
            verbose=request.verbose,
        )


def run_stream(source: Source, formatter: StreamingFormatter, run: Streamed) -> int:
    """Lint ``source`` and write each file's part of the report as it completes; the
    exit code is the one the whole run's reports would give."""
    tally = _Tally(run, source.linters[0].registry.metas)
    state = _Writing()
    started = time.perf_counter()

    def render(stream: TextIO) -> None:
        state.linting = True
        with contextlib.closing(stream_inputs(source)) as reports:
            for index, report in reports:
                kept = tally.add(report, source.settings_of(index).fail_on)
                stream = _write(formatter, kept, stream, run.output, state)
        state.linting = False

    try:
        write_output(run.output, render)
    except OSError as error:
        if state.linting and state.failed is None:
            raise  # the engine's, not the output's: an internal error, as in other formats
        where = "standard output" if run.output in (None, STDOUT) else f"--output {run.output}"
        reason = "broken pipe" if isinstance(error, BrokenPipeError) else os_reason(error)
        error_line(f"{where}: cannot write: {reason}")
        return 2
    baseline = run.baseline
    if baseline is not None:
        if tally.linted and baseline.recorded and not tally.matched:
            error_line(f"warning: {one_line(baseline.matches_nothing())}")
        error_line(withheld_line(baseline.path.name, tally.withheld))
    say_notes(tally.notes())  # after the last line, where both reach one log
    if run.verbose:
        from xodrlint.cli.check.verbose import describe_end

        describe_end(tally.linted, time.perf_counter() - started)
    return tally.code


def _write(
    formatter: StreamingFormatter,
    report: FileReport,
    stream: TextIO,
    output: str | None,
    state: _Writing,
) -> TextIO:
    """Write and flush one file's part; returns the stream to write the next to."""
    try:
        formatter.write_file(report, stream)
        stream.flush()
    except BrokenPipeError as error:
        if output not in (None, STDOUT):  # a FIFO named by -o, its reader gone
            state.failed = error
            raise
        # its reader stopped early (| head): the run goes on to its exit code, as with
        # every other format, writing to nowhere
        release(sys.stdout)
        return sys.stdout
    except OSError as error:
        state.failed = error
        raise
    return stream


class _Writing:
    """Where a streaming run is: linting (and writing) or not, and the error writing
    met, so an error of the engine's is told from one of the output's."""

    linting = False
    failed: OSError | None = None


class _Tally:
    """What a streaming run keeps of its reports: the exit code so far, the files linted,
    one stand-in per version the built-in schema alone validated and the count of files
    some rules did not judge (for the notes)."""

    def __init__(self, run: Streamed, rules: Sequence[RuleMeta]) -> None:
        self._run = run
        self._rules = rules
        self._not_applied = NotApplied()
        self._hidden: list[str] = []  # one note per file xsd-scope left errors out of
        self._remaining = None if run.baseline is None else run.baseline.recorded.copy()
        self.withheld = 0
        self.matched = False  # whether the baseline is about a file linted so far
        self._builtin: dict[str | None, FileReport] = {}
        self.linted = 0
        self.code = 0

    def add(self, report: FileReport, fail_on: Severity) -> FileReport:
        """Count ``report`` (whose file's configuration fails on ``fail_on``) and say on
        stderr what its file's line there says; returns it without what the baseline
        withholds."""
        if self._remaining is not None:
            from xodrlint.engine.baseline import withhold_recorded

            keep = self._run.keep_suppressed
            root = cast("Baseline", self._run.baseline).root
            before = len(report.findings)
            report = withhold_recorded(report, self._remaining, root, keep=keep)
            self.withheld += before - len(report.findings)
            if not self.matched and report.error is None:
                self.matched = cast("Baseline", self._run.baseline).covers(report.path)
        if report.error is None:
            self.linted += 1
        # exit_code over all reports is the largest of each report's own: 3 before 2
        # before 1 before 0, and --exit-zero turns only findings to 0
        own = exit_code((report,), fail_on, self._run.exit_zero)
        self.code = max(self.code, own)
        self._not_applied.add(report)
        hidden = hidden_note(report)
        if hidden is not None:
            self._hidden.append(hidden)
        version = report.declared_version
        if report.schema_builtin and version not in self._builtin:
            self._builtin[version] = FileReport(
                report.path, declared_version=version, schema_builtin=True
            )
        if self._run.verbose:
            from xodrlint.cli.check.verbose import describe_file

            describe_file(report)
        if report.error:
            error_line(one_line(report.error))  # it names the file: escaped
        for crash in report.internal_errors:
            error_line(f"internal error: {crash}")
        return report

    def notes(self) -> tuple[str, ...]:
        return (
            *run_notes(self._builtin.values()),
            *self._not_applied.notes(self._rules),
            *self._hidden,
        )
