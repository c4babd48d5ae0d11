"""SW008 switch-name-duplicate: two switches share a name.

## What it does
Reports every switch whose `@name` an earlier switch of the file already has, naming the
first one.

## Why is this bad?
ASAM OpenDRIVE describes `@name` as the unique name of the switch, and a `partner` may
name its switch by it. Switch names are what operators and interlocking tables use; two
switches of one name make those references ambiguous.

## Example
```xml
<switch name="W1" id="102" position="dynamic"> <!-- expect: SW008 -->
  <!-- switch 101 in road 1 is already named W1 -->
  <mainTrack id="3" s="50" dir="-"/>
  <sideTrack id="4" s="0" dir="+"/>
</switch>
```

Use instead:
```xml
<switch name="W2" id="102" position="dynamic">
  <!-- switch 101 in road 1 is named W1 -->
  <mainTrack id="3" s="50" dir="-"/>
  <sideTrack id="2" s="20" dir="-"/>
  <partner id="101" name="W1"/>
</switch>
```

## Related rules
This rule takes over a schema duplicate-key error on the switch name where the schema
keys it (XS006 stays silent then). SW007 checks the ids; PT003 checks that a partner's
name matches its switch.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (`name`: unique name of the
  switch); rule UID `xodrlint:xodr:1.4.0:road.railroad.switch.name_unique`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import later_duplicates, quoted


@rule(
    code="SW008",
    name="switch-name-duplicate",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.name_unique",
    severity=Severity.ERROR,
)
def switch_name_duplicate(network: RailNetwork) -> Iterator[Hit]:
    for switch, first in later_duplicates(network.switches, lambda sw: sw.name):
        yield Hit(
            switch.element,
            f"switch name '{switch.name}' is already used by switch {quoted(first.id)}",
            related=(first.element,),
        )
