"""What the map shows, in world coordinates: roads, rail tracks, switches, partner links,
platforms, and what could not be drawn (with its line and the reason)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import partial

from xodrlint.document.load import Document
from xodrlint.geometry import polylines
from xodrlint.mapview.place import Placer, Point
from xodrlint.model import RailNetwork, Road
from xodrlint.model.lane_profiles import centre_terms, lateral_value

Runs = list[list[Point]]


@dataclass(frozen=True, slots=True)
class RoadShape:
    id: str | None
    name: str | None
    junction: bool
    runs: Runs


@dataclass(frozen=True, slots=True)
class TrackShape:
    road_id: str | None
    road_name: str | None
    lane_id: int | None
    lane_type: str
    section_s: float
    runs: Runs


@dataclass(frozen=True, slots=True)
class SwitchMark:
    id: str | None
    name: str | None
    position: str | None
    main_road: str | None
    main_s: float | None
    at: Point
    side_road: str | None = None
    side_at: Point | None = None


@dataclass(frozen=True, slots=True)
class PartnerLink:
    first: str
    second: str
    a: Point
    b: Point


@dataclass(frozen=True, slots=True)
class PlatformBar:
    station_id: str | None
    station_name: str | None
    platform_id: str | None
    platform_name: str | None
    road_id: str | None
    side: str | None
    runs: Runs


@dataclass(frozen=True, slots=True)
class NotDrawn:
    line: int
    what: str
    reason: str


@dataclass
class Scene:
    roads: list[RoadShape] = field(default_factory=list)
    tracks: list[TrackShape] = field(default_factory=list)
    switches: list[SwitchMark] = field(default_factory=list)
    partners: list[PartnerLink] = field(default_factory=list)
    platforms: list[PlatformBar] = field(default_factory=list)
    not_drawn: list[NotDrawn] = field(default_factory=list)

    def road_count(self) -> int:
        """Roads drawn: by their reference line, or by their tracks."""
        return len(self.roads) + len({track.road_id for track in self.tracks})

    def points(self) -> Iterator[Point]:
        shapes: list[RoadShape | TrackShape | PlatformBar] = [
            *self.roads,
            *self.tracks,
            *self.platforms,
        ]
        for shape in shapes:
            for run in shape.runs:
                yield from run
        for switch in self.switches:
            yield switch.at


def build_scene(doc: Document, network: RailNetwork, placer: Placer, tolerance: float) -> Scene:
    """Everything of ``network`` that can be drawn, to within ``tolerance`` metres."""
    scene = Scene()
    for road in network.roads:
        _add_road(scene, doc, placer, road, tolerance)
    _add_switches(scene, doc, network, placer)
    _add_platforms(scene, doc, network, placer, tolerance)
    return scene


def _add_road(scene: Scene, doc: Document, placer: Placer, road: Road, tolerance: float) -> None:
    line = placer.line(road)
    for problem in line.problems:
        scene.not_drawn.append(
            NotDrawn(doc.line_of(problem.element), f"road '{road.id}'", problem.message)
        )
    tracks = _tracks(scene, doc, placer, road, tolerance) if road.has_rail_lane else []
    scene.tracks.extend(tracks)
    if not tracks:
        junction = road.element.get("junction", "-1") not in ("-1", "")
        runs = polylines(line, tolerance)
        scene.roads.append(RoadShape(road.id, road.element.get("name"), junction, runs))


def _tracks(
    scene: Scene, doc: Document, placer: Placer, road: Road, tolerance: float
) -> list[TrackShape]:
    """Each rail or tram lane's centre line, lane section by lane section."""
    line = placer.line(road)
    shapes = []
    for section, start, end in road.section_ranges():
        for lane in section.rail_lanes:
            terms = centre_terms(road, section, start, lane)
            if terms is None:
                scene.not_drawn.append(
                    NotDrawn(
                        doc.line_of(lane.element),
                        f"rail lane '{lane.id}' of road '{road.id}'",
                        "its centre is unknown (no readable width or laneOffset entries)",
                    )
                )
                continue
            runs = polylines(line, tolerance, partial(lateral_value, terms), (start, end))
            shapes.append(
                TrackShape(road.id, road.element.get("name"), lane.id, lane.type or "", start, runs)
            )
    return shapes


def _add_switches(scene: Scene, doc: Document, network: RailNetwork, placer: Placer) -> None:
    placed: dict[str, SwitchMark] = {}
    for switch in network.switches:
        main, side = switch.main_track, switch.side_track
        at = placer.track_point(main.road_id, main.s) if main is not None else None
        if at is None or main is None:
            where = f"road '{main.road_id}' at s={main.s}" if main is not None else "none given"
            scene.not_drawn.append(
                NotDrawn(
                    doc.line_of(switch.element),
                    f"switch '{switch.id}'",
                    f"its main track ({where}) is not on the map",
                )
            )
            continue
        side_at = placer.track_point(side.road_id, side.s) if side is not None else None
        mark = SwitchMark(
            switch.id,
            switch.name,
            switch.position,
            main.road_id,
            main.s,
            at,
            side.road_id if side is not None else None,
            side_at,
        )
        scene.switches.append(mark)
        if switch.id is not None:
            placed.setdefault(switch.id, mark)
    for switch in network.switches:
        partner = switch.partner.id if switch.partner is not None else None
        if switch.id is None or partner is None or switch.id >= partner:
            continue
        if switch.id in placed and partner in placed:
            link = PartnerLink(switch.id, partner, placed[switch.id].at, placed[partner].at)
            scene.partners.append(link)


def _add_platforms(
    scene: Scene, doc: Document, network: RailNetwork, placer: Placer, tolerance: float
) -> None:
    for station in network.stations:
        for platform in station.platforms:
            for segment in platform.segments:
                road = placer.road(segment.road_id)
                lateral = placer.segment_side(segment)
                ends = (segment.s_start, segment.s_end)
                runs: Runs = []
                if road is not None and lateral is not None and None not in ends:
                    low, high = sorted(float(value or 0.0) for value in ends)
                    runs = polylines(placer.line(road), tolerance, lateral, (low, high))
                if not runs:
                    scene.not_drawn.append(
                        NotDrawn(
                            doc.line_of(segment.element),
                            f"segment of platform '{platform.id}'",
                            f"road '{segment.road_id}' from s={segment.s_start} to "
                            f"s={segment.s_end} is not on the map",
                        )
                    )
                    continue
                bar = PlatformBar(
                    station.id,
                    station.name,
                    platform.id,
                    platform.name,
                    segment.road_id,
                    segment.side,
                    runs,
                )
                scene.platforms.append(bar)
