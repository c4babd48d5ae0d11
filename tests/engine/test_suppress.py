"""Inline suppressions in XML comments, unused-suppression warnings, and the baseline."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from tests.conftest import REPO
from xodrlint.api import default_registry
from xodrlint.cli import app
from xodrlint.engine.linter import Linter, LintOptions

BROKEN = REPO / "examples" / "broken.xodr"
SWITCH_102 = '      <switch id="102" position="dynamic">'
SEGMENT = '      <segment roadId="1" sStart="60" sEnd="240" side="up"/>'


def _variant(tmp_path: Path, *replacements: tuple[str, str]) -> Path:
    text = BROKEN.read_text("utf-8")
    for old, new in replacements:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "map.xodr"
    path.write_text(text, "utf-8")
    return path


def _lint(path: Path, **options: object) -> list[tuple[str, int]]:
    report = Linter(default_registry(), LintOptions(**options)).lint_path(path)  # type: ignore[arg-type]
    return [(f.code, f.line) for f in report.findings]


def test_ignore_before_an_element_covers_its_subtree(tmp_path: Path) -> None:
    path = _variant(
        tmp_path,
        (
            SWITCH_102,
            "      <!-- xodrlint: ignore[XS006, SW006] W2 is renamed in ticket 42 -->\n"
            + SWITCH_102,
        ),
    )
    codes = [code for code, _ in _lint(path)]
    assert codes.count("XS006") == 2  # switch 101 and the segment stay
    assert "SW006" not in codes  # the sideTrack inside switch 102 is covered


def test_ignore_matches_prefixes_names_and_uids(tmp_path: Path) -> None:
    path = _variant(
        tmp_path,
        (
            SEGMENT,
            "      <!-- xodrlint: ignore[segment-s-out-of-range, asam.net:xodr:1.0.0:xml.valid_schema] -->\n"
            + SEGMENT,
        ),
    )
    assert [c for c, _ in _lint(path)] == ["XS006", "XS006", "SW006", "RL003"]


def test_ignore_file_applies_anywhere(tmp_path: Path) -> None:
    path = _variant(
        tmp_path, ("</OpenDRIVE>", "<!-- xodrlint: ignore-file[XS, RL] -->\n</OpenDRIVE>")
    )
    assert [c for c, _ in _lint(path)] == ["SW006", "ST004"]


def test_suppression_applies_after_the_chains(tmp_path: Path) -> None:
    # partner '999' names no switch: PT001; withholding PT001 must not let SW002/PT002 through
    path = _variant(
        tmp_path,
        (
            '<partner name="W2" id="102"/>',
            '<!-- xodrlint: ignore[PT001] -->\n        <partner name="W2" id="999"/>',
        ),
    )
    linter = Linter(default_registry(), LintOptions(select=("PT", "SW"), keep_suppressed=True))
    report = linter.lint_path(path)
    partner = "/OpenDRIVE/road[@id='1']/railroad/switch[@id='101']/partner"
    assert [f.code for f in report.findings if f.xpath == partner] == []
    assert [s.finding.code for s in report.suppressed] == ["PT001"]
    # switch 102's partner is a defect of its own: 101 does not answer it
    assert "PT002" in [f.code for f in report.findings]


def test_a_comment_that_is_not_a_directive_changes_nothing(tmp_path: Path) -> None:
    path = _variant(tmp_path, (SEGMENT, "      <!-- xodrlint ignore PT001 -->\n" + SEGMENT))
    assert len(_lint(path)) == 6


def test_unused_suppressions_are_reported_when_asked(tmp_path: Path) -> None:
    path = _variant(
        tmp_path,
        (SEGMENT, "      <!-- xodrlint: ignore[ST004, PT001] -->\n" + SEGMENT),
        ("</OpenDRIVE>", "<!-- xodrlint: ignore-file[NOPE999] -->\n</OpenDRIVE>"),
    )
    assert "XL001" not in [c for c, _ in _lint(path)]
    unused = [(c, line) for c, line in _lint(path, warn_unused_suppressions=True) if c == "XL001"]
    lines = path.read_text("utf-8").splitlines()
    assert unused == [
        ("XL001", lines.index("      <!-- xodrlint: ignore[ST004, PT001] -->") + 1),
        ("XL001", len(lines) - 1),
    ]
    # each at the column of its comment's "<!--"
    report = Linter(default_registry(), LintOptions(warn_unused_suppressions=True)).lint_path(path)
    assert [f.column for f in report.findings if f.code == "XL001"] == [7, 1]


def test_suppressed_findings_are_kept_only_when_asked(tmp_path: Path) -> None:
    path = _variant(
        tmp_path, (SEGMENT, "      <!-- xodrlint: ignore[ST004] not our map -->\n" + SEGMENT)
    )
    linter = Linter(default_registry(), LintOptions(keep_suppressed=True))
    report = linter.lint_path(path)
    [withheld] = report.suppressed
    assert (withheld.finding.code, withheld.kind, withheld.justification) == (
        "ST004",
        "inSource",
        "not our map",
    )
    assert Linter(default_registry(), LintOptions()).lint_path(path).suppressed == ()


def run(*args: str | Path) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


def test_baseline_reports_only_new_findings(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    # the baseline's paths are relative to the working folder
    maps = tmp_path / "maps"
    maps.mkdir()
    (maps / "a.xodr").write_bytes(BROKEN.read_bytes())
    baseline = tmp_path / "baseline.json"
    written = run("check", "maps", "--write-baseline", baseline)
    assert written.exit_code == 0
    assert "recorded 6 findings" in written.stderr
    one = run("check", "maps", "--select", "SW006", "--write-baseline", tmp_path / "one.json")
    assert one.stderr == f"xodrlint: recorded 1 finding in {tmp_path / 'one.json'}\n"
    document = json.loads(baseline.read_text("utf-8"))
    assert {e["path"] for e in document["findings"]} == {"maps/a.xodr"}

    assert run("check", "maps", "--baseline", baseline).exit_code == 0
    # lines moved by an edit above do not matter; a new defect does
    text = (maps / "a.xodr").read_text("utf-8")
    text = text.replace("<OpenDRIVE>", "<OpenDRIVE>\n  <!-- a new comment -->\n", 1)
    text = text.replace('<switch name="W1" id="101"', '<switch name="W1" id="103"')
    (maps / "a.xodr").write_text(text, "utf-8")
    result = run("check", "-f", "json", "maps", "--baseline", baseline)
    findings = json.loads(result.stdout)["findings"]
    assert [f["code"] for f in findings] == ["XS006", "PT002", "PT001"]
    assert result.exit_code == 1


def test_bad_baseline_is_exit_2(tmp_path: Path) -> None:
    bad = tmp_path / "baseline.json"
    bad.write_text("[1, 2]", "utf-8")
    result = run("check", BROKEN, "--baseline", bad)
    assert result.exit_code == 2
    assert "not an xodrlint baseline" in result.stderr


def test_the_documented_example_is_the_shipped_one_and_withholds_three_findings() -> None:
    doc = (REPO / "docs" / "suppressions.md").read_text("utf-8")
    example = (REPO / "examples" / "suppressed.xodr").read_text("utf-8")
    blocks = doc.split("```xml\n")[1:]
    assert blocks
    for block in blocks:
        assert block.split("```", 1)[0] in example
    linter = Linter(default_registry(), LintOptions(keep_suppressed=True))
    report = linter.lint_path(REPO / "examples" / "suppressed.xodr")
    assert [f.code for f in report.findings] == ["XS006", "ST004", "XS006"]
    assert sorted((s.finding.code, s.justification) for s in report.suppressed) == [
        ("RL003", "the siding is metre gauge"),
        ("SW006", "W2 is replaced in ticket 4711"),
        ("XS006", "W2 is replaced in ticket 4711"),
    ]


def test_suppressions_work_in_utf16_files(tmp_path: Path) -> None:
    text = (REPO / "examples" / "suppressed.xodr").read_text("utf-8")
    text = text.replace('encoding="UTF-8"', 'encoding="UTF-16"')
    path = tmp_path / "wide.xodr"
    path.write_bytes(text.encode("utf-16"))
    assert [c for c, _ in _lint(path)] == ["XS006", "ST004", "XS006"]


def test_unused_suppressions_only_count_rules_that_ran(tmp_path: Path) -> None:
    path = REPO / "examples" / "suppressed.xodr"
    # only ST004 runs: the XS006/SW006/RL003 entries cannot be judged, so none is stale
    findings = _lint(path, select=("ST004",), warn_unused_suppressions=True)
    assert [code for code, _ in findings] == ["ST004"]
    typo = _variant(tmp_path, (SEGMENT, "      <!-- xodrlint: ignore[NOPE123] -->\n" + SEGMENT))
    assert "XL001" in [c for c, _ in _lint(typo, select=("ST004",), warn_unused_suppressions=True)]


def test_writing_a_baseline_over_the_one_in_use_keeps_every_finding(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a.xodr").write_bytes(BROKEN.read_bytes())
    assert run("check", "a.xodr", "--write-baseline", "b.json").exit_code == 0
    again = run("check", "a.xodr", "--baseline", "b.json", "--write-baseline", "b.json")
    assert again.exit_code == 0 and "recorded 6 findings" in again.stderr
    assert len(json.loads((tmp_path / "b.json").read_text("utf-8"))["findings"]) == 6


def test_write_baseline_refuses_to_overwrite_an_input(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a.xodr").write_bytes(BROKEN.read_bytes())
    result = run("check", "a.xodr", "--write-baseline", "a.xodr")
    assert result.exit_code == 2
    assert "--write-baseline a.xodr: is one of the inputs" in result.stderr
    assert (tmp_path / "a.xodr").read_bytes() == BROKEN.read_bytes()


@pytest.mark.parametrize(
    "codec", ["utf-8", "utf-16", "utf-16-be", "utf-32", "utf-32-be", "utf-32-le", "latin-1"]
)
def test_only_a_file_with_a_directive_marker_has_its_comments_walked(codec: str) -> None:
    from xodrlint.engine.suppressions import may_hold_directives

    named = '<OpenDRIVE><header name="checked by xodrlint"/><!-- c --></OpenDRIVE>'
    holding = "<OpenDRIVE><!-- xodrlint: ignore[SW006] why --><road/></OpenDRIVE>"
    assert not may_hold_directives(named.encode(codec))
    assert may_hold_directives(holding.encode(codec))


def test_the_directive_markers_are_the_encodings_of_its_start() -> None:
    from xodrlint.engine.suppressions import _MARKER, _WIDE_MARKERS

    assert _MARKER == b"xodrlint:"
    assert {codec: "xodrlint:".encode(codec) for codec in _WIDE_MARKERS} == _WIDE_MARKERS
    assert set(_WIDE_MARKERS) == {"utf-16-le", "utf-16-be", "utf-32-le", "utf-32-be"}


def test_a_file_is_searched_for_the_marker_of_its_own_encoding_only() -> None:
    # a UTF-8 map cannot hold the UTF-16 bytes of a comment: one search of a large
    # file, not five (31 ms of a 20 MB map's run)
    from xodrlint.engine import suppressions

    searched: list[bytes] = []

    class Data(bytes):
        def __contains__(self, marker: object) -> bool:
            assert isinstance(marker, bytes)
            searched.append(marker)
            return super().__contains__(marker)

    assert not suppressions.may_hold_directives(Data(b"<OpenDRIVE><!-- c --></OpenDRIVE>"))
    assert searched == [b"xodrlint:"]


# -- XL001, a rule like the others, off by default -------------------------------------------

STALE = "      <!-- xodrlint: ignore[ST004, PT001] -->"
XL001_UID = "xodrlint:xodr:1.0.0:xodrlint.unused_suppression"


def _stale(tmp_path: Path) -> Path:
    """broken.xodr with one comment whose PT001 entry withholds nothing."""
    return _variant(tmp_path, (SEGMENT, STALE + "\n" + SEGMENT))


@pytest.mark.parametrize(
    ("select", "reported"),
    [
        (("ALL",), False),  # the default: XL001 is off
        (("X",), False),  # a prefix shorter than its family does not name it
        (("ALL", "XL001"), True),
        (("ALL", "XL"), True),
        (("ALL", "unused-suppression"), True),
        (("ALL", XL001_UID), True),
    ],
)
def test_xl001_runs_only_when_a_selection_names_it(
    tmp_path: Path, select: tuple[str, ...], reported: bool
) -> None:
    path = _stale(tmp_path)
    assert ("XL001" in [c for c, _ in _lint(path, select=select)]) is reported


def test_xl001_is_reported_at_the_comment_about_the_element_after_it(tmp_path: Path) -> None:
    path = _stale(tmp_path)
    report = Linter(default_registry(), LintOptions(select=("ST", "PT", "XL001"))).lint_path(path)
    [unused] = [f for f in report.findings if f.code == "XL001"]
    assert unused.line == path.read_text("utf-8").splitlines().index(STALE) + 1
    assert unused.xpath == "/OpenDRIVE/station[@id='500']/platform[@id='501']/segment"
    assert (unused.uid, unused.severity) == (XL001_UID, "warning")
    assert unused.message == "'xodrlint: ignore[ST004, PT001]' withholds no finding (PT001)"


def test_an_entry_naming_xl001_keeps_the_stale_entries_of_its_comment(tmp_path: Path) -> None:
    path = _variant(tmp_path, (SEGMENT, STALE.replace("PT001", "PT001, XL") + "\n" + SEGMENT))
    options = LintOptions(select=("ALL", "XL001"), keep_suppressed=True)
    report = Linter(default_registry(), options).lint_path(path)
    assert "XL001" not in [f.code for f in report.findings]
    assert [(s.finding.code, s.kind) for s in report.suppressed if s.finding.code == "XL001"] == [
        ("XL001", "inSource")
    ]


def test_ignore_all_in_a_comment_does_not_hide_its_own_xl001(tmp_path: Path) -> None:
    path = _variant(tmp_path, (SEGMENT, "      <!-- xodrlint: ignore[ALL] -->\n" + SEGMENT))
    # ALL withholds the segment's ST004 and XS006: used
    assert "XL001" not in [c for c, _ in _lint(path, select=("ALL", "XL001"))]
    # the partner rules find nothing on the segment: ALL withholds nothing, and says so
    assert [c for c, _ in _lint(path, select=("PT", "XL001"))] == ["XL001"]


def _check(tmp_path: Path, *args: str, config: str = "") -> Result:
    (tmp_path / "xodrlint.toml").write_text(config, "utf-8")
    return run("check", "-f", "json", *args)


def _xl001(result: Result) -> list[dict[str, object]]:
    return [f for f in json.loads(result.stdout)["findings"] if f["code"] == "XL001"]


def test_the_command_line_selects_and_ignores_xl001(tmp_path: Path) -> None:
    path = str(_stale(tmp_path))
    assert _xl001(_check(tmp_path, path)) == []
    assert len(_xl001(_check(tmp_path, path, "--extend-select", "XL001"))) == 1
    assert len(_xl001(_check(tmp_path, path, "--warn-unused-suppressions"))) == 1
    ignored = _check(tmp_path, path, "--warn-unused-suppressions", "--ignore", "XL001")
    assert ignored.exit_code == 1 and _xl001(ignored) == []
    from_config = "warn-unused-suppressions = true\n"
    assert _xl001(_check(tmp_path, path, "--ignore", "XL001", config=from_config)) == []
    assert len(_xl001(_check(tmp_path, path, config='extend-select = ["XL001"]\n'))) == 1


def test_the_config_sets_xl001s_severity_and_per_file_ignores_withhold_it(tmp_path: Path) -> None:
    path = str(_stale(tmp_path))
    severity = '[severity]\nXL001 = "error"\n'
    [finding] = _xl001(_check(tmp_path, path, "--extend-select", "XL001", config=severity))
    assert finding["severity"] == "error"
    ignores = '[per-file-ignores]\n"map.xodr" = ["XL001"]\n'
    result = _check(tmp_path, path, "--extend-select", "XL001", config=ignores)
    assert result.exit_code == 1 and _xl001(result) == []
    # the per-file-ignores above still apply
    sarif = run("check", "-f", "sarif", path, "--extend-select", "XL001", "--show-suppressed")
    [withheld] = [
        r for r in json.loads(sarif.stdout)["runs"][0]["results"] if r["ruleId"] == "XL001"
    ]
    assert withheld["suppressions"][0]["kind"] == "external"


def test_sarif_describes_the_rules_that_rules_lists(tmp_path: Path) -> None:
    listed = [entry["code"] for entry in json.loads(run("rules", "-f", "json").stdout)]
    assert "XL001" in listed
    for extra in ((), ("--warn-unused-suppressions",)):
        sarif = json.loads(run("check", "-f", "sarif", BROKEN, *extra).stdout)
        assert [rule["id"] for rule in sarif["runs"][0]["tool"]["driver"]["rules"]] == listed


def test_rules_and_explain_say_xl001_is_off_by_default() -> None:
    entries = {e["code"]: e for e in json.loads(run("rules", "-f", "json").stdout)}
    assert entries["XL001"]["enabled_by_default"] is False
    assert entries["XL001"]["uid"] == XL001_UID
    assert all(e["enabled_by_default"] for code, e in entries.items() if code != "XL001")
    page = run("explain", "XL001").stdout
    assert page.startswith("# XL001 unused-suppression\n")
    assert "off by default (`--extend-select XL001`)" in page
