"""Elevation and superelevation (geometry/profiles.py) and the rules on them (TR010 to
TR012) against independent computations: dense sampling of each cubic and of its
derivative with numpy, refined by scipy's bounded minimisation, and numpy's polynomial
evaluation at the boundaries. And: values that cannot be read give silence."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from xodrlint.api import lint_bytes
from xodrlint.document.load import load_bytes
from xodrlint.geometry.profiles import Span, VerticalProfiles
from xodrlint.model import build_network

scipy_optimize = pytest.importorskip("scipy.optimize", reason="scipy is a test dependency")

Cubic = tuple[float, float, float, float]

LANES = """<lanes><laneSection s="0"><center><lane id="0" type="none" level="false"/></center>
  <right><lane id="-1" type="{kind}" level="false"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane></right>
</laneSection></lanes>"""


def _document(length: float, elevation: str = "", lateral: str = "", kind: str = "rail") -> bytes:
    profile = f"<elevationProfile>{elevation}</elevationProfile>" if elevation else ""
    roll = f"<lateralProfile>{lateral}</lateralProfile>" if lateral else ""
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<OpenDRIVE><header revMajor="1" revMinor="7" name="t"/>
  <road name="track" length="{length}" id="1" junction="-1">
    <planView><geometry s="0" x="0" y="0" hdg="0" length="{length}"><line/></geometry></planView>
    {profile}{roll}{LANES.format(kind=kind)}
  </road>
</OpenDRIVE>""".encode()


def _entries(tag: str, entries: list[tuple[float, Cubic]]) -> str:
    return "".join(
        f'<{tag} s="{s!r}" a="{a!r}" b="{b!r}" c="{c!r}" d="{d!r}"/>' for s, (a, b, c, d) in entries
    )


def _polynomial(cubic: Cubic) -> np.polynomial.Polynomial:
    return np.polynomial.Polynomial(cubic)


def _dense_extreme(function: np.polynomial.Polynomial, length: float) -> tuple[float, float]:
    """The largest |function| on [0, length] and where: a dense grid, then scipy's bounded
    minimisation around the best grid point (an interior extreme lies between two)."""
    grid = np.linspace(0.0, length, 20001)
    values = np.abs(function(grid))
    best = int(np.argmax(values))
    low, high = grid[max(best - 1, 0)], grid[min(best + 1, len(grid) - 1)]
    if high > low:
        refined = scipy_optimize.minimize_scalar(
            lambda x: -abs(float(function(x))),
            bounds=(low, high),
            method="bounded",
            options={"xatol": 1e-12},
        )
        if -refined.fun > values[best]:
            return float(-refined.fun), float(refined.x)
    return float(values[best]), float(grid[best])


def _span(cubic: Cubic, length: float) -> Span:
    return Span(None, 0.0, length, *cubic)  # type: ignore[arg-type]  # no element needed


coefficient = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
cubics = st.tuples(
    st.floats(-50, 50, allow_nan=False),
    coefficient.map(lambda v: v / 10),
    coefficient.map(lambda v: v / 1_000),
    coefficient.map(lambda v: v / 100_000),
)


@settings(max_examples=300, deadline=None)
@given(cubic=cubics, length=st.floats(0.5, 400.0))
def test_steepest_gradient_equals_dense_sampling(cubic: Cubic, length: float) -> None:
    steepest = _span(cubic, length).steepest()
    assert steepest is not None
    expected, _ = _dense_extreme(_polynomial(cubic).deriv(), length)
    assert abs(steepest[0]) == pytest.approx(expected, rel=1e-9, abs=1e-12)
    assert abs(float(_polynomial(cubic).deriv()(steepest[1]))) == pytest.approx(
        abs(steepest[0]), rel=1e-9, abs=1e-12
    )


