"""PT002 partner-not-reciprocal: a switch names a partner that does not name it back.

## What it does
Reports the `partner` of switch A when it names switch B, but B has no `partner` or names
another switch.

## Why is this bad?
This is an inference: partner switches are two switches that are set together, and the
relation is symmetric in the standard's description and in all its examples. A one-sided
partner makes the crossover depend on which switch a reader looks at first.

## Example
```xml
<switch name="W101" id="101" position="dynamic">
  <mainTrack id="1" s="20" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
  <partner name="W102" id="102"/> <!-- expect: PT002 -->
</switch>
<switch name="W102" id="102" position="dynamic">
  <mainTrack id="1" s="80" dir="-"/>
  <sideTrack id="2" s="60.68" dir="-"/>
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

## Fix
Unsafe: where the answering switch names no partner at all, `xodrlint check --fix
--unsafe-fixes` adds `<partner id=".." name=".."/>` naming this switch to it, after its
tracks and indented as they are. A partner it names already is never replaced.

## Related rules
Last in the chain on a `partner`: PT001 (unknown id), PT005 (the switch itself), SW002
(single switch) and PT004 (different side tracks) report first, and PT002 stays silent on
a partner they report.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (partner switches); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.partner_reciprocal`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import (
    Applicability,
    Fix,
    Hit,
    RailNetwork,
    Severity,
    Switch,
    insert_element,
    rule,
)
from xodrlint.rules._shared import quoted
from xodrlint.rules.partners._pairs import partner_of


@rule(
    code="PT002",
    name="partner-not-reciprocal",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.partner_reciprocal",
    severity=Severity.ERROR,
    defers_to=("PT001", "PT005", "SW002", "PT004"),
)
def partner_not_reciprocal(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        other = partner_of(network, switch)
        if other is None or switch.partner is None:
            continue
        if other.partner is not None and (other.partner.id is None or switch.id is None):
            continue  # a missing id hides whom the other switch names
        answer = other.partner.id if other.partner is not None else None
        if answer != switch.id:
            yield Hit(
                switch.partner.element,
                f"switch {quoted(switch.id)} names '{other.id}' as partner, but '{other.id}' "
                f"names {quoted(answer) if other.partner is not None else 'no partner'}",
                fix=_answer(other, switch) if other.partner is None else None,
            )


def _answer(answering: Switch, switch: Switch) -> Fix | None:
    """``<partner id=".." name=".."/>`` naming ``switch``, added to ``answering`` after
    its tracks (where the schema wants it), indented as they are; never where it names
    a partner already."""
    if switch.id is None:
        return None
    tracks = [child for child in answering.element if child.tag in ("mainTrack", "sideTrack")]
    if not tracks:
        return None
    attributes = {"id": switch.id}
    if switch.name is not None:
        attributes["name"] = switch.name
    return Fix(
        f"add the answering partner to switch '{answering.id}'",
        (insert_element(tracks[-1], "partner", attributes),),
        Applicability.UNSAFE,
    )
