"""``xodrlint map``: exit codes, a self-contained page, where things and findings are drawn,
broken input, and the Berlin map's render time and size."""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree

from tests.cli.test_cli import BROKEN, BROKEN_FINDINGS, CLEAN, cli
from tests.conftest import REPO, SHARED
from xodrlint.api import lint_bytes
from xodrlint.cli.map import render_map
from xodrlint.document.load import load_bytes
from xodrlint.findings import Finding, Severity
from xodrlint.mapview.locate import Locator
from xodrlint.mapview.place import Placer
from xodrlint.mapview.svg import path_data
from xodrlint.model import build_network

BERLIN = SHARED / "corpus" / "large" / "SUMO-gen_DRT_Berlin-Adlershof.xodr"
MINIMAL = """<?xml version="1.0"?>
<OpenDRIVE><header revMajor="1" revMinor="7"/>{roads}</OpenDRIVE>"""
ONE_TRACK = """<road id="9" length="50" junction="-1">
  <planView>{geometry}</planView>
  <lanes><laneSection s="0"><center><lane id="0" type="none"/></center>
    <right><lane id="-1" type="rail"><width sOffset="0" a="3" b="0" c="0" d="0"/></lane></right>
  </laneSection></lanes>
</road>"""


def _page_data(html: str) -> dict[str, object]:
    found = re.search(r'<script type="application/json" id="map-data">(.*?)</script>', html, re.S)
    assert found is not None
    data: dict[str, object] = json.loads(found[1])
    return data


def _svg(html: str) -> etree._Element:
    """The inline SVG of a page, parsed as XML (it must be well-formed on its own)."""
    start, end = html.index("<svg xmlns"), html.index("</svg>", html.index('id="findings"'))
    return etree.fromstring(html[start : end + len("</svg>")])


def _count(svg: etree._Element, css: str) -> int:
    return sum(1 for el in svg.iter() if css in (el.get("class") or "").split())


def test_map_of_the_broken_example_has_every_thing_and_finding(tmp_path: Path) -> None:
    out = tmp_path / "map.html"
    result = cli("map", BROKEN, "-o", out, code=1)
    assert result.stdout.count(f"{BROKEN}:") == len(BROKEN_FINDINGS)  # the findings, printed
    html = out.read_text("utf-8")
    svg = _svg(html)
    assert (_count(svg, "switch-mark"), _count(svg, "platform"), _count(svg, "finding")) == (
        2,
        1,
        6,
    )
    assert _count(svg, "track") == 2 and _count(svg, "partner") == 1
    data = _page_data(html)
    findings = data["findings"]
    assert isinstance(findings, list)
    assert [(f["line"], f["code"], f["xpath"]) for f in findings] == BROKEN_FINDINGS
    # a count of one takes the singular: "1 platform segment", "1 finding"
    assert result.stderr.endswith(
        ": 2 roads, 2 switches, 1 platform segment, 6 of 6 findings placed, 0 items not drawn\n"
    )
    one = tmp_path / "one.xodr"
    one.write_text(BROKEN.read_text("utf-8").replace('sEnd="240"', 'sEnd="200"'), "utf-8")
    assert cli("map", one, "-o", out, "--select", "ST004,SW00", code=1).stderr.endswith(
        ": 2 roads, 2 switches, 1 platform segment, 1 of 1 finding placed, 0 items not drawn\n"
    )


def test_the_map_parses_and_models_its_file_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from xodrlint import model
    from xodrlint.cli import map as command
    from xodrlint.engine import linter as engine

    calls: list[str] = []

    def counted(name: str, real: Any) -> Any:
        def call(*args: Any) -> Any:
            calls.append(name)
            return real(*args)

        return call

    for module in (engine, command):
        monkeypatch.setattr(module, "load_bytes", counted("parse", load_bytes))
        monkeypatch.setattr(module, "build_network", counted("model", model.build_network))
    cli("map", BROKEN, "-o", tmp_path / "m.html", code=1)
    assert sorted(calls) == ["model", "parse"]


