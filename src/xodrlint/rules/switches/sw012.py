"""SW012 switch-direction-mismatch: a switch sends trains onto its side track in another direction.

## What it does
Reports a `switch` where the direction of travel on the main track (`mainTrack/@dir` at
`mainTrack/@s`) and on the side track after entering it (`sideTrack/@dir` at
`sideTrack/@s`) differ by more than the tolerance (default 15 degrees). The direction of
travel is the road's reference-line heading at s for `+`, and that heading plus pi for
`-`; the two are compared as the smallest angle between them.

## Why is this bad?
ASAM OpenDRIVE defines `mainTrack/@dir` as the direction on the main track "for entering
the side track via the switch" and `sideTrack/@dir` as the direction on the side track
"for after entering it via the switch". A train keeps its heading through a turnout: the
side track leaves the main track at a small angle. Directions that differ by more say
that one of the `dir` values, or one of the roads, points the wrong way: a train routed
through the switch would reverse or turn on the spot.

## Example
```xml
<switch name="W1" id="101" position="dynamic"> <!-- expect: SW012 -->
  <!-- road 1 heads 0 rad at s=30; road 2 leaves the switch point at 20 degrees -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
</switch>
```

Use instead:
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- road 1 heads 0 rad at s=30; road 2 leaves the switch point at 6 degrees -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
</switch>
```

## Options
- `switch-angle` (degrees, default 15): the largest angle allowed between the two
  directions of travel. Configuration: `switch-angle = 15` in `[tool.xodrlint]`;
  command line: `--rule-option switch-angle=15`.
- `switch-tolerance` (metres, default 0.1): shared with SW011; SW012 judges only switches
  whose track points are at most this far apart.
- `s-tolerance` (metres, default 1e-06): the largest difference between two
  s-coordinates or lengths that counts as none; 0.0005 for data rounded to
  millimetres. Configuration: `s-tolerance = 0.0005` in `[tool.xodrlint]`; command
  line: `--rule-option s-tolerance=0.0005`.

## Fix
Unsafe: `xodrlint check --fix --unsafe-fixes` flips the main track's `@dir`, when the
flip brings the two directions within `switch-angle`. The side track's `@dir` is the one
its road end dictates (SW006 reports it otherwise), so the main track's is the wrong one.

## Related rules
SW003, SW004, SW005 and SW006 report a switch whose tracks cannot be judged; SW012 stays
silent on it. SW011 reports tracks that do not meet at the switch; their directions are
taken at two different places and say nothing, so SW012 stays silent there too. A road
whose plan view cannot be evaluated is left alone.

## References
- ASAM OpenDRIVE 1.7, section 15.3.1 "Switches" (`mainTrack/@dir`, `sideTrack/@dir`); rule
  UID `xodrlint:xodr:1.4.0:road.railroad.switch.directions_agree`
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Final

from xodrlint.rules import (
    Applicability,
    Fix,
    Hit,
    RailNetwork,
    RuleOption,
    Settings,
    Severity,
    TrackRef,
    rule,
    set_attribute,
)
from xodrlint.rules._shared import S_TOLERANCE, S_TOLERANCE_OPTION, beyond, degrees, metres, quoted
from xodrlint.rules.switches._geometry import switches_with_points
from xodrlint.rules.switches.sw011 import TOLERANCE

ANGLE: Final = RuleOption(
    name="switch-angle",
    default=15.0,
    description="Largest angle between the directions of travel on a switch's two tracks",
    unit="degrees",
)


@rule(
    code="SW012",
    name="switch-direction-mismatch",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.directions_agree",
    severity=Severity.ERROR,
    options=(ANGLE, TOLERANCE, S_TOLERANCE_OPTION),
)
def switch_direction_mismatch(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    s_tolerance = S_TOLERANCE_OPTION.number(settings)
    from xodrlint.rules.geometry import turn_beyond

    limit = ANGLE.number(settings)
    apart = TOLERANCE.number(settings) + S_TOLERANCE
    for switch, (main_point, side_point) in switches_with_points(network, s_tolerance):
        main, side = switch.main_track, switch.side_track
        if main is None or side is None or main.dir not in ("+", "-") or side.dir not in ("+", "-"):
            continue
        if main_point.distance_to(side_point) > apart:
            continue  # SW011's defect: directions at two places say nothing
        entering = main_point.direction(main.dir)
        leaving = side_point.direction(side.dir)
        angle = turn_beyond(entering, leaving, limit)
        if angle is not None:
            yield Hit(
                switch.element,
                f"switch {quoted(switch.id)} turns trains by "
                f"{beyond(math.degrees(angle), limit, 2)} degrees: main track "
                f"'{main.road_id}' at s={metres(main.s or 0.0)} runs {degrees(entering)} "
                f"degrees ('{main.dir}'), side track '{side.road_id}' at "
                f"s={metres(side.s or 0.0)} runs {degrees(leaving)} degrees ('{side.dir}')",
                fix=_flipped(main, entering + math.pi, leaving, limit),
            )


def _flipped(main: TrackRef, flipped: float, leaving: float, limit: float) -> Fix | None:
    """The main track's ``dir`` flipped, where that brings the two directions within
    ``switch-angle``. The side track's ``dir`` is the one its road end dictates (SW006
    holds here: '+' at its start, '-' at its end), so the main track's is the wrong one."""
    from xodrlint.rules.geometry import turn_beyond

    if turn_beyond(flipped, leaving, limit) is not None:
        return None
    direction = "-" if main.dir == "+" else "+"
    return Fix(
        f"let the main track point '{direction}'",
        (set_attribute(main.element, "dir", direction),),
        Applicability.UNSAFE,
    )
