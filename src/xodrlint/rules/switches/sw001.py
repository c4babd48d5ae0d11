"""SW001 main-track-connects-switches: a switch's side track is another switch's main track.

## What it does
Reports a `sideTrack` that names a road which is the `mainTrack` of another switch.

## Why is this bad?
ASAM OpenDRIVE 1.7 says a main track shall not be used to connect two switches: the road
that links two switches is a side track, and a main track is the through route a switch
sits on. A road that is both breaks the track topology that simulators and interlocking
models derive from the switches.

## Example
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- road 2 is the main track of switch W2 -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/> <!-- expect: SW001 -->
</switch>
```

Use instead:
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- road 2 only links W1 and W2: it is the main track of no switch -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
  <partner id="102" name="W2"/>
</switch>
```

## Related rules
SW010 reports a side track used by more than two switches; PT007 reports two switches on
one side track that are not partners.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (main track); rule UID
  `asam.net:xodr:1.7.0:road.railroad.switch.check_switch_conn`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted


@rule(
    code="SW001",
    name="main-track-connects-switches",
    uid="asam.net:xodr:1.7.0:road.railroad.switch.check_switch_conn",
    severity=Severity.ERROR,
)
def main_track_connects_switches(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        side = switch.side_track
        if side is None or side.road_id is None:
            continue
        for other in network.switches_by_main_track.get(side.road_id, ()):
            if other is not switch and other.main_track is not None:
                yield Hit(
                    side.element,
                    f"side track road '{side.road_id}' of switch {quoted(switch.id)} is the "
                    f"main track of switch {quoted(other.id)}",
                    related=(other.main_track.element,),
                )
                break
