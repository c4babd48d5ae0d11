"""The radius of rail lanes' centre lines (geometry/curvature.py, TR013) against an
independent computation: the reference curve from closed forms (line, arc, paramPoly3)
or integrated by scipy (a spiral's heading by solve_ivp, a poly3's arc length by
solve_ivp), the lane's centre placed t(s) along its normal with numpy's polynomials,
and the curvature of that offset curve by finite differences of densely sampled points.
Every record type, each with the lane at a constant offset and with an offset that
varies; and random arcs and spirals (hypothesis)."""

from __future__ import annotations

import math
import re
from collections.abc import Callable

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xodrlint.api import lint_bytes
from xodrlint.document.load import load_bytes
from xodrlint.geometry.curvature import LaneCurvature, record_elements
from xodrlint.geometry.tracks import TrackGeometry
from xodrlint.model import build_network

scipy_integrate = pytest.importorskip("scipy.integrate", reason="scipy is a test dependency")

Cubic = tuple[float, float, float, float]
LENGTH = 40.0
#: Points of the dense reference: finite differences over about 0.2 mm.
DENSE = 200_001
CONSTANT: Cubic = (0.0, 0.0, 0.0, 0.0)
#: laneOffset and width of a lane whose centre wanders: t = offset - width / 2 (lane -1).
WANDERING = ((0.5, 0.01, -0.0008, 1.5e-5), (1.5, 0.002, 2e-4, -4e-6))
STEADY = ((0.75, 0.0, 0.0, 0.0), (1.5, 0.0, 0.0, 0.0))


def _attributes(cubic: Cubic) -> str:
    return 'a="{!r}" b="{!r}" c="{!r}" d="{!r}"'.format(*cubic)


def _document(curve: str, lanes: tuple[Cubic, Cubic], length: float = LENGTH) -> bytes:
    offset, width = lanes
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<OpenDRIVE><header revMajor="1" revMinor="7" name="t"/>
  <road name="track" length="{length!r}" id="1" junction="-1">
    <planView>
      <geometry s="0" x="100" y="-50" hdg="0.4" length="{length!r}">{curve}</geometry>
    </planView>
    <lanes>
      <laneOffset s="0" {_attributes(offset)}/>
      <laneSection s="0"><center><lane id="0" type="none" level="false"/></center>
        <right><lane id="-1" type="rail" level="false"><width sOffset="0" {_attributes(width)}/></lane></right>
      </laneSection>
    </lanes>
  </road>
</OpenDRIVE>""".encode()


def _lateral(lanes: tuple[Cubic, Cubic]) -> np.polynomial.Polynomial:
    offset, width = lanes
    return np.polynomial.Polynomial(offset) - np.polynomial.Polynomial(width) / 2


def _offset_curvature(
    x: np.ndarray, y: np.ndarray, heading: np.ndarray, t: np.ndarray, parameter: np.ndarray
) -> np.ndarray:
    """The curvature of the points ``t`` left of (x, y, heading), by finite differences
    in whatever ``parameter`` the points are spaced by (curvature does not depend on it)."""
    px, py = x - t * np.sin(heading), y + t * np.cos(heading)
    dx, dy = np.gradient(px, parameter, edge_order=2), np.gradient(py, parameter, edge_order=2)
    ddx, ddy = np.gradient(dx, parameter, edge_order=2), np.gradient(dy, parameter, edge_order=2)
    return np.asarray(np.abs(dx * ddy - dy * ddx) / (dx * dx + dy * dy) ** 1.5)


def _line(lanes: tuple[Cubic, Cubic]) -> tuple[np.ndarray, np.ndarray]:
    s = np.linspace(0.0, LENGTH, DENSE)
    return s, _offset_curvature(s, 0 * s, 0 * s, _lateral(lanes)(s), s)


def _arc(k: float) -> Callable[[tuple[Cubic, Cubic]], tuple[np.ndarray, np.ndarray]]:
    def dense(lanes: tuple[Cubic, Cubic]) -> tuple[np.ndarray, np.ndarray]:
        s = np.linspace(0.0, LENGTH, DENSE)
        x, y = np.sin(k * s) / k, (1 - np.cos(k * s)) / k
        return s, _offset_curvature(x, y, k * s, _lateral(lanes)(s), s)

    return dense


def _spiral(k0: float, k1: float) -> Callable[[tuple[Cubic, Cubic]], tuple[np.ndarray, np.ndarray]]:
    """The clothoid's points by integrating its heading k0·s + rate·s²/2 with solve_ivp."""
    rate = (k1 - k0) / LENGTH

    def heading(s: np.ndarray) -> np.ndarray:
        return np.asarray(k0 * s + rate * s * s / 2)

    def dense(lanes: tuple[Cubic, Cubic]) -> tuple[np.ndarray, np.ndarray]:
        s = np.linspace(0.0, LENGTH, DENSE)
        solved = scipy_integrate.solve_ivp(
            lambda u, _: [math.cos(k0 * u + rate * u * u / 2), math.sin(k0 * u + rate * u * u / 2)],
            (0.0, LENGTH),
            [0.0, 0.0],
            t_eval=s,
            rtol=1e-12,
            atol=1e-12,
        )
        x, y = solved.y
        return s, _offset_curvature(x, y, heading(s), _lateral(lanes)(s), s)

    return dense


