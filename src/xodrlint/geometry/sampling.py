"""Polylines for drawing: as few points as keep every chord within a tolerance of the curve.

A straight record needs its two ends; a curve is split until the midpoint and quarter
points of each piece lie within the tolerance of its chord (quarter points too, so that
an S-bend whose middle happens to sit on the chord is still split). Curves with a known
curvature start from pieces that turn at most half a radian, so no bend hides between
two samples.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Final

from xodrlint.geometry.curves import MAX_COORDINATE, Record
from xodrlint.geometry.planview import ReferenceLine

Point = tuple[float, float]
#: The deepest a piece is split: 2**16 pieces per record is far more than any drawing needs.
_MAX_DEPTH: Final = 16
_START_TURN: Final = 0.5
#: Samples one record may have at most: a curve that still strays from its chords after
#: that many (a poly3 with absurd coefficients) must not hold the drawing up.
_MAX_SAMPLES: Final = 4096


def drawable(point: Point) -> bool:
    return abs(point[0]) < MAX_COORDINATE and abs(point[1]) < MAX_COORDINATE


#: Pieces a curve of unknown curvature (poly3, paramPoly3) starts from.
_UNKNOWN_CURVATURE_PIECES: Final = 4


def _distance_to_chord(point: Point, start: Point, end: Point) -> float:
    dx, dy = end[0] - start[0], end[1] - start[1]
    length_sq = dx * dx + dy * dy
    px, py = point[0] - start[0], point[1] - start[1]
    if length_sq == 0:
        return math.hypot(px, py)
    along = max(0.0, min(1.0, (px * dx + py * dy) / length_sq))
    return math.hypot(px - along * dx, py - along * dy)


def adaptive(
    curve: Callable[[float], Point], start: float, end: float, tolerance: float, pieces: int = 1
) -> list[tuple[float, Point]]:
    """``(s, point)`` samples of ``curve`` over ``[start, end]``, both ends included."""
    bounds = [start + (end - start) * i / pieces for i in range(pieces + 1)]
    points = [curve(s) for s in bounds]
    samples = [(bounds[0], points[0])]
    for i in range(pieces):
        _split(curve, (bounds[i], points[i]), (bounds[i + 1], points[i + 1]), tolerance, samples)
    return samples


def _split(
    curve: Callable[[float], Point],
    first: tuple[float, Point],
    last: tuple[float, Point],
    tolerance: float,
    samples: list[tuple[float, Point]],
    depth: int = 0,
    known_middle: Point | None = None,
) -> None:
    """Append the samples after ``first`` up to and including ``last``.

    The quarter points are only computed when the midpoint is within the tolerance, and
    handed down as the halves' midpoints when they are not: no point is computed twice.
    """
    s0, p0 = first
    s1, p1 = last
    middle = 0.5 * (s0 + s1)
    pm = known_middle if known_middle is not None else curve(middle)
    if depth >= _MAX_DEPTH or len(samples) >= _MAX_SAMPLES or not drawable(pm):
        samples.append(last)
        return
    q1 = q3 = None
    if _distance_to_chord(pm, p0, p1) <= tolerance:
        q1, q3 = curve(0.5 * (s0 + middle)), curve(0.5 * (middle + s1))
        if max(_distance_to_chord(q1, p0, p1), _distance_to_chord(q3, p0, p1)) <= tolerance:
            samples.append(last)
            return
    _split(curve, first, (middle, pm), tolerance, samples, depth + 1, q1)
    _split(curve, (middle, pm), last, tolerance, samples, depth + 1, q3)


def start_pieces(max_curvature: float | None, length: float) -> int:
    """How many pieces a record starts from before it is split adaptively."""
    if max_curvature is None:
        return _UNKNOWN_CURVATURE_PIECES
    return max(1, math.ceil(min(max_curvature * length / _START_TURN, _MAX_SAMPLES)))


def polylines(
    line: ReferenceLine,
    tolerance: float,
    lateral: Callable[[float], float] | None = None,
    window: tuple[float, float] | None = None,
) -> list[list[Point]]:
    """The reference line (or the curve ``lateral(s)`` metres left of it) as polylines.

    ``window`` limits the s range. A new polyline starts wherever a record does not begin
    within ``tolerance`` of where the previous one ended, so a gap in the data stays a gap
    in the drawing.
    """
    runs: list[list[Point]] = []
    current: list[Point] = []
    for record in line.records:
        low, high = record.s, record.s + record.length
        if window is not None:
            low, high = max(low, window[0]), min(high, window[1])
            if high < low:
                continue
        pieces = start_pieces(record.max_curvature(), high - low)
        curve = _curve_of(record, lateral)
        samples = [point for _, point in adaptive(curve, low, high, tolerance, pieces)]
        if current and math.dist(current[-1], samples[0]) > tolerance:
            runs.append(current)
            current = []
        for index, point in enumerate(samples):
            if not drawable(point):  # NaN fails the test too
                # a value past any map's extent: the run ends, the rest is not drawn
                runs.append(current)
                current = []
            elif index > 0 or not current:  # a record starts where the previous one ended
                current.append(point)
    if current:
        runs.append(current)
    return [run for run in runs if len(run) > 1]


def _curve_of(record: Record, lateral: Callable[[float], float] | None) -> Callable[[float], Point]:
    def curve(s: float) -> Point:
        pose = record.pose_at(min(max(s - record.s, 0.0), record.length))
        return pose.offset(lateral(s)) if lateral is not None else (pose.x, pose.y)

    return curve