def test_the_page_is_self_contained(tmp_path: Path) -> None:
    out = tmp_path / "map.html"
    cli("map", BROKEN, "-o", out, code=1)
    html = out.read_text("utf-8")
    assert "default-src 'none'" in html  # the browser may fetch nothing at all
    assert not re.search(r"<(script|img|link|iframe)[^>]*\b(src|href)=", html)
    urls = set(re.findall(r"https?://[^\s\"'<>)]+", html))
    assert urls <= {"http://www.w3.org/2000/svg"}, urls
    assert "<script>" in html and "function select(" in html and ".finding.error" in html


def test_static_svg_is_well_formed_with_style_and_no_script(tmp_path: Path) -> None:
    out = tmp_path / "map.svg"
    cli("map", BROKEN, "-o", out, code=1)
    svg = etree.parse(str(out)).getroot()
    assert svg.tag == "{http://www.w3.org/2000/svg}svg"
    assert _count(svg, "finding") == 6 and _count(svg, "switch-mark") == 2
    assert svg.find("{http://www.w3.org/2000/svg}style") is not None
    assert svg.find(".//{http://www.w3.org/2000/svg}script") is None


def test_clean_map_exits_0(tmp_path: Path) -> None:
    out = tmp_path / "clean.html"
    cli("map", CLEAN, "-o", out, code=0)
    assert _count(_svg(out.read_text("utf-8")), "finding") == 0


@pytest.mark.parametrize(
    ("text", "code"),
    [("<OpenDRIVE><header", "XS001"), ("<notOpenDRIVE/>", "XS002")],
)
def test_a_file_that_is_no_opendrive_document_gets_findings_and_no_picture(
    tmp_path: Path, text: str, code: str
) -> None:
    source, out = tmp_path / "bad.xodr", tmp_path / "bad.html"
    source.write_text(text, "utf-8")
    result = cli("map", source, "-o", out, code=1)
    assert f" {code} [error] " in result.stdout
    assert "no map written" in result.stderr
    assert not out.exists()


def test_quiet_prints_the_findings_alone_and_exit_zero_exits_0(tmp_path: Path) -> None:
    loud = cli("map", BROKEN, "-o", tmp_path / "loud.html", code=1)
    quiet = cli("map", BROKEN, "-o", tmp_path / "quiet.html", "-q", "--exit-zero", code=0)
    assert quiet.stdout.splitlines() == [
        line for line in loud.stdout.splitlines() if " [error] " in line or " [warning] " in line
    ]
    assert len(quiet.stdout.splitlines()) == 6
    assert "wrote" in loud.stderr and "wrote" not in quiet.stderr
    assert (tmp_path / "quiet.html").read_bytes() == (tmp_path / "loud.html").read_bytes()
    source = tmp_path / "bad.xodr"
    source.write_text("<notOpenDRIVE/>", "utf-8")
    cli("map", source, "-o", tmp_path / "bad.html", "--exit-zero", code=0)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["missing.xodr", "-o", "{tmp}/m.html"], "missing.xodr: no such file or directory"),
        ([str(BROKEN), "-o", "{tmp}/m.png"], "name a .html or .svg file"),
        ([str(BROKEN), "-o", "{tmp}/no/such/m.html"], "does not exist"),
        ([str(BROKEN), "-o", "{tmp}/m.svg", "--select", "NOPE"], "'NOPE' matches no rule"),
        ([str(REPO / "examples"), "-o", "{tmp}/m.html"], "is a folder"),
    ],
)
def test_usage_errors_exit_2_with_one_line(tmp_path: Path, args: list[str], message: str) -> None:
    result = cli("map", *[arg.replace("{tmp}", str(tmp_path)) for arg in args], code=2)
    assert result.stderr.count("\n") == 1 and message in result.stderr, result.stderr
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("link", ["symlink", "hardlink"])
def test_the_input_under_another_name_is_not_overwritten(tmp_path: Path, link: str) -> None:
    source, out = tmp_path / "map.xodr", tmp_path / "map.html"
    source.write_bytes(BROKEN.read_bytes())
    if link == "symlink":
        out.symlink_to(source)
    else:
        os.link(source, out)
    result = cli("map", source, "-o", out, code=2)
    assert result.stderr == f"xodrlint: --output {out}: is the input; refusing to overwrite it\n"
    assert source.read_bytes() == BROKEN.read_bytes()


