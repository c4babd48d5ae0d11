"""Track points against independent references: closed forms for lines, arcs and
paramPoly3, Fresnel integrals (scipy) for spirals, adaptive quadrature (scipy) for poly3,
each 1 km from its record's start, with laneOffset and width cubics. And: geometry that
cannot be evaluated gives silence, never a traceback."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from tests.conftest import CORPUS_RAIL, REPO, needs_shared
from xodrlint.api import lint_bytes
from xodrlint.document.load import load_bytes
from xodrlint.geometry.tracks import TrackGeometry, TrackPoint, angle_between
from xodrlint.model import build_network
from xodrlint.model.lane_profiles import centre_at, centre_terms, lateral_value

scipy_special = pytest.importorskip("scipy.special", reason="scipy is a test dependency")
scipy_integrate = pytest.importorskip("scipy.integrate")
scipy_optimize = pytest.importorskip("scipy.optimize")

#: The record starts away from the origin, heading 0.7 rad; evaluated 1 km along it.
X0, Y0, HDG0 = 1000.0, -500.0, 0.7
LENGTH = 1200.0
AT = 1000.0
#: laneOffset and the rail lane's width: cubics in s that stay near track sizes to 1.2 km.
OFFSET = (0.5, 1e-4, -1e-7, 1e-10)
WIDTH = (1.5, 1e-5, 1e-8, -1e-11)
MILLIMETRE = 1e-3
CASES = REPO / "rules"


def _cubic(coefficients: tuple[float, float, float, float], s: float) -> float:
    a, b, c, d = coefficients
    return a + s * (b + s * (c + s * d))


def _document(curve: str) -> bytes:
    offset = 'a="{}" b="{}" c="{}" d="{}"'.format(*OFFSET)
    width = 'a="{}" b="{}" c="{}" d="{}"'.format(*WIDTH)
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<OpenDRIVE>
  <header revMajor="1" revMinor="7" name="t"/>
  <road name="track" length="{LENGTH}" id="1" junction="-1">
    <planView>
      <geometry s="0" x="{X0}" y="{Y0}" hdg="{HDG0}" length="{LENGTH}">{curve}</geometry>
    </planView>
    <lanes>
      <laneOffset s="0" {offset}/>
      <laneSection s="0">
        <center><lane id="0" type="none" level="false"/></center>
        <right><lane id="-1" type="rail" level="false"><width sOffset="0" {width}/></lane></right>
      </laneSection>
    </lanes>
  </road>
</OpenDRIVE>
""".encode()


def _track_point(curve: str, s: float = AT) -> TrackPoint:
    doc = load_bytes(_document(curve), "t.xodr")
    network = build_network(doc.root)
    point = network.shared(TrackGeometry).point(network.roads[0], s)
    assert point is not None
    return point


def _expected(u: float, v: float, turn: float, s: float = AT) -> tuple[float, float, float]:
    """The track point for a local position (u, v) and heading change ``turn`` of the
    record: placed by the record's start, then moved to the rail lane's centre."""
    cos_h, sin_h = math.cos(HDG0), math.sin(HDG0)
    x = X0 + u * cos_h - v * sin_h
    y = Y0 + u * sin_h + v * cos_h
    heading = HDG0 + turn
    t = _cubic(OFFSET, s) - _cubic(WIDTH, s) / 2  # lane -1: right of the offset line
    return x - t * math.sin(heading), y + t * math.cos(heading), heading


def _assert_close(point: TrackPoint, expected: tuple[float, float, float]) -> None:
    x, y, heading = expected
    assert math.hypot(point.x - x, point.y - y) < MILLIMETRE, (point, expected)
    assert angle_between(point.heading, heading) < 1e-6


def test_line_against_its_closed_form() -> None:
    _assert_close(_track_point("<line/>"), _expected(AT, 0.0, 0.0))


@pytest.mark.parametrize("curvature", [0.001, -0.0015, 1e-12])
def test_arc_against_its_closed_form(curvature: float) -> None:
    turn = curvature * AT
    if abs(turn) < 1e-9:
        local = (AT, 0.0)
    else:
        local = (math.sin(turn) / curvature, (1 - math.cos(turn)) / curvature)
    _assert_close(_track_point(f'<arc curvature="{curvature}"/>'), _expected(*local, turn))


