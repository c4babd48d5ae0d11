"""The model's indexes: one pass over the tree builds the read-only facts all rules share.

Only the subtrees railroad rules care about are visited (``road/lanes``,
``road/railroad``, ``station``), so building the model costs a fraction of parsing.
Attributes are read leniently: a missing or malformed value becomes ``None`` and the
rules stay silent on it (the schema stage reports the value itself). The values are named
tuples: as immutable as frozen dataclasses, and several times faster to create, which
counts when a city map makes tens of thousands of them.
"""

# No ``from __future__ import annotations``: each string annotation of a named tuple is
# compiled when the class is made, 2 ms of every run's start-up here.
import math
import re
import weakref
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from types import MappingProxyType
from typing import Final, NamedTuple, TypeVar, cast

from lxml import etree

from xodrlint.findings import Hit

#: Lane types that carry trains or trams.
RAIL_LANE_TYPES: Final = frozenset({"rail", "tram"})

#: Lane types that carry no traffic, so they may share a road with a rail lane.
NON_TRAFFIC_LANE_TYPES: Final = frozenset(
    {"none", "border", "shoulder", "curb", "sidewalk", "walking", "median"}
)

#: Roads with a rail or tram lane in any lane section, found by libxml2 in one pass.
_RAIL_ROADS: Final = etree.XPath(
    "road[lanes/laneSection/*/lane["
    + " or ".join(f"@type='{lane_type}'" for lane_type in sorted(RAIL_LANE_TYPES))
    + "]]"
)


def number(element: etree._Element, attribute: str) -> float | None:
    """The finite number in ``attribute``, or ``None`` if absent or not a finite xs:double."""
    return _double(element.get(attribute))


def numbers(element: etree._Element, attributes: Sequence[str]) -> list[float | None]:
    """:func:`number` for each of ``attributes``, in one pass where all are plain finite
    numbers (nearly always): a plan-view record or a width entry has five to eight."""
    raws = list(map(element.get, attributes))
    if None not in raws:
        try:
            values = list(map(float, raws))  # type: ignore[arg-type]  # no None: checked
        except ValueError:
            pass
        else:
            joined = "".join(raws)  # type: ignore[arg-type]
            if "_" not in joined and joined.isascii() and all(map(math.isfinite, values)):
                return values  # type: ignore[return-value]  # list is invariant
    return list(map(_double, raws))


def _double(raw: str | None) -> float | None:
    if raw is None:
        return None
    try:
        value = float(raw)
    except ValueError:
        return None
    # float() also takes "1_0", "infinity", "nan" and non-ASCII digits; xs:double does not
    # (and a value too big for a double is no length or position we can use)
    if not math.isfinite(value) or "_" in raw or not raw.isascii():
        return None
    return value


#: xs:double's numerals: a value such as "1e999" is one, but too large for a double.
_XS_NUMERAL: Final = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[Ee][+-]?[0-9]+)?")
#: xs:double's own spellings of its infinities and of not-a-number ("+INF" since XSD 1.1).
_XS_SPECIALS: Final = frozenset({"INF", "-INF", "+INF", "NaN"})


def non_finite(element: etree._Element, attribute: str) -> str | None:
    """The text of ``attribute`` when it is an xs:double that is no finite number (``INF``,
    ``-INF``, ``NaN``, or a numeral too large for a double such as ``1e999``), as written:
    the schema accepts it, and it lies outside every range, so the range rules report it.
    ``None`` for a finite number, a missing value, or text that is no xs:double (that is
    the schema rule's to report)."""
    raw = element.get(attribute)
    if raw is None:
        return None
    text = raw.strip(" \t\r\n")  # xs:double collapses whitespace
    if text in _XS_SPECIALS:
        return text
    if _XS_NUMERAL.fullmatch(text) and not math.isfinite(float(text)):
        return text
    return None


def integer(element: etree._Element, attribute: str) -> int | None:
    """The integer in ``attribute`` (an optional sign, then ASCII digits), or ``None``."""
    raw = element.get(attribute)
    if raw is None:
        return None
    text = raw.strip()
    sign = text[:1] in "+-" and text[:1] != ""
    digits = text[1:] if sign else text
    if not digits.isascii() or not digits.isdigit():
        return None
    return int(text)


