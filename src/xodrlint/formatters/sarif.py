"""SARIF 2.1.0, the way GitHub code scanning reads it (one run, every rule described).

- ``tool.driver.rules`` lists every rule of the run's registry; each result points at
  its rule by ``ruleId`` and ``ruleIndex``. A rule's ``defaultConfiguration.level`` is its
  default severity, a result's ``level`` the severity it was reported with (which a run
  may have overridden): error -> ``error``, warning -> ``warning``, info -> ``note``.
- Paths are URIs relative to ``%SRCROOT%`` (the run's root, given in
  ``originalUriBaseIds``), percent-encoded; a file outside the root gets an absolute
  ``file:`` URI instead, since a relative one would climb out of the checkout.
- ``partialFingerprints["xodrlint/v1"]`` is :func:`xodrlint.findings.fingerprints`: rule,
  relative path and XPath, never a line number, so an alert survives edits above it.
- The XPath of a finding is its logical location (``kind: element``); a finding's
  related elements are ``relatedLocations``.
- Suppressed findings, when the run kept them, are results with ``suppressions``.
- Files that could not be read, rule crashes and files that do not parse (XS001, which
  is a result too) are ``toolExecutionNotifications`` of the one invocation; a run with
  an unreadable file or a crash has ``executionSuccessful: false``. The run's notes (the
  built-in schema only checked railroad elements) are ``toolConfigurationNotifications``,
  and so is each file that a schema given for every version validated although the file
  declares another version.
- Which schema validated each file is in the run's ``properties.schemas``; which rules
  did not judge a file, because it declares an older OpenDRIVE version than they apply
  from, in ``properties.rulesNotApplied`` (only where some did not), and the run's note
  says it in words among the ``toolConfigurationNotifications`` (a rule the
  configuration left out, as SARIF's own example of such a notification is).
- GitHub rejects a run of more than 25,000 results. A log that would hold more than
  ``max_results`` (GitHub's 25,000 unless ``--sarif-max-results`` or the config's
  ``sarif-max-results`` says otherwise; 0 for no limit) keeps the most important:
  unsuppressed results before suppressed ones (a suppressed result is one a reader has
  already dismissed, so any open one matters more), within each errors, then warnings,
  then notes, within a level by path and line, then in the usual finding order. The kept
  results stay in the usual order. A warning-level ``toolExecutionNotifications`` entry
  says how many were left out (its ``properties`` give the counts), and so does
  :attr:`SarifFormatter.warnings`, which the command prints on stderr. Fingerprints are
  those of the whole run, so a kept result's alert is the same with or without the
  limit. Each result carries its own ``relatedLocations`` (elements of the file, never
  other results), so leaving a result out leaves nothing pointing at it; a rule is
  described for a result of a rule outside the table only when that result is kept.

The output holds no timestamps: the same input gives the same bytes.
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Final, TextIO
from urllib.parse import quote

from xodrlint.config.settings import DEFAULT_SARIF_MAX_RESULTS
from xodrlint.findings import Finding, RuleMeta, RunResult, Severity, Suppressed, relative_path
from xodrlint.inputs.remote import is_url

from ._common import MALFORMED, rules_by_code, run_fingerprints

SCHEMA_URI: Final = "https://json.schemastore.org/sarif-2.1.0.json"
SARIF_VERSION: Final = "2.1.0"
INFORMATION_URI: Final = "https://github.com/xodrlint/xodrlint"
HELP_URI: Final = INFORMATION_URI + "/blob/main/docs/rules/{code}.md"
#: Rules of these packs have a doc page in the repository (a plugin's rules do not).
BUILTIN_PACK_PREFIX: Final = "xodrlint.rules"
FINGERPRINT_KEY: Final = "xodrlint/v1"
SRCROOT: Final = "%SRCROOT%"

LEVEL: Final = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}
#: GitHub's ``problem.severity`` (the severity code scanning shows for a non-security rule).
PROBLEM_SEVERITY: Final = {
    Severity.ERROR: "error",
    Severity.WARNING: "warning",
    Severity.INFO: "recommendation",
}

_SEMVER: Final = re.compile(
    r"(0|[1-9]\d*)\.(0|[1-9]\d*)\.(0|[1-9]\d*)"
    r"(-[0-9A-Za-z-]+(\.[0-9A-Za-z-]+)*)?(\+[0-9A-Za-z-]+(\.[0-9A-Za-z-]+)*)?"
)
_LINK: Final = re.compile(r"\[([^\]]+)\]\(([^)\s]+)\)")
_LIST_ITEM: Final = re.compile(r"^\s*([-*+]|\d+[.)])\s")

JsonObject = dict[str, Any]


class SarifFormatter:
    carries_notes = True
    shows_fixes = True  # each result's "fixes" (SARIF 2.1.0 section 3.55)
    says_withheld = True  # in the run's properties

    def __init__(
        self,
        *,
        max_results: int = DEFAULT_SARIF_MAX_RESULTS,
    ) -> None:
        if max_results < 0:
            raise ValueError(f"max_results must be 0 (no limit) or more, got {max_results}")
        self.max_results = max_results
        self.warnings: tuple[str, ...] = ()
        """What the last render left out, one line each (the command prints them)."""

    def render(self, result: RunResult, stream: TextIO) -> None:
        log = as_sarif(result, max_results=self.max_results)
        note = limit_note(result_count(result), self.max_results)
        self.warnings = (note,) if note else ()
        json.dump(log, stream, indent=2, ensure_ascii=False)
        stream.write("\n")


def as_sarif(result: RunResult, *, max_results: int = 0) -> JsonObject:
    """The SARIF log of ``result`` as a JSON-ready dict, with at most ``max_results``
    results (0: all of them)."""
    rules = [rule_descriptor(meta) for meta in result.rules]
    index = {meta.code: i for i, meta in enumerate(result.rules)}

    def rule_index(code: str) -> int:
        if code not in index:  # a finding of a rule the table lacks: describe it minimally
            index[code] = len(rules)
            rules.append({"id": code, "shortDescription": {"text": code}})
        return index[code]

    suppressed = [item for report in result.reports for item in report.suppressed]
    prints = run_fingerprints(result, (item.finding for item in suppressed))
    entries: list[tuple[Finding, Suppressed | None]] = [(f, None) for f in result.findings]
    entries += [(item.finding, item) for item in suppressed]
    kept = most_important(entries, max_results)
    results = [
        _result(finding, rule_index(finding.code), prints[i], item, result.root)
        for i, (finding, item) in enumerate(entries)
        if kept is None or i in kept
    ]
    invocation = _invocation(result, rule_index)
    note = limit_note(len(entries), max_results)
    if note is not None:  # a warning, not a failure: the log is complete up to the limit
        counts = {"results": len(entries), "kept": len(results)}
        invocation["toolExecutionNotifications"].append(
            {
                "level": "warning",
                "message": {"text": note},
                "properties": {**counts, "leftOut": len(entries) - len(results)},
            }
        )
    driver: JsonObject = {"name": "xodrlint", "version": result.tool_version}
    if _SEMVER.fullmatch(result.tool_version):
        driver["semanticVersion"] = result.tool_version
    driver["informationUri"] = INFORMATION_URI
    driver["rules"] = rules
    run: JsonObject = {
        "tool": {"driver": driver},
        "invocations": [invocation],
        "originalUriBaseIds": {SRCROOT: {"uri": root_uri(result.root)}},
        "results": results,
        "columnKind": "unicodeCodePoints",
        "properties": {"schemas": _schemas(result)},
    }
    if result.baseline is not None:
        run["properties"]["baseline"] = {"file": result.baseline, "withheld": result.withheld}
    not_applied = _rules_not_applied(result)
    if not_applied:
        run["properties"]["rulesNotApplied"] = not_applied
    return {"$schema": SCHEMA_URI, "version": SARIF_VERSION, "runs": [run]}


def result_count(result: RunResult) -> int:
    """How many results the log of ``result`` would hold without a limit."""
    return len(result.findings) + sum(len(report.suppressed) for report in result.reports)


def most_important(
    entries: Sequence[tuple[Finding, Suppressed | None]], max_results: int
) -> frozenset[int] | None:
    """The indices of the ``max_results`` entries to keep, ``None`` for all of them:
    unsuppressed first, then by level (errors first), path, line and the given order."""
    if not max_results or len(entries) <= max_results:
        return None
    ranked = sorted(
        range(len(entries)),
        key=lambda i: (
            entries[i][1] is not None,
            -entries[i][0].severity.rank,
            entries[i][0].path,
            entries[i][0].line,
            i,
        ),
    )
    return frozenset(ranked[:max_results])


def limit_note(total: int, max_results: int) -> str | None:
    """The line that says how many of ``total`` results the limit left out, if any."""
    if not max_results or total <= max_results:
        return None
    return (
        f"left out {total - max_results} of {total} SARIF results, keeping the {max_results} "
        f"most important (errors first); --sarif-max-results N changes the limit (default "
        f"{DEFAULT_SARIF_MAX_RESULTS}, the most GitHub code scanning accepts; 0: no limit)"
    )


def rule_descriptor(meta: RuleMeta) -> JsonObject:
    page = meta.page or meta.summary
    what = meta.section("What it does") or meta.summary
    descriptor: JsonObject = {
        "id": meta.code,
        "name": meta.name,
        "shortDescription": {"text": plain_text(meta.summary), "markdown": meta.summary},
        "fullDescription": {"text": plain_text(what), "markdown": what},
        "help": {"text": page, "markdown": page},
    }
    if meta.pack == BUILTIN_PACK_PREFIX or meta.pack.startswith(BUILTIN_PACK_PREFIX + "."):
        descriptor["helpUri"] = HELP_URI.format(code=meta.code)
    descriptor["defaultConfiguration"] = {"level": LEVEL[meta.severity]}
    origin = meta.origin
    family = origin.name if origin else meta.pack.rpartition(".")[2]
    descriptor["properties"] = {
        "uid": meta.uid,
        "aliases": list(meta.aliases),
        "tags": ["opendrive", family] if family else ["opendrive"],
        "precision": "very-high",
        "problem.severity": PROBLEM_SEVERITY[meta.severity],
    }
    if origin is not None and not origin.builtin:  # which pack to update or report to
        descriptor["properties"]["pack"] = origin.name
        if origin.distribution:
            descriptor["properties"]["packDistribution"] = origin.distribution
            descriptor["properties"]["packVersion"] = origin.version
    return descriptor


def plain_text(markdown: str) -> str:
    """Short Markdown as plain text: no backticks, links as ``text (url)``, lines unwrapped.

    Paragraphs stay apart (a blank line between them), and so do list items.
    """
    text = _LINK.sub(r"\1 (\2)", markdown).replace("`", "")
    paragraphs = []
    for paragraph in re.split(r"\n\s*\n", text.strip()):
        lines: list[str] = []
        for line in paragraph.splitlines():
            if lines and not _LIST_ITEM.match(line):
                lines[-1] += " " + line.strip()
            else:
                lines.append(line.strip())
        paragraphs.append("\n".join(lines))
    return "\n\n".join(paragraphs)


def root_uri(root: str) -> str:
    """The ``file:`` URI of the run's root folder, ending with ``/`` as SARIF requires."""
    uri = _absolute(root).as_uri()
    return uri if uri.endswith("/") else uri + "/"


