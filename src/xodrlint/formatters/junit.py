"""JUnit XML, as GitLab's test reports and Jenkins' junit step read it.

One ``testsuite`` per input file (named by its path relative to the run's root), one
failing ``testcase`` per finding (with a ``failure`` whose type is the code and whose
text is ``path:line:column: CODE [severity] message`` and the XPath), and one passing
``testcase`` named ``xodrlint`` for a file without findings. A file that could not be
read, or on which a rule crashed, has a ``testcase`` with an ``error`` instead. A rule
that did not judge a file, because the file declares an older OpenDRIVE version than the
rule applies from, is a ``skipped`` test case ``CODE not applied`` of its suite, saying
why (the run's note, on stderr, says it once for the run).

A finding's test case is named ``CODE line N col C XPATH`` (``col C`` only where the
column is known): GitLab keys test cases by name and keeps one of each, so names must
differ within a suite, and four schema errors on one element's line would all be
``XS006 line 56``. Findings that still share a name (one element, one code) are told
apart by their order among themselves: the second is ``... #2``, the third ``... #3``.
Findings are sorted (path, line, code, column, message), so the same file gives the same
names in every run. Times are always ``0``: the output depends on the input only.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import Final, TextIO

from lxml import etree

from xodrlint.findings import FileReport, Finding, RuleMeta, RunResult

from ._common import not_applied_reason, report_path, rules_by_code

DECLARATION: Final = '<?xml version="1.0" encoding="UTF-8"?>\n'
CLEAN_CASE: Final = "xodrlint"
#: Characters XML 1.0 cannot hold at all, not even escaped.
_NOT_XML: Final = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def xml_text(text: str) -> str:
    """``text`` with the characters XML cannot carry replaced by U+FFFD."""
    return _NOT_XML.sub("\ufffd", text)


class JunitFormatter:
    def render(self, result: RunResult, stream: TextIO) -> None:
        stream.write(DECLARATION)
        stream.write(etree.tostring(as_junit(result), encoding="unicode", pretty_print=True))


def as_junit(result: RunResult) -> etree._Element:
    root = etree.Element("testsuites", name="xodrlint")
    totals = [0, 0, 0]
    rules = rules_by_code(result)
    for report in result.reports:
        suite = _suite(report, report_path(report.path, result), result)
        _skipped(suite, report, rules, report_path(report.path, result))
        root.append(suite)
        for i, key in enumerate(("tests", "failures", "errors")):
            totals[i] += int(suite.get(key, "0"))
    for key, value in zip(("tests", "failures", "errors"), totals, strict=True):
        root.set(key, str(value))
    root.set("time", "0")
    return root


def _suite(report: FileReport, path: str, result: RunResult) -> etree._Element:
    suite = etree.Element("testsuite", name=xml_text(path))
    cases: list[etree._Element] = []
    if report.error:
        cases.append(_error_case(path, CLEAN_CASE, "unreadable", report.error))
    cases.extend(
        _error_case(path, "internal error", "internal-error", crash)
        for crash in report.internal_errors
    )
    for finding in report.findings:  # one in an included file names that file
        own = finding.path == report.path
        cases.append(_failure_case(finding, path if own else report_path(finding.path, result)))
    if not cases:
        cases.append(_case(CLEAN_CASE, path))
    for case, name in zip(cases, unique_names(case.get("name", "") for case in cases), strict=True):
        case.set("name", name)
    errors = (1 if report.error else 0) + len(report.internal_errors)
    suite.set("tests", str(len(cases)))
    suite.set("failures", str(len(report.findings)))
    suite.set("errors", str(errors))
    suite.set("skipped", "0")
    suite.set("time", "0")
    suite.extend(cases)
    return suite


def _skipped(
    suite: etree._Element, report: FileReport, rules: dict[str, RuleMeta], path: str
) -> None:
    """A skipped test case per rule that did not judge the file."""
    for code in report.rules_not_applied:
        case = _case(f"{code} not applied", path)
        why = xml_text(not_applied_reason(rules.get(code), report.declared_version))
        etree.SubElement(case, "skipped", message=why)
        suite.append(case)
    if report.rules_not_applied:
        suite.set("tests", str(int(suite.get("tests", "0")) + len(report.rules_not_applied)))
        suite.set("skipped", str(len(report.rules_not_applied)))


def _case(name: str, path: str) -> etree._Element:
    return etree.Element("testcase", name=xml_text(name), classname=xml_text(path), time="0")


def case_name(finding: Finding) -> str:
    """What tells a finding apart in its file: code, line, column (where known), XPath."""
    column = f" col {finding.column}" if finding.column is not None else ""
    return f"{finding.code} line {finding.line}{column} {finding.xpath}".rstrip()


def unique_names(names: Iterable[str]) -> list[str]:
    """``names`` in order, a repeat of a name given ``#2``, ``#3``, ... (the first keeps
    it), skipping any a name of its own already took."""
    taken: set[str] = set()
    last: dict[str, int] = {}  # the ordinal each name reached: no rescan from #2 each time
    unique = []
    for name in names:
        ordinal = last.get(name, 1)
        candidate = name if ordinal == 1 else f"{name} #{ordinal}"
        while candidate in taken:
            ordinal += 1
            candidate = f"{name} #{ordinal}"
        last[name] = ordinal
        taken.add(candidate)
        unique.append(candidate)
    return unique


def _failure_case(finding: Finding, path: str) -> etree._Element:
    case = _case(case_name(finding), path)
    failure = etree.SubElement(
        case, "failure", message=xml_text(finding.message), type=finding.code
    )
    column = "" if finding.column is None else f":{finding.column}"
    failure.text = xml_text(
        f"{path}:{finding.line}{column}: {finding.code} [{finding.severity}] "
        f"{finding.message}\n{finding.xpath}"
    )
    return case


def _error_case(path: str, name: str, kind: str, text: str) -> etree._Element:
    case = _case(name, path)
    error = etree.SubElement(case, "error", message=xml_text(text), type=kind)
    error.text = xml_text(text)
    return case
