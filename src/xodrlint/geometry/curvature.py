"""How tightly a track's rail and tram lanes bend: the radius of each lane's centre line
along each plan-view record, for TR013.

The centre of a lane lies ``t(s)`` left of the reference line (``laneOffset``, the inner
lanes' widths and half its own: :func:`~xodrlint.model.lane_profiles.centre_terms`), so
the lane's centre line is the offset curve ``P(s) = C(s) + t(s)·N(s)`` of the reference
curve ``C``, with ``N`` its left normal. With ``v`` the reference curve's speed
``|dC/ds|`` (1 but for ``paramPoly3``, whose parameter runs linearly in s), ``k`` its
curvature (positive turning left) and primes derivatives in s:

    P'  = A·T + B·N,   A = v (1 - k t),  B = t'
    P'' = G·T + D·N,   G = v' (1 - k t) - v (k' t + 2 k t'),  D = v² k (1 - k t) + t''
    curvature = (A D - B G) / (A² + B²)^(3/2)

Where ``t`` is constant this is ``k / (1 - k t)``: monotonic in ``k`` while ``1 - k t > 0``,
so a line, an arc and a spiral are exact (a spiral's tightest point is one of its ends).
Where ``A`` reaches 0 the lane's centre lies at the reference line's centre of curvature
or beyond it: the lane folds back on itself (a cusp, radius 0). Elsewhere (``poly3``,
``paramPoly3``, a ``t`` that varies) the curvature is sampled at most
:data:`MAX_STEP` apart, each end included.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Sequence
from typing import TYPE_CHECKING, Final, NamedTuple

from lxml import etree

from xodrlint.geometry.curves import (
    MAX_COORDINATE,
    Arc,
    Line,
    ParamPoly3,
    Poly3,
    Record,
    Spiral,
    gauss_legendre,
)
from xodrlint.geometry.planview import ReferenceLine
from xodrlint.model import Lane, RailNetwork, Road, number
from xodrlint.model.lane_profiles import S_TOLERANCE, Piecewise, Poly, centre_terms, summed_pieces
from xodrlint.model.network import section_ranges

if TYPE_CHECKING:
    from xodrlint.geometry.evaluable import PlanView

#: The longest step between two samples of a curvature that is not exact (m).
MAX_STEP: Final = 1.0
#: Samples one stretch may take at most: 100 km at a metre apart; a track record is a
#: few hundred metres, and a bound keeps a hostile length from taking forever.
MAX_SAMPLES: Final = 100_000


class Bend(NamedTuple):
    """The tightest point of a lane's centre line on a stretch: its radius (m; 0 where the
    lane folds back, ``inf`` on a straight) and its s."""

    radius: float
    s: float


class LaneBend(NamedTuple):
    """The tightest bend of one rail or tram lane along one record."""

    record: int
    """The record's index in the reference line."""
    lane: Lane
    """The lane, as the road's lane template holds it (its id and type are the road's)."""
    section_start: float
    bend: Bend


class Stretch(NamedTuple):
    """Where a lane's ``t`` is one cubic: ``[start, end]`` (absolute s) and the cubic."""

    start: float
    end: float
    lateral: Poly


