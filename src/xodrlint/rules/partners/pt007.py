"""PT007 linked-switches-not-partners: two switches share a side track but are not partners.

## What it does
Reports two switches whose `sideTrack` elements name the same road while neither names
the other as its `partner`; once per pair, on the `sideTrack` of the later switch (a
third or later switch on the same road gets one finding, naming the first of the two
earlier switches it is not paired with).

## Why is this bad?
ASAM OpenDRIVE says partner switches shall be used to indicate that a side track links
two switches. Without the partner relation, readers see two unrelated switches and may
set one end of a crossover without the other.

## Example
```xml
<switch name="W101" id="101" position="dynamic">
  <mainTrack id="1" s="20" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
</switch>
<switch name="W102" id="102" position="dynamic">
  <mainTrack id="1" s="80" dir="-"/>
  <sideTrack id="2" s="60.68" dir="-"/> <!-- expect: PT007 -->
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
SW010 reports the third and later switches on one side track; PT007 stays silent on a
`sideTrack` SW010 reports.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (partner switches); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.linked_switches_are_partners`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, Switch, rule
from xodrlint.rules._shared import quoted


def _names(switch: Switch, other: Switch) -> bool | None:
    """Whether ``switch`` names ``other`` as partner; ``None`` when a missing id hides it."""
    if switch.partner is None:
        return False
    if switch.partner.id is None or other.id is None:
        return None
    return switch.partner.id == other.id


@rule(
    code="PT007",
    name="linked-switches-not-partners",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.linked_switches_are_partners",
    severity=Severity.WARNING,
    defers_to=("SW010",),
)
def linked_switches_not_partners(network: RailNetwork) -> Iterator[Hit]:
    for road_id, users in network.switches_by_side_track.items():
        for index, later in enumerate(users):
            if later.side_track is None:
                continue
            # Past the second switch the road is overused (SW010): one finding per side
            # track is enough there, and comparing with the first two keeps this linear.
            for first in users[: min(index, 2)]:
                if _names(first, later) is False and _names(later, first) is False:
                    yield Hit(
                        later.side_track.element,
                        f"switches {quoted(first.id)} and {quoted(later.id)} share side track "
                        f"road '{road_id}', but neither names the other as partner",
                    )
                    break