def test_lint_options_are_check_s_options(tmp_path: Path) -> None:
    out = tmp_path / "map.html"
    cli("map", BROKEN, "-o", out, "--select", "SW", code=1)
    findings = _page_data(out.read_text("utf-8"))["findings"]
    assert isinstance(findings, list) and [f["code"] for f in findings] == ["SW006"]
    config = tmp_path / "xodrlint.toml"
    config.write_text('ignore = ["XS006", "SW", "RL", "ST"]\n', "utf-8")
    cli("map", BROKEN, "-o", out, "--config", config, code=0)


def _render(text: str) -> str:
    return render_map(load_bytes(text.encode(), "t.xodr"), (), "html", 0.05).text


def test_broken_geometry_is_drawn_as_far_as_possible_and_listed() -> None:
    roads = (
        ONE_TRACK.format(
            geometry='<geometry s="0" x="0" y="0" hdg="0" length="20"><line/></geometry>'
            '<geometry s="20" x="20" y="0" hdg="0" length="30"><clothoid/></geometry>'
        )
        + '<road id="10" length="5"/>'
    )
    html = _render(MINIMAL.format(roads=roads))
    data = _page_data(html)
    assert [(item["what"], item["reason"]) for item in data["notDrawn"]] == [  # type: ignore[attr-defined]
        ("road '9'", "geometry has no line, arc, spiral, poly3 or paramPoly3"),
        ("road '10'", "road has no planView geometry"),
    ]
    # the rail lane is 3 m wide right of the reference line: its centre 1.5 m right (y -1.5)
    [track] = [el for el in _svg(html).iter() if "track" in (el.get("class") or "")]
    assert track.get("d") == "M0 150l2000 0"


def _finding(xpath: str) -> Finding:
    return Finding("t.xodr", 1, None, "XX001", "uid", Severity.ERROR, "m", xpath)


def _placed(xpath: str, path: Path = BROKEN) -> tuple[float, float] | None:
    doc = load_bytes(path.read_bytes(), "b")
    assert doc.tree is not None
    network = build_network(doc.root)
    point = Locator(doc, network, Placer(network)).place(_finding(xpath))
    return (round(point[0], 6), round(point[1], 6)) if point is not None else None


class _NoXPathTree:
    """A tree that refuses XPath evaluation: readable XPaths must be walked, not searched."""

    def __init__(self, tree: etree._ElementTree) -> None:
        self._tree = tree

    def getroot(self) -> etree._Element:
        return self._tree.getroot()

    def xpath(self, _: str) -> object:
        raise AssertionError("evaluated an XPath")


def test_findings_are_located_by_walking_their_readable_xpath() -> None:
    doc = load_bytes(BROKEN.read_bytes(), "b")
    assert doc.tree is not None
    network = build_network(doc.root)
    elements = list(doc.tree.getroot().iter(etree.Element))
    doc.tree = _NoXPathTree(doc.tree)  # type: ignore[assignment]
    locator = Locator(doc, network, Placer(network))
    assert [locator.element(doc.xpath_of(e)) for e in elements] == elements