def _poly3(cubic: Cubic) -> Callable[[tuple[Cubic, Cubic]], tuple[np.ndarray, np.ndarray]]:
    """v(u) in the record's frame; s(u) by integrating ds/du = sqrt(1 + v'²) with
    solve_ivp up to the u where s reaches the record's length."""
    v = np.polynomial.Polynomial(cubic)
    slope = v.deriv()

    def dense(lanes: tuple[Cubic, Cubic]) -> tuple[np.ndarray, np.ndarray]:
        reach = scipy_integrate.solve_ivp(
            lambda u, s: [math.hypot(1.0, float(slope(u)))],
            (0.0, LENGTH),
            [0.0],
            events=lambda u, s: s[0] - LENGTH,
            rtol=1e-12,
            atol=1e-12,
        )
        u_end = float(reach.t_events[0][0])
        u = np.linspace(0.0, u_end, DENSE)
        s = scipy_integrate.solve_ivp(
            lambda x, s: [math.hypot(1.0, float(slope(x)))],
            (0.0, u_end),
            [0.0],
            t_eval=u,
            rtol=1e-12,
            atol=1e-12,
        ).y[0]
        curvature = _offset_curvature(u, v(u), np.arctan(slope(u)), _lateral(lanes)(s), u)
        return s, curvature

    return dense


def _param_poly3(
    u_cubic: Cubic, v_cubic: Cubic, normalized: bool
) -> Callable[[tuple[Cubic, Cubic]], tuple[np.ndarray, np.ndarray]]:
    """u(p), v(p) with p running linearly in s (over [0, 1] when normalized)."""
    u, v = np.polynomial.Polynomial(u_cubic), np.polynomial.Polynomial(v_cubic)

    def dense(lanes: tuple[Cubic, Cubic]) -> tuple[np.ndarray, np.ndarray]:
        p = np.linspace(0.0, 1.0 if normalized else LENGTH, DENSE)
        s = p * LENGTH if normalized else p
        heading = np.arctan2(v.deriv()(p), u.deriv()(p))
        return s, _offset_curvature(u(p), v(p), heading, _lateral(lanes)(s), p)

    return dense


