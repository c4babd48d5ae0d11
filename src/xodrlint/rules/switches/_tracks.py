"""The two track references of a switch, named the way messages name them, and what makes
a side track unusable (SW006), which the geometry rules must not judge again."""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import RailNetwork, Road, Switch, TrackRef
from xodrlint.rules._shared import metres, within


def track_refs(switch: Switch) -> Iterator[tuple[str, TrackRef]]:
    if switch.main_track is not None:
        yield "main track", switch.main_track
    if switch.side_track is not None:
        yield "side track", switch.side_track


def named_road(network: RailNetwork, track: TrackRef) -> Road | None:
    """The road a track names, when it names one that exists."""
    return network.road_by_id.get(track.road_id) if track.road_id is not None else None


def side_track_problem(road: Road, side: TrackRef, tolerance: float) -> str | None:
    """Why ``side`` cannot be where its road begins or ends, pointing onto it (SW006's
    words after "side track of switch 'ID' "), or ``None``; ``tolerance`` is the
    ``s-tolerance``. Silent when the road's length or the position is unknown."""
    if road.length is None or side.s is None:
        return None
    at_start = abs(side.s) <= tolerance
    at_end = abs(side.s - road.length) <= tolerance
    if not at_start and not at_end:
        return (
            f"is at s={metres(side.s)} of road '{road.id}', not at its start (0) "
            f"or end ({metres(road.length)})"
        )
    if at_start != at_end and side.dir in ("+", "-"):
        expected = "+" if at_start else "-"
        if side.dir != expected:
            end = "start" if at_start else "end"
            return (
                f"is at the {end} of road '{road.id}' but points '{side.dir}', "
                f"off the road (expected '{expected}')"
            )
    return None


def usable_tracks(
    network: RailNetwork, switch: Switch, tolerance: float
) -> tuple[Road, Road] | None:
    """The main and side track roads of a switch that no bookkeeping rule reports (SW003,
    SW004, SW005, SW006, under the ``s-tolerance`` ``tolerance``): the only switches
    whose geometry is worth judging."""
    main, side = switch.main_track, switch.side_track
    if main is None or side is None or main.s is None or side.s is None:
        return None
    main_road, side_road = named_road(network, main), named_road(network, side)
    if main_road is None or side_road is None or main.road_id != switch.road.id:
        return None
    for track, road in ((main, main_road), (side, side_road)):
        if road.length is None or not within(track.s or 0.0, 0.0, road.length, tolerance):
            return None
    if side_track_problem(side_road, side, tolerance) is not None:
        return None
    return main_road, side_road
