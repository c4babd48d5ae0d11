"""Whether a road's plan view can be evaluated: the one predicate behind the track points
the geometry rules judge (:class:`~xodrlint.geometry.tracks.TrackGeometry`) and behind
the rule that says why a track is not judged (TR014), so that no rule is silent on a
track without a reason a user is told.

A plan view can be evaluated when it has records, every record can be read (no missing,
non-numeric or non-finite number, a curve element, a known ``pRange``, no turn or
curvature rate beyond what a double holds: :func:`~xodrlint.geometry.planview.read_record`),
no record's length had to be guessed, and each record has a positive length, starts at a
place and heading a map holds, and ends at one (its numbers do not overflow on the way).
Each record's start and end pose are worked out here once, for the continuity rule.
"""

from __future__ import annotations

import math
from typing import Final, NamedTuple

from lxml import etree

from xodrlint.geometry.curves import MAX_COORDINATE, MAX_HEADING, ParamPoly3, Poly3, Pose, Record
from xodrlint.geometry.planview import (
    GeometryProblem,
    ReferenceLine,
    curve_element,
    geometries,
    reference_line,
    written,
)

#: How messages write the limits: ``1e9``, not ``1e+09``.
_COORDINATE_LIMIT: Final = f"{MAX_COORDINATE:.0e}".replace("e+0", "e")
_HEADING_LIMIT: Final = f"{MAX_HEADING:.0e}".replace("e+0", "e")


class PlanView(NamedTuple):
    """A road's plan view as the rules see it: its reference line and each record's start
    and end pose when every record can be evaluated; otherwise no line, and why not
    (one problem for each record that cannot be evaluated, in document order, or one on
    the road when it has no geometry)."""

    line: ReferenceLine | None
    problems: tuple[GeometryProblem, ...]
    ends: tuple[tuple[Pose, Pose], ...] = ()
    """The start and end pose of each record of ``line``, in order of s."""


def judge_plan_view(road: etree._Element) -> PlanView:
    """``road``'s plan view, judged (see the module's docstring)."""
    line = reference_line(road)
    reasons: dict[etree._Element, list[str]] = {}
    for problem in (*line.problems, *line.guessed):
        reasons.setdefault(problem.element, []).append(problem.message)
    ends: list[tuple[Pose, Pose]] = []
    for record, element in zip(line.records, line.elements, strict=True):
        found = _ends(record)
        if found is None:
            reasons.setdefault(element, []).append(_why_not(record, element))
        else:
            ends.append(found)
    if not reasons:
        return PlanView(line, (), tuple(ends))
    order = {element: index for index, element in enumerate(geometries(road))}
    road_id = road.get("id")
    problems = tuple(
        GeometryProblem(element, road_id, "; ".join(messages))
        for element, messages in sorted(reasons.items(), key=lambda item: order.get(item[0], -1))
    )
    return PlanView(None, problems)


def _ends(record: Record) -> tuple[Pose, Pose] | None:
    """The start and end pose of a record the rules can use; ``None`` for one they cannot
    (a railway's every record passes here: the common case costs two evaluations)."""
    x, y, hdg = record.x, record.y, record.hdg
    if not (
        record.length > 0
        and abs(x) < MAX_COORDINATE
        and abs(y) < MAX_COORDINATE
        and abs(hdg) < MAX_HEADING
    ):
        return None
    try:
        # a line, an arc and a spiral start at their own x, y and hdg; a poly3's a and b
        # and a paramPoly3's aU, aV, bU, bV move and turn the start
        start = record.pose_at(0.0) if isinstance(record, Poly3 | ParamPoly3) else Pose(x, y, hdg)
        end = record.end
    except (ArithmeticError, ValueError):
        return None
    return (start, end) if _on_map(start) and _on_map(end) else None


def _why_not(record: Record, element: etree._Element) -> str:
    """Why the rules cannot use a record that was read (see :func:`_ends`)."""
    reasons = []
    if not record.length > 0:  # a negative one is not even read
        reasons.append(f"geometry has length {written(element, 'length')}, not above 0")
    far = [name for name in ("x", "y") if not abs(getattr(record, name)) < MAX_COORDINATE]
    if far:
        values = ", ".join(f"{name} ({written(element, name)})" for name in far)
        reasons.append(f"geometry starts {_COORDINATE_LIMIT} m or more from the origin: {values}")
    if not abs(record.hdg) < MAX_HEADING:
        reasons.append(f"geometry has hdg {written(element, 'hdg')}, {_HEADING_LIMIT} rad or more")
    if reasons:
        return "; ".join(reasons)
    curve = curve_element(element)
    kind = curve.tag if curve is not None else "geometry"
    return (
        f"{kind}'s numbers overflow: it starts or ends {_COORDINATE_LIMIT} m or more from "
        "the origin, or at no number"
    )


def _on_map(pose: Pose) -> bool:
    """A place a map holds and a direction (also false for nan and inf)."""
    return abs(pose.x) < MAX_COORDINATE and abs(pose.y) < MAX_COORDINATE and math.isfinite(pose.hdg)
