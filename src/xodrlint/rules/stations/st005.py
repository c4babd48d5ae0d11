"""ST005 segment-s-reversed: a platform segment starts after it ends.

## What it does
Reports a `segment` whose `@sStart` is greater than its `@sEnd` (by more than 1e-6 m).

## Why is this bad?
This is an inference: the standard gives a segment's extent as `sStart` to `sEnd` along
the road, and its examples always run from the smaller s to the larger. Its schema says
`@side` is the side of the track "when going from sStart to sEnd", so a reversed
segment's side reads mirrored against every other segment's. Readers that take the range
as given get an empty or negative platform.

## Example
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="0" sEnd="80" side="right"/>
      <segment roadId="1" sStart="140" sEnd="60" side="left"/> <!-- expect: ST005 -->
    </platform>
  </station>
```

Use instead:
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="0" sEnd="80" side="right"/>
      <segment roadId="1" sStart="120" sEnd="200" side="left"/>
    </platform>
  </station>
```

## Options
- `s-tolerance` (metres, default 1e-06): the largest difference between two
  s-coordinates or lengths that counts as none; 0.0005 for data rounded to
  millimetres. Configuration: `s-tolerance = 0.0005` in `[tool.xodrlint]`; command
  line: `--rule-option s-tolerance=0.0005`.

## Fix
Unsafe: `xodrlint check --fix --unsafe-fixes` swaps `@sStart` and `@sEnd` (as written)
and mirrors `@side` (left and right; `both` stays): the segment is then written along
increasing s, and the platform stays on the side of the track where it stands.

## Related rules
ST006 reports a segment whose ends coincide; ST011 compares segments by the s range they
cover whichever way round they are written. An end that is no finite number (`NaN`,
`INF`) has no order: ST004 reports it, once, and ST005 stays silent.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations" (segments); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.segment.s_ordered`
"""

from __future__ import annotations

from collections.abc import Iterator

from lxml import etree

from xodrlint.rules import (
    Applicability,
    Fix,
    Hit,
    RailNetwork,
    Settings,
    Severity,
    rule,
    set_attribute,
)
from xodrlint.rules._shared import S_TOLERANCE_OPTION, metres, quoted
from xodrlint.rules.stations._walk import segments_with_platform


@rule(
    code="ST005",
    name="segment-s-reversed",
    uid="xodrlint:xodr:1.4.0:road.railroad.segment.s_ordered",
    severity=Severity.ERROR,
    options=(S_TOLERANCE_OPTION,),
)
def segment_s_reversed(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    tolerance = S_TOLERANCE_OPTION.number(settings)
    for segment, platform in segments_with_platform(network):
        start, end = segment.s_start, segment.s_end
        if start is not None and end is not None and start > end + tolerance:
            yield Hit(
                segment.element,
                f"segment of platform {quoted(platform.id)} starts at sStart={metres(start)}, "
                f"after its end sEnd={metres(end)}",
                fix=_swapped(segment.element),
            )


#: The side a platform stands on, seen from the other direction of travel.
_MIRRORED = {"left": "right", "right": "left"}


def _swapped(segment: etree._Element) -> Fix | None:
    """``sStart`` and ``sEnd`` swapped, as written, and ``side`` mirrored (left and right
    are said along increasing s, so the platform stays where it stands)."""
    start, end = segment.get("sStart"), segment.get("sEnd")
    if start is None or end is None:
        return None
    edits = [set_attribute(segment, "sStart", end), set_attribute(segment, "sEnd", start)]
    side = segment.get("side")
    mirrored = _MIRRORED.get(side) if side is not None else None
    if mirrored is not None:
        edits.append(set_attribute(segment, "side", mirrored))
    what = " and mirror its side" if mirrored else ""
    return Fix(f"swap sStart and sEnd{what}", tuple(edits), Applicability.UNSAFE)