def _clothoid(start: float, rate: float, s: float) -> tuple[float, float, float]:
    """Position and heading change of a clothoid with curvature ``start + rate·s``, by the
    Fresnel integrals: the phase ``rate/2·(s + start/rate)² - start²/(2 rate)``."""
    if rate < 0:  # the mirror image of the curve with both signs turned
        u, v, turn = _clothoid(-start, -rate, s)
        return u, -v, -turn
    alpha, shift = rate / 2, start / rate
    gamma = -(start**2) / (2 * rate)
    scale = math.sqrt(2 * alpha / math.pi)
    sin_1, cos_1 = scipy_special.fresnel(scale * (s + shift))
    sin_0, cos_0 = scipy_special.fresnel(scale * shift)
    factor = math.sqrt(math.pi / (2 * alpha))
    cosine, sine = cos_1 - cos_0, sin_1 - sin_0
    u = factor * (math.cos(gamma) * cosine - math.sin(gamma) * sine)
    v = factor * (math.sin(gamma) * cosine + math.cos(gamma) * sine)
    return u, v, start * s + rate * s * s / 2


@pytest.mark.parametrize(("start", "end"), [(0.0, 0.002), (0.001, -0.0015), (-0.0005, -0.002)])
def test_spiral_against_fresnel_integrals(start: float, end: float) -> None:
    curve = f'<spiral curvStart="{start}" curvEnd="{end}"/>'
    _assert_close(_track_point(curve), _expected(*_clothoid(start, (end - start) / LENGTH, AT)))


def test_poly3_against_adaptive_quadrature() -> None:
    a, b, c, d = 0.2, 0.01, 1e-5, -5e-9

    def slope(u: float) -> float:
        return b + 2 * c * u + 3 * d * u * u

    def arc_length(u: float) -> float:
        value, _ = scipy_integrate.quad(lambda x: math.hypot(1.0, slope(x)), 0.0, u, epsabs=1e-12)
        return float(value)

    u = scipy_optimize.brentq(lambda x: arc_length(x) - AT, 0.0, AT, xtol=1e-12)
    v = a + b * u + c * u * u + d * u**3
    curve = f'<poly3 a="{a}" b="{b}" c="{c}" d="{d}"/>'
    _assert_close(_track_point(curve), _expected(u, v, math.atan(slope(u))))


@pytest.mark.parametrize("p_range", ["normalized", "arcLength"])
def test_param_poly3_against_its_closed_form(p_range: str) -> None:
    if p_range == "normalized":
        u_poly, v_poly, p = (0.0, LENGTH, 0.0, 0.0), (0.0, 0.0, 100.0, -50.0), AT / LENGTH
    else:
        u_poly, v_poly, p = (0.0, 1.0, 0.0, 0.0), (0.0, 0.0, 1e-4, -5e-8), AT
    names = ("aU", "bU", "cU", "dU", "aV", "bV", "cV", "dV")
    values = (*u_poly, *v_poly)
    attributes = " ".join(f'{n}="{v}"' for n, v in zip(names, values, strict=True))
    curve = f'<paramPoly3 {attributes} pRange="{p_range}"/>'

    def derivative(poly: tuple[float, ...]) -> float:
        return poly[1] + 2 * poly[2] * p + 3 * poly[3] * p * p

    expected = _expected(
        _cubic(u_poly, p),
        _cubic(v_poly, p),
        math.atan2(derivative(v_poly), derivative(u_poly)),
    )
    _assert_close(_track_point(curve), expected)


@needs_shared
@pytest.mark.parametrize(
    "name", ["ASAM-1.6.0_Ex-Railway-Switch.xodr", "ASAM-1.7.0_Ex_Railway-Switch.xodr"]
)
def test_asam_switch_examples_meet_exactly(name: str) -> None:
    doc = load_bytes((CORPUS_RAIL / name).read_bytes(), name)
    network = build_network(doc.root)
    tracks = network.shared(TrackGeometry)
    met = {}
    for switch in network.switches:
        main, side = switch.main_track, switch.side_track
        assert main is not None and side is not None
        main_point = tracks.point(network.road_by_id[str(main.road_id)], main.s or 0.0)
        side_point = tracks.point(network.road_by_id[str(side.road_id)], side.s or 0.0)
        assert main_point is not None and side_point is not None
        assert main_point.distance_to(side_point) < 1e-9
        entering, leaving = main_point.direction(str(main.dir)), side_point.direction(str(side.dir))
        assert angle_between(entering, leaving) < 1e-9
        met[switch.id] = (round(main_point.x, 9), round(main_point.y, 9), entering % math.tau)
    assert met["12"] == (10.0, 0.0, 0.0)
    assert met["32"][:2] == (44.5, 4.5) and math.isclose(met["32"][2], math.pi)


