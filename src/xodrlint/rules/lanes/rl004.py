"""RL004 rail-road-shared: a road with a rail or tram lane also carries road traffic lanes.

## What it does
On a road that has a lane of type `rail` or `tram`, reports the first traffic lane of
each lane section: any left or right lane whose type is neither `rail`/`tram` nor a
non-traffic type (`none`, `border`, `shoulder`, `curb`, `sidewalk`, `walking`, `median`);
once per lane section. The centre lane has no width and carries nothing, whatever its
type; a lane without a type is not judged.

## Why is this bad?
ASAM OpenDRIVE says railroad tracks always need an own road. A street-running tram shares
space with cars, but in OpenDRIVE its track is still a road of its own, overlapping the
street: switches and stations name the track's road, and a road that is both track and
street gives them two meanings.

## Example
```xml
<laneSection s="0">
  <left>
    <lane id="2" type="sidewalk" level="false"><width sOffset="0" a="2" b="0" c="0" d="0"/></lane>
    <lane id="1" type="driving" level="false"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane> <!-- expect: RL004 -->
  </left>
  <center><lane id="0" type="none" level="false"/></center>
  <right>
    <lane id="-1" type="tram" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane>
    <lane id="-2" type="driving" level="false"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane>
  </right>
</laneSection>
```

Use instead:
```xml
<laneSection s="0">
  <left>
    <lane id="2" type="walking" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane>
    <lane id="1" type="tram" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane>
  </left>
  <center><lane id="0" type="none" level="false"/></center>
</laneSection>
```

## Related rules
RL002 judges the centring of rail lanes only on roads without traffic lanes.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads"; rule UID
  `xodrlint:xodr:1.4.0:road.railroad.own_road`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import (
    NON_TRAFFIC_LANE_TYPES,
    RAIL_LANE_TYPES,
    Hit,
    RailNetwork,
    Road,
    Severity,
    rule,
)
from xodrlint.rules.lanes._labels import lane_label
from xodrlint.rules.lanes._templates import judged_once_per_layout, own_lane


@rule(
    code="RL004",
    name="rail-road-shared",
    uid="xodrlint:xodr:1.4.0:road.railroad.own_road",
    severity=Severity.WARNING,
)
def rail_road_shared(network: RailNetwork) -> Iterator[Hit]:
    for road, traffic in judged_once_per_layout(network, _first_traffic_lanes):
        for section_index, lane_index in traffic:
            section, lane = own_lane(road, section_index, lane_index)
            yield Hit(
                lane.element,
                f"{lane_label(lane, road, section.s)} is a '{lane.type}' lane "
                "on a road with a rail or tram lane; a railroad track needs its own road",
            )


def _first_traffic_lanes(template: Road, length: float | None) -> list[tuple[int, int]]:
    """(lane section, lane) of the first traffic lane of each lane section that has one."""
    found = []
    for section_index, section in enumerate(template.lane_sections):
        traffic = [
            lane_index
            for lane_index, lane in enumerate(section.lanes)
            if lane.side != "center"
            and lane.type is not None
            and lane.type not in RAIL_LANE_TYPES
            and lane.type not in NON_TRAFFIC_LANE_TYPES
        ]
        if traffic:
            found.append((section_index, traffic[0]))
    return found
