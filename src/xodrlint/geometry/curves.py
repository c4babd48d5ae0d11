"""The plan-view curves of OpenDRIVE: ``line``, ``arc``, ``spiral``, ``poly3``, ``paramPoly3``.

Each record is a curve of its own, placed by its start pose (``x``, ``y``, ``hdg``) and
parametrised by the distance ``ds`` from its start. Closed forms where they exist; the
clothoid's Fresnel-type integrals and the arc length of ``poly3`` by composite
Gauss-Legendre quadrature, whose panels are kept short enough in heading change that the
error stays far below a millimetre (the tests compare against brute-force integration).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import lru_cache
from typing import Any, ClassVar, Final, NamedTuple

#: Heading change (rad) one quadrature panel may span: 8 nodes over 0.25 rad integrate
#: cos and sin of a quadratic phase to about 1e-15 relative error.
_PANEL_TURN: Final = 0.25
_NODES: Final = 8
#: Panels one integral may use at most: enough for the largest turn a record may have
#: (:data:`MAX_TURN`); a bound on the work any one point costs.
_MAX_PANELS: Final = 256
#: Coordinates beyond a million kilometres belong to no map (and would overflow when
#: written in centimetres): such points are neither drawn nor judged.
MAX_COORDINATE: Final = 1e9
#: The most a record may turn, in radians (about ten full circles): no track or road does,
#: and a record that would is a data error, listed rather than drawn.
MAX_TURN: Final = 64.0
#: Headings beyond this many radians have lost their meaning to rounding (an ulp of 1e6
#: is 1e-10 rad); a record heading so far is a data error, not a direction.
MAX_HEADING: Final = 1e6


class Pose(NamedTuple):
    """A point of a curve and the curve's heading there (rad, counter-clockwise from +x)."""

    x: float
    y: float
    hdg: float

    def offset(self, t: float) -> tuple[float, float]:
        """The point ``t`` metres left of this pose (right for negative ``t``)."""
        return (self.x - t * math.sin(self.hdg), self.y + t * math.cos(self.hdg))


@lru_cache(maxsize=4)
def gauss_legendre(n: int) -> tuple[tuple[float, float], ...]:
    """The ``n`` nodes and weights of Gauss-Legendre quadrature on ``[-1, 1]``."""
    rule = []
    for i in range(1, n + 1):
        x = math.cos(math.pi * (i - 0.25) / (n + 0.5))  # Tricomi's first guess
        derivative = 1.0
        for _ in range(100):
            p0, p1 = 1.0, x
            for k in range(2, n + 1):
                p0, p1 = p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
            derivative = n * (x * p1 - p0) / (x * x - 1)
            step = p1 / derivative
            x -= step
            if abs(step) < 1e-16:
                break
        rule.append((x, 2 / ((1 - x * x) * derivative * derivative)))
    return tuple(rule)


def integrate(
    function: Callable[[float], tuple[float, float]], start: float, end: float, panels: int
) -> tuple[float, float]:
    """The integral of a 2-vector function over ``[start, end]``, composite Gauss-Legendre."""
    rule = gauss_legendre(_NODES)
    width = (end - start) / panels
    half = width / 2
    sum_x = sum_y = 0.0
    for panel in range(panels):
        middle = start + (panel + 0.5) * width
        for node, weight in rule:
            fx, fy = function(middle + half * node)
            sum_x += weight * fx
            sum_y += weight * fy
    return sum_x * half, sum_y * half


def _panels(turn: float) -> int:
    bend = abs(turn)
    if not bend < _MAX_PANELS * _PANEL_TURN:  # also a turn that overflowed to inf or nan
        return _MAX_PANELS
    return max(1, math.ceil(bend / _PANEL_TURN))


class Record:
    """One ``geometry`` record: a start pose, a start s and a length. Treated as immutable.

    Plain slotted classes, not frozen dataclasses: making the six dataclasses cost 4 ms
    of every lint run that evaluates a switch, a third of a small map's rules (measured
    with ``-X importtime``)."""

    __slots__ = ("hdg", "length", "s", "x", "y")
    _fields: ClassVar[tuple[str, ...]] = ("s", "x", "y", "hdg", "length")

    def __init__(self, s: float, x: float, y: float, hdg: float, length: float) -> None:
        self.s, self.x, self.y, self.hdg, self.length = s, x, y, hdg, length

    def _values(self) -> tuple[Any, ...]:
        return tuple(getattr(self, name) for name in self._fields)

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and self._values() == other._values()

    def __hash__(self) -> int:
        return hash((type(self), self._values()))

    def __repr__(self) -> str:
        values = ", ".join(f"{name}={getattr(self, name)!r}" for name in self._fields)
        return f"{type(self).__name__}({values})"

    def local(self, ds: float) -> Pose:
        """The pose at ``ds`` in the record's own frame (start at the origin, heading +x)."""
        return Pose(ds, 0.0, 0.0)

    def max_curvature(self) -> float | None:
        """A bound on |curvature| along the record; ``None`` when not known in closed form."""
        return 0.0

    def pose_at(self, ds: float) -> Pose:
        u, v, turn = self.local(ds)
        cos_h, sin_h = math.cos(self.hdg), math.sin(self.hdg)
        return Pose(self.x + u * cos_h - v * sin_h, self.y + u * sin_h + v * cos_h, self.hdg + turn)

    @property
    def end(self) -> Pose:
        return self.pose_at(self.length)


