"""The track network's links (rules/tracks/_joints.py): joints judged lane by lane at the
lanes' own centres (TR001, TR002), checked against independent computations; which
lanes a joint joins; links judged as links (TR003-TR005) and lane links (TR006, TR007);
and bad values in links giving silence or a finding, never a traceback."""

from __future__ import annotations

import math
from collections import Counter

import pytest

from tests.conftest import SHARED, needs_shared
from xodrlint.api import lint_bytes
from xodrlint.document.load import load_bytes
from xodrlint.model import build_network
from xodrlint.rules.tracks._joints import Joint
from xodrlint.rules.tracks._network import joints, track_network

scipy_integrate = pytest.importorskip("scipy.integrate", reason="scipy is a test dependency")

LARGE = SHARED / "corpus" / "large"


def _lane(lane_id: int, lane_type: str, width: float, links: str = "") -> str:
    link = f"<link>{links}</link>" if links else ""
    return (
        f'<lane id="{lane_id}" type="{lane_type}" level="false">{link}'
        f'<width sOffset="0" a="{width}" b="0" c="0" d="0"/></lane>'
    )


def _road(
    road_id: str,
    geometry: str,
    length: float,
    *,
    links: str = "",
    right: str = "",
    left: str = "",
    offset: float = 0.0,
    junction: str = "-1",
) -> str:
    sides = f"<left>{left}</left>" if left else ""
    sides += '<center><lane id="0" type="none" level="false"/></center>'
    sides += f"<right>{right}</right>" if right else ""
    return (
        f'<road name="" length="{length}" id="{road_id}" junction="{junction}">'
        f"<link>{links}</link><planView>{geometry}</planView><lanes>"
        f'<laneOffset s="0" a="{offset}" b="0" c="0" d="0"/>'
        f'<laneSection s="0">{sides}</laneSection></lanes></road>'
    )


def _document(*parts: str) -> bytes:
    body = "".join(parts)
    return (
        '<OpenDRIVE><header revMajor="1" revMinor="7" name="t"/>' + body + "</OpenDRIVE>"
    ).encode()


def _joints(data: bytes) -> list[Joint]:
    doc = load_bytes(data, "t.xodr")
    return joints(build_network(doc.root))


def _codes(data: bytes, select: str = "TR") -> Counter[str]:
    return Counter(f.code for f in lint_bytes(data, "t.xodr", select=(select,)).findings)


# an arc of radius 50 m turning left, 40 m long, then a straight road where it ends
RADIUS, ARC = 50.0, 40.0


def _arc_end(t: float) -> tuple[float, float]:
    """Where a lane centre ``t`` metres left of the arc's reference line ends, by
    integrating the heading (scipy), independent of the plan-view code."""
    x = scipy_integrate.quad(lambda s: math.cos(s / RADIUS), 0.0, ARC)[0]
    y = scipy_integrate.quad(lambda s: math.sin(s / RADIUS), 0.0, ARC)[0]
    heading = ARC / RADIUS
    return x - t * math.sin(heading), y + t * math.cos(heading)


def _double_track(widths: tuple[float, float], start_offset: float) -> bytes:
    """Road 1: an arc with two rail lanes on the right (-1, -2), linked lane by lane to
    road 2, a straight road starting where the arc's reference line ends, shifted
    ``start_offset`` metres to its left, with two rail lanes of ``widths``."""
    heading = ARC / RADIUS
    x, y = _arc_end(start_offset)
    arc = f'<geometry s="0" x="0" y="0" hdg="0" length="{ARC}"><arc curvature="{1 / RADIUS}"/></geometry>'
    line = f'<geometry s="0" x="{x!r}" y="{y!r}" hdg="{heading!r}" length="30"><line/></geometry>'
    first = _road(
        "1",
        arc,
        ARC,
        links='<successor elementType="road" elementId="2" contactPoint="start"/>',
        right=_lane(-1, "rail", 1.5, '<successor id="-1"/>')
        + _lane(-2, "rail", 1.5, '<successor id="-2"/>'),
    )
    second = _road(
        "2",
        line,
        30,
        links='<predecessor elementType="road" elementId="1" contactPoint="end"/>',
        right=_lane(-1, "rail", widths[0], '<predecessor id="-1"/>')
        + _lane(-2, "rail", widths[1], '<predecessor id="-2"/>'),
        offset=-start_offset,
    )
    return _document(first, second)


def test_double_track_is_judged_lane_by_lane_at_the_lanes_own_centres() -> None:
    # road 2's reference line starts 2 m left of the arc's end, and its laneOffset of -2 m
    # brings its lanes back: every lane centre meets, though the reference lines do not
    found = _joints(_double_track((1.5, 1.5), 2.0))
    assert len(found) == 1
    pairs = found[0].lanes
    assert [(p.first.lane.id, p.second.lane.id) for p in pairs] == [(-1, -1), (-2, -2)]
    for pair, t in zip(pairs, (-0.75, -2.25), strict=True):
        expected = _arc_end(t)
        for got in (pair.first_point, pair.second_point):
            assert got is not None
            assert math.hypot(got.x - expected[0], got.y - expected[1]) < 1e-6
    assert _codes(_double_track((1.5, 1.5), 2.0)) == Counter()


