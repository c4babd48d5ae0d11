"""HR003 platform-too-short: a platform is shorter than the house minimum.

## What it does
Adds up the lengths of a platform's segments (`@sEnd` minus `@sStart` on each) and
reports the platform when they come to less than `platform-min-length` (100 m by
default). A platform with no segment, or with a segment whose range is unreadable or
reversed, is left to xodrlint's station rules.

## Why is this bad?
A train stops with every door at the platform. A platform shorter than the house's
longest stopping train is a timetable and safety question the map must raise before
operations do.

## Example
```xml
<platform name="Platform 1" id="501"> <!-- expect: HR003 -->
  <segment roadId="1" sStart="60" sEnd="140" side="left"/>
</platform>
```

Use instead:
```xml
<platform name="Platform 1" id="501">
  <segment roadId="1" sStart="40" sEnd="180" side="left"/>
</platform>
```

## Options
- `platform-min-length` (metres, default 100): the shortest platform allowed; the
  segments of a platform count together, on every road they lie on.

## Related rules
ST002 (xodrlint) reports a platform without segments, ST004 and ST005 a segment whose
range lies off its road or is reversed; this rule stays silent on such platforms.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations" (platforms and segments);
  rule UID `example-rail.com:xodr:1.4.0:road.railroad.platform.min_length`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

from xodrlint.rules import Hit, Platform, RailNetwork, RuleOption, Settings, Severity, rule

MIN_LENGTH: Final = RuleOption(
    name="platform-min-length",
    default=100.0,
    description="Shortest platform allowed: its segments together",
)


@rule(
    code="HR003",
    name="platform-too-short",
    uid="example-rail.com:xodr:1.4.0:road.railroad.platform.min_length",
    severity=Severity.WARNING,
    options=(MIN_LENGTH,),
)
def platform_too_short(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    minimum = MIN_LENGTH.number(settings)
    for platform in network.platforms:
        length = _length(platform)
        if length is not None and length < minimum:
            name = f"'{platform.name}'" if platform.name else f"with id '{platform.id}'"
            yield Hit(
                platform.element,
                f"platform {name} is {length:g} m long, shorter than {minimum:g} m "
                f"({MIN_LENGTH.name})",
            )


def _length(platform: Platform) -> float | None:
    """The segments' lengths together; ``None`` when one is unreadable or reversed."""
    total = 0.0
    for segment in platform.segments:
        if segment.s_start is None or segment.s_end is None or segment.s_end < segment.s_start:
            return None
        total += segment.s_end - segment.s_start
    return total if platform.segments else None
