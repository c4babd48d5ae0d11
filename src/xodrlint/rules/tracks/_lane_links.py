"""Where each rail lane's lane links point: the neighbouring lane section of the same
road, or, at the road's first or last lane section, the section at the contact point end
of the road its road link joins (TR006 reports a link to a lane that is not there, TR007
a rail lane that continues as a lane of another type)."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import NamedTuple

from xodrlint.rules import Lane, LaneLink, LaneSection, RailNetwork, Road
from xodrlint.rules.tracks._joints import END_OF, LINK_AT, LaneEnd, TrackLink, end_section


class LaneLinkTarget(NamedTuple):
    """Where a rail lane's lane link points: a lane section, and the lane it names there
    (``None``: the section has no lane of that id)."""

    source: LaneEnd
    kind: str
    """``predecessor`` or ``successor``."""
    position: int
    """Which of the lane's links of that kind (0 for the first)."""
    link: LaneLink
    road: Road
    section: LaneSection
    where: str
    """How messages name the section pointed into."""
    lane: Lane | None
    crossing: TrackLink | None
    """The road link the lane link crosses at its road's end (``None`` inside a road)."""


def lane_link_targets(network: RailNetwork, links: Sequence[TrackLink]) -> Iterator[LaneLinkTarget]:
    """Where each lane link of each rail lane of each track points, where that is known."""
    at_end: dict[tuple[int, str], TrackLink] | None = None  # made when a lane link needs it
    # the rail lanes with lane links of each lane layout: a railway's are a few, most
    # linking no lanes at all
    linking: dict[int, list[tuple[int, int, LaneSection, Lane]]] = {}
    for road in network.rail_roads:
        template = road.lane_template
        lanes = linking.get(id(template))
        if lanes is None:
            lanes = linking[id(template)] = _linking_rail_lanes(template)
        sections = template.lane_sections
        for section_index, lane_index, section, lane in lanes:
            source = LaneEnd(road, section_index, lane_index, section, lane)
            if at_end is None:
                at_end = {(id(judged.road.element), judged.end): judged for judged in links}
            for kind, lane_links in (
                ("predecessor", lane.predecessors),
                ("successor", lane.successors),
            ):
                if not lane_links:
                    continue
                target = _pointed_section(road, sections, section_index, kind, at_end)
                if target is None:
                    continue
                target_road, target_section, where, crossing = target
                for index, lane_link in enumerate(lane_links):
                    if lane_link.id is None:
                        continue  # not an integer: the schema reports it
                    named = next(
                        (other for other in target_section.lanes if other.id == lane_link.id),
                        None,
                    )
                    yield LaneLinkTarget(
                        source,
                        kind,
                        index,
                        lane_link,
                        target_road,
                        target_section,
                        where,
                        named,
                        crossing,
                    )


def _linking_rail_lanes(template: Road) -> list[tuple[int, int, LaneSection, Lane]]:
    """The rail and tram lanes of a lane layout that have lane links, by position."""
    return [
        (section_index, lane_index, section, lane)
        for section_index, section in enumerate(template.lane_sections)
        for lane_index, lane in enumerate(section.lanes)
        if lane.is_rail and (lane.predecessors or lane.successors)
    ]


def _pointed_section(
    road: Road,
    sections: Sequence[LaneSection],
    index: int,
    kind: str,
    at_end: dict[tuple[int, str], TrackLink],
) -> tuple[Road, LaneSection, str, TrackLink | None] | None:
    """The lane section a lane link of section ``index`` points into, with words for it
    and the road link crossed; ``None`` where it is not known (no road link at that end,
    a link to a junction, a road the file lacks or a link without a contact point)."""
    step = -1 if kind == "predecessor" else 1
    if 0 <= index + step < len(sections):
        neighbour = index + step
        where = f"lane section {neighbour + 1} of road '{road.id}'"
        return road, sections[neighbour], where, None
    judged = at_end.get((id(road.element), END_OF[kind]))
    if judged is None or judged.target is None:
        return None
    target = judged.target
    contact = judged.link.contact_point
    found = end_section(target, contact) if contact in LINK_AT else None
    if found is None:
        return None
    return target, found[1], f"the {contact} of road '{target.id}'", judged
