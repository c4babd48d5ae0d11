"""TR004 track-link-not-reciprocal: a track links another that does not link it back.

## What it does
Reports a road link between two tracks (`elementType="road"`, both roads with a rail or
tram lane) that the other road does not answer: track A links track B at B's
`contactPoint` end, but B's link at that end (its `predecessor` for `start`, its
`successor` for `end`) names nothing, another road, or A at the wrong end of A. A link
of B naming a junction of which A is a connecting road answers it (that is how a
junction's connecting road is linked). A pair of roads is reported once: on the
earlier road's link when both links of the pair go unanswered.

## Why is this bad?
This is an inference from the standard's road linkage: a link says that traffic leaving
one road through that end enters the other, and the other road's link at its end says
the same in the other direction; the two describe one connection. A one-sided link is a
network that can be driven one way only, or a link that points at the wrong end:
routers that follow links both ways (esmini, CARLA's OpenDRIVE reader, VTD) find no
path back, or a path that jumps to the other end of a track.

## Example
```xml
<link>
  <!-- road 2 has no predecessor: it does not link back to road 1 -->
  <successor elementType="road" elementId="2" contactPoint="start"/> <!-- expect: TR004 -->
</link>
```

Use instead:
```xml
<link>
  <!-- road 2's predecessor is the end of road 1 -->
  <successor elementType="road" elementId="2" contactPoint="start"/>
</link>
```

## Related rules
TR003 (the link names a road the file lacks) and TR005 (no `contactPoint`) come first:
TR004 stays silent on such a link, and on a link answered by one without a contact
point. TR004 silences TR001, TR002, TR007 and TR010 for the link: what a wrong link
joins is not judged.

## References
- ASAM OpenDRIVE 1.7, section 8.4 "Road linkage"; rule UID
  `xodrlint:xodr:1.4.0:road.railroad.track.link_reciprocal`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules.tracks._joints import NOT_ANSWERED
from xodrlint.rules.tracks._network import link_faults


@rule(
    code="TR004",
    name="track-link-not-reciprocal",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.link_reciprocal",
    severity=Severity.ERROR,
    defers_to=("TR003", "TR005"),
)
def track_link_not_reciprocal(network: RailNetwork) -> Iterator[Hit]:
    yield from link_faults(network, NOT_ANSWERED)
