"""Where a finding goes on the map: the element its XPath names, placed by what it is (a
switch at its point, a segment at its middle, a lane or lane section at its start, a
geometry record at its start, an elevation or superelevation entry at its road's track
point at its s, a road link at the road end it joins, a lane link at the end of its lane,
a junction's lane link where it enters its connecting road, a road at its middle, or at
its plan view's end for a finding about its length), or else by its nearest ancestor
that has a place. Switch tracks and road links are placed at the track points the
track-geometry rules name in their messages."""

from __future__ import annotations

from collections.abc import Callable
from typing import Final

from lxml import etree

from xodrlint.document.load import Document
from xodrlint.findings import Finding
from xodrlint.geometry.tracks import TrackGeometry
from xodrlint.mapview.place import Placer, Point, geometry_start
from xodrlint.model import RailNetwork, Road, Segment, Switch, number

#: Rules whose finding on a road is about where the road ends (its length against its
#: plan view's): drawn at the plan view's end, the place their message names.
AT_ROAD_END: Final = frozenset({"TR009"})


class Locator:
    """Finds the element of a finding's XPath and the point it is drawn at."""

    def __init__(self, doc: Document, network: RailNetwork, placer: Placer) -> None:
        self._doc = doc
        self._placer = placer
        self._tracks = network.shared(TrackGeometry)
        self._switches: dict[etree._Element, Switch] = {sw.element: sw for sw in network.switches}
        self._segments: dict[etree._Element, Segment] = {
            segment.element: segment for segment in network.segments
        }
        self._by_tag: dict[str, Callable[[etree._Element], Point | None]] = {
            "switch": self._switch,
            "mainTrack": self._track,
            "sideTrack": self._track,
            "segment": self._segment,
            "platform": self._first_child_placed,
            "station": self._first_child_placed,
            "lane": self._lane,
            "laneSection": self._lane_section,
            "geometry": geometry_start,
            "elevation": self._profile_entry,
            "superelevation": self._profile_entry,
            "predecessor": self._link,
            "successor": self._link,
            "laneLink": self._junction_lane_link,
            "road": self._road,
        }

    def element(self, xpath: str, path: str | None = None) -> etree._Element | None:
        """The element ``xpath`` names in the file ``path`` (the map's own, or one it
        includes)."""
        found_fast = self._doc.element_at(xpath, path)  # the XPaths findings carry
        if found_fast is not None or self._doc.tree is None:
            return found_fast
        if self._doc.part_named(path) is not None:
            return None  # an included file's XPath says nothing about the whole tree
        try:
            found = self._doc.tree.xpath(xpath)
        except etree.XPathError:
            return None
        if isinstance(found, list) and found and isinstance(found[0], etree._Element):
            return found[0]
        return None

    def place(self, finding: Finding) -> Point | None:
        element = self.element(finding.xpath, finding.path)
        if element is None:
            return None
        if finding.code in AT_ROAD_END and element.tag == "road":
            road = self._placer.road_of(element)
            end = self._placer.road_end(road) if road is not None else None
            if end is not None:
                return end
        return self.position(element)

    def position(self, element: etree._Element) -> Point | None:
        node: etree._Element | None = element
        while node is not None:
            own = self._by_tag.get(str(node.tag))
            point = own(node) if own is not None else None
            if point is not None:
                return point
            node = node.getparent()
        return None

    def _switch(self, element: etree._Element) -> Point | None:
        switch = self._switches.get(element)
        track = switch.main_track if switch is not None else None
        return self._track_point(track.road_id, track.s) if track is not None else None

    def _track(self, element: etree._Element) -> Point | None:
        return self._track_point(element.get("id"), number(element, "s"))

    def _link(self, element: etree._Element) -> Point | None:
        """A road link at the end of its road it joins (TR001 and TR002 name that point);
        a lane's link at the end of its lane it joins."""
        link = element.getparent()
        road = self._road_above(element) if link is not None and link.tag == "link" else None
        if road is None or link is None:
            return None
        lane = link.getparent()
        if lane is not None and lane.tag == "lane":
            end = "start" if element.tag == "predecessor" else "end"
            return self._placer.lane_end(road, lane, end)
        return self._track_point(road.id, 0.0 if element.tag == "predecessor" else road.length)

    def _junction_lane_link(self, element: etree._Element) -> Point | None:
        """A junction's lane link where it enters its connecting road (at the contact
        point the connection names, its start when it names none)."""
        connection = element.getparent()
        if connection is None:
            return None
        road = self._placer.road(connection.get("connectingRoad"))
        if road is None:
            return None
        at_end = connection.get("contactPoint") == "end"
        return self._track_point(road.id, road.length if at_end else 0.0)

    def _profile_entry(self, element: etree._Element) -> Point | None:
        """An ``elevation`` or ``superelevation`` entry at its road's track point at its
        ``s`` (TR010 to TR012 report on them)."""
        road = self._road_above(element)
        s = number(element, "s")
        if road is None or s is None:
            return None
        point = self._tracks.point(road, s)
        return (point.x, point.y) if point is not None else self._placer.track_point(road.id, s)

    def _track_point(self, road_id: str | None, s: float | None) -> Point | None:
        """The track point the geometry rules compute, else the map's own placement (a
        road whose plan view they cannot evaluate may still be drawn in part)."""
        road = self._placer.road(road_id)
        point = self._tracks.point(road, s) if road is not None and s is not None else None
        if point is not None:
            return (point.x, point.y)
        return self._placer.track_point(road_id, s)

    def _segment(self, element: etree._Element) -> Point | None:
        segment = self._segments.get(element)
        return self._placer.segment_middle(segment) if segment is not None else None

    def _first_child_placed(self, element: etree._Element) -> Point | None:
        child_tag = "platform" if element.tag == "station" else "segment"
        for child in element.iterchildren(child_tag):
            point = self._by_tag[child_tag](child)
            if point is not None:
                return point
        return None

    def _lane(self, element: etree._Element) -> Point | None:
        road = self._road_above(element)
        return self._placer.lane_start(road, element) if road is not None else None

    def _lane_section(self, element: etree._Element) -> Point | None:
        road = self._road_above(element)
        if road is None:
            return None
        for section in road.lane_sections:
            if section.element is element:
                return self._placer.section_start(road, section)
        return None

    def _road(self, element: etree._Element) -> Point | None:
        road = self._placer.road_of(element)
        return self._placer.road_middle(road) if road is not None else None

    def _road_above(self, element: etree._Element) -> Road | None:
        for ancestor in element.iterancestors("road"):
            return self._placer.road_of(ancestor)
        return None
