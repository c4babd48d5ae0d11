"""Platforms and segments with the station and platform that hold them, for messages."""

from __future__ import annotations

from collections.abc import Iterator

from xodrlint.rules import Platform, RailNetwork, Segment, Station


def platforms_with_station(network: RailNetwork) -> Iterator[tuple[Platform, Station]]:
    for station in network.stations:
        for platform in station.platforms:
            yield platform, station


def segments_with_platform(network: RailNetwork) -> Iterator[tuple[Segment, Platform]]:
    for station in network.stations:
        for platform in station.platforms:
            for segment in platform.segments:
                yield segment, platform
