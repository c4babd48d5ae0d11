"""The JSON report: a documented public contract (``docs/json-output.schema.json``)."""

from __future__ import annotations

import json
from typing import Final, TextIO

from xodrlint.findings import FileReport, Finding, RunResult

#: Bumped only on incompatible changes to the shape below.
FORMAT_VERSION: Final = 1


class JsonFormatter:
    carries_notes = True
    shows_fixes = True  # each finding's "fix" with its edits
    says_withheld = True  # in its summary

    def render(self, result: RunResult, stream: TextIO) -> None:
        """Write ``json.dump(as_document(result), indent=2, ensure_ascii=False)``, byte
        for byte, with each finding written as it comes: the indenting encoder is pure
        Python (1.8 s for 200,000 findings) and the document of dicts a second copy of
        every finding; the findings' own lines are formatted here, their strings encoded
        by json's C escaper."""
        document = as_document(result, findings=False)
        stream.write("{")
        separator = "\n"
        for key, value in document.items():
            stream.write(f"{separator}  {_string(key)}: ")
            separator = ",\n"
            if key == "findings":
                _write_findings(result.findings, stream)
            else:
                stream.write(json.dumps(value, indent=2, ensure_ascii=False).replace("\n", "\n  "))
        stream.write("\n}\n")


def as_document(result: RunResult, *, findings: bool = True) -> dict[str, object]:
    """The report as one JSON value; ``findings=False`` leaves the findings list empty
    (:meth:`JsonFormatter.render` writes it finding by finding)."""
    every = result.findings
    return {
        "format_version": FORMAT_VERSION,
        "tool": {"name": "xodrlint", "version": result.tool_version},
        "files": [_file(report) for report in result.reports],
        "findings": [finding.as_dict() for finding in every] if findings else [],
        "summary": summary(result),
        "notes": list(result.notes),
    }


def summary(result: RunResult) -> dict[str, object]:
    """The counts of a run (the report's ``summary``; ``--statistics`` gives it too)."""
    counts: dict[str, object] = {
        "files": len(result.reports),
        "files_with_findings": sum(1 for r in result.reports if r.findings),
        "unreadable_files": sum(1 for r in result.reports if r.error),
        "findings": len(result.findings),
        "by_severity": result.count_by_severity(),
    }
    if result.baseline is not None:
        counts["baseline"] = {"file": result.baseline, "withheld": result.withheld}
    return counts


def _file(report: FileReport) -> dict[str, object]:
    return {
        "path": report.path,
        "declared_version": report.declared_version,
        "schema": (
            None
            if report.schema is None
            else {
                "description": report.schema,
                "builtin": report.schema_builtin,
                "note": report.schema_note,
            }
        ),
        "findings": len(report.findings),
        "error": report.error,
        "internal_errors": list(report.internal_errors),
        "rules_not_applied": list(report.rules_not_applied),
    }


#: How ``json.dumps(..., ensure_ascii=False)`` writes a string (C where available).
_string: Final = json.encoder.encode_basestring


def _write_findings(findings: tuple[Finding, ...], stream: TextIO) -> None:
    """The findings list as ``json.dumps(indent=2)`` lays it out at depth 1."""
    if not findings:
        stream.write("[]")
        return
    stream.write("[")
    separator = "\n"
    for finding in findings:
        stream.write(separator)
        stream.write(_finding(finding))
        separator = ",\n"
    stream.write("\n  ]")


def _other_file(path: str | None) -> str:
    return "" if path is None else f',\n          "path": {_string(path)}'


def _finding(finding: Finding) -> str:
    column = "null" if finding.column is None else str(int(finding.column))
    if finding.related:
        related = (
            "[\n"
            + ",\n".join(
                f'        {{\n          "line": {int(location.line)},\n'
                f'          "xpath": {_string(location.xpath)}{_other_file(location.path)}'
                "\n        }"
                for location in finding.related
            )
            + "\n      ]"
        )
    else:
        related = "[]"
    return (
        f'    {{\n      "path": {_string(finding.path)},\n'
        f'      "line": {int(finding.line)},\n'
        f'      "column": {column},\n'
        f'      "code": {_string(finding.code)},\n'
        f'      "uid": {_string(finding.uid)},\n'
        f'      "severity": {_string(str(finding.severity))},\n'
        f'      "message": {_string(finding.message)},\n'
        f'      "xpath": {_string(finding.xpath)},\n'
        f'      "related": {related},\n'
        f'      "fix": {_fix(finding)}\n    }}'
    )


def _fix(finding: Finding) -> str:
    """The finding's fix as ``json.dumps(indent=2)`` lays it out at depth 3 (rare: the
    plain encoder serves)."""
    if finding.fix is None:
        return "null"
    return json.dumps(finding.fix.as_dict(), indent=2, ensure_ascii=False).replace("\n", "\n      ")
