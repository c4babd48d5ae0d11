"""PT006 partner-position-inconsistent: two partner switches are not set consistently.

## What it does
Reports a pair of partner switches where one has `@position` `dynamic` and the other a
static position, or both are static with different positions (`straight` and `turn`);
once per pair, on the later switch of the pair.

## Why is this bad?
This is an inference from the standard's statement that partner switches are set
consistently: a crossover is either operated as a whole or fixed as a whole. One fixed
straight and one fixed turn end leads a train off the side track into nothing.

## Example
```xml
<switch name="W101" id="101" position="dynamic">
  <mainTrack id="1" s="20" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
  <partner name="W102" id="102"/>
</switch>
<switch name="W102" id="102" position="straight"> <!-- expect: PT006 -->
  <mainTrack id="1" s="80" dir="-"/>
  <sideTrack id="2" s="60.68" dir="-"/>
  <partner name="W101" id="101"/>
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
```

## Related rules
PT004 reports partners that do not share a side track; PT006 still reports their
positions, which are a separate defect.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (partner switches); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.partners_set_consistently`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

from xodrlint.rules import Hit, RailNetwork, Severity, rule
from xodrlint.rules._shared import quoted
from xodrlint.rules.partners._pairs import partner_pairs

DYNAMIC: Final = "dynamic"
POSITIONS: Final = frozenset({DYNAMIC, "straight", "turn"})


@rule(
    code="PT006",
    name="partner-position-inconsistent",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.partners_set_consistently",
    severity=Severity.WARNING,
)
def partner_position_inconsistent(network: RailNetwork) -> Iterator[Hit]:
    for pair in partner_pairs(network):
        first, later = pair.first.position, pair.later.position
        if first not in POSITIONS or later not in POSITIONS or first == later:
            continue
        yield Hit(
            pair.later.element,
            f"partner switches {quoted(pair.first.id)} and {quoted(pair.later.id)} are not "
            f"set consistently: {quoted(pair.first.id)} is '{first}', "
            f"{quoted(pair.later.id)} is '{later}'",
        )
