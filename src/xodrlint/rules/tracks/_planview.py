"""The plan views of a railway's tracks, judged once per file: TR008, TR009 and TR014
read them, and the switch and joint rules read the same judgement through the track
points (:class:`~xodrlint.geometry.tracks.TrackGeometry`)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from xodrlint.model import RailNetwork, Road

if TYPE_CHECKING:
    from xodrlint.geometry.evaluable import PlanView


def track_plan_views(network: RailNetwork) -> Iterator[tuple[Road, PlanView]]:
    """Each road with a rail or tram lane, with its plan view judged."""
    from xodrlint.geometry.tracks import TrackGeometry  # loaded only for a railway

    tracks: TrackGeometry | None = None
    for road in network.rail_roads:
        tracks = tracks or network.shared(TrackGeometry)
        yield road, tracks.plan_view(road)
