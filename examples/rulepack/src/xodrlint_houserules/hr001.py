"""HR001 switch-id-not-uint32: a switch id is not an integer from 0 to 4294967295.

## What it does
Reports a switch whose `@id` is not written as an unsigned 32-bit integer: digits only,
no sign, no leading zero, at most 4294967295. A switch without an id is left to the
schema.

## Why is this bad?
ASAM OpenDRIVE calls a switch's id "preferably an integer number, see uint32_t", and the
house's interlocking tables keep switch ids in a 32-bit field. An id such as `W12` or
`4294967296` cannot be entered there, and `007` would be entered as `7`, which then no
longer matches the map.

## Example
```xml
<switch name="W2" id="W102" position="dynamic"> <!-- expect: HR001 -->
```

Use instead:
```xml
<switch name="W2" id="102" position="dynamic">
```

## Related rules
SW007 (xodrlint) reports two switches with one id; this rule judges each id alone.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Switches" (`@id`: "preferably an
  integer number, see uint32_t"); rule UID
  `example-rail.com:xodr:1.4.0:road.railroad.switch.id_is_uint32`
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import Final

from xodrlint.rules import Hit, RailNetwork, Severity, rule

UINT32_MAX: Final = 2**32 - 1
_DIGITS: Final = re.compile(r"0|[1-9][0-9]*")


@rule(
    code="HR001",
    name="switch-id-not-uint32",
    uid="example-rail.com:xodr:1.4.0:road.railroad.switch.id_is_uint32",
    severity=Severity.WARNING,
)
def switch_id_not_uint32(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        if switch.id is None:
            continue
        why = _why_not_uint32(switch.id)
        if why:
            yield Hit(switch.element, f"switch id '{switch.id}' {why}")


def _why_not_uint32(text: str) -> str:
    """Why ``text`` is no canonical uint32 (``""`` when it is one)."""
    if text.isascii() and text.isdigit():
        if not _DIGITS.fullmatch(text):
            return "has a leading zero (the interlocking reads it as another number)"
        if int(text) > UINT32_MAX:
            return f"is above {UINT32_MAX}, the largest uint32"
        return ""
    return f"is not an integer from 0 to {UINT32_MAX}"
