"""SARIF's result limit: GitHub rejects a run of more than 25,000 results, so a log keeps
the most important (errors first), says how many it left out on stderr and in the run,
and ``--sarif-max-results`` / ``sarif-max-results`` change the limit (0: none)."""

from __future__ import annotations

import io
import json
import re
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner, Result

from tests.conftest import REPO
from xodrlint import __version__
from xodrlint.api import default_registry
from xodrlint.cli import app
from xodrlint.config.plugins import Plugin
from xodrlint.config.settings import DEFAULT_SARIF_MAX_RESULTS
from xodrlint.findings import FileReport, Location, RunResult, Severity, Suppressed
from xodrlint.formatters import Formatter, get_formatter, warnings_of
from xodrlint.formatters.sarif import SarifFormatter, as_sarif

from .test_formatters import PLAIN_ENV, assert_valid_sarif, finding, render, sarif

BROKEN = REPO / "examples" / "broken.xodr"
SUPPRESSED = REPO / "examples" / "suppressed.xodr"
#: examples/broken.xodr: (line, code, level) of its six findings, in the usual order.
BROKEN_RESULTS = [
    (25, "XS006", "error"),
    (30, "XS006", "error"),
    (32, "SW006", "warning"),
    (53, "RL003", "error"),
    (62, "ST004", "error"),
    (62, "XS006", "error"),
]
LIMIT_WARNING = re.compile(
    r"xodrlint: warning: left out (\d+) of (\d+) SARIF results, keeping the (\d+) most "
    r"important \(errors first\); --sarif-max-results N changes the limit \(default 25000, "
    r"the most GitHub code scanning accepts; 0: no limit\)"
)


def run(*args: str | Path, code: int) -> Result:
    result = CliRunner().invoke(app, [str(a) for a in args], env=PLAIN_ENV)
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception
    assert result.exit_code == code, (result.stdout, result.stderr)
    return result


def summary(log: dict[str, Any]) -> list[tuple[int, str, str]]:
    return [
        (r["locations"][0]["physicalLocation"]["region"]["startLine"], r["ruleId"], r["level"])
        for r in log["runs"][0]["results"]
    ]


def limit_notifications(log: dict[str, Any]) -> list[dict[str, Any]]:
    notifications = log["runs"][0]["invocations"][0]["toolExecutionNotifications"]
    return [n for n in notifications if n["level"] == "warning"]


def left_out(stderr: str) -> tuple[int, int, int] | None:
    """(left out, total, kept) from the one limit warning on stderr, ``None`` without one."""
    found = [LIMIT_WARNING.fullmatch(line) for line in stderr.splitlines()]
    matches = [m for m in found if m]
    assert len(matches) <= 1, stderr
    return (int(matches[0][1]), int(matches[0][2]), int(matches[0][3])) if matches else None


# The command line ------------------------------------------------------------------


@pytest.mark.parametrize("to_file", [False, True], ids=["stdout", "output-file"])
def test_a_small_limit_keeps_errors_first_and_says_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, to_file: bool
) -> None:
    monkeypatch.chdir(REPO)
    target = tmp_path / "x.sarif"
    output = ("-o", target) if to_file else ()
    done = run("check", "-f", "sarif", "--sarif-max-results", "3", *output, BROKEN, code=1)
    log = json.loads(target.read_text("utf-8") if to_file else done.stdout)
    assert_valid_sarif(log)
    # the warning at line 32 comes before the errors at 53 and 62 in the file, but they
    # are errors: it is left out, and so are the two errors of the highest line
    assert summary(log) == [(25, "XS006", "error"), (30, "XS006", "error"), (53, "RL003", "error")]
    (note,) = limit_notifications(log)
    assert note["properties"] == {"results": 6, "kept": 3, "leftOut": 3}
    assert left_out(done.stderr) == (3, 6, 3)
    assert f"xodrlint: warning: {note['message']['text']}" in done.stderr.splitlines()
    assert log["runs"][0]["invocations"][0]["executionSuccessful"] is True


def test_a_report_file_keeps_to_the_limit_and_its_warning_names_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(REPO)
    first, second = tmp_path / "a.sarif", tmp_path / "b.sarif"
    done = run(
        "check",
        "-f",
        "sarif",
        "-o",
        first,
        "--report",
        f"sarif={second}",
        "--report",
        f"json={tmp_path / 'x.json'}",
        "--sarif-max-results",
        "2",
        BROKEN,
        code=1,
    )
    for target in (first, second):
        log = json.loads(target.read_text("utf-8"))
        assert summary(log) == [(25, "XS006", "error"), (30, "XS006", "error")]
    assert len(json.loads((tmp_path / "x.json").read_text("utf-8"))["findings"]) == 6
    lines = done.stderr.splitlines()
    assert left_out(lines[0]) == (4, 6, 2)
    prefix = f"xodrlint: warning: --report sarif={second}: "
    assert lines[1].startswith(prefix)
    assert left_out(lines[1].replace(prefix, "xodrlint: warning: ")) == (4, 6, 2)
    assert len(lines) == 2


