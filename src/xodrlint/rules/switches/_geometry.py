"""Where a switch's two tracks are at the switch: the track points SW011 and SW012 judge."""

from __future__ import annotations

from typing import TYPE_CHECKING

from xodrlint.model import RailNetwork, Switch
from xodrlint.rules.switches._tracks import usable_tracks

if TYPE_CHECKING:
    from xodrlint.geometry.tracks import TrackGeometry, TrackPoint

SwitchPoints = tuple["TrackPoint", "TrackPoint"]


class _EverySwitch:
    """Each switch's track points, worked out once per file: SW011 and SW012 ask for the
    same ones (a railway has thousands of switches)."""

    def __init__(self, network: RailNetwork) -> None:
        # imported here: a file without switches never loads the plan-view geometry
        from xodrlint.geometry.tracks import TrackGeometry

        tracks = network.shared(TrackGeometry)
        self.points = [_points(network, tracks, switch) for switch in network.switches]


def switches_with_points(network: RailNetwork) -> list[tuple[Switch, SwitchPoints]]:
    """Each switch with the main track's and the side track's track points at the switch,
    leaving out a switch a bookkeeping rule reports (SW003 to SW006) or whose geometry
    cannot be evaluated."""
    if not network.switches:
        return []
    found = network.shared(_EverySwitch).points
    return [
        (switch, points)
        for switch, points in zip(network.switches, found, strict=True)
        if points is not None
    ]


def _points(network: RailNetwork, tracks: TrackGeometry, switch: Switch) -> SwitchPoints | None:
    roads = usable_tracks(network, switch)
    if roads is None or switch.main_track is None or switch.side_track is None:
        return None
    main = tracks.point(roads[0], switch.main_track.s or 0.0)
    side = tracks.point(roads[1], switch.side_track.s or 0.0) if main is not None else None
    return (main, side) if main is not None and side is not None else None
