"""GitHub Actions workflow commands: one annotation line per finding, nothing else.

``::error file=PATH,line=N,title=CODE name::message`` (``::warning`` for warnings,
``::notice`` for infos; ``col=`` when the finding has a column). A file that could not be
read gets an ``::error`` line with its path and the reason. Paths are relative to the
run's root (the checkout), which is what GitHub resolves them against. Each of the run's
notes (what it did not check) is a ``::notice title=xodrlint::`` line of its own, after
the findings: an annotation of the run, on no file.

The message is escaped as workflow command data (``%``, CR, LF); property values (file,
title) also escape ``:`` and ``,``, which would otherwise end the value.
"""

from __future__ import annotations

from typing import Final, TextIO

from xodrlint.findings import Finding, RunResult, Severity

from ._common import report_path, rules_by_code

COMMAND: Final = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def escape_data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(text: str) -> str:
    return escape_data(text).replace(":", "%3A").replace(",", "%2C")


NOTE_TITLE: Final = "xodrlint"


class GithubFormatter:
    carries_notes = True

    def render(self, result: RunResult, stream: TextIO) -> None:
        names = {code: meta.name for code, meta in rules_by_code(result).items()}
        for report in result.reports:
            if report.error:
                path = escape_property(report_path(report.path, result))
                stream.write(f"::error file={path}::{escape_data(report.error)}\n")
            for finding in report.findings:
                stream.write(annotation(finding, report_path(finding.path, result), names))
        for note in result.notes:
            stream.write(f"::notice title={escape_property(NOTE_TITLE)}::{escape_data(note)}\n")


def annotation(finding: Finding, path: str, names: dict[str, str]) -> str:
    title = f"{finding.code} {names[finding.code]}" if finding.code in names else finding.code
    properties = [f"file={escape_property(path)}", f"line={finding.line}"]
    if finding.column is not None:
        properties.append(f"col={finding.column}")
    properties.append(f"title={escape_property(title)}")
    command = COMMAND[finding.severity]
    return f"::{command} {','.join(properties)}::{escape_data(finding.message)}\n"
