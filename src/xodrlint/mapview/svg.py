"""The scene as SVG markup. One SVG user unit is one centimetre, so every coordinate is an
integer (the drawing is accurate to 1 cm and the numbers stay short); y is flipped so that
north is up. Ordinary roads share one path per class; each subpath starts with an absolute
``M`` and continues with relative ``l`` steps, which the page's script reads back for
hover and search instead of a second copy of the coordinates."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from html import escape
from typing import Final

from xodrlint.findings import Finding, Severity
from xodrlint.mapview.place import Point
from xodrlint.mapview.scene import PlatformBar, RoadShape, Runs, Scene, SwitchMark, TrackShape

UNITS_PER_METRE: Final = 100
#: Margin around the drawing, as a share of its larger side.
_MARGIN: Final = 0.04
#: Severities drawn in this order, so that errors lie on top.
_DRAW_ORDER: Final = (Severity.INFO, Severity.WARNING, Severity.ERROR)


@dataclass(frozen=True, slots=True)
class PlacedFinding:
    index: int
    finding: Finding
    at: Point | None
    file: str | None = None
    """The file the finding stands in, where the map includes it from another."""

    @property
    def where(self) -> str:
        """ "line 12", or "parts/x.xml line 12" for a finding in an included file."""
        line = f"line {self.finding.line}"
        return line if self.file is None else f"{self.file} {line}"


@dataclass(frozen=True, slots=True)
class Frame:
    """The drawing's extent in SVG units: ``x, y, width, height`` of its viewBox."""

    x: int
    y: int
    width: int
    height: int

    @property
    def units_per_pixel(self) -> float:
        """The scale of the whole drawing shown 1,000 pixels wide (the page sets its own)."""
        return max(self.width, self.height) / 1000

    @property
    def marker(self) -> int:
        """A marker radius for viewers that size circles by attribute only."""
        return max(1, round(self.units_per_pixel * 6))

    def view_box(self) -> str:
        return f"{self.x} {self.y} {self.width} {self.height}"


def unit(point: Point) -> tuple[int, int]:
    return round(point[0] * UNITS_PER_METRE), round(-point[1] * UNITS_PER_METRE)


def frame_of(points: Iterable[Point]) -> Frame:
    xs, ys = [], []
    for point in points:
        ux, uy = unit(point)
        xs.append(ux)
        ys.append(uy)
    if not xs:
        return Frame(-1000, -1000, 2000, 2000)
    width, height = max(xs) - min(xs), max(ys) - min(ys)
    margin = max(200, math.ceil(max(width, height) * _MARGIN))
    return Frame(min(xs) - margin, min(ys) - margin, width + 2 * margin, height + 2 * margin)


def path_data(runs: Runs) -> str:
    """``M x y l dx dy …`` per run; steps that round to nothing are left out."""
    parts: list[str] = []
    for run in runs:
        start = x, y = unit(run[0])
        steps: list[int] = []
        for point in run[1:]:
            nx, ny = unit(point)
            if (nx, ny) != (x, y):
                steps += (nx - x, ny - y)
                x, y = nx, ny
        if steps:
            parts.append(f"M{start[0]} {start[1]}l{_numbers(steps)}")
    return "".join(parts)


def _numbers(values: Sequence[int]) -> str:
    """Numbers separated by a space, or by nothing before a minus sign (as SVG allows)."""
    text = [str(values[0])]
    for value in values[1:]:
        text.append(str(value) if value < 0 else f" {value}")
    return "".join(text)


def _attr(value: object) -> str:
    return escape(str(value), quote=True)


def _title(text: str) -> str:
    return f"<title>{escape(text, quote=False)}</title>"


#: A road in the page's index: id, name, and how many subpaths of its class's path it has.
RoadEntry = tuple[str | None, str | None, int]


