"""TR014 track-geometry-unreadable: a track's geometry cannot be evaluated, so it is not judged.

## What it does
Reports each `geometry` record of a road with a rail or tram lane that keeps its plan
view from being evaluated, naming the attributes at fault with their values as written:
a parameter that is missing, no number or no finite number (`x="INF"`,
`curvStart="NaN"`, no `@length`, the curve's own coefficients included), no `line`,
`arc`, `spiral`, `poly3` or `paramPoly3`, a length that is not above 0, an unknown
`paramPoly3/@pRange`, a start 1e9 m or more from the origin or a heading of 1e6 rad or
more, a curve that turns more than 64 rad or whose numbers overflow on the way to its
end. A track with no `planView` geometry at all is reported on the `road`. These are
exactly the records for which the geometry rules give up on a track: every track they
are silent on is reported here.

Also reports each `elevationProfile/elevation` and `lateralProfile/superelevation` entry
of such a road with a missing, non-numeric or non-finite `s`, `a`, `b`, `c` or `d`.
Each record or entry is reported once, whatever else is wrong with it.

## Why is this bad?
A value the schema accepts is not always one a reader can compute with: `INF` and `NaN`
are valid `xs:double`s, and ASAM OpenDRIVE requires a geometry record's length to be
above 0 but gives no bound on coordinates. A track whose reference line cannot be
computed has no place on the ground: no tool can run a train along it, and no rule can
tell whether its switches, joints and curves fit. Saying so is better than silence.

## Example
```xml
<planView>
  <geometry s="0" x="0" y="0" hdg="0" length="60"><line/></geometry>
  <geometry s="60" x="60" y="0" hdg="0" length="40"> <!-- expect: TR014 -->
    <spiral curvStart="0" curvEnd="NaN"/>
  </geometry>
</planView>
```

Use instead:
```xml
<planView>
  <geometry s="0" x="0" y="0" hdg="0" length="60"><line/></geometry>
  <geometry s="60" x="60" y="0" hdg="0" length="40">
    <spiral curvStart="0" curvEnd="0.002"/>
  </geometry>
</planView>
```

## Related rules
A track whose plan view TR014 reports is not judged by SW011 and SW012 (its switch
points), TR001 and TR002 (its joints), TR008 (its continuity), TR009 (its length) and
TR013 (its curve radii); an unreadable elevation entry silences TR010 and TR011 there,
an unreadable superelevation entry TR012. A missing or non-numeric value is also the
schema's (XS006, with the official schema): TR014 adds what it keeps from being judged.

## References
- ASAM OpenDRIVE 1.7, chapter "Geometry" (geometry records), chapter "Roads" (elevation
  and superelevation), and the schema (`xs:double`, `t_grZero`); rule UID
  `xodrlint:xodr:1.4.0:road.railroad.track.geometry_readable`
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import TYPE_CHECKING, Final

from lxml import etree

from xodrlint.rules import Hit, RailNetwork, Road, Severity, number, rule
from xodrlint.rules._shared import metres, quoted
from xodrlint.rules.tracks._planview import track_plan_views

if TYPE_CHECKING:
    from xodrlint.rules.geometry import Entry, GeometryProblem

#: What a bad entry of each profile keeps from being judged.
_ELEVATION_NOT_JUDGED: Final = "its gradient and elevation steps are"
_CANT_NOT_JUDGED: Final = "its cant is"
_ENTRY_ATTRIBUTES: Final = ("s", "a", "b", "c", "d")
_NOT_JUDGED: Final = (
    "its plan view cannot be evaluated, so its switch points, joints, continuity, "
    "length and curve radii are not judged"
)


@rule(
    code="TR014",
    name="track-geometry-unreadable",
    uid="xodrlint:xodr:1.4.0:road.railroad.track.geometry_readable",
    severity=Severity.ERROR,
)
def track_geometry_unreadable(network: RailNetwork) -> Iterator[Hit]:
    from xodrlint.rules.geometry import VerticalProfiles

    for road, view in track_plan_views(network):
        for problem in view.problems:
            yield Hit(problem.element, f"{_where(road, problem)}; {_NOT_JUDGED}")
    for road, elevation, superelevation in network.shared(VerticalProfiles).tracks(network):
        yield from _unreadable_entries(road, elevation.unreadable, _ELEVATION_NOT_JUDGED)
        yield from _unreadable_entries(road, superelevation.unreadable, _CANT_NOT_JUDGED)


def _where(road: Road, problem: GeometryProblem) -> str:
    """The track, the record by its s (or its place in the plan view), and why."""
    track = f"track {quoted(road.id)}"
    element = problem.element
    if element is road.element:
        return f"{track}: {problem.message}"
    # the reason's own subject is the record (``geometry lacks ...``): said once
    subject, _, rest = problem.message.partition(" ")
    if subject == element.tag:
        return f"{track}, {_entry(element)} {rest}"
    return f"{track}, {_entry(element)}: {problem.message}"


def _entry(element: etree._Element) -> str:
    """``geometry at s=20``; ``elevation 3`` where its s is unreadable."""
    s = number(element, "s")
    if s is not None:
        return f"{element.tag} at s={metres(s)}"
    parent = element.getparent()
    siblings = list(parent.iterchildren(str(element.tag))) if parent is not None else [element]
    return f"{element.tag} {siblings.index(element) + 1}"


def _unreadable_entries(road: Road, entries: Iterable[Entry], judged: str) -> Iterator[Hit]:
    """Each elevation or superelevation entry with a number that is missing, no number or
    no finite number (the vertical rules read the same entries and stay silent on these)."""
    from xodrlint.rules.geometry import unreadable_numbers

    for entry in entries:
        yield Hit(
            entry.element,
            f"track {quoted(road.id)}, {_entry(entry.element)}: lacks a finite number in "
            f"{unreadable_numbers(entry.element, _ENTRY_ATTRIBUTES)}; {judged} not judged there",
        )
