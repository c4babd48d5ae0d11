"""TR009 track-length-mismatch: a track's length is not the length of its plan view.

## What it does
Reports a road with a rail or tram lane whose `@length` differs from the length of its
plan view, the last geometry record's `s` plus its `length` (records taken in order of
s), by more than 0.01 m. A `@length` that is no finite number (`INF`, `-INF`, `NaN`,
`1e999`: valid `xs:double`s the schema accepts) is no length at all and is reported as
written.

## Why is this bad?
ASAM OpenDRIVE defines `road/@length` as the "total length of the reference line in the
xy-plane", and the plan view's geometry records lay that reference line out. When the
two disagree, everything placed by s near the road's end (lane sections, switches,
platform segments, the joint to the next track) is placed by one of two lengths, and
tools that trust the other put it somewhere else or nowhere.

## Example
```xml
<road name="main" length="100.5" id="1" junction="-1"> <!-- expect: TR009 -->
  <planView>
    <geometry s="0" x="0" y="0" hdg="0" length="60"><line/></geometry>
    <geometry s="60" x="60" y="0" hdg="0" length="40"><line/></geometry>
  </planView>
```

Use instead:
```xml
<road name="main" length="100" id="1" junction="-1">
  <planView>
    <geometry s="0" x="0" y="0" hdg="0" length="60"><line/></geometry>
    <geometry s="60" x="60" y="0" hdg="0" length="40"><line/></geometry>
  </planView>
```

## Options
- `s-tolerance` (metres, default 1e-06): the largest difference between two
  s-coordinates or lengths that counts as none; 0.0005 for data rounded to
  millimetres. Configuration: `s-tolerance = 0.0005` in `[tool.xodrlint]`; command
  line: `--rule-option s-tolerance=0.0005`.

## Fix
Unsafe: `xodrlint check --fix --unsafe-fixes` sets the road's `@length` to where its plan
view ends (the shortest decimal that reads back as that number). Which of the two is
wrong only a person can say: the diff shows the new length.

## Related rules
TR014 reports a track whose plan view cannot be evaluated; TR009 stays silent on it. A
`@length` that is missing or no number at all is the schema's (XS006). TR008 reports
records that do not join up; TR009 compares only the total length.

## References
- ASAM OpenDRIVE 1.7, chapter "Roads" (`road/@length`: "total length of the reference
  line in the xy-plane") and chapter "Geometry"; rule UID
  `xodrlint:xodr:1.4.0:road.railroad.track.length`
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import TYPE_CHECKING, Final

from lxml import etree

from xodrlint.rules import (
    Applicability,
    Fix,
    Hit,
    RailNetwork,
    Settings,
    Severity,
    non_finite,
    rule,
    set_attribute,
)
from xodrlint.rules._shared import S_TOLERANCE_OPTION, beyond, metres, quoted
from xodrlint.rules.tracks._planview import track_plan_views

if TYPE_CHECKING:
    from xodrlint.rules.geometry import Record

#: The largest difference (m) allowed between a track's length and its plan view's.
LENGTH_TOLERANCE: Final = 0.01


@rule(
    code="TR009",
    name="track-length-mismatch",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.length",
    severity=Severity.ERROR,
    options=(S_TOLERANCE_OPTION,),
)
def track_length_mismatch(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    tolerance = S_TOLERANCE_OPTION.number(settings)
    for road, view in track_plan_views(network):
        line = view.line
        if line is None:
            continue  # TR014 says why
        last = line.records[-1]
        end = last.s + last.length
        if road.length is None:
            written = non_finite(road.element, "length")
            if written is not None:
                yield Hit(
                    road.element,
                    f"track {quoted(road.id)} has length '{written}', but {_ends(last)}",
                    fix=_length_fix(road.element, end),
                )
            continue
        difference = abs(road.length - end)
        if difference > LENGTH_TOLERANCE + tolerance:
            yield Hit(
                road.element,
                f"track {quoted(road.id)} has length {metres(road.length)}, but "
                f"{_ends(last)}: {beyond(difference, LENGTH_TOLERANCE, 4)} m apart",
                fix=_length_fix(road.element, end),
            )


def _length_fix(road: etree._Element, end: float) -> Fix | None:
    """``road/@length`` := where its plan view ends, written as the shortest decimal
    that reads back as that number once a sum's rounding noise is gone (to a nanometre:
    60.1 + 39.9 is 100, not 100.00000000000001)."""
    if not math.isfinite(end):
        return None
    value = round(end, 9)
    written = str(int(value)) if value.is_integer() else repr(value)
    return Fix(
        f"set the length to {written}, where the plan view ends",
        (set_attribute(road, "length", written),),
        Applicability.UNSAFE,
    )


def _ends(last: Record) -> str:
    """Where the plan view ends, for messages."""
    return (
        f"its plan view ends at s={_metres(last.s + last.length)} (the geometry at "
        f"s={metres(last.s)} is {_metres(last.length)} m long)"
    )


def _metres(value: float) -> str:
    """A length for messages; one too short for six decimals in three digits (1e-08)."""
    text = metres(value)
    return f"{value:.3g}" if text == "0" and value != 0 else text
