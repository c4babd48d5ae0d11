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

## Fix
Unsafe: where the other road's end names nothing, `xodrlint check --fix --unsafe-fixes`
adds the answering `predecessor` or `successor` (naming this road's end) to that road's
`link`, in the schema's order, making a `<link>` where the road has none. A link that
names something is never replaced: which of the two is right only a person can say.

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

from xodrlint.rules import Applicability, Fix, Hit, RailNetwork, Severity, insert_element, rule
from xodrlint.rules.tracks._joints import END_OF, LINK_AT, NOT_ANSWERED, TrackLink
from xodrlint.rules.tracks._network import link_faults


@rule(
    code="TR004",
    name="track-link-not-reciprocal",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.link_reciprocal",
    severity=Severity.ERROR,
    defers_to=("TR003", "TR005"),
)
def track_link_not_reciprocal(network: RailNetwork) -> Iterator[Hit]:
    yield from link_faults(network, NOT_ANSWERED, _answer)


def _answer(judged: TrackLink) -> Fix | None:
    """The answering ``predecessor`` or ``successor`` added to the other road's ``link``
    (a ``link`` made where it has none), where that road's end names nothing; a link
    that names something is never replaced."""
    target, end, contact = judged.target, judged.end, judged.link.contact_point
    road_id = judged.road.id
    if target is None or contact not in LINK_AT or road_id is None:
        return None
    kind = LINK_AT[contact]
    if any(link.kind == kind for link in target.links):
        return None  # it names something (or nothing readable): a person decides
    answer = {"elementType": "road", "elementId": road_id, "contactPoint": end}
    message = f"add the answering {kind} to road '{target.id}'"
    elements = [child for child in target.element if isinstance(child.tag, str)]
    link = next((child for child in elements if child.tag == "link"), None)
    if link is None:
        if not elements:
            return None
        edit = insert_element(elements[0], "link", {}, where="before", children=[(kind, answer)])
        return Fix(message, (edit,), Applicability.UNSAFE)
    held = [child for child in link if isinstance(child.tag, str)]
    if not held:
        return None  # an empty <link/>: nothing to stand beside
    # the schema's order: predecessor, successor, then any additional data
    if END_OF[kind] == "start":
        edit = insert_element(held[0], kind, answer, where="before")
    else:
        before = [child for child in held if child.tag == "predecessor"]
        edit = (
            insert_element(before[-1], kind, answer)
            if before
            else insert_element(held[0], kind, answer, where="before")
        )
    return Fix(message, (edit,), Applicability.UNSAFE)
