"""Streaming: the engines' shape (``(index, FileReport)`` pairs as files complete) and
``--output-format jsonl``, which writes each file's lines as soon as it is done, keeps no
report, and says of every file what the JSON report says."""

from __future__ import annotations

import gc
import io
import json
import os
import re
import shutil
import stat
import subprocess
import sys
import threading
import time
import tracemalloc
from collections import Counter
from collections.abc import Iterator, Sequence
from itertools import product
from pathlib import Path
from typing import Any, TextIO

import jsonschema  # type: ignore[import-untyped, unused-ignore]
import pytest
from hypothesis import given
from hypothesis import strategies as st
from referencing import Registry, Resource

from tests.conftest import REPO, record_forks
from xodrlint.api import default_registry, exit_code
from xodrlint.cli.check.inputs import collect
from xodrlint.cli.check.request import CheckRequest
from xodrlint.cli.check.run import prepare_linter, run_check
from xodrlint.cli.check.stream import Source, Streamed, run_stream, stream_inputs
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import FileReport, Finding, Location, RunResult, Severity
from xodrlint.formatters import get_formatter, streaming
from xodrlint.formatters.jsonl import JsonlFormatter
from xodrlint.runners import batch
from xodrlint.runners.batch import ReportStream, Task, in_order, lint_tasks, stream_tasks

from .test_cli import BROKEN, CLEAN, OUTPUT_SCHEMA, cli

TWO = REPO / "examples" / "two-findings.xodr"
CONSOLE_SCRIPT = Path(sys.executable).parent / "xodrlint"
LINE_SCHEMA = json.loads((REPO / "docs" / "jsonl-output.schema.json").read_text("utf-8"))
needs_fork = pytest.mark.skipif(not hasattr(os, "fork"), reason="needs os.fork")


def _line_validator() -> jsonschema.Draft202012Validator:
    # a finding's line is the JSON report's finding: the schema takes it from there
    registry: Registry[Any] = Registry().with_resource(
        OUTPUT_SCHEMA["$id"], Resource.from_contents(OUTPUT_SCHEMA)
    )
    return jsonschema.Draft202012Validator(LINE_SCHEMA, registry=registry)


def lines_of(stdout: str) -> list[dict[str, Any]]:
    """Each line of a jsonl report, parsed alone and checked against the line schema."""
    validator = _line_validator()
    parsed = []
    for line in stdout.splitlines():
        value = json.loads(line)
        validator.validate(value)
        parsed.append(value)
    return parsed


def _copies(folder: Path, count: int, source: Path = TWO) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    paths = [folder / f"m{index:04}.xodr" for index in range(count)]
    for path in paths:
        shutil.copyfile(source, path)
    return paths


# The engine's shape --------------------------------------------------------------------


def _tasks(paths: Sequence[Path]) -> list[Task]:
    return [Task(path, path.name) for path in paths]


@pytest.mark.parametrize("jobs", [1, 2])
def test_stream_tasks_yields_every_task_once_with_its_index(tmp_path: Path, jobs: int) -> None:
    paths = [*_copies(tmp_path, 5), tmp_path / "missing.xodr"]
    linter = Linter(default_registry(), LintOptions())
    pairs = list(stream_tasks(linter, _tasks(paths), jobs))
    assert sorted(index for index, _ in pairs) == list(range(6))
    assert all(report.path == paths[index].name for index, report in pairs)
    if jobs == 1:  # one process: one by one, in their order
        assert [index for index, _ in pairs] == list(range(6))
    untimed = [report._replace(timings={}) for report in in_order(iter(pairs), 6)]
    assert untimed == [r._replace(timings={}) for r in lint_tasks(linter, _tasks(paths), 1)]


def test_in_order_puts_a_stream_in_order_and_never_loses_a_file() -> None:
    first, second = FileReport("a.xodr"), FileReport("b.xodr")
    assert in_order(iter([(1, second), (0, first)]), 2) == [first, second]
    with pytest.raises(RuntimeError, match="no report for task 1 of 2"):
        in_order(iter([(0, first)]), 2)


def _marking_worker(task: Task) -> FileReport:
    """Lints as workers do, leaving a mark beside each file it linted."""
    task.path.with_suffix(".linted").touch()
    return batch.lint_in_worker(task)


