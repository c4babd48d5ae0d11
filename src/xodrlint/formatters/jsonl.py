"""JSON Lines, for pipelines: one JSON object per line, written file by file as each file
is done (``docs/jsonl-output.schema.json``).

A finding's line is the object a finding is in the JSON report (the same keys, the same
values); a file that could not be read is ``{"path": ..., "error": ...}``, and each
internal error of a file (a rule that crashed or ran out of time on it: its findings
may be incomplete, and the run exits 3) ``{"path": ..., "internal_error": ...}``, so a
reader tells them apart by their keys. Nothing else is written: no summary, no
header, no notes (the command prints the run's notes, what was not checked, on stderr
after the last line), and a file without findings writes no line.

:meth:`JsonlFormatter.write_file` is the streaming form the command line uses (each
file's lines as it completes, in the order files complete); :meth:`JsonlFormatter.render`
writes a whole run in input order, for ``--report jsonl=FILE`` beside another format.
"""

from __future__ import annotations

import json
import re
from typing import Final, TextIO

from xodrlint.findings import FileReport, Finding, RunResult

#: Characters that ``json.dumps(ensure_ascii=False)`` leaves raw but that line readers
#: other than ``for line in file`` split on (``str.splitlines``, JavaScript's line
#: terminators): escaped, so one object is one line for every reader.
_LINE_BREAKS: Final = str.maketrans({"\x85": "\\u0085", "\u2028": "\\u2028", "\u2029": "\\u2029"})


class JsonlFormatter:
    shows_fixes = True  # each finding's "fix" with its edits

    def render(self, result: RunResult, stream: TextIO) -> None:
        for report in result.reports:
            self.write_file(report, stream)

    def write_file(self, report: FileReport, stream: TextIO) -> None:
        """The lines of one file: its error, or one per finding in the report's order."""
        if report.error is not None:
            error = f'{{"path":{_string(report.path)},"error":{_string(report.error)}}}'
            stream.write(_escaped(error))
        for finding in report.findings:
            stream.write(line(finding))
        for crash in report.internal_errors:  # what the findings may lack (exit 3)
            failed = f'{{"path":{_string(report.path)},"internal_error":{_string(crash)}}}'
            stream.write(_escaped(failed))


#: How ``json.dumps(..., ensure_ascii=False)`` writes a string (C where available).
_string: Final = json.encoder.encode_basestring
_BREAK: Final = re.compile("[\x85\u2028\u2029]")


def line(finding: Finding) -> str:
    """``json.dumps(finding.as_dict(), ensure_ascii=False, separators=(",", ":"))`` and a
    line break, in a fifth of its time (the parent of a streaming run writes every line
    while its workers lint, on the same cores): character for character, but that
    U+0085, U+2028 and U+2029 are written as ``\\u`` escapes, which ``json.dumps`` leaves
    raw and line-splitting readers take for line breaks. Numbers are written as plain
    ``int``: a subclass's ``__format__`` (a plugin's) could write anything there."""
    column = "null" if finding.column is None else str(int(finding.column))
    related = ",".join(
        f'{{"line":{int(location.line)},"xpath":{_string(location.xpath)}'
        + ("" if location.path is None else f',"path":{_string(location.path)}')
        + "}"
        for location in finding.related
    )
    text = (
        f'{{"path":{_string(finding.path)},"line":{int(finding.line)},"column":{column},'
        f'"code":{_string(finding.code)},"uid":{_string(finding.uid)},'
        f'"severity":{_string(str(finding.severity))},"message":{_string(finding.message)},'
        f'"xpath":{_string(finding.xpath)},"related":[{related}],"fix":{_fix(finding)}}}'
    )
    return _escaped(text)


def _fix(finding: Finding) -> str:
    if finding.fix is None:
        return "null"
    return json.dumps(finding.fix.as_dict(), ensure_ascii=False, separators=(",", ":"))


def _escaped(text: str) -> str:
    if _BREAK.search(text) is not None:
        text = text.translate(_LINE_BREAKS)
    return text + "\n"
