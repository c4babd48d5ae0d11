"""PT005 partner-is-self: a switch names itself as its partner.

## What it does
Reports a `partner` whose `@id` is the `@id` of the switch that holds it.

## Why is this bad?
This is an inference: a partner switch is the other switch at the far end of a side
track, and a switch cannot be set together with itself. A self reference is almost always
a copy-and-paste slip that hides the real partner.

## Example
```xml
<switch name="W101" id="101" position="dynamic">
  <mainTrack id="1" s="20" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
  <partner name="W102" id="102"/>
</switch>
<switch name="W102" id="102" position="dynamic">
  <mainTrack id="1" s="80" dir="-"/>
  <sideTrack id="2" s="60.68" dir="-"/>
  <partner name="W102" id="102"/> <!-- expect: PT005 -->
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
On a `partner`, PT001 reports first; SW002, PT004 and PT002 stay silent on a partner
PT005 reports.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (partner); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.partner_not_self`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule


@rule(
    code="PT005",
    name="partner-is-self",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.partner_not_self",
    severity=Severity.ERROR,
    defers_to=("PT001",),
)
def partner_is_self(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        partner = switch.partner
        if partner is not None and partner.id is not None and partner.id == switch.id:
            yield Hit(partner.element, f"switch '{switch.id}' names itself as its partner")
