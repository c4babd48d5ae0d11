"""Lateral profiles: ``laneOffset`` and lane ``width`` as the piecewise cubics they are.

A lane's centre and width along a lane section are sums of cubic polynomials whose
pieces start at different s. On every stretch between two consecutive piece starts the
sum is itself one cubic, so its extremes are exact: the stretch's two ends and the
roots of its derivative (a quadratic) inside it. Each piece is evaluated on its closed
stretch, so the value just before a new ``width`` or ``laneOffset`` entry starts counts
too. Rules use this to say "anywhere along the lane section" without sampling.
"""

from __future__ import annotations

import bisect
import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Final, NamedTuple

from xodrlint.model import Cubic, Lane, LaneSection, Road

#: Absolute tolerance for lengths and s-coordinates (the catalogue's 1e-6 m).
S_TOLERANCE: Final = 1e-6


class Poly(NamedTuple):
    """``a + b·x + c·x² + d·x³`` with ``x = s - base`` (``base`` an absolute s)."""

    base: float
    a: float
    b: float
    c: float
    d: float

    @classmethod
    def of(cls, cubic: Cubic, origin: float = 0.0) -> Poly:
        return cls(origin + cubic.start, cubic.a, cubic.b, cubic.c, cubic.d)

    def shifted(self, base: float) -> Poly:
        """The same polynomial, written around ``base``."""
        h = base - self.base
        a = self.a + h * (self.b + h * (self.c + h * self.d))
        b = self.b + h * (2 * self.c + 3 * h * self.d)
        c = self.c + 3 * h * self.d
        return Poly(base, a, b, c, self.d)

    def scaled(self, factor: float) -> Poly:
        return Poly(self.base, factor * self.a, factor * self.b, factor * self.c, factor * self.d)

    def at(self, s: float) -> float:
        x = s - self.base
        return self.a + x * (self.b + x * (self.c + x * self.d))


@dataclass(frozen=True, slots=True)
class Piecewise:
    """Cubic pieces, each valid from its base to the next piece's base.

    ``zero_before`` says the function is 0 before its first piece (a road without
    ``laneOffset`` has no offset); otherwise it is undefined there (a lane width).
    """

    pieces: tuple[Poly, ...]
    zero_before: bool = False
    starts: tuple[float, ...] = field(init=False, repr=False, compare=False)
    """The pieces' bases in order, for the bisection in :meth:`piece_at`."""

    def __post_init__(self) -> None:
        ordered = tuple(sorted(self.pieces, key=lambda piece: piece.base))
        object.__setattr__(self, "pieces", ordered)
        object.__setattr__(self, "starts", tuple(piece.base for piece in ordered))

    @property
    def defined_from(self) -> float:
        """The first s the function has a value at."""
        if self.zero_before or not self.pieces:
            return -math.inf
        return self.pieces[0].base

    def piece_at(self, s: float) -> Poly | None:
        """The piece that holds from ``s`` on; ``None`` where the function is undefined."""
        index = bisect.bisect_right(self.starts, s + S_TOLERANCE) - 1
        if index >= 0:
            return self.pieces[index]
        return Poly(s, 0.0, 0.0, 0.0, 0.0) if self.zero_before else None


class Extremes(NamedTuple):
    low: float
    s_low: float
    high: float
    s_high: float