def test_kept_results_have_the_fingerprints_of_the_whole_run(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(REPO)
    whole = json.loads(run("check", "-f", "sarif", BROKEN, code=1).stdout)
    cut = json.loads(run("check", "-f", "sarif", "--sarif-max-results", "4", BROKEN, code=1).stdout)
    prints = {
        r["partialFingerprints"]["xodrlint/v1"]: r["message"]["text"]
        for r in whole["runs"][0]["results"]
    }
    kept = cut["runs"][0]["results"]
    assert len(kept) == 4
    assert all(
        prints[r["partialFingerprints"]["xodrlint/v1"]] == r["message"]["text"] for r in kept
    )


def test_suppressed_results_count_after_every_unsuppressed_one(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # examples/suppressed.xodr: three reported errors; suppressed an RL003 error (line 52),
    # an SW006 warning (31) and an XS006 error (29)
    monkeypatch.chdir(REPO)
    args = ("check", "-f", "sarif", "--show-suppressed", SUPPRESSED)
    whole = json.loads(run(*args, code=1).stdout)
    assert sum("suppressions" in r for r in whole["runs"][0]["results"]) == 3
    log = json.loads(run(*args, "--sarif-max-results", "4", code=1).stdout)
    assert_valid_sarif(log)
    results = log["runs"][0]["results"]
    assert ["suppressions" in r for r in results] == [False, False, False, True]
    assert summary(log)[3] == (29, "XS006", "error")  # the first suppressed error
    two = json.loads(run(*args, "--sarif-max-results", "2", code=1).stdout)
    assert not any("suppressions" in r for r in two["runs"][0]["results"])


def test_zero_is_no_limit_and_the_command_line_wins_over_the_config(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "xodrlint.toml").write_text("sarif-max-results = 2\n", "utf-8")
    map_file = tmp_path / "broken.xodr"
    map_file.write_bytes(BROKEN.read_bytes())
    monkeypatch.chdir(tmp_path)
    from_config = run("check", "-f", "sarif", map_file, code=1)
    assert len(json.loads(from_config.stdout)["runs"][0]["results"]) == 2
    assert left_out(from_config.stderr) == (4, 6, 2)
    unlimited = run("check", "-f", "sarif", "--sarif-max-results", "0", map_file, code=1)
    log = json.loads(unlimited.stdout)
    assert summary(log) == [(line, code, level) for line, code, level in BROKEN_RESULTS]
    assert limit_notifications(log) == []
    assert "warning" not in unlimited.stderr


def test_other_formats_ignore_the_limit(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(REPO)
    done = run("check", "-f", "json", "--sarif-max-results", "1", BROKEN, code=1)
    assert len(json.loads(done.stdout)["findings"]) == 6
    assert "warning" not in done.stderr


@pytest.mark.parametrize("value", ["-1", "2.5", "many"])
def test_a_bad_limit_on_the_command_line_is_a_usage_error(value: str) -> None:
    done = run("check", "-f", "sarif", f"--sarif-max-results={value}", BROKEN, code=2)
    assert "--sarif-max-results" in done.stderr
    assert done.stdout == ""


@pytest.mark.parametrize("value", ["-1", "2.5", '"3"', "true"])
def test_a_bad_limit_in_the_config_is_a_usage_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, value: str
) -> None:
    (tmp_path / "xodrlint.toml").write_text(f"sarif-max-results = {value}\n", "utf-8")
    (tmp_path / "broken.xodr").write_bytes(BROKEN.read_bytes())
    monkeypatch.chdir(tmp_path)
    done = run("check", "-f", "sarif", "broken.xodr", code=2)
    (line,) = done.stderr.splitlines()
    assert line.startswith(f"xodrlint: {tmp_path / 'xodrlint.toml'}: 'sarif-max-results' must be")
    assert run("config", ".", code=2).stderr == done.stderr


def test_the_config_command_shows_the_limit_and_its_source(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    shown = json.loads(run("config", ".", "-f", "json", code=0).stdout)["settings"]
    assert shown["sarif-max-results"] == {"value": DEFAULT_SARIF_MAX_RESULTS, "source": "default"}
    (tmp_path / "xodrlint.toml").write_text("sarif-max-results = 0\n", "utf-8")
    text = run("config", ".", code=0).stdout
    (row,) = [line for line in text.splitlines() if line.startswith("sarif-max-results ")]
    assert row.split() == ["sarif-max-results", "0", "#", str(tmp_path / "xodrlint.toml")]


def many_findings_map(warnings: int, errors: int) -> str:
    """A map of one rail road, then ``warnings`` stations that share one name (ST008: a
    warning each but the first), then ``errors`` stations without a platform (ST001: an
    error each): the errors come last in the file. The road adds one RL002 warning."""
    length = 2 * warnings + 10
    head = f"""<?xml version="1.0" encoding="UTF-8"?>
<OpenDRIVE>
  <header revMajor="1" revMinor="7" name="many"/>
  <road name="main" length="{length}" id="1" junction="-1">
    <planView><geometry s="0" x="0" y="0" hdg="0" length="{length}"><line/></geometry></planView>
    <lanes><laneSection s="0"><center><lane id="0" type="none" level="false"/></center>
      <right><lane id="-1" type="rail" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane></right>
    </laneSection></lanes>
  </road>
"""
    named = (
        f'  <station name="S" id="w{i}"><platform id="p{i}"><segment roadId="1" '
        f'sStart="{2 * i}" sEnd="{2 * i + 1}" side="right"/></platform></station>\n'
        for i in range(warnings + 1)
    )
    bare = (f'  <station name="E{i}" id="e{i}"/>\n' for i in range(errors))
    return head + "".join(named) + "".join(bare) + "</OpenDRIVE>\n"


def test_the_default_limit_is_githubs_25000(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    warnings, errors = 19_000, 6_001  # 25,002 results with the RL002 warning
    (tmp_path / "many.xodr").write_text(many_findings_map(warnings, errors), "utf-8")
    monkeypatch.chdir(tmp_path)
    done = run("check", "-f", "sarif", "-o", "many.sarif", "many.xodr", code=1)
    assert left_out(done.stderr) == (2, 25_002, 25_000)
    log = json.loads((tmp_path / "many.sarif").read_text("utf-8"))
    results = summary(log)
    assert len(results) == DEFAULT_SARIF_MAX_RESULTS
    assert sum(level == "error" for _, _, level in results) == errors  # every error kept
    # the two warnings of the highest lines are the ones left out
    lines = [line for line, _, _ in results]
    assert lines == sorted(lines)
    last_warning = max(line for line, _, level in results if level == "warning")
    assert last_warning == 10 + warnings - 2  # the stations start at line 10
    (note,) = limit_notifications(log)
    assert note["properties"] == {"results": 25_002, "kept": 25_000, "leftOut": 2}
    # the schema check of 25,000 results takes seconds; their shape is that of a few
    sample = json.loads(json.dumps(log))
    run_log = sample["runs"][0]
    run_log["results"] = run_log["results"][:3] + run_log["results"][-3:]
    assert_valid_sarif(sample)


# The formatter -----------------------------------------------------------------------


def synthetic(count: int, **changes: Any) -> RunResult:
    findings = tuple(
        finding(line=i + 1, xpath=f"/OpenDRIVE/road[@id='{i}']", **changes) for i in range(count)
    )
    report = FileReport("net.xodr", findings=findings)
    return RunResult((report,), default_registry().metas, __version__, root=str(REPO))


def test_the_formatter_defaults_to_the_limit_and_zero_lifts_it() -> None:
    # the API's formatter (no option given) keeps to GitHub's limit too
    result = synthetic(DEFAULT_SARIF_MAX_RESULTS + 1, severity=Severity.INFO)
    default = get_formatter("sarif")
    log = json.loads(render_with(default, result))
    assert len(log["runs"][0]["results"]) == DEFAULT_SARIF_MAX_RESULTS
    assert summary(log)[-1][0] == DEFAULT_SARIF_MAX_RESULTS  # the last line is left out
    (warning,) = warnings_of(default)
    assert warning.startswith(f"left out 1 of {DEFAULT_SARIF_MAX_RESULTS + 1} SARIF results")
    unlimited = as_sarif(result, max_results=0)["runs"][0]
    assert len(unlimited["results"]) == DEFAULT_SARIF_MAX_RESULTS + 1
    assert limit_notifications({"runs": [unlimited]}) == []
    with pytest.raises(ValueError, match="max_results"):
        SarifFormatter(max_results=-1)


def render_with(formatter: Formatter, result: RunResult) -> str:
    stream = io.StringIO()
    formatter.render(result, stream)
    return stream.getvalue()


def test_levels_rank_before_paths_and_lines() -> None:
    info, warning, error = Severity.INFO, Severity.WARNING, Severity.ERROR
    findings = (
        finding(path="a.xodr", line=1, severity=info, code="XS005"),
        finding(path="a.xodr", line=9, severity=error),
        finding(path="b.xodr", line=2, severity=warning, code="SW006"),
        finding(path="b.xodr", line=1, severity=error),
        finding(path="a.xodr", line=5, severity=warning, code="SW006"),
    )
    reports = (FileReport("a.xodr", findings=findings[:2]), FileReport("b.xodr", findings[2:]))
    result = RunResult(reports, default_registry().metas, __version__, root=str(REPO))
    kept = as_sarif(result, max_results=3)["runs"][0]["results"]
    # both errors, then the warning of the first path; shown in the usual order
    assert [(uri(r), r["level"]) for r in kept] == [
        ("a.xodr", "error"),
        ("b.xodr", "error"),
        ("a.xodr", "warning"),
    ]
    whole = as_sarif(result)["runs"][0]["results"]
    assert as_sarif(result, max_results=5)["runs"][0]["results"] == whole


def uri(entry: dict[str, Any]) -> str:
    return str(entry["locations"][0]["physicalLocation"]["artifactLocation"]["uri"])


def test_left_out_results_leave_no_rule_or_location_behind() -> None:
    # a kept error names the element of a left-out finding as related; a left-out
    # finding of a rule outside the table gets no rule descriptor
    related = (Location(7, "/OpenDRIVE/road[@id='7']"), Location(8, "/OpenDRIVE/road[@id='8']"))
    kept = finding(line=3, related=related)
    dropped = finding(
        line=7, xpath="/OpenDRIVE/road[@id='7']", code="ZZ999", severity=Severity.INFO
    )
    suppressed = Suppressed(finding(line=8, code="ZZ998"), "inSource", "reviewed")
    report = FileReport("net.xodr", findings=(kept, dropped), suppressed=(suppressed,))
    result = RunResult((report,), default_registry().metas, __version__, root=str(REPO))
    log = sarif(result)  # the default limit: all three
    assert {"ZZ999", "ZZ998"} <= {rule["id"] for rule in log["runs"][0]["tool"]["driver"]["rules"]}
    limited = as_sarif(result, max_results=1)
    assert_valid_sarif(limited)
    run_log = limited["runs"][0]
    (only,) = run_log["results"]
    assert [loc["id"] for loc in only["relatedLocations"]] == [1, 2]
    assert [loc["physicalLocation"]["region"]["startLine"] for loc in only["relatedLocations"]] == [
        7,
        8,
    ]
    rule_ids = [rule["id"] for rule in run_log["tool"]["driver"]["rules"]]
    assert "ZZ999" not in rule_ids and "ZZ998" not in rule_ids
    assert rule_ids[only["ruleIndex"]] == only["ruleId"]


def test_the_warning_says_nothing_under_the_limit() -> None:
    formatter = get_formatter("sarif", sarif_max_results=6)
    render_with(formatter, synthetic(6))
    assert warnings_of(formatter) == ()
    assert limit_notifications(json.loads(render("sarif", synthetic(6)))) == []


# Plugin formatters -------------------------------------------------------------------


class PluginFormatter:
    """A third-party formatter whose factory takes the two keywords it always got."""

    def __init__(self, *, show_source: bool, quiet: bool) -> None:
        self.options = (show_source, quiet)
        self.warnings: tuple[str, ...] = ()

    def render(self, result: RunResult, stream: Any) -> None:
        stream.write(f"{len(result.findings)} findings\n")
        self.warnings = ("the plugin left something out",)


def test_plugin_factories_keep_their_two_keywords(monkeypatch: pytest.MonkeyPatch) -> None:
    point = Plugin("plugin", f"{__name__}:PluginFormatter", "xodrlint.formatters")
    monkeypatch.setattr("xodrlint.formatters._entry_points", lambda: [point])
    formatter = get_formatter("plugin", show_source=True, quiet=False, sarif_max_results=5)
    assert isinstance(formatter, PluginFormatter)
    assert formatter.options == (True, False)
    monkeypatch.chdir(REPO)
    done = run("check", "-f", "plugin", "--sarif-max-results", "1", BROKEN, code=1)
    assert done.stdout == "6 findings\n"
    # what a plugin says it left out is printed as SARIF's limit is
    assert done.stderr.splitlines()[-1] == "xodrlint: warning: the plugin left something out"


def test_warnings_of_a_formatter_without_any() -> None:
    assert warnings_of(get_formatter("json")) == ()

    class Odd:
        warnings = "not a tuple"

        def render(self, result: RunResult, stream: Any) -> None:
            pass

    assert warnings_of(Odd()) == ()
