"""SW011 switch-tracks-apart: a switch's main track and side track do not meet at the switch.

## What it does
Reports a `sideTrack` whose track point at `sideTrack/@s` is more than the tolerance
(default 0.10 m) away from the main track's track point at `mainTrack/@s`. A track point
is the centre line of the road's rail or tram lane when the lane section there holds
exactly one such lane (`laneOffset` plus the lane's inner edge and half its width, the
widths as the cubic polynomials they are), and the reference line otherwise. The message
names both points.

## Why is this bad?
ASAM OpenDRIVE defines `mainTrack/@s` as the s-coordinate of the switch, "the point where
main track and side track meet", and `sideTrack/@s` as the s-coordinate of the switch on
the side track. Both must therefore be the same place on the ground. A side track that
starts metres away from its switch describes a turnout no train can take, and a
simulator that routes a train through it teleports the train.

## Example
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- the switch point is (30, 0); road 2 starts 0.15 m beside it -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/> <!-- expect: SW011 -->
</switch>
```

Use instead:
```xml
<switch name="W1" id="101" position="dynamic">
  <!-- the switch point is (30, 0); road 2 starts there -->
  <mainTrack id="1" s="30" dir="+"/>
  <sideTrack id="2" s="0" dir="+"/>
</switch>
```

## Options
- `switch-tolerance` (metres, default 0.1): the largest distance allowed between the two
  track points. Configuration: `switch-tolerance = 0.1` in `[tool.xodrlint]`; command
  line: `--rule-option switch-tolerance=0.1`.
- `s-tolerance` (metres, default 1e-06): the largest difference between two
  s-coordinates or lengths that counts as none; 0.0005 for data rounded to
  millimetres. Configuration: `s-tolerance = 0.0005` in `[tool.xodrlint]`; command
  line: `--rule-option s-tolerance=0.0005`.

## Fix
Unsafe: `xodrlint check --fix --unsafe-fixes` moves `mainTrack/@s` to the s on the main
track whose track point is nearest the side track's track point, when the two are then
within `switch-tolerance`; a side track that does not reach the main track gets no fix.

## Related rules
SW003, SW004, SW005 and SW006 report a switch whose tracks name the wrong road, no road,
a position off the road or a side track that does not begin or end at the switch; SW011
stays silent on such a switch. SW012 judges the directions only where SW011 finds the
tracks meeting. A road whose plan view cannot be evaluated is left alone (XS006 reports
bad values).

## References
- ASAM OpenDRIVE 1.7, section 15.3.1 "Switches" (`mainTrack/@s`, `sideTrack/@s`); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.switch.tracks_meet`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Final

from xodrlint.rules import (
    Applicability,
    Fix,
    Hit,
    RailNetwork,
    RuleOption,
    Settings,
    Severity,
    Switch,
    rule,
    set_attribute,
)
from xodrlint.rules._shared import S_TOLERANCE, S_TOLERANCE_OPTION, beyond, metres, point, quoted
from xodrlint.rules.switches._geometry import switches_with_points

if TYPE_CHECKING:
    from xodrlint.rules.geometry import TrackPoint

TOLERANCE: Final = RuleOption(
    name="switch-tolerance",
    default=0.1,
    description="Largest distance between a switch's main-track and side-track points",
)


@rule(
    code="SW011",
    name="switch-tracks-apart",
    uid="xodrlint:xodr:1.4.0:road.railroad.switch.tracks_meet",
    severity=Severity.ERROR,
    options=(TOLERANCE, S_TOLERANCE_OPTION),
)
def switch_tracks_apart(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    s_tolerance = S_TOLERANCE_OPTION.number(settings)
    tolerance = TOLERANCE.number(settings)
    for switch, (main, side) in switches_with_points(network, s_tolerance):
        if switch.main_track is None or switch.side_track is None:
            continue
        distance = main.distance_to(side)
        if distance > tolerance + S_TOLERANCE:
            # SW006 holds: the side track's s is its road's start or end
            begins = "starts" if abs(switch.side_track.s or 0.0) <= s_tolerance else "ends"
            yield Hit(
                switch.side_track.element,
                f"side track of switch {quoted(switch.id)} {begins} {beyond(distance, tolerance, 4)} m "
                f"from the switch point on road '{switch.main_track.road_id}' at "
                f"s={metres(switch.main_track.s or 0.0)} "
                f"(main track at {point(main.x, main.y)}, side track at "
                f"{point(side.x, side.y)})",
                fix=_moved_main_track(network, switch, side, tolerance),
            )


def _moved_main_track(
    network: RailNetwork, switch: Switch, side: TrackPoint, tolerance: float
) -> Fix | None:
    """``mainTrack/@s`` := the s whose track point on the main track is nearest the side
    track's, where the two are then within ``switch-tolerance``; else no fix (the side
    track does not reach the main track at all)."""
    from xodrlint.rules.geometry import TrackGeometry

    main_track = switch.main_track
    road = network.road_by_id.get(main_track.road_id or "") if main_track else None
    if main_track is None or road is None or road.length is None:
        return None
    tracks = network.shared(TrackGeometry)
    nearest = tracks.nearest(road, side)
    if nearest is None or nearest[1].distance_to(side) > tolerance:
        return None
    written = f"{nearest[0]:.6f}".rstrip("0").rstrip(".")
    moved = tracks.point(road, float(written))
    if moved is None or moved.distance_to(side) > tolerance:
        return None
    return Fix(
        f"move the switch to s={written} on road '{road.id}', where the side track starts",
        (set_attribute(main_track.element, "s", written),),
        Applicability.UNSAFE,
    )
