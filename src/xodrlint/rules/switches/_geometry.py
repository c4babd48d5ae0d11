"""Where a switch's two tracks are at the switch: the track points SW011 and SW012 judge."""

from __future__ import annotations

from typing import TYPE_CHECKING

from xodrlint.model import RailNetwork, Switch
from xodrlint.rules.switches._tracks import usable_tracks

if TYPE_CHECKING:
    from xodrlint.geometry.tracks import TrackPoint


def switch_points(network: RailNetwork, switch: Switch) -> tuple[TrackPoint, TrackPoint] | None:
    """The main track's and the side track's track points at the switch, or ``None`` for
    a switch a bookkeeping rule reports (SW003 to SW006) or whose geometry cannot be
    evaluated."""
    roads = usable_tracks(network, switch)
    if roads is None or switch.main_track is None or switch.side_track is None:
        return None
    # imported here: a file without switches never loads the plan-view geometry
    from xodrlint.geometry.tracks import TrackGeometry

    tracks = network.shared(TrackGeometry)
    main = tracks.point(roads[0], switch.main_track.s or 0.0)
    side = tracks.point(roads[1], switch.side_track.s or 0.0) if main is not None else None
    return (main, side) if main is not None and side is not None else None
