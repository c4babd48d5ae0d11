"""Rules that apply from an OpenDRIVE version on (issue 28): ``rule(..., since=)``, the
engine leaving them out on files declaring an older version unless ``all_versions``, the
report's ``rules_not_applied`` (through worker processes too), the run's note, the
setting (``--all-versions``, ``all-versions = true``, the API, the language server's
options) and what ``rules``, ``explain`` and the pages say."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tests.conftest import REPO
from xodrlint import lint_bytes, lint_file
from xodrlint.api import default_registry
from xodrlint.cli import app
from xodrlint.cli.check.notes import NotApplied, run_notes
from xodrlint.config.discovery import find_config
from xodrlint.config.settings import Settings, settings_from
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import FileReport, Hit, RuleMeta, Severity
from xodrlint.model import RailNetwork
from xodrlint.rules import rule
from xodrlint.rules.registry import Registry
from xodrlint.runners.batch import Task, lint_tasks
from xodrlint.testing.pages import render_page

PLAIN_ENV: dict[str, str | None] = {"FORCE_COLOR": None, "TTY_COMPATIBLE": None, "NO_COLOR": None}
#: A 1.4 file with two tram lanes in one lane section: RL001's defect, by 1.7's convention.
TWO_TRAMS_1_4 = REPO / "rules" / "RL001" / "valid_1_4_two_tram_lanes_not_applied.xodr"
TWO_TRAMS_1_6 = REPO / "rules" / "RL001" / "valid_1_6_two_tram_lanes_not_applied.xodr"
#: A 1.7 file with RL001's defect: judged with or without --all-versions.
TWO_RAILS_1_7 = REPO / "rules" / "RL001" / "invalid_rail_lanes_both_sides.xodr"
CONVENTIONS = ("RL001", "RL002")


def _since_rules() -> list[str]:
    """The rules of the registry that apply from a version on (computed, not listed)."""
    return sorted(m.code for m in default_registry().metas if m.since is not None)


def _with_version(source: Path, target: Path, minor: str) -> Path:
    text = source.read_text("utf-8")
    target.write_text(text.replace('revMinor="4"', f'revMinor="{minor}"', 1), "utf-8")
    return target


# The declaration -------------------------------------------------------------------------


def test_rl001_and_rl002_apply_from_1_7() -> None:
    by_code = default_registry().by_code
    assert _since_rules() == list(CONVENTIONS)
    for code in CONVENTIONS:
        assert by_code[code].meta.since == (1, 7)
        assert by_code[code].meta.since_label == "1.7"
    assert by_code["RL003"].meta.since is None


@pytest.mark.parametrize("since", [(1,), (1, 7, 0), "1.7", (1, -1), (True, 7), (1.0, 7)])
def test_a_since_that_is_no_version_fails_the_declaration(since: object) -> None:
    with pytest.raises(ValueError, match="is not an OpenDRIVE version"):
        rule(code="AC001", name="x", uid="a.b:xodr:1.7.0:x", severity=Severity.INFO, since=since)  # type: ignore[arg-type]


def _pack_rule(since: tuple[int, int] | None) -> Registry:
    @rule(
        code="AC001", name="any-road", uid="a.b:xodr:1.5.0:x", severity=Severity.INFO, since=since
    )
    def any_road(network: RailNetwork) -> list[Hit]:
        return [Hit(road.element, f"road '{road.id}'") for road in network.roads[:1]]

    return Registry((any_road,))


ROAD = b"""<OpenDRIVE><header revMajor="1" revMinor="%s"/>
<road id="1" length="10" junction="-1"><planView/></road></OpenDRIVE>"""


@pytest.mark.parametrize(
    ("minor", "all_versions", "judged"),
    [
        (b"4", False, False),
        (b"5", False, True),  # the first version it applies to
        (b"9", False, True),
        (b"4", True, True),
        (b"x", False, True),  # no readable version (XS004): nothing says it does not hold
    ],
)
def test_the_engine_leaves_a_rule_out_below_its_version(
    minor: bytes, all_versions: bool, judged: bool
) -> None:
    linter = Linter(_pack_rule((1, 5)), LintOptions(all_versions=all_versions))
    report = linter.lint_bytes(ROAD % minor, "net.xodr")
    assert [f.code for f in report.findings] == (["AC001"] if judged else [])
    assert report.rules_not_applied == (() if judged else ("AC001",))


def test_a_rule_without_since_judges_every_version() -> None:
    report = Linter(_pack_rule(None), LintOptions()).lint_bytes(ROAD % b"1", "net.xodr")
    assert [f.code for f in report.findings] == ["AC001"]
    assert report.rules_not_applied == ()


def test_only_selected_rules_are_named_as_not_applied() -> None:
    data = TWO_TRAMS_1_4.read_bytes()
    assert lint_bytes(data).rules_not_applied == CONVENTIONS
    assert lint_bytes(data, select=["RL002", "ST"]).rules_not_applied == ("RL002",)
    assert lint_bytes(data, select=["ST"]).rules_not_applied == ()


def test_the_api_applies_every_rule_with_all_versions() -> None:
    assert [f.code for f in lint_file(TWO_TRAMS_1_4, select=["RL001"]).findings] == []
    judged = lint_file(TWO_TRAMS_1_4, select=["RL001"], all_versions=True)
    assert [f.code for f in judged.findings] == ["RL001"]
    assert judged.rules_not_applied == ()
    assert [f.code for f in lint_file(TWO_RAILS_1_7, select=["RL001"]).findings] == ["RL001"]


def test_track_rules_still_judge_what_rl001_leaves_out() -> None:
    # the catalogue: where RL001 and RL002 are not applied, the other rules run as usual
    report = lint_file(TWO_TRAMS_1_4)
    assert report.rules_not_applied == CONVENTIONS
    assert set(report.rules_not_applied).isdisjoint(f.code for f in report.findings)
    ran = Linter(default_registry(), LintOptions()).rules
    assert any(r.code.startswith("TR") for r in ran)


# Suppressions: a rule that did not judge a file cannot tell an entry naming it stale -----


SUPPRESSED = """<!-- xodrlint: ignore-file[RL001] 1.4 exports put both tracks on one road -->"""


def test_a_suppression_of_a_rule_not_applied_is_not_unused(tmp_path: Path) -> None:
    text = TWO_TRAMS_1_4.read_text("utf-8").replace("<OpenDRIVE>", f"<OpenDRIVE>\n{SUPPRESSED}", 1)
    select = ["RL001", "XL001"]
    default = lint_bytes(text.encode(), "a.xodr", select=select)
    assert [f.code for f in default.findings] == []  # not stale: RL001 did not judge it
    every = lint_bytes(text.encode(), "a.xodr", select=select, all_versions=True)
    assert [f.code for f in every.findings] == []  # withholds RL001's finding
    plain = lint_bytes(TWO_TRAMS_1_4.read_bytes(), "a.xodr", select=select, all_versions=True)
    assert [f.code for f in plain.findings] == ["RL001"]
    # on a 1.7 file without the defect the same comment is stale
    clean = (REPO / "rules" / "RL001" / "valid_one_rail_lane_per_section.xodr").read_text()
    stale = clean.replace("<OpenDRIVE>", f"<OpenDRIVE>\n{SUPPRESSED}", 1)
    assert [f.code for f in lint_bytes(stale.encode(), select=select).findings] == ["XL001"]


# The note --------------------------------------------------------------------------------


def _report(version: str, codes: tuple[str, ...] = CONVENTIONS) -> FileReport:
    return FileReport(f"{version}.xodr", declared_version=version, rules_not_applied=codes)


def _meta(code: str, since: tuple[int, int] | None) -> RuleMeta:
    return RuleMeta(code, code.lower(), "a.b:xodr:1.4.0:x", Severity.ERROR, "s", "", since=since)


METAS = (_meta("RL001", (1, 7)), _meta("RL002", (1, 7)), _meta("AC001", (1, 5)))


def test_the_note_counts_files_by_declared_version() -> None:
    reports = [_report("1.6"), _report("1.4"), _report("1.4"), _report("1.5"), _report("1.4")]
    reports.append(FileReport("new.xodr", declared_version="1.7"))  # judged by every rule
    assert run_notes(reports, METAS) == (
        "RL001, RL002 not applied to 3 files declaring OpenDRIVE 1.4, 1 declaring 1.5 and "
        "1 declaring 1.6 (they apply from 1.7 on; --all-versions applies them)",
    )


def test_the_note_of_one_rule_and_one_file() -> None:
    assert run_notes([_report("1.4", ("RL002",))], METAS) == (
        "RL002 not applied to 1 file declaring OpenDRIVE 1.4 (it applies from 1.7 on; "
        "--all-versions applies it)",
    )


def test_rules_of_different_versions_get_a_note_each() -> None:
    reports = [_report("1.4", ("AC001", "RL001")), _report("1.6", ("RL001",))]
    assert run_notes(reports, METAS) == (
        "AC001 not applied to 1 file declaring OpenDRIVE 1.4 (it applies from 1.5 on; "
        "--all-versions applies it)",
        "RL001 not applied to 1 file declaring OpenDRIVE 1.4 and 1 declaring 1.6 (it "
        "applies from 1.7 on; --all-versions applies it)",
    )


def test_no_note_when_every_rule_judged_every_file() -> None:
    assert run_notes([FileReport("a.xodr", declared_version="1.4")], METAS) == ()
    tally = NotApplied()
    tally.add(FileReport("a.xodr", declared_version="1.7"))
    assert tally.notes(METAS) == ()


def test_the_note_follows_the_built_in_schema_note() -> None:
    builtin = _report("1.4")._replace(schema_builtin=True)
    notes = run_notes([builtin], METAS)
    assert len(notes) == 2 and notes[1].startswith("RL001, RL002 not applied")


# Settings --------------------------------------------------------------------------------


def test_all_versions_is_a_config_key_and_an_option(tmp_path: Path) -> None:
    (tmp_path / "xodrlint.toml").write_text("all-versions = true\n", "utf-8")
    settings = settings_from(find_config(tmp_path / "a.xodr"), {})
    assert settings.all_versions is True
    assert ("all-versions", True, str(tmp_path / "xodrlint.toml")) in settings.as_rows()
    assert LintOptions.of(settings).all_versions is True  # the language server's too
    assert LintOptions.of(Settings()).all_versions is False
    overridden = settings_from(find_config(tmp_path / "a.xodr"), {"all-versions": False})
    assert overridden.all_versions is False


def test_a_config_value_that_is_no_boolean_is_refused(tmp_path: Path) -> None:
    config = tmp_path / "xodrlint.toml"
    config.write_text('all-versions = "yes"\n', "utf-8")
    args = ["check", "--config", str(config), str(TWO_TRAMS_1_4)]
    result = CliRunner().invoke(app, args, env=PLAIN_ENV)
    assert result.exit_code == 2 and "all-versions" in result.stderr


def test_xodrlint_config_shows_the_key(tmp_path: Path) -> None:
    (tmp_path / "xodrlint.toml").write_text("all-versions = true\n", "utf-8")
    result = CliRunner().invoke(app, ["config", str(tmp_path), "-f", "json"], env=PLAIN_ENV)
    assert result.exit_code == 0, result.output
    shown = json.loads(result.stdout)["settings"]["all-versions"]
    assert shown == {"value": True, "source": str(tmp_path / "xodrlint.toml")}
    assert ("all-versions", False, "default") in Settings().as_rows()
    plain = CliRunner().invoke(app, ["config", str(tmp_path)], env=PLAIN_ENV).stdout
    assert "all-versions" in plain


def test_check_takes_all_versions_from_the_config(tmp_path: Path) -> None:
    (tmp_path / "xodrlint.toml").write_text("all-versions = true\n", "utf-8")
    target = tmp_path / "two.xodr"
    target.write_bytes(TWO_TRAMS_1_4.read_bytes())
    args = ["check", "-f", "json", "--select", "RL001", str(target)]
    document = json.loads(CliRunner().invoke(app, args, env=PLAIN_ENV).stdout)
    assert [f["code"] for f in document["findings"]] == ["RL001"]
    assert document["notes"] == [] or all("not applied" not in n for n in document["notes"])


# Many files: the report's field travels from worker processes ---------------------------


def test_worker_processes_carry_what_was_not_applied(tmp_path: Path) -> None:
    paths = [_with_version(TWO_TRAMS_1_4, tmp_path / f"m{m}.xodr", m) for m in "4567"]
    tasks = [Task(path, path.name) for path in paths]
    linter = Linter(default_registry(), LintOptions())
    reports = lint_tasks(linter, tasks, jobs=2)
    assert [r.rules_not_applied for r in reports] == [CONVENTIONS] * 3 + [()]
    assert [r.declared_version for r in reports] == ["1.4", "1.5", "1.6", "1.7"]


# What rules, explain and the pages say --------------------------------------------------


def test_rules_json_and_explain_say_from_which_version() -> None:
    entries = json.loads(CliRunner().invoke(app, ["rules", "-f", "json"]).stdout)
    since = {entry["code"]: entry["since"] for entry in entries}
    assert sorted(code for code, version in since.items() if version) == _since_rules()
    assert since["RL001"] == "1.7" and since["RL003"] is None
    page = CliRunner().invoke(app, ["explain", "RL002"], env=PLAIN_ENV).stdout
    assert "from OpenDRIVE 1.7 on (older files: `--all-versions`)" in page
    assert "from OpenDRIVE" not in CliRunner().invoke(app, ["explain", "RL003"]).stdout


def test_the_page_of_a_rule_with_since_says_so() -> None:
    meta = default_registry().by_code["RL001"].meta
    page = render_page(meta, [], REPO)
    assert "- Applies to files declaring OpenDRIVE 1.7 or later; older ones only with " in page
    written = (REPO / "docs" / "rules" / "RL001.md").read_text("utf-8")
    assert "OpenDRIVE 1.7 or later" in written
    assert "or later" not in render_page(default_registry().by_code["RL003"].meta, [], REPO)