@settings(max_examples=300, deadline=None)
@given(cubic=cubics, length=st.floats(0.5, 400.0))
def test_largest_value_equals_dense_sampling(cubic: Cubic, length: float) -> None:
    largest = _span(cubic, length).largest()
    assert largest is not None
    expected, _ = _dense_extreme(_polynomial(cubic), length)
    assert abs(largest[0]) == pytest.approx(expected, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize(
    ("cubic", "length", "where"),
    [
        # the gradient 0.012x - 0.0003x² is 0 at both ends: its vertex, x=20, is 0.12
        ((0.0, 0.0, 0.006, -0.0001), 40.0, 20.0),
        # the gradient -0.05 + 0.01x - 0.0001x² is steepest inside: x=50 gives 0.2
        ((1.0, -0.05, 0.005, -0.0001 / 3), 80.0, 50.0),
    ],
)
def test_an_interior_vertex_of_the_gradient_is_found(
    cubic: Cubic, length: float, where: float
) -> None:
    steepest = _span(cubic, length).steepest()
    derivative = _polynomial(cubic).deriv()
    ends = max(abs(derivative(0.0)), abs(derivative(length)))
    assert steepest is not None and steepest[1] == pytest.approx(where)
    assert abs(steepest[0]) > ends + 0.05  # the endpoints alone would miss it
    assert abs(steepest[0]) == pytest.approx(_dense_extreme(derivative, length)[0])


def test_an_interior_maximum_of_the_cant_is_found() -> None:
    cubic = (0.0, 0.04, -0.0008, 0.0)  # 0 at s=0 and s=50, 0.5 rad at s=25
    largest = _span(cubic, 50.0).largest()
    assert largest is not None and largest[1] == pytest.approx(25.0)
    assert largest[0] == pytest.approx(_dense_extreme(_polynomial(cubic), 50.0)[0])


def _reported(data: bytes, code: str, **options: float) -> list[str]:
    report = lint_bytes(data, "t.xodr", select=[code], rule_options=options)
    assert not report.internal_errors and report.error is None
    return [f.message for f in report.findings]


@settings(max_examples=40, deadline=None)
@given(cubic=cubics, length=st.floats(5.0, 300.0))
def test_tr011_reports_the_gradient_dense_sampling_finds(cubic: Cubic, length: float) -> None:
    expected, _ = _dense_extreme(_polynomial(cubic).deriv(), length)
    assume(expected > 1e-6)
    data = _document(length, elevation=_entries("elevation", [(0.0, cubic)]))
    # a limit just below the steepest gradient is exceeded, one just above it is not
    below = _reported(data, "TR011", **{"max-gradient-rail": expected * 0.999 - 1e-8})
    above = _reported(data, "TR011", **{"max-gradient-rail": expected * 1.001 + 1e-8})
    assert above == [] and len(below) == 1
    found = re.search(r"gradient of ([0-9.e-]+) at s=", below[0])
    # the message gives four decimals (more only where needed not to read as the limit)
    assert found is not None and float(found[1]) == pytest.approx(expected, rel=1e-3, abs=6e-5)


@settings(max_examples=40, deadline=None)
@given(cubic=cubics, length=st.floats(5.0, 300.0))
def test_tr012_reports_the_angle_dense_sampling_finds(cubic: Cubic, length: float) -> None:
    cubic = (cubic[0] / 100, *cubic[1:])  # angles of a few tenths of a radian
    expected, _ = _dense_extreme(_polynomial(cubic), length)
    assume(expected > 1e-6)
    data = _document(length, lateral=_entries("superelevation", [(0.0, cubic)]))
    below = _reported(data, "TR012", **{"max-cant": expected * 0.999 - 1e-8})
    above = _reported(data, "TR012", **{"max-cant": expected * 1.001 + 1e-8})
    assert above == [] and len(below) == 1


@settings(max_examples=60, deadline=None)
@given(
    first=cubics,
    second=cubics,
    boundary=st.floats(1.0, 100.0),
    length=st.floats(101.0, 300.0),
)
def test_elevation_at_and_the_step_equal_numpy(
    first: Cubic, second: Cubic, boundary: float, length: float
) -> None:
    entries = [(0.0, first), (boundary, second)]
    data = _document(length, elevation=_entries("elevation", entries))
    doc = load_bytes(data, "t.xodr")
    network = build_network(doc.root)
    road = network.roads[0]
    profiles = network.shared(VerticalProfiles)
    for s in (0.0, boundary / 3, boundary - 1e-3):
        assert profiles.elevation_at(road, s) == pytest.approx(float(_polynomial(first)(s)))
    for s in (boundary, (boundary + length) / 2, length):
        expected = float(_polynomial(second)(s - boundary))
        assert profiles.elevation_at(road, s) == pytest.approx(expected)  # the later entry
    [step] = profiles.elevation(road).steps()
    assert step.before == pytest.approx(float(_polynomial(first)(boundary)))
    assert step.after == second[0]
    size = abs(step.after - step.before)
    findings = _reported(data, "TR010", **{"elevation-tolerance": 0.05})
    assert len(findings) == (1 if size > 0.05 + 1e-6 else 0)


def test_elevation_at_without_entries_is_zero_and_before_the_first_unknown() -> None:
    flat = build_network(load_bytes(_document(100.0), "t.xodr").root)
    assert flat.shared(VerticalProfiles).elevation_at(flat.roads[0], 50.0) == 0.0
    late = _document(100.0, elevation=_entries("elevation", [(10.0, (1.0, 0.0, 0.0, 0.0))]))
    network = build_network(load_bytes(late, "t.xodr").root)
    profiles = network.shared(VerticalProfiles)
    assert profiles.elevation_at(network.roads[0], 5.0) is None
    assert profiles.elevation_at(network.roads[0], 10.0) == 1.0
    assert profiles.elevation_at(network.roads[0], math.nan) is None


_BAD_VALUES = ["", "abc", "NaN", "INF", "-INF", "1e999"]


@pytest.mark.parametrize("attribute", ["s", "a", "b", "c", "d"])
@pytest.mark.parametrize("value", _BAD_VALUES)
def test_an_unreadable_entry_gives_silence_there(attribute: str, value: str) -> None:
    # steep and stepping everywhere: only what involves the bad entry goes unjudged
    good = '<{tag} s="0" a="0" b="0.2" c="0" d="0"/>'
    bad = '<{tag} s="50" a="3" b="0.5" c="0" d="0"/>'
    bad = bad.replace(f' {attribute}="', f' {attribute}="{value}" old-{attribute}="')
    if value == "":
        bad = re.sub(f' {attribute}="" old-{attribute}="[^"]*"', "", bad)
    entries = good + bad
    elevation = entries.format(tag="elevation")
    lateral = entries.format(tag="superelevation").replace('b="0.2"', 'b="0.01"')
    data = _document(100.0, elevation=elevation, lateral=lateral)
    report = lint_bytes(data, "t.xodr", select=["TR010", "TR011", "TR012"])
    assert not report.internal_errors and report.error is None
    found = sorted((f.code, f.line) for f in report.findings)
    lines = data.decode().splitlines()
    first_line = next(i for i, line in enumerate(lines, 1) if "<elevation " in line)
    # the first entry's gradient stands where its end (the bad entry's s) is readable
    expected = [] if attribute == "s" else [("TR011", first_line)]
    if attribute != "s":
        expected.append(("TR012", first_line))  # 0.01·50 = 0.5 rad before the bad entry
    assert found == sorted(expected)


def test_unreadable_entries_are_listed_in_document_order_and_tracks_with_entries_once() -> None:
    from xodrlint.document.load import load_bytes
    from xodrlint.geometry.profiles import VerticalProfiles
    from xodrlint.model import build_network

    lane = (
        '<lanes><laneSection s="0"><right><lane id="-1" type="rail" level="false">'
        '<width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes>'
    )
    entries = (
        '<elevation s="50" a="0" b="x" c="0" d="0"/><elevation s="0" a="0" b="0" c="0" d="0"/>'
        '<elevation s="20" a="NaN" b="0" c="0" d="0"/>'
    )
    document = (
        '<OpenDRIVE><header revMajor="1" revMinor="7"/>'
        f'<road id="1" length="100"><elevationProfile>{entries}</elevationProfile>{lane}</road>'
        f'<road id="2" length="100">{lane}</road>'
        f'<road id="3" length="100"><elevationProfile>{entries}</elevationProfile></road>'
        "</OpenDRIVE>"
    )
    network = build_network(load_bytes(document.encode(), "v.xodr").root)
    profiles = network.shared(VerticalProfiles)
    tracks = profiles.tracks(network)
    assert [road.id for road, _, _ in tracks] == ["1"]  # a track with entries; no road
    assert profiles.tracks(network) is tracks
    _, elevation, superelevation = tracks[0]
    assert [entry.s for entry in elevation.entries] == [0.0, 20.0, 50.0]  # by s
    assert [entry.element.get("s") for entry in elevation.unreadable] == ["50", "20"]
    assert superelevation.unreadable == ()
