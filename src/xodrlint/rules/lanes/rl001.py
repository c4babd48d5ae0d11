"""RL001 more-than-one-rail-lane: a lane section holds more than one rail or tram lane.

## What it does
Reports a `laneSection` that holds two or more lanes of type `rail` or `tram`, once per
lane section.

It applies to files that declare OpenDRIVE 1.7 or later, the version that introduced the
convention: a file declaring 1.4 to 1.6 is not judged by it (the run's note names the
files), unless the run applies every rule to every version (`--all-versions`, or
`all-versions = true` in the configuration). A file whose version cannot be read (XS004)
is judged.

## Why is this bad?
ASAM OpenDRIVE 1.7 models each railroad track as its own road with exactly one rail lane:
switches, stations and partner links name roads, not lanes. A second rail lane in the
same lane section is a track that no switch can reach and no platform can name. Earlier
versions say nothing of it: their exporters (SUMO writes 1.4) put several tracks on one
road, which is no defect of theirs.

## Example
```xml
<laneSection s="0"> <!-- expect: RL001 -->
  <left>
    <lane id="1" type="rail" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane>
  </left>
  <center><lane id="0" type="none" level="false"/></center>
  <right>
    <lane id="-1" type="rail" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane>
  </right>
</laneSection>
```

Use instead:
```xml
<laneSection s="0">
  <center><lane id="0" type="none" level="false"/></center>
  <right>
    <lane id="-1" type="rail" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane>
    <lane id="-2" type="sidewalk" level="false"><width sOffset="0" a="2" b="0" c="0" d="0"/></lane>
  </right>
</laneSection>
```

## Related rules
RL002 judges the centring of a rail lane only in lane sections with exactly one of them.
RL004 reports roads that mix rail and road traffic. Where RL001 is not applied (a file
declaring 1.4 to 1.6), TR001, TR002 and TR007 judge such roads by their joined lanes as
usual.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads"; rule UID
  `asam.net:xodr:1.7.0:road.railroad.one_rail_per_road`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Road, Severity, rule
from xodrlint.rules._shared import metres, quoted
from xodrlint.rules.lanes._templates import judged_once_per_layout


@rule(
    code="RL001",
    name="more-than-one-rail-lane",
    uid="asam.net:xodr:1.7.0:road.railroad.one_rail_per_road",
    severity=Severity.ERROR,
    since=(1, 7),
)
def more_than_one_rail_lane(network: RailNetwork) -> Iterator[Hit]:
    for road, crowded in judged_once_per_layout(network, _crowded_sections):
        for index in crowded:
            section = road.lane_sections[index]
            rails = section.rail_lanes
            ids = ", ".join(quoted(lane.element.get("id")) for lane in rails)
            where = f" at s={metres(section.s)}" if section.s is not None else ""
            yield Hit(
                section.element,
                f"lane section{where} of road {quoted(road.id)} holds {len(rails)} rail "
                f"or tram lanes ({ids}); a track road has one",
            )


def _crowded_sections(template: Road, length: float | None) -> list[int]:
    return [
        index for index, section in enumerate(template.lane_sections) if len(section.rail_lanes) > 1
    ]
