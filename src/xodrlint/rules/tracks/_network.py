"""The track network of one file, judged once and shared by the track-network rules: its
links (:mod:`._joints`: TR003-TR005), its joints and their joined lanes (TR001, TR002,
TR007, TR010) and where its rail lanes' lane links point (:mod:`._lane_links`: TR006,
TR007)."""

from __future__ import annotations

from collections.abc import Callable, Iterator

from xodrlint.rules import Fix, Hit, RailNetwork
from xodrlint.rules.tracks._joints import Joint, TrackLink, find_joints, judged_links
from xodrlint.rules.tracks._lane_links import LaneLinkTarget, lane_link_targets


class TrackNetwork:
    """The judged links, joints and lane links of one file (see the module docstring);
    made once per file through :meth:`~xodrlint.model.RailNetwork.shared`."""

    def __init__(self, network: RailNetwork) -> None:
        self.links: list[TrackLink] = judged_links(network)
        self.joints: list[Joint] = list(find_joints(network, self.links))
        self.lane_links: list[LaneLinkTarget] = list(lane_link_targets(network, self.links))


def track_network(network: RailNetwork) -> TrackNetwork:
    """The one :class:`TrackNetwork` of ``network``'s file."""
    return network.shared(TrackNetwork)


def link_faults(
    network: RailNetwork, fault: str, fix: Callable[[TrackLink], Fix | None] | None = None
) -> Iterator[Hit]:
    """A finding on each link of a track that is wrong by the rule ``fault`` names and
    is reported on that link (TR003, TR004, TR005), with the fix ``fix`` makes of it."""
    for judged in track_network(network).links:
        if judged.fault == fault and judged.reported:
            link = judged.link
            yield Hit(
                link.element,
                f"{link.kind} of road '{judged.road.id}' {judged.why}",
                fix=fix(judged) if fix is not None else None,
            )


def joints(network: RailNetwork) -> list[Joint]:
    """Each joint between two tracks, once (see :class:`TrackNetwork`)."""
    return track_network(network).joints