class Cubic(NamedTuple):
    """``a + b·ds + c·ds² + d·ds³`` from ``start`` on (a ``laneOffset`` or lane ``width``)."""

    element: etree._Element
    start: float
    a: float
    b: float
    c: float
    d: float

    def at(self, s: float) -> float:
        ds = s - self.start
        return self.a + ds * (self.b + ds * (self.c + ds * self.d))


class LaneLink(NamedTuple):
    """A lane's ``link/predecessor`` or ``link/successor``: the lane it continues from or
    into, in the neighbouring lane section or, at the road's end, in the linked road."""

    element: etree._Element
    id: int | None
    """``@id`` of the lane linked to; ``None`` when missing or not an integer."""


class Lane(NamedTuple):
    """A ``lane`` of a lane section."""

    element: etree._Element
    id: int | None
    """``@id``: positive on the left, 0 for the centre lane, negative on the right."""
    side: str
    """``left``, ``center`` or ``right``: the group the lane is written in."""
    type: str | None
    """``@type``: ``rail``, ``tram``, ``driving``, ``sidewalk``, ..."""
    widths: tuple[Cubic, ...]
    """Width entries with ``start`` = ``sOffset`` relative to the lane section; entries
    with unreadable coefficients are left out."""
    widths_complete: bool = True
    """Every ``width`` entry of the lane was readable: ``widths`` is the lane's width."""
    predecessors: tuple[LaneLink, ...] = ()
    """``link/predecessor`` entries, in document order (OpenDRIVE allows several)."""
    successors: tuple[LaneLink, ...] = ()
    """``link/successor`` entries, in document order."""

    @property
    def is_rail(self) -> bool:
        return self.type in RAIL_LANE_TYPES


class LaneSection(NamedTuple):
    """A ``laneSection``: where it starts and its lanes, in document order."""

    element: etree._Element
    s: float | None
    """``@s``: where the section starts along the road."""
    lanes: tuple[Lane, ...]

    @property
    def rail_lanes(self) -> tuple[Lane, ...]:
        return tuple(lane for lane in self.lanes if lane.is_rail)


class RoadLanes(NamedTuple):
    """A road's ``lanes`` element, read: its lane sections and its lane offset."""

    sections: tuple[LaneSection, ...]
    offsets: tuple[Cubic, ...]
    offsets_complete: bool
    """Every ``laneOffset`` entry was readable: ``offsets`` is the road's offset."""