@pytest.mark.parametrize(
    ("xpath", "expected"),
    [
        # a switch at its main track's point: road 1 at s=40, on the rail lane's centre
        ("/OpenDRIVE/road[@id='1']/railroad/switch[@id='101']", (40.0, 0.0)),
        # a side track where it leaves: road 2 at s=60, on its straight (from s=53.433445934
        # at (93.233295813, 4) heading 0)
        ("/OpenDRIVE/road[@id='1']/railroad/switch[@id='102']/sideTrack", (99.79985, 4.0)),
        # a lane at its start; a width entry by its lane, the nearest ancestor with a place
        ("/OpenDRIVE/road[@id='2']/lanes/laneSection/right/lane[@id='-1']", (40.0, 0.0)),
        ("/OpenDRIVE/road[@id='2']/lanes/laneSection/right/lane[@id='-1']/width", (40.0, 0.0)),
        # a lane section at its start, on the lane offset (0.5 m left)
        ("/OpenDRIVE/road[@id='2']/lanes/laneSection", (40.0, 0.5)),
        # a segment at its middle (s 60 to 240, 'up' is no side: on the track)
        ("/OpenDRIVE/station[@id='500']/platform[@id='501']/segment", (150.0, 0.0)),
        ("/OpenDRIVE/station[@id='500']", (150.0, 0.0)),
        # a road-level element at the road's middle
        ("/OpenDRIVE/road[@id='1']", (100.0, 0.0)),
        ("/OpenDRIVE/road[@id='1']/planView", (100.0, 0.0)),
        ("/OpenDRIVE/road[@id='2']/planView/geometry", (40.0, 0.0)),
        # nothing on the map to put these at
        ("/OpenDRIVE/header", None),
        ("/", None),
        ("/OpenDRIVE/road[@id='404']", None),
    ],
)
def test_findings_are_placed_by_their_element(
    xpath: str, expected: tuple[float, float] | None
) -> None:
    assert _placed(xpath) == expected


@pytest.mark.parametrize(
    ("case", "xpath", "expected"),
    [
        # the side track's point the SW011 message names: road 2 starts 0.15 m beside (30, 0)
        (
            "SW011/invalid_side_track_apart.xodr",
            "/OpenDRIVE/road[@id='1']/railroad/switch[@id='101']/sideTrack",
            (30.0, 0.15),
        ),
        # the rail lane's centre, not the reference line (0.75 m right of it)
        (
            "SW011/invalid_reference_line_at_switch_but_lane_beside.xodr",
            "/OpenDRIVE/road[@id='1']/railroad/switch[@id='101']/sideTrack",
            (30.0, -0.75),
        ),
        # a link at the end of its road it joins: road 1's end, where TR001's gap begins
        (
            "TR001/invalid_gap_between_tracks.xodr",
            "/OpenDRIVE/road[@id='1']/link/successor",
            (100.0, 0.0),
        ),
        (
            "TR001/invalid_only_the_later_road_links.xodr",
            "/OpenDRIVE/road[@id='2']/link/predecessor",
            (100.0, 1.0),
        ),
        # TR006: a lane's successor where its lane section ends (s=50 of road 1, inside
        # the road; the lane's centre is on the reference line)
        (
            "TR006/invalid_next_section_lane_missing.xodr",
            "/OpenDRIVE/road[@id='1']/lanes/laneSection[1]/right/lane[@id='-1']/link/successor[@id='-3']",
            (50.0, 0.0),
        ),
        # TR006: a junction's laneLink where it enters its connecting road (road 2's start)
        (
            "TR006/invalid_junction_lane_link_from_missing.xodr",
            "/OpenDRIVE/junction[@id='5']/connection[@id='0']/laneLink",
            (100.0, 0.0),
        ),
        # TR003 to TR005: a link at the end of its road
        (
            "TR005/invalid_no_contact_point.xodr",
            "/OpenDRIVE/road[@id='1']/link/successor",
            (100.0, 0.0),
        ),
    ],
)
def test_geometry_findings_are_placed_at_the_points_their_messages_name(
    case: str, xpath: str, expected: tuple[float, float]
) -> None:
    assert _placed(xpath, REPO / "rules" / case) == expected