class LaneCurvature:
    """The rail and tram lane centres of one file's tracks, worked out once per lane
    layout and road length (a railway repeats a few layouts over thousands of tracks);
    shared through :meth:`~xodrlint.model.RailNetwork.shared`."""

    def __init__(self, network: RailNetwork) -> None:
        del network  # taken as RailNetwork.shared makes it; roads are passed per call
        self._lanes: dict[tuple[Road, float | None], tuple[list[_LaneStretches], float | None]] = {}

    def bends(
        self, road: Road, line: ReferenceLine, tighter_than: float = math.inf
    ) -> Iterator[LaneBend]:
        """Each rail or tram lane of each lane section overlapping each record of
        ``line`` whose centre bends more tightly than ``tighter_than`` there, with its
        tightest bend. Lanes whose centre cannot be computed (a lane described by
        ``border``, an unreadable width or offset) and stretches whose numbers overflow
        are left out."""
        lanes = self._candidates(road, line, tighter_than)
        if lanes:
            yield from _bends(line, lanes, tighter_than)

    def tracks_bending(
        self, tracks: Iterable[tuple[Road, PlanView]], tighter_than: float
    ) -> Iterator[tuple[Road, ReferenceLine, list[LaneBend]]]:
        """Each of ``tracks`` whose plan view can be evaluated and whose rail or tram lanes
        bend more tightly than ``tighter_than`` somewhere, with :meth:`bends`' findings
        (a railway's tracks pass over here without a generator each)."""
        for road, view in tracks:
            line = view.line
            if line is None:
                continue
            lanes = self._candidates(road, line, tighter_than)
            if lanes:
                found = list(_bends(line, lanes, tighter_than))
                if found:
                    yield road, line, found

    def _candidates(
        self, road: Road, line: ReferenceLine, tighter_than: float
    ) -> list[_LaneStretches]:
        """The road's rail and tram lane centres, none when no record can bend any of
        them more tightly than ``tighter_than``."""
        lanes, reach = self._lane_stretches(road, line)
        if lanes and reach is not None:
            # the bound of :func:`_bends` for the whole road at once: a railway's every
            # track passes it
            sharpest = _sharpest(line)
            if sharpest is not None and (sharpest == 0 or 1 / sharpest - reach >= tighter_than):
                return []
        return lanes

    def _lane_stretches(
        self, road: Road, line: ReferenceLine
    ) -> tuple[list[_LaneStretches], float | None]:
        """The road's rail and tram lane centres, and the largest reach of them all
        (``None`` unless every one of them has one)."""
        template = road.lane_template
        end = road.length
        if end is None:  # the last lane section ends where the plan view does
            span = line.s_range
            end = span[1] if span is not None else None
        key = (template, end)
        found = self._lanes.get(key)
        if found is None:  # a few a railway: its tracks share lane layouts and lengths
            lanes = list(_stretches_of(template, end))
            reaches = [lane.reach for lane in lanes if lane.reach is not None]
            reach = max(reaches) if lanes and len(reaches) == len(lanes) else None
            found = self._lanes[key] = (lanes, reach)
        return found


def _bends(
    line: ReferenceLine, lanes: list[_LaneStretches], tighter_than: float
) -> Iterator[LaneBend]:
    """See :meth:`LaneCurvature.bends`."""
    for index, record in enumerate(line.records):
        low, high = record.s, record.s + record.length
        sharpest = record.max_curvature()  # None where not known in closed form
        for lane in lanes:
            # at a constant offset t the radius is 1/k - |t| at least: most records of
            # a railway are judged by this bound alone
            if (
                lane.reach is not None
                and sharpest is not None
                and (sharpest == 0 or 1 / sharpest - lane.reach >= tighter_than)
            ):
                continue
            tightest: Bend | None = None
            for stretch in lane.stretches:
                start, stop = max(low, stretch.start), min(high, stretch.end)
                if stop - start <= S_TOLERANCE:
                    continue
                bend = tightest_bend(record, start, stop, stretch.lateral)
                if bend is not None and (tightest is None or bend.radius < tightest.radius):
                    tightest = bend
            if tightest is not None and tightest.radius < tighter_than:
                yield LaneBend(index, lane.lane, lane.section_start, tightest)


def _sharpest(line: ReferenceLine) -> float | None:
    """The largest curvature bound of ``line``'s records; ``None`` where one has none."""
    sharpest = 0.0
    for record in line.records:
        bound = record.max_curvature()
        if bound is None:
            return None
        if bound > sharpest:  # noqa: PLR1730 (a builtin call per record costs a railway 5 ms)
            sharpest = bound
    return sharpest


class _LaneStretches(NamedTuple):
    lane: Lane
    section_start: float
    stretches: list[Stretch]
    reach: float | None
    """The largest ``|t|`` where ``t`` is one constant on every stretch, else ``None``."""


def _stretches_of(template: Road, end: float | None) -> Iterator[_LaneStretches]:
    for section, start, stop in section_ranges(template.lane_sections, end):
        for lane in section.rail_lanes:
            terms = centre_terms(template, section, start, lane)
            stretches = lateral_stretches(terms, start, stop) if terms is not None else None
            if stretches:
                constant = all(
                    s.lateral.b == 0 and s.lateral.c == 0 and s.lateral.d == 0 for s in stretches
                )
                reach = max(abs(s.lateral.a) for s in stretches) if constant else None
                yield _LaneStretches(lane, start, stretches, reach)


