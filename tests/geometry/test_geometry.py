"""Plan-view geometry: closed forms, the clothoid against brute-force integration, drawing
tolerances, broken records, and continuity over the public corpus."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from pathlib import Path

import pytest
from lxml import etree

from tests.conftest import SHARED
from xodrlint.document.load import hardened_parser
from xodrlint.geometry import (
    Arc,
    Line,
    ParamPoly3,
    Poly3,
    Pose,
    Record,
    ReferenceLine,
    Spiral,
    polylines,
    read_record,
    reference_line,
)
from xodrlint.geometry.curves import gauss_legendre

CORPUS = sorted((SHARED / "corpus").glob("*/*.xodr"))


def _close(pose: Pose, expected: tuple[float, float, float], tolerance: float = 1e-9) -> None:
    assert math.isclose(pose.x, expected[0], abs_tol=tolerance), (pose, expected)
    assert math.isclose(pose.y, expected[1], abs_tol=tolerance), (pose, expected)
    assert math.isclose(pose.hdg, expected[2], abs_tol=tolerance), (pose, expected)


def test_gauss_legendre_is_exact_for_polynomials_up_to_degree_15() -> None:
    rule = gauss_legendre(8)
    assert math.isclose(sum(weight for _, weight in rule), 2.0)
    assert math.isclose(sum(weight * x**14 for x, weight in rule), 2 / 15)
    assert abs(sum(weight * x**15 for x, weight in rule)) < 1e-15


def test_line_ends_where_its_heading_points() -> None:
    line = Line(s=0.0, x=3.0, y=-2.0, hdg=math.radians(30), length=10.0)
    _close(line.end, (3 + 10 * math.cos(math.radians(30)), -2 + 5.0, math.radians(30)))


@pytest.mark.parametrize("curvature", [0.1, -0.1])
def test_quarter_arc_ends_on_its_circle(curvature: float) -> None:
    radius = 1 / abs(curvature)
    arc = Arc(0.0, 5.0, 7.0, math.pi / 2, math.pi / 2 * radius, curvature)
    # heading north, turning left (west) or right (east) by a quarter circle
    side = -1.0 if curvature > 0 else 1.0
    _close(
        arc.end,
        (5 + side * radius, 7 + radius, math.pi / 2 + math.copysign(math.pi / 2, curvature)),
    )
    _close(
        arc.pose_at(math.pi * radius / 4),
        (
            5 + side * radius * (1 - math.sqrt(0.5)),
            7 + radius * math.sqrt(0.5),
            math.pi / 2 + curvature * math.pi * radius / 4,
        ),
    )


def test_an_almost_straight_arc_is_a_line() -> None:
    arc = Arc(0.0, 0.0, 0.0, 0.0, 100.0, 1e-15)
    _close(arc.end, (100.0, 5e-12, 1e-13), tolerance=1e-12)


def _brute_force_spiral(spiral: Spiral, ds: float, steps: int = 200_000) -> tuple[float, float]:
    """The midpoint rule with many steps: slow, obvious, accurate to about 1e-8 m here."""
    rate = (spiral.curv_end - spiral.curv_start) / spiral.length
    x, y, h = spiral.x, spiral.y, ds / steps
    for i in range(steps):
        u = (i + 0.5) * h
        heading = spiral.hdg + spiral.curv_start * u + 0.5 * rate * u * u
        x += math.cos(heading) * h
        y += math.sin(heading) * h
    return x, y


@pytest.mark.parametrize(
    ("curv_start", "curv_end", "length"),
    [
        (0.0, 0.02, 100.0),  # the classic transition into a 50 m curve
        (0.0334, 0.0, 2.9),  # the ASAM switch example's spiral
        (-0.05, 0.05, 150.0),  # curvature changes sign: an S
        (0.2, 0.01, 60.0),  # a tight spiral opening out, several radians of turn
    ],
)
def test_spiral_matches_numerical_integration(
    curv_start: float, curv_end: float, length: float
) -> None:
    spiral = Spiral(0.0, 10.0, -4.0, 0.7, length, curv_start, curv_end)
    rate = (curv_end - curv_start) / length
    for ds in (length / 3, length):
        pose = spiral.pose_at(ds)
        x, y = _brute_force_spiral(spiral, ds)
        assert math.hypot(pose.x - x, pose.y - y) < 1e-6, (ds, pose, x, y)
        assert math.isclose(pose.hdg, 0.7 + curv_start * ds + 0.5 * rate * ds * ds, abs_tol=1e-12)


def test_spiral_with_constant_curvature_is_the_arc() -> None:
    spiral = Spiral(0.0, 1.0, 2.0, 0.3, 80.0, 0.03, 0.03)
    arc = Arc(0.0, 1.0, 2.0, 0.3, 80.0, 0.03)
    _close(spiral.end, tuple(arc.end), tolerance=1e-9)  # type: ignore[arg-type]


def test_poly3_is_parametrised_by_arc_length() -> None:
    # v = 0.5 u: a straight line at atan(0.5) whose arc length is u·√1.25
    poly = Poly3(0.0, 0.0, 0.0, 0.0, 20.0, 0.0, 0.5, 0.0, 0.0)
    angle = math.atan(0.5)
    _close(poly.pose_at(10.0), (10 * math.cos(angle), 10 * math.sin(angle), angle))
    # a real curve: the length of the sampled polyline is the distance travelled
    curved = Poly3(0.0, 0.0, 0.0, 0.0, 30.0, 0.0, 0.1, 0.01, -0.0002)
    points = [curved.pose_at(30.0 * i / 3000) for i in range(3001)]
    travelled = sum(math.dist(a[:2], b[:2]) for a, b in itertools.pairwise(points))
    assert math.isclose(travelled, 30.0, abs_tol=1e-4)


@pytest.mark.parametrize("normalized", [True, False])
def test_param_poly3_in_both_p_ranges(normalized: bool) -> None:
    length = 40.0
    scale = length if normalized else 1.0
    # u = p', v = 0.001 p'³ with p' the distance along u: the same curve in both ranges
    curve = ParamPoly3(
        0.0,
        0.0,
        0.0,
        0.0,
        length,
        (0.0, scale, 0.0, 0.0),
        (0.0, 0.0, 0.0, 0.001 * scale**3),
        normalized,
    )
    _close(curve.pose_at(20.0), (20.0, 8.0, math.atan2(3 * 0.001 * 400, 1.0)))


def _geometry(xml: str) -> etree._Element:
    return etree.fromstring(f'<geometry s="0" x="1" y="2" hdg="0.5" length="10">{xml}</geometry>')


@pytest.mark.parametrize(
    ("xml", "reason"),
    [
        ("", "geometry has no line, arc, spiral, poly3 or paramPoly3"),
        # 10 m at a 0.1 m radius: sixteen full circles, a data error rather than a track
        ('<arc curvature="10"/>', "geometry turns 100 rad in 10 m, more than 64"),
        ('<arc curvature="x"/>', "arc lacks a finite number in curvature ('x')"),
        (
            '<paramPoly3 aU="0" bU="1" cU="0" dU="0" aV="0" bV="0" cV="0" dV="0" pRange="meters"/>',
            "paramPoly3 has pRange 'meters', expected 'arcLength' or 'normalized'",
        ),
    ],
)
def test_unusable_records_say_why(xml: str, reason: str) -> None:
    assert read_record(_geometry(xml)) == reason


def test_a_record_without_coordinates_says_which_are_missing() -> None:
    element = etree.fromstring('<geometry s="0" hdg="0" length="5"><line/></geometry>')
    assert read_record(element) == "geometry lacks a finite number in x (missing), y (missing)"


def test_a_broken_record_leaves_the_others_drawn() -> None:
    road = etree.fromstring(
        """<road id="7" length="30"><planView>
        <geometry s="0" x="0" y="0" hdg="0" length="10"><line/></geometry>
        <geometry s="10" x="10" y="0" hdg="0" length="10"><clothoid/></geometry>
        <geometry s="20" x="20" y="0" hdg="0"><line/></geometry>
        </planView></road>"""
    )
    line = reference_line(road)
    assert [record.s for record in line.records] == [0.0, 20.0]
    assert line.records[1].length == 10.0  # the missing length runs to the road's end
    assert [(p.road_id, p.message) for p in line.problems] == [
        ("7", "geometry has no line, arc, spiral, poly3 or paramPoly3")
    ]
    assert line.pose(15.0) is None
    assert line.pose(25.0) == Pose(25.0, 0.0, 0.0)
    assert polylines(line, 0.05) == [[(0.0, 0.0), (10.0, 0.0)], [(20.0, 0.0), (30.0, 0.0)]]


def test_records_written_out_of_order_are_taken_in_order_of_s() -> None:
    road = etree.fromstring(
        """<road id="8" length="20"><planView>
        <geometry s="10" x="10" y="0" hdg="0" length="10"><line/></geometry>
        <geometry s="0" x="0" y="0" hdg="0" length="10"><line/></geometry>
        </planView></road>"""
    )
    line = reference_line(road)
    assert [record.s for record in line.records] == [0.0, 10.0]
    assert line.pose(15.0) == Pose(15.0, 0.0, 0.0)
    assert line.pose(5.0) == Pose(5.0, 0.0, 0.0)


def test_a_record_lacking_its_length_and_more_names_every_number_it_lacks() -> None:
    # the length would fall back to the next record's start, but the record cannot be
    # drawn without its x: every number it lacks is named, the length too (TR014 says it)
    road = etree.fromstring(
        '<road id="9" length="20"><planView><geometry s="0" y="0" hdg="0"><line/></geometry>'
        '<geometry s="10" x="10" y="0" hdg="0" length="10"><line/></geometry>'
        '<geometry y="0" hdg="0"><line/></geometry>'
        "</planView></road>"
    )
    assert [p.message for p in reference_line(road).problems] == [
        "geometry lacks a finite number in x (missing), length (missing)",
        "geometry lacks a finite number in s (missing), x (missing), length (missing)",
    ]


def test_a_road_without_plan_view_is_a_problem_not_an_error() -> None:
    line = reference_line(etree.fromstring('<road id="1" length="5"/>'))
    assert line.records == () and [p.message for p in line.problems] == [
        "road has no planView geometry"
    ]


def _deviation(points: list[tuple[float, float]], target: tuple[float, float]) -> float:
    """The distance from ``target`` to the polyline through ``points``."""
    best = math.inf
    for (ax, ay), (bx, by) in itertools.pairwise(points):
        dx, dy = bx - ax, by - ay
        along = max(
            0.0, min(1.0, ((target[0] - ax) * dx + (target[1] - ay) * dy) / (dx * dx + dy * dy))
        )
        best = min(best, math.hypot(target[0] - ax - along * dx, target[1] - ay - along * dy))
    return best


@pytest.mark.parametrize(
    "record",
    [
        Arc(0.0, 0.0, 0.0, 0.0, 2 * math.pi * 20, 1 / 20),  # a full circle: the chord is 0
        Spiral(0.0, 0.0, 0.0, 0.0, 100.0, 0.0, 0.08),
        ParamPoly3(
            0.0, 0.0, 0.0, 0.0, 1.0, (0.0, 60.0, 0.0, 0.0), (0.0, 0.0, 30.0, -20.0), True
        ),  # an S
    ],
    ids=["circle", "spiral", "s-bend"],
)
def test_sampled_polylines_stay_within_the_tolerance(record: Record) -> None:
    tolerance = 0.05
    line = ReferenceLine((record,))
    [points] = polylines(line, tolerance)
    for i in range(1001):
        pose = record.pose_at(record.length * i / 1000)
        assert _deviation(points, (pose.x, pose.y)) <= tolerance * 1.01
    assert len(points) < 200  # adaptive: nowhere near the 1001 checked points


def test_a_line_is_drawn_with_its_two_ends_and_offsets_follow_the_heading() -> None:
    line = ReferenceLine((Line(0.0, 0.0, 0.0, math.pi / 2, 50.0),))
    assert polylines(line, 0.05) == [[(0.0, 0.0), (pytest.approx(0.0), 50.0)]]
    [left] = polylines(line, 0.05, lateral=lambda s: 2.0)
    assert left == [pytest.approx((-2.0, 0.0)), pytest.approx((-2.0, 50.0))]


@pytest.mark.skipif(not CORPUS, reason="../shared/corpus (public maps) is absent")
@pytest.mark.parametrize("path", CORPUS, ids=lambda p: p.name)
def test_corpus_records_start_at_their_declared_pose_and_report_the_largest_gap(
    path: Path, record_property: Callable[[str, object], None]
) -> None:
    root = etree.parse(str(path), hardened_parser()).getroot()
    largest = 0.0
    for road in root.iterchildren("road"):
        line = reference_line(road)
        assert line.problems == (), [p.message for p in line.problems]
        for record in line.records:
            if not _offset_at_start(record):
                _close(record.pose_at(0.0), (record.x, record.y, record.hdg), tolerance=1e-9)
        for before, after in zip(line.records, line.records[1:], strict=False):
            end = before.end
            largest = max(largest, math.hypot(end.x - after.x, end.y - after.y))
    record_property("largest_gap_m", largest)
    print(f"{path.name}: largest gap between consecutive records {largest:.3g} m")
    if path.name.startswith("ASAM-"):
        # ASAM's examples join their spirals, arcs and lines exactly: our clothoid must too
        assert largest < 1e-6


def _offset_at_start(record: Record) -> bool:
    """Records whose own polynomial moves the start off the declared point (a, aU, aV)."""
    if isinstance(record, Poly3):
        return record.a != 0
    return isinstance(record, ParamPoly3) and (record.u[0] != 0 or record.v[0] != 0)


def test_a_spiral_whose_curvature_changes_faster_than_a_double_holds_is_not_drawn() -> None:
    # finite curvatures over 1e-300 m: the rate overflows and cos() raised (exit 3 in map)
    element = etree.fromstring(
        '<geometry s="0" x="0" y="0" hdg="0" length="1e-300">'
        '<spiral curvStart="0" curvEnd="1e300"/></geometry>'
    )
    assert "changes too fast" in str(read_record(element))
