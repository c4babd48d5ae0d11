"""A track's own plan view (issue 28): TR008 judges where each record ends against where
the next one starts, TR009 the road's length against the plan view's, and TR014 says why
a track is not judged at all.

The record ends are checked against an independent computation with scipy (quadrature of
the heading's cosine and sine, a root finder for the poly3's arc length), for every kind
of record, and TR008's verdict at its tolerances to a few micrometres."""

from __future__ import annotations

import math
from collections.abc import Callable

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree

from tests.conftest import REPO
from xodrlint.api import lint_bytes
from xodrlint.document.load import load_bytes
from xodrlint.findings import FileReport
from xodrlint.geometry.tracks import TrackGeometry
from xodrlint.model import build_network

scipy_integrate = pytest.importorskip("scipy.integrate", reason="scipy is a test dependency")
scipy_optimize = pytest.importorskip("scipy.optimize")

Pose = tuple[float, float, float]
#: Every record starts here; the parameters below keep each one a plausible track.
X0, Y0, H0 = 12.5, -7.25, 0.7
TIGHT = {"epsabs": 1e-13, "epsrel": 1e-13, "limit": 200}

_LANES = """<lanes><laneSection s="0"><center><lane id="0" type="none"/></center>
      <right><lane id="-1" type="rail"><width sOffset="0" a="1.5" b="0" c="0" d="0"/></lane></right>
    </laneSection></lanes>"""


def _document(records: list[str], length: float | str = 1000.0) -> bytes:
    geometry = "\n      ".join(records)
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<OpenDRIVE>
  <header revMajor="1" revMinor="7" name="t"/>
  <road name="track" length="{length}" id="1" junction="-1">
    <planView>
      {geometry}
    </planView>
    {_LANES}
  </road>
</OpenDRIVE>
""".encode()


def _record(s: float, pose: Pose, length: float, curve: str) -> str:
    x, y, hdg = pose
    return (
        f'<geometry s="{s!r}" x="{x!r}" y="{y!r}" hdg="{hdg!r}" length="{length!r}">'
        f"{curve}</geometry>"
    )


# -- the independent computation ------------------------------------------------------------


def _placed(u: float, v: float, turn: float) -> Pose:
    """A pose in a record's own frame (start at the origin, heading +x), placed at X0, Y0, H0."""
    cos_h, sin_h = math.cos(H0), math.sin(H0)
    return X0 + u * cos_h - v * sin_h, Y0 + u * sin_h + v * cos_h, H0 + turn


def _integrated(length: float, turn: Callable[[float], float]) -> Pose:
    """Where a curve of heading ``H0 + turn(s)`` ends after ``length`` metres."""
    u = scipy_integrate.quad(lambda s: math.cos(turn(s)), 0.0, length, **TIGHT)[0]
    v = scipy_integrate.quad(lambda s: math.sin(turn(s)), 0.0, length, **TIGHT)[0]
    return _placed(u, v, turn(length))


def _poly3_at(a: float, b: float, c: float, d: float, length: float) -> Pose:
    """The poly3's pose ``length`` metres along its own arc: u found where the arc length
    ``∫ sqrt(1 + v'(u)²) du`` reaches it."""

    def slope(u: float) -> float:
        return b + 2 * c * u + 3 * d * u * u

    def arc(u: float) -> float:
        return float(scipy_integrate.quad(lambda t: math.hypot(1.0, slope(t)), 0.0, u, **TIGHT)[0])

    u = scipy_optimize.brentq(lambda u: arc(u) - length, 0.0, length, xtol=1e-14) if length else 0.0
    return _placed(u, a + u * (b + u * (c + u * d)), math.atan(slope(u)))


def _param_poly3_at(u: tuple[float, ...], v: tuple[float, ...], p: float) -> Pose:
    """The paramPoly3's pose at parameter ``p``: its point by integrating its derivative
    from its start (aU, aV), its heading from the derivative's direction."""

    def derivative(q: float, coefficients: tuple[float, ...]) -> float:
        return coefficients[1] + 2 * coefficients[2] * q + 3 * coefficients[3] * q * q

    along = u[0] + scipy_integrate.quad(lambda q: derivative(q, u), 0.0, p, **TIGHT)[0]
    across = v[0] + scipy_integrate.quad(lambda q: derivative(q, v), 0.0, p, **TIGHT)[0]
    return _placed(along, across, math.atan2(derivative(p, v), derivative(p, u)))


_PN = ((0.2, 30.0, 2.0, -1.0), (-0.1, 1.0, 4.0, -1.5))
_PA = ((0.0, 1.0, 0.001, 0.0), (0.1, 0.02, 0.003, -5e-5))