def extremes(terms: Sequence[tuple[float, Piecewise]], start: float, end: float) -> Extremes | None:
    """The exact minimum and maximum of ``Σ weight·function`` over ``[start, end]``.

    Where a term only starts inside the range (a first ``width`` entry with ``sOffset``
    > 0), the range begins there: nothing is known before it. ``None`` when no part of
    the range has every term defined, or a value is not finite.
    """
    start = max([start, *(fn.defined_from for _, fn in terms)])
    if start > end + S_TOLERANCE:
        return None
    end = max(start, end)
    constant = _constant_sum(terms, start)
    if constant is not None:  # most lanes: one constant width, one constant offset
        return Extremes(constant, start, constant, start) if math.isfinite(constant) else None
    stretches = summed_pieces(terms, start, end)
    if stretches is None:
        return None
    found: Extremes | None = None
    for low_s, high_s, summed in stretches:
        for s in _candidates(summed, low_s, high_s):
            value = summed.at(s)
            if not math.isfinite(value):
                return None
            if found is None:
                found = Extremes(value, s, value, s)
            elif value < found.low:
                found = Extremes(value, s, found.high, found.s_high)
            elif value > found.high:
                found = Extremes(found.low, found.s_low, value, s)
    return found


def summed_pieces(
    terms: Sequence[tuple[float, Piecewise]], start: float, end: float
) -> list[tuple[float, float, Poly]] | None:
    """``Σ weight·function`` over ``[start, end]`` as one cubic per stretch between the
    functions' piece starts, each written around its stretch's start; ``None`` where a
    function has no piece there. Shared by :func:`extremes` and the lane curvature of
    :mod:`xodrlint.geometry.curvature`."""
    breaks = sorted(
        {b for _, fn in terms for b in fn.starts if start + S_TOLERANCE < b < end - S_TOLERANCE}
    )
    stretches = []
    for low, high in itertools.pairwise([start, *breaks, end]):
        summed = Poly(low, 0.0, 0.0, 0.0, 0.0)
        for weight, fn in terms:
            piece = fn.piece_at(low)
            if piece is None:
                return None
            part = piece.shifted(low).scaled(weight)
            summed = Poly(
                low, summed.a + part.a, summed.b + part.b, summed.c + part.c, summed.d + part.d
            )
        stretches.append((low, high, summed))
    return stretches


def _constant_sum(terms: Sequence[tuple[float, Piecewise]], start: float) -> float | None:
    """``Σ weight·function`` when every function is one constant over the range."""
    total = 0.0
    for weight, fn in terms:
        pieces = fn.pieces
        if not pieces and fn.zero_before:
            continue
        if len(pieces) != 1 or pieces[0].base > start + S_TOLERANCE:
            return None
        piece = pieces[0]
        if piece.b != 0 or piece.c != 0 or piece.d != 0:
            return None
        total += weight * piece.a
    return total


def _candidates(poly: Poly, start: float, end: float) -> Iterator[float]:
    """The ends of ``[start, end]`` and the stationary points of ``poly`` inside it."""
    yield start
    yield end
    length = end - start
    for x in quadratic_roots(3 * poly.d, 2 * poly.c, poly.b):
        if 0 < x < length:
            yield start + x


def quadratic_roots(a: float, b: float, c: float) -> tuple[float, ...]:
    """The real roots of ``a·x² + b·x + c`` (a linear one where ``a`` is 0); none where
    the discriminant is negative or not finite. Also the extremes of the elevation and
    superelevation cubics (:mod:`xodrlint.geometry.profiles`)."""
    if a == 0:
        return (-c / b,) if b != 0 else ()
    discriminant = b * b - 4 * a * c
    if not math.isfinite(discriminant) or discriminant < 0:
        return ()
    # the numerically stable pair: no cancellation between b and the square root
    q = -0.5 * (b + math.copysign(math.sqrt(discriminant), b))
    if q == 0:
        return (0.0,)
    return (q / a, c / q)


def lateral_value(terms: Sequence[tuple[float, Piecewise]], s: float) -> float:
    """``Σ weight·function(s)`` of :func:`centre_terms`: the lateral position at ``s``. A
    function not yet started at ``s`` (a ``width`` whose first ``sOffset`` lies beyond)
    is taken from its first piece."""
    total = 0.0
    for weight, function in terms:
        piece = function.piece_at(s) or (function.pieces[0] if function.pieces else None)
        total += weight * piece.at(s) if piece is not None else 0.0
    return total


