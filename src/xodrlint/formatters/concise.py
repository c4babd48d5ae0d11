"""One line per finding, ``path:line:column: CODE [severity] message``, for editors and
grep (``path:line: ...`` where a finding has no column: a parse error libxml2 gave none).

Nothing else in the report: no summary, no notes (the command prints the run's notes,
what was not checked, on stderr after the findings, with or without ``--quiet``).
Files that could not be read are not findings (the CLI reports them on stderr). Paths are
as given on the command line, like the text report's; a line break inside a message
becomes a space, so each finding stays one line.
"""

from __future__ import annotations

from typing import TextIO

from xodrlint.findings import Finding, RunResult
from xodrlint.messages import one_line

from ._common import single_line


class ConciseFormatter:
    def render(self, result: RunResult, stream: TextIO) -> None:
        for finding in result.findings:
            stream.write(line(finding) + "\n")


def line(finding: Finding) -> str:
    column = "" if finding.column is None else f":{finding.column}"
    return (
        f"{one_line(finding.path)}:{finding.line}{column}: {finding.code} "
        f"[{finding.severity}] {single_line(finding.message)}"
    )
