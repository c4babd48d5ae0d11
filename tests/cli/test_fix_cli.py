"""``xodrlint check --fix``, ``--diff`` and ``--unsafe-fixes`` as a user runs them: files
written back, diffs, standard input's fixed document on standard output, the marks and
counts of the text report, the JSON report's fixes, and what is refused."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from tests.cli.test_cli import OUTPUT_SCHEMA, cli
from tests.conftest import REPO

CASES = REPO / "rules" / "PT003"
MISMATCH = CASES / "invalid_name_mismatch.xodr"
MISMATCH_FIXED = CASES / "invalid_name_mismatch.fixed.xodr"


def _copy(tmp_path: Path, source: Path = MISMATCH, name: str = "a.xodr") -> Path:
    target = tmp_path / name
    shutil.copyfile(source, target)
    return target


def test_check_marks_fixable_findings_and_counts_them(tmp_path: Path) -> None:
    target = _copy(tmp_path)
    done = cli("check", "--select", "PT003", target, code=1)
    assert "PT003 [warning] [*] partner of switch '12'" in done.stdout
    assert "[*] 1 fixable with --fix." in done.stdout


def test_fix_writes_the_file_and_reports_what_is_left(tmp_path: Path) -> None:
    target = _copy(tmp_path)
    done = cli("check", "--select", "PT003", "--fix", target, code=0)
    assert "Found 1 finding (1 fixed, 0 remaining) in 1 file." in done.stdout
    assert target.read_bytes() == MISMATCH_FIXED.read_bytes()
    again = cli("check", "--select", "PT003", "--fix", target, code=0)
    assert "All checks passed" in again.stdout
    assert target.read_bytes() == MISMATCH_FIXED.read_bytes()


def test_diff_shows_what_fix_would_change_and_writes_nothing(tmp_path: Path) -> None:
    target = _copy(tmp_path)
    done = cli("check", "--select", "PT003", "--diff", target, code=1)
    assert target.read_bytes() == MISMATCH.read_bytes()
    assert f"--- a/{target.as_posix()}" in done.stdout
    assert '-        <partner name="W23" id="32"/>' in done.stdout
    assert '+        <partner name="W32" id="32"/>' in done.stdout
    assert "would fix 1 finding in 1 file" in done.stderr
    clean = cli("check", "--select", "PT003", "--diff", MISMATCH_FIXED, code=0)
    assert clean.stdout == "" and "no fixes available" in clean.stderr


def test_fix_on_standard_input_writes_the_document_to_standard_output() -> None:
    done = cli("check", "--select", "PT003", "--fix", "-", code=0, stdin=MISMATCH.read_bytes())
    assert done.stdout_bytes == MISMATCH_FIXED.read_bytes()
    assert "1 fixed, 0 remaining" in done.stderr


def test_json_findings_carry_their_fix_with_its_edits(tmp_path: Path) -> None:
    import jsonschema  # type: ignore[import-untyped, unused-ignore]

    done = cli("check", "-f", "json", "--select", "PT003", _copy(tmp_path), code=1)
    document = json.loads(done.stdout)
    jsonschema.validate(document, OUTPUT_SCHEMA)
    (finding,) = document["findings"]
    assert finding["fix"] == {
        "applicability": "safe",
        "message": "name the partner 'W32'",
        "edits": [{"content": "W32", "line": 22, "column": 24, "end_line": 22, "end_column": 27}],
    }
    lines = json.loads(cli("check", "-f", "jsonl", "--select", "PT003", MISMATCH, code=1).stdout)
    assert lines["fix"] == finding["fix"]


def test_fix_with_jobs_fixes_every_file_in_the_workers(tmp_path: Path) -> None:
    targets = [_copy(tmp_path, name=f"{n}.xodr") for n in range(4)]
    done = cli("check", "--select", "PT003", "--fix", "--jobs", "2", tmp_path, code=0)
    assert "Found 4 findings (4 fixed, 0 remaining) in 4 files." in done.stdout
    assert all(t.read_bytes() == MISMATCH_FIXED.read_bytes() for t in targets)


def test_fix_refuses_a_read_only_file_and_goes_on(tmp_path: Path) -> None:
    locked = _copy(tmp_path, name="a.xodr")
    locked.chmod(0o444)
    free = _copy(tmp_path, name="b.xodr")
    done = cli("check", "--select", "PT003", "--fix", tmp_path, code=2)
    assert f"{locked.as_posix()}: not fixed: is read-only" in done.stderr
    assert locked.read_bytes() == MISMATCH.read_bytes()
    assert free.read_bytes() == MISMATCH_FIXED.read_bytes()


def test_fix_is_refused_for_a_url_and_a_scheduler(tmp_path: Path) -> None:
    url = cli("check", "--fix", "s3://bucket/a.xodr", code=2)
    assert url.stderr.count("\n") == 1 and "cannot fix an object by URL" in url.stderr
    cluster = cli("check", "--fix", "--scheduler", "local", _copy(tmp_path), code=2)
    assert "--fix" in cluster.stderr and "--scheduler" in cluster.stderr


def test_sarif_results_carry_their_fixes_valid_against_the_oasis_schema(tmp_path: Path) -> None:
    from tests.formatters.test_formatters import assert_valid_sarif

    crlf = tmp_path / "crlf.xodr"
    crlf.write_bytes(
        (REPO / "rules" / "XL001" / "invalid_alone_and_beside_markup_crlf.xodr").read_bytes()
    )
    done = cli(
        "check", "-f", "sarif", "--select", "PT003,XL001,ST001,ST002", _copy(tmp_path), crlf,
        code=1,
    )  # fmt: skip
    log = json.loads(done.stdout)
    assert_valid_sarif(log)
    results = log["runs"][0]["results"]
    pt003 = next(r for r in results if r["ruleId"] == "PT003")
    location = pt003["locations"][0]["physicalLocation"]["artifactLocation"]  # the same file
    assert pt003["fixes"] == [
        {
            "description": {"text": "name the partner 'W32' (safe fix)"},
            "artifactChanges": [
                {
                    "artifactLocation": location,
                    "replacements": [
                        {
                            "deletedRegion": {
                                "startLine": 22,
                                "startColumn": 24,
                                "endLine": 22,
                                "endColumn": 27,
                            },
                            "insertedContent": {"text": "W32"},
                        }
                    ],
                }
            ],
        }
    ]
    # a comment alone on its line goes with the line: the region ends at the next line
    removal = next(r for r in results if r["ruleId"] == "XL001")["fixes"][0]
    (replacement,) = removal["artifactChanges"][0]["replacements"]
    region = replacement["deletedRegion"]
    assert (region["startColumn"], region["endLine"] - region["startLine"]) == (1, 1)
    assert replacement["insertedContent"]["text"] == ""


def test_fix_through_a_link_swapped_out_of_the_walk_after_listing_is_refused(
    tmp_path: Path,
) -> None:
    from xodrlint.api import default_registry
    from xodrlint.engine.fixing import APPLY, FixPolicy
    from xodrlint.engine.linter import Linter, LintOptions
    from xodrlint.inputs.collect import collect_inputs
    from xodrlint.runners.batch import lint_task, task_of

    walked = tmp_path / "maps"
    walked.mkdir()
    inside = _copy(walked, name="inside.xodr")
    link = walked / "a.xodr"
    link.symlink_to(inside)
    (item,) = [i for i in collect_inputs([str(walked)]) if i.display.endswith("a.xodr")]
    assert item.root == walked
    # between the listing and the write, the link comes to lead out of the folder
    outside = _copy(tmp_path, name="outside.xodr")
    link.unlink()
    link.symlink_to(outside)
    options = LintOptions(select=("PT003",), fixes=FixPolicy(mode=APPLY), place_fixes=True)
    report = lint_task(Linter(default_registry(), options), task_of(item))
    assert report.error is not None and "link leading out of the folder walked" in report.error
    assert outside.read_bytes() == MISMATCH.read_bytes()


def test_a_folders_fix_setting_writes_from_check_alone(tmp_path: Path) -> None:
    folder = tmp_path / "maps" / "sub"
    folder.mkdir(parents=True)
    (folder / "xodrlint.toml").write_text("fix = true\n")
    target = _copy(folder)
    # a baseline records the files as they are: refused, not fixed
    refused = cli("check", "--write-baseline", tmp_path / "b.json", tmp_path / "maps", code=2)
    assert "--fix does not go with --write-baseline" in refused.stderr
    assert target.read_bytes() == MISMATCH.read_bytes()
    # the map draws the file as it is, and writes nothing back
    cli("map", target, "-o", tmp_path / "m.html", code=1)
    assert target.read_bytes() == MISMATCH.read_bytes()
    # check makes the fix the folder asks for
    cli("check", "--select", "PT003", tmp_path / "maps", code=0)
    assert target.read_bytes() == MISMATCH_FIXED.read_bytes()


def test_diff_says_each_error_once_and_refuses_other_reports(tmp_path: Path) -> None:
    done = cli(
        "check", "--select", "PT003", "--diff", tmp_path / "gone.xodr", _copy(tmp_path), code=2
    )
    assert done.stderr.count("gone.xodr") == 1
    cli("check", "--select", "PT003", "--diff", "-f", "text", _copy(tmp_path), code=1)
    for extra in (["-o", str(tmp_path / "r.json")], ["--report", f"sarif={tmp_path / 'r'}"]):
        refused = cli("check", "--diff", *extra, _copy(tmp_path), code=2)
        assert "--diff prints a diff: it does not go with" in refused.stderr


def test_an_unknown_fixable_entry_is_a_usage_error(tmp_path: Path) -> None:
    done = cli("check", "--fixable", "SW999", _copy(tmp_path), code=2)
    assert "fixable: 'SW999' matches no rule code, name or UID" in done.stderr
    cli("check", "--select", "PT003", "--unfixable", "XL", _copy(tmp_path), code=1)
