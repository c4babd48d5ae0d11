"""The joints of a railway: the ends of two rail roads that a road link joins, each once."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import TYPE_CHECKING, NamedTuple

from xodrlint.model import RailNetwork, Road, RoadLink

if TYPE_CHECKING:
    from xodrlint.geometry.tracks import TrackPoint

#: A road's end, as a link names it: where it is and the way a train leaves through it.
_ENDS = {"start": "-", "end": "+"}


class Joint(NamedTuple):
    """Two rail roads joined by ``link``: the first leaves at ``first_end``, the second is
    entered at ``second_end`` (``start`` or ``end``), with their track points there."""

    link: RoadLink
    first: Road
    first_end: str
    second: Road
    second_end: str
    first_point: TrackPoint
    second_point: TrackPoint

    @property
    def leaving(self) -> float:
        """The direction of travel leaving the first road through the joint."""
        return self.first_point.direction(_ENDS[self.first_end])

    @property
    def entering(self) -> float:
        """The direction of travel entering the second road through the joint."""
        return self.second_point.direction("-" if _ENDS[self.second_end] == "+" else "+")

    def describe(self) -> str:
        """How messages name the joint."""
        return (
            f"{self.link.kind} of road '{self.first.id}' joins its {self.first_end} to the "
            f"{self.second_end} of road '{self.second.id}'"
        )


def joints(network: RailNetwork) -> list[Joint]:
    """Each joint between two roads with a rail or tram lane, once: on the link of the road
    that comes first in the document when both name each other. Joints whose track points
    cannot be evaluated (no usable plan view, an unreadable lane) are left out. Worked
    out once per file: TR001 and TR002 judge the same joints."""
    return network.shared(_EveryJoint).joints


class _EveryJoint:
    def __init__(self, network: RailNetwork) -> None:
        self.joints = list(_find_joints(network))


def _find_joints(network: RailNetwork) -> Iterator[Joint]:
    from xodrlint.geometry.tracks import TrackGeometry  # loaded only for a railway's links

    seen: set[frozenset[tuple[int, str]]] = set()
    tracks: TrackGeometry | None = None
    for road in network.rail_roads:
        for link in road.links:
            other = _linked_rail_road(network, link)
            own_end = "start" if link.kind == "predecessor" else "end"
            if other is None or link.contact_point not in _ENDS:
                continue
            key = frozenset({(id(road.element), own_end), (id(other.element), link.contact_point)})
            if key in seen:
                continue
            seen.add(key)
            tracks = tracks or network.shared(TrackGeometry)
            first = tracks.point(road, _s_at(road, own_end))
            second = tracks.point(other, _s_at(other, link.contact_point))
            if first is not None and second is not None:
                yield Joint(link, road, own_end, other, link.contact_point, first, second)


def _linked_rail_road(network: RailNetwork, link: RoadLink) -> Road | None:
    if link.element_type != "road" or link.element_id is None:
        return None
    other = network.road_by_id.get(link.element_id)
    return other if other is not None and other.has_rail_lane else None


def _s_at(road: Road, end: str) -> float:
    return 0.0 if end == "start" else (road.length if road.length is not None else math.nan)