def _absolute(path: str) -> Path:
    """``path`` made absolute and normalised, without resolving links (as reports do)."""
    return Path(os.path.normpath(Path(path).absolute()))


def artifact_location(path: str, root: str) -> JsonObject:
    """``path`` as a URI relative to ``%SRCROOT%``, or absolute when outside the root; a
    URL (``s3://bucket/a.xodr``) is its own URI, percent-encoded where a key needs it."""
    if is_url(path):
        scheme, rest = path.split("://", 1)
        return {"uri": f"{scheme}://{quote(rest, safe='/:@')}"}
    relative = relative_path(path, root)
    if path != "-" and (
        Path(relative).is_absolute() or relative == ".." or relative.startswith("../")
    ):
        return {"uri": _absolute(path).as_uri()}
    return {"uri": quote(relative, safe="/"), "uriBaseId": SRCROOT}


def _location(path: str, line: int, column: int | None, xpath: str, root: str) -> JsonObject:
    region: JsonObject = {"startLine": max(line, 1)}
    if column is not None:
        region["startColumn"] = max(column, 1)
    return {
        "physicalLocation": {"artifactLocation": artifact_location(path, root), "region": region},
        "logicalLocations": [{"fullyQualifiedName": xpath, "kind": "element"}],
    }


def _result(
    finding: Finding, rule_index: int, fingerprint: str, item: Suppressed | None, root: str
) -> JsonObject:
    entry: JsonObject = {
        "ruleId": finding.code,
        "ruleIndex": rule_index,
        "level": LEVEL[finding.severity],
        "message": {"text": finding.message},
        "locations": [_location(finding.path, finding.line, finding.column, finding.xpath, root)],
    }
    if finding.related:
        entry["relatedLocations"] = [
            {
                "id": number,
                **_location(other.path or finding.path, other.line, None, other.xpath, root),
            }
            for number, other in enumerate(finding.related, start=1)
        ]
    entry["partialFingerprints"] = {FINGERPRINT_KEY: fingerprint}
    if finding.fix is not None and finding.fix.edits:
        entry["fixes"] = [_fix(finding, root)]
    if item is not None:
        suppression: JsonObject = {"kind": item.kind}
        if item.justification:
            suppression["justification"] = item.justification
        entry["suppressions"] = [suppression]
    return entry


