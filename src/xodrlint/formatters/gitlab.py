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

Files that could not be read are not findings and are left out (the CLI reports them on
stderr and exits 2). Written as UTF-8 without a byte order mark, non-ASCII kept as is.
"""

from __future__ import annotations

import json
from typing import Final, TextIO

from xodrlint.findings import Finding, RunResult, Severity

from ._common import MALFORMED, report_path, run_fingerprints

SEVERITY: Final = {Severity.INFO: "info", Severity.WARNING: "minor", Severity.ERROR: "major"}
UNPARSEABLE_SEVERITY: Final = "critical"


class GitlabFormatter:
    def __init__(self, *, show_source: bool = False, quiet: bool = False) -> None:
        del show_source, quiet  # the report is always complete

    def render(self, result: RunResult, stream: TextIO) -> None:
        json.dump(as_code_quality(result), stream, indent=2, ensure_ascii=False)
        stream.write("\n")


def severity(finding: Finding) -> str:
    return UNPARSEABLE_SEVERITY if finding.code == MALFORMED else SEVERITY[finding.severity]


def as_code_quality(result: RunResult) -> list[dict[str, object]]:
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