class Kind:
    """A record of one kind: its curve element, its length, and its true start and end."""

    def __init__(self, curve: str, length: float, at: Callable[[float], Pose]) -> None:
        self.curve, self.length, self.at = curve, length, at

    @property
    def start(self) -> Pose:
        return self.at(0.0)

    @property
    def end(self) -> Pose:
        return self.at(self.length)


KINDS = {
    "line": Kind("<line/>", 40.0, lambda s: _integrated(s, lambda _: 0.0)),
    "arc": Kind('<arc curvature="-0.02"/>', 60.0, lambda s: _integrated(s, lambda t: -0.02 * t)),
    "spiral": Kind(
        '<spiral curvStart="0.004" curvEnd="-0.03"/>',
        80.0,
        lambda s: _integrated(s, lambda t: 0.004 * t - 0.034 / (2 * 80.0) * t * t),
    ),
    "poly3": Kind(
        '<poly3 a="0.3" b="0.05" c="0.002" d="-4e-05"/>',
        30.0,
        lambda s: _poly3_at(0.3, 0.05, 0.002, -4e-5, s),
    ),
    "paramPoly3 normalized": Kind(
        '<paramPoly3 aU="0.2" bU="30" cU="2" dU="-1" aV="-0.1" bV="1" cV="4" dV="-1.5" '
        'pRange="normalized"/>',
        35.0,
        lambda s: _param_poly3_at(*_PN, s / 35.0),
    ),
    "paramPoly3 arcLength": Kind(
        '<paramPoly3 aU="0" bU="1" cU="0.001" dU="0" aV="0.1" bV="0.02" cV="0.003" '
        'dV="-5e-05" pRange="arcLength"/>',
        25.0,
        lambda s: _param_poly3_at(*_PA, s),
    ),
}


# -- TR008 against it -----------------------------------------------------------------------


def _aside(pose: Pose, gap: float, turn: float) -> Pose:
    """``pose`` moved ``gap`` metres to its left and turned by ``turn``."""
    x, y, hdg = pose
    return x - gap * math.sin(hdg), y + gap * math.cos(hdg), hdg + turn


def _followed(kind: Kind, gap: float, turn: float) -> bytes:
    """A record of ``kind``, then a line from ``gap`` metres beside its true end."""
    first = _record(0.0, (X0, Y0, H0), kind.length, kind.curve)
    then = _record(kind.length, _aside(kind.end, gap, turn), 10.0, "<line/>")
    return _document([first, then], kind.length + 10.0)


def _preceded(kind: Kind, gap: float, turn: float) -> bytes:
    """A line ending ``gap`` metres beside the true start of a record of ``kind``."""
    x, y, hdg = _aside(kind.start, gap, turn)
    line = _record(0.0, (x - 10.0 * math.cos(hdg), y - 10.0 * math.sin(hdg), hdg), 10.0, "<line/>")
    after = _record(10.0, (X0, Y0, H0), kind.length, kind.curve)
    return _document([line, after], kind.length + 10.0)


def _tr008(data: bytes) -> list[str]:
    report = lint_bytes(data, "t.xodr", select=["TR008"])
    assert not report.internal_errors
    return [f.message for f in report.findings]


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_every_record_ends_and_starts_where_scipy_says(kind: str) -> None:
    record = KINDS[kind]
    doc = load_bytes(_followed(record, 0.0, 0.0), "t.xodr")
    network = build_network(doc.root)
    view = network.shared(TrackGeometry).plan_view(network.roads[0])
    assert view.problems == ()
    for found, expected in zip(view.ends[0], (record.start, record.end), strict=True):
        assert math.hypot(found.x - expected[0], found.y - expected[1]) < 1e-9, (found, expected)
        assert abs(math.remainder(found.hdg - expected[2], math.tau)) < 1e-9


#: Just outside and just inside: the tolerance (0.1 m) allows 1e-6 m of rounding.
GAPS = [(0.1 + 3e-6, True), (0.1 - 3e-6, False), (0.0, False)]
#: The angle (5 degrees) allows 1e-9 rad.
TURNS = [(math.radians(5) + 1e-7, True), (-math.radians(5) - 1e-7, True)]
TURNS += [(math.radians(5) - 1e-7, False), (math.tau - math.radians(5) + 1e-7, False)]


@pytest.mark.parametrize("kind", sorted(KINDS))
@pytest.mark.parametrize(("gap", "reported"), GAPS)
@pytest.mark.parametrize("where", ["end", "start"])
def test_tr008_judges_the_gap_at_every_kind_of_record_to_a_micrometre(
    kind: str, gap: float, reported: bool, where: str
) -> None:
    build = _followed if where == "end" else _preceded
    messages = _tr008(build(KINDS[kind], gap, 0.0))
    assert len(messages) == int(reported), messages
    if reported:
        # the gap it names is the true one, to the micrometre it writes
        assert f" starts {gap:.6f} m away from the end of the geometry at s=" in messages[0]


