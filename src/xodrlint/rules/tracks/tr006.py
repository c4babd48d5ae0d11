"""TR006 rail-lane-link-target-missing: a rail lane's lane link names a lane that is not there.

## What it does
Reports a lane link (`lane/link/predecessor` or `successor`) of a rail or tram lane whose
`@id` names no lane of the lane section it points into: the previous (predecessor) or
next (successor) lane section of the same road, or, at the road's first or last lane
section, the section at the `contactPoint` end of the road the road link joins. Also
reports a junction's `laneLink` whose `@from` names no lane of its incoming road (at
the end that joins the junction) or whose `@to` names no lane of its connecting road
(at the connection's `contactPoint`), where either road has a rail or tram lane.

## Why is this bad?
The standard links lanes by id: a lane's predecessor and successor give "the IDs of
lanes on the preceding or following lane section", or of the other road's first or last
lane section across a road link, and a junction's `laneLink` pairs a lane of the
incoming road with one of the connecting road. A link to a lane id that does not exist
leads a train onto no track: lane-level routing in esmini and VTD ends there, or picks
a lane of its own.

## Example
```xml
<lane id="-1" type="rail" level="false">
  <!-- road 2 has lanes 0 and -1 at its start -->
  <link><successor id="-2"/></link> <!-- expect: TR006 -->
```

Use instead:
```xml
<lane id="-1" type="rail" level="false">
  <!-- road 2 has lanes 0 and -1 at its start -->
  <link><successor id="-1"/></link>
```

## Related rules
TR006 silences TR007 for the lane: a link to no lane says nothing about what the track
turns into. TR003 and TR005 report a road link whose far end is unknown; the lane links
across it are not judged.

## References
- ASAM OpenDRIVE 1.7, section 9.4 "Lane linkage" and section 10 "Junctions"
  (`connection/laneLink`); rule UID `xodrlint:xodr:1.4.0:road.railroad.track.lane_link_target`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Connection, Hit, Junction, RailNetwork, Road, Severity, rule
from xodrlint.rules.tracks._joints import END_OF, end_section, lane_ids
from xodrlint.rules.tracks._network import track_network


@rule(
    code="TR006",
    name="rail-lane-link-target-missing",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.lane_link_target",
    severity=Severity.ERROR,
)
def rail_lane_link_target_missing(network: RailNetwork) -> Iterator[Hit]:
    for target in track_network(network).lane_links:
        if target.lane is None:
            yield Hit(
                target.source.own_link(target.kind, target.position),
                f"{target.source.describe()} names {target.kind} lane {target.link.id}, "
                f"which {target.where} does not have (lanes: {lane_ids(target.section)})",
            )
    yield from _junction_lane_links(network)


def _junction_lane_links(network: RailNetwork) -> Iterator[Hit]:
    """The ``laneLink`` elements of the junctions tracks lead into or run through: a junction
    no track names is a road junction, and its connections are not read."""
    if not network.junctions:
        return  # nothing to read (a railway without junctions: thousands of tracks)
    wanted = {
        link.element_id
        for road in network.rail_roads
        for link in road.links
        if link.element_type == "junction"
    }
    wanted.update(road.element.get("junction") for road in network.rail_roads)
    for junction in network.junctions:
        if junction.id not in wanted:
            continue
        for connection in junction.connections:
            yield from _connection_lane_links(network, junction, connection)


def _connection_lane_links(
    network: RailNetwork, junction: Junction, connection: Connection
) -> Iterator[Hit]:
    incoming = network.road_by_id.get(connection.incoming_road or "")
    connecting = network.road_by_id.get(connection.connecting_road or "")
    if not any(road is not None and road.has_rail_lane for road in (incoming, connecting)):
        return
    ends_at_junction = [
        END_OF[link.kind]
        for link in (incoming.links if incoming is not None else ())
        if link.element_type == "junction" and link.element_id == junction.id
    ]
    contact = connection.contact_point
    both = ["start", "end"]
    at_contact = [end for end in both if end == contact] or both
    sides = (
        ("from", "incoming", incoming, ends_at_junction or both),
        ("to", "connecting", connecting, at_contact),
    )
    for lane_link in connection.lane_links:
        for attribute, role, road, ends in sides:
            lane_id = lane_link.from_id if attribute == "from" else lane_link.to_id
            if road is None or lane_id is None:
                continue
            present = _lane_ids_at(road, ends)
            if lane_id not in present:
                have = ", ".join(str(i) for i in sorted(present, reverse=True)) or "none"
                yield Hit(
                    lane_link.element,
                    f"laneLink of connection '{connection.id}' in junction '{junction.id}' "
                    f"names lane {lane_id} of {role} road '{road.id}' ({attribute}), which "
                    f"its {' or '.join(ends)} does not have (lanes: {have})",
                )
                break  # one finding a laneLink


def _lane_ids_at(road: Road, ends: list[str]) -> set[int]:
    present: set[int] = set()
    for end in ends:
        found = end_section(road, end)
        if found is not None:
            present.update(lane.id for lane in found[1].lanes if lane.id is not None)
    return present
