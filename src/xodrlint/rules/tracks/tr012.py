"""TR012 track-cant-too-large: a track is banked more steeply than any track is canted.

## What it does
Reports a `superelevation` entry of a track (a road with a rail or tram lane) along which
the roll angle (`lateralProfile/superelevation`, in radians) exceeds the limit (default
0.13 rad, about 7.4 degrees) in magnitude. The entry holds from its `s` to the next
entry's `s` (the last one to the road's `@length`); its largest magnitude is found
exactly, at the stretch's ends or where the cubic's derivative vanishes inside it, not
by sampling. Reported once per entry, with the largest roll angle and where it is.

## Why is this bad?
This is an inference: the standard gives a road's superelevation but no limit on it. A
track's superelevation is its cant, the height of the outer rail over the inner one:
railways allow about 150 to 200 mm over a gauge of 1.435 m (a rail head distance of about
1.5 m), a roll angle of 0.10 to 0.13 rad, and a train standing in a curve must not slide
or tip inwards. A larger angle is most often a value in degrees written where radians
belong, or a road's banking copied onto a track.

## Example
```xml
<lateralProfile>
  <!-- the roll angle peaks at 0.04·25 - 0.0008·625 = 0.5 rad at s=25 -->
  <superelevation s="0" a="0" b="0.04" c="-0.0008" d="0"/> <!-- expect: TR012 -->
</lateralProfile>
```

Use instead:
```xml
<lateralProfile>
  <!-- the roll angle peaks at 0.008·25 - 0.00016·625 = 0.1 rad at s=25 -->
  <superelevation s="0" a="0" b="0.008" c="-0.00016" d="0"/>
</lateralProfile>
```

## Options
- `max-cant` (radians, default 0.13): the largest roll angle allowed on a track.
  Configuration: `max-cant = 0.13` in `[tool.xodrlint]`; command line:
  `--rule-option max-cant=0.13`.

## Related rules
TR014 reports a `superelevation` entry with a missing, non-numeric or non-finite value;
TR012 does not judge that entry, nor the one before it when the entry's `s` is unreadable
(where that one ends is unknown).

## References
- ASAM OpenDRIVE 1.7, chapter "Roads", section "Superelevation", and chapter
  "Railroads"; rule UID `xodrlint:xodr:1.4.0:road.railroad.track.cant`
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Final

from xodrlint.rules import Hit, RailNetwork, RuleOption, Settings, Severity, rule
from xodrlint.rules._shared import beyond, metres, quoted

MAX_CANT: Final = RuleOption(
    name="max-cant",
    default=0.13,
    description="Largest roll angle (superelevation) of a track",
    unit="rad",
)
#: Angles equal within this are equal: a value computed from a cubic carries rounding.
_SLACK: Final = 1e-9


@rule(
    code="TR012",
    name="track-cant-too-large",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.cant",
    severity=Severity.WARNING,
    options=(MAX_CANT,),
    defers_to=("TR014",),
)
def track_cant_too_large(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    from xodrlint.rules.geometry import VerticalProfiles

    limit = MAX_CANT.number(settings)
    profiles = network.shared(VerticalProfiles)
    for road, _, superelevation in profiles.tracks(network):
        for span in superelevation.spans():
            largest = span.largest()
            if largest is None or abs(largest[0]) <= limit + _SLACK:
                continue
            angle, s = largest
            sign = "-" if angle < 0 else ""
            yield Hit(
                span.element,
                f"superelevation of road {quoted(road.id)} reaches "
                f"{sign}{beyond(abs(angle), limit, 4)} rad "
                f"({sign}{math.degrees(abs(angle)):.2f} degrees) at s={metres(s)}, "
                f"more than {metres(limit)} rad",
            )