_SWITCHED = """<?xml version="1.0" encoding="UTF-8"?>
<OpenDRIVE>
  <header revMajor="1" revMinor="7" name="t"/>
  <road name="main" length="100" id="1" junction="-1">
    <link><successor elementType="road" elementId="2" contactPoint="start"/></link>
    <planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>
    <lanes><laneSection s="0"><center><lane id="0" type="none" level="false"/></center>
      <right><lane id="-1" type="rail" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane></right>
    </laneSection></lanes>
    <railroad><switch name="W1" id="101" position="dynamic">
      <mainTrack id="1" s="30" dir="+"/><sideTrack id="2" s="0" dir="+"/>
    </switch></railroad>
  </road>
  <road name="side" length="{length}" id="2" junction="-1">
    <link><predecessor elementType="road" elementId="1" contactPoint="end"/></link>
    <planView><geometry s="0" x="{x}" y="5" hdg="{hdg}" length="{glength}">{curve}</geometry></planView>
    <lanes>
      <laneOffset s="0" a="{offset}" b="0" c="0" d="0"/>
      <laneSection s="{section_s}"><center><lane id="0" type="none" level="false"/></center>
      <right><lane id="-1" type="rail" level="false"><width sOffset="0" a="{width}" b="0" c="0" d="0"/></lane></right>
    </laneSection></lanes>
  </road>
</OpenDRIVE>
"""
_NORMAL = {
    "glength": "20",
    "section_s": "0",
    "x": "30",
    "hdg": "0.3",
    "length": "20",
    "curve": "<line/>",
    "offset": "0.75",
    "width": "1.5",
}
_HOSTILE: dict[str, dict[str, str]] = {
    "NaN x": {"x": "NaN"},
    "INF heading": {"hdg": "INF"},
    "huge x": {"x": "1e308"},
    "huge heading": {"hdg": "1e308"},
    "missing lengths": {"length": "", "glength": ""},
    "missing record length, road length kept": {"glength": ""},
    "NaN record length, road length kept": {"glength": "NaN"},
    "NaN lane section start": {"section_s": "NaN"},
    "lane section starting after the joint": {"section_s": "5"},
    "zero-length record": {"length": "0", "glength": "0"},
    "spiral whose rate overflows": {
        "length": "1e-300",
        "glength": "1e-300",
        "curve": '<spiral curvStart="0" curvEnd="1e300"/>',
    },
    "curvature that overflows": {"curve": '<arc curvature="1e308"/>'},
    "spiral that overflows": {"curve": '<spiral curvStart="-1e308" curvEnd="1e308"/>'},
    "poly3 whose slope overflows": {"curve": '<poly3 a="0" b="0" c="1.7e308" d="-1.7e308"/>'},
    "paramPoly3 of huge numbers": {
        "curve": '<paramPoly3 aU="0" bU="1e308" cU="1e308" dU="1e308" aV="0" bV="0" cV="0" dV="1e308"/>'
    },
    "INF laneOffset": {"offset": "INF"},
    "huge width": {"width": "1e308"},
    "NaN width": {"width": "NaN"},
}


#: The hostile values in the plan view: TR014 says the track is not judged, on the record.
_PLAN_VIEW_CASES = {case for case, values in _HOSTILE.items() if set(values) - {"length"} & {
    "x", "hdg", "glength", "curve"}}  # fmt: skip


@pytest.mark.parametrize("case", sorted(_HOSTILE))
def test_geometry_that_cannot_be_evaluated_gives_silence(case: str) -> None:
    values = {**_NORMAL, **_HOSTILE[case]}
    data = _SWITCHED.format(**values).replace(' length=""', "").replace(' s=""', "")
    report = lint_bytes(data.encode(), "hostile.xodr", select=["SW011", "SW012", "TR"])
    assert not report.internal_errors, report.internal_errors
    assert report.error is None
    # the road with the bad value is silenced; road 1's own track is fine. Where the bad
    # value is in the plan view, TR014 says why, once, on the record (line 16); a bad lane
    # is the lane rules' (RL002, RL003) to report
    expected = [(16, "TR014")] if case in _PLAN_VIEW_CASES else []
    assert [(f.line, f.code) for f in report.findings] == expected