def _fix(finding: Finding, root: str) -> JsonObject:
    """A finding's fix as SARIF's ``fix`` (3.55): its edits as replacements in its file,
    each a deleted region (empty for an insertion) and the content put there; columns
    count code points, the end's being the one after the region, as SARIF's do."""
    fix = finding.fix
    assert fix is not None
    replacements = [
        {
            "deletedRegion": {
                "startLine": edit.start_line,
                "startColumn": edit.start_column,
                "endLine": edit.end_line,
                "endColumn": edit.end_column,
            },
            "insertedContent": {"text": edit.content},
        }
        for edit in fix.edits
    ]
    return {
        "description": {"text": f"{fix.message} ({fix.applicability} fix)"},
        "artifactChanges": [
            {
                "artifactLocation": artifact_location(finding.path, root),
                "replacements": replacements,
            }
        ],
    }


def _schemas(result: RunResult) -> list[JsonObject]:
    """Which schema validated each file (every report says so), with its note when the
    schema was given for every version and is not the file's own."""
    return [
        {
            "artifactLocation": artifact_location(report.path, result.root),
            "schema": report.schema,
            "builtin": report.schema_builtin,
            "note": report.schema_note,
        }
        for report in result.reports
        if report.schema is not None
    ]


def _rules_not_applied(result: RunResult) -> list[JsonObject]:
    """The rules that did not judge each file, for the version it declares (the run's
    note says it in words)."""
    return [
        {
            "artifactLocation": artifact_location(report.path, result.root),
            "declaredVersion": report.declared_version,
            "rules": list(report.rules_not_applied),
        }
        for report in result.reports
        if report.rules_not_applied
    ]


