"""ST006 segment-zero-length: a platform segment has no length.

## What it does
Reports a `segment` whose `@sStart` equals its `@sEnd` (within 1e-6 m).

## Why is this bad?
This is an inference: a segment is the stretch of track a platform runs along, and a
stretch of length zero is no platform at all. It is usually a segment whose end was never
filled in.

## Example
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
      <segment roadId="1" sStart="40" sEnd="40" side="left"/> <!-- expect: ST006 -->
    </platform>
  </station>
```

Use instead:
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="60" sEnd="140" side="right"/>
      <segment roadId="1" sStart="40" sEnd="100" side="left"/>
    </platform>
  </station>
```

## Options
- `s-tolerance` (metres, default 1e-06): the largest difference between two
  s-coordinates or lengths that counts as none; 0.0005 for data rounded to
  millimetres. Configuration: `s-tolerance = 0.0005` in `[tool.xodrlint]`; command
  line: `--rule-option s-tolerance=0.0005`.

## Related rules
ST005 reports segments that run backwards; ST004 reports segments off their road.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations" (segments); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.segment.non_empty`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Settings, Severity, rule
from xodrlint.rules._shared import S_TOLERANCE_OPTION, metres, quoted
from xodrlint.rules.stations._walk import segments_with_platform


@rule(
    code="ST006",
    name="segment-zero-length",
    uid="xodrlint:xodr:1.4.0:road.railroad.segment.non_empty",
    severity=Severity.WARNING,
    options=(S_TOLERANCE_OPTION,),
)
def segment_zero_length(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    tolerance = S_TOLERANCE_OPTION.number(settings)
    for segment, platform in segments_with_platform(network):
        start, end = segment.s_start, segment.s_end
        if start is not None and end is not None and abs(start - end) <= tolerance:
            yield Hit(
                segment.element,
                f"segment of platform {quoted(platform.id)} has zero length "
                f"(sStart and sEnd are both {metres(start)})",
            )
