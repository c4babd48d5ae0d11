"""The note of rules a run did not apply (issue 28), once per run in every format: text
(also ``--quiet``), json (and each file's ``rules_not_applied``), sarif, github in the
report; concise, jsonl, gitlab, junit and xqar on stderr, junit and xqar also per file
(skipped cases and checkers). Nothing when every rule judged every file, and nothing with
``--all-versions``, which ``check``, ``map``, ``qc`` and a Dask cluster take."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path
from typing import Any

import jsonschema  # type: ignore[import-untyped, unused-ignore]
import pytest
from lxml import etree
from typer.testing import CliRunner, Result

from tests.conftest import REPO
from tests.validation.test_versions import PLAIN_ENV, TWO_RAILS_1_7, TWO_TRAMS_1_4, TWO_TRAMS_1_6
from xodrlint.api import default_registry
from xodrlint.cli import app
from xodrlint.cli.check.notes import FULL_VALIDATION_NOTE
from xodrlint.engine.linter import LintOptions
from xodrlint.formatters.xqar import checker_id

from .test_formatters import assert_valid_sarif, only_run, read_junit

NOTE = (
    "RL001, RL002 not applied to 1 file declaring OpenDRIVE 1.4 and 1 declaring 1.6 "
    "(they apply from 1.7 on; --all-versions applies them)"
)
#: What the note and the per-file reasons say (a rule's help text may say "not applied" too).
NOTED = re.compile(r"not applied to (\d|OpenDRIVE)")
FILES = (TWO_TRAMS_1_4, TWO_TRAMS_1_6, TWO_RAILS_1_7)
JSON_SCHEMA = json.loads((REPO / "docs" / "json-output.schema.json").read_text("utf-8"))


@pytest.fixture(autouse=True)
def _in_the_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(REPO)  # reports name the cases by their paths in the repository


def check(*args: str | Path, files: tuple[Path, ...] = FILES, code: int = 1) -> Result:
    shown = (path.relative_to(REPO).as_posix() for path in files)
    argv = ["check", "--isolated", *map(str, args), *shown]
    result = CliRunner().invoke(app, argv, env=PLAIN_ENV)
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    assert result.exit_code == code, (result.stdout, result.stderr)
    return result


def notes_on_stderr(result: Result) -> list[str]:
    return [line.removeprefix("xodrlint: note: ") for line in result.stderr.splitlines()]


@pytest.mark.parametrize("quiet", [(), ("--quiet",)], ids=["default", "quiet"])
def test_text_says_it_once_after_the_findings(quiet: tuple[str, ...]) -> None:
    result = check(*quiet)
    # on stderr, after the report: standard output holds the report alone
    assert notes_on_stderr(result) == [FULL_VALIDATION_NOTE, NOTE]
    assert "note: " not in result.stdout


def test_json_has_the_note_and_each_file_what_it_did_not_apply() -> None:
    document = json.loads(check("-f", "json").stdout)
    jsonschema.validate(document, JSON_SCHEMA)
    assert document["notes"] == [FULL_VALIDATION_NOTE, NOTE]
    assert [f["rules_not_applied"] for f in document["files"]] == [  # by name
        [],
        ["RL001", "RL002"],
        ["RL001", "RL002"],
    ]
    assert [f["code"] for f in document["findings"]] == ["RL001"]  # the 1.7 file's


def test_sarif_has_it_as_a_configuration_notification_and_per_file() -> None:
    log = json.loads(check("-f", "sarif").stdout)
    assert_valid_sarif(log)
    run = only_run(log)
    notes = run["invocations"][0]["toolConfigurationNotifications"]
    assert [n["message"]["text"] for n in notes] == [FULL_VALIDATION_NOTE, NOTE]
    assert {n["level"] for n in notes} == {"note"}
    assert run["invocations"][0]["executionSuccessful"] is True
    assert run["properties"]["rulesNotApplied"] == [
        {
            "artifactLocation": {
                "uri": path.relative_to(REPO).as_posix(),
                "uriBaseId": "%SRCROOT%",
            },
            "declaredVersion": version,
            "rules": ["RL001", "RL002"],
        }
        for path, version in ((TWO_TRAMS_1_4, "1.4"), (TWO_TRAMS_1_6, "1.6"))
    ]


def test_github_says_it_as_a_notice_of_the_run() -> None:
    lines = check("-f", "github").stdout.splitlines()
    assert lines[-1] == f"::notice title=xodrlint::{NOTE}"
    assert sum(line.startswith("::notice title=xodrlint::") for line in lines) == 2
    assert [line for line in lines if "not applied" in line] == [lines[-1]]


@pytest.mark.parametrize("output_format", ["concise", "gitlab", "junit", "xqar"])
def test_a_report_without_a_place_for_notes_leaves_them_to_stderr(output_format: str) -> None:
    result = check("-f", output_format)
    assert notes_on_stderr(result) == [FULL_VALIDATION_NOTE, NOTE]
    assert NOTE not in result.stdout


@pytest.mark.parametrize("output_format", ["text", "json"])
def test_statistics_leave_the_notes_to_stderr(output_format: str) -> None:
    result = check("-f", output_format, "--statistics")
    assert notes_on_stderr(result) == [FULL_VALIDATION_NOTE, NOTE]
    assert not NOTED.search(result.stdout)


def test_jsonl_says_it_on_stderr_after_the_last_line_with_workers() -> None:
    result = check("-f", "jsonl", "--jobs", "2")
    assert notes_on_stderr(result) == [FULL_VALIDATION_NOTE, NOTE]
    assert [json.loads(line)["code"] for line in result.stdout.splitlines()] == ["RL001"]


def test_gitlab_keeps_its_issues_to_findings() -> None:
    issues = json.loads(check("-f", "gitlab").stdout)
    assert [issue["check_name"] for issue in issues] == ["RL001"]


def test_junit_has_a_skipped_case_per_rule_and_file() -> None:
    xml = read_junit(check("-f", "junit").stdout)
    skipped = {
        (suite.name, case.name, item.message)
        for suite in xml
        for case in suite
        for item in case.result
        if type(item).__name__ == "Skipped"
    }
    shown = {path: path.relative_to(REPO).as_posix() for path in FILES}
    assert xml.tests == sum(suite.tests for suite in xml)
    assert skipped == {
        (
            shown[path],
            f"{code} not applied",
            f"not applied to OpenDRIVE {version}: it applies from 1.7 on (--all-versions "
            "applies it)",
        )
        for path, version in ((TWO_TRAMS_1_4, "1.4"), (TWO_TRAMS_1_6, "1.6"))
        for code in ("RL001", "RL002")
    }


def test_xqar_skips_the_checkers_on_those_files() -> None:
    root = etree.fromstring(check("-f", "xqar").stdout.encode())
    ids = {code: checker_id(default_registry().by_code[code].meta) for code in ("RL001", "RL002")}
    bundles = root.findall("CheckerBundle")
    for bundle, judged in zip(bundles, (True, False, False), strict=True):  # by name
        by_id = {c.get("checkerId"): c for c in bundle.iter("Checker")}
        for code, checker in ((code, by_id[ids[code]]) for code in ids):
            if judged:
                assert checker.get("status") == "completed", code
            else:
                assert checker.get("status") == "skipped"
                assert checker.get("summary", "").startswith("Not applied to OpenDRIVE 1.")
                assert "it applies from 1.7 on (--all-versions applies it)." in checker.get(
                    "summary", ""
                )


@pytest.mark.parametrize(
    "output_format", ["text", "concise", "json", "jsonl", "sarif", "github", "gitlab", "junit"]
)
def test_no_note_with_all_versions(output_format: str) -> None:
    result = check("-f", output_format, "--all-versions")
    assert not NOTED.search(result.stdout + result.stderr)
    if output_format == "json":
        document = json.loads(result.stdout)
        judged = {(f["path"], f["code"]) for f in document["findings"]}
        assert {path for path, code in judged if code == "RL001"} == {
            path.relative_to(REPO).as_posix() for path in FILES
        }
        assert all(f["rules_not_applied"] == [] for f in document["files"])


@pytest.mark.parametrize("output_format", ["text", "concise", "json", "sarif", "github"])
def test_no_note_when_every_file_declares_1_7_or_later(output_format: str) -> None:
    result = check("-f", output_format, files=(TWO_RAILS_1_7,))
    assert not NOTED.search(result.stdout + result.stderr)


def test_a_report_file_beside_the_output_is_the_same_run(tmp_path: Path) -> None:
    extra = tmp_path / "report.json"
    result = check("--report", f"json={extra}")
    assert result.stderr.count(NOTE) == 1
    assert json.loads(extra.read_text("utf-8"))["notes"][-1] == NOTE


def test_map_takes_all_versions(tmp_path: Path) -> None:
    page = tmp_path / "map.html"
    base = ["map", str(TWO_TRAMS_1_4), "-o", str(page), "--select", "RL", "--isolated"]
    default = CliRunner().invoke(app, base, env=PLAIN_ENV)
    assert default.exit_code == 0, default.output
    assert f"note: {NOTE.replace(' and 1 declaring 1.6', '')}" in default.stderr
    every = CliRunner().invoke(app, [*base, "--all-versions"], env=PLAIN_ENV)
    assert every.exit_code == 1, every.output
    assert " RL001 [error] " in every.stdout and "not applied" not in every.stdout


def _qc_config(folder: Path, all_versions: str | None) -> Path:
    shutil.copy(TWO_TRAMS_1_4, folder / "map.xodr")
    param = f'<Param name="allVersions" value="{all_versions}"/>' if all_versions else ""
    config = folder / "config.xml"
    config.write_text(
        '<?xml version="1.0"?>\n<Config>\n  <Param name="InputFile" value="map.xodr"/>\n'
        f'  <CheckerBundle application="xodrlintBundle">{param}'
        '<Param name="resultFile" value="out.xqar"/></CheckerBundle>\n</Config>\n',
        "utf-8",
    )
    return config


@pytest.mark.parametrize(("param", "status"), [(None, "skipped"), ("true", "completed")])
def test_qc_takes_an_all_versions_parameter(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, param: str | None, status: str
) -> None:
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(app, ["qc", "-c", str(_qc_config(tmp_path, param))])
    assert result.exit_code == 0, result.output
    root = etree.parse(str(tmp_path / "out.xqar")).getroot()
    rl001 = checker_id(default_registry().by_code["RL001"].meta)
    (checker,) = [c for c in root.iter("Checker") if c.get("checkerId") == rl001]
    assert checker.get("status") == status
    assert len(checker.findall("Issue")) == (1 if param else 0)


def test_qc_refuses_an_all_versions_parameter_that_is_no_flag(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(app, ["qc", "-c", str(_qc_config(tmp_path, "maybe"))])
    assert result.exit_code == 2
    assert "allVersions='maybe' is not 'true' or 'false'" in result.stderr


@pytest.mark.loopback
def test_dask_workers_carry_what_was_not_applied(dask_client: Any) -> None:
    from xodrlint.runners.batch import Task
    from xodrlint.runners.dask import lint_on_cluster

    tasks = [Task(path, path.name) for path in FILES]
    for options, expected in (
        (LintOptions(), [("RL001", "RL002"), ("RL001", "RL002"), ()]),
        (LintOptions(all_versions=True), [(), (), ()]),
    ):
        reports = dict(lint_on_cluster(dask_client, options, tasks))
        assert [reports[i].rules_not_applied for i in range(len(tasks))] == expected
