"""PT001 partner-undefined: a switch's partner names no switch of the file.

## What it does
Reports a `partner` whose `@id` is the id of no switch in the file.

## Why is this bad?
ASAM OpenDRIVE requires every reference to name a defined id. A partner that does not
exist leaves the crossover half built: the other end of the side track has no switch to
set together with this one.

## Example
```xml
<switch name="W101" id="101" position="dynamic">
  <mainTrack id="1" s="20" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
  <partner name="W102" id="120"/> <!-- expect: PT001 -->
</switch>
<switch name="W102" id="102" position="dynamic">
  <mainTrack id="1" s="80" dir="-"/>
  <sideTrack id="2" s="60.68" dir="-"/>
  <partner name="W101" id="101"/>
</switch>
```

Use instead:
```xml
<switch name="W101" id="101" position="dynamic">
  <mainTrack id="1" s="20" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
  <partner name="W102" id="102"/>
</switch>
<switch name="W102" id="102" position="dynamic">
  <mainTrack id="1" s="80" dir="-"/>
  <sideTrack id="2" s="60.68" dir="-"/>
  <partner name="W101" id="101"/>
</switch>
```

## Related rules
First in the chain on a `partner`: PT005, SW002, PT004 and PT002 stay silent on a partner
PT001 reports. This rule also takes over the schema's keyref error for the same partner
(XS006 stays silent on it).

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (partner); rule UID
  `asam.net:xodr:1.4.0:ids.only_ref_defined_ids`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted


@rule(
    code="PT001",
    name="partner-undefined",
    uid="asam.net:xodr:1.4.0:ids.only_ref_defined_ids",
    severity=Severity.ERROR,
)
def partner_undefined(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        partner = switch.partner
        if partner is None or partner.id is None:
            continue
        if partner.id not in network.switch_by_id:
            yield Hit(
                partner.element,
                f"partner '{partner.id}' of switch {quoted(switch.id)} names no switch",
            )
