"""XQAR, the result format of the ASAM Quality Checker framework (qc-framework).

One ``CheckerBundle`` named ``xodrlintBundle`` per input file, holding one ``Checker`` per
rule. Per rule, not per family: the framework's configuration selects checkers by id and
filters their issues by level, and a railway engineer switches off one rule (PT003, a
name mismatch) without losing its family's errors. Each checker addresses its rule's UID
and aliases; each finding is an ``Issue`` (level 1 error, 2 warning, 3 info) whose
``Locations`` hold the line (``FileLocation``) and the XPath (``XMLLocation``), and a
second ``Locations`` per related element. A rule that did not run is ``skipped`` and its
summary says why (not selected; the input unreadable or no OpenDRIVE tree; a convention of
a later OpenDRIVE version than the file declares, which ``--all-versions`` applies); a
rule that crashed is ``error``.

ASAM's rule UID schema wants a domain name as the emanating entity, and qc-baselib refuses
a result file whose UIDs lack one. The catalogue's own UIDs (``xodrlint:xodr:...``) are
therefore written under ``xodrlint.github.io``, the domain of the project's home
organisation; the catalogue UID stays in each issue's ``DomainSpecificInfo``.
"""

from __future__ import annotations

import datetime
import os
import re
from collections.abc import Iterable, Mapping, Sequence
from typing import Final, TextIO

from lxml import etree

from xodrlint.findings import FileReport, Finding, RuleMeta, RunResult, Severity

from ._common import not_applied_reason
from .junit import DECLARATION, xml_text

BUNDLE_NAME: Final = "xodrlintBundle"
RESULT_VERSION: Final = "1.0.0"
LEVELS: Final = {Severity.ERROR: 1, Severity.WARNING: 2, Severity.INFO: 3}
#: Emanating entities that are no domain name, and the domain each is written under.
ENTITY_DOMAINS: Final = {"xodrlint": "xodrlint.github.io"}
#: ASAM's rule UID schema (qc-framework doc/manual/rule_uid_schema.md), as qc-baselib checks it.
_ASAM_UID: Final = re.compile(
    r"^\w+(\.\w+)+:[a-z]*:([0-9]+(\.[0-9]+)+)?:([^\W\d_][\w]*\.)*[^\W\d_]\w*$"
)
_DOCUMENT_PACK: Final = "xodrlint.rules.document"
_UNPARSED: Final = frozenset({"XS001", "XS002"})
_CRASH: Final = re.compile(r"^rule (?P<code>\w+) failed")

#: (maxLevel, minLevel) of a checker: its issues with a level in that range are kept.
LevelRange = tuple[int, int]


def asam_rule_uid(uid: str) -> str:
    """``uid`` as ASAM's rule UID schema allows it: a bare emanating entity becomes a domain."""
    if _ASAM_UID.match(uid):
        return uid
    entity, colon, rest = uid.partition(":")
    if not colon or "." in entity:
        return uid
    return f"{ENTITY_DOMAINS.get(entity, entity + '.invalid')}:{rest}"


def checker_id(meta: RuleMeta) -> str:
    """The checker of one rule, named as ASAM's bundles name theirs."""
    return f"check_xodrlint_{meta.code.lower()}_{meta.name.replace('-', '_')}"


