"""Synthetic railroad networks for tests: clean by construction, any size.

Each unit is a crossover: two parallel tracks, a side track between them, two partner
switches, and a station with one platform on the first track. The side track is a
balloon loop: it leaves the first track at its switch heading the same way, turns on a
semicircle of radius 30 m (a curve a train can run: TR013) and ends at the second
track's switch heading back, so both switches fit together (SW011, SW012).
"""

from __future__ import annotations

import math

RAIL_ROAD = """  <road name="t{id}" length="{length}" id="{id}" junction="-1">
    <planView>{geometry}</planView>
    <lanes>
      <laneOffset s="0" a="{offset}" b="0" c="0" d="0"/>
      <laneSection s="0">
        <center><lane id="0" type="none" level="false"/></center>
        <right><lane id="-1" type="rail" level="false"><width sOffset="0" a="{width}" b="0" c="0" d="0"/></lane></right>
      </laneSection>
    </lanes>{railroad}
  </road>
"""


def rail_road(
    ident: str,
    *,
    length: float = 200,
    x: float = 0,
    y: float = 0,
    hdg: float = 0,
    width: float = 1.5,
    offset: float | None = None,
    railroad: str = "",
    geometry: str | None = None,
) -> str:
    """A track road with one rail lane, centred on its reference line unless ``offset``;
    a straight line from (``x``, ``y``) unless ``geometry`` gives its records."""
    centre = width / 2 if offset is None else offset
    records = geometry or (
        f'<geometry s="0" x="{x}" y="{y}" hdg="{hdg}" length="{length}"><line/></geometry>'
    )
    return RAIL_ROAD.format(
        id=ident, length=length, geometry=records, offset=centre, width=width, railroad=railroad
    )


def balloon_loop(x: float, y: float, width: float, length: float) -> str:
    """Records of a track from (``x``, ``y``) heading 0 that turns on a semicircle of
    diameter ``width`` and ends at (``x``, ``y + width``) heading pi, ``length`` long."""
    turn = math.pi * width / 2
    leg = (length - turn) / 2
    return (
        f'<geometry s="0" x="{x}" y="{y}" hdg="0" length="{leg}"><line/></geometry>'
        f'<geometry s="{leg}" x="{x + leg}" y="{y}" hdg="0" length="{turn}">'
        f'<arc curvature="{2 / width}"/></geometry>'
        f'<geometry s="{leg + turn}" x="{x + leg}" y="{y + width}" hdg="{math.pi}" '
        f'length="{leg}"><line/></geometry>'
    )


SWITCH = """
    <railroad>
      <switch name="W{id}" id="{id}" position="dynamic">
        <mainTrack id="{main}" s="50" dir="+"/>
        <sideTrack id="{side}" s="{side_s}" dir="{side_dir}"/>
        <partner name="W{partner}" id="{partner}"/>
      </switch>
    </railroad>"""
STATION = """  <station name="S{id}" id="{id}" type="small">
    <platform name="P{id}" id="{id}-1">
      <segment roadId="{road}" sStart="60" sEnd="140" side="right"/>
    </platform>
  </station>
"""


#: The distance between a unit's two tracks: the balloon loop's diameter.
LOOP_WIDTH = 60
#: The distance between the first tracks of two units.
UNIT_SPACING = 80


def network(units: int, minor: int = 7) -> bytes:
    roads: list[str] = []
    stations: list[str] = []
    for unit in range(units):
        first, side, second = (str(unit * 3 + k + 1) for k in range(3))
        switch_a, switch_b = f"{unit}01", f"{unit}02"
        roads.append(
            rail_road(
                first,
                y=unit * UNIT_SPACING,
                railroad=SWITCH.format(
                    id=switch_a, main=first, side=side, side_s=0, side_dir="+", partner=switch_b
                ),
            )
        )
        roads.append(
            rail_road(side, geometry=balloon_loop(50, unit * UNIT_SPACING, LOOP_WIDTH, 200))
        )
        roads.append(
            rail_road(
                second,
                y=unit * UNIT_SPACING + LOOP_WIDTH,
                railroad=SWITCH.format(
                    id=switch_b, main=second, side=side, side_s=200, side_dir="-", partner=switch_a
                ),
            )
        )
        stations.append(STATION.format(id=f"{unit}", road=first))
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n<OpenDRIVE>\n'
        f'  <header revMajor="1" revMinor="{minor}" name="synthetic"/>\n'
        + "".join(roads)
        + "".join(stations)
        + "</OpenDRIVE>\n"
    ).encode()