@needs_fork
@pytest.mark.parametrize("forked", [True, False])
def test_a_caller_that_stops_early_stops_the_workers_at_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, forked: bool
) -> None:
    monkeypatch.setattr(batch, "FORK_WORKERS", forked)
    started = record_forks(monkeypatch)
    linter = Linter(default_registry(), LintOptions())
    stream = stream_tasks(linter, _tasks(_copies(tmp_path, 80)), 2, worker=_marking_worker)
    next(stream)
    stream.close()
    # the files not yet handed out are never linted: the workers are gone, or the
    # executor's queued messages cancelled
    assert len(list(tmp_path.glob("*.linted"))) < 80
    for pid in started:  # each forked worker was stopped and waited for
        with pytest.raises(ChildProcessError):
            os.waitpid(pid, os.WNOHANG)
    if forked:
        assert len(started) == 2


def test_an_engine_of_any_kind_serves_the_command_line(tmp_path: Path) -> None:
    # the Dask engine has the forked pool's shape: the CLI takes any function from tasks
    # to (index, report) pairs, in whatever order they complete
    paths = _copies(tmp_path, 3)
    request = CheckRequest(paths=(str(tmp_path),), output_format="jsonl")
    settings, linter = prepare_linter(default_registry(), request)
    inputs = collect(request.paths, settings)

    def backwards(tasks: Sequence[Task]) -> ReportStream:
        for index in reversed(range(len(tasks))):
            yield index, linter.lint_path(tasks[index].path, tasks[index].display)

    pairs = list(stream_inputs(Source(linter, settings, inputs, backwards)))
    assert [index for index, _ in pairs] == [2, 1, 0]
    assert [report.path for _, report in pairs] == [str(p) for p in reversed(paths)]


def test_inputs_the_engine_does_not_lint_keep_their_place(tmp_path: Path) -> None:
    paths = _copies(tmp_path, 2)
    # named to sort in this order: inputs are linted and reported by name
    named = (str(paths[0]), str(tmp_path / "m0000z.xodr"), str(paths[1]), str(tmp_path / "x"))
    request = CheckRequest(paths=named)
    settings, linter = prepare_linter(default_registry(), request)
    inputs = collect(named, settings)
    engine = lambda tasks: stream_tasks(linter, tasks, 1)  # noqa: E731
    pairs = list(stream_inputs(Source(linter, settings, inputs, engine)))
    assert [index for index, _ in pairs] == [0, 1, 2, 3]
    assert [bool(report.error) for _, report in pairs] == [False, True, False, True]


# jsonl: the same findings as the JSON report ------------------------------------------


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_jsonl_lines_are_the_json_reports_findings(jobs: str) -> None:
    paths = [REPO / "examples", REPO / "rules" / "PT003", REPO / "rules" / "ST004"]
    streamed = cli("check", "-f", "jsonl", "-j", jobs, *paths, code=1)
    whole = json.loads(cli("check", "-f", "json", "-j", jobs, *paths, code=1).stdout)
    lines = lines_of(streamed.stdout)
    assert len(lines) > 10
    as_text = Counter(json.dumps(line, sort_keys=True) for line in lines)
    assert as_text == Counter(json.dumps(f, sort_keys=True) for f in whole["findings"])
    if jobs == "1":  # one job: input order, findings as the JSON report sorts them
        assert lines == whole["findings"]


def test_an_unreadable_file_gives_its_line_in_its_place(tmp_path: Path) -> None:
    missing = tmp_path / "missing.xodr"
    result = cli("check", "-f", "jsonl", "-j", "1", BROKEN, missing, TWO, code=2)
    lines = lines_of(result.stdout)
    codes_by_file = {
        missing: ["error"],
        BROKEN: ["XS006", "XS006", "SW006", "RL003", "ST004", "XS006"],
        TWO: ["PT003", "ST004"],
    }
    # by name, wherever the checkout lives relative to the temporary folder
    by_name = sorted(codes_by_file, key=lambda path: path.parts)
    expected = [code for path in by_name for code in codes_by_file[path]]
    assert [line.get("code", "error") for line in lines] == expected
    error = f"{missing}: no such file or directory"
    assert {"path": str(missing), "error": error} in lines
    assert f"xodrlint: {error}\n" in result.stderr