class Line(Record):
    __slots__ = ()

    def pose_at(self, ds: float) -> Pose:
        # the general form's arithmetic without its local pose (v = 0, no turn), so that
        # even the sign of a zero is the same
        cos_h, sin_h = math.cos(self.hdg), math.sin(self.hdg)
        return Pose(
            self.x + ds * cos_h - 0.0 * sin_h, self.y + ds * sin_h + 0.0 * cos_h, self.hdg + 0.0
        )


class Arc(Record):
    __slots__ = ("curvature",)
    _fields = (*Record._fields, "curvature")

    def __init__(
        self, s: float, x: float, y: float, hdg: float, length: float, curvature: float
    ) -> None:
        super().__init__(s, x, y, hdg, length)
        self.curvature = curvature

    def local(self, ds: float) -> Pose:
        k = self.curvature
        turn = k * ds
        if abs(turn) < 1e-9:  # the closed form loses its digits: a second-order expansion
            return Pose(ds, 0.5 * k * ds * ds, turn)
        return Pose(math.sin(turn) / k, (1 - math.cos(turn)) / k, turn)

    def max_curvature(self) -> float | None:
        return abs(self.curvature)


class Spiral(Record):
    """A clothoid: curvature linear in s from ``curv_start`` to ``curv_end``."""

    __slots__ = ("curv_end", "curv_start")
    _fields = (*Record._fields, "curv_start", "curv_end")

    def __init__(
        self,
        s: float,
        x: float,
        y: float,
        hdg: float,
        length: float,
        curv_start: float,
        curv_end: float,
    ) -> None:
        super().__init__(s, x, y, hdg, length)
        self.curv_start, self.curv_end = curv_start, curv_end

    def local(self, ds: float) -> Pose:
        k0 = self.curv_start
        rate = (self.curv_end - k0) / self.length if self.length > 0 else 0.0

        def phase(u: float) -> float:
            return u * (k0 + 0.5 * rate * u)

        def direction(u: float) -> tuple[float, float]:
            angle = phase(u)
            return math.cos(angle), math.sin(angle)

        turn_bound = max(abs(k0), abs(k0 + rate * ds)) * abs(ds)
        u, v = integrate(direction, 0.0, ds, _panels(turn_bound)) if ds else (0.0, 0.0)
        return Pose(u, v, phase(ds))

    def max_curvature(self) -> float | None:
        return max(abs(self.curv_start), abs(self.curv_end))


class Poly3(Record):
    """``v = a + b·u + c·u² + d·u³`` in the record's frame, ``ds`` the arc length along it."""

    __slots__ = ("a", "b", "c", "d")
    _fields = (*Record._fields, "a", "b", "c", "d")

    def __init__(
        self,
        s: float,
        x: float,
        y: float,
        hdg: float,
        length: float,
        a: float,
        b: float,
        c: float,
        d: float,
    ) -> None:
        super().__init__(s, x, y, hdg, length)
        self.a, self.b, self.c, self.d = a, b, c, d

    def slope(self, u: float) -> float:
        return self.b + u * (2 * self.c + 3 * self.d * u)

    def arc_length(self, u: float) -> float:
        def speed(x: float) -> tuple[float, float]:
            return math.hypot(1.0, self.slope(x)), 0.0

        bend = abs(math.atan(self.slope(u)) - math.atan(self.slope(0.0)))
        return integrate(speed, 0.0, u, 4 + _panels(bend))[0] if u else 0.0

    def local(self, ds: float) -> Pose:
        u = ds  # the arc length is at least u: Newton's method comes down from above
        for _ in range(50):
            step = (self.arc_length(u) - ds) / math.hypot(1.0, self.slope(u))
            u -= step
            if abs(step) < 1e-10:
                break
        v = self.a + u * (self.b + u * (self.c + u * self.d))
        return Pose(u, v, math.atan(self.slope(u)))

    def max_curvature(self) -> float | None:
        return None


class ParamPoly3(Record):
    """``u(p)``, ``v(p)`` cubics; ``p`` runs over ``[0, length]`` (``arcLength``) or
    ``[0, 1]`` (``normalized``), linearly in s, as OpenDRIVE tools evaluate it."""

    __slots__ = ("normalized", "u", "v")
    _fields = (*Record._fields, "u", "v", "normalized")

    def __init__(
        self,
        s: float,
        x: float,
        y: float,
        hdg: float,
        length: float,
        u: tuple[float, float, float, float],
        v: tuple[float, float, float, float],
        normalized: bool,
    ) -> None:
        super().__init__(s, x, y, hdg, length)
        self.u, self.v, self.normalized = u, v, normalized

    def local(self, ds: float) -> Pose:
        p = ds / self.length if self.normalized and self.length > 0 else ds
        (au, bu, cu, du), (av, bv, cv, dv) = self.u, self.v
        u = au + p * (bu + p * (cu + p * du))
        v = av + p * (bv + p * (cv + p * dv))
        du_dp = bu + p * (2 * cu + 3 * du * p)
        dv_dp = bv + p * (2 * cv + 3 * dv * p)
        turn = math.atan2(dv_dp, du_dp) if du_dp or dv_dp else 0.0
        return Pose(u, v, turn)

    def max_curvature(self) -> float | None:
        return None
