"""Stage 3, model: the read-only facts of one file that every rule shares.

- :mod:`~xodrlint.model.network`: one pass over the tree builds the indexes (roads and
  their lanes and lane links, junctions and their connections, switches, stations,
  platforms, segments); :class:`RailNetwork` is what a rule receives.
- :mod:`~xodrlint.model.lane_profiles`: ``laneOffset`` and lane ``width`` as the piecewise
  cubics they are, so a rule can say "anywhere along the lane section" exactly.

The names below are the model's public surface; rule packs import them from here.
"""

from xodrlint.model.network import (
    NON_TRAFFIC_LANE_TYPES,
    RAIL_LANE_TYPES,
    Connection,
    Cubic,
    Junction,
    JunctionLaneLink,
    Lane,
    LaneLink,
    LaneSection,
    PartnerRef,
    Platform,
    RailNetwork,
    Road,
    RoadLanes,
    RoadLink,
    Segment,
    Station,
    Switch,
    TrackRef,
    build_network,
    integer,
    non_finite,
    number,
    numbers,
    section_ranges,
)

__all__ = [
    "NON_TRAFFIC_LANE_TYPES",
    "RAIL_LANE_TYPES",
    "Connection",
    "Cubic",
    "Junction",
    "JunctionLaneLink",
    "Lane",
    "LaneLink",
    "LaneSection",
    "PartnerRef",
    "Platform",
    "RailNetwork",
    "Road",
    "RoadLanes",
    "RoadLink",
    "Segment",
    "Station",
    "Switch",
    "TrackRef",
    "build_network",
    "integer",
    "non_finite",
    "number",
    "numbers",
    "section_ranges",
]
