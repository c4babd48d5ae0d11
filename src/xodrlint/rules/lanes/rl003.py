"""RL003 rail-lane-too-narrow: a rail or tram lane is narrower than the track gauge.

## What it does
Reports a lane of type `rail` or `tram` whose width drops below the minimum (1.435 m,
standard gauge, by default) anywhere along its lane section; once per lane section. A
`width` value that is no finite number (`INF`, `-INF`, `NaN`, `1e999`: valid
`xs:double`s the schema may accept) gives no width at all and lies outside every range: it
is reported as written.

The width is computed exactly: each `width` entry is the cubic polynomial it is, on its
whole stretch up to where the next entry starts, and the narrowest point is found where
the polynomial's derivative vanishes, not by sampling.

## Why is this bad?
ASAM OpenDRIVE 1.7 says the width of a rail lane shall cover the track it carries. A
rail lane narrower than the gauge cannot hold the track (a width of 0 or a negative width
makes the lane vanish), and clearance and platform-gap checks built on it go wrong.

## Example
```xml
<center><lane id="0" type="none" level="false"/></center>
<right>
  <lane id="-1" type="rail" level="false"> <!-- expect: RL003 -->
    <width sOffset="0" a="1.5" b="-0.02" c="0.0002" d="0"/>
  </lane>
</right>
```

Use instead:
```xml
<laneSection s="0">
  <center><lane id="0" type="none" level="false"/></center>
  <right>
    <lane id="-1" type="rail" level="false"><width sOffset="0" a="1.435" b="0" c="0" d="0"/></lane>
  </right>
</laneSection>
```

## Options
- `rail-min-width` (metres, default 1.435): the narrowest allowed rail or tram lane. Set
  it for narrow-gauge networks (for example 1.0 for metre gauge). Command line:
  `--rail-min-width`.

## Related rules
A lane described by `border` instead of `width`, or with an unreadable coefficient, is
not judged; the schema (XS006) reports unreadable values.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads" and chapter "Lanes" (lane width); rule UID
  `asam.net:xodr:1.7.0:road.railroad.rail_lane_width_validity`
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Final, NamedTuple

from xodrlint.rules import (
    S_TOLERANCE,
    Hit,
    RailNetwork,
    Road,
    RuleOption,
    Settings,
    Severity,
    extremes,
    lane_width,
    rule,
)
from xodrlint.rules._shared import first_non_finite, metres
from xodrlint.rules.lanes._labels import lane_label
from xodrlint.rules.lanes._templates import judged_once_per_layout, own_lane, ranged_sections

MIN_WIDTH: Final = RuleOption(
    name="rail-min-width",
    default=1.435,
    description="Narrowest allowed rail or tram lane (standard gauge by default)",
)


@rule(
    code="RL003",
    name="rail-lane-too-narrow",
    uid="asam.net:xodr:1.7.0:road.railroad.rail_lane_width_validity",
    severity=Severity.ERROR,
    options=(MIN_WIDTH,),
)
def rail_lane_too_narrow(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    minimum = MIN_WIDTH.number(settings)

    def narrowest(template: Road, length: float | None) -> list[_Narrow]:
        found = []
        for index, section, start, end in ranged_sections(template, length):
            for lane_index, lane in enumerate(section.lanes):
                if not lane.is_rail:
                    continue
                written = first_non_finite(lane.element.iterchildren("width"), _WIDTH_VALUES)
                if written is not None:  # no width at all, and no range holds it
                    found.append(_Narrow(index, lane_index, start, math.nan, start, written))
                    continue
                width = lane_width(lane, start)
                low = extremes([(1.0, width)], start, end) if width is not None else None
                if low is not None and low.low < minimum - S_TOLERANCE:
                    found.append(_Narrow(index, lane_index, start, low.low, low.s_low))
        return found

    for road, narrow in judged_once_per_layout(network, narrowest, by_length=True):
        for found in narrow:
            _, lane = own_lane(road, found.section, found.lane)
            label = lane_label(lane, road, found.start)
            if found.written is not None:
                message = f"{lane.type} {label} has a width entry with {found.written}, no width"
            else:
                message = (
                    f"{lane.type} {label} is {metres(found.width)} m wide at "
                    f"s={metres(found.s)}, narrower than {metres(minimum)} m"
                )
            yield Hit(lane.element, message)


class _Narrow(NamedTuple):
    section: int
    lane: int
    start: float
    width: float
    s: float
    written: str | None = None
    """A width value that is no finite number, as written (``a=INF``)."""


_WIDTH_VALUES: Final = ("sOffset", "a", "b", "c", "d")