class Road:
    """A road: id and length at once; its lanes are read on first use.

    Most roads of a city map carry no rail lane, and the rail rules never look at their
    lanes: reading them lazily keeps the model a fraction of the parse.
    ``has_rail_lane`` is known up front (one XPath over the whole tree finds those roads).
    """

    __slots__ = (
        "__weakref__",
        "_lanes",
        "_link_elements",
        "_links",
        "_profiles",
        "_template",
        "_templates",
        "element",
        "has_rail_lane",
        "id",
        "length",
    )

    def __init__(
        self,
        element: etree._Element,
        id: str | None,
        length: float | None,
        has_rail_lane: bool,
        templates: "Templates | None" = None,
    ) -> None:
        self.element = element
        self.id = id
        self.length = length
        self.has_rail_lane = has_rail_lane
        self._lanes: RoadLanes | None = None
        self._links: tuple[RoadLink, ...] | None = None
        # the road's link and profile elements, when the model's one pass over the
        # road's children found them (None: not looked for yet)
        self._link_elements: tuple[etree._Element, ...] | None = None
        self._profiles: tuple[etree._Element, ...] | None = None
        # the template road once known, None for this road itself: no road refers to
        # itself, and the layouts refer to their roads weakly, so a model holds no
        # cycles (the command line freezes what a lint made; a cycle there never died)
        self._template: Road | object | None = _UNKNOWN
        self._templates = templates

    def __repr__(self) -> str:
        return f"Road(id={self.id!r}, length={self.length!r})"

    @property
    def lanes(self) -> RoadLanes:
        if self._lanes is None:
            self._lanes = _read_lanes(self.element)
        return self._lanes

    @property
    def lane_template(self) -> "Road":
        """One road of the file whose ``lanes`` read as this road's do, text for text (the
        first one asked, maybe this road itself): every fact of its lanes but the
        elements is this road's own.

        A railway repeats a few lane layouts over thousands of tracks, so rules that
        judge lanes judge each layout once (and read a road's own lanes only to report
        on them); reading every road's lanes was a third of a rail-dense map's run."""
        template = self._template
        if template is None:
            return self
        if isinstance(template, Road):  # asked a hundred thousand times on a railway
            return template
        if template is _UNKNOWN:
            templates = self._templates
            if templates is None:
                template = None
            else:
                key = b"".join(
                    etree.tostring(lanes, with_tail=False)
                    for lanes in self.element.iterchildren("lanes")
                )
                template = templates.setdefault(key, self)
                template = None if template is self else template
            self._template = template
        return self if template is None else cast("Road", template)

    @property
    def links(self) -> tuple["RoadLink", ...]:
        """The road's ``link/predecessor`` and ``link/successor``, in document order."""
        links = self._links
        if links is None:
            if self._link_elements is None:
                self._found_parts(*_link_and_profile_elements(self.element))
            assert self._link_elements is not None
            links = self._links = tuple(
                RoadLink(
                    end, tag, end.get("elementType"), end.get("elementId"), end.get("contactPoint")
                )
                for link in self._link_elements
                for end in link
                if (tag := end.tag) == "predecessor" or tag == "successor"
            )
        return links

    @property
    def profiles(self) -> tuple[etree._Element, ...]:
        """The road's ``elevationProfile`` and ``lateralProfile`` elements, in document order."""
        if self._profiles is None:
            self._found_parts(*_link_and_profile_elements(self.element))
        assert self._profiles is not None
        return self._profiles

    def _found_parts(
        self, links: tuple[etree._Element, ...], profiles: tuple[etree._Element, ...]
    ) -> None:
        """The road's ``link`` and its ``elevationProfile`` and ``lateralProfile`` elements,
        found by a pass over its children made anyway (the model's, reading switches)."""
        self._link_elements, self._profiles = links, profiles

    @property
    def lane_sections(self) -> tuple[LaneSection, ...]:
        return self.lanes.sections

    @property
    def lane_offsets(self) -> tuple[Cubic, ...]:
        return self.lanes.offsets

    @property
    def lane_offsets_complete(self) -> bool:
        return self.lanes.offsets_complete

    @property
    def lane_types(self) -> frozenset[str]:
        return frozenset(
            lane.type for section in self.lane_sections for lane in section.lanes if lane.type
        )

    def section_ranges(self) -> Iterator[tuple[LaneSection, float, float]]:
        """Each lane section with the s range it covers, where both ends are known.

        A section ends where the next one starts, the last one at the road's length; a
        section whose start or end is unreadable (or reversed) is left out.
        """
        return section_ranges(self.lane_sections, self.length)


def section_ranges(
    sections: Sequence[LaneSection], length: float | None
) -> Iterator[tuple[LaneSection, float, float]]:
    """:meth:`Road.section_ranges` of ``sections`` on a road ``length`` long."""
    for index, section in enumerate(sections):
        following = sections[index + 1].s if index + 1 < len(sections) else length
        if section.s is not None and following is not None and following >= section.s:
            yield section, section.s, following


#: A road whose template is not looked for yet.
_UNKNOWN: Final = object()

#: The lane layouts of one file, by their text: a road of each, held weakly.
Templates = weakref.WeakValueDictionary[bytes, Road]


class RoadLink(NamedTuple):
    """A road's ``link/predecessor`` or ``link/successor``."""

    element: etree._Element
    kind: str
    """``predecessor`` or ``successor``."""
    element_type: str | None
    element_id: str | None
    contact_point: str | None


class JunctionLaneLink(NamedTuple):
    """A connection's ``laneLink``: a lane of the incoming road into one of the connecting
    road."""

    element: etree._Element
    from_id: int | None
    """``@from``: the lane of the incoming road."""
    to_id: int | None
    """``@to``: the lane of the connecting road."""


class Connection(NamedTuple):
    """A junction's ``connection``: an incoming road and the connecting road it enters."""

    element: etree._Element
    id: str | None
    incoming_road: str | None
    """``@incomingRoad``."""
    connecting_road: str | None
    """``@connectingRoad``."""
    contact_point: str | None
    """``@contactPoint``: the end of the connecting road the incoming road enters at."""
    lane_links: tuple[JunctionLaneLink, ...]


