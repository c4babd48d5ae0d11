"""TR013 track-radius-too-small: a rail or tram lane bends more tightly than any train runs.

## What it does
Reports a plan-view `geometry` record of a track (a road with a rail or tram lane) along
which the centre line of a rail lane bends at a radius below 25 m, or that of a tram lane
below 13 m (by default). The centre line is the lane's own: `laneOffset` plus the widths
of the lanes between it and the reference line and half its own width, each the cubic it
is, so a lane beside the reference line on the inside of a curve bends more tightly than
the reference line. Every rail and tram lane of every lane section the record overlaps
counts; reported once per record, with the smallest radius, where it is and the lane.

Lines, arcs and spirals with the lane at a constant offset are judged exactly (the
tightest point of a spiral is one of its ends); `poly3`, `paramPoly3` and lanes whose
offset varies are sampled at most 1 m apart. Where the lane's centre reaches the
reference line's centre of curvature, or lies beyond it, the lane folds back on itself
(a cusp): radius 0.

## Why is this bad?
This is an inference: the standard describes the plan view but sets no radius. The
defaults flag only curves that no train or tram can run: main lines are laid at
hundreds of metres and more, sidings and depots rarely below 100 to 150 m, and tram
networks at about 15 to 25 m at their tightest (ASAM's own switch example bends its rail
at 29.9 m). A tighter curve is most often a curvature in the wrong unit or sign, a lane
offset to the inside of a curve, or a road's geometry copied onto a track. A project
sets its own line's design minimum (150 m and more on a main line).

## Example
```xml
<planView>
  <!-- the reference line turns right at a radius of 25.5 m; the rail lane's centre, 0.75 m to its right, at 24.75 m -->
  <geometry s="0" x="0" y="0" hdg="0" length="20"><arc curvature="-0.0392156862745098"/></geometry> <!-- expect: TR013 -->
</planView>
```

Use instead:
```xml
<planView>
  <!-- the reference line turns left at a radius of 25.5 m; the rail lane's centre, 0.75 m to its right, at 26.25 m -->
  <geometry s="0" x="0" y="0" hdg="0" length="20"><arc curvature="0.0392156862745098"/></geometry>
</planView>
```

## Options
- `min-radius-rail` (metres, default 25): the tightest radius allowed on a rail lane's
  centre line. Configuration: `min-radius-rail = 25` in `[tool.xodrlint]`; command line:
  `--rule-option min-radius-rail=25`.
- `min-radius-tram` (metres, default 13): the tightest radius allowed on a tram lane's
  centre line. Configuration: `min-radius-tram = 13`; command line:
  `--rule-option min-radius-tram=13`.

## Related rules
TR014 reports a record or road whose plan view cannot be evaluated (a missing,
non-numeric or non-finite value); TR013 stays silent on such a road. A lane described by
`border` instead of `width`, or with an unreadable width or offset, is not judged.

## References
- ASAM OpenDRIVE 1.7, chapter "Geometry" (plan view), chapter "Lanes" (lane offset and
  width), and chapter "Railroads"; rule UID `xodrlint:xodr:1.4.0:road.railroad.track.radius`
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Final

from xodrlint.rules import Hit, RailNetwork, RuleOption, Settings, Severity, rule
from xodrlint.rules._shared import S_TOLERANCE, below, metres, quoted
from xodrlint.rules.tracks._planview import track_plan_views

if TYPE_CHECKING:
    from xodrlint.rules.geometry import LaneBend

MIN_RAIL: Final = RuleOption(
    name="min-radius-rail",
    default=25.0,
    description="Tightest radius of a rail lane's centre line",
)
MIN_TRAM: Final = RuleOption(
    name="min-radius-tram",
    default=13.0,
    description="Tightest radius of a tram lane's centre line",
)


@rule(
    code="TR013",
    name="track-radius-too-small",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.radius",
    severity=Severity.WARNING,
    options=(MIN_RAIL, MIN_TRAM),
    defers_to=("TR014",),
)
def track_radius_too_small(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    from xodrlint.rules.geometry import LaneCurvature, record_elements

    limits = {"rail": MIN_RAIL.number(settings), "tram": MIN_TRAM.number(settings)}
    curvature = network.shared(LaneCurvature)
    tightest_limit = max(limits.values())
    tracks = track_plan_views(network)
    for road, line, bends in curvature.tracks_bending(tracks, tightest_limit):
        tightest: dict[int, LaneBend] = {}  # by the record's index
        for found in bends:
            limit = limits.get(str(found.lane.type), 0.0)
            if found.bend.radius >= limit - S_TOLERANCE:
                continue
            known = tightest.get(found.record)
            if known is None or found.bend.radius < known.bend.radius:
                tightest[found.record] = found
        elements = record_elements(road, line) if tightest else None
        if elements is None:
            continue
        for index, found in sorted(tightest.items()):
            yield Hit(elements[index], _message(road.id, found, limits))


def _message(road_id: str | None, found: LaneBend, limits: dict[str, float]) -> str:
    lane_type = str(found.lane.type)
    limit = limits[lane_type]
    lane = (
        f"{lane_type} lane {quoted(found.lane.element.get('id'))} of road {quoted(road_id)} "
        f"(lane section at s={metres(found.section_start)})"
    )
    bend = found.bend
    if bend.radius == 0:
        return (
            f"centre line of {lane} folds back on itself at s={metres(bend.s)}: it reaches "
            f"the reference line's centre of curvature (radius 0), tighter than "
            f"{metres(limit)} m"
        )
    return (
        f"centre line of {lane} bends at a radius of {below(bend.radius, limit, 2)} m at "
        f"s={metres(bend.s)}, tighter than {metres(limit)} m"
    )