@pytest.mark.parametrize("kind", sorted(KINDS))
@pytest.mark.parametrize(("turn", "reported"), TURNS)
def test_tr008_judges_the_angle_at_every_kind_of_record(
    kind: str, turn: float, reported: bool
) -> None:
    messages = _tr008(_followed(KINDS[kind], 0.0, turn))
    assert len(messages) == int(reported), messages
    if reported:
        assert " at 5.00001 degrees to the end " in messages[0]


def test_a_gap_and_a_kink_at_one_boundary_are_one_finding_that_says_both() -> None:
    line = KINDS["line"]
    [message] = _tr008(_followed(line, 0.5, 0.2))
    assert (
        "starts 0.5 m away from and at 11.46 degrees to the end of the geometry at s=0" in message
    )
    end = line.end
    assert f"heading {math.degrees(H0 + 0.2):.2f} degrees and (" in message
    assert f"({end[0]:.3f}, {end[1]:.3f}) heading {math.degrees(H0):.2f} degrees)" in message


def test_the_options_are_the_joint_rules_options() -> None:
    from xodrlint.rules.tracks import tr001, tr002, tr008

    assert tr008.track_plan_view_discontinuous.meta.options == (tr001.TOLERANCE, tr002.ANGLE)
    data = _followed(KINDS["arc"], 0.15, 0.1)  # 0.15 m and 5.73 degrees
    assert _tr008(data)
    wider = {"link-tolerance": 0.2, "link-angle": 6}
    assert lint_bytes(data, "t.xodr", select=["TR008"], rule_options=wider).findings == ()


# -- TR009 --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("length", "expected"),
    [
        ("90.0101", "has length 90.0101, but its plan view ends at s=90 "),
        ("89.99", None),
        ("INF", "has length 'INF', but its plan view ends at s=90 "),
        ("-1e999", "has length '-1e999', but its plan view ends at s=90 "),
        ("ninety", None),  # no xs:double: the schema's
    ],
)
def test_tr009_compares_the_length_with_the_plan_view_s(length: str, expected: str | None) -> None:
    spiral = KINDS["spiral"]
    records = [
        _record(0.0, (X0, Y0, H0), spiral.length, spiral.curve),
        _record(spiral.length, spiral.end, 10.0, "<line/>"),
    ]
    report = lint_bytes(_document(records, length), "t.xodr", select=["TR008", "TR009"])
    assert [f.message for f in report.findings if expected and expected in f.message] == [
        f.message for f in report.findings
    ]
    assert len(report.findings) == (expected is not None)


# -- TR014: the one predicate ------------------------------------------------------------------

_HOSTILE_NUMBERS = ["0", "1", "-1", "25", "1e-300", "2e9", "1e7", "1e308", "INF", "-INF", "NaN"]
_HOSTILE_NUMBERS += ["1e999", "x", ""]
_CURVES = ["line", "arc", "spiral", "poly3", "paramPoly3", "clothoid", None]
_COEFFICIENTS = {
    "line": (),
    "arc": ("curvature",),
    "spiral": ("curvStart", "curvEnd"),
    "poly3": ("a", "b", "c", "d"),
    "paramPoly3": ("aU", "bU", "cU", "dU", "aV", "bV", "cV", "dV"),
    "clothoid": ("curvature",),
}


@st.composite
def _records(draw: st.DrawFn) -> str:
    """A geometry record of mostly good numbers, some of them hostile or missing."""

    def value(good: str) -> str | None:
        if draw(st.integers(0, 4)):
            return good
        return draw(st.sampled_from([*_HOSTILE_NUMBERS, None]))

    def attributes(pairs: list[tuple[str, str]]) -> str:
        found = [(name, value(good)) for name, good in pairs]
        return " ".join(f'{name}="{text}"' for name, text in found if text is not None)

    s = draw(st.sampled_from(["0", "20", "40"]))
    own = attributes([("s", s), ("x", "1"), ("y", "2"), ("hdg", "0.5"), ("length", "20")])
    tag = draw(st.sampled_from(_CURVES))
    if tag is None:
        return f"<geometry {own}/>"
    coefficients = attributes([(name, "0.01") for name in _COEFFICIENTS[tag]])
    range_ = draw(st.sampled_from(["", ' pRange="arcLength"', ' pRange="metres"']))
    return f"<geometry {own}><{tag} {coefficients}{range_}/></geometry>"


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_records(), max_size=4), st.sampled_from(["60", "INF", "x", ""]))
def test_tr014_reports_exactly_the_tracks_the_geometry_rules_give_up_on(
    records: list[str], length: str
) -> None:
    data = _document(records, length).replace(b' length=""', b"")
    report = lint_bytes(data, "t.xodr", select=["TR008", "TR009", "TR014"])
    assert not report.internal_errors and report.error is None
    network = build_network(load_bytes(data, "t.xodr").root)
    road = network.roads[0]
    gives_up = network.shared(TrackGeometry).reference_line(road) is None
    codes = [f.code for f in report.findings]
    assert ("TR014" in codes) == gives_up, (codes, data.decode())
    if gives_up:  # and then it alone speaks, once a record (or on the road)
        assert set(codes) == {"TR014"}
        xpaths = [f.xpath for f in report.findings]
        assert len(set(xpaths)) == len(xpaths)
    assert all("Traceback" not in f.message for f in report.findings)


