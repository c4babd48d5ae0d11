"""What ``check`` writes: --statistics in the requested format, several reports from one
run (--report FORMAT=PATH), and a reader of standard output that stops early."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import jsonschema  # type: ignore[import-untyped, unused-ignore]
import pytest
from junitparser import JUnitXml  # type: ignore[import-untyped, unused-ignore]
from referencing import Registry, Resource

from tests.conftest import REPO

from .test_cli import BROKEN, CLEAN, OUTPUT_SCHEMA, cli

CONSOLE_SCRIPT = Path(sys.executable).parent / "xodrlint"
EXAMPLES = REPO / "examples"
STATISTICS_SCHEMA = json.loads((REPO / "docs" / "json-statistics.schema.json").read_text("utf-8"))


def _statistics_validator() -> jsonschema.Draft202012Validator:
    # the statistics schema takes 'tool' and 'summary' from the report's schema
    registry: Registry[Any] = Registry().with_resource(
        OUTPUT_SCHEMA["$id"], Resource.from_contents(OUTPUT_SCHEMA)
    )
    return jsonschema.Draft202012Validator(STATISTICS_SCHEMA, registry=registry)


def test_statistics_follow_the_json_format() -> None:
    done = cli("check", "--statistics", "-f", "json", BROKEN, code=1)
    document = json.loads(done.stdout)
    _statistics_validator().validate(document)
    rows = [(row["code"], row["count"], row["severity"]) for row in document["statistics"]]
    assert rows == [
        ("XS006", 3, "error"),
        ("RL003", 1, "error"),
        ("ST004", 1, "error"),
        ("SW006", 1, "warning"),
    ]
    assert document["statistics"][0]["name"] == "schema-violation"
    assert document["summary"]["findings"] == 6


def test_statistics_carry_a_severity_the_config_overrides(tmp_path: Path) -> None:
    config = tmp_path / "xodrlint.toml"
    config.write_text('[severity]\nSW006 = "info"\n', "utf-8")
    table = cli("check", "--statistics", "--config", config, BROKEN, code=1).stdout
    assert "     1  SW006  [info]    side-track-not-at-end" in table.splitlines()


@pytest.mark.parametrize("output_format", ["sarif", "junit", "gitlab", "github", "xqar"])
def test_statistics_are_refused_where_the_format_cannot_hold_them(
    tmp_path: Path, output_format: str
) -> None:
    target = tmp_path / "report"
    done = cli("check", "--statistics", "-f", output_format, "-o", target, BROKEN, code=2)
    assert done.stderr == (
        f"xodrlint: --statistics: the {output_format} format cannot hold statistics "
        "(use text, concise or json)\n"
    )
    assert not target.exists()  # refused before anything was written


def test_statistics_table_in_concise_and_text_alike() -> None:
    text = cli("check", "--statistics", BROKEN, code=1).stdout
    concise = cli("check", "--statistics", "-f", "concise", BROKEN, code=1).stdout
    assert text == concise and text.startswith("     3  XS006  [error]   schema-violation\n")


def test_reports_from_one_run(tmp_path: Path) -> None:
    gitlab, junit = tmp_path / "gl-code-quality.json", tmp_path / "junit.xml"
    done = cli(
        "check",
        EXAMPLES,
        "--report",
        f"gitlab={gitlab}",
        "--report",
        f"junit={junit}",
        "-f",
        "json",
        code=1,
    )
    document = json.loads(done.stdout)  # the main report still goes to standard output
    findings = len(document["findings"])
    assert findings > 0
    assert len(json.loads(gitlab.read_text("utf-8"))) == findings
    suites = JUnitXml.fromfile(str(junit))
    assert sum(suite.failures + suite.errors for suite in suites) == findings


def test_reports_beside_statistics_hold_the_findings(tmp_path: Path) -> None:
    sarif = tmp_path / "x.sarif"
    done = cli("check", "--statistics", BROKEN, "--report", f"sarif={sarif}", code=1)
    assert done.stdout.startswith("     3  XS006")
    log = json.loads(sarif.read_text("utf-8"))
    assert len(log["runs"][0]["results"]) == 6


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ("gitlab", "--report gitlab: expected FORMAT=PATH"),
        ("=x.json", "--report =x.json: expected FORMAT=PATH"),
        ("gitlab=-", "--report gitlab=-: a report file cannot be standard output"),
        ("nosuch=x.json", "--report nosuch=x.json: unknown output format 'nosuch'"),
        ("gitlab=missing/x.json", "--report gitlab=missing/x.json: its folder missing does"),
    ],
)
def test_a_report_that_cannot_be_written_is_refused_before_linting(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, entry: str, message: str
) -> None:
    monkeypatch.chdir(tmp_path)
    done = cli("check", CLEAN, "--report", entry, code=2)
    assert done.stderr.startswith(f"xodrlint: {message}"), done.stderr
    assert done.stdout == ""


def test_a_report_never_overwrites_an_input_or_another_report(tmp_path: Path) -> None:
    source = tmp_path / "map.xodr"
    shutil.copyfile(CLEAN, source)
    before = source.read_bytes()
    done = cli("check", tmp_path, "--report", f"json={source}", code=2)
    assert "is one of the inputs; refusing to overwrite it" in done.stderr
    assert source.read_bytes() == before
    same = tmp_path / "out.json"
    twice = cli("check", source, "-o", same, "--report", f"gitlab={tmp_path}/./out.json", code=2)
    assert f"--output {same} writes the same file" in twice.stderr
    assert not same.exists()


def _closed_pipe_run(*args: str | Path) -> subprocess.CompletedProcess[bytes]:
    """Run the console script with standard output a pipe whose reader is gone."""
    if not CONSOLE_SCRIPT.is_file():
        pytest.skip(f"no console script at {CONSOLE_SCRIPT}")
    reader, writer = os.pipe()
    os.close(reader)
    try:
        return subprocess.run(
            [CONSOLE_SCRIPT, *map(str, args)],
            stdout=writer,
            stderr=subprocess.PIPE,
            timeout=60,
            check=False,
        )
    finally:
        os.close(writer)


def _errors(stderr: bytes) -> bytes:
    """``stderr`` less the notes ``concise`` prints there (what was not checked)."""
    lines = stderr.splitlines(keepends=True)
    return b"".join(line for line in lines if not line.startswith(b"xodrlint: note: "))


@pytest.mark.parametrize("output_format", ["text", "concise", "json", "sarif", "junit"])
def test_a_reader_that_stops_early_is_no_error(output_format: str) -> None:
    clean = _closed_pipe_run("check", "-f", output_format, CLEAN)
    assert (clean.returncode, _errors(clean.stderr)) == (0, b"")
    broken = _closed_pipe_run("check", "-f", output_format, BROKEN)
    assert (broken.returncode, _errors(broken.stderr)) == (1, b"")


def test_a_reader_that_stops_early_still_gets_the_report_files(tmp_path: Path) -> None:
    junit = tmp_path / "junit.xml"
    done = _closed_pipe_run("check", "--statistics", BROKEN, "--report", f"junit={junit}")
    assert (done.returncode, _errors(done.stderr)) == (1, b"")
    assert JUnitXml.fromfile(str(junit))


def test_a_reader_that_stops_after_the_first_line(tmp_path: Path) -> None:
    for index in range(60):  # a report larger than a pipe's buffer
        shutil.copyfile(BROKEN, tmp_path / f"b{index:02}.xodr")
    for output_format in ("text", "json"):
        done = subprocess.run(
            f"{CONSOLE_SCRIPT} check -f {output_format} {tmp_path} | head -c 1 >/dev/null;"
            " exit ${PIPESTATUS[0]}",
            shell=True,
            executable="/bin/bash",
            capture_output=True,
            text=True,
            timeout=60,
            check=False,
        )
        notes = [line for line in done.stderr.splitlines() if "note: " not in line]
        assert (done.returncode, notes) == (1, [])  # no broken pipe, no traceback


def test_a_full_disk_is_still_an_error() -> None:
    if not Path("/dev/full").exists():
        pytest.skip("no /dev/full on this system")
    with Path("/dev/full").open("wb") as full:
        done = subprocess.run(
            [CONSOLE_SCRIPT, "check", "-f", "json", BROKEN],
            stdout=full,
            stderr=subprocess.PIPE,
            text=True,
            timeout=60,
            check=False,
        )
    assert done.returncode == 2
    assert done.stderr.startswith("xodrlint: standard output: cannot write: ")


def _closed_stderr_run(*args: str | Path) -> subprocess.CompletedProcess[bytes]:
    """Run the console script with standard error a pipe whose reader is gone."""
    if not CONSOLE_SCRIPT.is_file():
        pytest.skip(f"no console script at {CONSOLE_SCRIPT}")
    reader, writer = os.pipe()
    os.close(reader)
    try:
        return subprocess.run(
            [CONSOLE_SCRIPT, *map(str, args)],
            stdout=subprocess.PIPE,
            stderr=writer,
            timeout=60,
            check=False,
        )
    finally:
        os.close(writer)


def test_a_reader_of_stderr_that_stops_early_changes_nothing(tmp_path: Path) -> None:
    # '2>&1 | head': what stderr would say is dropped, the run goes on as it would have
    assert _closed_stderr_run("check", "-v", CLEAN).returncode == 0
    assert _closed_stderr_run("check", CLEAN, tmp_path / "gone.xodr").returncode == 2
    junit = tmp_path / "junit.xml"
    done = _closed_stderr_run("check", "-v", BROKEN, "--report", f"junit={junit}")
    assert done.returncode == 1
    assert JUnitXml.fromfile(str(junit))
    assert b"XS006" in done.stdout


def test_report_files_are_plain_whatever_the_terminal_asks(tmp_path: Path) -> None:
    text, main = tmp_path / "report.txt", tmp_path / "main.txt"
    cli("check", BROKEN, "-f", "json", "--report", f"text={text}", code=1, FORCE_COLOR="1")
    cli("check", BROKEN, "--color", "always", "-o", main, code=1)
    for written in (text, main):
        content = written.read_text("utf-8")
        assert "XS006" in content and "\x1b" not in content


def test_a_baseline_run_writes_no_report_and_says_so(tmp_path: Path) -> None:
    done = cli(
        "check",
        BROKEN,
        "--write-baseline",
        tmp_path / "baseline.json",
        "--report",
        f"junit={tmp_path / 'junit.xml'}",
        code=2,
    )
    assert done.stderr == (
        f"xodrlint: --report junit={tmp_path / 'junit.xml'}: --write-baseline writes the "
        "baseline and no report\n"
    )
    assert not (tmp_path / "baseline.json").exists()


def test_the_concise_notes_are_said_once_by_the_command(tmp_path: Path) -> None:
    done = cli(
        "check",
        CLEAN,
        "-f",
        "concise",
        "--report",
        f"concise={tmp_path / 'a.txt'}",
        "--report",
        f"concise={tmp_path / 'b.txt'}",
        code=0,
    )
    assert len(done.stderr.splitlines()) == 1 and done.stderr.startswith("xodrlint: note: ")
    assert (tmp_path / "a.txt").read_text("utf-8") == ""