def record_elements(road: Road, line: ReferenceLine) -> list[etree._Element] | None:
    """The ``geometry`` element of each of ``line``'s records, in its order (the records
    of a plan view written out of order are sorted by s, stably); ``None`` when the
    elements are not one a record (a line of a plan view with problems)."""
    elements = [
        element
        for plan_view in road.element.iterchildren("planView")
        for element in plan_view.iterchildren("geometry")
    ]
    if len(elements) != len(line.records):
        return None
    starts = [record.s for record in line.records]
    if [number(element, "s") for element in elements] != starts:
        elements.sort(key=lambda element: number(element, "s") or 0.0)
    return elements


def lateral_stretches(
    terms: Sequence[tuple[float, Piecewise]], start: float, end: float
) -> list[Stretch] | None:
    """``Σ weight·function`` over ``[start, end]`` as one cubic per stretch between the
    functions' piece starts; from where every function is defined (as
    :func:`~xodrlint.model.lane_profiles.extremes` takes it). ``None`` where a function
    has no value."""
    start = max([start, *(function.defined_from for _, function in terms)])
    if end - start <= S_TOLERANCE:
        return []
    pieces = summed_pieces(terms, start, end)
    if pieces is None:
        return None
    return [Stretch(low, high, summed) for low, high, summed in pieces]


def tightest_bend(record: Record, start: float, end: float, lateral: Poly) -> Bend | None:
    """The tightest bend of the curve ``lateral`` (t) left of ``record`` between ``start``
    and ``end`` (absolute s, inside the record); ``None`` where a number overflows."""
    try:
        if not all(map(math.isfinite, lateral)):
            return None
        constant = lateral.b == 0 and lateral.c == 0 and lateral.d == 0
        if constant and isinstance(record, Line | Arc | Spiral):
            return _exact(record, start, end, lateral.a)
        return _sampled(record, start, end, lateral)
    except (ArithmeticError, ValueError):
        return None


def _exact(record: Line | Arc | Spiral, start: float, end: float, t: float) -> Bend | None:
    if abs(t) > MAX_COORDINATE:
        return None
    if isinstance(record, Line):
        return Bend(math.inf, start)
    if isinstance(record, Arc):
        k0 = k1 = record.curvature
    else:
        rate = (record.curv_end - record.curv_start) / record.length
        k0 = record.curv_start + rate * (start - record.s)
        k1 = record.curv_start + rate * (end - record.s)
    folds0, folds1 = 1 - k0 * t <= 0, 1 - k1 * t <= 0
    if folds0 or folds1:
        # 1 - k t is linear in s along a spiral: where it first reaches 0
        if folds0 or k1 == k0:
            return Bend(0.0, start)
        fraction = (1 / t - k0) / (k1 - k0)
        return Bend(0.0, start + min(max(fraction, 0.0), 1.0) * (end - start))
    ends = ((_offset_radius(k0, t), start), (_offset_radius(k1, t), end))
    radius, s = min(ends)
    return Bend(radius, s)


def _offset_radius(k: float, t: float) -> float:
    """The radius of the curve ``t`` left of one of curvature ``k`` (``1 - k t > 0``)."""
    return (1 - k * t) / abs(k) if k != 0 else math.inf


class _Frame(NamedTuple):
    """The reference curve at one s: speed v and its derivative, curvature k and its
    derivative (in s)."""

    speed: float
    speed_rate: float
    curvature: float
    curvature_rate: float


