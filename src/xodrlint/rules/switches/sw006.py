"""SW006 side-track-not-at-end: a side track does not start at an end of its road, pointing onto it.

## What it does
Reports a `sideTrack` whose `@s` is neither 0 nor the length of the side track road
(tolerance 1e-6 m), or whose `@dir` points off the road: at s = 0 the side track must run
in `+` direction, at s = length in `-` direction.

## Why is this bad?
This is an inference from the standard's description and its examples: a side track is
the road that branches off at the switch, so the switch sits where that road begins or
ends, and the direction says which way a train leaves the switch along it. A side track
that starts in the middle of its road, or points off its end, describes a branch no train
can take.

## Example
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- road 2 is 20 m long -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="10" dir="+"/> <!-- expect: SW006 -->
</switch>
```

Use instead:
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- road 2 is 20 m long: it starts here -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
  <partner id="102" name="W2"/>
</switch>
```

## Related rules
SW004 (unknown road) and SW005 (s outside the road) report first; SW006 stays silent on
a side track they report.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (side track); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.side_track_at_end`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.findings import Hit, Severity
from xodrlint.model import RailNetwork
from xodrlint.model.lane_profiles import S_TOLERANCE
from xodrlint.rules import rule
from xodrlint.rules._shared import metres, quoted
from xodrlint.rules.switches._tracks import named_road


@rule(
    code="SW006",
    name="side-track-not-at-end",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.side_track_at_end",
    severity=Severity.WARNING,
    defers_to=("SW004", "SW005"),
)
def side_track_not_at_end(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        side = switch.side_track
        road = named_road(network, side) if side is not None else None
        if side is None or road is None or road.length is None or side.s is None:
            continue
        at_start = abs(side.s) <= S_TOLERANCE
        at_end = abs(side.s - road.length) <= S_TOLERANCE
        where = f"side track of switch {quoted(switch.id)}"
        if not at_start and not at_end:
            yield Hit(
                side.element,
                f"{where} is at s={metres(side.s)} of road '{road.id}', not at its start (0) "
                f"or end ({metres(road.length)})",
            )
        elif at_start != at_end and side.dir in ("+", "-"):
            expected = "+" if at_start else "-"
            if side.dir != expected:
                end = "start" if at_start else "end"
                yield Hit(
                    side.element,
                    f"{where} is at the {end} of road '{road.id}' but points '{side.dir}', "
                    f"off the road (expected '{expected}')",
                )
