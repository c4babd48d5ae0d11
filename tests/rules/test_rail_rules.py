"""The railroad rule packs as a whole: options, one defect one finding, related locations."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from tests.conftest import REPO
from tests.networks import rail_road
from xodrlint.api import default_registry, lint_bytes
from xodrlint.cli import app
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.rules.options import OptionError


def _file(*roads: str, tail: str = "") -> bytes:
    body = "".join(roads)
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n<OpenDRIVE>\n'
        '  <header revMajor="1" revMinor="7" name="t"/>\n' + body + tail + "</OpenDRIVE>\n"
    ).encode()


def _road(ident: str, **options: Any) -> str:
    # road 1 runs along the x axis; the others leave it at its s=30, where _switch puts
    # the switches, 5.7 degrees apart: side tracks meet their switches (SW011, SW012)
    start = {"x": 0, "y": 0, "hdg": 0} if ident == "1" else {"x": 30, "y": 0, "hdg": 0.1}
    return rail_road(ident, length=100, **{**start, **options})


def _switch(ident: str, main: str, side: str, partner: str | None = None, s: float = 0) -> str:
    partner_xml = f'<partner id="{partner}"/>' if partner is not None else ""
    return (
        f'<switch name="W{ident}" id="{ident}" position="dynamic">'
        f'<mainTrack id="{main}" s="30" dir="+"/><sideTrack id="{side}" s="{s}" dir="+"/>'
        f"{partner_xml}</switch>"
    )


def _railroad(*switches: str) -> str:
    return "\n    <railroad>" + "".join(switches) + "</railroad>"


def _codes(data: bytes, **options: object) -> list[tuple[str, str]]:
    report = lint_bytes(data, **options)  # type: ignore[arg-type]
    assert not report.internal_errors
    return sorted((f.code, f.xpath) for f in report.findings if not f.code.startswith("XS"))


def test_rail_min_width_option_changes_rl003() -> None:
    narrow = _file(_road("1", width=1.2))
    assert [code for code, _ in _codes(narrow)] == ["RL003"]
    assert _codes(narrow, rule_options={"rail-min-width": 1.0}) == []
    assert [code for code, _ in _codes(narrow, rule_options={"rail-min-width": 1.2})] == []


def test_refline_tolerance_option_changes_rl002() -> None:
    off_centre = _file(_road("1", width=1.5, offset=0.75 + 0.2))
    assert [code for code, _ in _codes(off_centre)] == ["RL002"]
    assert _codes(off_centre, rule_options={"refline-tolerance": 0.2}) == []
    assert [c for c, _ in _codes(off_centre, rule_options={"refline-tolerance": 0.19})] == ["RL002"]


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({"rail-width": 1.0}, "unknown rule option 'rail-width'"),
        ({"rail-min-width": -1.0}, "must be a finite number >= 0"),
        ({"refline-tolerance": float("nan")}, "must be a finite number"),
        ({"refline-tolerance": float("inf")}, "must be a finite number"),
    ],
)
def test_bad_rule_options_are_refused(values: dict[str, float], message: str) -> None:
    with pytest.raises(OptionError, match=message):
        Linter(default_registry(), LintOptions(rule_options=values))


def test_cli_rule_options(tmp_path: pytest.TempPathFactory) -> None:
    path = tmp_path / "narrow.xodr"  # type: ignore[operator]
    path.write_bytes(_file(_road("1", width=1.2)))
    runner = CliRunner()
    assert runner.invoke(app, ["check", "-q", str(path)]).exit_code == 1
    assert runner.invoke(app, ["check", "-q", "--rail-min-width", "1.0", str(path)]).exit_code == 0
    refused = runner.invoke(app, ["check", "--rail-min-width", "-2", str(path)])
    assert refused.exit_code == 2
    assert "rail-min-width" in refused.output and "Traceback" not in refused.output


def test_rules_json_lists_options_and_deferrals() -> None:
    result = CliRunner().invoke(app, ["rules", "-f", "json"])
    entries = {entry["code"]: entry for entry in json.loads(result.stdout)}
    assert [o["name"] for o in entries["RL003"]["options"]] == ["rail-min-width"]
    assert entries["RL003"]["options"][0]["default"] == 1.435
    assert entries["PT002"]["defers_to"] == ["PT001", "PT005", "SW002", "PT004"]
    assert len([code for code in entries if code[:2] in ("SW", "PT", "ST", "RL")]) == 34


def test_explain_shows_options() -> None:
    result = CliRunner().invoke(app, ["explain", "RL003"])
    assert result.exit_code == 0
    assert "## Options" in result.stdout and "rail-min-width" in result.stdout


PARTNER_XPATH = "/OpenDRIVE/road[@id='1']/railroad/switch[@id='11']/partner"


def test_partner_chain_reports_the_first_rule_that_applies() -> None:
    # switch 11 names partner '99', which does not exist; it is also a single switch
    data = _file(_road("1", railroad=_railroad(_switch("11", "1", "2", partner="99"))), _road("2"))
    assert _codes(data) == [("PT001", PARTNER_XPATH)]
    # without PT001 the next rule of the chain that applies reports it
    assert _codes(data, ignore=["PT001"]) == [("SW002", PARTNER_XPATH)]
    # a rule selected alone reports everything it sees
    assert _codes(data, select=["SW002"]) == [("SW002", PARTNER_XPATH)]


def test_self_partner_is_pt005_only() -> None:
    data = _file(_road("1", railroad=_railroad(_switch("11", "1", "2", partner="11"))), _road("2"))
    assert _codes(data) == [("PT005", PARTNER_XPATH)]


def test_undefined_main_track_is_sw004_not_sw003() -> None:
    data = _file(_road("1", railroad=_railroad(_switch("11", "7", "2", s=0))), _road("2"))
    main = "/OpenDRIVE/road[@id='1']/railroad/switch[@id='11']/mainTrack"
    assert _codes(data) == [("SW004", main)]
    assert _codes(data, select=["SW003"]) == [("SW003", main)]


def test_out_of_range_side_track_is_sw005_not_sw006() -> None:
    data = _file(_road("1", railroad=_railroad(_switch("11", "1", "2", s=120))), _road("2"))
    side = "/OpenDRIVE/road[@id='1']/railroad/switch[@id='11']/sideTrack"
    assert _codes(data) == [("SW005", side)]
    assert _codes(data, select=["SW006"]) == [("SW006", side)]


def test_overused_side_track_silences_pt007_on_the_same_element() -> None:
    switches = _railroad(_switch("11", "1", "2"), _switch("12", "1", "2"), _switch("13", "1", "2"))
    data = _file(_road("1", railroad=switches), _road("2"))
    side = "/OpenDRIVE/road[@id='1']/railroad/switch[@id='{}']/sideTrack"
    assert _codes(data) == [("PT007", side.format("12")), ("SW010", side.format("13"))]


def test_duplicates_name_the_first_with_its_line() -> None:
    data = _file(
        _road("1", railroad=_railroad(_switch("11", "1", "2"))),
        _road("2", railroad=_railroad(_switch("11", "2", "1", s=0))),
    )
    report = lint_bytes(data, select=["SW007"])
    (finding,) = report.findings
    first = (
        data.decode()
        .splitlines()
        .index(next(line for line in data.decode().splitlines() if 'id="11"' in line))
    )
    assert (
        finding.message
        == f"switch id '11' is already used by switch 'W11' in road '1' at line {first + 1}"
    )
    assert [(r.line, r.xpath) for r in finding.related] == [
        (first + 1, "/OpenDRIVE/road[@id='1']/railroad/switch[@id='11']")
    ]
    assert finding.as_dict()["related"] == [
        {"line": first + 1, "xpath": "/OpenDRIVE/road[@id='1']/railroad/switch[@id='11']"}
    ]


def test_any_rule_option_by_name_on_the_command_line(tmp_path: Path) -> None:
    path = tmp_path / "narrow.xodr"
    path.write_bytes(_file(_road("1", width=1.2)))
    runner = CliRunner()
    ok = runner.invoke(app, ["check", "-q", "--rule-option", "rail-min-width=1.0", str(path)])
    assert ok.exit_code == 0
    for bad, expected in [
        ("rail-min-width", "--rule-option rail-min-width: expected NAME=VALUE"),
        ("=1", "--rule-option =1: expected NAME=VALUE"),
        (
            "rail-min-width=wide",
            "--rule-option rail-min-width=wide: expected NAME=NUMBER, "
            "'rail-min-width' takes a finite number >= 0",
        ),
        (
            "rail-min-width=-1",
            "--rule-option rail-min-width=-1: expected NAME=NUMBER, "
            "'rail-min-width' takes a finite number >= 0",
        ),
    ]:
        refused = runner.invoke(app, ["check", "--rule-option", bad, str(path)])
        assert refused.exit_code == 2 and refused.stderr == f"xodrlint: {expected}\n"
    unknown = runner.invoke(app, ["check", "--rule-option", "gauge=1", str(path)])
    assert unknown.exit_code == 2 and "unknown rule option 'gauge'" in unknown.stderr


def test_the_option_flags_state_the_rules_defaults() -> None:
    from xodrlint.rules.lanes.rl002 import TOLERANCE
    from xodrlint.rules.lanes.rl003 import MIN_WIDTH

    # click wraps help at 80 columns whatever COLUMNS says: read it unwrapped
    text = " ".join(CliRunner().invoke(app, ["check", "--help"]).stdout.split())
    assert f"default {MIN_WIDTH.default:g}" in text
    assert f"default {TOLERANCE.default:g}" in text


# -- issue 18, item 4: numbers that are no finite number ------------------------------------

RULES_DIR = Path(__file__).resolve().parents[2] / "rules"


@pytest.mark.parametrize(
    ("case", "family", "expected"),
    [
        ("SW005/invalid_s_not_a_finite_number.xodr", "SW", {18: "SW005", 19: "SW005"}),
        ("SW005/valid_road_length_not_a_finite_number.xodr", "SW", {}),
        (
            "ST004/invalid_s_not_a_finite_number.xodr",
            "ST",
            {32: "ST004", 33: "ST004", 34: "ST004"},
        ),
        (
            "RL003/invalid_width_not_a_finite_number.xodr",
            "RL",
            {14: "RL003", 22: "RL003", 30: "RL003"},
        ),
        ("RL002/invalid_offset_not_a_finite_number.xodr", "RL", {14: "RL002", 33: "RL002"}),
    ],
)
def test_a_number_that_is_no_finite_number_is_reported_once_by_the_range_rule(
    case: str, family: str, expected: dict[int, str]
) -> None:
    # INF, NaN and 1e999 are valid xs:doubles: the schema is silent, and only the range
    # rule speaks (SW006, SW011, SW012, ST005, ST006, ST011 stay silent), with the value
    # as written
    path = RULES_DIR / case
    report = Linter(default_registry(), LintOptions(select=(family,))).lint_path(path)
    assert {f.line: f.code for f in report.findings} == expected
    assert len(report.findings) == len(expected)
    written = {"INF", "NaN", "1e999", "-1e999"}
    assert all(any(w in f.message for w in written) for f in report.findings)


def test_finite_looking_text_that_is_no_double_stays_the_schemas() -> None:
    from lxml import etree

    from xodrlint.model import non_finite

    for text, expected in [("INF", "INF"), (" -INF ", "-INF"), ("+INF", "+INF"),
                           ("NaN", "NaN"), ("1e999", "1e999"), (".5E+400", ".5E+400"),
                           ("inf", None), ("Infinity", None), ("nan", None),
                           ("1e308", None), ("1_0e999", None), ("", None)]:  # fmt: skip
        element = etree.fromstring(f'<mainTrack s="{text}"/>')
        assert non_finite(element, "s") == expected, text
    assert non_finite(etree.fromstring("<mainTrack/>"), "s") is None


def test_a_lane_offset_that_is_no_finite_number_is_reported_where_it_holds() -> None:
    # one bad laneOffset entry from s=80: only the lane section it reaches says so
    sections = "".join(
        f'<laneSection s="{s}"><center><lane id="0" type="none" level="false"/></center>'
        '<right><lane id="-1" type="rail" level="false"><width sOffset="0" a="1.5" b="0" '
        'c="0" d="0"/></lane></right></laneSection>'
        for s in (0, 30, 60)
    )
    text = (
        '<OpenDRIVE><header revMajor="1" revMinor="7"/><road id="1" length="100" '
        'junction="-1"><planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/>'
        '</geometry></planView><lanes><laneOffset s="0" a="0.75" b="0" c="0" d="0"/>'
        f'<laneOffset s="80" a="INF" b="0" c="0" d="0"/>{sections}</lanes></road></OpenDRIVE>'
    )
    report = lint_bytes(text.encode(), "offset.xodr", select=("RL",))
    assert [(f.code, f.message) for f in report.findings] == [
        (
            "RL002",
            "the centre of rail lane '-1' of road '1' (lane section at s=60) lies nowhere: "
            "laneOffset has a=INF",
        )
    ]


@pytest.mark.parametrize("value", ["-INF", "-1e999", "-INF "])
def test_a_value_the_schema_refuses_is_reported_once_by_the_schema(value: str) -> None:
    # -INF where s must not be negative (blanks after it or not): XS006 says it, the
    # range rule stays silent
    from tests.conftest import SHARED_SCHEMAS

    if not SHARED_SCHEMAS.is_dir():
        pytest.skip("../shared is absent")
    case = (RULES_DIR / "SW005" / "invalid_s_not_a_finite_number.xodr").read_text()
    text = case.replace('s="INF"', f's="{value}"')
    linter = Linter(
        default_registry(), LintOptions(select=("SW005", "XS006"), schema=SHARED_SCHEMAS)
    )
    report = linter.lint_bytes(text.encode(), "refused.xodr")
    on_main_track = [f.code for f in report.findings if f.xpath.endswith("/mainTrack")]
    assert on_main_track == ["XS006"]


def test_blanks_after_inf_are_collapsed_as_xsd_says() -> None:
    # XSD collapses the blanks around an xs:double (libxml2 alone refuses them after INF
    # and NaN): 'INF ' is INF, which the schema takes and the range rule reports
    from tests.conftest import SHARED_SCHEMAS

    if not SHARED_SCHEMAS.is_dir():
        pytest.skip("../shared is absent")
    case = (RULES_DIR / "SW005" / "invalid_s_not_a_finite_number.xodr").read_text()
    linter = Linter(
        default_registry(), LintOptions(select=("SW005", "XS006"), schema=SHARED_SCHEMAS)
    )
    found = {}
    for value in ("INF", "INF ", " INF\t"):
        report = linter.lint_bytes(case.replace('s="INF"', f's="{value}"').encode(), "inf.xodr")
        found[value] = [f.code for f in report.findings if f.xpath.endswith("/mainTrack")]
    assert found == {"INF": ["SW005"], "INF ": ["SW005"], " INF\t": ["SW005"]}


def test_the_partner_pairs_of_a_file_are_found_once(monkeypatch: pytest.MonkeyPatch) -> None:
    # PT004 and PT006 both read every pair: found once per file (36 ms a search on a
    # 20 MB railway), each rule's findings as before
    from xodrlint.rules.partners import _pairs

    searches: list[int] = []
    real = _pairs._found_pairs

    def counted(network: Any) -> Any:
        searches.append(1)
        return real(network)

    monkeypatch.setattr(_pairs, "_found_pairs", counted)
    data = (REPO / "rules" / "PT004" / "invalid_different_side_tracks.xodr").read_bytes()
    both = lint_bytes(data, select=["PT004", "PT006"])
    assert len(searches) == 1
    assert {f.code for f in both.findings} == {"PT004"}