@pytest.mark.parametrize(
    ("case", "code", "expected"),
    [
        # a gap between records at the later record's start
        ("TR008/invalid_gap_between_records.xodr", "TR008", [(100.0, 0.15)]),
        # a length that is not the plan view's at the plan view's end, not the middle (50, 0)
        ("TR009/invalid_length_longer_than_plan_view.xodr", "TR009", [(100.0, 0.0)]),
        # profile entries at their road's track point at their s (the rail lane's centre,
        # 0.75 m right of the reference line); one whose s is no number by its road (the
        # middle of its reference line)
        (
            "TR014/invalid_profile_entries.xodr",
            "TR014",
            [(40.0, -0.75), (50.0, 0.0), (50.0, -0.75)],
        ),
        # an unreadable record at its start; one whose start is no number on a track with no
        # other record has no place on the map (the page counts it as not placed)
        (
            "families/track-geometry/invalid_unreadable_plan_views.xodr",
            "TR014",
            [(65.3, 32.9), None],
        ),
    ],
)
def test_a_track_s_plan_view_findings_are_placed_where_the_defect_is(
    case: str, code: str, expected: list[tuple[float, float] | None]
) -> None:
    path = REPO / "rules" / case
    report = lint_bytes(path.read_bytes(), path.name, select=[code])
    doc = load_bytes(path.read_bytes(), path.name)
    network = build_network(doc.root)
    locator = Locator(doc, network, Placer(network))
    placed = [locator.place(finding) for finding in report.findings]
    assert [
        (round(point[0], 6), round(point[1], 6)) if point is not None else None for point in placed
    ] == expected


@pytest.mark.parametrize(
    ("case", "xpath", "expected"),
    [
        # an elevation entry at its road's track point at its s: road 1 at s=80, on the
        # rail lane's centre (centred on the reference line by the lane offset)
        (
            "TR010/invalid_full_cubic_reaches_the_next_entry.xodr",
            "/OpenDRIVE/road[@id='1']/elevationProfile/elevation[3]",
            (80.0, 0.0),
        ),
        # the rail lane's centre, 0.75 m right of the reference line (no lane offset)
        (
            "TR011/invalid_rail_and_tram_lanes_take_the_rail_limit.xodr",
            "/OpenDRIVE/road[@id='1']/elevationProfile/elevation",
            (0.0, -0.75),
        ),
        (
            "TR012/invalid_each_entry_once.xodr",
            "/OpenDRIVE/road[@id='1']/lateralProfile/superelevation[3]",
            (45.0, 0.0),
        ),
        # a plan-view record at its start
        (
            "TR013/invalid_spiral_tightens_below_the_limit.xodr",
            "/OpenDRIVE/road[@id='1']/planView/geometry[2]",
            (20.0, 0.0),
        ),
    ],
)
def test_profile_entries_are_placed_at_their_track_point(
    case: str, xpath: str, expected: tuple[float, float]
) -> None:
    assert _placed(xpath, REPO / "rules" / case) == expected


def test_the_vertical_and_curve_findings_are_on_the_map(tmp_path: Path) -> None:
    # one track with each of TR010 to TR013: every finding placed where its element is
    track = ONE_TRACK.format(
        geometry='<geometry s="0" x="0" y="0" hdg="0" length="50"><arc curvature="0.05"/></geometry>'
    ).replace(
        "<lanes>",
        '<elevationProfile><elevation s="0" a="0" b="0.1" c="0" d="0"/>'
        '<elevation s="20" a="9" b="0" c="0" d="0"/></elevationProfile>'
        '<lateralProfile><superelevation s="30" a="0.2" b="0" c="0" d="0"/></lateralProfile>'
        "<lanes>",
    )
    path = tmp_path / "vertical.xodr"
    path.write_text(MINIMAL.format(roads=track), "utf-8")
    out = tmp_path / "map.html"
    result = cli("map", path, "-o", out, "--select", "TR010,TR011,TR012,TR013", code=1)
    assert result.stderr.endswith("4 of 4 findings placed, 0 items not drawn\n")
    findings = _page_data(out.read_text("utf-8"))["findings"]
    assert isinstance(findings, list)
    placed = {f["code"]: f["at"] for f in findings}
    assert sorted(placed) == ["TR010", "TR011", "TR012", "TR013"]
    assert all(at is not None for at in placed.values())
    # the entries at s=0, 20 and 30 along an arc of radius 20 m, 1.5 m right of it
    doc = load_bytes(path.read_bytes(), "v")
    network = build_network(doc.root)
    locator = Locator(doc, network, Placer(network))
    road = "/OpenDRIVE/road[@id='9']"
    for xpath, s in (
        (f"{road}/elevationProfile/elevation[2]", 20.0),
        (f"{road}/lateralProfile/superelevation", 30.0),
    ):
        point = locator.place(_finding(xpath))
        radius = 20.0 + 1.5
        angle = s / 20.0
        assert point is not None
        assert point[0] == pytest.approx(radius * math.sin(angle))
        assert point[1] == pytest.approx(20.0 - radius * math.cos(angle))