class XqarFormatter:
    """``params`` are copied into each bundle (as the framework's bundles copy their
    configuration); ``levels`` keeps, per rule code, only issues in its level range."""

    def __init__(
        self,
        *,
        params: Sequence[tuple[str, str]] = (),
        levels: Mapping[str, LevelRange] | None = None,
    ) -> None:
        self._params = tuple(params)
        self._levels = dict(levels or {})

    def render(self, result: RunResult, stream: TextIO) -> None:
        stream.write(DECLARATION)
        root = etree.Element("CheckerResults", version=RESULT_VERSION)
        for report in result.reports:
            root.append(self._bundle(report, result))
        stream.write(etree.tostring(root, encoding="unicode", pretty_print=True))

    def _bundle(self, report: FileReport, result: RunResult) -> etree._Element:
        bundle = etree.Element(
            "CheckerBundle",
            name=BUNDLE_NAME,
            description="xodrlint: railroad rules for ASAM OpenDRIVE",
            version=result.tool_version,
            build_date=_build_date(),
        )
        for name, value in self._params:
            etree.SubElement(bundle, "Param", name=xml_text(name), value=xml_text(value))
        if "InputFile" not in dict(self._params):
            etree.SubElement(bundle, "Param", name="InputFile", value=xml_text(report.path))
        statuses: list[str] = []
        issues = 0
        for meta in result.rules:
            checker = self._checker(meta, report, result, issue_base=issues)
            statuses.append(checker.get("status", ""))
            issues += len(checker.findall("Issue"))
            bundle.append(checker)
        bundle.set("summary", _bundle_summary(statuses, issues, report.error))
        return bundle

    def _checker(
        self, meta: RuleMeta, report: FileReport, result: RunResult, *, issue_base: int
    ) -> etree._Element:
        checker = etree.Element(
            "Checker", checkerId=checker_id(meta), description=xml_text(meta.summary)
        )
        status, why = _status(meta, report, result)
        found = [f for f in report.findings if f.code == meta.code and self._kept(f)]
        for number, finding in enumerate(found if status == "completed" else []):
            checker.append(_issue(finding, issue_base + number))
        for uid in dict.fromkeys(asam_rule_uid(uid) for uid in meta.uids):
            etree.SubElement(checker, "AddressedRule", ruleUID=uid)
        checker.set("status", status)
        count = len(checker.findall("Issue"))
        checker.set("summary", xml_text(f"{why}{count} issue(s) are found."))
        return checker

    def _kept(self, finding: Finding) -> bool:
        levels = self._levels.get(finding.code)
        if levels is None:
            return True
        most_severe, least_severe = levels
        return most_severe <= LEVELS[finding.severity] <= least_severe


def _status(meta: RuleMeta, report: FileReport, result: RunResult) -> tuple[str, str]:
    """The checker's status and the start of its summary (why it did not complete)."""
    if result.selected is not None and meta.code not in result.selected:
        return "skipped", "Not selected by the configuration. "
    if report.error:
        return "skipped", f"The input could not be read: {report.error}. "
    if meta.code in report.rules_not_applied:
        why = not_applied_reason(meta, report.declared_version)
        return "skipped", f"{why[:1].upper()}{why[1:]}. "
    for crash in report.internal_errors:
        found = _CRASH.match(crash)
        if found is not None and found["code"] == meta.code:
            return "error", f"Internal error: {crash}. "
    unparsed = any(f.code in _UNPARSED for f in report.findings)
    if unparsed and meta.pack != _DOCUMENT_PACK:
        return "skipped", "Preconditions are not satisfied (the file is no OpenDRIVE tree). "
    return "completed", ""


def _issue(finding: Finding, number: int) -> etree._Element:
    issue = etree.Element(
        "Issue",
        issueId=str(number),
        description=xml_text(finding.message),
        level=str(LEVELS[finding.severity]),
        ruleUID=asam_rule_uid(finding.uid),
    )
    _locations(issue, f"{finding.code} is reported here", finding.line, finding.xpath)
    for related in finding.related:
        _locations(issue, "related element", related.line, related.xpath)
    info = etree.SubElement(issue, "DomainSpecificInfo", name="xodrlint")
    etree.SubElement(
        info, "rule", code=finding.code, uid=finding.uid, severity=str(finding.severity)
    )
    return issue


def _locations(issue: etree._Element, description: str, line: int, xpath: str) -> None:
    locations = etree.SubElement(issue, "Locations", description=description)
    etree.SubElement(locations, "FileLocation", row=str(line))
    if xpath.startswith("/"):
        etree.SubElement(locations, "XMLLocation", xpath=xml_text(xpath))


def _bundle_summary(statuses: Iterable[str], issues: int, error: str | None) -> str:
    listed = list(statuses)
    counts = {status: listed.count(status) for status in ("completed", "skipped", "error")}
    text = (
        f"{len(listed)} checker(s) are executed. {counts['completed']} checker(s) are "
        f"completed. {counts['skipped']} checker(s) are skipped. {counts['error']} "
        f"checker(s) have internal error. {issues} issue(s) are found."
    )
    return xml_text(f"{text} The input could not be read: {error}." if error else text)


def _build_date() -> str:
    """The day of the run; ``SOURCE_DATE_EPOCH`` fixes it (reproducible output)."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH", "").strip()
    if epoch.isdigit():
        moment = datetime.datetime.fromtimestamp(int(epoch), tz=datetime.UTC)
        return moment.date().isoformat()
    return datetime.date.today().isoformat()