def lane_offset(road: Road) -> Piecewise | None:
    """The road's ``laneOffset`` (0 where none is given); ``None`` if an entry is unreadable."""
    if not road.lane_offsets_complete:
        return None
    return Piecewise(tuple(Poly.of(cubic) for cubic in road.lane_offsets), zero_before=True)


def lane_width(lane: Lane, section_start: float) -> Piecewise | None:
    """The lane's width along its section; ``None`` if it has no readable ``width`` entries
    (a lane described by ``border`` entries, or an unreadable coefficient)."""
    if not lane.widths or not lane.widths_complete:
        return None
    return Piecewise(tuple(Poly.of(cubic, section_start) for cubic in lane.widths))


def centre_terms(
    road: Road, section: LaneSection, section_start: float, lane: Lane
) -> list[tuple[float, Piecewise]] | None:
    """The lateral position of ``lane``'s centre line as weighted terms for :func:`extremes`.

    Left of the centre lane t grows, right of it t falls: the centre of lane ``k`` lies at
    the offset plus (or minus) the widths of lanes 1..k-1 and half the width of lane k.
    ``None`` when a lane in between is missing or has no usable width.
    """
    offset = lane_offset(road)
    if offset is None or lane.id is None or lane.id == 0:
        return None
    sign = 1.0 if lane.id > 0 else -1.0
    by_id = {other.id: other for other in section.lanes if other.side == lane.side}
    terms = [(1.0, offset)]
    for step in range(1, abs(lane.id) + 1):
        inner = by_id.get(int(sign) * step)
        width = lane_width(inner, section_start) if inner is not None else None
        if width is None:
            return None
        terms.append((sign * (0.5 if step == abs(lane.id) else 1.0), width))
    return terms


def centre_at(
    road: Road, section: LaneSection, section_start: float, lane: Lane, s: float
) -> float | None:
    """``lateral_value(centre_terms(road, section, section_start, lane), s)``, evaluated at
    the one ``s`` without building the piecewise functions: the track-geometry rules ask
    once per switch or joint, where building them cost three times the evaluation.
    Where a lane's width is not yet defined at ``s`` (its first ``sOffset`` lies beyond),
    ``None``: :func:`extremes` leaves that stretch unjudged too."""
    lanes = road.lanes
    if not lanes.offsets_complete or lane.id is None or lane.id == 0:
        return None
    total = _piece_value(lanes.offsets, 0.0, s, True) or 0.0
    depth = abs(lane.id)
    sign = 1.0 if lane.id > 0 else -1.0
    # the lanes from the centre out to ``lane``, each the first of its id (a railway's
    # track lane is nearly always -1 or 1: one pass over a few lanes)
    inner: dict[int, Lane] = {}
    for other in section.lanes:
        if other.side == lane.side and other.id is not None and other.id not in inner:
            inner[other.id] = other
    for step in range(1, depth + 1):
        found = inner.get(int(sign) * step)
        if found is None or not found.widths or not found.widths_complete:
            return None
        width = _piece_value(found.widths, section_start, s, False)
        if width is None:
            return None
        total += sign * (0.5 if step == depth else 1.0) * width
    return total


def _piece_value(
    cubics: Sequence[Cubic], origin: float, s: float, zero_before: bool
) -> float | None:
    """The value at ``s`` of the piece that holds there, chosen as :meth:`Piecewise.piece_at`
    chooses it (the later of equal starts); before the first piece, 0 (``zero_before``)
    or ``None``."""
    chosen: Cubic | None = None
    for cubic in cubics:
        started = cubic.start + origin <= s + S_TOLERANCE
        if started and (chosen is None or cubic.start >= chosen.start):
            chosen = cubic
    if chosen is None:
        return 0.0 if zero_before else None
    x = s - (origin + chosen.start)
    return chosen.a + x * (chosen.b + x * (chosen.c + x * chosen.d))