class Junction:
    """A ``junction``: its id at once; its connections are read on first use (a city map
    has thousands, and only the track rules look into those of tracks)."""

    __slots__ = ("_connections", "element", "id")

    def __init__(self, element: etree._Element, id: str | None) -> None:
        self.element = element
        self.id = id
        self._connections: tuple[Connection, ...] | None = None

    def __repr__(self) -> str:
        return f"Junction(id={self.id!r})"

    @property
    def connections(self) -> tuple[Connection, ...]:
        if self._connections is None:
            self._connections = _read_connections(self.element)
        return self._connections


class TrackRef(NamedTuple):
    """A ``mainTrack`` or ``sideTrack``: a road, a position on it and a direction."""

    element: etree._Element
    road_id: str | None
    """``@id``: the road the track runs on."""
    s: float | None
    """``@s``: where on that road the switch is."""
    dir: str | None
    """``@dir``: ``+`` or ``-``, the direction of travel along the road."""


class PartnerRef(NamedTuple):
    """A switch's ``partner``: the other switch of the pair, by id and name."""

    element: etree._Element
    id: str | None
    name: str | None


class Switch(NamedTuple):
    """A ``road/railroad/switch``."""

    element: etree._Element
    id: str | None
    name: str | None
    position: str | None
    """``@position``: ``dynamic``, ``straight`` or ``turn``."""
    road: Road
    """The road whose ``railroad`` holds the switch."""
    main_track: TrackRef | None
    side_track: TrackRef | None
    partner: PartnerRef | None


class Segment(NamedTuple):
    """A platform's ``segment``: the stretch of a road it lies beside."""

    element: etree._Element
    road_id: str | None
    """``@roadId``."""
    s_start: float | None
    """``@sStart``."""
    s_end: float | None
    """``@sEnd``."""
    side: str | None
    """``@side``: ``left`` or ``right`` of the road."""


class Platform(NamedTuple):
    """A station's ``platform``."""

    element: etree._Element
    id: str | None
    name: str | None
    segments: tuple[Segment, ...]


class Station(NamedTuple):
    """A ``station`` and its platforms."""

    element: etree._Element
    id: str | None
    name: str | None
    type: str | None
    """``@type``: ``small``, ``medium`` or ``large``."""
    platforms: tuple[Platform, ...]


_T = TypeVar("_T")
_V = TypeVar("_V")


def _first_by_id(items: Sequence[_T], key: str) -> Mapping[str, _T]:
    index: dict[str, _T] = {}
    for item in items:
        ident = getattr(item, key)
        if ident is not None:
            index.setdefault(ident, item)
    return MappingProxyType(index)


def _group_by(
    items: Sequence[_T], key_of: Callable[[_T], str | None]
) -> Mapping[str, tuple[_T, ...]]:
    groups: dict[str, list[_T]] = {}
    for item in items:
        key = key_of(item)
        if key is not None:
            groups.setdefault(key, []).append(item)
    return MappingProxyType({key: tuple(members) for key, members in groups.items()})


