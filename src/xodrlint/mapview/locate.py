"""Where a finding goes on the map: the element its XPath names, placed by what it is (a
switch at its point, a segment at its middle, a lane or lane section at its start, a road
link at the road end it joins, an elevation or superelevation entry at its s, a road at
its middle), or else by its nearest ancestor that has a place. Switch tracks, road links
and profile entries are placed at the track points the track-geometry rules name in
their messages."""

from __future__ import annotations

from collections.abc import Callable

from lxml import etree

from xodrlint.document import Document
from xodrlint.findings import Finding
from xodrlint.geometry.tracks import TrackGeometry
from xodrlint.mapview.place import Placer, Point, geometry_start
from xodrlint.model import RailNetwork, Road, Segment, Switch, number


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
            "predecessor": self._link,
            "successor": self._link,
            "elevation": self._profile_entry,
            "superelevation": self._profile_entry,
            "road": self._road,
        }

    def element(self, xpath: str) -> etree._Element | None:
        found_fast = self._doc.element_at(xpath)  # the XPaths findings carry
        if found_fast is not None or self._doc.tree is None:
            return found_fast
        try:
            found = self._doc.tree.xpath(xpath)
        except etree.XPathError:
            return None
        if isinstance(found, list) and found and isinstance(found[0], etree._Element):
            return found[0]
        return None

    def place(self, finding: Finding) -> Point | None:
        element = self.element(finding.xpath)
        return self.position(element) if element is not None else None

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
        """A road link at the end of its road it joins (TR001 and TR002 name that point)."""
        link = element.getparent()
        road = self._road_above(element) if link is not None and link.tag == "link" else None
        if road is None:
            return None
        return self._track_point(road.id, 0.0 if element.tag == "predecessor" else road.length)

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
