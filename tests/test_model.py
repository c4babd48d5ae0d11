"""Stage 3: the indexes rules share, built in one pass, lenient with bad attributes."""

from __future__ import annotations

import math

import pytest
from lxml import etree

from xodrlint.document import load_bytes
from xodrlint.model import build_network, number, numbers

from .conftest import REPO


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
