"""Each file is linted under the nearest configuration above it (issue 31, item 1): the
order of the paths never changes a report, and the command line, ``--jobs``, standard
input with ``--stdin-filename``, ``xodrlint config PATH`` and the language server agree
on every file."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from tests.conftest import REPO
from xodrlint.api import default_registry
from xodrlint.cli import app
from xodrlint.server.folders import Folders

BROKEN = REPO / "examples" / "broken.xodr"  # XS006 x3, SW006, RL003, ST004
TWO = REPO / "examples" / "two-findings.xodr"  # PT003 (warning), ST004 (error)

#: a/ ignores every finding broken.xodr has; b/ has no configuration
A_CONFIG = 'ignore = ["RL003", "XS006", "ST", "SW"]\n'


def run(*args: str | Path, stdin: bytes | None = None) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args], input=stdin)


@pytest.fixture
def repo(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / ".git").mkdir()  # the search for configurations stops here
    for folder, source in (("a", BROKEN), ("b", TWO)):
        (tmp_path / folder).mkdir()
        shutil.copy(source, tmp_path / folder / f"{folder}.xodr")
    (tmp_path / "a" / "xodrlint.toml").write_text(A_CONFIG, "utf-8")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _findings(result: Result) -> list[tuple[str, str]]:
    return [(f["path"], f["code"]) for f in json.loads(result.stdout)["findings"]]


def test_each_file_has_its_own_configuration_in_either_order(repo: Path) -> None:
    forward = run("check", "-f", "json", "a/a.xodr", "b/b.xodr")
    backward = run("check", "-f", "json", "b/b.xodr", "a/a.xodr")
    assert forward.exit_code == backward.exit_code == 1, forward.stderr
    assert _findings(forward) == [("b/b.xodr", "PT003"), ("b/b.xodr", "ST004")]
    assert forward.stdout == backward.stdout
    assert forward.stderr == backward.stderr


def test_a_folder_walk_lints_each_file_under_its_folders_configuration(repo: Path) -> None:
    walked = run("check", "-f", "json", ".")
    assert walked.exit_code == 1, walked.stderr
    assert _findings(walked) == [("b/b.xodr", "PT003"), ("b/b.xodr", "ST004")]


def test_worker_processes_lint_each_file_under_its_configuration(repo: Path) -> None:
    for copy in range(3):  # enough files for workers
        shutil.copy(BROKEN, repo / "a" / f"more{copy}.xodr")
        shutil.copy(TWO, repo / "b" / f"more{copy}.xodr")
    alone = run("check", "-f", "json", "-j", "1", ".")
    workers = run("check", "-f", "json", "-j", "2", ".")
    assert workers.stdout == alone.stdout
    assert {path.split("/")[0] for path, _ in _findings(workers)} == {"b"}


def test_standard_input_takes_the_configuration_of_its_name(repo: Path) -> None:
    data = BROKEN.read_bytes()
    as_a = run("check", "-f", "json", "--stdin-filename", "a/new.xodr", "-", stdin=data)
    assert as_a.exit_code == 0 and _findings(as_a) == [], as_a.stdout
    as_b = run("check", "-f", "json", "--stdin-filename", "b/new.xodr", "-", stdin=data)
    assert as_b.exit_code == 1 and ("b/new.xodr", "RL003") in _findings(as_b)


def test_a_config_file_given_governs_every_file(repo: Path) -> None:
    given = run("check", "-f", "json", "--config", "a/xodrlint.toml", "b/b.xodr", "a/a.xodr")
    assert _findings(given) == [("b/b.xodr", "PT003")]  # ST004 ignored in b/ too


def test_the_command_line_applies_on_top_of_every_files_configuration(repo: Path) -> None:
    result = run("check", "-f", "json", "--select", "ST,PT", "a/a.xodr", "b/b.xodr")
    # a/ still ignores ST; the selection is the command line's for both
    assert _findings(result) == [("b/b.xodr", "PT003"), ("b/b.xodr", "ST004")]


def test_config_shows_what_applies_to_a_path(repo: Path) -> None:
    for path in ("a/a.xodr", "a"):
        shown = json.loads(run("config", "-f", "json", path).stdout)
        assert shown["config_file"] == str(repo / "a" / "xodrlint.toml")
        assert shown["settings"]["ignore"]["value"] == ["RL003", "XS006", "ST", "SW"]
    shown = json.loads(run("config", "-f", "json", "b/b.xodr").stdout)
    assert shown["config_file"] is None and shown["settings"]["ignore"]["value"] == []


def test_each_files_own_fail_on_decides_its_exit_code(repo: Path) -> None:
    (repo / "b" / "xodrlint.toml").write_text('fail-on = "error"\nselect = ["PT"]\n', "utf-8")
    only_warnings = run("check", "a/a.xodr", "b/b.xodr")  # b/ holds one PT003 warning
    assert only_warnings.exit_code == 0, only_warnings.stdout
    (repo / "a" / "xodrlint.toml").write_text('select = ["PT"]\n', "utf-8")
    shutil.copy(TWO, repo / "a" / "a.xodr")
    assert run("check", "a/a.xodr", "b/b.xodr").exit_code == 1  # a/ fails on warnings


def test_each_folders_exclude_applies_to_its_own_files(repo: Path) -> None:
    (repo / "a" / "xodrlint.toml").write_text(A_CONFIG + 'exclude = ["old/"]\n', "utf-8")
    for folder in ("a", "b"):
        (repo / folder / "old").mkdir()
        shutil.copy(TWO, repo / folder / "old" / "x.xodr")
    listed = run("check", "--show-files", ".").stdout.splitlines()
    assert listed == ["a/a.xodr", "b/b.xodr", "b/old/x.xodr"]


def test_a_run_setting_below_the_runs_folder_is_said_and_not_used(repo: Path) -> None:
    (repo / "b" / "xodrlint.toml").write_text('output-format = "json"\n', "utf-8")
    both = run("check", "a/a.xodr", "b/b.xodr")
    assert not both.stdout.startswith("{")  # the run's own format: text
    assert both.stderr.count("output-format applies to a whole run") == 1
    alone = run("check", "b/b.xodr")  # a run of b/ alone is b/'s own
    assert json.loads(alone.stdout)["findings"]


def test_the_language_server_lints_each_file_as_check_does(repo: Path) -> None:
    folders = Folders(default_registry())
    for path in (repo / "a" / "a.xodr", repo / "b" / "b.xodr"):
        choice = folders.linter_for(path)
        served = choice.linter.lint_path(path, external=choice.external(path))
        checked = run("check", "-f", "json", path)
        assert [f.code for f in served.findings] == [c for _, c in _findings(checked)]


# -- what a review of the first version found ---------------------------------------------


def test_a_rule_no_configuration_knows_is_refused_before_linting(repo: Path) -> None:
    (repo / "b" / "xodrlint.toml").write_text('select = ["NOPE"]\n', "utf-8")
    for jobs in ("1", "2"):
        result = run("check", "-j", jobs, "a/a.xodr", "b/b.xodr")
        assert result.exit_code == 2, result.output
        assert result.stderr.splitlines() == [
            f"xodrlint: {repo / 'b' / 'xodrlint.toml'}: 'select': 'NOPE' matches no rule "
            "code, name or UID"
        ]


def test_a_file_named_two_ways_gets_one_report_whatever_the_order(repo: Path) -> None:
    (repo / "b" / "link.xodr").symlink_to("../a/a.xodr")
    forward = run("check", "-f", "json", "a/a.xodr", "b/link.xodr")
    backward = run("check", "-f", "json", "b/link.xodr", "a/a.xodr")
    assert forward.stdout == backward.stdout and forward.exit_code == backward.exit_code == 0


def test_unnamed_standard_input_has_the_working_folders_configuration(repo: Path) -> None:
    data = BROKEN.read_bytes()
    alone = run("check", "-f", "json", "-", stdin=data)
    beside = run("check", "-f", "json", "-", "a/a.xodr", stdin=data)
    assert [c for p, c in _findings(beside) if p == "-"] == [c for _, c in _findings(alone)]
    assert _findings(alone)


def test_the_runs_folder_is_found_as_the_paths_are_written(
    repo: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (repo / "a" / "xodrlint.toml").write_text(A_CONFIG + 'output-format = "json"\n', "utf-8")
    monkeypatch.chdir(repo / "a")
    text = run("check", "a.xodr", "../b/b.xodr")  # the folder holding both is the top
    assert not text.stdout.startswith("{") and "output-format applies" in text.stderr
    (repo / "b" / "link.xodr").symlink_to("../a/a.xodr")
    monkeypatch.chdir(repo)
    linked = run("check", "b/link.xodr")  # b/'s, where the link is, not a/'s
    assert not linked.stdout.startswith("{")


def test_a_configuration_above_two_repositories_governs_neither(tmp_path: Path) -> None:
    for name in ("r1", "r2"):
        (tmp_path / name / ".git").mkdir(parents=True)
        shutil.copy(TWO, tmp_path / name / "x.xodr")
    (tmp_path / "xodrlint.toml").write_text('output-format = "json"\n', "utf-8")
    result = run("check", tmp_path / "r1" / "x.xodr", tmp_path / "r2" / "x.xodr")
    assert result.exit_code == 1 and not result.stdout.startswith("{"), result.output


def test_no_report_overwrites_any_configuration_the_run_reads(repo: Path) -> None:
    (repo / "b" / "xodrlint.toml").write_text('select = ["PT"]\n', "utf-8")
    refused = run("check", "a", "b", "-o", "b/xodrlint.toml")
    assert refused.exit_code == 2
    assert "is a config file this run reads; refusing to overwrite it" in refused.stderr
    assert (repo / "b" / "xodrlint.toml").read_text("utf-8") == 'select = ["PT"]\n'
