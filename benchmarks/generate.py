"""Deterministic OpenDRIVE railroad networks of a requested size, clean by construction.

Every block holds a crossover (two parallel tracks 4.5 m apart, a side track between them
that leaves one and joins the other, two partner switches), a single switch with its own
siding, a station with a platform on the first track, and ordinary roads with driving
lanes, the way city maps mix both. The tracks are railways that can exist: side tracks
leave their switch points along reverse curves (lines and arcs, so every position is
exact), every rail lane is centred on its reference line, every id is unique: xodrlint
gives no finding and the official schema of the version accepts it.

    python benchmarks/generate.py --size-mb 20 --version 1.7 -o network-20mb-1.7.xodr
    python benchmarks/generate.py --files 200 --size-kb 20 -o small/   # a batch folder
    python benchmarks/generate.py --shape railway --size-mb 20 -o railway-20mb-1.7.xodr
    python benchmarks/generate.py --shape railway --defects --blocks 1000 -o findings.xodr
    python benchmarks/generate.py --invalid-roads 1000000 -o roads-1m.xodr

``--shape railway`` is the rail-dense shape of ``railway.py`` (every road a track);
``--defects`` gives each of its switches a schema and a rule defect; ``--invalid-roads``
writes that many tiny roads that each fail the schema.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Final

#: Bumped whenever the networks change, so a benchmark's work folder never reuses a network
#: an older generator wrote (version 2: side tracks that meet their switches; 3: the railway shape).
GENERATOR_VERSION: Final = 3
TRACK_LENGTH: Final = 200.0
STREET_LANES: Final = 3  # per side
#: Heading change of each arc of a reverse curve (8.6 degrees: a 1:6.6 turnout).
TURN: Final = 0.15
#: Distance between the two tracks of a crossover, and of a siding from its main track.
TRACK_SPACING: Final = 4.5
SIDING_SPACING: Final = 3.0

HEADER: Final = """<?xml version="1.0" encoding="UTF-8"?>
<OpenDRIVE>
  <header revMajor="1" revMinor="{minor}" name="xodrlint benchmark network" version="1.0"/>
"""

TRACK: Final = """  <road name="track {id}" length="{length}" id="{id}" junction="-1">
    <planView>
{geometry}    </planView>
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
        <mainTrack id="{main}" s="{s}" dir="{main_dir}"/>
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


def _number(value: float) -> str:
    text = f"{value:.9f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _record(s: float, x: float, y: float, hdg: float, length: float, curve: str) -> str:
    return (
        f'      <geometry s="{_number(s)}" x="{_number(x)}" y="{_number(y)}" '
        f'hdg="{_number(hdg)}" length="{_number(length)}">{curve}</geometry>\n'
    )


def _line(x: float, y: float, length: float) -> str:
    return _record(0.0, x, y, 0.0, length, "<line/>")


def _reverse_curves(x: float, y: float, offset: float, length: float) -> tuple[str, float]:
    """A track that leaves (x, y) heading 0, moves ``offset`` sideways along two arcs of
    opposite curvature (each turning :data:`TURN`), then runs straight to ``length``
    (at least the two arcs). Returns its records and how far along x the arcs reach."""
    curvature = 2 * (1 - math.cos(TURN)) / abs(offset)
    arc = TURN / curvature
    sign = 1.0 if offset > 0 else -1.0
    middle_x = x + math.sin(TURN) / curvature
    middle_y = y + sign * (1 - math.cos(TURN)) / curvature
    records = _record(0.0, x, y, 0.0, arc, f'<arc curvature="{_number(sign * curvature)}"/>')
    records += _record(
        arc,
        middle_x,
        middle_y,
        sign * TURN,
        arc,
        f'<arc curvature="{_number(-sign * curvature)}"/>',
    )
    along = 2 * math.sin(TURN) / curvature
    if length > 2 * arc:
        records += _record(2 * arc, x + along, y + offset, 0.0, length - 2 * arc, "<line/>")
    return records, along


