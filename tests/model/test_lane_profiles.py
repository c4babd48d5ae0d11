"""Piecewise cubics: exact extremes, pieces, and the lane centre built from them."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from xodrlint.model import build_network
from xodrlint.model.lane_profiles import (
    Piecewise,
    Poly,
    centre_terms,
    extremes,
    lane_offset,
    lane_width,
)


def _sampled(terms: list[tuple[float, Piecewise]], start: float, end: float) -> list[float]:
    values = []
    for i in range(2001):
        s = start + (end - start) * i / 2000
        total = 0.0
        for weight, fn in terms:
            piece = fn.piece_at(s)
            assert piece is not None
            total += weight * piece.at(s)
        values.append(total)
    return values


def test_interior_minimum_is_found_exactly() -> None:
    # 1.5 - 0.02 x + 0.0002 x²: minimum 1.0 at x = 50, both ends 1.5 or more
    width = Piecewise((Poly(0.0, 1.5, -0.02, 0.0002, 0.0),))
    found = extremes([(1.0, width)], 0.0, 100.0)
    assert found is not None
    assert math.isclose(found.low, 1.0) and math.isclose(found.s_low, 50.0)
    assert math.isclose(found.high, 1.5)


def test_cubic_with_two_stationary_points() -> None:
    # x³ - 3x on [-2, 2] shifted to start at s=10: max 2 at x=-1 and x=2, min -2 at x=1, x=-2
    poly = Poly(12.0, 0.0, -3.0, 0.0, 1.0)
    found = extremes([(1.0, Piecewise((Poly(10.0, *_coefficients(poly, 10.0)),)))], 10.0, 14.0)
    assert found is not None
    assert math.isclose(found.low, -2.0) and math.isclose(found.high, 2.0)


def _coefficients(poly: Poly, base: float) -> tuple[float, float, float, float]:
    shifted = poly.shifted(base)
    return shifted.a, shifted.b, shifted.c, shifted.d


def test_value_just_before_a_new_piece_counts() -> None:
    # the first piece falls to 1.0 at s=40, where a new piece restarts at 2.0
    width = Piecewise((Poly(0.0, 2.0, -0.025, 0.0, 0.0), Poly(40.0, 2.0, 0.0, 0.0, 0.0)))
    found = extremes([(1.0, width)], 0.0, 100.0)
    assert found is not None
    assert math.isclose(found.low, 1.0) and math.isclose(found.s_low, 40.0)


def test_a_width_is_judged_from_its_first_entry_on() -> None:
    # 1.0 + 0.1 (s - 5): nothing is known before s=5, so the minimum is 1.0 there
    width = Piecewise((Poly(5.0, 1.0, 0.1, 0.0, 0.0),))
    found = extremes([(1.0, width)], 0.0, 10.0)
    assert found is not None and (found.low, found.s_low) == (1.0, 5.0)
    assert extremes([(1.0, width)], 0.0, 4.0) is None


def test_offset_is_zero_before_its_first_entry() -> None:
    offset = Piecewise((Poly(50.0, 1.0, 0.0, 0.0, 0.0),), zero_before=True)
    found = extremes([(1.0, offset)], 0.0, 100.0)
    assert found is not None and (found.low, found.high) == (0.0, 1.0)


def test_overflow_gives_no_result_instead_of_raising() -> None:
    width = Piecewise((Poly(0.0, 1e308, 1e308, 1e308, 1e308),))
    assert extremes([(1.0, width)], 0.0, 1e10) is None


finite = st.floats(min_value=-10, max_value=10, allow_nan=False, allow_infinity=False)


@settings(max_examples=200, deadline=None)
@given(
    first=st.tuples(finite, finite, finite, finite),
    second=st.tuples(finite, finite, finite, finite),
    split=st.floats(min_value=0.1, max_value=9.9),
    offset=st.tuples(finite, finite, finite, finite),
)
def test_extremes_bound_every_sample(
    first: tuple[float, float, float, float],
    second: tuple[float, float, float, float],
    split: float,
    offset: tuple[float, float, float, float],
) -> None:
    width = Piecewise((Poly(0.0, *first), Poly(split, *second)))
    lane_off = Piecewise((Poly(0.0, *offset),), zero_before=True)
    terms = [(1.0, lane_off), (-0.5, width)]
    found = extremes(terms, 0.0, 10.0)
    assert found is not None
    samples = _sampled(terms, 0.0, 10.0)
    slack = 1e-9 * (1 + max(abs(v) for v in samples))
    assert found.low <= min(samples) + slack
    assert found.high >= max(samples) - slack
    # and the extremes are attained values, not loose bounds
    for value, s in ((found.low, found.s_low), (found.high, found.s_high)):
        assert 0.0 <= s <= 10.0
        assert math.isclose(
            value, _sum_at(terms, s, prefer_left=True), abs_tol=1e-6
        ) or math.isclose(value, _sum_at(terms, s, prefer_left=False), abs_tol=1e-6)


def _sum_at(terms: list[tuple[float, Piecewise]], s: float, *, prefer_left: bool) -> float:
    total = 0.0
    for weight, fn in terms:
        pieces = [p for p in fn.pieces if p.base <= s + 1e-6] if fn.pieces else []
        if prefer_left:
            pieces = [p for p in fn.pieces if p.base < s - 1e-6] or pieces
        piece = pieces[-1] if pieces else Poly(0.0, 0.0, 0.0, 0.0, 0.0)
        total += weight * piece.at(s)
    return total


ROAD = """<OpenDRIVE><header revMajor="1" revMinor="7"/>
<road id="1" length="100" junction="-1"><lanes>
<laneOffset s="0" a="0.5" b="0" c="0" d="0"/>
<laneSection s="0"><center><lane id="0" type="none"/></center><right>
<lane id="-1" type="border"><width sOffset="0" a="0.4" b="0" c="0" d="0"/></lane>
<lane id="-2" type="rail"><width sOffset="0" a="1.6" b="0" c="0" d="0"/></lane>
<lane id="-3" type="none"><border sOffset="0" a="1" b="0" c="0" d="0"/></lane>
</right></laneSection></lanes></road></OpenDRIVE>"""


def test_centre_of_an_outer_right_lane() -> None:
    road = build_network(etree.fromstring(ROAD)).roads[0]
    section = road.lane_sections[0]
    rail = section.rail_lanes[0]
    terms = centre_terms(road, section, 0.0, rail)
    assert terms is not None
    found = extremes(terms, 0.0, 100.0)
    assert found is not None
    # 0.5 - (0.4 + 1.6 / 2) = -0.7 all along
    assert math.isclose(found.low, -0.7) and math.isclose(found.high, -0.7)


def test_lane_with_border_only_has_no_width() -> None:
    road = build_network(etree.fromstring(ROAD)).roads[0]
    outer = road.lane_sections[0].lanes[-1]
    assert lane_width(outer, 0.0) is None
    assert lane_offset(road) is not None


def test_unreadable_offset_entry_leaves_the_offset_unknown() -> None:
    text = ROAD.replace('<laneOffset s="0" a="0.5"', '<laneOffset s="0" a="x"')
    road = build_network(etree.fromstring(text)).roads[0]
    assert lane_offset(road) is None
    assert (
        centre_terms(road, road.lane_sections[0], 0.0, road.lane_sections[0].rail_lanes[0]) is None
    )