def test_a_gap_on_one_track_of_two_is_reported_once_with_its_own_distance() -> None:
    # lane -1 of road 2 is 0.3 m wider: its centre is 0.15 m further out, and lane -2's
    # centre 0.3 m (both beyond 0.1 m); an independent sum of the widths says where
    data = _double_track((1.8, 1.5), 0.0)
    report = lint_bytes(data, "t.xodr", select=("TR001",))
    messages = [f.message for f in report.findings]
    assert len(messages) == 2
    assert "rail lane -1 of road '1' and rail lane -1 of road '2' are 0.15 m apart" in messages[0]
    assert "rail lane -2 of road '1' and rail lane -2 of road '2' are 0.3 m apart" in messages[1]


def test_the_one_lane_each_default_and_a_lane_link_pointing_elsewhere() -> None:
    line1 = '<geometry s="0" x="0" y="0" hdg="0" length="10"><line/></geometry>'
    line2 = '<geometry s="0" x="10" y="0" hdg="0" length="10"><line/></geometry>'
    to2 = '<successor elementType="road" elementId="2" contactPoint="start"/>'
    to1 = '<predecessor elementType="road" elementId="1" contactPoint="end"/>'
    plain = _document(
        _road("1", line1, 10, links=to2, right=_lane(-1, "rail", 1.5)),
        _road("2", line2, 10, links=to1, right=_lane(-1, "tram", 1.5)),
    )
    assert [(p.first.lane.id, p.second.lane.id) for p in _joints(plain)[0].lanes] == [(-1, -1)]
    # road 1's rail lane names road 2's sidewalk: the default still joins the two rail
    # lanes (the catalogue: "joined even without a lane link"); the link is TR007's alone
    elsewhere = _document(
        _road("1", line1, 10, links=to2, right=_lane(-1, "rail", 1.5, '<successor id="-2"/>')),
        _road("2", line2, 10, links=to1, right=_lane(-1, "tram", 1.5) + _lane(-2, "sidewalk", 2)),
    )
    assert [(p.first.lane.id, p.second.lane.id) for p in _joints(elsewhere)[0].lanes] == [(-1, -1)]
    assert _codes(elsewhere) == Counter({"TR007": 1})  # the rail lane turns into a sidewalk


def test_links_are_judged_before_what_they_join() -> None:
    line1 = '<geometry s="0" x="0" y="0" hdg="0" length="10"><line/></geometry>'
    far = '<geometry s="0" x="15" y="3" hdg="1" length="10"><line/></geometry>'
    rail = _lane(-1, "rail", 1.5)
    one_sided = _document(
        _road(
            "1",
            line1,
            10,
            links='<successor elementType="road" elementId="2" contactPoint="start"/>',
            right=rail,
        ),
        _road("2", far, 10, right=rail),
    )
    # a one-sided link: TR004 alone, though the roads are 5 m apart at an angle
    assert _codes(one_sided) == Counter({"TR004": 1})
    # selected alone, TR001 still says what it sees (the engine's one-defect policy)
    assert _codes(one_sided, "TR001") == Counter({"TR001": 1})
    answered = track_network(build_network(load_bytes(one_sided, "t").root))
    assert [(link.fault, link.reported) for link in answered.links] == [("TR004", True)]


def test_a_junction_answers_for_its_connecting_road() -> None:
    line = '<geometry s="0" x="{}" y="0" hdg="0" length="10"><line/></geometry>'
    rail = _lane(-1, "rail", 1.5)
    for connecting_attribute, connection in (
        ("5", ""),  # road 2's own @junction says it belongs to junction 5
        ("-1", '<connection id="0" incomingRoad="1" connectingRoad="2" contactPoint="start"/>'),
    ):
        data = _document(
            _road(
                "1",
                line.format(0),
                10,
                links='<successor elementType="junction" elementId="5"/>',
                right=rail,
            ),
            _road(
                "2",
                line.format(10),
                10,
                links='<predecessor elementType="road" elementId="1" contactPoint="end"/>',
                right=rail,
                junction=connecting_attribute,
            ),
            f'<junction id="5" name="j">{connection}</junction>',
        )
        assert _codes(data) == Counter(), connecting_attribute


def test_a_junction_lane_link_to_a_lane_the_connecting_track_lacks() -> None:
    line = '<geometry s="0" x="{}" y="0" hdg="0" length="10"><line/></geometry>'
    rail = _lane(-1, "rail", 1.5)
    data = _document(
        _road(
            "1",
            line.format(0),
            10,
            links='<successor elementType="junction" elementId="5"/>',
            right=rail,
        ),
        _road(
            "2",
            line.format(10),
            10,
            links='<predecessor elementType="road" elementId="1" contactPoint="end"/>',
            right=rail,
            junction="5",
        ),
        '<junction id="5" name="j"><connection id="0" incomingRoad="1" connectingRoad="2" '
        'contactPoint="start"><laneLink from="-1" to="-3"/></connection></junction>',
    )
    report = lint_bytes(data, "t.xodr", select=("TR006",))
    assert [f.message for f in report.findings] == [
        "laneLink of connection '0' in junction '5' names lane -3 of connecting road '2' (to), "
        "which its start does not have (lanes: 0, -1)"
    ]


