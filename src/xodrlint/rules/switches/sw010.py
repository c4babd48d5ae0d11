"""SW010 side-track-overused: a road is the side track of more than two switches.

## What it does
Reports the `sideTrack` of the third and every later switch (in document order) that
names a road already used as side track by two switches.

## Why is this bad?
ASAM OpenDRIVE says side tracks shall be used to link two switches only. A road that
branches off three switches has no defined pair of partner switches and no defined route.

## Example
```xml
<switch name="W3" id="103" position="dynamic">
  <!-- W1 and W2 already use road 2 as side track -->
  <mainTrack id="3" s="80" dir="-"/>
  <sideTrack id="2" s="20" dir="-"/> <!-- expect: SW010 -->
</switch>
```

Use instead:
```xml
<switch name="W3" id="103" position="dynamic">
  <!-- road 4, not road 2: W1 and W2 already use road 2 -->
  <mainTrack id="3" s="70" dir="+"/>
  <sideTrack id="4" s="0" dir="+"/>
  <partner id="104" name="W4"/>
</switch>
```

## Related rules
PT007 stays silent on a side track SW010 reports (the pairing is undefined there).

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (side track); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.side_track_links_two`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted


@rule(
    code="SW010",
    name="side-track-overused",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.side_track_links_two",
    severity=Severity.ERROR,
)
def side_track_overused(network: RailNetwork) -> Iterator[Hit]:
    for road_id, users in network.switches_by_side_track.items():
        if len(users) < 3:
            continue
        first, second = users[0], users[1]
        for switch in users[2:]:
            if switch.side_track is None:  # grouped by side track, so never; keeps mypy sure
                continue
            yield Hit(
                switch.side_track.element,
                f"road '{road_id}' is already the side track of switches {quoted(first.id)} "
                f"and {quoted(second.id)}; a side track links two switches only",
            )
