"""What ``xodrlint check`` writes: its report (or ``--statistics``) and every
``--report FORMAT=PATH`` file, or the baseline of ``--write-baseline``, each refused
before any linting when it cannot be written safely, each written whole, and standard
output let go quietly when its reader stops early (``| head``)."""

from __future__ import annotations

import json
import os
import sys
from collections import Counter
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Final, NamedTuple, TextIO

from xodrlint.findings import FileReport, RunResult
from xodrlint.formatters import Formatter
from xodrlint.formatters.output import STDOUT, error_line, release, write_output
from xodrlint.inputs.files import os_reason, overwrites
from xodrlint.messages import plural

#: The formats that hold ``--statistics``: a table for people, a document for programs.
STATISTICS_FORMATS: Final = ("text", "concise", "json")


class OutputRefused(ValueError):
    """An output this run must not write: exit 2 with this one line, before linting."""


class ExtraReport(NamedTuple):
    """One ``--report FORMAT=PATH``."""

    format: str
    path: str

    @property
    def flag(self) -> str:
        return f"--report {self.format}={self.path}"


def parse_reports(entries: Iterable[str]) -> tuple[ExtraReport, ...]:
    """``FORMAT=PATH`` entries; the format is checked when its formatter is made."""
    reports = []
    for entry in entries:
        name, sign, path = entry.partition("=")
        if not sign or not name.strip() or not path:
            raise OutputRefused(f"--report {entry}: expected FORMAT=PATH")
        if path == STDOUT:
            raise OutputRefused(
                f"--report {entry}: a report file cannot be standard output "
                "(use --output-format for the report printed there)"
            )
        reports.append(ExtraReport(name.strip(), path))
    return tuple(reports)


def check_statistics_format(name: str) -> None:
    if name not in STATISTICS_FORMATS:
        raise OutputRefused(
            f"--statistics: the {name} format cannot hold statistics "
            f"(use {', '.join(STATISTICS_FORMATS[:-1])} or {STATISTICS_FORMATS[-1]})"
        )


def check_outputs(
    output: str | None,
    extra: Iterable[tuple[ExtraReport, object]],
    write_baseline: Path | None,
    inputs: Iterable[Path],
    config_files: Iterable[Path],
    baseline: Path | None,
) -> None:
    """Refuse, before any linting, an output of a check that would overwrite what the
    run reads (its inputs, every configuration file it read) or another output: its
    report (``output``) and ``extra`` reports, or the baseline it writes instead (which
    may replace the baseline it reads)."""
    targets: list[tuple[str, str | None]]
    read: list[tuple[str, Path | None]] = [("a config file", path) for path in config_files]
    extra = list(extra)
    if write_baseline is not None and (extra or output not in (None, STDOUT)):
        given = extra[0][0].flag if extra else f"--output {output}"
        raise OutputRefused(f"{given}: --write-baseline writes the baseline and no report")
    if write_baseline is not None:
        targets = [(f"--write-baseline {write_baseline}", str(write_baseline))]
    else:
        targets = [(f"--output {output}", output)]
        targets += [(report.flag, report.path) for report, _ in extra]
        read.append(("the baseline", baseline))
    check_targets(targets, inputs, read)


def check_targets(
    targets: Iterable[tuple[str, str | None]],
    inputs: Iterable[Path],
    read: Iterable[tuple[str, Path | None]],
) -> None:
    """Refuse, before any linting, an output that would overwrite an input or a file the
    run reads (``read``: what each is, e.g. "the baseline"), that is a folder or has no
    folder, or that two outputs share. ``targets`` pairs each output's flag (as errors
    name it) with its path (``None`` or ``-``: standard output)."""
    inputs, read = list(inputs), list(read)
    claimed: dict[object, str] = {}
    for flag, output in targets:
        if output in (None, STDOUT):
            continue
        target = Path(output)
        if overwrites(target, inputs):
            raise OutputRefused(f"{flag}: is one of the inputs; refusing to overwrite it")
        for what, path in read:
            if path is not None and overwrites(target, [path]):
                raise OutputRefused(f"{flag}: is {what} this run reads; refusing to overwrite it")
        if target.is_dir():
            raise OutputRefused(f"{flag}: is a folder")
        if not target.parent.is_dir():
            raise OutputRefused(f"{flag}: its folder {target.parent} does not exist")
        identity = _identity(target)
        if identity in claimed:
            raise OutputRefused(f"{flag}: {claimed[identity]} writes the same file")
        claimed[identity] = flag


def _identity(target: Path) -> object:
    """What names one file whatever the path says: its inode where it exists, else its
    path with every link resolved (no output exists yet, in the usual run)."""
    try:
        status = target.stat()
    except OSError:
        return os.path.realpath(target)
    return (status.st_dev, status.st_ino)


Render = Callable[[TextIO], None]


