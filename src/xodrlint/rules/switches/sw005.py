"""SW005 track-s-out-of-range: a switch's main or side track position lies off its road.

## What it does
Reports a `mainTrack` or `sideTrack` whose `@s` lies outside `[0, length]` of the road it
names (with a tolerance of 1e-6 m). A value that is no finite number (`INF`, `-INF`,
`NaN`, or a numeral too large for a double such as `1e999`) is a valid `xs:double`, so
the schema may accept it; it lies outside every range and is reported as written
(unless the schema rule already reports the value: `-INF` where s must not be negative).

## Why is this bad?
This is an inference: the standard defines `s` of a track as the position of the switch
on that road, and an s-coordinate only has a meaning between 0 and the road's `@length`.
A position past the end cannot be placed, so the switch floats in space.

## Example
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- road 1 is 100 m long, road 2 is 20 m long -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="60" dir="-"/> <!-- expect: SW005 -->
</switch>
```

Use instead:
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- road 1 is 100 m long, road 2 is 20 m long -->
  <mainTrack id="1" s="0" dir="+"/>
  <sideTrack id="2" s="20" dir="-"/>
</switch>
```

## Options
- `s-tolerance` (metres, default 1e-06): the largest difference between two
  s-coordinates or lengths that counts as none; 0.0005 for data rounded to
  millimetres. Configuration: `s-tolerance = 0.0005` in `[tool.xodrlint]`; command
  line: `--rule-option s-tolerance=0.0005`.

## Related rules
SW004 reports a track that names an unknown road; SW005 cannot judge that one. SW006
stays silent on a side track SW005 reports.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches"; rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.s_in_road_range`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

from xodrlint.rules import Hit, RailNetwork, Settings, Severity, non_finite, rule
from xodrlint.rules._shared import S_TOLERANCE_OPTION, metres, quoted, within
from xodrlint.rules.switches._tracks import named_road, track_refs

_AFTER_THE_SCHEMA: Final = ("SW004", "XS006")


@rule(
    code="SW005",
    name="track-s-out-of-range",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.s_in_road_range",
    severity=Severity.ERROR,
    defers_to=("SW004",),
    options=(S_TOLERANCE_OPTION,),
)
def track_s_out_of_range(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    tolerance = S_TOLERANCE_OPTION.number(settings)
    for switch in network.switches:
        for kind, track in track_refs(switch):
            road = named_road(network, track)
            if road is None:
                continue
            where = f"{kind} of switch {quoted(switch.id)}"
            written = non_finite(track.element, "s") if track.s is None else None
            if written is not None:  # no range holds it, whatever the road's length
                span = f" (0 to {metres(road.length)})" if road.length is not None else ""
                yield Hit(
                    track.element,
                    f"{where} is at s={written}, outside road '{road.id}'{span}",
                    # where the schema refuses the value too (-INF, blanks): one finding
                    defers_to=_AFTER_THE_SCHEMA,
                )
            elif (
                road.length is not None
                and track.s is not None
                and not within(track.s, 0.0, road.length, tolerance)
            ):
                yield Hit(
                    track.element,
                    f"{where} is at s={metres(track.s)}, outside road '{road.id}' "
                    f"(0 to {metres(road.length)})",
                )
