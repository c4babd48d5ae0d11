"""ST010 platform-not-on-track: no segment of a platform lies on a track road.

## What it does
Reports a `platform` none of whose segments lies on a road with a lane of type `rail` or
`tram`. A platform all of whose segment roads carry a `bus` lane is a bus stop, which the
standard allows, and is not reported.

## Why is this bad?
ASAM OpenDRIVE says a platform shall be referenced by one or more railroad tracks. A
platform whose segments all lie on ordinary roads is not served by any train; usually a
segment names the wrong road or the track's lane type is missing.

## Example
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
    </platform>
    <platform name="Platform 2" id="P2"> <!-- expect: ST010 -->
      <segment roadId="3" sStart="20" sEnd="80" side="right"/>
    </platform>
  </station>
```

Use instead:
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
    </platform>
    <platform name="Platform 2" id="P2">
      <segment roadId="2" sStart="20" sEnd="80" side="right"/>
    </platform>
  </station>
```

## Related rules
ST002 reports a platform without segments, ST003 a segment on an unknown road: while a
segment's road is unknown, ST010 cannot judge the platform and stays silent.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations" (platforms); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.platforms.on_track`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted
from xodrlint.rules.stations._walk import platforms_with_station

BUS_LANE: Final = "bus"


@rule(
    code="ST010",
    name="platform-not-on-track",
    uid="xodrlint:xodr:1.4.0:road.railroad.platforms.on_track",
    severity=Severity.WARNING,
)
def platform_not_on_track(network: RailNetwork) -> Iterator[Hit]:
    for platform, station in platforms_with_station(network):
        if not platform.segments:
            continue
        roads = [
            network.road_by_id.get(segment.road_id) if segment.road_id is not None else None
            for segment in platform.segments
        ]
        known = [road for road in roads if road is not None]
        if len(known) < len(roads) or any(road.has_rail_lane for road in known):
            continue
        if all(BUS_LANE in road.lane_types for road in known):
            continue
        names = ", ".join(sorted({f"'{road.id}'" for road in known}))
        yield Hit(
            platform.element,
            f"platform {quoted(platform.id)} of station {quoted(station.id)} lies only on "
            f"roads without a rail or tram lane ({names})",
        )