def _invocation(result: RunResult, rule_index: Callable[[str], int]) -> JsonObject:
    rules = rules_by_code(result)
    notifications: list[JsonObject] = []
    for report in result.reports:
        file_location = {
            "physicalLocation": {"artifactLocation": artifact_location(report.path, result.root)}
        }
        if report.error:
            notifications.append(
                {"level": "error", "message": {"text": report.error}, "locations": [file_location]}
            )
        notifications.extend(
            {
                "level": "error",
                "message": {"text": f"internal error: {crash}"},
                "locations": [file_location],
            }
            for crash in report.internal_errors
        )
        for finding in report.findings:
            if finding.code != MALFORMED:
                continue
            meta = rules.get(MALFORMED)
            text = f"{meta.summary}: {finding.message}" if meta else finding.message
            notifications.append(
                {
                    "level": "error",
                    "message": {"text": text},
                    "locations": [
                        _location(
                            finding.path, finding.line, finding.column, finding.xpath, result.root
                        )
                    ],
                    "associatedRule": {"id": MALFORMED, "index": rule_index(MALFORMED)},
                }
            )
    invocation: JsonObject = {
        "executionSuccessful": not any(r.error or r.internal_errors for r in result.reports),
        "toolExecutionNotifications": notifications,
    }
    configuration: list[JsonObject] = [
        {"level": "note", "message": {"text": note}} for note in result.notes
    ]
    configuration += [
        {
            "level": "warning",
            "message": {"text": f"{report.path}: {report.schema_note}"},
            "locations": [
                {
                    "physicalLocation": {
                        "artifactLocation": artifact_location(report.path, result.root)
                    }
                }
            ],
        }
        for report in result.reports
        if report.schema_note
    ]
    if configuration:
        invocation["toolConfigurationNotifications"] = configuration
    return invocation
