"""ST008 station-name-duplicate: two stations share a name.

## What it does
Reports every `station` whose `@name` an earlier station of the file already has, naming
the first one.

## Why is this bad?
ASAM OpenDRIVE describes `station/@name` as the unique name of the station, although the
schema does not key it. Passengers, timetables and scenario authors know stations by
name; two stations of one name send them to the wrong one.

## Example
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
    </platform>
  </station>
  <station name="Central" id="S2" type="small"> <!-- expect: ST008 -->
    <platform name="Platform 2" id="P2">
      <segment roadId="2" sStart="60" sEnd="140" side="right"/>
    </platform>
  </station>
```

Use instead:
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
    </platform>
  </station>
  <station name="North" id="S2" type="small">
    <platform name="Platform 2" id="P2">
      <segment roadId="2" sStart="60" sEnd="140" side="right"/>
    </platform>
  </station>
```

## Related rules
ST007 checks station ids.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations" (`name`: unique name of the
  station); rule UID `xodrlint:xodr:1.4.0:road.railroad.stations.name_unique`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import later_duplicates, quoted


@rule(
    code="ST008",
    name="station-name-duplicate",
    uid="xodrlint:xodr:1.4.0:road.railroad.stations.name_unique",
    severity=Severity.WARNING,
)
def station_name_duplicate(network: RailNetwork) -> Iterator[Hit]:
    for station, first in later_duplicates(network.stations, lambda st: st.name):
        yield Hit(
            station.element,
            f"station name '{station.name}' is already used by station {quoted(first.id)}",
            related=(first.element,),
        )
