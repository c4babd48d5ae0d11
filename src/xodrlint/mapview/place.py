"""Where things are on the plan view: points at (road, s, lateral offset), the centre line
of rail lanes, and the position of any element a finding can be about."""

from __future__ import annotations

from collections.abc import Callable
from typing import Final

from lxml import etree

from xodrlint.geometry import Pose, ReferenceLine, reference_line
from xodrlint.geometry.sampling import drawable
from xodrlint.model import Lane, LaneSection, RailNetwork, Road, Segment, number
from xodrlint.model.lane_profiles import Piecewise, centre_terms, lane_offset, lateral_value

Point = tuple[float, float]
Terms = list[tuple[float, Piecewise]]

#: How far a platform bar is drawn beside its track's centre line, in metres.
PLATFORM_DISTANCE: Final = 3.0


class Placer:
    """Positions on one network's roads; reference lines are computed once per road."""

    def __init__(self, network: RailNetwork) -> None:
        self.network = network
        self._lines: dict[str, ReferenceLine] = {}
        self._road_of: dict[etree._Element, Road] = {road.element: road for road in network.roads}

    def line(self, road: Road) -> ReferenceLine:
        key = road.id if road.id is not None else f"#{id(road.element)}"
        found = self._lines.get(key)
        if found is None:
            found = self._lines[key] = reference_line(road.element)
        return found

    def road(self, road_id: str | None) -> Road | None:
        return self.network.road_by_id.get(road_id) if road_id is not None else None

    def pose(self, road: Road, s: float) -> Pose | None:
        return self.line(road).pose(_clamp(s, road.length))

    def point(self, road: Road, s: float, lateral: float = 0.0) -> Point | None:
        """The point ``lateral`` metres left of ``road``'s reference line at ``s``; ``None``
        where no record covers ``s`` or the numbers run past any map."""
        pose = self.pose(road, s)
        point = pose.offset(lateral) if pose is not None else None
        return point if point is not None and drawable(point) else None

    def track_lateral(self, road: Road, s: float) -> float:
        """The lateral offset of ``road``'s first rail lane at ``s``; else its lane offset."""
        for section, start, end in road.section_ranges():
            if start <= s <= end:
                for lane in section.rail_lanes:
                    terms = centre_terms(road, section, start, lane)
                    if terms is not None:
                        return lateral_value(terms, s)
        offset = lane_offset(road)
        return lateral_value([(1.0, offset)], s) if offset is not None else 0.0

    def track_point(self, road_id: str | None, s: float | None) -> Point | None:
        road = self.road(road_id)
        if road is None or s is None:
            return None
        s = _clamp(s, road.length)
        return self.point(road, s, self.track_lateral(road, s))

    def segment_side(self, segment: Segment) -> Callable[[float], float] | None:
        """The lateral offset of a platform bar along the segment's road."""
        road = self.road(segment.road_id)
        if road is None:
            return None
        side = {"left": 1.0, "right": -1.0}.get(segment.side or "", 0.0)
        return lambda s: self.track_lateral(road, s) + side * PLATFORM_DISTANCE

    def segment_middle(self, segment: Segment) -> Point | None:
        road, lateral = self.road(segment.road_id), self.segment_side(segment)
        ends = [value for value in (segment.s_start, segment.s_end) if value is not None]
        if road is None or lateral is None or not ends:
            return None
        middle = _clamp(sum(ends) / len(ends), road.length)
        return self.point(road, middle, lateral(middle))

    def road_of(self, element: etree._Element) -> Road | None:
        return self._road_of.get(element)

    def road_middle(self, road: Road) -> Point | None:
        span = self.line(road).s_range
        if span is None:
            return None
        return self.point(road, 0.5 * (span[0] + span[1]))

    def road_end(self, road: Road) -> Point | None:
        """Where the road's plan view ends (which may not be where its length says)."""
        line = self.line(road)
        span = line.s_range
        pose = line.pose(span[1]) if span is not None else None
        point = (pose.x, pose.y) if pose is not None else None
        return point if point is not None and drawable(point) else None

    def lane_start(self, road: Road, lane_element: etree._Element) -> Point | None:
        """A lane's centre at the start of its lane section (the section's start if the
        centre cannot be computed)."""
        return self.lane_end(road, lane_element, "start")

    def lane_end(self, road: Road, lane_element: etree._Element, end: str) -> Point | None:
        """A lane's centre at the ``start`` or ``end`` of its lane section (a lane link is
        drawn where it joins); the section's start if the centre cannot be computed."""
        for section, start, stop in road.section_ranges():
            if lane_element not in section.element.iter("lane"):
                continue
            lane = next((lane for lane in section.lanes if lane.element is lane_element), None)
            terms = _lane_terms(road, section, start, lane)
            s = start if end == "start" else stop
            if terms is not None:
                return self.point(road, s, lateral_value(terms, s))
            return self.section_start(road, section)
        return None

    def section_start(self, road: Road, section: LaneSection) -> Point | None:
        if section.s is None:
            return None
        offset = lane_offset(road)
        lateral = lateral_value([(1.0, offset)], section.s) if offset is not None else 0.0
        return self.point(road, section.s, lateral)


def _lane_terms(road: Road, section: LaneSection, start: float, lane: Lane | None) -> Terms | None:
    if lane is None or not lane.id:
        return None
    return centre_terms(road, section, start, lane)


def _clamp(s: float, length: float | None) -> float:
    upper = length if length is not None else s
    return min(max(s, 0.0), max(upper, 0.0))


def geometry_start(element: etree._Element) -> Point | None:
    x, y = number(element, "x"), number(element, "y")
    return (x, y) if x is not None and y is not None and drawable((x, y)) else None
