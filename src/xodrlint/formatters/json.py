"""The JSON report: a documented public contract (``docs/json-output.schema.json``)."""

from __future__ import annotations

import json
from typing import Final, TextIO

from xodrlint.findings import FileReport, RunResult

#: Bumped only on incompatible changes to the shape below.
FORMAT_VERSION: Final = 1


class JsonFormatter:
    def __init__(self, *, show_source: bool = False, quiet: bool = False) -> None:
        del show_source, quiet  # the JSON document is always complete

    def render(self, result: RunResult, stream: TextIO) -> None:
        json.dump(as_document(result), stream, indent=2, ensure_ascii=False)
        stream.write("\n")


def as_document(result: RunResult) -> dict[str, object]:
    findings = result.findings
    return {
        "format_version": FORMAT_VERSION,
        "tool": {"name": "xodrlint", "version": result.tool_version},
        "files": [_file(report) for report in result.reports],
        "findings": [finding.as_dict() for finding in findings],
        "summary": {
            "files": len(result.reports),
            "files_with_findings": sum(1 for r in result.reports if r.findings),
            "unreadable_files": sum(1 for r in result.reports if r.error),
            "findings": len(findings),
            "by_severity": result.count_by_severity(),
        },
        "notes": list(result.notes),
    }


def _file(report: FileReport) -> dict[str, object]:
    return {
        "path": report.path,
        "declared_version": report.declared_version,
        "schema": (
            None
            if report.schema is None
            else {"description": report.schema, "builtin": report.schema_builtin}
        ),
        "findings": len(report.findings),
        "error": report.error,
    }
