"""ST002 platform-without-segment: a platform has no segment.

## What it does
Reports a `platform` element that holds no `segment`.

## Why is this bad?
ASAM OpenDRIVE says each platform shall have at least one segment: segments place the
platform along a track road (which road, which s range, which side). A platform without
a segment is nowhere on the network.

## Example
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
    </platform>
    <platform name="Platform 2" id="P2"/> <!-- expect: ST002 -->
  </station>
```

Use instead:
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
    </platform>
    <platform name="Platform 2" id="P2">
      <segment roadId="1" sStart="60" sEnd="140" side="left"/>
    </platform>
  </station>
```

## Related rules
This rule takes over the schema's missing-child error for the same platform (XS006 stays
silent on it). ST010 checks that some segment lies on a track.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations" (platforms and segments);
  rule UID `asam.net:xodr:1.7.0:road.railroad.platforms.min_segments` (aliases
  `asam.net:xodr:1.7.0:road.railroad.segment.segments_per_platform_min_amount`,
  `asam.net:xodr:1.7.0:road.railroad.segment.segmenta_per_platform_min_amount`)
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted
from xodrlint.rules.stations._walk import platforms_with_station


@rule(
    code="ST002",
    name="platform-without-segment",
    uid="asam.net:xodr:1.7.0:road.railroad.platforms.min_segments",
    aliases=(
        "asam.net:xodr:1.7.0:road.railroad.segment.segments_per_platform_min_amount",
        "asam.net:xodr:1.7.0:road.railroad.segment.segmenta_per_platform_min_amount",
    ),
    severity=Severity.ERROR,
)
def platform_without_segment(network: RailNetwork) -> Iterator[Hit]:
    for platform, station in platforms_with_station(network):
        if not platform.segments:
            yield Hit(
                platform.element,
                f"platform {quoted(platform.id)} of station {quoted(station.id)} has no segment",
            )
