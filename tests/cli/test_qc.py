"""XQAR output and the checker-bundle mode for the ASAM Quality Checker framework."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from lxml import etree

from tests.conftest import REPO, SHARED
from xodrlint.api import default_registry
from xodrlint.cli.check.notes import FULL_VALIDATION_NOTE
from xodrlint.formatters.xqar import BUNDLE_NAME, asam_rule_uid, checker_id

from .test_cli import BROKEN, CLEAN, cli, report

QC = SHARED / "qc"
TWO = REPO / "examples" / "two-findings.xodr"
# ASAM's rule UID schema, as qc-framework's doc/manual/rule_uid_schema.md writes it
ASAM_UID = re.compile(r"^\w+(\.\w+)+:[a-z]*:([0-9]+(\.[0-9]+)+)?:(([a-z][\w_]*)\.)*[a-z][\w_]*$")
LEVEL = {"error": "1", "warning": "2", "info": "3"}
#: What a bundle says on stderr of a map only the built-in schema validated.
NOTED = f"xodrlint: note: {FULL_VALIDATION_NOTE}\n"


def xqar(*args: str | Path, code: int = 1) -> etree._Element:
    """``check -f xqar``, checked against the published schema when it is present."""
    text = cli("check", "-f", "xqar", *args, code=code).stdout
    root = etree.fromstring(text.encode())
    if (QC / "xqar_result_format.xsd").is_file():
        schema = etree.XMLSchema(etree.parse(str(QC / "xqar_result_format.xsd")))
        assert schema.validate(root), schema.error_log
    return root


def checkers(root: etree._Element) -> dict[str, etree._Element]:
    return {c.get("checkerId", ""): c for c in root.iter("Checker")}


def test_every_finding_is_an_issue_with_level_uid_line_and_xpath() -> None:
    findings = report(BROKEN, code=1)["findings"]
    root = xqar(BROKEN)
    by_code = {rule.code: rule.meta for rule in default_registry().rules}
    expected = sorted(
        (
            checker_id(by_code[f["code"]]),
            LEVEL[f["severity"]],
            asam_rule_uid(f["uid"]),
            f["message"],
            str(f["line"]),
            f["xpath"],
            f["uid"],
        )
        for f in findings
    )
    seen = []
    for issue in root.iter("Issue"):
        row = issue.find("Locations/FileLocation")
        where = issue.find("Locations/XMLLocation")
        rule = issue.find("DomainSpecificInfo/rule")
        assert row is not None and where is not None and rule is not None
        seen.append(
            (
                issue.getparent().get("checkerId"),  # type: ignore[union-attr]
                issue.get("level"),
                issue.get("ruleUID"),
                issue.get("description"),
                row.get("row"),
                where.get("xpath"),
                rule.get("uid"),
            )
        )
    assert sorted(seen) == expected and len(expected) == 6
    ids = sorted(int(i.get("issueId", "")) for i in root.iter("Issue"))
    assert ids == list(range(6))


def test_each_rule_is_a_checker_addressing_its_uids_and_aliases() -> None:
    root = xqar(CLEAN, code=0)
    found = checkers(root)
    rules = default_registry().rules
    assert len(found) == len(rules)
    for rule in rules:
        checker = found[checker_id(rule.meta)]
        addressed = [a.get("ruleUID") for a in checker.iter("AddressedRule")]
        assert addressed == [asam_rule_uid(uid) for uid in rule.meta.uids]
        if rule.meta.opt_in:  # XL001 runs only when selected by name
            assert checker.get("status") == "skipped"
            assert checker.get("summary", "").startswith("Not selected")
            continue
        assert checker.get("status") == "completed"
        assert checker.get("summary") == "0 issue(s) are found."
    bundle = root.find("CheckerBundle")
    assert bundle is not None and bundle.get("name") == BUNDLE_NAME
    assert bundle.find("Param[@name='InputFile']").get("value") == str(CLEAN)  # type: ignore[union-attr]


def test_every_rule_uid_meets_asams_rule_uid_schema() -> None:
    for rule in default_registry().rules:
        for uid in rule.meta.uids:
            assert ASAM_UID.match(asam_rule_uid(uid)), uid
            if uid.startswith("asam.net:"):
                assert asam_rule_uid(uid) == uid  # ASAM's own are joined verbatim
    assert asam_rule_uid("xodrlint:xodr:1.4.0:a.b") == "xodrlint.github.io:xodr:1.4.0:a.b"
    assert asam_rule_uid("acme:xodr:1.4.0:a.b") == "acme.invalid:xodr:1.4.0:a.b"


def test_rules_that_did_not_run_are_skipped_with_the_reason() -> None:
    found = checkers(xqar(TWO, "--select", "PT"))
    statuses = {c.get("status") for i, c in found.items() if i.startswith("check_xodrlint_pt")}
    assert statuses == {"completed"}
    skipped = [c for i, c in found.items() if not i.startswith("check_xodrlint_pt")]
    assert skipped and all(c.get("status") == "skipped" for c in skipped)
    assert all(c.get("summary", "").startswith("Not selected") for c in skipped)
    assert not any(c.find("Issue") is not None for c in skipped)


def test_a_file_that_does_not_parse_skips_the_railroad_rules(tmp_path: Path) -> None:
    broken = tmp_path / "cut.xodr"
    broken.write_bytes(CLEAN.read_bytes()[:300])
    found = checkers(xqar(broken))
    xs001 = next(c for i, c in found.items() if i.startswith("check_xodrlint_xs001"))
    assert xs001.get("status") == "completed" and xs001.find("Issue") is not None
    railroad = [c for i, c in found.items() if not i.startswith("check_xodrlint_x")]
    assert all(c.get("status") == "skipped" for c in railroad)
    assert all("Preconditions are not satisfied" in c.get("summary", "") for c in railroad)


def test_an_unreadable_input_is_still_a_complete_result(tmp_path: Path) -> None:
    root = xqar(tmp_path / "missing.xodr", code=2)
    bundle = root.find("CheckerBundle")
    assert bundle is not None and "could not be read" in bundle.get("summary", "")
    assert {c.get("status") for c in root.iter("Checker")} == {"skipped"}


def test_the_build_date_follows_source_date_epoch() -> None:
    text = cli("check", "-f", "xqar", CLEAN, code=0, SOURCE_DATE_EPOCH="1700000000").stdout
    assert 'build_date="2023-11-14"' in text


# -- the checker-bundle mode ---------------------------------------------------------------


def _config(folder: Path, *checkers: str, result: str = "out.xqar") -> Path:
    (folder / "map.xodr").write_bytes(BROKEN.read_bytes())
    lines = [f"<Checker {c}/>" for c in checkers]
    path = folder / "config.xml"
    path.write_text(
        '<?xml version="1.0"?>\n<Config>\n  <Param name="InputFile" value="map.xodr"/>\n'
        '  <CheckerBundle application="otherBundle"><Param name="resultFile" value="x.xqar"/>'
        "</CheckerBundle>\n"
        f'  <CheckerBundle application="{BUNDLE_NAME}">\n'
        f'    <Param name="resultFile" value="{result}"/>\n    {"".join(lines)}\n'
        "  </CheckerBundle>\n</Config>\n",
        "utf-8",
    )
    return path


def test_qc_runs_the_configured_checkers_and_keeps_their_levels(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)  # the framework starts a bundle in its working folder
    config = _config(
        tmp_path,
        'checkerId="check_xodrlint_st004_segment_s_out_of_range" maxLevel="1" minLevel="3"',
        'checkerId="xs006" maxLevel="1" minLevel="1"',
        'checkerId="PT003" maxLevel="1" minLevel="1"',
    )
    cli("qc", "-c", config, code=0)
    root = etree.parse(str(tmp_path / "out.xqar")).getroot()
    ran = {i for i, c in checkers(root).items() if c.get("status") == "completed"}
    assert {i.split("_")[2] for i in ran} == {"st004", "xs006", "pt003"}
    codes = [_checker_of(issue).split("_")[2] for issue in root.iter("Issue")]
    assert sorted(codes) == ["st004", "xs006", "xs006", "xs006"]  # no PT003 warning kept
    params = [(p.get("name"), p.get("value")) for p in root.iterfind("CheckerBundle/Param")]
    assert params == [("InputFile", "map.xodr"), ("resultFile", "out.xqar")]


def test_qc_without_checkers_runs_every_rule(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    cli("qc", "-c", _config(tmp_path), code=0)
    root = etree.parse(str(tmp_path / "out.xqar")).getroot()
    statuses = {i: c.get("status") for i, c in checkers(root).items()}
    unused = checker_id(default_registry().by_code["XL001"].meta)
    assert statuses.pop(unused) == "skipped"  # off by default, as in check
    assert set(statuses.values()) == {"completed"}
    assert len(list(root.iter("Issue"))) == 6


def test_qc_takes_the_input_file_as_an_argument(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    done = cli("qc", BROKEN, code=0)
    # the result has no place for the run's notes (what was not checked): stderr has them
    assert done.stderr == f"{NOTED}xodrlint: wrote results to {BUNDLE_NAME}.xqar\n"
    assert len(list(etree.parse(f"{BUNDLE_NAME}.xqar").getroot().iter("Issue"))) == 6
    done = cli("qc", BROKEN, "-o", "elsewhere.xqar", code=0)
    assert done.stderr == f"{NOTED}xodrlint: wrote results to elsewhere.xqar\n"
    assert (tmp_path / "elsewhere.xqar").is_file()
    to_stdout = cli("qc", BROKEN, "-o", "-", code=0)
    assert to_stdout.stdout.startswith("<?xml") and "wrote" not in to_stdout.stderr
    refused = cli("qc", BROKEN, "-o", "missing/x.xqar", code=2)
    assert (
        refused.stderr == "xodrlint: --output missing/x.xqar: its folder missing does not exist\n"
    )


@pytest.mark.parametrize(
    "where",
    # any name too, as ASAM's bundles take it (the framework's pooling reads only
    # *.xqar beside it, and keeps Result.xqar for itself: docs/qc-framework.md says so)
    ["out/x.xqar", "out/deeper/../x.xqar", "{tmp}/results/x.xqar", "Result.xqar", "x.xml"],
)
def test_qc_writes_the_result_where_the_configuration_says(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, where: str
) -> None:
    # as ASAM's bundles: relative to the working folder (not the configuration's folder)
    work = tmp_path / "work"
    for folder in (work / "out" / "deeper", tmp_path / "results"):
        folder.mkdir(parents=True)
    result = where.format(tmp=tmp_path)
    config = _config(tmp_path, result=result)
    (work / "map.xodr").write_bytes(BROKEN.read_bytes())
    monkeypatch.chdir(work)
    done = cli("qc", "-c", config, code=0)
    assert done.stderr == f"{NOTED}xodrlint: wrote results to {result}\n"
    written = work / result if not Path(result).is_absolute() else Path(result)
    assert len(list(etree.parse(str(written)).getroot().iter("Issue"))) == 6
    assert not (tmp_path / "out").exists()  # not beside the configuration


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"checker": 'checkerId="nope"'}, "'nope' is no checker of xodrlintBundle"),
        ({"checker": 'checkerId="PT001" minLevel="4"'}, "minLevel='4' of 'PT001' is not 1, 2 or 3"),
        ({"result": "sub/out.xqar"}, "resultFile sub/out.xqar: its folder sub does not exist"),
        ({"result": "map.xodr/x.xqar"}, "its folder map.xodr is not a folder"),
        ({"result": "sub/"}, "resultFile sub/: names a folder, not a file"),
        ({"result": "map.xodr"}, "resultFile map.xodr: is the input file; refusing to overwrite"),
        ({"result": "./map.xodr"}, "resultFile ./map.xodr: is the input file"),
        ({"text": "<Confi"}, "cannot read the configuration"),
        ({"text": "<Other/>"}, "the root element is 'Other', not 'Config'"),
        ({"text": "<Config/>"}, "no Param named 'InputFile'"),
    ],
)
def test_a_bad_configuration_is_one_line_and_exit_2(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, change: dict[str, str], message: str
) -> None:
    checker = change.get("checker")
    monkeypatch.chdir(tmp_path)  # where the framework starts a bundle
    config = _config(
        tmp_path, *([checker] if checker else []), result=change.get("result", "o.xqar")
    )
    if "text" in change:
        config.write_text(change["text"], "utf-8")
    result = cli("qc", "-c", config, code=2)
    assert result.stderr.count("\n") == 1 and message in result.stderr, result.stderr
    assert (tmp_path / "map.xodr").read_bytes() == BROKEN.read_bytes()


def test_qc_refuses_a_configuration_and_an_input_together(tmp_path: Path) -> None:
    result = cli("qc", "-c", _config(tmp_path), BROKEN, code=2)
    assert "not both" in result.stderr


def test_the_manifest_starts_this_installation_as_the_framework_would(tmp_path: Path) -> None:
    out = tmp_path / "manifest.json"
    cli("qc", "--manifest", out, code=0)
    manifest: dict[str, Any] = json.loads(out.read_text("utf-8"))
    [module] = manifest["module"]
    assert module["name"] == BUNDLE_NAME
    assert (module["exec_type"], module["module_type"]) == ("executable", "checker_bundle")
    # run the command with the variables the framework's runtime sets
    config = _config(tmp_path)
    env = {
        **os.environ,
        "ASAM_QC_FRAMEWORK_WORKING_DIR": str(tmp_path),
        "ASAM_QC_FRAMEWORK_CONFIG_FILE": str(config),
    }
    done = subprocess.run(
        module["exec_command"], check=False, shell=True, env=env, capture_output=True
    )
    assert done.returncode == 0, done.stderr
    assert len(list(etree.parse(str(tmp_path / "out.xqar")).getroot().iter("Issue"))) == 6
    assert sys.executable in module["exec_command"]


@pytest.mark.skipif(
    not os.environ.get("XODRLINT_QC_BASELIB_PYTHON"),
    reason="set XODRLINT_QC_BASELIB_PYTHON to a Python with asam-qc-baselib (CI does)",
)
def test_asam_qc_baselib_reads_the_result(tmp_path: Path) -> None:
    # a stale suppression too: XL001's UID must pass qc-baselib's rule UID check
    stale = tmp_path / "stale.xodr"
    stale.write_text(
        CLEAN.read_text("utf-8").replace(
            "</OpenDRIVE>", "<!-- xodrlint: ignore-file[PT001] -->\n</OpenDRIVE>"
        ),
        "utf-8",
    )
    args = (BROKEN, TWO, stale, "--extend-select", "XL001")
    findings = report(*args, code=1)["findings"]
    assert "XL001" in [f["code"] for f in findings]
    result = tmp_path / "result.xqar"
    cli("check", "-f", "xqar", *args, "-o", result, code=1)
    expected = tmp_path / "expected.json"
    expected.write_text(json.dumps(findings), "utf-8")
    reader = REPO / "tests" / "interop" / "read_with_qc_baselib.py"
    python = os.environ["XODRLINT_QC_BASELIB_PYTHON"]
    done = subprocess.run(
        [python, str(reader), str(result), str(expected)],
        check=False,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert f"read {len(findings)} issues" in done.stdout


def _checker_of(issue: etree._Element) -> str:
    checker = issue.getparent()
    assert checker is not None
    return checker.get("checkerId", "")


def _blocks(language: str) -> list[str]:
    page = (REPO / "docs" / "qc-framework.md").read_text("utf-8")
    return re.findall(rf"```{language}\n(.*?)```", page, flags=re.DOTALL)


def test_the_documented_configuration_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    [config] = _blocks("xml")
    (tmp_path / "config.xml").write_text(config, "utf-8")
    (tmp_path / "broken.xodr").write_bytes(BROKEN.read_bytes())
    monkeypatch.chdir(tmp_path)
    cli("qc", "-c", "config.xml", code=0)
    root = etree.parse("xodrlint.xqar").getroot()
    assert sorted(_checker_of(i).split("_")[2] for i in root.iter("Issue")) == [
        "st004",
        "xs006",
        "xs006",
        "xs006",
    ]


def test_the_documented_manifest_is_the_one_written() -> None:
    from xodrlint.cli.qc import module_manifest

    shown = json.loads(_blocks("json")[0])
    written = module_manifest()
    interpreter = "/opt/venv/bin/python"
    shown["module"][0]["exec_command"] = shown["module"][0]["exec_command"].replace(
        interpreter, sys.executable
    )
    assert shown == written
