"""TR010 track-elevation-step: a track's elevation jumps where a train cannot climb.

## What it does
Reports a track (a road with a rail or tram lane) whose elevation jumps by more than the
tolerance (default 0.05 m):

- between two consecutive `elevation` entries of its `elevationProfile`: the value the
  earlier entry's cubic reaches at the later entry's `s`, against the later entry's `a`;
  reported on the later `elevation`;
- at a joint (a road link, `elementType="road"`, between two tracks): the elevation at the
  end of one road that the link joins, against the elevation at the other road's
  `contactPoint` end; reported on the `predecessor` or `successor`, once per joint (on
  the link of the road that comes first in the document when both name each other).

Each entry holds from its `s` to the next entry's `s`, the last one to the road's
`@length`; a road without `elevation` entries lies at elevation 0. Elevations are those
of the reference line.

## Why is this bad?
This is an inference from the standard: OpenDRIVE describes a road's height as a chain
of cubic polynomials, and a road link says that a vehicle leaving one road enters the
other there, so the height must run on without a break. A road vehicle may bump over a
few centimetres; a rail cannot step: a step in a track's elevation is a step in the rails,
which derails a train in a simulator and makes a vertical alignment no designer drew.

## Example
```xml
<elevationProfile>
  <!-- the first entry ends at 10 + 0.01·50 = 10.5 m; the next starts at 10.6 m -->
  <elevation s="0" a="10" b="0.01" c="0" d="0"/>
  <elevation s="50" a="10.6" b="0.01" c="0" d="0"/> <!-- expect: TR010 -->
</elevationProfile>
```

Use instead:
```xml
<elevationProfile>
  <!-- the first entry ends at 10.5 m, where the next starts -->
  <elevation s="0" a="10" b="0.01" c="0" d="0"/>
  <elevation s="50" a="10.5" b="0.01" c="0" d="0"/>
</elevationProfile>
```

## Options
- `elevation-tolerance` (metres, default 0.05): the largest step allowed in a track's
  elevation. Configuration: `elevation-tolerance = 0.05` in `[tool.xodrlint]`; command
  line: `--rule-option elevation-tolerance=0.05`.

## Related rules
TR003 (the link names no road), TR005 (the link has no contact point) and TR004 (the
link is not answered) report a link whose joint is unknown; TR010 stays silent on that
link. TR014 reports an `elevation` entry with a missing, non-numeric or non-finite value;
TR010 judges no step into or out of it. TR011 judges the gradient inside each entry.

## References
- ASAM OpenDRIVE 1.7, chapter "Roads", sections "Road linkage" and "Elevation", and
  chapter "Railroads"; rule UID `xodrlint:xodr:1.4.0:road.railroad.track.elevation_step`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Final

from xodrlint.rules import Hit, RailNetwork, RuleOption, Settings, Severity, rule
from xodrlint.rules._shared import S_TOLERANCE, beyond, metres, quoted
from xodrlint.rules.tracks._network import joints

if TYPE_CHECKING:
    from xodrlint.rules.geometry import VerticalProfiles

TOLERANCE: Final = RuleOption(
    name="elevation-tolerance",
    default=0.05,
    description="Largest step in a track's elevation, between two entries or at a joint",
)


@rule(
    code="TR010",
    name="track-elevation-step",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.elevation_step",
    severity=Severity.ERROR,
    options=(TOLERANCE,),
    defers_to=("TR003", "TR004", "TR005", "TR014"),
)
def track_elevation_step(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    from xodrlint.rules.geometry import VerticalProfiles

    tolerance = TOLERANCE.number(settings)
    profiles = network.shared(VerticalProfiles)
    yield from _steps_inside_tracks(network, profiles, tolerance)
    yield from joint_steps(network, profiles, tolerance)


def _steps_inside_tracks(
    network: RailNetwork, profiles: VerticalProfiles, tolerance: float
) -> Iterator[Hit]:
    for road, elevation, _ in profiles.tracks(network):
        for step in elevation.steps():
            size = abs(step.after - step.before)
            if size > tolerance + S_TOLERANCE:
                yield Hit(
                    step.element,
                    f"elevation of road {quoted(road.id)} steps {beyond(size, tolerance, 4)} m "
                    f"at s={metres(step.s)}: the entry before reaches {metres(step.before)} m, "
                    f"this one starts at {metres(step.after)} m",
                )


def joint_steps(
    network: RailNetwork, profiles: VerticalProfiles, tolerance: float
) -> Iterator[Hit]:
    """The steps at joints: each joint once, judged by its link and the two ends it joins
    (a joint's ``link``, ``first``, ``first_end``, ``second`` and ``second_end``)."""
    elevated = {road for road, elevation, _ in profiles.tracks(network) if elevation.entries}
    if not elevated:
        return  # every track at elevation 0
    for joint in joints(network):
        if joint.first not in elevated and joint.second not in elevated:
            continue  # both ends at elevation 0
        ends = []
        for road, end, _, _ in joint.sides():
            s = 0.0 if end == "start" else road.length
            elevation = profiles.elevation_at(road, s) if s is not None else None
            if elevation is None:
                break
            ends.append((road, end, elevation))
        else:
            (first, first_end, here), (second, second_end, there) = ends
            size = abs(there - here)
            if size > tolerance + S_TOLERANCE:
                yield Hit(
                    joint.link.element,
                    f"{joint.link.element.tag} of road {quoted(first.id)} joins its "
                    f"{first_end} at elevation {metres(here)} m to the {second_end} of road "
                    f"{quoted(second.id)} at {metres(there)} m, a step of "
                    f"{beyond(size, tolerance, 4)} m",
                )
