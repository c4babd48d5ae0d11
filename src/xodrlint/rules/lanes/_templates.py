"""Judging each lane layout once: a railway repeats a few layouts over thousands of roads.

A rule's judge looks at a template road (:attr:`~xodrlint.model.Road.lane_template`: a
road whose ``lanes`` read the same) and the length of the road it stands for, and
returns what it found as positions (lane section, lane) and values. The rule then reads
the road's own lanes, and only where there is something to report, for the elements and
ids of its message.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TypeVar

from xodrlint.rules import Lane, LaneSection, RailNetwork, Road, section_ranges

_V = TypeVar("_V")


def judged_once_per_layout(
    network: RailNetwork,
    judge: Callable[[Road, float | None], list[_V]],
    *,
    by_length: bool = False,
) -> Iterator[tuple[Road, list[_V]]]:
    """Each rail road with what ``judge(template, length)`` finds: called once per lane
    layout, or once per layout and road length where ``by_length`` (the last lane
    section ends where the road does)."""
    judged: dict[tuple[Road, float | None], list[_V]] = {}
    for road in network.rail_roads:
        key = (road.lane_template, road.length if by_length else None)
        found = judged.get(key)
        if found is None:
            found = judged[key] = judge(key[0], road.length)
        if found:
            yield road, found


def own_lane(road: Road, section_index: int, lane_index: int) -> tuple[LaneSection, Lane]:
    """The road's own lane section and lane at the positions a judge of its template
    named (the layouts are the same, text for text)."""
    section = road.lane_sections[section_index]
    return section, section.lanes[lane_index]


def ranged_sections(
    template: Road, length: float | None
) -> Iterator[tuple[int, LaneSection, float, float]]:
    """:meth:`~xodrlint.model.Road.section_ranges` of ``template`` on a road ``length``
    long, each lane section with its index among all of the road's sections."""
    sections = template.lane_sections
    index_of = {id(section): index for index, section in enumerate(sections)}
    for section, start, end in section_ranges(sections, length):
        yield index_of[id(section)], section, start, end