def test_the_normal_case_of_the_hostile_ones_is_judged() -> None:
    # the hostile cases would pass vacuously if the document never reached the rules:
    # the normal one has the side road 5 m off (SW011, which silences SW012) and a gap and
    # a 17 degree kink at the joint (TR001, which silences TR002 on the same lanes)
    data = _SWITCHED.format(**_NORMAL).encode()
    report = lint_bytes(data, "normal.xodr", select=["SW011", "SW012", "TR"])
    assert sorted(f.code for f in report.findings) == ["SW011", "TR001"]
    kink = lint_bytes(data, "normal.xodr", select=["TR002"])
    assert [f.code for f in kink.findings] == []  # a gap makes the angle meaningless


def _sections_of_the_cases() -> list[tuple[str, int, int]]:
    cases = sorted((CASES / "RL002").glob("*.xodr")) + sorted((CASES / "RL003").glob("*.xodr"))
    cases += sorted((CASES / "SW011").glob("*.xodr"))
    found = []
    for path in cases:
        network = build_network(load_bytes(path.read_bytes(), path.name).root)
        for r, road in enumerate(network.roads):
            for k, _ in enumerate(road.section_ranges()):
                found.append((str(path.relative_to(CASES)), r, k))
    return found


@pytest.mark.parametrize(("case", "road_index", "section_index"), _sections_of_the_cases())
def test_centre_at_one_s_equals_the_centre_functions(
    case: str, road_index: int, section_index: int
) -> None:
    # centre_at evaluates at one s what centre_terms builds as functions for RL002/RL003
    path = CASES / case
    road = build_network(load_bytes(path.read_bytes(), path.name).root).roads[road_index]
    section, start, end = list(road.section_ranges())[section_index]
    for lane in section.lanes:
        terms = centre_terms(road, section, start, lane)
        for s in (start - 1.0, start, (start + end) / 2, end, start + 0.3 * (end - start)):
            at = centre_at(road, section, start, lane, s)
            # before a width is defined, centre_at says so; the map's functions extrapolate
            defined = terms is not None and all(f.defined_from <= s + 1e-6 for _, f in terms)
            if not defined:
                assert at is None
            else:
                assert terms is not None and at is not None
                assert math.isclose(at, lateral_value(terms, s), abs_tol=1e-12)


def test_a_message_never_reads_as_its_limit() -> None:
    from xodrlint.rules._shared import beyond, degrees

    assert beyond(0.1000011, 0.1, 4) == "0.100001"
    assert beyond(0.15, 0.1, 4) == "0.15"
    assert beyond(5.0000001, 5.0, 2) == "5.0000001"
    assert degrees(math.tau - 1e-7) == "0"
    assert degrees(-0.1) == "354.27"  # a direction reads on the circle


def _rail_case_files() -> list[Path]:
    files = sorted((REPO / "rules").glob("*/*.xodr"))
    return files + (sorted(CORPUS_RAIL.glob("*.xodr")) if CORPUS_RAIL.is_dir() else [])


def test_a_constant_layout_gives_the_lateral_position_the_general_path_gives() -> None:
    # the shortcut for one lane section of constant offset and widths must agree with
    # centre_at everywhere along the road, for every layout of the cases and the corpus
    from xodrlint.geometry import tracks

    shortcuts = 0
    for path in _rail_case_files():
        root = load_bytes(path.read_bytes(), path.name).root
        if root is None or root.tag != "OpenDRIVE":
            continue
        for road in build_network(root).roads:
            constant = tracks._constant_lateral(road)
            if constant is None:
                continue
            shortcuts += 1
            start = road.lane_sections[0].s or 0.0
            for s in (start, start + 0.5, start + 17.25, start + 1000.0):
                assert tracks._lateral_at(road.lane_sections, road, s) == constant, (path, road)
    assert shortcuts > 20


