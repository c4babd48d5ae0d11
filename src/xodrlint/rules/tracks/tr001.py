"""TR001 track-link-gap: two linked tracks do not meet where the link joins them.

## What it does
Reports a joint (a `link/predecessor` or `link/successor` with `elementType="road"`
between two roads with a rail or tram lane) where two lanes it joins are more than the
tolerance (default 0.10 m) apart. The joined lanes are the pairs of rail/tram lanes, one
of each road's lane section at the joined ends, that a lane link (`lane/link/predecessor`
or `successor`, on either road) pairs; where each of the two sections holds exactly one
rail/tram lane, those two are joined even without a lane link. Each pair is judged at the
two lanes' own centres (`laneOffset` plus the inner lanes' widths and half the lane's
own, the widths as the cubics they are) at the joined ends: this road's start for a
predecessor and its end for a successor, the other road's end as `contactPoint` says. So
a double track (two rail lanes on one road, linked `-1 -> -1` and `1 -> 1`) is judged
track by track. A joint is reported once per pair of joined lanes: on the link of the
road that comes first in the document when both roads name each other.

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
TR003 (the link names a road the file lacks), TR005 (no `contactPoint`) and TR004 (the
other road does not link back) report a link whose joint cannot be judged; TR001 defers
to them on that link. TR002 judges the directions of the same joined lanes and stays
silent where TR001 reports a gap. TR007 reports a rail lane that a joint joins to no
rail lane of the other road. TR014 reports a plan view that cannot be evaluated; the
joints of such a road are left alone. Links to junctions, and links between a track and
a road without a rail or tram lane, are not judged.

## References
- ASAM OpenDRIVE 1.7, chapter "Roads", section "Road linkage", and chapter "Railroads"; rule
  UID `xodrlint:xodr:1.4.0:road.railroad.track.link_gap`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

from xodrlint.rules import Hit, RailNetwork, RuleOption, Settings, Severity, rule
from xodrlint.rules._shared import S_TOLERANCE, beyond, point
from xodrlint.rules.tracks._joints import JoinedLanes, Joint
from xodrlint.rules.tracks._network import joints

TOLERANCE: Final = RuleOption(
    name="link-tolerance",
    default=0.1,
    description="Largest distance between the centres of two lanes a joint of tracks joins",
)


@rule(
    code="TR001",
    name="track-link-gap",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.link_gap",
    severity=Severity.ERROR,
    options=(TOLERANCE,),
    defers_to=("TR003", "TR004", "TR005"),
)
def track_link_gap(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    tolerance = TOLERANCE.number(settings)
    for joint, lanes, distance in joint_gaps(network, tolerance + S_TOLERANCE):
        first, second = lanes.first_point, lanes.second_point
        assert first is not None and second is not None  # a gap is measured between two
        yield Hit(
            joint.link.element,
            f"{joint.describe()}: {lanes.first.describe()} and "
            f"{lanes.second.describe()} are {beyond(distance, tolerance, 4)} m apart "
            f"({point(first.x, first.y)} and {point(second.x, second.y)})",
        )


def joint_gaps(
    network: RailNetwork, wider_than: float = -1.0
) -> Iterator[tuple[Joint, JoinedLanes, float]]:
    """Each pair of joined lanes whose two centres can be evaluated and are more than
    ``wider_than`` apart, with their distance."""
    for joint in joints(network):
        for lanes in joint.lanes:
            gap = lanes.gap
            if gap is not None and gap > wider_than:
                yield joint, lanes, gap