def write_reports(written: Iterable[tuple[str, str | None, Render]]) -> bool:
    """Write each (flag, path, render): files first, standard output last, so that a
    reader of standard output that stops early costs no file its report. A reader that
    stops early is no error (``check | head`` exits as the run would have); anything else
    that cannot be written is one line each. Returns whether everything was written."""
    ordered = sorted(written, key=lambda item: item[1] in (None, STDOUT))
    complete = True
    for flag, path, render in ordered:
        try:
            write_output(path, render)
        except BrokenPipeError:
            if path not in (None, STDOUT):  # a FIFO named by -o whose reader went away
                error_line(f"{flag}: cannot write: broken pipe")
                complete = False
                continue
            release(sys.stdout)
        except OSError as error:
            where = "standard output" if path in (None, STDOUT) else flag
            error_line(f"{where}: cannot write: {os_reason(error)}")
            complete = False
    return complete


def statistics_renderer(name: str, result: RunResult) -> Render:
    """``--statistics`` in the format ``name`` (one of :data:`STATISTICS_FORMATS`)."""
    if name == "json":
        return lambda stream: _statistics_json(result, stream)
    return lambda stream: _statistics_table(result, stream)


class _Row(NamedTuple):
    code: str
    findings: int
    severity: str
    name: str | None
    uid: str | None


def _rows(result: RunResult) -> list[_Row]:
    """One row per code that reported anything, most frequent first, then by code; the
    severity is the findings' own (the configuration may override a rule's)."""
    counts = Counter(finding.code for finding in result.findings)
    severities = {finding.code: str(finding.severity) for finding in result.findings}
    metas = {meta.code: meta for meta in result.rules}
    rows = []
    for code, count in sorted(counts.items(), key=lambda item: (-item[1], item[0])):
        meta = metas.get(code)
        name, uid = (meta.name, meta.uid) if meta else (None, None)
        rows.append(_Row(code, count, severities[code], name, uid))
    return rows


def _statistics_table(result: RunResult, stream: TextIO) -> None:
    rows = _rows(result)
    for row in rows:
        severity = f"[{row.severity}]"
        stream.write(f"{row.findings:>6}  {row.code}  {severity:<9} {row.name or ''}\n")
    if not rows:  # an empty table, not nothing: the run did count
        stream.write(f"{0:>6}  findings\n")


def _statistics_json(result: RunResult, stream: TextIO) -> None:
    """The document ``docs/json-statistics.schema.json`` describes."""
    from xodrlint.formatters.json import FORMAT_VERSION, summary  # a statistics run's

    document = {
        "format_version": FORMAT_VERSION,
        "tool": {"name": "xodrlint", "version": result.tool_version},
        "statistics": [
            {
                "code": r.code,
                "name": r.name,
                "uid": r.uid,
                "severity": r.severity,
                "count": r.findings,
            }
            for r in _rows(result)
        ],
        "summary": summary(result),
    }
    json.dump(document, stream, indent=2, ensure_ascii=False)
    stream.write("\n")


def report_renderer(formatter: Formatter, result: RunResult) -> Render:
    return lambda stream: formatter.render(result, stream)


def withheld_line(baseline: str, count: int) -> str:
    """What a run whose report has no summary says on stderr of its baseline's work."""
    return f"{baseline} withheld {plural(count, 'finding')} recorded in it"


def checkout_root(environ: Mapping[str, str] = os.environ) -> str:
    """The folder the CI formats (SARIF, GitLab's, GitHub's, JUnit) name paths relative
    to, whatever folder the run starts in: the CI service's checkout (GitLab's
    ``CI_PROJECT_DIR``, GitHub's ``GITHUB_WORKSPACE``) when set to a folder, else the top
    of the git repository holding the working folder, else the working folder."""
    for name in ("CI_PROJECT_DIR", "GITHUB_WORKSPACE"):
        given = environ.get(name)
        if given and Path(given).is_dir():
            return str(Path(given).absolute())
    here = Path.cwd()
    top = next((folder for folder in (here, *here.parents) if (folder / ".git").exists()), here)
    return str(top)


def write_baseline(path: Path, reports: list[FileReport]) -> int:
    """``--write-baseline FILE``: every finding of ``reports`` recorded in ``path``
    (relative to its folder); returns the exit code (2 when a file could not be read, so
    was not recorded)."""
    from xodrlint.engine.baseline import baseline_document

    document = baseline_document(reports, path)
    try:
        write_output(str(path), lambda stream: _dump(document, stream))
    except OSError as error:
        error_line(f"--write-baseline {path}: cannot write: {os_reason(error)}")
        return 2
    count = sum(len(r.findings) for r in reports)
    print(f"xodrlint: recorded {plural(count, 'finding')} in {path}", file=sys.stderr)
    return 2 if any(r.error for r in reports) else 0


def _dump(document: object, stream: TextIO) -> None:
    json.dump(document, stream, indent=2, ensure_ascii=False)
    stream.write("\n")
