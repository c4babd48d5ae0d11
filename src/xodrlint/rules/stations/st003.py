"""ST003 segment-road-undefined: a platform segment names a road that does not exist.

## What it does
Reports a `segment` whose `@roadId` is the id of no road in the file.

## Why is this bad?
ASAM OpenDRIVE requires every reference to name a defined id; the schema declares
`segment/@roadId` as a reference to a road id. A segment on a missing road puts its
platform nowhere.

## Example
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
      <segment roadId="9" sStart="0" sEnd="40" side="right"/> <!-- expect: ST003 -->
    </platform>
  </station>
```

Use instead:
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
      <segment roadId="2" sStart="0" sEnd="40" side="right"/>
    </platform>
  </station>
```

## Related rules
This rule takes over the schema's keyref error for the same segment (XS006 stays silent
on it). With an unknown road, ST004 and ST010 cannot judge the segment and stay silent.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations" (segments); rule UID
  `asam.net:xodr:1.4.0:ids.only_ref_defined_ids`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted
from xodrlint.rules.stations._walk import segments_with_platform


@rule(
    code="ST003",
    name="segment-road-undefined",
    uid="asam.net:xodr:1.4.0:ids.only_ref_defined_ids",
    severity=Severity.ERROR,
)
def segment_road_undefined(network: RailNetwork) -> Iterator[Hit]:
    for segment, platform in segments_with_platform(network):
        if segment.road_id is not None and segment.road_id not in network.road_by_id:
            yield Hit(
                segment.element,
                f"segment of platform {quoted(platform.id)} names road '{segment.road_id}', "
                "which does not exist",
            )