def test_jsonl_exit_codes_are_those_of_every_format(tmp_path: Path) -> None:
    assert cli("check", "-f", "jsonl", CLEAN, code=0).stdout == ""
    cli("check", "-f", "jsonl", BROKEN, "--exit-zero", code=0)
    only_warning = tmp_path / "warning.xodr"
    only_warning.write_text(CLEAN.read_text("utf-8").replace('revMinor="7"', 'revMinor="12"'))
    cli("check", "-f", "jsonl", only_warning, code=1)
    cli("check", "-f", "jsonl", only_warning, "--fail-on", "error", code=0)


def test_the_exit_code_of_a_run_is_the_largest_of_its_files() -> None:
    # what lets a streaming run keep one number instead of its reports
    finding = {
        severity: Finding("a", 1, None, "XS006", "u", severity, "m", "/") for severity in Severity
    }
    kinds = [
        FileReport("clean"),
        FileReport("crash", internal_errors=("boom",)),
        FileReport("gone", error="gone: no such file"),
        *(FileReport(str(s), findings=(f,)) for s, f in finding.items()),
    ]
    for count, fail_on, exit_zero in product((1, 2, 3), Severity, (False, True)):
        for reports in product(kinds, repeat=count):
            each = max(exit_code((report,), fail_on, exit_zero) for report in reports)
            assert each == exit_code(reports, fail_on, exit_zero)


def test_jsonl_reads_standard_input_under_its_given_name() -> None:
    result = cli(
        "check", "-f", "jsonl", "-", "--stdin-filename", "maps/in.xodr",
        code=1, stdin=BROKEN.read_bytes(),
    )  # fmt: skip
    assert {line["path"] for line in lines_of(result.stdout)} == {"maps/in.xodr"}


def test_notes_and_verbose_lines_go_to_stderr_file_by_file(tmp_path: Path) -> None:
    result = cli("check", "-f", "jsonl", "-v", "-j", "1", BROKEN, CLEAN, code=1)
    assert len(lines_of(result.stdout)) == 6
    errors = result.stderr.splitlines()
    assert "xodrlint: files: 2, linted in this process" in errors
    described = [line for line in errors if line.startswith(("xodrlint: /", "xodrlint: examples"))]
    assert [line.split(":")[1].strip() for line in described] == [str(BROKEN), str(CLEAN)]
    assert errors[-2].startswith("xodrlint: note: only railroad elements were validated")
    assert errors[-1].startswith("xodrlint: linted 2 files in ")


def test_the_baseline_is_applied_file_by_file(tmp_path: Path) -> None:
    baseline = tmp_path / "baseline.json"
    cli("check", BROKEN, "--write-baseline", baseline, "-f", "jsonl", code=0)
    assert json.loads(baseline.read_text("utf-8"))["findings"]  # written, not streamed
    result = cli("check", "-f", "jsonl", "--baseline", baseline, BROKEN, TWO, code=1)
    assert {line["path"] for line in lines_of(result.stdout)} == {str(TWO)}
    cli("check", "-f", "jsonl", "--baseline", baseline, BROKEN, code=0)


def test_what_needs_every_report_is_refused_before_linting(tmp_path: Path) -> None:
    refused = cli("check", "-f", "jsonl", "--statistics", BROKEN, code=2)
    assert refused.stderr == (
        "xodrlint: --statistics: the jsonl format cannot hold statistics "
        "(use text, concise or json)\n"
    )
    sarif = tmp_path / "out.sarif"
    refused = cli("check", "-f", "jsonl", "--report", f"sarif={sarif}", BROKEN, code=2)
    assert refused.stderr == (
        f"xodrlint: --report sarif={sarif}: -f jsonl writes findings as files are done and "
        "keeps no reports to write another from (for both from one run: -f sarif --report "
        "jsonl=FILE)\n"
    )
    assert refused.stdout == "" and not sarif.exists()


def test_jsonl_as_a_report_file_beside_another_format(tmp_path: Path) -> None:
    target = tmp_path / "findings.jsonl"
    whole = cli("check", "-f", "json", "--report", f"jsonl={target}", BROKEN, TWO, code=1)
    assert lines_of(target.read_text("utf-8")) == json.loads(whole.stdout)["findings"]


