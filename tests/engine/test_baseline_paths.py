"""A baseline matches from any folder, says what it withheld, and warns when it matches
nothing; the CI formats name paths from the repository's top (issue 31, item 3)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from tests.conftest import REPO
from xodrlint.cli import app

BROKEN = REPO / "examples" / "broken.xodr"  # 6 findings
TWO = REPO / "examples" / "two-findings.xodr"  # 2 findings


def run(*args: str | Path) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.fixture
def repo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / ".git").mkdir()
    (tmp_path / "sub").mkdir()
    shutil.copy(BROKEN, tmp_path / "sub" / "a.xodr")
    shutil.copy(TWO, tmp_path / "b.xodr")
    monkeypatch.chdir(tmp_path)
    written = run("check", ".", "--write-baseline", "baseline.json")
    assert written.exit_code == 0, written.stderr
    return tmp_path


def test_a_baseline_made_at_the_top_matches_from_a_folder_below(
    repo: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    recorded = json.loads((repo / "baseline.json").read_text("utf-8"))
    assert recorded["format_version"] == 2
    assert {entry["path"] for entry in recorded["findings"]} == {"b.xodr", "sub/a.xodr"}
    monkeypatch.chdir(repo / "sub")
    result = run("check", "..", "--baseline", "../baseline.json")
    assert result.exit_code == 0, result.stdout
    assert result.stdout.splitlines()[0] == (
        "All checks passed: 2 files, no new findings; 8 withheld by baseline.json."
    )


def test_every_report_says_what_the_baseline_withheld(repo: Path) -> None:
    shutil.copy(TWO, repo / "sub" / "new.xodr")
    text = run("check", ".", "--baseline", "baseline.json")
    assert text.exit_code == 1
    assert "Found 2 new findings (1 error, 1 warning) in 1 of 3 files; 8 withheld by " in (
        text.stdout
    )
    summary = json.loads(run("check", "-f", "json", ".", "--baseline", "baseline.json").stdout)
    assert summary["summary"]["baseline"] == {"file": "baseline.json", "withheld": 8}
    sarif = json.loads(run("check", "-f", "sarif", ".", "--baseline", "baseline.json").stdout)
    assert sarif["runs"][0]["properties"]["baseline"] == {"file": "baseline.json", "withheld": 8}
    for quiet_format in ("concise", "gitlab", "jsonl"):
        result = run("check", "-f", quiet_format, ".", "--baseline", "baseline.json")
        assert "xodrlint: baseline.json withheld 8 findings recorded in it" in result.stderr


def test_a_baseline_that_matches_no_linted_file_is_a_warning(
    repo: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a format-1 baseline names paths from the folder it was written in: read as before,
    # from the working folder, so from sub/ it is about no file this run lints
    old = json.loads((repo / "baseline.json").read_text("utf-8"))
    old["format_version"] = 1
    (repo / "old.json").write_text(json.dumps(old), "utf-8")
    assert run("check", ".", "--baseline", "old.json").exit_code == 0  # as written
    monkeypatch.chdir(repo / "sub")
    for output_format in ("text", "jsonl"):
        result = run("check", "-f", output_format, "..", "--baseline", "../old.json")
        assert result.exit_code == 1
        assert (
            "xodrlint: warning: --baseline ../old.json: none of its 8 findings is about a "
            f"file this run linted (its paths are relative to {repo / 'sub'})"
        ) in result.stderr


def test_ci_paths_are_relative_to_the_repository_whatever_the_working_folder(
    repo: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(repo / "sub")
    gitlab = json.loads(run("check", "-f", "gitlab", "a.xodr").stdout)
    assert {issue["location"]["path"] for issue in gitlab} == {"sub/a.xodr"}
    sarif = json.loads(run("check", "-f", "sarif", "a.xodr").stdout)["runs"][0]
    assert sarif["originalUriBaseIds"]["%SRCROOT%"]["uri"] == repo.as_uri() + "/"
    uris = {
        r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in sarif["results"]
    }
    assert uris == {"sub/a.xodr"}
    github = run("check", "-f", "github", "a.xodr").stdout
    assert "file=sub/a.xodr," in github
    # a CI service's checkout folder wins over the repository found
    monkeypatch.setenv("CI_PROJECT_DIR", str(repo / "sub"))
    gitlab = json.loads(run("check", "-f", "gitlab", "a.xodr").stdout)
    assert {issue["location"]["path"] for issue in gitlab} == {"a.xodr"}
