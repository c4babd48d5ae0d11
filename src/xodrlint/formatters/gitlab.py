"""GitLab Code Quality (the Code Climate subset GitLab reads): a JSON array of issues.

Each finding is ``{"description", "check_name", "fingerprint", "severity", "location":
{"path", "lines": {"begin"}}}``. ``path`` is relative to the run's root (the checkout);
``fingerprint`` is :func:`xodrlint.findings.fingerprints` (rule, path and XPath; unique
within the report and unchanged when lines move), the same as SARIF's.

Severities (GitLab knows info, minor, major, critical, blocker):

====================================  ============
xodrlint                              GitLab
====================================  ============
info                                  ``info``
warning                               ``minor``
error                                 ``major``
XS001, the file is not XML at all     ``critical``
====================================  ============

A file that could not be read (missing, unreadable, too large, a FIFO) is an issue too,
with ``check_name`` ``xodrlint:unreadable`` and severity ``blocker``, at line 1, and so is a
rule that crashed on a file (``xodrlint:internal-error``): the merge request shows that a
file went unchecked, and the CLI says it on stderr and exits 2 (or 3). Written as UTF-8
without a byte order mark, non-ASCII kept as is.
"""

from __future__ import annotations

import json
from typing import Final, TextIO

from xodrlint.findings import Finding, RunResult, Severity

from ._common import MALFORMED, report_path, run_fingerprints, single_line

SEVERITY: Final = {Severity.INFO: "info", Severity.WARNING: "minor", Severity.ERROR: "major"}
UNPARSEABLE_SEVERITY: Final = "critical"
#: A file that went unchecked: worse than any finding in it could be.
UNCHECKED_SEVERITY: Final = "blocker"
UNREADABLE_CHECK: Final = "xodrlint:unreadable"
INTERNAL_ERROR_CHECK: Final = "xodrlint:internal-error"


class GitlabFormatter:
    def render(self, result: RunResult, stream: TextIO) -> None:
        json.dump(as_code_quality(result), stream, indent=2, ensure_ascii=False)
        stream.write("\n")


def severity(finding: Finding) -> str:
    return UNPARSEABLE_SEVERITY if finding.code == MALFORMED else SEVERITY[finding.severity]


def as_code_quality(result: RunResult) -> list[dict[str, object]]:
    return _finding_issues(result) + _unchecked_issues(result)


def _finding_issues(result: RunResult) -> list[dict[str, object]]:
    return [
        {
            "description": f"{finding.code} {finding.message}",
            "check_name": finding.code,
            "fingerprint": fingerprint,
            "severity": severity(finding),
            "location": {
                "path": report_path(finding.path, result),
                "lines": {"begin": finding.line},
            },
        }
        for finding, fingerprint in zip(result.findings, run_fingerprints(result), strict=True)
    ]


def _unchecked_issues(result: RunResult) -> list[dict[str, object]]:
    """An issue per file that could not be read and per rule that crashed on a file."""
    import hashlib

    issues: list[dict[str, object]] = []
    for report in result.reports:
        path = report_path(report.path, result)
        problems = [(UNREADABLE_CHECK, report.error)] if report.error else []
        problems += [(INTERNAL_ERROR_CHECK, crash) for crash in report.internal_errors]
        for check, text in problems:
            key = "\x1f".join((check, path, text))
            issues.append(
                {
                    "description": single_line(text),
                    "check_name": check,
                    "fingerprint": hashlib.sha256(key.encode()).hexdigest()[:32],
                    "severity": UNCHECKED_SEVERITY,
                    "location": {"path": path, "lines": {"begin": 1}},
                }
            )
    return issues