@dataclass(frozen=True)
class RailNetwork:
    """The read-only facts of one file that rules query.

    ``problems`` holds the hits the load and schema stages found, by document rule code;
    the document rules (XS) report them. Every index is built once, in document order;
    ``*_by_id`` maps keep the first element with an id (duplicates are a rule's business).
    """

    roads: tuple[Road, ...] = ()
    """Every ``road``, in document order."""
    switches: tuple[Switch, ...] = ()
    """Every switch of every road's ``railroad``, in document order."""
    stations: tuple[Station, ...] = ()
    problems: Mapping[str, Sequence[Hit]] = field(default_factory=dict)
    """What loading and validating the file found, by the code of the document rule
    (``XS001`` ... ``XS006``) that reports it."""
    junctions: tuple[Junction, ...] = ()
    """Every ``junction``, in document order."""
    derived: dict[type, object] = field(default_factory=dict, repr=False, compare=False)
    """What rules compute from the model once per file and share (the plan-view geometry
    of the roads they touch), keyed by the type of the value; see :meth:`shared`."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "road_by_id", _first_by_id(self.roads, "id"))
        object.__setattr__(self, "switch_by_id", _first_by_id(self.switches, "id"))
        object.__setattr__(self, "junction_by_id", _first_by_id(self.junctions, "id"))
        object.__setattr__(
            self,
            "switches_by_side_track",
            _group_by(self.switches, lambda sw: sw.side_track and sw.side_track.road_id),
        )
        object.__setattr__(
            self,
            "switches_by_main_track",
            _group_by(self.switches, lambda sw: sw.main_track and sw.main_track.road_id),
        )

    road_by_id: Mapping[str, Road] = field(init=False, repr=False)
    """Roads by ``@id``, the first of each id."""
    switch_by_id: Mapping[str, Switch] = field(init=False, repr=False)
    """Switches by ``@id``, the first of each id."""
    junction_by_id: Mapping[str, Junction] = field(init=False, repr=False)
    """Junctions by ``@id``, the first of each id."""
    switches_by_side_track: Mapping[str, tuple[Switch, ...]] = field(init=False, repr=False)
    """Switches in document order, by the road their ``sideTrack`` names."""
    switches_by_main_track: Mapping[str, tuple[Switch, ...]] = field(init=False, repr=False)
    """Switches in document order, by the road their ``mainTrack`` names."""

    def shared(self, kind: Callable[["RailNetwork"], _V]) -> _V:
        """The one ``kind(self)`` of this file: made on first use, then shared by every
        rule that asks (``kind`` is a class taking the network)."""
        key = cast(type, kind)
        found = self.derived.get(key)
        if found is None:
            found = self.derived[key] = kind(self)
        return cast(_V, found)

    @cached_property
    def rail_roads(self) -> tuple[Road, ...]:
        """Roads with a rail or tram lane: the only ones the lane rules read lanes of
        (listed once: a railway's track rules pass over them a dozen times)."""
        return tuple(road for road in self.roads if road.has_rail_lane)

    @property
    def platforms(self) -> Iterable[Platform]:
        """Every station's platforms."""
        return (platform for station in self.stations for platform in station.platforms)

    @property
    def segments(self) -> Iterable[Segment]:
        """Every platform's segments."""
        return (segment for platform in self.platforms for segment in platform.segments)


def build_network(
    root: etree._Element | None, problems: Mapping[str, Sequence[Hit]] | None = None
) -> RailNetwork:
    """Build the model of an ``OpenDRIVE`` root; ``None`` gives an empty network."""
    frozen_problems = MappingProxyType(dict(problems or {}))
    if root is None or root.tag != "OpenDRIVE":
        return RailNetwork(problems=frozen_problems)
    roads: list[Road] = []
    switches: list[Switch] = []
    stations: list[Station] = []
    junctions: list[Junction] = []
    found = _RAIL_ROADS(root)
    rail_roads = set(found) if isinstance(found, list) else set()
    templates: Templates = weakref.WeakValueDictionary()
    for child in root.iterchildren("road", "station", "junction"):
        tag = child.tag
        if tag == "road":
            road = Road(
                child, child.get("id"), number(child, "length"), child in rail_roads, templates
            )
            roads.append(road)
            # one pass over the road's children for its switches, and the elements the
            # track rules read of every track: a second pass cost a microsecond a road
            links: tuple[etree._Element, ...] = ()
            profiles: tuple[etree._Element, ...] = ()
            for part in child.iterchildren(
                "link", "elevationProfile", "lateralProfile", "railroad"
            ):
                part_tag = part.tag
                if part_tag == "railroad":
                    switches.extend(
                        _read_switch(switch, road) for switch in part.iterchildren("switch")
                    )
                elif part_tag == "link":
                    links += (part,)
                else:
                    profiles += (part,)
            road._found_parts(links, profiles)
        elif tag == "station":
            stations.append(_read_station(child))
        else:
            junctions.append(Junction(child, child.get("id")))
    return RailNetwork(
        tuple(roads),
        tuple(switches),
        tuple(stations),
        frozen_problems,
        junctions=tuple(junctions),
    )


def _read_lanes(road: etree._Element) -> RoadLanes:
    sections: list[LaneSection] = []
    offsets: list[Cubic] = []
    complete = True
    for lanes in road.iterchildren("lanes"):
        for child in lanes.iterchildren("laneOffset", "laneSection"):
            if child.tag == "laneSection":
                sections.append(_read_lane_section(child))
                continue
            cubic = _cubic(child, "s")
            if cubic is None:
                complete = False
            else:
                offsets.append(cubic)
    return RoadLanes(tuple(sections), tuple(offsets), complete)


def _link_and_profile_elements(
    road: etree._Element,
) -> tuple[tuple[etree._Element, ...], tuple[etree._Element, ...]]:
    links: list[etree._Element] = []
    profiles: list[etree._Element] = []
    for child in road.iterchildren("link", "elevationProfile", "lateralProfile"):
        (links if child.tag == "link" else profiles).append(child)
    return tuple(links), tuple(profiles)


def _read_connections(junction: etree._Element) -> tuple[Connection, ...]:
    return tuple(
        Connection(
            connection,
            connection.get("id"),
            connection.get("incomingRoad"),
            connection.get("connectingRoad"),
            connection.get("contactPoint"),
            tuple(
                JunctionLaneLink(link, integer(link, "from"), integer(link, "to"))
                for link in connection.iterchildren("laneLink")
            ),
        )
        for connection in junction.iterchildren("connection")
    )


def _read_lane_section(element: etree._Element) -> LaneSection:
    lanes: list[Lane] = []
    for side in element.iterchildren("left", "center", "right"):
        tag = side.tag
        lanes.extend(_read_lane(lane, tag) for lane in side.iterchildren("lane"))
    return LaneSection(element, number(element, "s"), tuple(lanes))


def _read_lane(element: etree._Element, side: str) -> Lane:
    widths: list[Cubic] = []
    complete = True
    predecessors: list[LaneLink] = []
    successors: list[LaneLink] = []
    for entry in element.iterchildren("width", "link"):
        if entry.tag == "link":
            for end in entry.iterchildren("predecessor", "successor"):
                found = predecessors if end.tag == "predecessor" else successors
                found.append(LaneLink(end, integer(end, "id")))
            continue
        cubic = _cubic(entry, "sOffset")
        if cubic is None:
            complete = False
        else:
            widths.append(cubic)
    return Lane(
        element,
        integer(element, "id"),
        side,
        element.get("type"),
        tuple(widths),
        complete,
        tuple(predecessors),
        tuple(successors),
    )


def _cubic(entry: etree._Element, start_attribute: str) -> Cubic | None:
    """A ``laneOffset`` or ``width`` entry, ``None`` when a value is unreadable."""
    start, a, b, c, d = numbers(entry, (start_attribute, "a", "b", "c", "d"))
    if start is None or a is None or b is None or c is None or d is None:
        return None
    return Cubic(entry, start, a, b, c, d)


def _read_switch(switch: etree._Element, road: Road) -> Switch:
    # the first of each child, in one pass: find() goes through ElementPath each time,
    # three times a switch (a third of the model of a railway)
    first: dict[str, etree._Element] = {}
    for child in switch.iterchildren("mainTrack", "sideTrack", "partner"):
        first.setdefault(str(child.tag), child)
    get = switch.get
    return Switch(
        switch,
        get("id"),
        get("name"),
        get("position"),
        road,
        _track(first.get("mainTrack")),
        _track(first.get("sideTrack")),
        _partner(first.get("partner")),
    )


def _track(element: etree._Element | None) -> TrackRef | None:
    if element is None:
        return None
    return TrackRef(element, element.get("id"), number(element, "s"), element.get("dir"))


def _partner(element: etree._Element | None) -> PartnerRef | None:
    if element is None:
        return None
    return PartnerRef(element, element.get("id"), element.get("name"))


def _read_station(element: etree._Element) -> Station:
    platforms = tuple(
        Platform(
            element=platform,
            id=platform.get("id"),
            name=platform.get("name"),
            segments=tuple(
                Segment(
                    element=segment,
                    road_id=segment.get("roadId"),
                    s_start=number(segment, "sStart"),
                    s_end=number(segment, "sEnd"),
                    side=segment.get("side"),
                )
                for segment in platform.iterchildren("segment")
            ),
        )
        for platform in element.iterchildren("platform")
    )
    return Station(element, element.get("id"), element.get("name"), element.get("type"), platforms)
