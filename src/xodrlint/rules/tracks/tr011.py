"""TR011 track-too-steep: a track climbs or falls more steeply than trains or trams can.

## What it does
Reports an `elevation` entry of a track (a road with a rail or tram lane) along which the
gradient, the derivative of the entry's cubic, exceeds the limit in magnitude: 0.08 (8 %)
on a road with a rail lane, 0.14 (14 %) on a road whose rail-bound lanes are all tram
lanes. The entry holds from its `s` to the next entry's `s` (the last one to the road's
`@length`); the steepest point is found exactly, at the stretch's ends or at the vertex
of the derivative (a quadratic) inside it, not by sampling. Reported once per entry,
with the steepest gradient and where it is. Gradients are those of the reference line.

## Why is this bad?
This is an inference: the standard gives a road's elevation but no limit on it. Trains
run on the adhesion of steel wheels on steel rails: main lines keep within a few percent
(about 4 % on the steepest high-speed lines), only a handful of mountain adhesion lines
go beyond 8 %, and trams in hilly cities reach about 10 % to 14 %. A steeper track is most
often an elevation in the wrong unit, a sign error, or a road's profile copied onto a
track. A project sets its own line's design limit (a mountain line raises it).

## Example
```xml
<elevationProfile>
  <!-- the gradient is 0.02 + 2·0.001·40 = 0.1 at s=40 -->
  <elevation s="0" a="0" b="0.02" c="0.001" d="0"/> <!-- expect: TR011 -->
</elevationProfile>
```

Use instead:
```xml
<elevationProfile>
  <!-- the gradient is 0.02 + 2·0.0005·40 = 0.06 at s=40 -->
  <elevation s="0" a="0" b="0.02" c="0.0005" d="0"/>
</elevationProfile>
```

## Options
- `max-gradient-rail` (a ratio, default 0.08): the steepest gradient allowed on a road
  with a rail lane. Configuration: `max-gradient-rail = 0.08` in `[tool.xodrlint]`;
  command line: `--rule-option max-gradient-rail=0.08`.
- `max-gradient-tram` (a ratio, default 0.14): the steepest gradient allowed on a road
  whose rail-bound lanes are all tram lanes. Configuration: `max-gradient-tram = 0.14`;
  command line: `--rule-option max-gradient-tram=0.14`.

## Related rules
TR014 reports an `elevation` entry with a missing, non-numeric or non-finite value; TR011
does not judge that entry, nor the one before it when the entry's `s` is unreadable (where
that one ends is unknown). TR010 reports a step between two entries.

## References
- ASAM OpenDRIVE 1.7, chapter "Roads", section "Elevation", and chapter "Railroads"; rule
  UID `xodrlint:xodr:1.4.0:road.railroad.track.gradient`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

from xodrlint.rules import Hit, RailNetwork, RuleOption, Settings, Severity, rule
from xodrlint.rules._shared import beyond, metres, quoted

MAX_RAIL: Final = RuleOption(
    name="max-gradient-rail",
    default=0.08,
    description="Steepest gradient of a road with a rail lane (rise over run)",
    unit="ratio",
)
MAX_TRAM: Final = RuleOption(
    name="max-gradient-tram",
    default=0.14,
    description="Steepest gradient of a road whose rail-bound lanes are all tram lanes",
    unit="ratio",
)
#: Gradients equal within this are equal: a derivative computed from a cubic carries rounding.
_SLACK: Final = 1e-9


@rule(
    code="TR011",
    name="track-too-steep",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.gradient",
    severity=Severity.WARNING,
    options=(MAX_RAIL, MAX_TRAM),
    defers_to=("TR014",),
)
def track_too_steep(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    from xodrlint.rules.geometry import VerticalProfiles

    rail_limit, tram_limit = MAX_RAIL.number(settings), MAX_TRAM.number(settings)
    profiles = network.shared(VerticalProfiles)
    for road, elevation, _ in profiles.tracks(network):
        spans = list(elevation.spans())
        if not spans:
            continue
        kind = "rail" if "rail" in road.lane_template.lane_types else "tram"
        limit = rail_limit if kind == "rail" else tram_limit
        for span in spans:
            steepest = span.steepest()
            if steepest is None or abs(steepest[0]) <= limit + _SLACK:
                continue
            gradient, s = steepest
            yield Hit(
                span.element,
                f"elevation of road {quoted(road.id)} {'rises' if gradient > 0 else 'falls'} "
                f"at a gradient of {beyond(abs(gradient), limit, 4)} at s={metres(s)}, "
                f"steeper than {metres(limit)} on a {kind} track",
            )
