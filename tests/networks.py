"""Synthetic railroad networks for tests: clean by construction, any size.

Each unit is a crossover: two parallel tracks, a side track between them, two partner
switches, and a station with one platform on the first track.
"""

from __future__ import annotations

RAIL_ROAD = """  <road name="t{id}" length="{length}" id="{id}" junction="-1">
    <planView><geometry s="0" x="0" y="{y}" hdg="0" length="{length}"><line/></geometry></planView>
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
    y: float = 0,
    width: float = 1.5,
    offset: float | None = None,
    railroad: str = "",
) -> str:
    """A track road with one rail lane, centred on its reference line unless ``offset``."""
    centre = width / 2 if offset is None else offset
    return RAIL_ROAD.format(
        id=ident, length=length, y=y, offset=centre, width=width, railroad=railroad
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


def network(units: int, minor: int = 7) -> bytes:
    roads: list[str] = []
    stations: list[str] = []
    for unit in range(units):
        first, side, second = (str(unit * 3 + k + 1) for k in range(3))
        switch_a, switch_b = f"{unit}01", f"{unit}02"
        roads.append(
            rail_road(
                first,
                y=unit * 20,
                railroad=SWITCH.format(
                    id=switch_a, main=first, side=side, side_s=0, side_dir="+", partner=switch_b
                ),
            )
        )
        roads.append(rail_road(side, y=unit * 20 + 5))
        roads.append(
            rail_road(
                second,
                y=unit * 20 + 10,
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
