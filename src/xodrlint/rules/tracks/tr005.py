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

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules.tracks._joints import NO_CONTACT_POINT
from xodrlint.rules.tracks._network import link_faults


@rule(
    code="TR005",
    name="track-link-without-contact-point",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.link_contact_point",
    severity=Severity.ERROR,
)
def track_link_without_contact_point(network: RailNetwork) -> Iterator[Hit]:
    yield from link_faults(network, NO_CONTACT_POINT)
