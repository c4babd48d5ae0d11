"""The two track references of a switch, named the way messages name them."""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.model import RailNetwork, Road, Switch, TrackRef


def track_refs(switch: Switch) -> Iterator[tuple[str, TrackRef]]:
    if switch.main_track is not None:
        yield "main track", switch.main_track
    if switch.side_track is not None:
        yield "side track", switch.side_track


def named_road(network: RailNetwork, track: TrackRef) -> Road | None:
    """The road a track names, when it names one that exists."""
    return network.road_by_id.get(track.road_id) if track.road_id is not None else None
