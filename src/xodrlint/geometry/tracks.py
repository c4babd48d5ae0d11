"""Track points and directions of travel: where a railway's tracks are, for the rules that
check that switches and linked tracks physically fit together (SW011, SW012, TR001,
TR002).

- The **track point** of a road at s is the centre line of the road's rail or tram lane
  at s when the lane section there holds exactly one such lane (t = ``laneOffset(s)``
  plus the lane's inner edge and half its width, the widths as the cubics they are);
  otherwise the reference line (t = 0). At a joint, each pair of joined lanes is
  judged at the two lanes' own centres (:meth:`TrackGeometry.lane_point`).
- The **direction of travel** for ``dir`` is the reference line's heading at s for
  ``+``, that heading plus pi for ``-``. Angles are compared on the circle.

Geometry is evaluated only where a rule asks (a switch point, a road's end): a binary
search for the record and one evaluation, never a walk along a road. A road's plan view
is read and judged the first time it is asked for, once per file (:class:`TrackGeometry`
is shared through :meth:`~xodrlint.model.RailNetwork.shared`). A road whose plan view
cannot be evaluated (:mod:`~xodrlint.geometry.evaluable`: no geometry, an unreadable or
zero-length record, a start or heading no map holds, numbers that overflow) has no track
points: the rules stay silent on it, and TR014 says why.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from typing import Final, NamedTuple

from xodrlint.geometry.curves import MAX_COORDINATE
from xodrlint.geometry.evaluable import PlanView, judge_plan_view
from xodrlint.geometry.planview import COVERS, ReferenceLine
from xodrlint.model import Cubic, Lane, LaneSection, RailNetwork, Road
from xodrlint.model.lane_profiles import S_TOLERANCE, centre_at


class TrackPoint(NamedTuple):
    """A point of a track, and the reference line's heading there (rad)."""

    x: float
    y: float
    heading: float

    def distance_to(self, other: TrackPoint) -> float:
        return math.hypot(self.x - other.x, self.y - other.y)

    def direction(self, dir: str) -> float:
        """The direction of travel along the road for ``dir`` (``+`` or ``-``)."""
        return self.heading + (math.pi if dir == "-" else 0.0)


#: Angles equal within this are equal: a heading computed from a cubic carries rounding.
_ANGLE_SLACK: Final = 1e-9


def angle_between(first: float, second: float) -> float:
    """The smallest difference of two directions on the circle, in radians (0 to pi)."""
    difference = math.remainder(first - second, math.tau)
    return abs(difference)


def turn_beyond(first: float, second: float, limit_degrees: float) -> float | None:
    """The angle between two directions (radians) when it exceeds ``limit_degrees``."""
    angle = abs(math.remainder(first - second, math.tau))  # angle_between, called inline:
    # a railway's every joint and record boundary is judged by it
    return angle if angle > math.radians(limit_degrees) + _ANGLE_SLACK else None


#: :meth:`TrackGeometry.nearest` samples a plan view record at most this many times, and
#: narrows the best sample's neighbourhood down in this many steps (a third each).
_SAMPLES: Final = 200
_NARROWING: Final = 50


