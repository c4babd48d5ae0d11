"""TR007 rail-lane-not-continued: a track turns into a road lane, or ends at a joint.

## What it does
Reports a rail or tram lane that does not continue as a rail or tram lane:
- its lane link (`lane/link/predecessor` or `successor`) names a lane that exists but is
  not of type `rail` or `tram`, in the next lane section of its road or in the road a
  road link joins (a track or not): the track turns into a road lane;
- or, at a joint between two tracks, no rail or tram lane of the other track is joined
  to it (no lane link pairs it, and the one-lane-each default does not apply: a section
  with two rail lanes facing one with one): the track ends at the joint.

Reported once per lane end.

## Why is this bad?
This is an inference from the standard's lane linkage and railroad chapter: a rail lane
is a track, and a track continues only into a track. A lane link from a rail lane into a
driving lane or a sidewalk, or a rail lane a joint leaves unlinked, is a track that
stops dead in the middle of a network that goes on: a simulator's train either halts
there or is routed onto a road lane.

## Example
```xml
<lane id="-1" type="rail" level="false"> <!-- expect: TR007 -->
  <!-- lane -1 of road 2 is a driving lane -->
  <link><successor id="-1"/></link>
```

Use instead:
```xml
<lane id="-1" type="rail" level="false">
  <!-- lane -1 of road 2 is a rail lane -->
  <link><successor id="-1"/></link>
```

## Related rules
TR006 reports a lane link naming a lane that is not there; TR007 stays silent on that
lane end, and on the rail lanes at both ends of that joint: which lane the broken link
meant is unknown, so no lane there is said to end. TR003, TR004 and TR005 report a road link that is wrong; the lanes it would
join are not judged. TR001 and TR002 judge the lanes a joint does join.

## References
- ASAM OpenDRIVE 1.7, section 9.4 "Lane linkage" and chapter 15 "Railroads"; rule UID
  `xodrlint:xodr:1.4.0:road.railroad.track.lane_continues`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, Lane, RailNetwork, Road, Severity, rule
from xodrlint.rules.tracks._joints import END_OF, Joint, end_section, rail_lanes_at
from xodrlint.rules.tracks._network import track_network


@rule(
    code="TR007",
    name="rail-lane-not-continued",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.lane_continues",
    severity=Severity.WARNING,
)
def rail_lane_not_continued(network: RailNetwork) -> Iterator[Hit]:
    judged = track_network(network)
    # a lane end whose lane links TR006 reports, or that this rule reported already
    settled: set[tuple[int, int, int, str]] = set()
    # road ends where a lane link names a lane that is not there: what it joins is unknown
    unknown_ends: set[tuple[int, str]] = set()
    for target in judged.lane_links:
        if target.lane is None:
            end = END_OF[target.kind]
            settled.add(target.source.key(end))
            unknown_ends.add((id(target.source.road.element), end))
            crossing = target.crossing
            if crossing is not None and crossing.target is not None:
                contact = crossing.link.contact_point or ""
                unknown_ends.add((id(crossing.target.element), contact))
    for target in judged.lane_links:
        end = END_OF[target.kind]
        key = target.source.key(end)
        if target.lane is None or target.lane.is_rail or key in settled:
            continue
        if target.crossing is not None and target.crossing.fault is not None:
            continue  # the road link is wrong (TR004): what it joins is not judged
        settled.add(key)
        yield Hit(
            target.source.element,
            f"{target.source.describe()} continues as {target.lane.type or 'untyped'} "
            f"lane {target.lane.id} at {target.where}: the track turns into a road lane",
        )
    yield from _unjoined_lane_ends(network, judged.joints, settled, unknown_ends)


def _unjoined_lane_ends(
    network: RailNetwork,
    joints: list[Joint],
    settled: set[tuple[int, int, int, str]],
    unknown_ends: set[tuple[int, str]],
) -> Iterator[Hit]:
    """The rail lanes of a road end that none of the joints at that end joins to a rail
    lane. A road end in a junction is reached by several connecting roads, each joining
    one of its lanes: the end is judged by all of them together, and not at all when one
    of its links is wrong (TR004 reports it)."""
    # the road ends where a joint leaves a rail lane unjoined: judged by all their joints
    # together (a railway's every joint joins every rail lane of both ends)
    open_ends = {
        (id(side.road.element), side.end)
        for joint in joints
        if False in joint.joins_all  # nearly never: no sides made for the others
        for side in joint.sides()
        if not side.joins_all
    }
    if not open_ends:
        return
    # each such end with its joints, and whether the road is each joint's first
    at_end: dict[tuple[int, str], tuple[Road, str, list[tuple[Joint, bool]]]] = {}
    for joint in joints:
        for side in joint.sides():
            road_end = (id(side.road.element), side.end)
            if road_end in open_ends:
                entry = at_end.setdefault(road_end, (side.road, side.end, []))
                entry[2].append((joint, side.is_first))
    for road_end, (road, end, found) in at_end.items():
        if road_end in unknown_ends or not all(joint.answered for joint, _ in found):
            continue
        joined = {
            (pair.first if is_first else pair.second).lane.id
            for joint, is_first in found
            for pair in joint.lanes
        }
        its_joints = [joint for joint, _ in found]
        for lane_end in rail_lanes_at(road, end):
            key = lane_end.key(end)
            if lane_end.lane.id in joined or key in settled:
                continue
            settled.add(key)
            others = ", ".join(
                f"the {joint.second_end if joint.first is road else joint.first_end} of road "
                f"'{(joint.second if joint.first is road else joint.first).id}'"
                for joint in its_joints
            )
            road_lanes = _road_lanes_into(network, road, end, lane_end.lane.id)
            fate = f"the track turns into {road_lanes}" if road_lanes else "the track ends there"
            yield Hit(
                lane_end.element,
                f"{lane_end.describe()} is joined to no rail or tram lane at the {end} of its "
                f"road (joints to {others}): {fate}",
            )


def _road_lanes_into(network: RailNetwork, road: Road, end: str, lane_id: int | None) -> str:
    """The lanes of other types that a junction at ``road``'s ``end`` leads ``lane_id``
    into (its connections' ``laneLink`` elements from that lane), for the message."""
    link = next((link for link in road.links if END_OF[link.kind] == end), None)
    if link is None or link.element_type != "junction" or link.element_id is None:
        return ""
    junction = network.junction_by_id.get(link.element_id)
    found = []
    for connection in junction.connections if junction is not None else ():
        connecting = network.road_by_id.get(connection.connecting_road or "")
        if connection.incoming_road != road.id or connecting is None:
            continue
        for lane_link in connection.lane_links:
            if lane_link.from_id != lane_id:
                continue
            named = _lane_at(connecting, connection.contact_point, lane_link.to_id)
            if named is not None and not named.is_rail:
                found.append(f"{named.type} lane {named.id} of road '{connecting.id}'")
    return ", ".join(found)


def _lane_at(road: Road, end: str | None, lane_id: int | None) -> Lane | None:
    found = end_section(road, end) if end in ("start", "end") and end is not None else None
    if found is None:
        return None
    return next((lane for lane in found[1].lanes if lane.id == lane_id), None)