RECORDS: dict[str, tuple[str, Callable[[tuple[Cubic, Cubic]], tuple[np.ndarray, np.ndarray]]]] = {
    "line": ("<line/>", _line),
    "arc left": ('<arc curvature="0.03"/>', _arc(0.03)),
    "arc right": ('<arc curvature="-0.045"/>', _arc(-0.045)),
    "spiral through zero": ('<spiral curvStart="-0.02" curvEnd="0.045"/>', _spiral(-0.02, 0.045)),
    "spiral tightening": ('<spiral curvStart="0.01" curvEnd="0.05"/>', _spiral(0.01, 0.05)),
    "poly3": (
        '<poly3 a="0.2" b="0.05" c="0.004" d="-0.0001"/>',
        _poly3((0.2, 0.05, 0.004, -0.0001)),
    ),
    "paramPoly3 normalized": (
        '<paramPoly3 aU="0" bU="38" cU="2" dU="-1.5" aV="0" bV="1" cV="9" dV="-5" pRange="normalized"/>',
        _param_poly3((0.0, 38.0, 2.0, -1.5), (0.0, 1.0, 9.0, -5.0), normalized=True),
    ),
    "paramPoly3 arcLength": (
        '<paramPoly3 aU="0" bU="1" cU="-0.0005" dU="0" aV="0" bV="0" cV="0.012" dV="-0.0002" pRange="arcLength"/>',
        _param_poly3((0.0, 1.0, -0.0005, 0.0), (0.0, 0.0, 0.012, -0.0002), normalized=False),
    ),
}
#: Exact where the lane is at a constant offset from a line, an arc or a spiral.
EXACT = {"line", "arc left", "arc right", "spiral through zero", "spiral tightening"}


def _rule_bend(curve: str, lanes: tuple[Cubic, Cubic]) -> tuple[float, float]:
    """The tightest bend the rule's geometry finds (infinite radius where it finds none)."""
    network = build_network(load_bytes(_document(curve, lanes), "t.xodr").root)
    road = network.roads[0]
    line = network.shared(TrackGeometry).reference_line(road)
    assert line is not None
    found = list(network.shared(LaneCurvature).bends(road, line))
    if not found:
        return math.inf, 0.0
    [bend] = found
    return bend.bend.radius, bend.bend.s


@pytest.mark.parametrize("lanes", [STEADY, WANDERING], ids=["constant t", "varying t"])
@pytest.mark.parametrize("name", sorted(RECORDS))
def test_the_tightest_radius_equals_the_offset_curve_s(
    name: str, lanes: tuple[Cubic, Cubic]
) -> None:
    curve, reference = RECORDS[name]
    s, curvature = reference(lanes)
    tightest = float(np.max(curvature))
    radius, where = _rule_bend(curve, lanes)
    if name == "line" and lanes is STEADY:
        assert radius == math.inf
        return
    true_radius = 1 / tightest
    # the curvature there is what the independent computation finds at that s
    assert 1 / float(np.interp(where, s, curvature)) == pytest.approx(radius, rel=1e-4)
    if name in EXACT and lanes is STEADY:
        assert radius == pytest.approx(true_radius, rel=1e-4)
    else:  # sampled at most 1 m apart: never tighter than the truth, and close to it
        assert true_radius * (1 - 1e-4) <= radius <= true_radius * 1.02


@pytest.mark.parametrize("name", sorted(RECORDS))
def test_tr013_reports_below_the_independent_radius_and_not_above(name: str) -> None:
    curve, reference = RECORDS[name]
    _, curvature = reference(WANDERING)
    true_radius = 1 / float(np.max(curvature))
    data = _document(curve, WANDERING)

    def findings(limit: float) -> list[str]:
        report = lint_bytes(
            data, "t.xodr", select=["TR013"], rule_options={"min-radius-rail": limit}
        )
        assert not report.internal_errors and report.error is None
        return [f.message for f in report.findings]

    assert findings(true_radius * 0.97) == []
    [message] = findings(true_radius * 1.03)
    found = re.search(r"radius of ([0-9.]+) m at s=([0-9.]+)", message)
    assert found is not None
    assert float(found[1]) == pytest.approx(true_radius, rel=0.02)


finite = st.floats(allow_nan=False, allow_infinity=False)


