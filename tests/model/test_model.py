"""Stage 3: the indexes rules share, built in one pass, lenient with bad attributes."""

from __future__ import annotations

import math

import pytest
from lxml import etree

from tests.conftest import REPO
from xodrlint.document.load import load_bytes
from xodrlint.model import build_network, number, numbers


def test_indexes_of_the_clean_example() -> None:
    doc = load_bytes((REPO / "examples" / "clean.xodr").read_bytes(), "clean.xodr")
    net = build_network(doc.root)
    assert [road.id for road in net.roads] == ["1", "2"]
    assert net.road_by_id["2"].length == 120.0
    assert net.road_by_id["1"].has_rail_lane
    section = net.road_by_id["1"].lane_sections[0]
    assert [lane.id for lane in section.rail_lanes] == [-1]
    assert section.rail_lanes[0].widths[0].at(10.0) == 1.5
    assert [sw.id for sw in net.switches] == ["101", "102"]
    first = net.switch_by_id["101"]
    assert first.road.id == "1" and first.partner is not None and first.partner.id == "102"
    assert first.main_track is not None and first.main_track.s == 40.0
    assert [sw.id for sw in net.switches_by_side_track["2"]] == ["101", "102"]
    assert [sw.id for sw in net.switches_by_main_track["1"]] == ["101", "102"]
    assert [p.id for p in net.platforms] == ["501"]
    assert [(s.road_id, s.s_start, s.s_end, s.side) for s in net.segments] == [
        ("1", 60.0, 140.0, "left")
    ]


@pytest.mark.parametrize(
    ("raw", "expected"),
    [
        ("1.5", 1.5),
        (" 2e3 ", 2000.0),
        ("-0", -0.0),
        (".5", 0.5),
        ("NaN", None),
        ("INF", None),
        ("1e999", None),
        ("", None),
        ("0x10", None),
        ("1,5", None),
        ("1_0", None),
        ("abc", None),
        ("\u0661\u0662", None),  # Arabic-Indic digits: float() reads them, xs:double not
    ],
)
def test_numbers_are_read_as_finite_xsd_doubles_or_none(raw: str, expected: float | None) -> None:
    element = etree.Element("x", v=raw)
    value = number(element, "v")
    assert value == expected
    if value is not None:
        assert math.isfinite(value)
    # read with others in one pass, each value is judged on its own: the others neither
    # rescue nor spoil it (a record's five attributes are read this way)
    element.set("w", "2.5")
    assert numbers(element, ("w", "v", "missing", "w")) == [2.5, expected, None, 2.5]


def test_malformed_attributes_become_none_not_errors() -> None:
    data = b"""<OpenDRIVE><header revMajor="1" revMinor="7"/>
    <road id="1" length="long"><lanes><laneOffset s="0" a="x" b="0" c="0" d="0"/>
    <laneSection s="NaN"><right><lane id="minus one" type="rail"><width sOffset="0" a="1"/></lane></right></laneSection></lanes>
    <railroad><switch><mainTrack s="inf"/></switch></railroad></road>
    <station><platform><segment sStart="" sEnd="1e999"/></platform></station></OpenDRIVE>"""
    net = build_network(load_bytes(data, "bad.xodr").root)
    road = net.roads[0]
    assert road.length is None and road.lane_offsets == ()
    lane = road.lane_sections[0].lanes[0]
    assert road.lane_sections[0].s is None and lane.id is None and lane.widths == ()
    switch = net.switches[0]
    assert switch.id is None and switch.side_track is None and switch.main_track is not None
    assert switch.main_track.s is None and switch.main_track.road_id is None
    segment = next(iter(net.segments))
    assert segment.s_start is None and segment.s_end is None
    assert net.switches_by_side_track == {}


def test_non_opendrive_roots_give_an_empty_network() -> None:
    assert (
        build_network(etree.fromstring(b"<OpenSCENARIO><road id='1'/></OpenSCENARIO>")).roads == ()
    )
    assert build_network(None).switches == ()


def _same_layout_roads(count: int, offset: float) -> bytes:
    road = (
        '<road id="{n}" length="{length}" junction="-1"><planView><geometry s="0" x="{n}" '
        'y="0" hdg="0" length="{length}"><line/></geometry></planView><lanes>'
        f'<laneOffset s="0" a="{offset}" b="0" c="0" d="0"/><laneSection s="0">'
        '<center><lane id="0" type="none" level="false"/></center><right>'
        '<lane id="-1" type="rail" level="false"><width sOffset="0" a="1.5" b="0" c="0" '
        'd="0"/></lane></right></laneSection></lanes></road>'
    )
    roads = "".join(road.format(n=n, length=100 + n % 2) for n in range(count))
    return f'<OpenDRIVE><header revMajor="1" revMinor="7"/>{roads}</OpenDRIVE>'.encode()


