"""Vertical and lateral profiles: a road's elevation (``elevationProfile/elevation``) and
superelevation (``lateralProfile/superelevation``), each the cubic polynomials of its
entries, for the vertical track rules (TR010 to TR012) and the joints between tracks.

- An entry ``s a b c d`` holds from its ``s`` to the next entry's ``s``, the last one to
  the road's ``@length``; its value there is ``a + b·ds + c·ds² + d·ds³``, ``ds`` measured
  from its ``s``. A road without entries has the value 0 everywhere.
- The entries are taken in order of ``s`` (as written where an ``s`` is unreadable: its
  place is then known only from the document).
- An entry with a missing, non-numeric or non-finite ``s``, ``a``, ``b``, ``c`` or ``d``
  is unreadable: nothing is judged where it holds, nor across its boundaries, and the
  value there is unknown (TR014 reports the entry).

Extremes are exact: a cubic's extremes on a stretch are at the stretch's ends and at the
real roots of its derivative inside; its derivative's (a quadratic) at the ends and at
its vertex. A road's profiles are read the first time they are asked for, once per file
(:class:`VerticalProfiles` is shared through
:meth:`~xodrlint.model.RailNetwork.shared`).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterator
from typing import Final, NamedTuple

from lxml import etree

from xodrlint.model import RailNetwork, Road, numbers
from xodrlint.model.lane_profiles import S_TOLERANCE, quadratic_roots

_VALUES: Final = ("s", "a", "b", "c", "d")


class Entry(NamedTuple):
    """One ``elevation`` or ``superelevation`` entry as written; ``s`` or ``cubic`` is
    ``None`` when unreadable."""

    element: etree._Element
    s: float | None
    cubic: tuple[float, float, float, float] | None
    """``(a, b, c, d)``."""

    @property
    def readable(self) -> bool:
        return self.s is not None and self.cubic is not None


class Span(NamedTuple):
    """A readable entry and the stretch ``[start, end]`` it holds on (absolute s)."""

    element: etree._Element
    start: float
    end: float
    a: float
    b: float
    c: float
    d: float

    def value(self, s: float) -> float:
        x = s - self.start
        return self.a + x * (self.b + x * (self.c + x * self.d))

    def slope(self, s: float) -> float:
        x = s - self.start
        return self.b + x * (2 * self.c + 3 * self.d * x)

    def largest(self) -> tuple[float, float] | None:
        """The value of largest magnitude on the stretch and its s; ``None`` when a value
        is not finite."""
        return _largest(self.value, self._stationary_points())

    def steepest(self) -> tuple[float, float] | None:
        """The slope of largest magnitude on the stretch and its s; ``None`` when a slope
        is not finite."""
        vertex: tuple[float, ...] = (-self.c / (3 * self.d),) if self.d != 0 else ()
        return _largest(self.slope, self._inside(vertex))

    def _stationary_points(self) -> tuple[float, ...]:
        return self._inside(quadratic_roots(3 * self.d, 2 * self.c, self.b))

    def _inside(self, offsets: tuple[float, ...]) -> tuple[float, ...]:
        length = self.end - self.start
        return (
            self.start,
            self.end,
            *(self.start + x for x in offsets if math.isfinite(x) and 0 < x < length),
        )


class Step(NamedTuple):
    """Where one entry ends and the next begins: the value the earlier entry reaches at
    ``s``, and the value the later one (``element``) starts with."""

    element: etree._Element
    s: float
    before: float
    after: float


class Profile:
    """One road's entries of one kind, in the order they hold."""

    __slots__ = ("entries", "length", "unreadable")

    def __init__(self, entries: tuple[Entry, ...], length: float | None) -> None:
        #: The entries that are not readable, in document order (TR014 reports them).
        self.unreadable = tuple(entry for entry in entries if not entry.readable)
        if len(entries) > 1 and all(entry.s is not None for entry in entries):
            entries = tuple(sorted(entries, key=lambda entry: entry.s or 0.0))
        self.entries = entries
        self.length = length

    def spans(self) -> Iterator[Span]:
        """Each readable entry whose stretch is known and longer than the tolerance."""
        entries = self.entries
        for index, entry in enumerate(entries):
            end = entries[index + 1].s if index + 1 < len(entries) else self.length
            if entry.s is None or entry.cubic is None or end is None:
                continue
            if self.length is not None:
                end = min(end, self.length)  # an entry starting beyond the road holds nowhere
            if end - entry.s > S_TOLERANCE:
                yield Span(entry.element, entry.s, end, *entry.cubic)

    def steps(self) -> Iterator[Step]:
        """Each boundary between two readable entries inside the road (an entry starting
        beyond the road's end holds nowhere)."""
        entries = self.entries
        for earlier, later in itertools.pairwise(entries):
            if not (earlier.readable and later.readable):
                continue
            start, s = earlier.s or 0.0, later.s or 0.0
            if s < start - S_TOLERANCE or (
                self.length is not None and s > self.length + S_TOLERANCE
            ):
                continue
            assert earlier.cubic is not None and later.cubic is not None
            a, b, c, d = earlier.cubic
            x = s - start
            before = a + x * (b + x * (c + x * d))
            after = later.cubic[0]
            if math.isfinite(before) and math.isfinite(after):
                yield Step(later.element, s, before, after)

    def value_at(self, s: float) -> float | None:
        """The value at ``s``: that of the entry holding there (at a boundary, the one
        starting there), 0 without entries; ``None`` where the entry holding there is
        unreadable, unknown, or where ``s`` lies before the first entry."""
        entries = self.entries
        if not entries:
            return 0.0
        holder: Entry | None = None
        unknown_after = False
        for entry in entries:
            if entry.s is None:
                unknown_after = True  # an entry that may or may not start before s
            elif entry.s <= s + S_TOLERANCE:
                holder, unknown_after = entry, False
            else:
                break
        if holder is None or holder.cubic is None or holder.s is None or unknown_after:
            return None
        a, b, c, d = holder.cubic
        x = s - holder.s
        value = a + x * (b + x * (c + x * d))
        return value if math.isfinite(value) else None


