"""SW007 switch-id-duplicate: two switches share an id.

## What it does
Reports every switch whose `@id` an earlier switch of the file already has, naming the
first one.

## Why is this bad?
ASAM OpenDRIVE requires ids to be unique within their class; partner references and
external tools (interlocking tables, scenario files) address a switch by its id. With two
switches of one id, every reference to it is ambiguous.

## Example
```xml
<switch name="W2" id="101" position="dynamic"> <!-- expect: SW007 -->
  <!-- switch W1 in road 1 already has id 101 -->
  <mainTrack id="3" s="50" dir="-"/>
  <sideTrack id="4" s="0" dir="+"/>
</switch>
```

Use instead:
```xml
<switch name="W2" id="102" position="dynamic">
  <!-- switch W1 in road 1 has id 101 -->
  <mainTrack id="3" s="50" dir="-"/>
  <sideTrack id="2" s="20" dir="-"/>
  <partner id="101" name="W1"/>
</switch>
```

## Related rules
This rule takes over the schema's duplicate-key error for the same switch (XS006 stays
silent on it). SW008 checks the names.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches"; rule UID
  `asam.net:xodr:1.4.0:ids.id_unique_in_class`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import later_duplicates, quoted


@rule(
    code="SW007",
    name="switch-id-duplicate",
    uid="asam.net:xodr:1.4.0:ids.id_unique_in_class",
    severity=Severity.ERROR,
)
def switch_id_duplicate(network: RailNetwork) -> Iterator[Hit]:
    for switch, first in later_duplicates(network.switches, lambda sw: sw.id):
        yield Hit(
            switch.element,
            f"switch id '{switch.id}' is already used by switch {quoted(first.name)} in road "
            f"{quoted(first.road.id)}",
            related=(first.element,),
        )