def test_output_to_a_file_and_a_full_disk(tmp_path: Path) -> None:
    target = tmp_path / "out.jsonl"
    assert cli("check", "-f", "jsonl", "-o", target, BROKEN, code=1).stdout == ""
    assert len(lines_of(target.read_text("utf-8"))) == 6
    assert [p.name for p in tmp_path.iterdir()] == ["out.jsonl"]  # no temp file left
    if Path("/dev/full").exists():
        full = cli("check", "-f", "jsonl", "-o", "/dev/full", BROKEN, code=2)
        assert full.stderr.splitlines()[0] == (
            "xodrlint: --output /dev/full: cannot write: no space left on device"
        )


def test_a_fifo_named_by_output_gets_the_lines_as_written(tmp_path: Path) -> None:
    fifo = tmp_path / "lines"
    os.mkfifo(fifo)
    received: list[bytes] = []
    reader = threading.Thread(target=lambda: received.append(fifo.read_bytes()))
    reader.start()
    cli("check", "-f", "jsonl", "-o", fifo, BROKEN, TWO, code=1)
    reader.join(timeout=30)
    assert stat.S_ISFIFO(fifo.lstat().st_mode)  # written into, not replaced
    assert len(lines_of(received[0].decode("utf-8"))) == 8


def test_an_error_of_the_engine_is_no_error_of_the_output(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # an OSError while linting (a fork the system refused) is an internal error, as in
    # every other format, never "cannot write"
    def refused(*_: object, **__: object) -> Iterator[tuple[int, FileReport]]:
        raise BlockingIOError(11, "Resource temporarily unavailable")
        yield  # a generator, as the engines are

    monkeypatch.setattr("xodrlint.cli.check.run.stream_tasks", refused)
    with pytest.raises(BlockingIOError):
        run_check(CheckRequest(paths=(str(BROKEN),), output_format="jsonl", output=os.devnull))


def test_a_reader_that_stops_after_the_first_line(tmp_path: Path) -> None:
    if not CONSOLE_SCRIPT.is_file():
        pytest.skip(f"no console script at {CONSOLE_SCRIPT}")
    _copies(tmp_path, 40, BROKEN)
    done = subprocess.run(
        f"{CONSOLE_SCRIPT} check -f jsonl -j 2 {tmp_path} | head -n 1 >/dev/null;"
        " exit ${PIPESTATUS[0]}",
        shell=True,
        executable="/bin/bash",
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    errors = [line for line in done.stderr.splitlines() if "note:" not in line]
    assert (done.returncode, errors) == (1, [])  # the run's own exit code, no error


def test_line_breaks_that_line_readers_split_on_are_escaped() -> None:
    message = "a\u2028b\u2029c\x85d\ne"
    finding = Finding("p.xodr", 3, 5, "XS006", "u", Severity.ERROR, message, "/")
    stream = io.StringIO()
    JsonlFormatter().write_file(FileReport("p.xodr", findings=(finding,)), stream)
    text = stream.getvalue()
    assert len(text.splitlines()) == 1 and text.endswith("\n")
    assert json.loads(text)["message"] == message
    assert streaming(JsonlFormatter()) is not None
    assert streaming(get_formatter("json")) is None


_TEXT = st.text(st.characters(exclude_categories=["Cs"]), min_size=1)


@given(
    path=_TEXT,
    line=st.integers(1, 10**9),
    column=st.none() | st.integers(1, 10**6),
    message=_TEXT,
    xpath=_TEXT.map(lambda text: "/" + text),
    related=st.lists(st.tuples(st.integers(1, 10**6), _TEXT), max_size=3),
    severity=st.sampled_from(Severity),
)
def test_a_line_is_what_json_dumps_writes(
    path: str,
    line: int,
    column: int | None,
    message: str,
    xpath: str,
    related: list[tuple[int, str]],
    severity: Severity,
) -> None:
    # written by hand for speed: it must stay the finding of the JSON report, exactly
    locations = tuple(Location(number, where) for number, where in related)
    finding = Finding(path, line, column, "XS006", "u:id", severity, message, xpath, locations)
    stream = io.StringIO()
    JsonlFormatter().write_file(FileReport(path, findings=(finding,)), stream)
    dumped = json.dumps(finding.as_dict(), ensure_ascii=False, separators=(",", ":"))
    escaped = dumped.replace("\x85", "\\u0085").replace("\u2028", "\\u2028")
    assert stream.getvalue() == escaped.replace("\u2029", "\\u2029") + "\n"
    assert json.loads(stream.getvalue()) == finding.as_dict()


def test_render_writes_a_whole_run_in_input_order() -> None:
    reports = (FileReport("a", error="a: gone"), FileReport("b"))
    stream = io.StringIO()
    JsonlFormatter().render(RunResult(reports, (), "0"), stream)
    assert stream.getvalue() == '{"path":"a","error":"a: gone"}\n'


# Streaming: the first line early, memory flat ------------------------------------------


class _Stdout(io.StringIO):
    """Standard output that records, at each flush, that a line has been written."""

    def __init__(self, flushed: Path) -> None:
        super().__init__()
        self.flushed = flushed

    def flush(self) -> None:
        super().flush()
        if self.getvalue():
            self.flushed.touch()


@pytest.mark.parametrize("jobs", [1, 2])
def test_the_first_line_is_written_before_the_last_file_is_linted(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, jobs: int
) -> None:
    maps = tmp_path / "maps"
    _copies(maps, 4)
    shutil.copyfile(TWO, maps / "zz-last.xodr")
    flushed = tmp_path / "a line was flushed"
    real = Linter.lint_path

    def lint_path(self: Linter, path: Path, shown: str, *args: Any, **named: Any) -> FileReport:
        # the last file (in a forked worker too) waits until a line is out, then says
        # whether one came while it waited
        if Path(path).name == "zz-last.xodr":
            deadline = time.monotonic() + 20
            while not flushed.exists() and time.monotonic() < deadline:
                time.sleep(0.01)
            if not flushed.exists():
                return FileReport(shown, error="no line was written before the last file")
        return real(self, path, shown, *args, **named)

    monkeypatch.setattr(Linter, "lint_path", lint_path)
    stdout = _Stdout(flushed)
    monkeypatch.setattr(sys, "stdout", stdout)
    code = run_check(CheckRequest(paths=(str(maps),), output_format="jsonl", jobs=jobs))
    lines = lines_of(stdout.getvalue())
    assert (code, [line for line in lines if "error" in line]) == (1, [])
    assert Counter(Path(line["path"]).name for line in lines) == dict.fromkeys(
        ("m0000.xodr", "m0001.xodr", "m0002.xodr", "m0003.xodr", "zz-last.xodr"), 2
    )


class _Measuring(JsonlFormatter):
    """jsonl that notes, at the last file, what the run holds: Python's allocations
    still alive (a full collection first: garbage and free lists are no holding)."""

    def __init__(self, files: int, *, keep: bool = False) -> None:
        super().__init__()
        self.files, self.written, self.held = files, 0, 0
        self.kept: list[FileReport] | None = [] if keep else None

    def write_file(self, report: FileReport, stream: TextIO) -> None:
        super().write_file(report, stream)
        self.written += 1
        if self.kept is not None:  # a run that keeps every report, for comparison
            self.kept.append(report)
        if self.written == self.files:
            gc.collect()
            self.held = tracemalloc.get_traced_memory()[0]


def _held_by_a_streaming_run(folder: Path, files: int, *, keep: bool = False) -> int:
    """What the streaming loop of a jsonl run over ``folder`` holds at its last file,
    beyond what it held before (its inputs, collected beforehand)."""
    request = CheckRequest(paths=(str(folder),), output_format="jsonl")
    settings, linter = prepare_linter(default_registry(), request)
    inputs = collect(request.paths, settings)
    source = Source(linter, settings, inputs, lambda tasks: stream_tasks(linter, tasks, 1))
    run_stream(source, JsonlFormatter(), Streamed(os.devnull))  # schemas compiled, warm
    measuring = _Measuring(files, keep=keep)
    gc.collect()
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        assert run_stream(source, measuring, Streamed(os.devnull)) == 1
        return measuring.held - before
    finally:
        tracemalloc.stop()


def test_memory_of_a_streaming_run_stays_flat_as_files_grow(tmp_path: Path) -> None:
    _copies(tmp_path / "few", 20, BROKEN)
    _copies(tmp_path / "many", 200, BROKEN)
    few = _held_by_a_streaming_run(tmp_path / "few", 20)
    many = _held_by_a_streaming_run(tmp_path / "many", 200)
    # what one document leaves behind (the last tree, its validator's errors) does not
    # grow with the files; the loop's own index of the tasks is 8 bytes a file
    assert many - few < 64_000, (few, many)
    # the measure sees a run that keeps its reports (six findings each): 3 kB a file
    kept = _held_by_a_streaming_run(tmp_path / "many", 200, keep=True)
    assert kept - few > 400_000, (few, kept)


# docs/distributed.md: "## Streaming output" -------------------------------------------


def _streaming_commands() -> list[str]:
    text = (REPO / "docs" / "distributed.md").read_text("utf-8")
    start = text.index("\n## Streaming output\n")
    end = text.find("\n## ", start + 1)
    section = text[start : end if end != -1 else len(text)]
    blocks = re.findall(r"```sh\n(.*?)```", section, flags=re.DOTALL)
    return [line for block in blocks for line in block.splitlines() if line.strip()]


def test_the_streaming_section_shows_commands() -> None:
    commands = _streaming_commands()
    assert len(commands) >= 4 and all(c.startswith("xodrlint check ") for c in commands)


@pytest.mark.parametrize("command", _streaming_commands())
def test_a_streaming_command_runs(command: str, tmp_path: Path) -> None:
    if not CONSOLE_SCRIPT.is_file():
        pytest.skip(f"no console script at {CONSOLE_SCRIPT}")
    for tool in re.findall(r"\| (\w+)", command):
        if shutil.which(tool) is None:
            pytest.skip(f"{tool} is not installed")
    _copies(tmp_path / "maps", 3, BROKEN)
    _copies(tmp_path / "maps" / "more", 3)
    path = f"{CONSOLE_SCRIPT.parent}{os.pathsep}{os.environ['PATH']}"
    # run from the maps' folder: a source tree on the path must stay found from there
    given = os.environ.get("PYTHONPATH", "").split(os.pathsep)
    python_path = os.pathsep.join(str(Path(entry).resolve()) for entry in given if entry)
    done = subprocess.run(
        ["bash", "-o", "pipefail", "-c", command],
        cwd=tmp_path,
        env={**os.environ, "PATH": path, "PYTHONPATH": python_path},
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert done.returncode == 1, done.stderr  # the maps have errors: exit 1 through the pipe
    assert "Traceback" not in done.stderr
    written = [p for p in tmp_path.iterdir() if p.suffix == ".jsonl"]
    for output in written:  # what went to a file is lines of the format
        assert lines_of(output.read_text("utf-8"))
    if not written:
        assert done.stdout.strip()


def test_an_internal_error_is_a_line_of_its_own_and_in_the_json_report() -> None:
    # a pipeline reading jsonl or JSON tells which file's findings may be incomplete
    registry = default_registry()
    report = Linter(registry, LintOptions()).lint_path(TWO, "two.xodr")
    crashed = report._replace(internal_errors=("rule SW001 failed on two.xodr: KeyError('x')",))
    result = RunResult((crashed,), registry.metas, "0", root=str(REPO))
    stream = io.StringIO()
    get_formatter("jsonl").render(result, stream)
    lines = lines_of(stream.getvalue())
    assert lines[-1] == {
        "path": "two.xodr",
        "internal_error": "rule SW001 failed on two.xodr: KeyError('x')",
    }
    assert [line["code"] for line in lines[:-1]] == ["PT003", "ST004"]
    stream = io.StringIO()
    get_formatter("json").render(result, stream)
    document = json.loads(stream.getvalue())
    jsonschema.validate(document, OUTPUT_SCHEMA)
    assert document["files"][0]["internal_errors"] == list(crashed.internal_errors)


class _Sneaky(int):
    """An int whose text is JSON of a plugin's choosing (issue 30, item 12)."""

    def __str__(self) -> str:
        return '1,"injected":true'

    __repr__ = __format__ = lambda self, *_: str(self)  # type: ignore[assignment]


@pytest.mark.parametrize("kind", ["jsonl", "json"])
def test_numbers_are_written_as_plain_ints_whatever_their_type(kind: str) -> None:
    from xodrlint.findings import Finding, Location, Severity
    from xodrlint.formatters.json import _finding as render_finding
    from xodrlint.formatters.jsonl import line

    finding = Finding(
        "a.xodr", _Sneaky(3), _Sneaky(5), "HX001", "u", Severity.ERROR, "m", "/x",
        (Location(_Sneaky(7), "/y"),),
    )  # fmt: skip
    text = line(finding) if kind == "jsonl" else render_finding(finding)
    written = json.loads(text)
    assert "injected" not in written and written["line"] == 3 and written["column"] == 5
    assert written["related"] == [{"line": 7, "xpath": "/y"}]