def test_platform_bars_lie_on_their_side_of_the_track() -> None:
    text = BROKEN.read_text("utf-8").replace('side="up"', 'side="left"')
    html = _render(text)
    [bar] = [el for el in _svg(html).iter() if el.get("class") == "platform"]
    # left of road 1's track (y 0) by 3 m: y = -300 in SVG units (north is up); s 60 to 200
    assert bar.get("d") == "M6000 -300l14000 0"


def test_path_data_is_relative_and_in_centimetres() -> None:
    assert (
        path_data([[(0.0, 0.0), (1.234, 0.5), (1.2341, 0.5), (2.0, -1.0)]]) == "M0 0l123-50 77 150"
    )
    assert path_data([[(1.0, 1.0), (1.001, 1.0)]]) == ""  # nothing left at 1 cm


def test_check_does_not_import_the_map_modules() -> None:
    # the track-geometry rules read plan views (xodrlint.geometry.tracks); drawing them
    # (sampling, the map's modules) is the map's alone
    code = (
        "import sys\n"
        "from typer.testing import CliRunner\n"
        "from xodrlint.cli import app\n"
        f"CliRunner().invoke(app, ['check', {str(BROKEN)!r}])\n"
        "print(sorted(m for m in sys.modules if m.startswith(('xodrlint.mapview', 'xodrlint.geometry.sampling'))))\n"
        "print('xodrlint.engine.linter' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.splitlines() == ["[]", "True"]


@pytest.mark.skipif(
    not BERLIN.is_file(), reason="../shared/corpus/large (the Berlin map) is absent"
)
def test_the_berlin_map_renders_in_seconds_into_a_page_of_reasonable_size(tmp_path: Path) -> None:
    out = tmp_path / "berlin.html"
    started = time.perf_counter()
    # a SUMO export of OpenDRIVE 1.4: --all-versions applies RL002 (a convention of 1.7),
    # so that every track carries a finding to place
    cli("map", BERLIN, "-o", out, "--all-versions", code=1)
    seconds = time.perf_counter() - started
    size = out.stat().st_size
    print(f"Berlin: {seconds:.1f} s, {size / 1e6:.2f} MB")
    html = out.read_text("utf-8")
    svg = _svg(html)
    assert _count(svg, "road") == 2  # all 5,435 ordinary roads share two path elements
    # 109 tracks; findings: RL002 on each of them, TR001 on the two links of the junction
    # road 13515, whose tram lane runs against both tracks it joins (the gap silences
    # TR002 there), TR007 on road 15024, whose tram lane continues as a restricted lane,
    # TR009 on road 13479, 0.1 m long by its @length and 0.087 m by its plan view, and
    # TR013 on 111 of the short paramPoly3 records that fit the tram lines, bending below
    # 13 m
    assert _count(svg, "track") == 109 and _count(svg, "finding") == 113 + 111
    assert size < 2_000_000
    assert seconds < 30  # about 5 s on a 2-core machine; the margin is for a busy CI


def test_the_screenshots_are_in_the_readme_and_the_map_page() -> None:
    readme = (REPO / "README.md").read_text("utf-8")
    page = (REPO / "docs" / "map.md").read_text("utf-8")
    names = ("map-asam-switch.png", "map-asam-station.png", "map-broken.png")
    for name in names:
        image = REPO / "docs" / "images" / name
        assert image.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
        assert f"](docs/images/{name})" in readme and f"](images/{name})" in page


CURVES = {
    "line": (),
    "arc": ("curvature",),
    "spiral": ("curvStart", "curvEnd"),
    "poly3": ("a", "b", "c", "d"),
    "paramPoly3": ("aU", "bU", "cU", "dU", "aV", "bV", "cV", "dV"),
}
_ODD_NUMBERS = st.sampled_from(
    ["0", "1", "-1", "10", "1e-300", "1e300", "1.7e308", "-1e308", "nan", "INF", "", "x", "1e9"]
)


def test_a_poly3_whose_slope_overflows_to_nan_still_gives_a_map() -> None:
    # 2c and 3d overflow to +inf and -inf: their sum, the slope, is nan
    geometry = (
        '<geometry s="0" x="0" y="0" hdg="0" length="10">'
        '<poly3 a="0" b="0" c="1.7e308" d="-1.7e308"/></geometry>'
    )
    html = _render(MINIMAL.format(roads=ONE_TRACK.format(geometry=geometry)))
    assert "nan" not in (_svg(html).get("viewBox") or "").lower()


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.lists(
        st.tuples(
            st.sampled_from(sorted(CURVES)), st.lists(_ODD_NUMBERS, min_size=13, max_size=13)
        ),
        min_size=1,
        max_size=3,
    )
)
def test_any_geometry_values_give_a_map_and_never_an_error(
    records: list[tuple[str, list[str]]],
) -> None:
    geometries = []
    for tag, values in records:
        s, x, y, hdg, length, *rest = values
        coefficients = " ".join(
            f'{name}="{value}"' for name, value in zip(CURVES[tag], rest, strict=False)
        )
        geometries.append(
            f'<geometry s="{s}" x="{x}" y="{y}" hdg="{hdg}" length="{length}">'
            f"<{tag} {coefficients}/></geometry>"
        )
    track = ONE_TRACK.format(geometry="".join(geometries))
    html = _render(MINIMAL.format(roads=track))
    assert _svg(html).get("viewBox")
    assert "nan" not in (_svg(html).get("viewBox") or "").lower()


