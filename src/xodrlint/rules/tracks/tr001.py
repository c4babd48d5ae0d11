"""TR001 track-link-gap: two linked tracks do not meet where the link joins them.

## What it does
Reports a road link (`link/predecessor` or `link/successor` with `elementType="road"`)
between two roads with a rail or tram lane whose joined ends are more than the tolerance
(default 0.10 m) apart. The ends are this road's start for a predecessor and its end for a
successor, and the other road's start or end as `contactPoint` says; each is taken at
the road's track point (the centre of its single rail or tram lane, or the reference
line). A joint is reported once: on the link of the road that comes first in the
document when both roads name each other.

## Why is this bad?
This is an inference from the standard's road linkage: a link says that a vehicle leaving
one road through that end enters the other road through the named contact point, so
both ends must be the same place. Road vehicles can absorb a small gap on a wide lane; a
train cannot: a gap between two tracks is a gap in the rails, and a simulator that moves
a train along the link jumps it across.

## Example
```xml
<link>
  <!-- road 1 ends at (100, 0); road 2 starts at (100.15, 0) -->
  <successor elementType="road" elementId="2" contactPoint="start"/> <!-- expect: TR001 -->
</link>
```

Use instead:
```xml
<link>
  <!-- road 1 ends at (100, 0); road 2 starts there -->
  <successor elementType="road" elementId="2" contactPoint="start"/>
</link>
```

## Options
- `link-tolerance` (metres, default 0.1): the largest distance allowed between the two
  track points of a joint. Configuration: `link-tolerance = 0.1` in `[tool.xodrlint]`;
  command line: `--rule-option link-tolerance=0.1`.

## Related rules
TR002 reports the directions at the same joints. Links to junctions, and links between a
rail road and a road without a rail or tram lane, are not judged. A road whose plan view
cannot be evaluated is left alone (XS006 reports bad values).

## References
- ASAM OpenDRIVE 1.7, chapter "Roads", section "Road linkage", and chapter "Railroads"; rule
  UID `xodrlint:xodr:1.4.0:road.railroad.track.link_gap`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

from xodrlint.findings import Hit, RuleOption, Severity
from xodrlint.model import RailNetwork
from xodrlint.rules import Settings, rule
from xodrlint.rules._shared import S_TOLERANCE, beyond, point
from xodrlint.rules.tracks._joints import joints

TOLERANCE: Final = RuleOption(
    name="link-tolerance",
    default=0.1,
    description="Largest distance between the track points of two linked rail roads",
)


@rule(
    code="TR001",
    name="track-link-gap",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.link_gap",
    severity=Severity.ERROR,
    options=(TOLERANCE,),
)
def track_link_gap(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    tolerance = TOLERANCE.number(settings)
    for joint in joints(network):
        first, second = joint.first_point, joint.second_point
        distance = first.distance_to(second)
        if distance > tolerance + S_TOLERANCE:
            yield Hit(
                joint.link.element,
                f"{joint.describe()}, {beyond(distance, tolerance, 4)} m apart "
                f"({point(first.x, first.y)} and {point(second.x, second.y)})",
            )