def test_layouts_that_vary_take_the_general_path() -> None:
    from xodrlint.geometry import tracks

    def road_with(lanes: str) -> object:
        text = (
            '<OpenDRIVE><header revMajor="1" revMinor="7"/><road id="1" length="100" '
            f'junction="-1"><lanes>{lanes}</lanes></road></OpenDRIVE>'
        )
        return build_network(load_bytes(text.encode(), "t.xodr").root).roads[0]

    rail = '<right><lane id="-1" type="rail"><width sOffset="{w}" a="1.5" b="{b}" c="0" d="0"/></lane></right>'
    section = '<laneSection s="0"><center><lane id="0" type="none"/></center>{rail}</laneSection>'
    varying = [
        '<laneOffset s="0" a="0.75" b="0.01" c="0" d="0"/>'
        + section.format(rail=rail.format(w=0, b=0)),
        '<laneOffset s="5" a="0.75" b="0" c="0" d="0"/>'
        + section.format(rail=rail.format(w=0, b=0)),
        section.format(rail=rail.format(w=0, b=0.001)),
        section.format(rail=rail.format(w=2, b=0)),
        section.format(rail=rail.format(w=0, b=0)) * 2,
    ]
    for lanes in varying:
        assert tracks._constant_lateral(road_with(lanes)) is None, lanes  # type: ignore[arg-type]
    steady = section.format(rail=rail.format(w=0, b=0))
    assert tracks._constant_lateral(road_with(steady)) == -0.75  # type: ignore[arg-type]


def _end_points_agree(root: object) -> int:
    """Checks :meth:`TrackGeometry.lane_end_point` against :meth:`lane_point` at both ends
    of every rail lane of ``root``'s tracks; the number of points compared."""
    from xodrlint.rules.tracks._joints import rail_lanes_at

    network = build_network(root)  # type: ignore[arg-type]
    general, shortcut = TrackGeometry(network), TrackGeometry(network)
    compared = 0
    for road in network.rail_roads:
        shortcut.plan_view(road)  # judged first, as the joints find it
        for end in ("start", "end"):
            s = 0.0 if end == "start" else (road.length if road.length is not None else math.nan)
            for lane in rail_lanes_at(road, end):
                expected = general.lane_point(road, lane.section, lane.lane, s)
                found = shortcut.lane_end_point(road, lane.section, lane.lane, end)
                assert found == expected, (road, end, lane.lane.id)
                compared += 1
    return compared


def test_a_lane_end_point_is_the_lane_point_at_that_end() -> None:
    compared = 0
    for path in _rail_case_files():
        root = load_bytes(path.read_bytes(), path.name).root
        if root is not None and root.tag == "OpenDRIVE":
            compared += _end_points_agree(root)
    assert compared > 100


@pytest.mark.parametrize(
    ("records", "length"),
    [
        (
            '<geometry s="0" x="1" y="2" hdg="0.3" length="40"><spiral curvStart="0" curvEnd="0.02"/></geometry>',
            "40",
        ),
        (
            '<geometry s="0.0005" x="1" y="2" hdg="0.3" length="40"><arc curvature="0.01"/></geometry>',
            "40.0009",
        ),
        (
            '<geometry s="0" x="0" y="0" hdg="0" length="10"><line/></geometry>'
            '<geometry s="0" x="0" y="0" hdg="1" length="10"><line/></geometry>',
            "10",
        ),
        (
            '<geometry s="0" x="0" y="0" hdg="0" length="10"><line/></geometry>'
            '<geometry s="10" x="10" y="0" hdg="0" length="10"><arc curvature="-0.05"/></geometry>',
            "19.5",
        ),
        ('<geometry s="-2" x="0" y="0" hdg="0" length="12"><line/></geometry>', "10"),
        ('<geometry s="0.01" x="0" y="0" hdg="0" length="10"><line/></geometry>', "10.02"),
    ],
)
def test_a_lane_end_point_agrees_where_the_ends_are_not_the_records(
    records: str, length: str
) -> None:
    # a first record off s=0, a length short of or beyond the plan view, two records
    # at one s: the shortcut gives way to the general path, or gives its very numbers
    lanes = (
        '<lanes><laneOffset s="0" a="0.5" b="0" c="0" d="0"/><laneSection s="0"><left>'
        '<lane id="1" type="rail"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane>'
        '</left><center><lane id="0" type="none"/></center><right>'
        '<lane id="-1" type="tram"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane>'
        "</right></laneSection></lanes>"
    )
    text = (
        f'<OpenDRIVE><header revMajor="1" revMinor="7"/><road id="1" length="{length}" '
        f'junction="-1"><planView>{records}</planView>{lanes}</road></OpenDRIVE>'
    )
    assert _end_points_agree(load_bytes(text.encode(), "t.xodr").root) == 4
