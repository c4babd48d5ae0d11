"""PT003 partner-name-mismatch: a partner's name differs from the name of the switch it names.

## What it does
Reports a `partner` that has a `@name` which differs from the `@name` of the switch its
`@id` names.

## Why is this bad?
This is an inference: `partner/@name` repeats the name of the partner switch for readers
that go by names. When it disagrees with the switch the id names, one of the two is wrong,
and tools that resolve by name reach another switch than tools that resolve by id.

## Example
```xml
<switch name="W101" id="101" position="dynamic">
  <mainTrack id="1" s="20" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
  <partner name="W201" id="102"/> <!-- expect: PT003 -->
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

## Fix
Safe: `xodrlint check --fix` sets `partner/@name` to the `@name` of the switch that
`partner/@id` names (only where that switch has a name).

## Related rules
Stands alone: a wrong partner name is its own defect, also when another rule reports the
same partner. PT001 reports a partner id that names no switch (PT003 cannot compare then).

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (partner); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.partner_name_matches`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Fix, Hit, RailNetwork, Severity, rule, set_attribute
from xodrlint.rules._shared import quoted


@rule(
    code="PT003",
    name="partner-name-mismatch",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.partner_name_matches",
    severity=Severity.WARNING,
)
def partner_name_mismatch(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        partner = switch.partner
        if partner is None or partner.id is None or partner.name is None:
            continue
        named = network.switch_by_id.get(partner.id)
        if named is not None and named.name is not None and named.name != partner.name:
            yield Hit(
                partner.element,
                f"partner of switch {quoted(switch.id)} is named '{partner.name}', but switch "
                f"'{partner.id}' is named '{named.name}'",
                related=(named.element,),
                fix=Fix(
                    f"name the partner '{named.name}'",
                    (set_attribute(partner.element, "name", named.name),),
                ),
            )
