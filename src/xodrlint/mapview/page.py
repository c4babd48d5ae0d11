"""The self-contained page: the SVG inline, the page's CSS and script from the package's
data files, and the findings and road index as JSON the script reads. No network."""

from __future__ import annotations

import json
from collections.abc import Sequence
from html import escape
from importlib.resources import files
from string import Template
from typing import Final

from xodrlint.mapview.scene import Scene
from xodrlint.mapview.svg import Frame, PlacedFinding, RoadEntry, render_svg, unit


def resource(name: str) -> str:
    return files("xodrlint.mapview").joinpath(name).read_text("utf-8")


def standalone_svg(scene: Scene, findings: Sequence[PlacedFinding], frame: Frame) -> str:
    """A static SVG file: the drawing and its finding markers, styled, without a script."""
    svg, _ = render_svg(scene, findings, frame, style=resource("map.css"))
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + svg + "\n"


_SCRIPT_ESCAPES: Final = (("<", "\\u003c"), (">", "\\u003e"), ("&", "\\u0026"))


def html_page(title: str, scene: Scene, findings: Sequence[PlacedFinding], frame: Frame) -> str:
    svg, road_index = render_svg(scene, findings, frame)
    data = _data(title, scene, findings, road_index)
    # In a script element "</script" ends it and "<!--<script" makes the parser swallow
    # the page's own script: no "<" at all (JSON reads "\u003c" as "<"), nor ">" or "&"
    payload = json.dumps(data, ensure_ascii=False, separators=(",", ":"))
    for raw, escaped in _SCRIPT_ESCAPES:
        payload = payload.replace(raw, escaped)
    return Template(resource("template.html")).substitute(
        title=escape(title),
        css=resource("map.css"),
        svg=svg,
        data=payload,
        script=resource("map.js"),
    )


def _data(
    title: str,
    scene: Scene,
    findings: Sequence[PlacedFinding],
    road_index: list[list[RoadEntry]],
) -> dict[str, object]:
    return {
        "title": title,
        "roadCount": scene.road_count(),
        "roads": road_index,
        "findings": [
            {
                "code": placed.finding.code,
                "severity": str(placed.finding.severity),
                "message": placed.finding.message,
                "line": placed.finding.line,
                "file": placed.file,
                "xpath": placed.finding.xpath,
                "at": list(unit(placed.at)) if placed.at is not None else None,
            }
            for placed in findings
        ],
        "notDrawn": [
            {"line": item.line, "what": item.what, "reason": item.reason}
            for item in scene.not_drawn
        ],
    }
