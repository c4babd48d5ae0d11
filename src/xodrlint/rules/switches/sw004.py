"""SW004 track-road-undefined: a switch's main or side track names a road that does not exist.

## What it does
Reports a `mainTrack` or `sideTrack` whose `@id` is the id of no road in the file.

## Why is this bad?
ASAM OpenDRIVE requires every reference to name a defined id; the schema declares the
track ids as references to road ids. A switch that leads to a road that is not there cuts
the track network at that switch.

## Example
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- the file has roads 1 and 2 -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="5" s="0" dir="+"/> <!-- expect: SW004 -->
</switch>
```

Use instead:
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- the file has roads 1 and 2 -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
</switch>
```

## Related rules
This rule also takes over the schema's keyref error for the same reference (XS006 stays
silent on it). With an unknown road, SW005, SW006 and SW009 cannot judge the track and
stay silent; SW003 would also see a main track naming an unknown road (it differs from the
parent road) and defers to SW004, since the one defect is the broken reference.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches"; rule UID
  `asam.net:xodr:1.4.0:ids.only_ref_defined_ids`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted
from xodrlint.rules.switches._tracks import track_refs


@rule(
    code="SW004",
    name="track-road-undefined",
    uid="asam.net:xodr:1.4.0:ids.only_ref_defined_ids",
    severity=Severity.ERROR,
)
def track_road_undefined(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        for kind, track in track_refs(switch):
            if track.road_id is not None and track.road_id not in network.road_by_id:
                yield Hit(
                    track.element,
                    f"{kind} of switch {quoted(switch.id)} names road '{track.road_id}', "
                    "which does not exist",
                )