def render_svg(
    scene: Scene, findings: Sequence[PlacedFinding], frame: Frame, style: str = ""
) -> tuple[str, list[list[RoadEntry]]]:
    """The whole ``<svg>`` element (``style``, CSS, embedded for a standalone file) and
    the roads of each road path in the order of their subpaths."""
    roads_markup, road_index = _roads(scene.roads)
    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" id="map" viewBox="{frame.view_box()}" '
        f'data-units-per-metre="{UNITS_PER_METRE}" preserveAspectRatio="xMidYMid meet" '
        f'style="--upp:{frame.units_per_pixel:.4g}">'
    ]
    if style:
        parts.append(f"<style>{style}</style>")
    parts.append(roads_markup)
    parts.append('<g id="tracks">' + "".join(_track(track) for track in scene.tracks) + "</g>")
    parts.append('<g id="platforms">' + "".join(_platform(bar) for bar in scene.platforms) + "</g>")
    parts.append('<g id="partners">')
    for link in scene.partners:
        (x1, y1), (x2, y2) = unit(link.a), unit(link.b)
        parts.append(
            f'<line class="partner" x1="{x1}" y1="{y1}" x2="{x2}" y2="{y2}">'
            f"{_title(f'partner switches {link.first!r} and {link.second!r}')}</line>"
        )
    parts.append("</g>")
    radius = frame.marker
    parts.append(
        '<g id="switches">' + "".join(_switch(mark, radius) for mark in scene.switches) + "</g>"
    )
    parts.append(_findings(findings, radius))
    parts.append("</svg>")
    return "".join(parts), road_index


def _roads(roads: Sequence[RoadShape]) -> tuple[str, list[list[RoadEntry]]]:
    paths, index = [], []
    for junction, css in ((False, "road"), (True, "road junction")):
        data, entries = [], []
        for road in roads:
            if road.junction is junction:
                own = path_data(road.runs)
                data.append(own)
                entries.append((road.id, road.name, own.count("M")))
        paths.append(f'<path class="{css}" d="{"".join(data)}"/>')
        index.append(entries)
    return '<g id="roads">' + "".join(paths) + "</g>", index


def _track(track: TrackShape) -> str:
    label = f"{track.lane_type} lane {track.lane_id} of road '{track.road_id}'"
    if track.road_name:
        label += f" ({track.road_name})"
    label += f", lane section at s={track.section_s:g}"
    return (
        f'<path class="track {_attr(track.lane_type)}" data-road="{_attr(track.road_id)}" '
        f'd="{path_data(track.runs)}">{_title(label)}</path>'
    )


def _platform(bar: PlatformBar) -> str:
    label = (
        f"station '{bar.station_id}' ({bar.station_name}), platform '{bar.platform_id}' "
        f"({bar.platform_name}): road '{bar.road_id}', side {bar.side}"
    )
    return (
        f'<path class="platform" data-station="{_attr(bar.station_id)}" '
        f'data-platform="{_attr(bar.platform_id)}" d="{path_data(bar.runs)}">'
        f"{_title(label)}</path>"
    )


def _switch(mark: SwitchMark, radius: int) -> str:
    x, y = unit(mark.at)
    label = (
        f"switch '{mark.id}' ({mark.name}), position {mark.position}: "
        f"main track road '{mark.main_road}' at s={mark.main_s}"
    )
    leg = ""
    if mark.side_at is not None:
        sx, sy = unit(mark.side_at)
        leg = f'<line class="switch-leg" x1="{x}" y1="{y}" x2="{sx}" y2="{sy}"/>'
        label += f", side track road '{mark.side_road}'"
    return (
        f'<g class="switch" data-id="{_attr(mark.id)}">{_title(label)}{leg}'
        f'<circle class="switch-mark" cx="{x}" cy="{y}" r="{radius}"/></g>'
    )


def _findings(findings: Sequence[PlacedFinding], radius: int) -> str:
    parts = ['<g id="findings">']
    for severity in _DRAW_ORDER:
        for placed in findings:
            finding = placed.finding
            if placed.at is None or finding.severity is not severity:
                continue
            x, y = unit(placed.at)
            label = f"{finding.code} [{finding.severity}] {placed.where}: {finding.message}"
            parts.append(
                f'<circle class="finding {severity}" data-finding="{placed.index}" '
                f'cx="{x}" cy="{y}" r="{radius}">{_title(label)}</circle>'
            )
    parts.append("</g>")
    return "".join(parts)
