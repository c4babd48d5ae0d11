"""A road's reference line, read from its ``planView``: the records that can be used, and
a readable reason for each one that cannot (drawn as far as possible, never raised)."""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from typing import Final, NamedTuple

from lxml import etree

from xodrlint.geometry.curves import (
    MAX_TURN,
    Arc,
    Line,
    ParamPoly3,
    Poly3,
    Pose,
    Record,
    Spiral,
)
from xodrlint.model import number, numbers

#: The curve elements a ``geometry`` record may hold.
CURVE_TAGS: Final = ("line", "arc", "spiral", "poly3", "paramPoly3")
_RECORD_ATTRIBUTES: Final = ("s", "x", "y", "hdg", "length")
#: The coefficients of each curve but the line, in the order its record takes them.
_COEFFICIENTS: Final = {
    "arc": ("curvature",),
    "spiral": ("curvStart", "curvEnd"),
    "poly3": ("a", "b", "c", "d"),
    "paramPoly3": ("aU", "bU", "cU", "dU", "aV", "bV", "cV", "dV"),
}


#: How far beyond its ends a record still covers an s (m): the nearest end within a
#: millimetre counts as covering.
COVERS: Final = 1e-3


class GeometryProblem(NamedTuple):
    """A record (or a road) whose geometry cannot be drawn or judged, and why."""

    element: etree._Element
    road_id: str | None
    message: str


class ReferenceLine:
    """The usable records of one road, in order of s (a plain class, as the records are:
    see :class:`~xodrlint.geometry.curves.Record`)."""

    __slots__ = ("elements", "guessed", "problems", "records", "starts")

    def __init__(
        self,
        records: tuple[Record, ...],
        problems: tuple[GeometryProblem, ...] = (),
        *,
        guessed: tuple[GeometryProblem, ...] = (),
        elements: tuple[etree._Element, ...] = (),
    ) -> None:
        starts = [record.s for record in records]
        if starts != sorted(starts):  # a plan view written out of order
            order = sorted(range(len(records)), key=starts.__getitem__)  # stable, as s is
            records = tuple(records[index] for index in order)
            if elements:
                elements = tuple(elements[index] for index in order)
            starts = [starts[index] for index in order]
        self.records = records
        self.problems = problems
        self.starts = starts
        #: The ``geometry`` element of each record, in the same order (empty for a line
        #: made of records alone).
        self.elements = elements
        #: Records whose own length was unreadable and taken up to the next record or the
        #: road's end, each as a problem: good enough to draw, not to judge.
        self.guessed = guessed

    def __repr__(self) -> str:
        return f"ReferenceLine(records={self.records!r}, problems={self.problems!r})"

    def record_at(self, s: float) -> Record | None:
        """The record that covers ``s`` (the nearest end within 1 mm counts as covering)."""
        records = self.records
        index = bisect.bisect_right(self.starts, s) - 1
        for candidate in (index, index + 1):
            if 0 <= candidate < len(records):
                record = records[candidate]
                if record.s - COVERS <= s <= record.s + record.length + COVERS:
                    return record
        return None

    def pose(self, s: float) -> Pose | None:
        """The pose at ``s``; ``None`` where no usable record covers it."""
        record = self.record_at(s)
        if record is None:
            return None
        return record.pose_at(min(max(s - record.s, 0.0), record.length))

    @property
    def s_range(self) -> tuple[float, float] | None:
        if not self.records:
            return None
        last = self.records[-1]
        return self.records[0].s, last.s + last.length


def geometries(road: etree._Element) -> list[etree._Element]:
    """The ``geometry`` records of ``road``'s ``planView``, in document order."""
    # iterchildren, not find and findall: a third faster, and a railway reads every track
    plan_view = next(road.iterchildren("planView"), None)
    return list(plan_view.iterchildren("geometry")) if plan_view is not None else []


def reference_line(road: etree._Element) -> ReferenceLine:
    """Every usable record of ``road``'s ``planView``; the others as problems."""
    road_id = road.get("id")
    records: list[Record] = []
    elements: list[etree._Element] = []
    problems: list[GeometryProblem] = []
    guessed: list[GeometryProblem] = []
    found = geometries(road)
    if not found:
        problems.append(GeometryProblem(road, road_id, "road has no planView geometry"))
    for index, element in enumerate(found):
        record = read_record(element)
        if isinstance(record, str) and number(element, "length") is None:
            # drawn up to the next record or the road's end (looked up only on failure)
            why = record
            following = found[index + 1] if index + 1 < len(found) else None
            record = read_record(element, _length_fallback(element, following, road))
            if not isinstance(record, str):
                guessed.append(GeometryProblem(element, road_id, why))
        if isinstance(record, str):
            problems.append(GeometryProblem(element, road_id, record))
        else:
            records.append(record)
            elements.append(element)
    return ReferenceLine(
        tuple(records), tuple(problems), guessed=tuple(guessed), elements=tuple(elements)
    )