@settings(max_examples=200, deadline=None)
@given(
    k0=st.floats(-0.2, 0.2),
    k1=st.floats(-0.2, 0.2),
    t=st.floats(-6.0, 6.0),
    spiral=st.booleans(),
)
def test_arcs_and_spirals_at_a_constant_offset_against_k_over_1_minus_kt(
    k0: float, k1: float, t: float, spiral: bool
) -> None:
    if not spiral:
        k1 = k0
    curve = (
        f'<spiral curvStart="{k0!r}" curvEnd="{k1!r}"/>' if spiral else f'<arc curvature="{k0!r}"/>'
    )
    lanes = ((t + 0.75, 0.0, 0.0, 0.0), (1.5, 0.0, 0.0, 0.0))  # the lane's centre at t
    radius, where = _rule_bend(curve, lanes)
    s = np.linspace(0.0, LENGTH, 100_001)
    k = k0 + (k1 - k0) * s / LENGTH
    along = 1 - k * t
    if np.any(along <= 0):
        # the lane reaches the centre of curvature: folded where 1 - k t first reaches 0
        assert radius == 0.0
        first = float(s[np.argmax(along <= 0)])
        assert where == pytest.approx(first, abs=LENGTH / 100_000 + 1e-9)
        return
    with np.errstate(divide="ignore", over="ignore"):
        radii = np.where(k != 0, along / np.abs(k), np.inf)
    assert radius == pytest.approx(float(np.min(radii)), rel=1e-9)


def test_each_record_is_reported_on_its_own_geometry_even_when_written_out_of_order() -> None:
    data = b"""<?xml version="1.0" encoding="UTF-8"?>
<OpenDRIVE><header revMajor="1" revMinor="7" name="t"/>
  <road name="track" length="60" id="1" junction="-1">
    <planView>
      <geometry s="40" x="40" y="0" hdg="0" length="20"><arc curvature="0.05"/></geometry>
      <geometry s="0" x="0" y="0" hdg="0" length="20"><arc curvature="-0.02"/></geometry>
      <geometry s="20" x="20" y="0" hdg="0" length="20"><arc curvature="0.1"/></geometry>
    </planView>
    <lanes><laneSection s="0"><center><lane id="0" type="none" level="false"/></center>
      <right><lane id="-1" type="rail" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane></right>
    </laneSection></lanes>
  </road>
</OpenDRIVE>"""
    report = lint_bytes(data, "t.xodr", select=["TR013"])
    # the lane is 0.75 m right: outside the left turns (20.75 m, 10.75 m), fine on the right
    assert [(f.line, f.message.split("radius of ")[1].split(" m")[0]) for f in report.findings] == [
        (5, "20.75"),
        (7, "10.75"),
    ]
    network = build_network(load_bytes(data, "t.xodr").root)
    road = network.roads[0]
    line = network.shared(TrackGeometry).reference_line(road)
    assert line is not None
    elements = record_elements(road, line)
    assert elements is not None and [e.get("s") for e in elements] == ["0", "20", "40"]


@pytest.mark.parametrize(
    "curve",
    [
        '<poly3 a="0" b="0" c="1.7e308" d="-1.7e308"/>',
        '<paramPoly3 aU="0" bU="1e308" cU="1e308" dU="1e308" aV="0" bV="0" cV="0" dV="1e308"/>',
        '<paramPoly3 aU="0" bU="0" cU="0" dU="0" aV="0" bV="0" cV="0" dV="0"/>',
        '<spiral curvStart="-1e308" curvEnd="1e308"/>',
    ],
)
def test_numbers_that_overflow_give_silence(curve: str) -> None:
    for lanes in (STEADY, WANDERING, ((1e300, 1e300, 0.0, 0.0), (1.5, 0.0, 0.0, 0.0))):
        report = lint_bytes(_document(curve, lanes), "t.xodr", select=["TR013"])
        assert not report.internal_errors and report.error is None
        assert report.findings == ()
