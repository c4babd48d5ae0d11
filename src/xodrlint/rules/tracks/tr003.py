"""TR003 track-link-target-missing: a track's link names a road or junction the file lacks.

## What it does
Reports a `link/predecessor` or `link/successor` of a road with a rail or tram lane whose
`elementId` names no road (`elementType="road"`) or no junction
(`elementType="junction"`) of the file.

## Why is this bad?
The standard's road linkage names the element a road continues into by its id; a link
to an id the file does not define leads nowhere. A simulator routing a train along it
stops at the end of the track (esmini and VTD refuse or drop the route), and every check
of what the link joins (gaps, angles, lane links) has nothing to look at.

## Example
```xml
<link>
  <!-- the file has roads 1 and 2 only -->
  <successor elementType="road" elementId="9" contactPoint="start"/> <!-- expect: TR003 -->
</link>
```

Use instead:
```xml
<link>
  <successor elementType="road" elementId="2" contactPoint="start"/>
</link>
```

## Related rules
TR003 silences TR004, TR001, TR002, TR007 and TR010 for the link: what a link to
nothing joins is not judged. SW004 reports a switch track naming a road the file lacks.

## References
- ASAM OpenDRIVE 1.7, section 8.4 "Road linkage" (`link/predecessor`, `link/successor`,
  `@elementId`); rule UID `xodrlint:xodr:1.4.0:road.railroad.track.link_target`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules.tracks._joints import TARGET_MISSING
from xodrlint.rules.tracks._network import link_faults


@rule(
    code="TR003",
    name="track-link-target-missing",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.link_target",
    severity=Severity.ERROR,
)
def track_link_target_missing(network: RailNetwork) -> Iterator[Hit]:
    yield from link_faults(network, TARGET_MISSING)
