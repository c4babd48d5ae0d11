"""SW009 track-not-rail: a switch's main or side track is a road without a rail or tram lane.

## What it does
Reports a `mainTrack` or `sideTrack` that names a road with no lane of type `rail` or
`tram` in any lane section.

## Why is this bad?
This is an inference: switches connect railroad tracks, and the standard models a track
as a road whose lane is of type `rail` or `tram`. A switch onto a road without one leads
trains onto a road they cannot run on, which usually means a wrong id or a missing lane
type.

## Example
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- road 2 has a driving lane only -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/> <!-- expect: SW009 -->
</switch>
```

Use instead:
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- roads 1 and 2 have a rail lane -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
</switch>
```

## Related rules
SW004 reports a track that names an unknown road; SW009 cannot judge that one.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads" and section "Lane type"; rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.track_is_rail`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted
from xodrlint.rules.switches._tracks import named_road, track_refs


@rule(
    code="SW009",
    name="track-not-rail",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.track_is_rail",
    severity=Severity.WARNING,
    defers_to=("SW004",),
)
def track_not_rail(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        for kind, track in track_refs(switch):
            road = named_road(network, track)
            if road is not None and not road.has_rail_lane:
                yield Hit(
                    track.element,
                    f"{kind} of switch {quoted(switch.id)} names road '{road.id}', which has "
                    "no rail or tram lane",
                )
