"""SW003 main-track-not-parent-road: a switch's main track is not the road that holds it.

## What it does
Reports a `mainTrack` whose `@id` differs from the `@id` of the road whose `railroad`
element holds the switch.

## Why is this bad?
A switch is placed on its main track: ASAM OpenDRIVE defines the switch inside the
`railroad` element of the road it sits on, and `mainTrack` names that road again with the
position of the switch on it. A different id places the switch on two roads at once, and
readers disagree about where it is.

## Example
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- this switch is in road 1 -->
  <mainTrack id="3" s="30" dir="+"/> <!-- expect: SW003 -->
  <sideTrack id="2" s="0" dir="+"/>
</switch>
```

Use instead:
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- this switch is in road 1 -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
</switch>
```

## Related rules
When the main track names a road that does not exist, SW004 reports it and SW003 stays
silent (one defect, one finding).

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (main track); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.main_track_is_parent`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted


@rule(
    code="SW003",
    name="main-track-not-parent-road",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.main_track_is_parent",
    severity=Severity.ERROR,
    defers_to=("SW004",),
)
def main_track_not_parent_road(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        main = switch.main_track
        parent = switch.road.id
        if main is None or main.road_id is None or parent is None:
            continue
        if main.road_id != parent:
            yield Hit(
                main.element,
                f"main track of switch {quoted(switch.id)} names road '{main.road_id}', but "
                f"the switch is in road '{parent}'",
            )
