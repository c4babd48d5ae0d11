"""TR005 track-link-without-contact-point: a link between two tracks does not say which end.

## What it does
Reports a joint (a `link/predecessor` or `link/successor` with `elementType="road"`
between two roads with a rail or tram lane) that has no `contactPoint` (nor `elementS`,
its alternative since OpenDRIVE 1.7 for a link into the middle of a road, which is no
joint of two ends and is not judged).

## Why is this bad?
The standard requires `contactPoint` on a link whose `elementType` is `road`: it says
which end of the other road the link joins. Without it the link joins an unknown end:
tools guess (and guess differently), and no check of the joint (gap, angle, lane links,
reciprocity) can be made, so it would otherwise pass in silence.

## Example
```xml
<link>
  <successor elementType="road" elementId="2"/> <!-- expect: TR005 -->
</link>
```

Use instead:
```xml
<link>
  <successor elementType="road" elementId="2" contactPoint="start"/>
</link>
```

## Options
- `link-tolerance` (metres, default 0.1): TR001's gap. The fix names the end of the
  other road whose track point is within it of this road's end. Configuration:
  `link-tolerance = 0.1` in `[tool.xodrlint]`; command line:
  `--rule-option link-tolerance=0.1`.

## Fix
Unsafe: `xodrlint check --fix --unsafe-fixes` sets `@contactPoint` to the end of the
named road whose track point is nearest this road's end, only when that end is within
`link-tolerance` of it and the other end is not (a road that meets both ends, or
neither, gets no fix).

## Related rules
TR005 silences TR004, TR001, TR002, TR007 and TR010 for the link: what it joins is
unknown, so it is not judged.

## References
- ASAM OpenDRIVE 1.7, section 8.4 "Road linkage" (`@contactPoint`, the contact point of
  the link on the linked element, to be given for a linked road); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.track.link_contact_point`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from xodrlint.rules import (
    Applicability,
    Fix,
    Hit,
    RailNetwork,
    Road,
    Settings,
    Severity,
    rule,
    set_attribute,
)
from xodrlint.rules.tracks._joints import NO_CONTACT_POINT, TrackLink
from xodrlint.rules.tracks._network import link_faults
from xodrlint.rules.tracks.tr001 import TOLERANCE

if TYPE_CHECKING:
    from xodrlint.rules.geometry import TrackGeometry, TrackPoint


@rule(
    code="TR005",
    name="track-link-without-contact-point",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.link_contact_point",
    severity=Severity.ERROR,
    options=(TOLERANCE,),
)
def track_link_without_contact_point(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    tolerance = TOLERANCE.number(settings)
    yield from link_faults(
        network, NO_CONTACT_POINT, lambda judged: _contact_point(network, judged, tolerance)
    )


def _contact_point(network: RailNetwork, judged: TrackLink, tolerance: float) -> Fix | None:
    """``@contactPoint`` := the end of the named road that meets this road's end, where
    exactly one of its ends does (within ``link-tolerance``)."""
    from xodrlint.rules.geometry import TrackGeometry

    road, target = judged.road, judged.target
    if target is None or road.length is None or target.length is None:
        return None
    tracks = network.shared(TrackGeometry)
    here = tracks.point(road, 0.0 if judged.end == "start" else road.length)
    if here is None:
        return None
    meeting = [end for end in ("start", "end") if _near(tracks, target, end, here, tolerance)]
    if len(meeting) != 1:
        return None
    return Fix(
        f"join the {meeting[0]} of road '{target.id}', which this road's {judged.end} meets",
        (set_attribute(judged.link.element, "contactPoint", meeting[0]),),
        Applicability.UNSAFE,
    )


def _near(
    tracks: TrackGeometry, target: Road, end: str, here: TrackPoint, tolerance: float
) -> bool:
    """Whether ``target``'s track point at ``end`` is within ``tolerance`` of ``here``."""
    there = tracks.point(target, 0.0 if end == "start" else target.length or 0.0)
    return there is not None and there.distance_to(here) <= tolerance
