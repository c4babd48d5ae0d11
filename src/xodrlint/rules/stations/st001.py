"""ST001 station-without-platform: a station has no platform.

## What it does
Reports a `station` element that holds no `platform`.

## Why is this bad?
ASAM OpenDRIVE says each station shall have at least one platform: the platform is where
trains stop and what ties the station to the tracks (through its segments). A station
without one is a name without a place.

## Example
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
    </platform>
  </station>
  <station name="Depot" id="S2" type="small"/> <!-- expect: ST001 -->
```

Use instead:
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
    </platform>
  </station>
  <station name="Depot" id="S2" type="small">
    <platform name="Depot platform" id="P2">
      <segment roadId="1" sStart="160" sEnd="200" side="left"/>
    </platform>
  </station>
```

## Related rules
This rule takes over the schema's missing-child error for the same station (XS006 stays
silent on it). ST002 checks that each platform has a segment.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations"; rule UID
  `asam.net:xodr:1.7.0:road.railroad.stations.one_platform_per_station` (alias
  `asam.net:xodr:1.7.0:road.railroad.platforms.min_amount`)
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted


@rule(
    code="ST001",
    name="station-without-platform",
    uid="asam.net:xodr:1.7.0:road.railroad.stations.one_platform_per_station",
    aliases=("asam.net:xodr:1.7.0:road.railroad.platforms.min_amount",),
    severity=Severity.ERROR,
)
def station_without_platform(network: RailNetwork) -> Iterator[Hit]:
    for station in network.stations:
        if not station.platforms:
            yield Hit(station.element, f"station {quoted(station.id)} has no platform")