_SWITCH_AND_JOINT = (
    REPO / "rules" / "families" / "track-geometry" / "invalid_unreadable_plan_views.xodr"
)


def _lint(data: bytes) -> FileReport:
    return lint_bytes(data, "t.xodr", select=["SW", "TR"])


def test_tr014_silences_the_rules_that_would_judge_the_same_tracks() -> None:
    # the family case with its unreadable numbers made readable: the rules TR014 silenced
    # speak: the switch point 2 m off, the joint 0.5 m off (TR001, which silences TR002 on
    # its 20 degrees), the side track's gap and length, the onward track's length
    text = _SWITCH_AND_JOINT.read_bytes()
    silenced = _lint(text)
    readable = _lint(text.replace(b'curvEnd="NaN"', b'curvEnd="0"').replace(b'x="INF"', b'x="100"'))
    assert sorted({f.code for f in silenced.findings}) == ["TR008", "TR009", "TR014"]
    assert sorted(f.code for f in readable.findings) == [
        "SW011", "TR001", "TR008", "TR008", "TR009", "TR009", "TR009"
    ]  # fmt: skip


def test_tr014_names_each_value_as_written() -> None:
    path = REPO / "rules" / "TR014" / "invalid_every_reason.xodr"
    report = lint_bytes(path.read_bytes(), path.name, select=["TR014"])
    messages = "\n".join(f.message for f in report.findings)
    for fragment in [
        "track '1', geometry at s=0 lacks a finite number in x ('INF');",
        "in hdg ('north'); arc lacks a finite number in curvature ('1e999');",
        "track '3', geometry at s=60 lacks a finite number in length (missing);",
        "track '5', geometry at s=0 has length '0', not above 0;",
        "geometry at s=0 starts 1e9 m or more from the origin: x ('2e9'); geometry has hdg '1e7'",
        "paramPoly3 has pRange 'metres'",
        "track '12': road has no planView geometry;",
    ]:
        assert fragment in messages
    assert messages.count("so its switch points, joints, continuity, length") == len(
        report.findings
    )
    path = REPO / "rules" / "TR014" / "invalid_profile_entries.xodr"
    report = lint_bytes(path.read_bytes(), path.name, select=["TR014"])
    assert [f.message for f in report.findings] == [
        "track '1', elevation at s=40: lacks a finite number in a ('NaN'); its gradient and "
        "elevation steps are not judged there",
        "track '1', elevation 3: lacks a finite number in s ('1e999'), b ('INF'), d (missing); "
        "its gradient and elevation steps are not judged there",
        "track '1', superelevation at s=50: lacks a finite number in b ('steep'), d ('-INF'); "
        "its cant is not judged there",
    ]


def test_a_record_with_several_faults_is_reported_once_naming_them_all() -> None:
    record = '<geometry s="0" x="0" y="0" hdg="0"><spiral curvStart="NaN" curvEnd="0"/></geometry>'
    report = lint_bytes(_document([record], "INF"), "t.xodr", select=["TR"])
    [finding] = report.findings
    assert finding.code == "TR014"
    assert "lacks a finite number in length (missing); spiral lacks a finite number in " in (
        finding.message
    )


def test_the_reasons_are_the_map_s_too() -> None:
    # one reading of a record: what the map lists as not drawn is what TR014 says
    from xodrlint.geometry import reference_line

    road = etree.fromstring(
        '<road id="1"><planView><geometry s="0" x="INF" y="0" hdg="0" length="5"><line/>'
        "</geometry></planView></road>"
    )
    [problem] = reference_line(road).problems
    report = lint_bytes(
        _document(['<geometry s="0" x="INF" y="0" hdg="0" length="5"><line/></geometry>']),
        "t.xodr",
        select=["TR014"],
    )
    assert problem.message.removeprefix("geometry ") in report.findings[0].message