def _length_fallback(
    element: etree._Element, following: etree._Element | None, road: etree._Element
) -> float | None:
    """A record's length where its own is missing: up to the next record or the road end."""
    start = number(element, "s")
    end = number(following, "s") if following is not None else number(road, "length")
    return end - start if start is not None and end is not None and end > start else None


def curve_element(element: etree._Element) -> etree._Element | None:
    """The curve a ``geometry`` record holds (its first ``line``, ``arc``, ... child)."""
    for curve in element:
        if curve.tag in CURVE_TAGS:
            return curve
    return None


def written(element: etree._Element, attribute: str) -> str:
    """An attribute's value for messages, as written (quoted), or ``missing``."""
    raw = element.get(attribute)
    return "missing" if raw is None else f"'{raw}'"


def unreadable_numbers(element: etree._Element, names: Sequence[str]) -> str:
    """Each of ``names`` whose value is no finite number, with the value as written
    (``x ('INF'), length (missing)``); empty when every one is a finite number."""
    return ", ".join(
        f"{name} ({written(element, name)})" for name in names if number(element, name) is None
    )


def read_record(element: etree._Element, length_fallback: float | None = None) -> Record | str:
    """The record of a ``geometry`` element, or why it cannot be drawn."""
    s, x, y, hdg, length = numbers(element, _RECORD_ATTRIBUTES)
    if length is None:
        length = length_fallback
    curve = curve_element(element)
    if s is None or x is None or y is None or hdg is None or length is None or curve is None:
        return _unreadable_record(element, curve)
    if length < 0:
        return f"geometry has a negative length ({written(element, 'length')})"
    record = _curve(curve, s, x, y, hdg, length)
    if isinstance(record, str):
        return record
    bound = record.max_curvature()
    if bound is not None and bound * length > MAX_TURN:
        return f"geometry turns {bound * length:.3g} rad in {length:g} m, more than {MAX_TURN:g}"
    # finite curvatures over a tiny length can give a rate of change that overflows
    if (
        isinstance(record, Spiral)
        and length > 0
        and not math.isfinite((record.curv_end - record.curv_start) / length)
    ):
        return f"spiral's curvature changes too fast over {length:g} m: its rate overflows"
    return record


def _unreadable_record(element: etree._Element, curve: etree._Element | None) -> str:
    """Every reason a record's numbers cannot be read: its own attributes (its length too,
    where a fallback stood in), its curve element and that curve's coefficients."""
    reasons = []
    bad = unreadable_numbers(element, _RECORD_ATTRIBUTES)
    if bad:
        reasons.append(f"geometry lacks a finite number in {bad}")
    if curve is None:
        reasons.append("geometry has no line, arc, spiral, poly3 or paramPoly3")
    else:
        coefficients = _coefficients(curve, _COEFFICIENTS.get(str(curve.tag), ()))
        if isinstance(coefficients, str):
            reasons.append(coefficients)
    return "; ".join(reasons)


def _coefficients(element: etree._Element, names: Sequence[str]) -> list[float] | str:
    found = numbers(element, names)
    if None in found:
        return f"{element.tag} lacks a finite number in {unreadable_numbers(element, names)}"
    return found  # type: ignore[return-value]  # no None: checked


def _curve(
    curve: etree._Element, s: float, x: float, y: float, hdg: float, length: float
) -> Record | str:
    tag = curve.tag
    if tag == "line":
        return Line(s, x, y, hdg, length)
    values = _coefficients(curve, _COEFFICIENTS[str(tag)])
    if isinstance(values, str):
        return values
    if tag == "arc":
        return Arc(s, x, y, hdg, length, values[0])
    if tag == "spiral":
        return Spiral(s, x, y, hdg, length, values[0], values[1])
    if tag == "poly3":
        return Poly3(s, x, y, hdg, length, *values)
    p_range = curve.get("pRange", "normalized")
    if p_range not in ("normalized", "arcLength"):
        return f"paramPoly3 has pRange '{p_range}', expected 'arcLength' or 'normalized'"
    u = (values[0], values[1], values[2], values[3])
    v = (values[4], values[5], values[6], values[7])
    return ParamPoly3(s, x, y, hdg, length, u, v, p_range == "normalized")
