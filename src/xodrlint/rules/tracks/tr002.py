"""TR002 track-link-kink: two linked tracks meet at an angle a train cannot take.

## What it does
Reports a pair of lanes joined at a joint (the pairs TR001 judges: rail/tram lanes of
two tracks that a lane link pairs, or the single rail lane of each) where the direction
of travel leaving the first road and the direction entering the second differ by more
than the tolerance (default 5 degrees). Leaving through a road's end, a train runs along
the reference-line heading there; leaving through its start, the opposite way; entering
is the same in reverse. Angles are compared on the circle.

## Why is this bad?
This is an inference from the standard's road linkage: a link joins two roads end to end
so that traffic passes from one to the other. Rails cannot bend at a point: two tracks
that meet at an angle form a kink that derails a train, and where the angle is near 180
degrees the link or a contact point points the wrong way.

## Example
```xml
<link>
  <!-- road 1 ends heading 0 rad; road 2 starts heading 0.1 rad (5.73 degrees) -->
  <successor elementType="road" elementId="2" contactPoint="start"/> <!-- expect: TR002 -->
</link>
```

Use instead:
```xml
<link>
  <!-- road 1 ends heading 0 rad; road 2 starts heading 0.05 rad (2.86 degrees) -->
  <successor elementType="road" elementId="2" contactPoint="start"/>
</link>
```

## Options
- `link-angle` (degrees, default 5): the largest angle allowed between the directions of
  travel at a joint. Configuration: `link-angle = 5` in `[tool.xodrlint]`; command line:
  `--rule-option link-angle=5`.
- `link-tolerance` (metres, default 0.1): TR001's gap; a pair of joined lanes further
  apart than this is TR001's, not judged here.

## Related rules
TR001 reports a gap between the same joined lanes; a gap makes the angle meaningless, so
TR002 stays silent on a pair TR001 reports. TR003, TR004 and TR005 report a link whose
joint cannot be judged; TR002 defers to them on that link. Links to junctions and to
roads without a rail or tram lane are not judged.

## References
- ASAM OpenDRIVE 1.7, chapter "Roads", section "Road linkage", and chapter "Railroads"; rule
  UID `xodrlint:xodr:1.4.0:road.railroad.track.link_kink`
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Final

from xodrlint.rules import Hit, RailNetwork, RuleOption, Settings, Severity, rule
from xodrlint.rules._shared import S_TOLERANCE, beyond
from xodrlint.rules.tracks.tr001 import TOLERANCE, joint_gaps

ANGLE: Final = RuleOption(
    name="link-angle",
    default=5.0,
    description="Largest angle between the directions of travel at a joint of two rail roads",
    unit="degrees",
)


@rule(
    code="TR002",
    name="track-link-kink",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.link_kink",
    severity=Severity.WARNING,
    options=(ANGLE, TOLERANCE),
    defers_to=("TR003", "TR004", "TR005"),
)
def track_link_kink(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    from xodrlint.rules.geometry import turn_beyond

    limit = ANGLE.number(settings)
    gap = TOLERANCE.number(settings)
    for joint, lanes, distance in joint_gaps(network):
        if distance > gap + S_TOLERANCE:
            continue  # TR001's: a gap makes the angle meaningless
        assert lanes.first_point is not None and lanes.second_point is not None
        leaving, entering = joint.leaving(lanes.first_point), joint.entering(lanes.second_point)
        angle = turn_beyond(leaving, entering, limit)
        if angle is not None:
            yield Hit(
                joint.link.element,
                f"{joint.describe()}: a train from {lanes.first.describe()} onto "
                f"{lanes.second.describe()} turns by "
                f"{beyond(math.degrees(angle), limit, 2)} degrees at the joint (at most "
                f"{limit:g} allowed)",
            )
