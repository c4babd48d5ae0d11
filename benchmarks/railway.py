"""The rail-dense benchmark shape: a railway where every road is a track.

Real railway maps look like this, not like a city map with a few tram lines: every road
carries one rail lane, consecutive tracks are linked road to road, a switch stands every
100 to 200 m, and stations with platforms are everywhere. Corridors of two parallel main
lines run along x; each block of a corridor (100 to 200 m, cycling) holds

- a crossover: a side track leaving line A along a reverse curve and joining line B, with
  the two partner switches at its ends;
- a single switch on line A with a siding that leaves along a reverse curve and then
  curves away on an arc;
- every third block, a station with two platforms (on line A, and on line B across two
  blocks).

The rail lanes vary as maps do: a right lane centred by a positive ``laneOffset`` (line
A), a left lane centred by a negative one (line B), a rail lane between two ``border``
lanes (crossovers), two lane sections with an offset entry each (sidings). Everything is
exact (lines and arcs), so the network is clean: no rule and no official schema of the
version finds anything. ``defects=True`` gives every switch one schema defect (its
``position`` is not an allowed value: XS006) and one rule defect (its ``mainTrack/@dir``
reversed, so the directions of travel disagree: SW012).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Final

from generate import HEADER, TURN, _number, _record, _reverse_curves

#: Block lengths cycle through these (m): a switch every 100 to 200 m.
BLOCK_LENGTHS: Final = (100.0, 125.0, 150.0, 175.0, 200.0, 140.0, 110.0)
BLOCKS_PER_CORRIDOR: Final = 60
LINE_SPACING: Final = 4.5  # line B runs this far left of line A
SIDING_SPACING: Final = 3.0  # a siding leaves line A to its right
CORRIDOR_SPACING: Final = 60.0
CROSSOVER_AT: Final = 15.0  # s of the crossover's first switch on line A
SIDING_TAIL: Final = 30.0  # the siding's curved run after its reverse curve (m)
SIDING_CURVATURE: Final = -1 / 400  # curving away from line A
SWITCHES_PER_BLOCK: Final = 3
STATION_EVERY: Final = 3  # blocks


def _offset(s: str, a: str) -> str:
    return f'      <laneOffset s="{s}" a="{a}" b="0" c="0" d="0"/>\n'


def _lane(lane_id: int, lane_type: str, width: str) -> str:
    return (
        f'          <lane id="{lane_id}" type="{lane_type}" level="false">\n'
        f'            <width sOffset="0" a="{width}" b="0" c="0" d="0"/>\n'
        "          </lane>\n"
    )


def _section(start: str, left: str = "", right: str = "") -> str:
    """A lane section with its left lanes, the centre lane and its right lanes."""
    return (
        f'      <laneSection s="{start}">\n'
        + (f"        <left>\n{left}        </left>\n" if left else "")
        + '        <center><lane id="0" type="none" level="false"/></center>\n'
        + (f"        <right>\n{right}        </right>\n" if right else "")
        + "      </laneSection>\n"
    )


# A rail lane 1.5 m wide on one side of the reference line, centred by the lane offset.
RIGHT_RAIL: Final = _offset("0", "0.75") + _section("0", right=_lane(-1, "rail", "1.5"))
LEFT_RAIL: Final = _offset("0", "-0.75") + _section("0", left=_lane(1, "rail", "1.5"))
BALLAST_RAIL: Final = _offset("0", "0.75") + _section(
    "0",
    left=_lane(1, "border", "1"),
    right=_lane(-1, "rail", "1.5") + _lane(-2, "border", "1"),
)


def _two_sections(length: float) -> str:
    """A right rail lane in two lane sections, each with its own offset entry."""
    starts = ("0", _number(length / 2))
    rail = _lane(-1, "rail", "1.5")
    return "".join(_offset(s, "0.75") for s in starts) + "".join(
        _section(s, right=rail) for s in starts
    )


def _road(
    road_id: int,
    length: float,
    geometry: str,
    lanes: str,
    link: str = "",
    railroad: str = "",
) -> str:
    return (
        f'  <road name="track {road_id}" length="{_number(length)}" id="{road_id}" '
        f'junction="-1">\n{link}    <planView>\n{geometry}    </planView>\n'
        f"    <lanes>\n{lanes}    </lanes>\n{railroad}  </road>\n"
    )


def _link(predecessor: int | None, successor: int | None) -> str:
    ends = ""
    if predecessor is not None:
        ends += (
            f'      <predecessor elementType="road" elementId="{predecessor}" '
            'contactPoint="end"/>\n'
        )
    if successor is not None:
        ends += (
            f'      <successor elementType="road" elementId="{successor}" contactPoint="start"/>\n'
        )
    return f"    <link>\n{ends}    </link>\n" if ends else ""


def _switch(
    switch_id: int,
    main: tuple[int, float, str],
    side: tuple[int, float, str],
    partner: int | None,
    defects: bool,
) -> str:
    main_road, main_s, main_dir = main
    side_road, side_s, side_dir = side
    if defects:
        main_dir = "-" if main_dir == "+" else "+"
    position = "sideways" if defects else "dynamic"
    partner_line = (
        f'        <partner name="W{partner}" id="{partner}"/>\n' if partner is not None else ""
    )
    return (
        f'      <switch name="W{switch_id}" id="{switch_id}" position="{position}">\n'
        f'        <mainTrack id="{main_road}" s="{_number(main_s)}" dir="{main_dir}"/>\n'
        f'        <sideTrack id="{side_road}" s="{_number(side_s)}" dir="{side_dir}"/>\n'
        f"{partner_line}      </switch>\n"
    )


def _railroad(switches: list[str]) -> str:
    return "    <railroad>\n" + "".join(switches) + "    </railroad>\n"


def _siding_geometry(x: float, y: float) -> tuple[str, float]:
    """A reverse curve to the right of line A, then an arc curving further away."""
    records, along = _reverse_curves(x, y, -SIDING_SPACING, 0.0)
    curvature = 2 * (1 - math.cos(TURN)) / SIDING_SPACING
    arcs = 2 * TURN / curvature
    records += _record(
        arcs,
        x + along,
        y - SIDING_SPACING,
        0.0,
        SIDING_TAIL,
        f'<arc curvature="{_number(SIDING_CURVATURE)}"/>',
    )
    return records, arcs + SIDING_TAIL


def _block(corridor: int, index: int, corridor_blocks: int, defects: bool) -> tuple[str, str]:
    """One block's four roads (line A, line B, crossover, siding) and its station, if any;
    the corridor it belongs to has ``corridor_blocks`` blocks."""
    length = BLOCK_LENGTHS[index % len(BLOCK_LENGTHS)]
    start_x = sum(BLOCK_LENGTHS[k % len(BLOCK_LENGTHS)] for k in range(index))
    y = corridor * CORRIDOR_SPACING
    base = (corridor * BLOCKS_PER_CORRIDOR + index) * 10 + 1
    line_a, line_b, crossover, siding = base, base + 1, base + 2, base + 3

    def neighbour(road: int, step: int) -> int | None:
        other = index + step
        return road + 10 * step if 0 <= other < corridor_blocks else None

    cross_geometry, reach = _reverse_curves(start_x + CROSSOVER_AT, y, LINE_SPACING, 0.0)
    cross_length = 2 * TURN / (2 * (1 - math.cos(TURN)) / LINE_SPACING)
    siding_at = length * 0.6
    siding_geometry, siding_length = _siding_geometry(start_x + siding_at, y)
    switch_a, switch_b, switch_single = base, base + 1, base + 2
    roads = _road(
        line_a,
        length,
        _record(0.0, start_x, y, 0.0, length, "<line/>"),
        RIGHT_RAIL,
        _link(neighbour(line_a, -1), neighbour(line_a, +1)),
        _railroad(
            [
                _switch(
                    switch_a,
                    (line_a, CROSSOVER_AT, "+"),
                    (crossover, 0.0, "+"),
                    switch_b,
                    defects,
                ),
                _switch(switch_single, (line_a, siding_at, "+"), (siding, 0.0, "+"), None, defects),
            ]
        ),
    )
    roads += _road(
        line_b,
        length,
        _record(0.0, start_x, y + LINE_SPACING, 0.0, length, "<line/>"),
        LEFT_RAIL,
        _link(neighbour(line_b, -1), neighbour(line_b, +1)),
        # a train on line B running against its s enters the crossover at its end
        _railroad(
            [
                _switch(
                    switch_b,
                    (line_b, CROSSOVER_AT + reach, "-"),
                    (crossover, cross_length, "-"),
                    switch_a,
                    defects,
                )
            ]
        ),
    )
    roads += _road(crossover, cross_length, cross_geometry, BALLAST_RAIL)
    roads += _road(siding, siding_length, siding_geometry, _two_sections(siding_length))
    station = ""
    if index % STATION_EVERY == 0 and index + 1 < corridor_blocks:
        station = _station(base, line_a, line_b, length)
    return roads, station


def _station(base: int, line_a: int, line_b: int, length: float) -> str:
    next_b = line_b + 10
    return (
        f'  <station name="Station {base}" id="{base}" type="medium">\n'
        f'    <platform name="Platform {base}-1" id="{base}-1">\n'
        f'      <segment roadId="{line_a}" sStart="{_number(length * 0.2)}" '
        f'sEnd="{_number(length * 0.55)}" side="right"/>\n'
        "    </platform>\n"
        f'    <platform name="Platform {base}-2" id="{base}-2">\n'
        f'      <segment roadId="{line_b}" sStart="{_number(length * 0.7)}" '
        f'sEnd="{_number(length)}" side="left"/>\n'
        f'      <segment roadId="{next_b}" sStart="0" sEnd="20" side="left"/>\n'
        "    </platform>\n"
        "  </station>\n"
    )


def railway(
    size_bytes: int | None = None,
    minor: int = 7,
    *,
    blocks: int | None = None,
    defects: bool = False,
) -> Iterator[str]:
    """The text of a railway of whole corridors and at least ``size_bytes``, or of exactly
    ``blocks`` blocks (:data:`SWITCHES_PER_BLOCK` switches each), in pieces."""
    header = HEADER.format(minor=minor)
    yield header
    written = len(header)
    stations: list[str] = []
    corridor = 0
    while True:
        if blocks is not None:
            corridor_blocks = min(BLOCKS_PER_CORRIDOR, blocks - corridor * BLOCKS_PER_CORRIDOR)
        else:
            corridor_blocks = BLOCKS_PER_CORRIDOR if written < (size_bytes or 0) else 0
        if corridor_blocks <= 0:
            break
        for index in range(corridor_blocks):
            roads, station = _block(corridor, index, corridor_blocks, defects)
            yield roads
            if station:
                stations.append(station)
            written += len(roads) + len(station)
        corridor += 1
    yield from stations
    yield "</OpenDRIVE>\n"


def invalid_roads(count: int, minor: int = 7) -> Iterator[str]:
    """``count`` tiny roads, each invalid in the schema (no ``planView``, no ``lanes``):
    one schema finding per road, every road a sibling of every other."""
    yield HEADER.format(minor=minor)
    chunk = 10_000
    for first in range(0, count, chunk):
        yield "".join(
            f'  <road length="10" id="{number}" junction="-1"/>\n'
            for number in range(first, min(first + chunk, count))
        )
    yield "</OpenDRIVE>\n"
