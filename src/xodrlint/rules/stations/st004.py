"""ST004 segment-s-out-of-range: a platform segment starts or ends off its road.

## What it does
Reports a `segment` whose `@sStart` or `@sEnd` lies outside `[0, length]` of the road
its `@roadId` names (with a tolerance of 1e-6 m). A value that is no finite number
(`INF`, `-INF`, `NaN`, or a numeral too large for a double such as `1e999`) is a valid
`xs:double`, so the schema may accept it; it lies outside every range and is reported
as written (unless the schema rule already reports the value: `-INF` where s must not be
negative).

## Why is this bad?
This is an inference: `sStart` and `sEnd` are s-coordinates along the segment's road, and
an s-coordinate only has a meaning between 0 and the road's `@length`. A platform edge
past the end of its track cannot be placed.

## Example
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <segment roadId="1" sStart="120" sEnd="200" side="right"/>
      <segment roadId="1" sStart="120" sEnd="200.00001" side="left"/> <!-- expect: ST004 -->
    </platform>
  </station>
```

Use instead:
```xml
  <station name="Central" id="S1" type="small">
    <platform name="Platform 1" id="P1">
      <!-- 0 and the road length are on the road -->
      <segment roadId="1" sStart="0" sEnd="200" side="right"/>
    </platform>
  </station>
```

## Options
- `s-tolerance` (metres, default 1e-06): the largest difference between two
  s-coordinates or lengths that counts as none; 0.0005 for data rounded to
  millimetres. Configuration: `s-tolerance = 0.0005` in `[tool.xodrlint]`; command
  line: `--rule-option s-tolerance=0.0005`.

## Related rules
ST003 reports a segment on an unknown road; ST004 cannot judge that one. ST005 and ST006
report reversed and empty segments, which are separate defects.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations" (segments); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.segment.s_in_road_range`
"""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Hit, RailNetwork, Settings, Severity, non_finite, rule
from xodrlint.rules._shared import S_TOLERANCE_OPTION, metres, quoted, within
from xodrlint.rules.stations._walk import segments_with_platform


@rule(
    code="ST004",
    name="segment-s-out-of-range",
    uid="xodrlint:xodr:1.4.0:road.railroad.segment.s_in_road_range",
    severity=Severity.ERROR,
    defers_to=("ST003",),
    options=(S_TOLERANCE_OPTION,),
)
def segment_s_out_of_range(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    tolerance = S_TOLERANCE_OPTION.number(settings)
    for segment, platform in segments_with_platform(network):
        road = network.road_by_id.get(segment.road_id) if segment.road_id is not None else None
        if road is None:
            continue
        outside, written = [], False
        for name, value in (("sStart", segment.s_start), ("sEnd", segment.s_end)):
            if value is None:  # no finite number: reported as written if it is a double
                text = non_finite(segment.element, name)
                if text is not None:
                    outside.append(f"{name}={text}")
                    written = True
            elif road.length is not None and not within(value, 0.0, road.length, tolerance):
                outside.append(f"{name}={metres(value)}")
        if not outside:
            continue
        span = f" (0 to {metres(road.length)})" if road.length is not None else ""
        yield Hit(
            segment.element,
            f"segment of platform {quoted(platform.id)} has {' and '.join(outside)}, "
            f"outside road '{road.id}'{span}",
            # where the schema refuses the value too (-INF, blanks): one finding
            defers_to=("ST003", "XS006") if written else None,
        )