class VerticalProfiles:
    """The elevation and superelevation of one file's roads, each road's read once."""

    def __init__(self, network: RailNetwork) -> None:
        del network  # taken as RailNetwork.shared makes it; roads are passed per call
        self._profiles: dict[Road, tuple[Profile, Profile]] = {}
        self._tracks: list[tuple[Road, Profile, Profile]] | None = None

    def tracks(self, network: RailNetwork) -> list[tuple[Road, Profile, Profile]]:
        """Each road of ``network`` with a rail or tram lane and at least one elevation or
        superelevation entry, with both its profiles (listed once per file: a railway's
        four profile rules then pass over the tracks that have entries only)."""
        if self._tracks is None:
            self._tracks = []
            for road in network.rail_roads:
                if not road.profiles:
                    continue  # no entries (nearly every track of a railway)
                elevation, superelevation = self._read(road)
                if elevation.entries or superelevation.entries:
                    self._tracks.append((road, elevation, superelevation))
        return self._tracks

    def elevation(self, road: Road) -> Profile:
        """The road's elevation profile (``elevationProfile/elevation``)."""
        return self._read(road)[0]

    def superelevation(self, road: Road) -> Profile:
        """The road's superelevation (``lateralProfile/superelevation``, roll angle in rad)."""
        return self._read(road)[1]

    def elevation_at(self, road: Road, s: float) -> float | None:
        """The reference line's elevation of ``road`` at ``s``; ``None`` where it cannot be
        evaluated (see :meth:`Profile.value_at`)."""
        if not math.isfinite(s):
            return None
        return self._read(road)[0].value_at(s)

    def _read(self, road: Road) -> tuple[Profile, Profile]:
        found = self._profiles.get(road)
        if found is None:
            # both kinds from the one pass over the road's children that also reads its
            # links (most tracks have neither)
            elevation: list[Entry] = []
            superelevation: list[Entry] = []
            for container in road.profiles:
                if container.tag == "elevationProfile":
                    elevation.extend(map(_entry, container.iterchildren("elevation")))
                else:
                    superelevation.extend(map(_entry, container.iterchildren("superelevation")))
            found = self._profiles[road] = (
                Profile(tuple(elevation), road.length) if elevation else _NO_ENTRIES,
                Profile(tuple(superelevation), road.length) if superelevation else _NO_ENTRIES,
            )
        return found


def _entry(element: etree._Element) -> Entry:
    s, a, b, c, d = numbers(element, _VALUES)
    cubic = (
        (a, b, c, d)
        if a is not None and b is not None and c is not None and d is not None
        else None
    )
    return Entry(element, s, cubic)


def _largest(
    function: Callable[[float], float], candidates: tuple[float, ...]
) -> tuple[float, float] | None:
    best: tuple[float, float] | None = None
    for s in candidates:
        value = function(s)
        if not math.isfinite(value):
            return None
        if best is None or abs(value) > abs(best[0]):
            best = (value, s)
    return best


#: A road without entries: the value 0 everywhere, nothing to judge.
_NO_ENTRIES: Final = Profile((), None)
