"""Deterministic OpenDRIVE railroad networks of a requested size, clean by construction.

Every block holds a crossover (two parallel tracks, a side track between them, two
partner switches), a single switch with its own siding, a station with a platform on the
first track, and ordinary roads with driving lanes, the way city maps mix both. All
geometry is exact (lines), every rail lane is centred on its reference line, every id is
unique: xodrlint gives no finding and the official schema of the version accepts it.

    python benchmarks/generate.py --size-mb 20 --version 1.7 -o network-20mb-1.7.xodr
    python benchmarks/generate.py --files 200 --size-kb 20 -o small/   # a batch folder
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Final

TRACK_LENGTH: Final = 200.0
STREET_LANES: Final = 3  # per side

HEADER: Final = """<?xml version="1.0" encoding="UTF-8"?>
<OpenDRIVE>
  <header revMajor="1" revMinor="{minor}" name="xodrlint benchmark network" version="1.0"/>
"""

TRACK: Final = """  <road name="track {id}" length="{length}" id="{id}" junction="-1">
    <planView>
      <geometry s="0" x="{x}" y="{y}" hdg="0" length="{length}"><line/></geometry>
    </planView>
    <lanes>
      <laneOffset s="0" a="0.75" b="0" c="0" d="0"/>
      <laneSection s="0">
        <center><lane id="0" type="none" level="false"/></center>
        <right>
          <lane id="-1" type="rail" level="false">
            <width sOffset="0" a="1.5" b="0" c="0" d="0"/>
          </lane>
        </right>
      </laneSection>
    </lanes>{railroad}
  </road>
"""

SWITCH: Final = """
      <switch name="W{id}" id="{id}" position="dynamic">
        <mainTrack id="{main}" s="{s}" dir="+"/>
        <sideTrack id="{side}" s="{side_s}" dir="{side_dir}"/>{partner}
      </switch>"""

PARTNER: Final = """
        <partner name="W{id}" id="{id}"/>"""

STREET_LANE: Final = """          <lane id="{lane}" type="driving" level="false">
            <width sOffset="0" a="3.25" b="0" c="0" d="0"/>
            <roadMark sOffset="0" type="{mark}" weight="standard" color="standard" \
width="0.12" laneChange="both" height="0.02"/>
          </lane>
"""

STREET: Final = """  <road name="street {id}" length="{length}" id="{id}" junction="-1">
    <planView>
      <geometry s="0" x="{x}" y="{y}" hdg="1.5707963267948966" length="{length}"><line/></geometry>
    </planView>
    <lanes>
      <laneSection s="0">
        <left>
{left}        </left>
        <center><lane id="0" type="none" level="false"/></center>
        <right>
{right}        </right>
      </laneSection>
    </lanes>
  </road>
"""

STATION: Final = """  <station name="Station {id}" id="{id}" type="small">
    <platform name="Platform {id}" id="{id}-1">
      <segment roadId="{road}" sStart="60" sEnd="140" side="left"/>
    </platform>
  </station>
"""


def _street_lanes(side: int) -> str:
    lanes = range(STREET_LANES, 0, -1) if side > 0 else range(-1, -STREET_LANES - 1, -1)
    return "".join(
        STREET_LANE.format(lane=lane, mark="solid" if abs(lane) == STREET_LANES else "broken")
        for lane in lanes
    )


LEFT_LANES: Final = _street_lanes(+1)
RIGHT_LANES: Final = _street_lanes(-1)


def _block(index: int) -> tuple[str, str]:
    """One block's roads and its station."""
    base = index * 10
    x, y = (index % 100) * 500.0, (index // 100) * 50.0
    main_a, side, main_b, single, siding = (str(base + k) for k in range(1, 6))
    sw = [f"{base + k}" for k in range(1, 4)]
    roads = [
        TRACK.format(
            id=main_a,
            length=TRACK_LENGTH,
            x=x,
            y=y,
            railroad="\n    <railroad>"
            + SWITCH.format(
                id=sw[0],
                main=main_a,
                s=20,
                side=side,
                side_s=0,
                side_dir="+",
                partner=PARTNER.format(id=sw[1]),
            )
            + SWITCH.format(
                id=sw[2], main=main_a, s=150, side=siding, side_s=0, side_dir="+", partner=""
            )
            + "\n    </railroad>",
        ),
        TRACK.format(id=side, length=TRACK_LENGTH, x=x + 20, y=y + 2, railroad=""),
        TRACK.format(
            id=main_b,
            length=TRACK_LENGTH,
            x=x,
            y=y + 4.5,
            railroad="\n    <railroad>"
            + SWITCH.format(
                id=sw[1],
                main=main_b,
                s=50,
                side=side,
                side_s=TRACK_LENGTH,
                side_dir="-",
                partner=PARTNER.format(id=sw[0]),
            )
            + "\n    </railroad>",
        ),
        TRACK.format(id=siding, length=TRACK_LENGTH / 2, x=x + 150, y=y - 3, railroad=""),
    ]
    for street in range(6, 10):
        roads.append(
            STREET.format(
                id=base + street,
                length=TRACK_LENGTH,
                x=x + 30 * street,
                y=y + 10,
                left=LEFT_LANES,
                right=RIGHT_LANES,
            )
        )
    del single
    return "".join(roads), STATION.format(id=index, road=main_a)


def network(size_bytes: int, minor: int = 7) -> Iterator[str]:
    """The text of a network of at least ``size_bytes``, in pieces."""
    header = HEADER.format(minor=minor)
    yield header
    written = len(header)
    stations: list[str] = []
    index = 0
    while written < size_bytes:
        roads, station = _block(index)
        yield roads
        stations.append(station)
        written += len(roads) + len(station)
        index += 1
    yield from stations
    yield "</OpenDRIVE>\n"


def write_network(path: Path, size_bytes: int, minor: int = 7) -> None:
    with path.open("w", encoding="utf-8", newline="\n") as stream:
        for piece in network(size_bytes, minor):
            stream.write(piece)


def _minor(version: str) -> int:
    major, _, minor = version.partition(".")
    if major != "1" or not minor.isdigit():
        raise argparse.ArgumentTypeError(f"not an OpenDRIVE 1.x version: {version}")
    return int(minor)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", type=_minor, default=7, help="OpenDRIVE version (1.7)")
    size = parser.add_mutually_exclusive_group()
    size.add_argument("--size-mb", type=float, help="one network of about this size")
    size.add_argument("--size-kb", type=float, help="size of each file with --files")
    parser.add_argument("--files", type=int, help="write this many files into the -o folder")
    parser.add_argument("-o", "--output", type=Path, required=True)
    args = parser.parse_args(argv)
    if args.files:
        args.output.mkdir(parents=True, exist_ok=True)
        each = int((args.size_kb or 20) * 1024)
        for number in range(args.files):
            target = args.output / f"network-{number:04}.xodr"
            write_network(target, each + (number % 7) * 1024, args.version)
        return 0
    write_network(args.output, int((args.size_mb or 20) * 1024 * 1024), args.version)
    return 0


if __name__ == "__main__":
    sys.exit(main())
