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

## Options
- `s-tolerance` (metres, default 1e-06): the largest difference between two
  s-coordinates or lengths that counts as none; 0.0005 for data rounded to
  millimetres. Configuration: `s-tolerance = 0.0005` in `[tool.xodrlint]`; command
  line: `--rule-option s-tolerance=0.0005`.

## Fix
Unsafe: `xodrlint check --fix --unsafe-fixes` moves `sideTrack/@s` to the nearer end of
the side track's road (0, or the road's `@length` as written) and sets `@dir` to the
direction that leads onto the road from there (`+` at its start, `-` at its end). A side
track halfway along its road gets no fix.

## Related rules
SW004 (unknown road) and SW005 (s outside the road, or no finite number such as `INF`)
report first; SW006 stays silent on a side track they report.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (side track); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.side_track_at_end`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import (
    Applicability,
    Fix,
    Hit,
    RailNetwork,
    Road,
    Settings,
    Severity,
    TrackRef,
    rule,
    set_attribute,
)
from xodrlint.rules._shared import S_TOLERANCE_OPTION, quoted
from xodrlint.rules.switches._tracks import named_road, side_track_problem


@rule(
    code="SW006",
    name="side-track-not-at-end",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.side_track_at_end",
    severity=Severity.WARNING,
    defers_to=("SW004", "SW005"),
    options=(S_TOLERANCE_OPTION,),
)
def side_track_not_at_end(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    tolerance = S_TOLERANCE_OPTION.number(settings)
    for switch in network.switches:
        side = switch.side_track
        road = named_road(network, side) if side is not None else None
        problem = (
            side_track_problem(road, side, tolerance)
            if side is not None and road is not None
            else None
        )
        if side is not None and road is not None and problem is not None:
            yield Hit(
                side.element,
                f"side track of switch {quoted(switch.id)} {problem}",
                fix=_to_the_nearer_end(road, side, tolerance),
            )


def _to_the_nearer_end(road: Road, side: TrackRef, tolerance: float) -> Fix | None:
    """The side track moved to the nearer end of its road (``s`` 0, or the road's length
    as the road writes it) and pointed onto the road from there (``+`` at its start,
    ``-`` at its end); none where both ends are as near."""
    length, s = road.length, side.s
    if length is None or s is None or abs(s - length / 2) <= tolerance:
        return None
    at_start = s < length / 2
    position = "0" if at_start else road.element.get("length", "")
    direction = "+" if at_start else "-"
    edits = []
    if abs(s - (0.0 if at_start else length)) > tolerance:
        edits.append(set_attribute(side.element, "s", position))
    if side.dir != direction:
        edits.append(set_attribute(side.element, "dir", direction))
    end = "start" if at_start else "end"
    return Fix(
        f"put the side track at the {end} of road '{road.id}' (s={position}), pointing "
        f"'{direction}'",
        tuple(edits),
        Applicability.UNSAFE,
    )
