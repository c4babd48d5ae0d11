"""What every lint result must look like, whatever the input: the check the mutation
tests and the atheris harness share."""

from __future__ import annotations

from functools import cache

from xodrlint.api import default_registry
from xodrlint.findings import FileReport, Severity


@cache
def _known_codes() -> frozenset[str]:
    return frozenset(meta.code for meta in default_registry().metas)


def assert_well_formed(report: FileReport) -> None:
    """No rule crashed, and every finding names a known rule, a real position and one line
    of message."""
    assert report.internal_errors == (), report.internal_errors
    for finding in report.findings:
        assert finding.code in _known_codes(), finding
        assert isinstance(finding.severity, Severity), finding
        assert isinstance(finding.line, int) and finding.line >= 1, finding
        assert finding.column is None or finding.column >= 1, finding
        assert finding.xpath.startswith("/"), finding
        assert finding.message and "\n" not in finding.message, finding
        assert finding.message.isprintable(), finding
