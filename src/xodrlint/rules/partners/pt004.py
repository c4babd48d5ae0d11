"""PT004 partner-side-track-mismatch: two partner switches do not share their side track.

## What it does
Reports a pair of partner switches whose `sideTrack` elements name different roads, once
per pair, on the `partner` of the later switch of the pair (on the only `partner` of the
pair when just one switch names the other).

## Why is this bad?
ASAM OpenDRIVE defines partner switches as two switches linked by a side track: the side
track road runs from one to the other. Partners on different side tracks are not linked
at all, so setting them together describes a route that does not exist.

## Example
```xml
<switch name="W101" id="101" position="dynamic">
  <mainTrack id="1" s="20" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
  <partner name="W103" id="103"/>
</switch>
<switch name="W102" id="102" position="dynamic">
  <mainTrack id="1" s="80" dir="-"/>
  <sideTrack id="2" s="60.68" dir="-"/>
  <partner name="W104" id="104"/>
</switch>
<switch name="W103" id="103" position="dynamic">
  <mainTrack id="1" s="120" dir="+"/>
  <sideTrack id="3" s="0" dir="+"/>
  <partner name="W101" id="101"/> <!-- expect: PT004 -->
</switch>
<switch name="W104" id="104" position="dynamic">
  <mainTrack id="1" s="180" dir="-"/>
  <sideTrack id="3" s="60.68" dir="-"/>
  <partner name="W102" id="102"/> <!-- expect: PT004 -->
</switch>
```

Use instead:
```xml
<switch name="W101" id="101" position="dynamic">
  <mainTrack id="1" s="20" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
  <partner name="W102" id="102"/>
</switch>
<switch name="W102" id="102" position="dynamic">
  <mainTrack id="1" s="80" dir="-"/>
  <sideTrack id="2" s="60.68" dir="-"/>
  <partner name="W101" id="101"/>
</switch>
<switch name="W103" id="103" position="dynamic">
  <mainTrack id="1" s="120" dir="+"/>
  <sideTrack id="3" s="0" dir="+"/>
  <partner name="W104" id="104"/>
</switch>
<switch name="W104" id="104" position="dynamic">
  <mainTrack id="1" s="180" dir="-"/>
  <sideTrack id="3" s="60.68" dir="-"/>
  <partner name="W103" id="103"/>
</switch>
```

## Related rules
On a `partner`, PT001, PT005 and SW002 report first; PT004 stays silent on a partner they
report, and PT002 stays silent on a partner PT004 reports.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (partner switches); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.partners_share_side_track`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted
from xodrlint.rules.partners._pairs import partner_pairs


@rule(
    code="PT004",
    name="partner-side-track-mismatch",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.partners_share_side_track",
    severity=Severity.ERROR,
    defers_to=("PT001", "PT005", "SW002"),
)
def partner_side_track_mismatch(network: RailNetwork) -> Iterator[Hit]:
    for pair in partner_pairs(network):
        roads = [
            sw.side_track.road_id if sw.side_track else None for sw in (pair.first, pair.later)
        ]
        if None in roads or roads[0] == roads[1]:
            continue
        yield Hit(
            pair.partners[-1].element,
            f"partner switches {quoted(pair.first.id)} and {quoted(pair.later.id)} have "
            f"different side tracks: road '{roads[0]}' and road '{roads[1]}'",
        )
