"""ST009 platform-id-duplicate: two platforms share an id.

## What it does
Reports every `platform` whose `@id` an earlier platform of the file already has, in the
same station or another one, naming the first one.

## Why is this bad?
ASAM OpenDRIVE requires ids to be unique within their class, and platforms are one class
across the whole file, not per station. Stopping points and timetables refer to a
platform by its id.

## Example
```xml
  <!-- platform ids are unique in the whole file, not per station -->
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
    </platform>
  </station>
  <station name="North" id="S2" type="small">
    <platform name="Platform 1" id="1"> <!-- expect: ST009 -->
      <segment roadId="2" sStart="60" sEnd="140" side="right"/>
    </platform>
  </station>
```

Use instead:
```xml
  <station name="Central" id="S1" type="medium">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
    </platform>
    <platform name="Platform 2" id="P2">
      <segment roadId="2" sStart="60" sEnd="140" side="right"/>
    </platform>
  </station>
  <station name="North" id="S2" type="small">
    <platform name="Platform 3" id="P3">
      <segment roadId="1" sStart="60" sEnd="140" side="left"/>
    </platform>
  </station>
```

## Related rules
This rule takes over the schema's duplicate-key error for the same platform (XS006 stays
silent on it). ST007 checks station ids.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations" (platforms); rule UID
  `asam.net:xodr:1.4.0:ids.id_unique_in_class`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import later_duplicates, quoted
from xodrlint.rules.stations._walk import platforms_with_station


@rule(
    code="ST009",
    name="platform-id-duplicate",
    uid="asam.net:xodr:1.4.0:ids.id_unique_in_class",
    severity=Severity.ERROR,
)
def platform_id_duplicate(network: RailNetwork) -> Iterator[Hit]:
    pairs = later_duplicates(platforms_with_station(network), lambda pair: pair[0].id)
    for (platform, _), (first, station) in pairs:
        yield Hit(
            platform.element,
            f"platform id '{platform.id}' is already used by a platform of station "
            f"{quoted(station.id)}",
            related=(first.element,),
        )
