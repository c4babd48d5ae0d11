"""ST011 segments-overlap: two platform segments on one side of a road overlap.

## What it does
Reports two `segment` elements on the same road and the same `@side` whose s ranges
overlap by more than 1e-6 m, once per pair, on the later segment; segments that only
touch end to end are fine.

## Why is this bad?
This is an inference: a stretch of platform edge along one side of a track belongs to
one platform. Two overlapping segments either describe the same platform edge twice or
put two platforms in one place, and stopping positions derived from them are ambiguous.

## Example
```xml
  <station name="Central" id="S1" type="medium">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="20" sEnd="80" side="right"/>
      <segment roadId="1" sStart="60" sEnd="140" side="right"/> <!-- expect: ST011 -->
    </platform>
  </station>
```

Use instead:
```xml
  <!-- segments that meet end to end (within 1e-6 m) do not overlap -->
  <station name="Central" id="S1" type="medium">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="0" sEnd="60" side="right"/>
      <segment roadId="1" sStart="60" sEnd="120.000001" side="right"/>
    </platform>
    <platform name="Platform 2" id="P2">
      <segment roadId="1" sStart="120" sEnd="200" side="right"/>
    </platform>
  </station>
```

## Options
- `s-tolerance` (metres, default 1e-06): the largest difference between two
  s-coordinates or lengths that counts as none; 0.0005 for data rounded to
  millimetres. Configuration: `s-tolerance = 0.0005` in `[tool.xodrlint]`; command
  line: `--rule-option s-tolerance=0.0005`.

## Related rules
ST005 reports a reversed segment; ST011 still compares it by the range it covers. A
segment with an end that is no finite number (`NaN`, `INF`) covers no range: ST004
reports it, once, and ST011 leaves it out.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations" (segments); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.segment.no_overlap`
"""

from __future__ import annotations

import heapq
from collections.abc import Iterator

from xodrlint.rules import Hit, Platform, RailNetwork, Segment, Settings, Severity, rule
from xodrlint.rules._shared import S_TOLERANCE_OPTION, metres, quoted
from xodrlint.rules.stations._walk import segments_with_platform

_Span = tuple[float, float, int, Segment, Platform]


@rule(
    code="ST011",
    name="segments-overlap",
    uid="xodrlint:xodr:1.4.0:road.railroad.segment.no_overlap",
    severity=Severity.WARNING,
    options=(S_TOLERANCE_OPTION,),
)
def segments_overlap(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    tolerance = S_TOLERANCE_OPTION.number(settings)
    groups: dict[tuple[str, str], list[_Span]] = {}
    for order, (segment, platform) in enumerate(segments_with_platform(network)):
        start, end = segment.s_start, segment.s_end
        if segment.road_id is None or segment.side is None or start is None or end is None:
            continue
        span = (min(start, end), max(start, end), order, segment, platform)
        groups.setdefault((segment.road_id, segment.side), []).append(span)
    overlaps = [pair for spans in groups.values() for pair in _overlapping(spans, tolerance)]
    for earlier, later, amount in sorted(overlaps, key=lambda item: (item[1][2], item[0][2])):
        yield Hit(
            later[3].element,
            f"segment of platform {quoted(later[4].id)} overlaps a segment of platform "
            f"{quoted(earlier[4].id)} by {metres(amount)} m on the {later[3].side} side of "
            f"road '{later[3].road_id}'",
            related=(earlier[3].element,),
        )


def _overlapping(spans: list[_Span], tolerance: float) -> Iterator[tuple[_Span, _Span, float]]:
    """Pairs overlapping by more than ``tolerance`` (earlier, later in document order), by
    a sweep over s: the work is proportional to the spans plus the overlaps, not to all
    pairs."""
    active: list[tuple[float, int, _Span]] = []  # a heap by end
    for span in sorted(spans, key=lambda item: (item[0], item[2])):
        while active and active[0][0] <= span[0] + tolerance:
            heapq.heappop(active)
        for _, _, other in active:
            amount = min(other[1], span[1]) - span[0]
            if amount > tolerance:
                earlier, later = sorted((other, span), key=lambda item: item[2])
                yield earlier, later, amount
        heapq.heappush(active, (span[1], span[2], span))