class TrackGeometry:
    """The track points of one file's roads, each road's plan view read once."""

    def __init__(self, network: RailNetwork) -> None:
        del network  # taken as RailNetwork.shared makes it; roads are passed per call
        self._plan_views: dict[Road, PlanView] = {}
        # per lane layout (a template road): the track's t where it is the same all along
        self._constant_lateral: dict[Road, float | None] = {}
        # a switch's point is asked for by the map as well as the rules
        self._points: dict[tuple[Road, float], TrackPoint | None] = {}
        # per lane of a lane layout's section: its centre's t where it is the same all
        # along the section (a railway's joints ask for thousands, of a few layouts)
        self._constant_centres: dict[int, float | None] = {}

    def point(self, road: Road, s: float) -> TrackPoint | None:
        """The track point of ``road`` at ``s``; ``None`` where it cannot be evaluated."""
        key = (road, s)
        try:
            return self._points[key]
        except KeyError:
            found = self._points[key] = self._evaluate(road, s)
            return found

    def lane_point(
        self, road: Road, section: LaneSection, lane: Lane, s: float
    ) -> TrackPoint | None:
        """The centre of ``lane`` at ``s``, whatever other rail lanes its section holds
        (a joint judges each pair of joined lanes at their own centres); ``section`` and
        ``lane`` are read from ``road``'s lane template. ``None`` where the lane's centre
        or the plan view cannot be evaluated."""
        constant = self._constant_centre(road, section, lane)
        if constant is not None and section.s is not None and s >= section.s - S_TOLERANCE:
            return self._evaluate(road, s, None, constant)
        return self._evaluate(road, s, lambda: _lane_centre(road, section, lane, s))

    def lane_end_point(
        self, road: Road, section: LaneSection, lane: Lane, end: str
    ) -> TrackPoint | None:
        """:meth:`lane_point` at ``road``'s ``start`` (s=0) or ``end`` (s=``@length``).

        A railway's every joint asks for two: where the lane's centre is constant and the
        road's end is its plan view's first or last record's own, the point is that
        record's end pose (worked out when the plan view was judged) moved sideways,
        found here without looking for the record. The same numbers as
        :meth:`lane_point`'s: anything else is left to it."""
        view = self._plan_views.get(road)
        constant = self._constant_centre(road, section, lane)
        if view is None or view.line is None or constant is None or section.s is None:
            return self.lane_point(road, section, lane, _end_s(road, end))
        line = view.line
        records = line.records
        if end == "start":
            s, first = 0.0, records[0]
            # record_at(0) is the first record, at its start
            at_end = 0.0 <= first.s <= COVERS and (len(records) == 1 or line.starts[1] > 0.0)
            pose = view.ends[0][0] if at_end else None
        else:
            s, last = _end_s(road, end), records[-1]
            # record_at(s) is the last record, at its end
            at_end = s - last.s >= last.length and s <= last.s + last.length + COVERS
            pose = view.ends[-1][1] if at_end else None
        if pose is None or s < section.s - S_TOLERANCE:
            return self.lane_point(road, section, lane, s)
        x, y = pose.offset(constant)
        if not (abs(x) < MAX_COORDINATE and abs(y) < MAX_COORDINATE):
            return None
        return TrackPoint(x, y, pose.hdg)

    def _constant_centre(self, road: Road, section: LaneSection, lane: Lane) -> float | None:
        # by the template lane itself: each is its own object for as long as the file
        key = id(lane)
        try:
            return self._constant_centres[key]
        except KeyError:
            found = self._constant_centres[key] = _constant_centre(road, section, lane)
            return found

    def _evaluate(
        self,
        road: Road,
        s: float,
        lateral_of: Callable[[], float | None] | None = None,
        constant: float | None = None,
    ) -> TrackPoint | None:
        """The point ``constant`` (else ``lateral_of()``, else the track's t) metres left
        of ``road``'s reference line at ``s``; the lateral is computed only for a point
        on the plan view."""
        try:
            view = self._plan_views[road]
        except KeyError:
            view = self.plan_view(road)
        line = view.line
        if line is None or not math.isfinite(s):
            return None
        record = line.record_at(s)
        if record is None:
            return None
        try:
            lateral = constant
            if lateral is None:
                lateral = self._lateral(road, s) if lateral_of is None else lateral_of()
                if lateral is None:
                    return None
            ds = min(max(s - record.s, 0.0), record.length)
            # a road's two ends are where joints are judged: their poses were worked out
            # when the plan view was judged (the same computation)
            if ds == record.length and record is line.records[-1]:
                pose = view.ends[-1][1]
            elif ds == 0.0 and record is line.records[0]:
                pose = view.ends[0][0]
            else:
                pose = record.pose_at(ds)
            x, y = pose.offset(lateral)
        except (ArithmeticError, ValueError):
            # a record whose numbers are each finite can still overflow in between (a
            # spiral's curvature rate over a length of 1e-300): no place on any map
            return None
        # also false for nan and inf: a point no map holds says nothing about a railway
        if not (abs(x) < MAX_COORDINATE and abs(y) < MAX_COORDINATE and math.isfinite(pose.hdg)):
            return None
        return TrackPoint(x, y, pose.hdg)

    def nearest(self, road: Road, target: TrackPoint) -> tuple[float, TrackPoint] | None:
        """The s of ``road``'s track whose point is nearest ``target``, and that point;
        ``None`` where the track cannot be evaluated. Each record of the plan view is
        sampled (every half metre, at most 200 points a record), then the best sample's
        neighbourhood is narrowed down: a bounded number of points whatever the road's
        length says, and none of them kept in the cache. Rule API 1.3."""
        line = self.plan_view(road).line
        end = road.length if road.length is not None else math.inf
        if line is None:
            return None

        def distance(s: float) -> float:
            found = self._evaluate(road, s)
            return math.inf if found is None else found.distance_to(target)

        samples: list[float] = []
        for record in line.records:
            stop = min(record.s + record.length, end)
            if stop < record.s:
                continue
            count = min(max(1, math.ceil((stop - record.s) / 0.5)), _SAMPLES)
            samples += [record.s + (stop - record.s) * i / count for i in range(count + 1)]
        if not samples:
            return None
        distances = [distance(s) for s in samples]
        best = min(range(len(samples)), key=distances.__getitem__)
        if distances[best] == math.inf:
            return None
        low, high = samples[max(best - 1, 0)], samples[min(best + 1, len(samples) - 1)]
        for _ in range(_NARROWING):
            first, second = low + (high - low) / 3, high - (high - low) / 3
            if distance(first) <= distance(second):
                high = second
            else:
                low = first
        s = (low + high) / 2
        point = self._evaluate(road, s)
        return None if point is None else (s, point)

    def _lateral(self, road: Road, s: float) -> float | None:
        """The track's t at ``s``: the single rail/tram lane's centre, else the reference
        line. ``None`` when that lane's centre cannot be computed (a lane described by
        ``border``, an unreadable ``laneOffset`` or ``width``)."""
        # the lanes are the same, text for text, as those of the template road: read once
        template = road.lane_template
        try:
            constant = self._constant_lateral[template]
        except KeyError:
            constant = self._constant_lateral[template] = _constant_lateral(template)
        sections = template.lane_sections
        if constant is not None and s >= (sections[0].s or 0.0) - S_TOLERANCE:
            return constant
        return _lateral_at(sections, template, s)

    def plan_view(self, road: Road) -> PlanView:
        """The road's plan view, judged: its reference line and record ends when every
        record can be evaluated, else each record (or the road) that cannot be, and why."""
        try:
            return self._plan_views[road]
        except KeyError:
            found = self._plan_views[road] = judge_plan_view(road.element)
            return found

    def plan_views(self, roads: Iterable[Road]) -> list[tuple[Road, PlanView]]:
        """Each of ``roads`` with its plan view, judged (see :meth:`plan_view`)."""
        known = self._plan_views
        return [
            (road, view if (view := known.get(road)) is not None else self.plan_view(road))
            for road in roads
        ]

    def reference_line(self, road: Road) -> ReferenceLine | None:
        """The road's reference line when every record of it can be evaluated (the map
        draws a record whose own length is unreadable up to the next one; a rule judges
        nothing it would have to guess)."""
        return self.plan_view(road).line


