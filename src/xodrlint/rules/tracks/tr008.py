"""TR008 track-plan-view-discontinuous: a track's reference line breaks between two geometry records.

## What it does
Reports a `geometry` record of a road with a rail or tram lane that does not start where
the record before it (in order of s) ends: the two points are more than the tolerance
(default 0.10 m) apart, or the headings there differ by more than the angle (default 5
degrees, compared on the circle). A record's end is its pose at its own length, computed
for every curve (`line`, `arc`, `spiral`, `poly3`, `paramPoly3` in both `pRange`s); the
next record's start is where its curve begins: its `x`, `y` and `hdg`, moved and turned
by a `poly3`'s own `a` and `b` or a `paramPoly3`'s `aU`, `aV`, `bU` and `bV`. Once per
boundary, on the later record; the message names both records by their s, both points,
and the gap, the angle or both.

## Why is this bad?
ASAM OpenDRIVE says "each road runs along one road reference line", laid out in the plan
view by its geometry records one after another. A reference line that jumps or bends at a
point between two records is not one line: the rails drawn along it have a gap or a kink
that no train can run over, and every position along the track after the break is off.

## Example
```xml
<planView>
  <geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry>
  <!-- the line ends at (100, 0); the next record starts 0.15 m beside it -->
  <geometry s="100" x="100" y="0.15" hdg="0" length="50"><line/></geometry> <!-- expect: TR008 -->
</planView>
```

Use instead:
```xml
<planView>
  <geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry>
  <geometry s="100" x="100" y="0" hdg="0" length="50"><line/></geometry>
</planView>
```

## Options
- `link-tolerance` (metres, default 0.1): the largest distance allowed between the end of
  one record and the start of the next; shared with TR001 (joints). Configuration:
  `link-tolerance = 0.1` in `[tool.xodrlint]`; command line:
  `--rule-option link-tolerance=0.1`.
- `link-angle` (degrees, default 5): the largest angle allowed between the headings
  there; shared with TR002 (joints). Configuration: `link-angle = 5`; command line:
  `--rule-option link-angle=5`.

## Related rules
TR014 reports a track whose plan view cannot be evaluated (an unreadable, zero-length or
overflowing record, or no geometry at all); TR008 stays silent on that track. TR001 and
TR002 judge where two tracks meet at a joint, TR008 where two records of one track meet.

## References
- ASAM OpenDRIVE 1.7, chapter "Geometry" (the plan view and its geometry records) and the
  schema's `t_road` ("each road runs along one road reference line"); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.track.plan_view_continuous`
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import TYPE_CHECKING

from xodrlint.rules import Hit, RailNetwork, Road, Settings, Severity, rule
from xodrlint.rules._shared import S_TOLERANCE, beyond, degrees, metres, point, quoted
from xodrlint.rules.tracks._planview import track_plan_views
from xodrlint.rules.tracks.tr001 import TOLERANCE
from xodrlint.rules.tracks.tr002 import ANGLE

if TYPE_CHECKING:
    from xodrlint.rules.geometry import Pose, Record


@rule(
    code="TR008",
    name="track-plan-view-discontinuous",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.plan_view_continuous",
    severity=Severity.ERROR,
    options=(TOLERANCE, ANGLE),
)
def track_plan_view_discontinuous(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    from xodrlint.rules.geometry import turn_beyond

    tolerance, limit = TOLERANCE.number(settings), ANGLE.number(settings)
    for road, view in track_plan_views(network):
        ends = view.ends  # none where the line cannot be evaluated: TR014 says why
        for index in range(1, len(ends)):  # none for a single record
            end, start = ends[index - 1][1], ends[index][0]
            (end_x, end_y, end_hdg), (start_x, start_y, start_hdg) = end, start
            gap = math.hypot(start_x - end_x, start_y - end_y)
            apart = gap if gap > tolerance + S_TOLERANCE else None
            angle = turn_beyond(end_hdg, start_hdg, limit)
            if apart is not None or angle is not None:
                line = view.line
                assert line is not None  # a line whose ends are known
                records = line.records
                yield Hit(
                    line.elements[index],
                    _message(
                        road,
                        (records[index - 1], end),
                        (records[index], start),
                        (apart, angle),
                        (tolerance, limit),
                    ),
                )


def _message(
    road: Road,
    ending: tuple[Record, Pose],
    starting: tuple[Record, Pose],
    found: tuple[float | None, float | None],
    limits: tuple[float, float],
) -> str:
    """Both records by their s, how far apart and how turned, and both poses."""
    (before, end), (after, start) = ending, starting
    gap, angle = found
    off = []
    if gap is not None:
        off.append(f"{beyond(gap, limits[0], 4)} m away from")
    if angle is not None:
        off.append(f"at {beyond(math.degrees(angle), limits[1], 2)} degrees to")

    def where(pose: Pose) -> str:
        heading = f" heading {degrees(pose.hdg)} degrees" if angle is not None else ""
        return point(pose.x, pose.y) + heading

    return (
        f"track {quoted(road.id)}: geometry at s={metres(after.s)} starts "
        f"{' and '.join(off)} the end of the geometry at s={metres(before.s)} "
        f"({where(start)} and {where(end)})"
    )