@pytest.mark.parametrize(
    "link",
    [
        '<successor elementType="road" contactPoint="start"/>',
        '<successor elementType="road" elementId="2" contactPoint="middle"/>',
        '<successor elementType="lane" elementId="2" contactPoint="start"/>',
        '<successor elementType="junction"/>',
        '<successor elementType="road" elementId="1" contactPoint="start"/>',  # itself
    ],
)
@pytest.mark.parametrize(
    "lane_link", ['<successor id="x"/>', "<successor/>", '<successor id="-1"/><successor id="9"/>']
)
def test_bad_values_in_links_give_findings_or_silence_never_a_traceback(
    link: str, lane_link: str
) -> None:
    line = '<geometry s="0" x="{}" y="0" hdg="0" length="10"><line/></geometry>'
    data = _document(
        _road("1", line.format(0), 10, links=link, right=_lane(-1, "rail", 1.5, lane_link)),
        _road(
            "2",
            line.format(10),
            10,
            links='<predecessor elementType="road" elementId="1" contactPoint="end"/>',
            right=_lane(-1, "rail", 1.5),
        ),
    )
    report = lint_bytes(data, "t.xodr", select=("TR",))
    assert report.internal_errors == ()


#: Braunschweig's TR001 before lanes were joined: 30, of which 20 were double track
#: judged at its reference line (the lane links join those tracks with no gap).
BRAUNSCHWEIG_TR001_LINES = [28632, 30731, 44127, 52509, 52743, 52744, 53738, 54091, 59285, 59286]


@needs_shared
def test_braunschweig_keeps_only_the_true_gaps() -> None:
    path = LARGE / "SUMO-gen_bs3d_Braunschweig.xodr"
    report = lint_bytes(path.read_bytes(), path.name, select=("TR001", "TR002"))
    assert report.internal_errors == ()
    assert sorted(f.line for f in report.findings if f.code == "TR001") == BRAUNSCHWEIG_TR001_LINES
    # a connecting track of junction 111 ends 1.27 m from the start of rail lane -1 of road
    # 2463 (a 47 degree kink too, which TR001's gap silences)
    first = next(f for f in report.findings if f.line == 28632)
    assert (
        "rail lane -1 of road '2730' and rail lane -1 of road '2463' are 1.2712 m" in first.message
    )


def test_two_independent_one_sided_links_are_two_findings() -> None:
    # road 1 runs into road 2 at both of road 2's ends (a loop); road 2 links nothing back:
    # two joints, each one-sided, so two TR004 (a pair of links naming each other at the
    # wrong end is one defect; these are not such a pair)
    line1 = '<geometry s="0" x="0" y="0" hdg="0" length="10"><line/></geometry>'
    line2 = '<geometry s="0" x="10" y="0" hdg="0" length="10"><line/></geometry>'
    rail = _lane(-1, "rail", 1.5)
    data = _document(
        _road(
            "1",
            line1,
            10,
            links='<predecessor elementType="road" elementId="2" contactPoint="end"/>'
            '<successor elementType="road" elementId="2" contactPoint="start"/>',
            right=rail,
        ),
        _road("2", line2, 10, right=rail),
    )
    assert _codes(data) == Counter({"TR004": 2})


def test_links_to_or_from_a_repeated_road_id_are_not_judged() -> None:
    # two roads share id 2; which one road 1's successor means is unknown: XS006 says so
    line = '<geometry s="0" x="{}" y="0" hdg="0" length="10"><line/></geometry>'
    rail = _lane(-1, "rail", 1.5)
    back = '<predecessor elementType="road" elementId="1" contactPoint="end"/>'
    data = _document(
        _road(
            "1",
            line.format(0),
            10,
            links='<successor elementType="road" elementId="2" contactPoint="start"/>',
            right=rail,
        ),
        _road("2", line.format(10), 10, links=back, right=rail),
        _road("2", line.format(500), 10, links=back, right=rail),
    )
    assert _codes(data) == Counter()
    found = Counter(f.code for f in lint_bytes(data, "t.xodr").findings)
    assert found["XS006"] == 1 and not any(code.startswith("TR") for code in found)


def test_a_link_written_twice_is_one_joint() -> None:
    # a road end naming the same road end twice: one joint, one finding, whichever road
    # comes first in the document
    rail = _lane(-1, "rail", 1.5)
    twice = '<successor elementType="road" elementId="2" contactPoint="start"/>' * 2
    first = _road(
        "1",
        '<geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry>',
        100,
        links=twice,
        right=rail,
    )
    second = _road(
        "2",
        '<geometry s="0" x="101" y="0" hdg="0.5" length="50"><line/></geometry>',
        50,
        links='<predecessor elementType="road" elementId="1" contactPoint="end"/>',
        right=rail,
    )
    for roads in ((first, second), (second, first)):
        data = _document(*roads)
        assert _codes(data)["TR001"] == 1
        assert len(_joints(data)) == 1