def _end_s(road: Road, end: str) -> float:
    """The s of ``road``'s ``start`` or ``end`` (nan where its length is unreadable)."""
    if end == "start":
        return 0.0
    return road.length if road.length is not None else math.nan


def _constant_centre(road: Road, section: LaneSection, lane: Lane) -> float | None:
    """The t of ``lane``'s centre where the road's offset and the widths out to the lane
    are each one constant entry from the section's start: the same at every s of the
    section. ``None`` for any other layout (evaluated where asked instead)."""
    template = road.lane_template
    lanes = template.lanes
    start = section.s
    if start is None or lane.id is None or lane.id == 0 or not lanes.offsets_complete:
        return None
    if len(lanes.offsets) > 1 or not all(_constant_from(c, start, 0.0) for c in lanes.offsets):
        return None
    depth = abs(lane.id)
    inner: dict[int, Lane] = {}
    for other in section.lanes:
        if other.side == lane.side and other.id is not None and 0 < abs(other.id) <= depth:
            inner.setdefault(other.id, other)
    if len(inner) != depth or not all(
        other.widths_complete
        and len(other.widths) == 1
        and _constant_from(other.widths[0], 0.0, 0.0)
        for other in inner.values()
    ):
        return None
    return _lane_centre(road, section, lane, start)


def _lane_centre(road: Road, section: LaneSection, lane: Lane, s: float) -> float | None:
    if section.s is None:
        return None  # where the section starts, and so its widths, is unknown
    value = centre_at(road.lane_template, section, section.s, lane, s)
    return value if value is not None and math.isfinite(value) else None


def _lateral_at(sections: Sequence[LaneSection], template: Road, s: float) -> float | None:
    if not sections:
        return 0.0  # a road without lanes: its reference line
    section = _section_at(sections, s)
    if section is None:
        return None  # an unreadable section start, or s before the first section
    rails = section.rail_lanes
    if len(rails) != 1:
        return 0.0
    value = centre_at(template, section, section.s or 0.0, rails[0], s)
    return value if value is not None and math.isfinite(value) else None


def _constant_lateral(template: Road) -> float | None:
    """The track's t of a road with one lane section whose offset and widths (up to its
    rail lane) are each one constant entry from the section's start: the same at every s
    from there on (nearly every track). ``None`` for any other layout."""
    lanes = template.lanes
    sections = lanes.sections
    start = sections[0].s if len(sections) == 1 else None
    if start is None or not lanes.offsets_complete:
        return None
    section = sections[0]
    if len(lanes.offsets) > 1 or not all(_constant_from(c, start, 0.0) for c in lanes.offsets):
        return None
    rails = section.rail_lanes
    if len(rails) == 1:
        rail = rails[0]
        depth = abs(rail.id) if rail.id is not None else 0
        inner = [
            lane
            for lane in section.lanes
            if lane.side == rail.side and lane.id is not None and 0 < abs(lane.id) <= depth
        ]
        if len(inner) != depth or not all(
            lane.widths_complete
            and len(lane.widths) == 1
            and _constant_from(lane.widths[0], 0.0, 0.0)
            for lane in inner
        ):
            return None
    return _lateral_at(sections, template, start)


def _constant_from(cubic: Cubic, start: float, origin: float) -> bool:
    """Whether ``cubic`` is one constant that holds from ``start`` on (its own start,
    relative to ``origin``, at or before it)."""
    return cubic.b == 0 and cubic.c == 0 and cubic.d == 0 and cubic.start + origin <= start


def _section_at(sections: Sequence[LaneSection], s: float) -> LaneSection | None:
    """The lane section that holds ``s`` (at a boundary, the one that starts there), read
    from the sections' starts alone; ``None`` when a start is unreadable or ``s`` lies
    before the first."""
    found = None
    for section in sections:
        start = section.s
        if start is None:
            return None
        if start <= s + S_TOLERANCE:
            found = section
    return found