def _block(index: int) -> tuple[str, str]:
    """One block's roads and its station."""
    base = index * 10
    x, y = (index % 100) * 500.0, (index // 100) * 50.0
    main_a, side, main_b, single, siding_id = (str(base + k) for k in range(1, 6))
    sw = [f"{base + k}" for k in range(1, 4)]
    crossover, reach = _reverse_curves(x + 20, y, TRACK_SPACING, 0.0)
    crossover_length = 2 * TURN / (2 * (1 - math.cos(TURN)) / TRACK_SPACING)
    siding, _ = _reverse_curves(x + 150, y, -SIDING_SPACING, TRACK_LENGTH / 2)
    roads = [
        TRACK.format(
            id=main_a,
            length=TRACK_LENGTH,
            geometry=_line(x, y, TRACK_LENGTH),
            railroad="\n    <railroad>"
            + SWITCH.format(
                id=sw[0],
                main=main_a,
                s=20,
                main_dir="+",
                side=side,
                side_s=0,
                side_dir="+",
                partner=PARTNER.format(id=sw[1]),
            )
            + SWITCH.format(
                id=sw[2],
                main=main_a,
                s=150,
                main_dir="+",
                side=siding_id,
                side_s=0,
                side_dir="+",
                partner="",
            )
            + "\n    </railroad>",
        ),
        TRACK.format(id=side, length=_number(crossover_length), geometry=crossover, railroad=""),
        TRACK.format(
            id=main_b,
            length=TRACK_LENGTH,
            geometry=_line(x, y + TRACK_SPACING, TRACK_LENGTH),
            railroad="\n    <railroad>"
            # a train on this track running against its s enters the crossover at its end
            + SWITCH.format(
                id=sw[1],
                main=main_b,
                s=_number(20 + reach),
                main_dir="-",
                side=side,
                side_s=_number(crossover_length),
                side_dir="-",
                partner=PARTNER.format(id=sw[0]),
            )
            + "\n    </railroad>",
        ),
        TRACK.format(id=siding_id, length=TRACK_LENGTH / 2, geometry=siding, railroad=""),
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
    write_pieces(path, network(size_bytes, minor))


def _minor(version: str) -> int:
    major, _, minor = version.partition(".")
    if major != "1" or not minor.isdigit():
        raise argparse.ArgumentTypeError(f"not an OpenDRIVE 1.x version: {version}")
    return int(minor)


def write_pieces(path: Path, pieces: Iterable[str]) -> None:
    with path.open("w", encoding="utf-8", newline="\n") as stream:
        stream.writelines(pieces)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--version", type=_minor, default=7, help="OpenDRIVE version (1.7)")
    parser.add_argument("--shape", choices=("mixed", "railway"), default="mixed")
    parser.add_argument("--defects", action="store_true", help="railway: defects per switch")
    size = parser.add_mutually_exclusive_group()
    size.add_argument("--size-mb", type=float, help="one network of about this size")
    size.add_argument("--size-kb", type=float, help="size of each file with --files")
    size.add_argument("--blocks", type=int, help="railway: this many blocks (3 switches each)")
    size.add_argument("--invalid-roads", type=int, help="this many schema-invalid tiny roads")
    parser.add_argument("--files", type=int, help="write this many files into the -o folder")
    parser.add_argument("-o", "--output", type=Path, required=True)
    args = parser.parse_args(argv)
    from railway import invalid_roads, railway

    if args.invalid_roads:
        write_pieces(args.output, invalid_roads(args.invalid_roads, args.version))
        return 0
    if args.shape == "railway":
        size_bytes = int((args.size_mb or 20) * 1024 * 1024)
        if args.blocks:
            pieces = railway(minor=args.version, blocks=args.blocks, defects=args.defects)
        else:
            pieces = railway(size_bytes, args.version, defects=args.defects)
        write_pieces(args.output, pieces)
        return 0
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