def _sampled(record: Record, start: float, end: float, lateral: Poly) -> Bend | None:
    steps = min(MAX_SAMPLES, max(1, math.ceil((end - start) / MAX_STEP)))
    positions = [start - record.s + (end - start) * j / steps for j in range(steps + 1)]
    tightest = -1.0
    where = start
    for ds, frame in zip(positions, _frames(record, positions), strict=True):
        if frame is None:
            return None
        s = record.s + ds
        x = s - lateral.base
        t = lateral.a + x * (lateral.b + x * (lateral.c + x * lateral.d))
        t1 = lateral.b + x * (2 * lateral.c + 3 * lateral.d * x)
        t2 = 2 * lateral.c + 6 * lateral.d * x
        if abs(t) > MAX_COORDINATE:
            return None
        speed, speed_rate, k, k_rate = frame
        along = 1 - k * t
        alpha = speed * along
        if alpha <= 0:
            return Bend(0.0, s)  # at or beyond the centre of curvature: folded
        gamma = speed_rate * along - speed * (k_rate * t + 2 * k * t1)
        delta = speed * speed * k * along + t2
        norm = alpha * alpha + t1 * t1
        curvature = abs(alpha * delta - t1 * gamma) / (norm * math.sqrt(norm))
        if not math.isfinite(curvature):
            return None
        if curvature > tightest:
            tightest, where = curvature, s
    return Bend(1 / tightest if tightest > 0 else math.inf, where)


def _frames(record: Record, positions: Sequence[float]) -> Iterator[_Frame | None]:
    """The reference curve's frame at each of ``positions`` (ds from the record's start,
    ascending)."""
    if isinstance(record, Line):
        yield from (_Frame(1.0, 0.0, 0.0, 0.0) for _ in positions)
    elif isinstance(record, Arc):
        yield from (_Frame(1.0, 0.0, record.curvature, 0.0) for _ in positions)
    elif isinstance(record, Spiral):
        rate = (record.curv_end - record.curv_start) / record.length
        yield from (_Frame(1.0, 0.0, record.curv_start + rate * ds, rate) for ds in positions)
    elif isinstance(record, ParamPoly3):
        yield from (_param_poly3_frame(record, ds) for ds in positions)
    elif isinstance(record, Poly3):
        yield from _poly3_frames(record, positions)
    else:  # a record type of the future: nothing known of it
        yield from (None for _ in positions)


def _param_poly3_frame(record: ParamPoly3, ds: float) -> _Frame | None:
    rate = 1 / record.length if record.normalized else 1.0  # dp/ds
    p = ds * rate
    (_, bu, cu, du), (_, bv, cv, dv) = record.u, record.v
    u1, v1 = bu + p * (2 * cu + 3 * du * p), bv + p * (2 * cv + 3 * dv * p)
    u2, v2 = 2 * cu + 6 * du * p, 2 * cv + 6 * dv * p
    u3, v3 = 6 * du, 6 * dv
    q = u1 * u1 + v1 * v1
    if not q > 0:  # the reference curve stands still: no direction to bend from
        return None
    root = math.sqrt(q)
    w = u1 * v2 - v1 * u2
    dot = u1 * u2 + v1 * v2
    curvature = w / (q * root)
    curvature_rate = ((u1 * v3 - v1 * u3) / (q * root) - 3 * w * dot / (q * q * root)) * rate
    return _Frame(root * rate, dot / root * rate * rate, curvature, curvature_rate)


def _poly3_frames(record: Poly3, positions: Sequence[float]) -> Iterator[_Frame | None]:
    """A poly3 is parametrised by its u; each position's u is found from the previous
    one by Newton's method on the arc length between them."""
    u = record.local(positions[0]).x if positions else 0.0
    previous = positions[0] if positions else 0.0
    for ds in positions:
        u = _advance(record, u, ds - previous)
        previous = ds
        slope = record.slope(u)
        bend = 2 * record.c + 6 * record.d * u
        speed2 = 1 + slope * slope
        speed = math.sqrt(speed2)
        curvature = bend / (speed2 * speed)
        # dk/du, then dk/ds = dk/du / (ds/du)
        rate = (6 * record.d * speed2 - 3 * slope * bend * bend) / (speed2 * speed2 * speed)
        yield _Frame(1.0, 0.0, curvature, rate / speed)


def _advance(record: Poly3, u: float, length: float) -> float:
    """The u that lies ``length`` further along the poly3 than ``u``."""
    if length == 0:
        return u
    rule = gauss_legendre(8)
    target = u + length / math.hypot(1.0, record.slope(u))
    for _ in range(50):
        half = (target - u) / 2
        middle = u + half
        arc = half * sum(w * math.hypot(1.0, record.slope(middle + half * x)) for x, w in rule)
        step = (arc - length) / math.hypot(1.0, record.slope(target))
        target -= step
        if abs(step) < 1e-12 * max(1.0, abs(target)):
            break
    return target
