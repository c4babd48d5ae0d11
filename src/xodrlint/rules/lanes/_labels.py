"""How lane messages name a lane and its lane section."""

from __future__ import annotations

from xodrlint.rules import Lane, Road
from xodrlint.rules._shared import metres, quoted


def lane_label(lane: Lane, road: Road, section_start: float | None) -> str:
    where = f" (lane section at s={metres(section_start)})" if section_start is not None else ""
    return f"lane {quoted(lane.element.get('id'))} of road {quoted(road.id)}{where}"
