"""The links of a railway, read once per file and shared by the track-network rules.

- Every road link of a track is judged as a link: it names a road or junction the file
  does not define (TR003), it joins two tracks without a ``contactPoint`` (TR005), or the
  road it joins does not name it back at that end (TR004, once per pair of roads).
- A **joint** is a road link between two tracks with a contact point, once per pair of
  road ends (on the link of the road first in the document when both name each other).
  Its **joined lanes** are the pairs of rail/tram lanes of the two end lane sections that
  a lane link pairs (either side's), or the two single rail/tram lanes when each section
  holds exactly one, whatever their lane links say (TR001, TR002, TR007).
- Where each rail lane's lane links point (:mod:`._lane_links`: TR006, TR007).

Lanes are read from each road's lane template (:attr:`~xodrlint.model.Road.lane_template`:
a railway repeats a few lane layouts over thousands of tracks); a finding about a lane is
put on the road's own element, found by position.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING, Final, NamedTuple

from xodrlint.rules import Junction, Lane, LaneLink, LaneSection, RailNetwork, Road, RoadLink

if TYPE_CHECKING:
    from lxml import etree

    from xodrlint.rules.geometry import TrackGeometry, TrackPoint

#: The end of its road a road link (or a lane link) is at.
END_OF: Final = {"predecessor": "start", "successor": "end"}
#: The link that leaves a road through an end.
LINK_AT: Final = {"start": "predecessor", "end": "successor"}
#: The direction of travel that leaves a road through an end.
_LEAVING: Final = {"start": "-", "end": "+"}

#: Why a link of a track is wrong, by the code of the rule that reports it.
TARGET_MISSING: Final = "TR003"
NOT_ANSWERED: Final = "TR004"
NO_CONTACT_POINT: Final = "TR005"


class TrackLink(NamedTuple):
    """A ``link/predecessor|successor`` of a track, judged."""

    road: Road
    link: RoadLink
    end: str
    """The end of ``road`` it is at: ``start`` or ``end``."""
    target: Road | None
    """The road it names, when it names one the file defines."""
    fault: str | None
    """The code of the rule the link is wrong by (``TR003``, ``TR004``, ``TR005``)."""
    reported: bool
    """Whether the finding of ``fault`` goes on this link (TR004 reports a pair of roads
    whose links both go unanswered once, on the earlier road's link)."""
    why: str
    """What is wrong, for the message."""


#: A lane of a lane layout's section: the section's index, the lane's, both as read.
_LanePosition = tuple[int, int, LaneSection, Lane]


class LaneEnd(NamedTuple):
    """A lane of a road's lane section, read from the road's lane template."""

    road: Road
    section_index: int
    lane_index: int
    section: LaneSection
    lane: Lane

    def key(self, end: str) -> tuple[int, int, int, str]:
        """Which lane end this is, without reading the road's own lanes."""
        return (id(self.road.element), self.section_index, self.lane_index, end)

    @property
    def element(self) -> etree._Element:
        """The road's own ``lane`` element (``lane`` is the template's)."""
        own = self.road.lane_sections[self.section_index].lanes[self.lane_index]
        return own.element

    def own_link(self, kind: str, index: int) -> etree._Element:
        """The road's own ``link/predecessor|successor`` element number ``index``."""
        own = self.road.lane_sections[self.section_index].lanes[self.lane_index]
        return (own.predecessors if kind == "predecessor" else own.successors)[index].element

    def describe(self) -> str:
        return f"{self.lane.type} lane {self.lane.id} of road '{self.road.id}'"


class JoinedLanes(NamedTuple):
    """Two lanes a joint joins, and their centres at the joined ends (``None`` where the
    plan view or the lane's centre cannot be evaluated)."""

    first_road: Road
    first_at: _LanePosition
    second_road: Road
    second_at: _LanePosition
    first_point: TrackPoint | None
    second_point: TrackPoint | None
    gap: float | None
    """The distance between the two points, where both are known (TR001, TR002)."""

    # the lanes as :class:`LaneEnd`s made when asked: a railway's joints are judged by
    # their points, and only a finding names its lanes
    @property
    def first(self) -> LaneEnd:
        return LaneEnd(self.first_road, *self.first_at)

    @property
    def second(self) -> LaneEnd:
        return LaneEnd(self.second_road, *self.second_at)


class JointSide(NamedTuple):
    """One road end of a joint."""

    road: Road
    end: str
    is_first: bool
    """Whether the road is the joint's first (its lanes are the pairs' ``first``)."""
    joins_all: bool
    """Whether the joint joins every rail and tram lane of this end."""


class Joint(NamedTuple):
    """Two tracks joined by ``link``: the first leaves at ``first_end``, the second is
    entered at ``second_end`` (``start`` or ``end``)."""

    link: RoadLink
    first: Road
    first_end: str
    second: Road
    second_end: str
    answered: bool
    """The second road names the first back at that end (else TR004 reports the link)."""
    lanes: tuple[JoinedLanes, ...]
    joins_all: tuple[bool, bool]
    """Whether ``lanes`` take in every rail and tram lane of the first road's end, and of
    the second's (TR007 judges the ends where one does not)."""

    def sides(self) -> tuple[JointSide, JointSide]:
        """The two road ends the joint joins, the first road's first."""
        return (
            JointSide(self.first, self.first_end, True, self.joins_all[0]),
            JointSide(self.second, self.second_end, False, self.joins_all[1]),
        )

    def leaving(self, point: TrackPoint) -> float:
        """The direction of travel leaving the first road through the joint."""
        return point.direction(_LEAVING[self.first_end])

    def entering(self, point: TrackPoint) -> float:
        """The direction of travel entering the second road through the joint."""
        return point.direction("-" if _LEAVING[self.second_end] == "+" else "+")

    def describe(self) -> str:
        """How messages name the joint."""
        return (
            f"{self.link.kind} of road '{self.first.id}' joins its {self.first_end} to the "
            f"{self.second_end} of road '{self.second.id}'"
        )


def end_section(road: Road, end: str) -> tuple[int, LaneSection] | None:
    """The lane section of ``road`` (its template's) at ``end``, with its index."""
    sections = road.lane_template.lane_sections
    if not sections:
        return None
    index = 0 if end == "start" else len(sections) - 1
    return index, sections[index]


def lane_ids(section: LaneSection) -> str:
    """The ids of a section's lanes, for messages."""
    ids = sorted({lane.id for lane in section.lanes if lane.id is not None}, reverse=True)
    return ", ".join(str(lane_id) for lane_id in ids) or "none"


def judged_links(network: RailNetwork) -> list[TrackLink]:
    found: list[TrackLink] = []
    repeated = _repeated_road_ids(network)
    for road in network.rail_roads:
        for link in road.links:
            judged = _judge(network, road, link, repeated)
            if judged is not None:
                found.append(judged)
    if all(judged.fault != NOT_ANSWERED for judged in found):
        return found
    return list(_pairs_reported_once(found))


def _link_at(road: Road, end: str) -> RoadLink | None:
    """The first of ``road``'s links at ``end`` (the one a joint there is judged by)."""
    kind = LINK_AT[end]
    for link in road.links:
        if link.kind == kind:
            return link
    return None


def _names_back(answer: RoadLink, road: Road, end: str) -> bool:
    """Whether ``answer`` names ``road`` at ``end`` (or at no end that can be read: a
    missing contact point is TR005's, on that link)."""
    back = answer.contact_point
    return (
        answer.element_type == "road"
        and answer.element_id is not None
        and answer.element_id == road.id
        and (back == end or back not in LINK_AT)
    )


def _pairs_reported_once(found: list[TrackLink]) -> Iterator[TrackLink]:
    # two links that name each other's road and both go unanswered (one names the other
    # road at the wrong end) are one defect: reported once, on the earlier road's link;
    # any other unanswered link is a defect of its own
    # the unanswered links by the roads they join, for finding pairs in time linear in
    # the links (a map where every link is one-sided has thousands)
    unanswered: dict[tuple[int, int], list[TrackLink]] = {}
    for judged in found:
        if judged.fault == NOT_ANSWERED and judged.target is not None:
            key = (id(judged.road.element), id(judged.target.element))
            unanswered.setdefault(key, []).append(judged)
    reported_pairs: set[frozenset[tuple[int, str]]] = set()
    for judged in found:
        pair = _pair_of(judged, unanswered) if judged.fault == NOT_ANSWERED else None
        if pair is not None:
            if pair in reported_pairs:
                yield judged._replace(reported=False)
                continue
            reported_pairs.add(pair)
        yield judged


def _pair_of(
    judged: TrackLink, unanswered: dict[tuple[int, int], list[TrackLink]]
) -> frozenset[tuple[int, str]] | None:
    """The two road ends of an unanswered link and of the unanswered link of the other
    road it pairs with: A names B at B's end b, and B's link at b names A (at the wrong
    end). ``None`` for a link that pairs with none (a defect of its own)."""
    target, contact = judged.target, judged.link.contact_point
    if target is None or contact is None:
        return None
    own = (id(judged.road.element), judged.end)
    for other in unanswered.get((id(target.element), id(judged.road.element)), ()):
        if other.end == contact:  # this link names the end the other link is at
            return frozenset({own, (id(target.element), contact)})
        if other.link.contact_point == judged.end:  # the other link names this one's end
            return frozenset({own, (id(target.element), other.end)})
    return None


def _repeated_road_ids(network: RailNetwork) -> set[str]:
    if len(network.road_by_id) == len(network.roads):
        return set()  # every road has an id of its own
    seen: set[str] = set()
    repeated: set[str] = set()
    for road in network.roads:
        if road.id is not None:
            (repeated if road.id in seen else seen).add(road.id)
    return repeated


def _judge(
    network: RailNetwork, road: Road, link: RoadLink, repeated: set[str]
) -> TrackLink | None:
    end = END_OF[link.kind]
    if link.element_id is None:
        return None  # the schema reports the missing attribute
    if (
        repeated
        and link.element_type == "road"
        and (road.id in repeated or link.element_id in repeated)
    ):
        return None  # which of the roads of one id is meant is unknown (XS006 reports it)
    if link.element_type == "junction":
        if link.element_id in network.junction_by_id:
            return TrackLink(road, link, end, None, None, False, "")
        why = f"names junction '{link.element_id}', which the file does not define"
        return TrackLink(road, link, end, None, TARGET_MISSING, True, why)
    if link.element_type != "road":
        return None
    target = network.road_by_id.get(link.element_id)
    if target is None:
        why = f"names road '{link.element_id}', which the file does not define"
        return TrackLink(road, link, end, None, TARGET_MISSING, True, why)
    if not target.has_rail_lane:
        return TrackLink(road, link, end, target, None, False, "")
    if link.contact_point is not None and link.contact_point not in LINK_AT:
        return None  # a value outside the enumeration: the schema reports it
    if link.contact_point is None:
        if link.element.get("elementS") is not None:
            return None  # a virtual junction's link into the middle of a road: no joint of ends
        why = (
            f"joins road '{target.id}' without a contactPoint: which end of road "
            f"'{target.id}' it joins is unknown"
        )
        return TrackLink(road, link, end, target, NO_CONTACT_POINT, True, why)
    unanswered = _unanswered(network, road, end, target, link.contact_point)
    if unanswered is None:
        return TrackLink(road, link, end, target, None, False, "")
    return TrackLink(road, link, end, target, NOT_ANSWERED, True, unanswered)


def _unanswered(
    network: RailNetwork, road: Road, end: str, target: Road, target_end: str
) -> str | None:
    """Why ``target``'s link at ``target_end`` does not name ``road`` at ``end`` back;
    ``None`` when it does (a missing contact point there is TR005's, on that link)."""
    answer = _link_at(target, target_end)
    if answer is not None and answer.element_type == "road" and answer.element_id is not None:
        if _names_back(answer, road, end):
            return None
        if answer.element_id == road.id:
            return (
                f"{_answer(target, target_end)} names the {answer.contact_point} of road "
                f"'{road.id}', not its {end}"
            )
        return f"{_answer(target, target_end)} names road '{answer.element_id}'"
    if answer is None or answer.element_id is None:
        return f"{_answer(target, target_end)} names nothing"
    if answer.element_type == "junction":
        junction = network.junction_by_id.get(answer.element_id)
        if junction is None or _connects(junction, road):
            return None  # a missing junction is TR003's, on that link
        return (
            f"{_answer(target, target_end)} names junction '{answer.element_id}', of which "
            f"road '{road.id}' is not a connecting road"
        )
    return None  # the schema reports the element type


def _answer(target: Road, target_end: str) -> str:
    """The start of a message on a link that goes unanswered at ``target``'s end."""
    kind = LINK_AT[target_end]
    return f"joins the {target_end} of road '{target.id}', but the {kind} of road '{target.id}'"


def _connects(junction: Junction, road: Road) -> bool:
    """Whether ``road`` is a connecting road of ``junction``."""
    if road.element.get("junction") == junction.id:
        return True
    return any(connection.connecting_road == road.id for connection in junction.connections)


def find_joints(network: RailNetwork, links: Sequence[TrackLink]) -> Iterator[Joint]:
    tracks: TrackGeometry | None = None
    # each joint is named by the links of both its roads (or twice by one): the pairs of
    # road ends joined so far (roads and layouts hash by identity: no id() calls, a
    # railway passes here for each of its thousands of joints)
    seen: set[tuple[Road, str, Road, str]] = set()
    # the joined lanes of each pair of lane layouts and ends, as (section, lane) positions:
    # a railway joins thousands of tracks of a few layouts
    layouts: dict[tuple[Road, str, Road, str], _LanePairs] = {}
    for road, link, end, target, fault, reported, _ in links:
        target_end = link.contact_point
        if target is None or not target.has_rail_lane or target_end not in LINK_AT:
            continue
        if fault is not None and not reported:
            continue  # the other link of a pair TR004 reports once: neither is judged
        assert target_end is not None
        # either way round: named by the other road's link, or by a second link of this
        # road's end (a link written twice)
        ends = (road, end, target, target_end)
        if ends in seen or (target, target_end, road, end) in seen:
            continue
        seen.add(ends)
        if tracks is None:
            from xodrlint.rules.geometry import TrackGeometry  # loaded only for a railway

            tracks = network.shared(TrackGeometry)
        layout = (road.lane_template, end, target.lane_template, target_end)
        joined = layouts.get(layout)
        if joined is None:
            joined = layouts[layout] = _lane_pairs(layout[0], end, layout[2], target_end)
        end_point = tracks.lane_end_point
        lanes = tuple(
            _joined(
                road,
                first_at,
                end_point(road, first_at[2], first_at[3], end),
                target,
                second_at,
                end_point(target, second_at[2], second_at[3], target_end),
            )
            for first_at, second_at in joined.pairs
        )
        yield Joint(link, road, end, target, target_end, fault is None, lanes, joined.joins_all)


def _joined(
    first: Road,
    first_at: _LanePosition,
    first_point: TrackPoint | None,
    second: Road,
    second_at: _LanePosition,
    second_point: TrackPoint | None,
) -> JoinedLanes:
    gap = None
    if first_point is not None and second_point is not None:
        gap = first_point.distance_to(second_point)
    return JoinedLanes(first, first_at, second, second_at, first_point, second_point, gap)


def rail_lanes_at(road: Road, end: str) -> list[LaneEnd]:
    """The rail/tram lanes of ``road``'s lane section at ``end``."""
    found = end_section(road, end)
    if found is None:
        return []
    index, section = found
    return [
        LaneEnd(road, index, position, section, lane)
        for position, lane in enumerate(section.lanes)
        if lane.is_rail
    ]


def _links_at(lane: Lane, end: str) -> tuple[LaneLink, ...]:
    return lane.predecessors if end == "start" else lane.successors


class _LanePairs(NamedTuple):
    """The joined lanes of two lane layouts' ends, as positions in each."""

    pairs: tuple[tuple[_LanePosition, _LanePosition], ...]
    joins_all: tuple[bool, bool]
    """See :attr:`Joint.joins_all`."""


def _lane_pairs(first: Road, first_end: str, second: Road, second_end: str) -> _LanePairs:
    """The joined lanes of the ends of two roads (read from their lane templates)."""
    firsts, seconds = rail_lanes_at(first, first_end), rail_lanes_at(second, second_end)
    first_section = end_section(first, first_end)
    second_section = end_section(second, second_end)
    first_ids = {lane.id for lane in first_section[1].lanes} if first_section else set()
    second_ids = {lane.id for lane in second_section[1].lanes} if second_section else set()
    # every lane link of a rail lane at the joint that names a lane that is there
    edges: set[tuple[int | None, int | None]] = set()
    for lane_end in firsts:
        for lane_link in _links_at(lane_end.lane, first_end):
            if lane_link.id in second_ids:
                edges.add((lane_end.lane.id, lane_link.id))
    for lane_end in seconds:
        for lane_link in _links_at(lane_end.lane, second_end):
            if lane_link.id in first_ids:
                edges.add((lane_link.id, lane_end.lane.id))
    by_first = {lane_end.lane.id: lane_end for lane_end in firsts}
    by_second = {lane_end.lane.id: lane_end for lane_end in seconds}
    pairs = sorted(
        (edge for edge in edges if edge[0] in by_first and edge[1] in by_second),
        key=lambda edge: (-(edge[0] or 0), -(edge[1] or 0)),
    )
    if len(firsts) == 1 and len(seconds) == 1:
        # the one-lane-each default: joined whatever their lane links say (a link of one
        # into a road lane of the other is TR007's)
        pairs = [(firsts[0].lane.id, seconds[0].lane.id)]
    return _LanePairs(
        tuple((by_first[a][1:], by_second[b][1:]) for a, b in pairs),
        (
            by_first.keys() <= {a for a, _ in pairs},
            by_second.keys() <= {b for _, b in pairs},
        ),
    )
