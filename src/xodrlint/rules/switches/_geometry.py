"""Where a switch's two tracks are at the switch: the track points SW011 and SW012 judge."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from xodrlint.rules import RailNetwork, Switch
from xodrlint.rules.switches._tracks import usable_tracks

if TYPE_CHECKING:
    from xodrlint.rules.geometry import TrackGeometry, TrackPoint

SwitchPoints = tuple["TrackPoint", "TrackPoint"]


class _EverySwitch:
    """Each switch's track points, worked out once per file and ``s-tolerance``: SW011
    and SW012 ask for the same ones (a railway has thousands of switches)."""

    def __init__(self, network: RailNetwork) -> None:
        # imported here: a file without switches never loads the plan-view geometry
        from xodrlint.rules.geometry import TrackGeometry

        # no reference back to the network: a cycle would keep each file's model alive
        # until a collection, where the engine frees it as soon as the file is done
        self._tracks = network.shared(TrackGeometry)
        self._points: dict[float, list[SwitchPoints | None]] = {}

    def points(self, network: RailNetwork, tolerance: float) -> list[SwitchPoints | None]:
        found = self._points.get(tolerance)
        if found is None:
            tracks = self._tracks
            found = [_points(network, tracks, switch, tolerance) for switch in network.switches]
            self._points[tolerance] = found
        return found


def switches_with_points(
    network: RailNetwork, tolerance: float
) -> list[tuple[Switch, SwitchPoints]]:
    """Each switch with the main track's and the side track's track points at the switch,
    leaving out a switch a bookkeeping rule reports (SW003 to SW006, under the
    ``s-tolerance`` ``tolerance``) or whose geometry cannot be evaluated."""
    if not network.switches:
        return []
    found = network.shared(_EverySwitch).points(network, tolerance)
    return [
        (switch, points)
        for switch, points in zip(network.switches, found, strict=True)
        if points is not None
    ]


def _points(
    network: RailNetwork, tracks: TrackGeometry, switch: Switch, tolerance: float
) -> SwitchPoints | None:
    roads = usable_tracks(network, switch, tolerance)
    if roads is None or switch.main_track is None or switch.side_track is None:
        return None
    # a position within the tolerance past an end is at that end (data rounded to mm)
    main = tracks.point(roads[0], _on(roads[0].length, switch.main_track.s))
    side = tracks.point(roads[1], _on(roads[1].length, switch.side_track.s)) if main else None
    return (main, side) if main is not None and side is not None else None


def _on(length: float | None, s: float | None) -> float:
    return min(max(s or 0.0, 0.0), length if length is not None else math.inf)
