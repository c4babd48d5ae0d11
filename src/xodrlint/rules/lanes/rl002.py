"""RL002 refline-not-centered: a rail lane's centre is away from the road's reference line.

## What it does
On a road whose left and right lanes are only `rail`/`tram` lanes and non-traffic lanes
(`none`, `border`, `shoulder`, `curb`, `sidewalk`, `walking`, `median`; the type of the
centre lane, which has no width, does not count), reports the rail lane of a lane section
with exactly one rail or tram lane when the centre line of that lane is more than the
tolerance (0.05 m by default) away from the reference line anywhere along the lane
section; once per lane section. A `laneOffset` value, or a `width` value of a lane between
the centre lane and the rail lane, that is no finite number (`INF`, `-INF`, `NaN`,
`1e999`: valid `xs:double`s the schema may accept) places the centre nowhere: it is
reported as written (the rail lane's own width is RL003's).

The centre is computed exactly: `laneOffset` and the `width` of every lane between the
centre lane and the rail lane are the cubic polynomials they are, each piece on its whole
stretch, including the point where a new `width` or `laneOffset` entry starts; the
largest distance is found where the polynomial's derivative vanishes, not by sampling.

It applies to files that declare OpenDRIVE 1.7 or later, the version that introduced the
convention: a file declaring 1.4 to 1.6 is not judged by it (the run's note names the
files), unless the run applies every rule to every version (`--all-versions`, or
`all-versions = true` in the configuration). A file whose version cannot be read (XS004)
is judged.

## Why is this bad?
ASAM OpenDRIVE 1.7 says the reference line of a railroad track lies in the centre of its
rail lane: the reference line is the track axis that switches, stations and vehicle
positions refer to. A rail lane off the reference line puts trains beside their own
track. Earlier versions say nothing of it: their exporters (SUMO writes 1.4) put the
reference line at a lane's edge, which is no defect of theirs.

## Example
```xml
<laneOffset s="0" a="0.75" b="0.0024" c="-0.000024" d="0"/>
<laneSection s="0">
  <center><lane id="0" type="none" level="false"/></center>
  <right>
    <lane id="-1" type="rail" level="false"> <!-- expect: RL002 -->
      <width sOffset="0" a="1.5" b="0" c="0" d="0"/>
    </lane>
  </right>
```

Use instead:
```xml
<laneOffset s="0" a="0.75" b="0" c="0" d="0"/>
<laneSection s="0">
  <center><lane id="0" type="none" level="false"/></center>
  <right>
    <lane id="-1" type="rail" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane>
    <lane id="-2" type="sidewalk" level="false"><width sOffset="0" a="2" b="0" c="0" d="0"/></lane>
  </right>
</laneSection>
```

## Options
- `refline-tolerance` (metres, default 0.05): the largest distance allowed between the
  centre of the rail lane and the reference line. Command line: `--refline-tolerance`.

## Related rules
RL001 reports a lane section with several rail lanes; RL002 only judges lane sections
with exactly one. RL004 reports roads shared with road traffic, which RL002 leaves out.
Where RL002 is not applied (a file declaring 1.4 to 1.6), TR001, TR002 and TR007 judge
such roads by their joined lanes as usual.
Lanes described by `border` instead of `width`, and unreadable coefficients, leave the
lane section unjudged.

## References
- ASAM OpenDRIVE 1.7, chapter "Railroads" and chapter "Lanes" (lane offset, lane width);
  rule UID `asam.net:xodr:1.7.0:road.railroad.rail_refline_centered`
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Final, NamedTuple

from xodrlint.rules import (
    NON_TRAFFIC_LANE_TYPES,
    RAIL_LANE_TYPES,
    S_TOLERANCE,
    Hit,
    Lane,
    LaneSection,
    RailNetwork,
    Road,
    RuleOption,
    Settings,
    Severity,
    centre_terms,
    extremes,
    number,
    rule,
)
from xodrlint.rules._shared import first_non_finite, metres
from xodrlint.rules.lanes._labels import lane_label
from xodrlint.rules.lanes._templates import judged_once_per_layout, own_lane, ranged_sections

TOLERANCE: Final = RuleOption(
    name="refline-tolerance",
    default=0.05,
    description="Largest distance of a rail lane's centre from the reference line",
)
_TRACK_ROAD_LANE_TYPES: Final = RAIL_LANE_TYPES | NON_TRAFFIC_LANE_TYPES


def _is_track_road(road: Road) -> bool:
    # the centre lane has no width and carries nothing, whatever its type says
    lanes = [
        lane for section in road.lane_sections for lane in section.lanes if lane.side != "center"
    ]
    return any(lane.is_rail for lane in lanes) and all(
        lane.type in _TRACK_ROAD_LANE_TYPES for lane in lanes
    )


@rule(
    code="RL002",
    name="refline-not-centered",
    uid="asam.net:xodr:1.7.0:road.railroad.rail_refline_centered",
    severity=Severity.WARNING,
    options=(TOLERANCE,),
    since=(1, 7),
)
def refline_not_centered(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    tolerance = TOLERANCE.number(settings)

    def off_centre(template: Road, length: float | None) -> list[_OffCentre]:
        if not _is_track_road(template):
            return []
        found = []
        for index, section, start, end in ranged_sections(template, length):
            rails = [i for i, lane in enumerate(section.lanes) if lane.is_rail]
            if len(rails) != 1:
                continue
            rail = section.lanes[rails[0]]
            terms = centre_terms(template, section, start, rail)
            if terms is None:  # a value that is no finite number places the centre nowhere
                written = _non_finite_placement(template, section, rail, (index, start, end))
                if written is not None:
                    found.append(_OffCentre(index, rails[0], start, math.nan, start, written))
                continue
            farthest = extremes(terms, start, end)
            if farthest is None:
                continue
            distance, s = max(
                (abs(farthest.low), farthest.s_low), (abs(farthest.high), farthest.s_high)
            )
            if distance > tolerance + S_TOLERANCE:
                found.append(_OffCentre(index, rails[0], start, distance, s))
        return found

    for road, off in judged_once_per_layout(network, off_centre, by_length=True):
        for found in off:
            _, lane = own_lane(road, found.section, found.lane)
            centre = f"the centre of {lane.type} {lane_label(lane, road, found.start)}"
            if found.written is not None:
                message = f"{centre} lies nowhere: {found.written}"
            else:
                message = (
                    f"{centre} is {metres(found.distance)} m from the reference line at "
                    f"s={metres(found.s)} (tolerance {metres(tolerance)} m)"
                )
            yield Hit(lane.element, message)


def _non_finite_placement(
    template: Road, section: LaneSection, rail: Lane, where: tuple[int, float, float]
) -> str | None:
    """What places ``rail``'s centre in this lane section and is no finite number, as
    written: a ``laneOffset`` value that reaches the section, or a width value of a lane
    between the rail lane and the centre lane (its own width is RL003's to report)."""
    written = _offset_reaching(template, where)
    if written is not None:
        return f"laneOffset has {written}"
    depth = abs(rail.id) if rail.id is not None else 0
    for lane in section.lanes:
        if lane.side == rail.side and lane.id is not None and 0 < abs(lane.id) < depth:
            widths = lane.element.iterchildren("width")
            written = first_non_finite(widths, ("sOffset", "a", "b", "c", "d"))
            if written is not None:
                return f"lane '{lane.id}' has a width entry with {written}"
    return None


def _offset_reaching(template: Road, where: tuple[int, float, float]) -> str | None:
    """A non-finite value of a ``laneOffset`` entry that holds somewhere in the section
    ``where`` (its index, start and end): an entry holds from its s to the next entry's.
    An entry whose own s is no finite number is reported with the first section only."""
    index, start, end = where
    entries = [
        entry
        for lanes in template.element.iterchildren("lanes")
        for entry in lanes.iterchildren("laneOffset")
    ]
    starts = [number(entry, "s") for entry in entries]
    for position, entry in enumerate(entries):
        begins = starts[position]
        if begins is None:
            if index == 0:
                written = first_non_finite([entry], _CUBIC_VALUES)
                if written is not None:
                    return written
            continue
        following = [s for s in starts[position + 1 :] if s is not None and s > begins]
        ends = min(following, default=math.inf)
        if begins < end and ends > start:
            written = first_non_finite([entry], _CUBIC_VALUES[1:])
            if written is not None:
                return written
    return None


_CUBIC_VALUES: Final = ("s", "a", "b", "c", "d")


class _OffCentre(NamedTuple):
    section: int
    lane: int
    start: float
    distance: float
    s: float
    written: str | None = None
    """What places the centre nowhere, as written (``laneOffset has a=INF``)."""
