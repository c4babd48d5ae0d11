"""SW002 single-switch-has-partner: a switch names a partner but no other switch shares its side track.

## What it does
Reports the `partner` of a switch whose side track road is the `sideTrack` of no other
switch: a single switch, which has no partner. Silent when the switch the partner names
has no side track, or one without an id: its road may well be this one.

## Why is this bad?
Partner switches are two switches linked by one side track (a crossover). A switch whose
side track leads nowhere near another switch is a single switch, and ASAM OpenDRIVE 1.7
says a single switch shall not have a partner: readers would set a switch that is not
there.

## Example
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- no other switch uses road 2: W2 branches off to road 4 -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
  <partner id="102" name="W2"/> <!-- expect: SW002 -->
</switch>
```

Use instead:
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- no other switch uses road 2 -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
</switch>
```

## Related rules
On a `partner`, PT001 (unknown id) and PT005 (the switch itself) report first; SW002
stays silent then. PT004 and PT002 stay silent on a partner SW002 reports.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (partner switches); rule UID
  `asam.net:xodr:1.7.0:road.railroad.switch.single_switch_no_partner`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted


@rule(
    code="SW002",
    name="single-switch-has-partner",
    uid="asam.net:xodr:1.7.0:road.railroad.switch.single_switch_no_partner",
    severity=Severity.ERROR,
    defers_to=("PT001", "PT005"),
)
def single_switch_has_partner(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        side = switch.side_track
        if switch.partner is None or side is None or side.road_id is None:
            continue
        named = network.switch_by_id.get(switch.partner.id) if switch.partner.id else None
        if named is not None and (named.side_track is None or named.side_track.road_id is None):
            continue  # the partner's side track is unknown: it may well be this one
        users = network.switches_by_side_track.get(side.road_id, ())
        if all(user is switch for user in users):
            yield Hit(
                switch.partner.element,
                f"switch {quoted(switch.id)} names partner {quoted(switch.partner.id)}, but no "
                f"other switch uses its side track road '{side.road_id}'",
            )
