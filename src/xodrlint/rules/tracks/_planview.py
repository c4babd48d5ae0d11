"""The plan views of a railway's tracks, judged once per file: TR008, TR009 and TR014
read them, and the switch and joint rules read the same judgement through the track
points (:class:`~xodrlint.geometry.tracks.TrackGeometry`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from xodrlint.rules import RailNetwork, Road

if TYPE_CHECKING:
    from xodrlint.rules.geometry import PlanView


class TrackPlanViews(list[tuple[Road, "PlanView"]]):
    """Each road with a rail or tram lane, with its plan view judged; listed once per file
    (through :meth:`~xodrlint.model.RailNetwork.shared`) for the rules that pass over
    every track."""

    def __init__(self, network: RailNetwork) -> None:
        from xodrlint.rules.geometry import TrackGeometry  # loaded only for a railway

        roads = network.rail_roads
        super().__init__(network.shared(TrackGeometry).plan_views(roads) if roads else ())


def track_plan_views(network: RailNetwork) -> list[tuple[Road, PlanView]]:
    """Each road with a rail or tram lane, with its plan view judged."""
    return network.shared(TrackPlanViews)
