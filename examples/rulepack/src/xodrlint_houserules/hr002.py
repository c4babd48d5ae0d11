r"""HR002 station-name-pattern: a station name does not follow the house style.

## What it does
Reports a station whose `@name` does not match, as a whole, the regular expression
`station-name-pattern` (Python syntax). The default asks for words separated by single
spaces, without blanks at either end; a house sets its own scheme, for example
`[A-Z][a-z]+( [A-Z][a-z]+)*( Hbf)?`. A station without a name is left to the schema.

## Why is this bad?
Station names reach passenger information, timetables and the operator's asset register
from the map. A name with doubled or trailing blanks, or in another scheme, does not
match the register's entry, and the station goes missing downstream.

## Example
```xml
<station name="Example  Halt" id="500" type="small"> <!-- expect: HR002 -->
```

Use instead:
```xml
<station name="Example Halt" id="500" type="small">
```

## Options
- `station-name-pattern` (a regular expression, default `\S+( \S+)*`): what a whole
  station name must match. Set it in the configuration file
  (`station-name-pattern = '[A-Z][a-z]+( [A-Z][a-z]+)*'`) or on the command line
  (`--rule-option 'station-name-pattern=[A-Z].*'`).

## Fix
Safe: where the name with its runs of blanks made single spaces, and none at either end,
matches the pattern, `xodrlint check --fix` writes that name (`"Example  Halt"` becomes
`"Example Halt"`). A name in another scheme gets no fix: only a person can rename it.

## Related rules
ST008 (xodrlint) reports two stations with one name.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads", section "Stations" (`@name`: "unique name
  of the station"); rule UID `example-rail.com:xodr:1.4.0:road.railroad.station.name_style`
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import Final

from xodrlint.rules import (
    Fix,
    Hit,
    RailNetwork,
    RuleOption,
    Settings,
    Severity,
    rule,
    set_attribute,
)

PATTERN: Final = RuleOption(
    name="station-name-pattern",
    default=r"\S+( \S+)*",
    description="What a whole station name must match (a Python regular expression)",
    kind="regex",
)


@rule(
    code="HR002",
    name="station-name-pattern",
    uid="example-rail.com:xodr:1.4.0:road.railroad.station.name_style",
    severity=Severity.WARNING,
    options=(PATTERN,),
)
def station_name_pattern(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    pattern = re.compile(PATTERN.text(settings))
    for station in network.stations:
        if station.name is not None and not pattern.fullmatch(station.name):
            # rule API 1.3: a fix is a message and edits, made with the API's helpers
            tidy = " ".join(station.name.split())
            fix = (
                Fix(f"name it '{tidy}'", (set_attribute(station.element, "name", tidy),))
                if tidy != station.name and pattern.fullmatch(tidy)
                else None
            )
            yield Hit(
                station.element,
                f"station name '{station.name}' does not match '{pattern.pattern}' "
                f"({PATTERN.name})",
                fix=fix,
            )