def test_roads_of_one_lane_layout_share_a_template() -> None:
    network = build_network(load_bytes(_same_layout_roads(40, 0.75), "t.xodr").root)
    first = network.roads[0]
    assert all(road.lane_template is first for road in network.roads)
    other = build_network(load_bytes(_same_layout_roads(2, 0.5), "u.xodr").root)
    assert other.roads[1].lane_template is other.roads[1]  # the first one asked
    assert other.roads[0].lane_template is other.roads[1]
    assert other.roads[0].lane_template is not first  # a template is one file's


def test_lane_rules_judge_a_layout_once_and_report_on_each_roads_own_lane(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from xodrlint.api import default_registry
    from xodrlint.engine.linter import Linter, LintOptions
    from xodrlint.model import network as model_network

    reads: list[object] = []
    original = model_network._read_lanes

    def counted(element: etree._Element) -> object:
        reads.append(element)
        return original(element)

    monkeypatch.setattr(model_network, "_read_lanes", counted)
    linter = Linter(default_registry(), LintOptions(select=("RL", "SW011", "TR")))
    clean = linter.lint_bytes(_same_layout_roads(40, 0.75), "clean.xodr")
    assert clean.findings == ()
    assert len(reads) == 1  # the template's lanes; no road had anything to report
    reads.clear()
    off = linter.lint_bytes(_same_layout_roads(40, 0.95), "off.xodr")
    assert sorted((f.code, f.xpath, f.message) for f in off.findings) == sorted(
        (
            "RL002",
            f"/OpenDRIVE/road[@id='{n}']/lanes/laneSection/right/lane[@id='-1']",
            f"the centre of rail lane '-1' of road '{n}' (lane section at s=0) is 0.2 m "
            "from the reference line at s=0 (tolerance 0.05 m)",
        )
        for n in range(40)
    )
    assert len(reads) == 40  # the template's and then each reported road's own


def test_a_model_holds_no_reference_cycles() -> None:
    # the command line freezes what a lint made before the collector is back on: a cycle
    # there would keep every document of a batch alive
    import gc

    from xodrlint.api import default_registry
    from xodrlint.engine.linter import Linter, LintOptions

    linter = Linter(default_registry(), LintOptions(), keep_last_document=True)
    railway = _same_layout_roads(30, 0.75)
    was = gc.isenabled()
    gc.collect()
    gc.disable()
    try:
        for number in range(3):
            linter.lint_bytes(railway, f"r{number}.xodr")
        linter.lint_bytes(b"<OpenDRIVE/>", "last.xodr")  # lets the railway go
        assert gc.collect() == 0
    finally:
        gc.unfreeze()
        (gc.enable if was else gc.disable)()


_PARTS = (
    b'<OpenDRIVE><header revMajor="1" revMinor="7"/>'
    b'<road id="1" length="10"><link><!-- to the yard -->'
    b'<successor elementType="road" elementId="2" contactPoint="start"/>'
    b'<predecessor elementType="junction" elementId="7"/></link>'
    b'<elevationProfile><elevation s="0" a="1" b="0" c="0" d="0"/></elevationProfile>'
    b'<lateralProfile/><railroad><switch id="9" name="W9" position="dynamic">'
    b'<mainTrack id="1" s="5" dir="+"/><sideTrack id="2" s="0" dir="+"/></switch></railroad>'
    b'<link><successor elementType="road" elementId="3"/></link></road>'
    b'<road id="2" length="10"/></OpenDRIVE>'
)


def test_links_and_profiles_read_with_the_switches_equal_those_read_on_their_own() -> None:
    from xodrlint.model import Road

    root = load_bytes(_PARTS, "p.xodr").root
    assert root is not None
    network = build_network(root)
    built = network.roads[0]
    alone = Road(built.element, "1", 10.0, False)  # made without the model's pass
    assert alone.links == built.links
    assert [(link.kind, link.element_id, link.contact_point) for link in built.links] == [
        ("successor", "2", "start"),
        ("predecessor", "7", None),
        ("successor", "3", None),
    ]
    assert [element.tag for element in alone.profiles] == ["elevationProfile", "lateralProfile"]
    assert list(alone.profiles) == list(built.profiles)
    assert [switch.id for switch in network.switches] == ["9"]
    assert network.roads[1].links == () and network.roads[1].profiles == ()