@pytest.mark.parametrize(
    "geometry",
    [
        '<geometry s="0" x="1.7e308" y="0" hdg="0" length="10"><line/></geometry>',
        '<geometry s="0" x="0" y="0" hdg="0" length="1e7"><arc curvature="1"/></geometry>',
        '<geometry s="0" x="0" y="0" hdg="0" length="10"><spiral curvStart="0" curvEnd="1e300"/></geometry>',
        '<geometry s="0" x="0" y="0" hdg="0" length="10"><poly3 a="0" b="0" c="0" d="1e300"/></geometry>',
        '<geometry s="0" x="0" y="0" hdg="0" length="10"><paramPoly3 aU="0" bU="1e308" cU="1e308" dU="0" aV="0" bV="0" cV="0" dV="0"/></geometry>',
    ],
    ids=[
        "overflowing-x",
        "10000-km-circle",
        "huge-curvature",
        "huge-poly3",
        "overflowing-param-poly3",
    ],
)
def test_absurd_geometry_is_drawn_quickly_as_far_as_it_can_be(geometry: str) -> None:
    started = time.perf_counter()
    html = _render(MINIMAL.format(roads=ONE_TRACK.format(geometry=geometry)))
    assert time.perf_counter() - started < 10
    view_box = [float(value) for value in (_svg(html).get("viewBox") or "").split()]
    assert len(view_box) == 4 and all(math.isfinite(value) for value in view_box)


def test_markup_in_names_cannot_end_or_swallow_the_pages_scripts(tmp_path: Path) -> None:
    # "<!--<script>" in the data block made the HTML parser swallow the page's own script
    hostile = tmp_path / "<!--<script>x & -->.xodr"  # no "/": a file name
    hostile.write_bytes(BROKEN.read_bytes())
    out = tmp_path / "map.html"
    cli("map", hostile, "-o", out, code=1)
    html = out.read_text("utf-8")
    block = re.search(r'<script type="application/json" id="map-data">(.*?)</script>', html, re.S)
    assert block is not None and "<" not in block[1] and ">" not in block[1]
    assert len(re.findall(r"<script\b", html)) == 2  # the data and the page's own script
    assert _page_data(html)["title"] == str(hostile)
