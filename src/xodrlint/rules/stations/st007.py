"""ST007 station-id-duplicate: two stations share an id.

## What it does
Reports every `station` whose `@id` an earlier station of the file already has, naming
the first one.

## Why is this bad?
ASAM OpenDRIVE requires ids to be unique within their class. Timetables, scenarios and
signalling data refer to a station by its id; two stations of one id make every such
reference ambiguous.

## Example
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
    </platform>
  </station>
  <station name="North" id="S1" type="small"> <!-- expect: ST007 -->
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
This rule takes over the schema's duplicate-key error for the same station (XS006 stays
silent on it). ST008 checks station names, ST009 platform ids.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations"; rule UID
  `asam.net:xodr:1.4.0:ids.id_unique_in_class`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import later_duplicates, quoted


@rule(
    code="ST007",
    name="station-id-duplicate",
    uid="asam.net:xodr:1.4.0:ids.id_unique_in_class",
    severity=Severity.ERROR,
)
def station_id_duplicate(network: RailNetwork) -> Iterator[Hit]:
    for station, first in later_duplicates(network.stations, lambda st: st.id):
        yield Hit(
            station.element,
            f"station id '{station.id}' is already used by station {quoted(first.name)}",
            related=(first.element,),
        )
