"""The XSD 1.1 fast path (libxml2 on the XSD 1.0 form, plus the 1.1-only checks) finds what
full XSD 1.1 validation (xmlschema) finds: on the corpus, on files broken against every
assertion and type alternative of the official schemas, and on the rule cases; and its
cache of derived schema forms is written once, keyed by content, and optional."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import threading
from collections.abc import Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree
from typer.testing import CliRunner

from tests.conftest import CORPUS_RAIL, REPO, SHARED, SHARED_SCHEMAS, needs_shared, record_forks
from xodrlint.cli import app
from xodrlint.concurrency import background
from xodrlint.document.load import Document, load_bytes
from xodrlint.findings import Hit
from xodrlint.validation.libxml2 import Libxml2Validator
from xodrlint.validation.sets import SchemaFinder, SchemaLoadError, SchemaSet
from xodrlint.validation.source import XS
from xodrlint.validation.validators import SchemaValidators
from xodrlint.validation.xsd11 import fast as xsd11_fast
from xodrlint.validation.xsd11 import translation as translation_module
from xodrlint.validation.xsd11.alternatives import (
    XSI,
    XSI_TYPE,
    holds_a_site,
    needs_xsd11_reading,
)
from xodrlint.validation.xsd11.fast import FastXsd11Validator, xsd11_validator
from xodrlint.validation.xsd11.form import CACHE_DIR_ENV, derive_xsd10, xsd10_form
from xodrlint.validation.xsd11.full import Xsd11Validator
from xodrlint.validation.xsd11.selectors import Selectors
from xodrlint.validation.xsd11.wording import assertion_message

XSD11_SETS = ("1.8.0", "1.8.1", "1.9.0")
LARGE = SHARED / "corpus" / "large"
#: The rule cases: rules/<CODE>/*.xodr and rules/families/<pack>/*.xodr.
RULE_CASES = sorted(REPO.glob("rules/*/*.xodr")) + sorted(REPO.glob("rules/families/*/*.xodr"))

pytestmark = needs_shared


@pytest.fixture(autouse=True)
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Every test derives into its own cache folder, never the user's."""
    folder = tmp_path / "cache"
    monkeypatch.setenv(CACHE_DIR_ENV, str(folder))
    monkeypatch.delenv(xsd11_fast.MODE_ENV, raising=False)
    return folder


@dataclass(frozen=True)
class Pair:
    full: Xsd11Validator
    fast: FastXsd11Validator


@pytest.fixture(scope="module")
def pairs(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, Pair]]:
    """Both validators for every XSD 1.1 set, built once for the module."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv(CACHE_DIR_ENV, str(tmp_path_factory.mktemp("cache")))
        patch.delenv(xsd11_fast.MODE_ENV, raising=False)
        built = {}
        for version in XSD11_SETS:
            entry = _entry(version)
            fast = xsd11_validator(entry, Libxml2Validator)
            assert isinstance(fast, FastXsd11Validator)
            built[version] = Pair(Xsd11Validator(entry), fast)
        yield built


def _entry(version: str) -> Path:
    return SHARED_SCHEMAS / version / "OpenDRIVE_Core.xsd"


def _as_version(data: bytes, version: str) -> bytes:
    """The file, its header declaring ``version`` (major.minor)."""
    major, minor = version.split(".")[:2]
    header = re.search(rb"<header\b[^>]*>", data)
    assert header is not None
    tag = re.sub(rb'revMajor="[^"]*"', f'revMajor="{major}"'.encode(), header[0])
    tag = re.sub(rb'revMinor="[^"]*"', f'revMinor="{minor}"'.encode(), tag)
    return data[: header.start()] + tag + data[header.end() :]


Seen = tuple[int, str, str]


def _seen(doc: Document, hits: list[Hit]) -> tuple[set[Seen], set[tuple[Seen, str]]]:
    """What the engine makes of the hits: (line, XPath, kind); and with the message for
    what both paths word alike (keys, keyrefs, assertions)."""
    found: set[Seen] = set()
    worded: set[tuple[Seen, str]] = set()
    for hit in hits:
        if hit.element is not None:
            where = (doc.line_of(hit.element), doc.xpath_of(hit.element), hit.kind)
        else:
            where = (hit.line or 1, "/", hit.kind)
        found.add(where)
        if hit.kind in ("keyref", "duplicate") or _is_assertion(hit):
            worded.add((where, hit.message))
    return found, worded


def _is_assertion(hit: Hit) -> bool:
    """Is the hit a failed assertion of an official set, worded as such?"""
    return hit.element is not None and any(
        hit.message == assertion_message(hit.element, test) for test in ALL_ASSERTIONS
    )


def _same_findings(pair: Pair, data: bytes, name: str) -> set[Seen]:
    """Validate with both; assert they agree; return what they found."""
    doc = load_bytes(data, name)
    assert doc.tree is not None, name
    before = etree.tostring(doc.tree)
    fast, fast_worded = _seen(doc, list(pair.fast.hits(doc)))
    assert etree.tostring(doc.tree) == before, "the fast path left the tree changed"
    first, finish, _ = pair.fast.stages(doc)  # as a thread and the caller run it
    assert _seen(doc, finish(first)) == (fast, fast_worded), name
    full, full_worded = _seen(doc, list(pair.full.hits(doc)))
    assert fast == full, (name, sorted(full - fast), sorted(fast - full))
    assert fast_worded == full_worded, name
    return full


# -- (a) the corpus ------------------------------------------------------------------------


@pytest.mark.parametrize("version", XSD11_SETS)
def test_rail_corpus_gives_the_same_findings(pairs: dict[str, Pair], version: str) -> None:
    for path in sorted(CORPUS_RAIL.glob("*.xodr")):
        _same_findings(pairs[version], _as_version(path.read_bytes(), version), path.name)


@pytest.mark.parametrize(
    "name",
    [
        "CARLA_Town03.xodr",  # 2,090 errors, header children out of order
        "SUMO-gen_bs3d_Braunschweig.xodr",  # 69 rail lanes, 1,574 roads
    ],
)
def test_large_maps_declared_1_8_give_the_same_findings(pairs: dict[str, Pair], name: str) -> None:
    # "1.8" is checked against the newest 1.8 set, as the schema finder picks it
    found = _same_findings(pairs["1.8.1"], _as_version((LARGE / name).read_bytes(), "1.8"), name)
    assert (name == "CARLA_Town03.xodr") == bool(found)


# -- (b) a file broken against every assertion and type alternative ------------------------

BASE = """<?xml version="1.0" encoding="UTF-8"?>
<OpenDRIVE>
  <header revMajor="1" revMinor="{minor}" name="mutations"/>
  <road length="100" id="1" junction="-1">
    <planView>
      <geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry>
    </planView>
    {lateral}
    {lanes}
    <objects>{objects}</objects>
    <signals>{signals}</signals>
  </road>
  <road length="10" id="2" junction="10">
    <planView>
      <geometry s="0" x="0" y="0" hdg="0" length="10"><line/></geometry>
    </planView>
    <lanes>
      <laneSection s="0">
        <center><lane id="0" type="none" level="false"/></center>
      </laneSection>
    </lanes>
  </road>
  {junctions}
</OpenDRIVE>
"""
LANES = """<lanes{attrs}>{offset}
      <laneSection s="0"{section}>
        <center><lane id="0" type="none" level="false"/></center>
        <right><lane id="-1" type="driving" level="false">{width}</lane></right>
      </laneSection>
    </lanes>"""
WIDTH = '<width sOffset="0" a="3.5" b="0" c="0" d="0"/>'
BORDER = '<border sOffset="0" a="3.5" b="0" c="0" d="0"/>'
OFFSET = '<laneOffset s="0" a="0" b="0" c="0" d="0"/>'
OBJECT = '<object id="{id}" s="1" t="0" zOffset="0" orientation="none" {attrs}>{body}</object>'
MARKING = '<marking color="white" spaceLength="1" lineLength="1" startOffset="0" stopOffset="0"{side}>{corners}</marking>'
CORNERS = '<cornerReference id="0"/><cornerReference id="1"/>'
OUTLINE = '<outlines><outline id="0"><cornerLocal u="0" v="0" z="0" height="1"/><cornerLocal u="1" v="0" z="0" height="1"/>{markings}</outline></outlines>'
CONNECTION = (
    '<connection id="{id}" incomingRoad="1" contactPoint="start" {attrs}>{body}</connection>'
)
PREDECESSOR = '<predecessor elementType="road" elementId="1" elementS="0" elementDir="+"/>'
SUCCESSOR = '<successor elementType="road" elementId="1" elementS="1" elementDir="+"/>'


def _object(attrs: str, body: str = "") -> dict[str, str]:
    return {"objects": OBJECT.format(id=7, attrs=attrs, body=body)}


def _junction(attrs: str, body: str) -> dict[str, str]:
    return {"junctions": f'<junction id="10" {attrs}>{body}</junction>'}


def _twice(attrs: str, body: str = "") -> str:
    return CONNECTION.format(id=1, attrs=attrs, body=body) * 2


# Each assertion of the official sets, by (complex type, test), and a file part that
# breaks it, with the element it is about. Every assertion of every set must be here.
_PARKING = '<parkingSpace access="all"/>'
ASSERT_CASES: dict[tuple[str, str], tuple[dict[str, str], str]] = {
    ("t_junction_common", "count(connection/@id) = count(distinct-values(connection/@id))"): (
        _junction("", _twice('connectingRoad="2"')),
        ".//junction",
    ),
    ("t_junction_direct", "count(connection/@id) = count(distinct-values(connection/@id))"): (
        _junction('type="direct"', _twice('linkedRoad="2"')),
        ".//junction",
    ),
    ("t_junction_virtual", "count(connection/@id) = count(distinct-values(connection/@id))"): (
        _junction('type="virtual"', _twice('connectingRoad="2"')),
        ".//junction",
    ),
    (
        "t_road_objects_object",
        "not(@radius or @width or @length) or (@radius and not(@width or @length)) or  (@width and @length and not(@radius))",
    ): (_object('type="pole" width="1"'), ".//object"),
    (
        "t_road_objects_object_borders_border",
        "if (@useCompleteOutline) then not(cornerReference) else count(cornerReference) gt 1",
    ): (
        _object(
            'type="barrier"',
            '<borders><border width="0.1" type="concrete" outlineId="0" useCompleteOutline="true">'
            '<cornerReference id="0"/></border></borders>',
        ),
        ".//border",
    ),
    (
        "t_road_objects_object_markings_marking",
        "if (@side) then not(cornerReference) else count(cornerReference) gt 1",
    ): (
        _object(
            'type="roadMark"',
            "<markings>" + MARKING.format(side=' side="left"', corners=CORNERS) + "</markings>",
        ),
        ".//marking",
    ),
    (
        "t_road_objects_object_markings",
        "if (name(parent::*) = 'outline') then not(parent::*/parent::*/parent::*/markings) else true()",
    ): (
        # no instance breaks it either: XSD 1.1 evaluates an assertion on a tree rooted at
        # its element, where parent::* is empty. Both paths run it on what it is meant for
        # (markings of an outline of an object that has markings too) and let it hold.
        _object(
            'type="roadMark"',
            OUTLINE.format(
                markings="<markings>" + MARKING.format(side="", corners=CORNERS) + "</markings>"
            )
            + "<markings>"
            + MARKING.format(side="", corners=CORNERS)
            + "</markings>",
        ),
        "",
    ),
    (
        "t_road_objects_object_markings_marking_cornerReference",
        "if (name(parent::*) = 'object') then count(cornerReference) = 0 else true()",
    ): (
        # the same (and a cornerReference holds no cornerReference): run on a border's
        _object(
            'type="barrier"',
            '<borders><border width="0.1" type="concrete" outlineId="0">'
            + CORNERS
            + "</border></borders>",
        ),
        "",
    ),
    (
        "t_road_lateralProfile",
        "not(exists(crossSectionSurface)) or (not(exists(superelevation)) and not(exists(shape)))",
    ): (
        {
            "lateral": '<lateralProfile><superelevation s="0" a="0" b="0" c="0" d="0"/>'
            '<crossSectionSurface><tOffset><coefficients s="0" a="0" b="0" c="0" d="0"/>'
            "</tOffset></crossSectionSurface></lateralProfile>"
        },
        ".//lateralProfile",
    ),
    (
        "t_road_signals_signal_road",
        "not(@type = 'multiBoard') or (@type = 'multiBoard' and @dynamic = true() and count(./vmsBoard) gt 0 and count(./staticBoard) gt 0)",
    ): (
        # an error for every multiBoard: @dynamic is 'yes' or 'no', never a boolean
        {
            "signals": '<signal id="5" s="1" t="0" zOffset="0" dynamic="yes" orientation="+"'
            ' type="multiBoard" subtype="-1" country="DE"/>'
        },
        ".//signal",
    ),
    (
        "t_road_lanes",
        "if (count(laneOffset) > 0) then count(laneSection//border) = 0 else true()",
    ): ({"lanes": LANES.format(attrs="", offset=OFFSET, section="", width=BORDER)}, ".//lanes"),
    ("t_road_lanes", "if (@layer = 'permanent') then not(laneSection/@length) else true()"): (
        {
            "lanes": LANES.format(
                attrs=' layer="permanent"', offset="", section=' length="10"', width=WIDTH
            )
        },
        ".//lanes",
    ),
}

for _kind, _attrs, _body in [
    ("barrier", 'radius="1"', ""),
    ("building", "", _PARKING),
    ("crosswalk", 'radius="1"', ""),
    ("gantry", 'radius="1"', ""),
    ("obstacle", "", _PARKING),
    ("parkingSpace", 'radius="1"', ""),
    ("pole", "", _PARKING),
    ("roadMark", 'radius="1"', ""),
    ("roadSurface", "", _PARKING),
    ("trafficIsland", "", _PARKING),
    ("tree", "", _PARKING),
    ("vegetation", "", _PARKING),
]:
    # what each kind of object must not have; the test names it first
    ASSERT_CASES["t_road_objects_object", f"if (@type = '{_kind}') then"] = (
        _object(f'type="{_kind}" {_attrs}', _body),
        ".//object",
    )

# Each type alternative of the official sets, by (element, test or '' for the default),
# and a file part an element selecting it breaks only under the type it selects.
ALTERNATIVE_CASES: dict[tuple[str, str], dict[str, str]] = {
    ("junction", "@type='virtual'"): _junction(
        'type="virtual"', CONNECTION.format(id=1, attrs='type="virtual"', body="")
    ),
    ("junction", "@type='direct'"): _junction(
        'type="direct"', CONNECTION.format(id=1, attrs='connectingRoad="2"', body="")
    ),
    ("junction", "@type='crossing'"): _junction(
        'type="crossing"', CONNECTION.format(id=1, attrs='connectingRoad="2"', body="")
    ),
    ("junction", ""): _junction(
        'type="default"',
        CONNECTION.format(id=1, attrs='linkedRoad="2"', body="")
        + '<roadSection id="1" roadId="1" sStart="0" sEnd="1"/>',
    ),
    ("connection", "@type='virtual'"): _junction(
        'type="virtual"',
        CONNECTION.format(id=1, attrs='type="virtual" connectingRoad="2"', body=PREDECESSOR),
    ),
    ("connection", ""): _junction(
        'type="virtual"',
        CONNECTION.format(id=1, attrs='connectingRoad="2"', body=PREDECESSOR + SUCCESSOR),
    ),
    ("segment", "@type='lane'"): _junction(
        "",
        '<boundary><segment type="lane" roadId="1" boundaryLane="-1" sStart="1" sEnd="2"'
        ' contactPoint="start"/></boundary>',
    ),
    ("segment", "@type='joint'"): _junction(
        "",
        '<boundary><segment type="joint" roadId="1" contactPoint="start" jointLaneStart="1"'
        ' boundaryLane="1"/></boundary>',
    ),
    # no default: a segment of no known type keeps its abstract declared type
    ("segment", ""): _junction(
        "", '<boundary><segment roadId="1"/><segment type="x" roadId="1" a="1"/></boundary>'
    ),
}


def _schema_tests(version: str, tag: str) -> set[tuple[str, str]]:
    """(owner, test) of every xs:assert (owner: complex type) or xs:alternative (owner:
    element) in the set's files."""
    found = set()
    for path in (SHARED_SCHEMAS / version).glob("*.xsd"):
        for element in etree.parse(str(path)).iter(f"{{{XS}}}{tag}"):
            owner = next((a for a in element.iterancestors() if a.get("name")), element.getparent())
            assert owner is not None
            found.add((owner.get("name", ""), element.get("test", "")))
    return found


#: The test of every assertion of the official sets.
ALL_ASSERTIONS = (
    {test for version in XSD11_SETS for _, test in _schema_tests(version, "assert")}
    if SHARED.is_dir()
    else set()
)


def _document(version: str, parts: dict[str, str]) -> bytes:
    filled = {"lateral": "", "lanes": LANES.format(attrs="", offset="", section="", width=WIDTH)}
    filled |= {"objects": "", "signals": "", "junctions": ""} | parts
    return BASE.format(minor=version.split(".")[1], **filled).encode()


def _assert_case(owner: str, test: str) -> tuple[dict[str, str], str]:
    for (case_owner, case_test), case in ASSERT_CASES.items():
        if case_owner == owner and test.startswith(case_test):
            return case
    raise AssertionError(f"no mutation breaks the assertion of {owner}: {test}")


@pytest.mark.parametrize("version", XSD11_SETS)
def test_the_base_file_is_valid(pairs: dict[str, Pair], version: str) -> None:
    assert _same_findings(pairs[version], _document(version, {}), "base") == set()


@pytest.mark.parametrize("version", XSD11_SETS)
def test_every_assertion_broken_gives_the_same_findings(
    pairs: dict[str, Pair], version: str
) -> None:
    tests = _schema_tests(version, "assert")
    assert len(tests) >= (1 if version == "1.8.0" else 20)
    for owner, test in sorted(tests):
        parts, target = _assert_case(owner, test)
        data = _document(version, parts)
        found = _same_findings(pairs[version], data, f"{version} {owner}: {test}")
        if not target:
            continue
        doc = load_bytes(data, "mutated")
        assert doc.tree is not None
        element = doc.tree.getroot().find(target)
        assert element is not None, target
        where = (doc.line_of(element), doc.xpath_of(element))
        assertion = [h for h in pairs[version].full.hits(doc) if h.element is element]
        assert any(h.message == assertion_message(element, test) for h in assertion), (
            f"{version}: the mutation does not break {owner}: {test}"
        )
        assert (*where, "other") in found


@pytest.mark.parametrize("version", XSD11_SETS)
def test_every_type_alternative_selected_gives_the_same_findings(
    pairs: dict[str, Pair], version: str
) -> None:
    alternatives = _schema_tests(version, "alternative")
    assert len(alternatives) == 8
    for owner, test in sorted(alternatives | {("segment", "")}):
        parts = ALTERNATIVE_CASES[owner, test.replace(" ", "")]
        found = _same_findings(pairs[version], _document(version, parts), f"{owner} {test}")
        assert found, f"{version}: the {owner} selecting {test or 'the default'} is valid"


def test_the_fast_path_marks_the_selected_types_on_libxml2s_tree(
    pairs: dict[str, Pair],
) -> None:
    # a virtual junction's connection of type 'virtual' must name its predecessor: only
    # the type the alternatives select says so
    data = _document("1.9.0", ALTERNATIVE_CASES["connection", "@type='virtual'"])
    doc = load_bytes(data, "virtual.xodr")
    hits = list(pairs["1.9.0"].fast.hits(doc))
    assert [(h.kind, etree.QName(h.element).localname) for h in hits if h.element is not None] == [
        ("missing_child", "connection")
    ]


def test_keys_below_type_alternatives_are_checked_though_xmlschema_does_not(
    pairs: dict[str, Pair],
) -> None:
    # xmlschema resolves a selector through declared types: t_junction declares no
    # connection, so 'junction/connection' selects nothing for it. XSD selects instance
    # elements; libxml2 does, and a connection naming no road is a real defect.
    junction = _junction("", CONNECTION.format(id=1, attrs='connectingRoad="9"', body=""))
    for version, pair in pairs.items():
        refers = pair.full.schema.identities["r_junction_connection_connectingRoad"]
        assert dict(refers.elements) == {}, "xmlschema checks it now: compare in full"
        doc = load_bytes(_document(version, junction), "j.xodr")
        fast = [h for h in pair.fast.hits(doc) if h.element is not None]
        assert [(h.kind, h.message) for h in fast] == [
            ("keyref", "'connection/@connectingRoad' names '9', but no 'road' has that @id")
        ]
        assert list(pair.full.hits(doc)) == []


@pytest.mark.parametrize(
    ("root", "falls_back"),
    [
        (
            '<OpenDRIVE xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"'
            ' xsi:noNamespaceSchemaLocation="OpenDRIVE_Core.xsd">',
            False,
        ),
        ('<OpenDRIVE xmlns:i="http://www.w3.org/2001/XMLSchema-instance">', True),
    ],
    ids=["schema-location", "own-xsi-type"],
)
def test_files_using_the_xsi_namespace(
    pairs: dict[str, Pair], monkeypatch: pytest.MonkeyPatch, root: str, falls_back: bool
) -> None:
    text = _document("1.9.0", ALTERNATIVE_CASES["connection", "@type='virtual'"]).decode()
    text = text.replace("<OpenDRIVE>", root)
    if falls_back:  # a type of the file's own: only full validation knows what to do
        text = text.replace('<junction id="10"', '<junction i:type="t_junction_virtual" id="10"')
    fast = pairs["1.9.0"].fast
    calls: list[Document] = []

    def full_hits(doc: Document) -> Iterator[Hit]:
        calls.append(doc)
        return iter(())

    monkeypatch.setattr(fast.full, "hits", full_hits)
    doc = load_bytes(text.encode(), "xsi.xodr")
    assert doc.tree is not None
    before = etree.tostring(doc.tree)
    list(fast.hits(doc))
    assert etree.tostring(doc.tree) == before
    assert bool(calls) is falls_back


@pytest.mark.parametrize(
    "value", ["+INF", "INF", "-0", "1e400", " 1 ", "0x1", " NaN ", "NaN ", "INF ", "-INF "]
)
def test_numbers_read_as_xsd11_reads_them(pairs: dict[str, Pair], value: str) -> None:
    # '+INF' is an xs:double in XSD 1.1, not in XSD 1.0: such a file is validated in full.
    # Blanks around a number are collapsed (libxml2 alone refuses them after NaN and INF)
    parts = _object(f'type="pole" height="{value}"')
    found = _same_findings(pairs["1.9.0"], _document("1.9.0", parts), value)
    assert bool(found) is (value in ("0x1", "-INF "))


# -- what libxml2 skips: children after an unexpected one, and elements of abstract type ---

SWITCH = (
    (CORPUS_RAIL / "ASAM-1.7.0_Ex_Railway-Switch.xodr").read_bytes() if SHARED.is_dir() else b""
)
SKIPPED_CASES = {
    # every road after it is unchecked by libxml2, their ids go missing for the keyrefs
    "unknown element before the roads": [(b"<road ", b"<foo/><road ")],
    "unknown element before the roads, a duplicate road id": [
        (b"<road ", b"<foo/><road "),
        (b'id="3" junction', b'id="1" junction'),
    ],
    "unknown element before the roads, a side track naming no road": [
        (b"<road ", b"<foo/><road "),
        (b'<sideTrack id="2" s="0.0000000000000000e+00"', b'<sideTrack id="77" s="x"'),
    ],
    "a railroad before the objects": [(b"<objects>", b"<railroad/><objects>")],
    "a switch without a name among skipped roads": [
        (b"<road ", b"<foo/><road "),
        (b'<switch name="Switch12" id="12"', b'<switch id="12"'),
    ],
}


@pytest.mark.parametrize("case", sorted(SKIPPED_CASES))
@pytest.mark.parametrize("version", ["1.8.1", "1.9.0"])
def test_what_libxml2_skips_is_checked_as_xsd11_does(
    pairs: dict[str, Pair], version: str, case: str
) -> None:
    data = SWITCH
    for old, new in SKIPPED_CASES[case]:
        assert old in data
        data = data.replace(old, new, 1)
    assert _same_findings(pairs[version], _as_version(data, version), case)


# -- (c) the rule cases, declared as 1.8 ---------------------------------------------------


@pytest.mark.parametrize("version", XSD11_SETS)
def test_rule_cases_declared_1_8_give_the_same_findings(
    pairs: dict[str, Pair], version: str
) -> None:
    compared = 0
    for path in RULE_CASES:
        data = path.read_bytes()
        if re.search(rb"<header\b[^>]*revMinor=", data) is None:
            continue  # the XS00x cases that have no version to change
        if load_bytes(data, path.name).tree is None:
            continue
        _same_findings(pairs[version], _as_version(data, "1." + version.split(".")[1]), str(path))
        compared += 1
    assert compared > 250


# -- the XSD 1.0 form and its cache --------------------------------------------------------


@pytest.mark.parametrize("version", XSD11_SETS)
def test_the_derived_form_compiles_in_libxml2_without_xsd11_constructs(version: str) -> None:
    with xsd10_form(_entry(version)) as form:
        assert form.entry is not None and form.unsupported == ()
        text = "".join(p.read_text("utf-8") for p in form.entry.parent.glob("*.xsd"))
        etree.XMLSchema(etree.parse(str(form.entry)))
    assert form.asserts == len(_schema_tests(version, "assert"))
    assert form.alternatives == 8
    for construct in ("xs:assert", "xs:alternative", "vc:minVersion"):
        assert construct not in text


def test_the_second_compile_reuses_the_cached_form(
    cache: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    first = xsd11_validator(_entry("1.8.0"), Libxml2Validator)
    assert isinstance(first, FastXsd11Validator) and first.form.cached
    assert first.form.schema_checked  # later builds of these files skip the meta-schema
    folders = list((cache / "xsd10").iterdir())
    assert [f.name for f in folders] == [first.form.key]
    written = {p: p.stat().st_mtime_ns for p in folders[0].iterdir()}

    def never(*args: Any) -> None:
        raise AssertionError("derived again")

    monkeypatch.setattr("xodrlint.validation.xsd11.form.derive_xsd10", never)
    second = xsd11_validator(_entry("1.8.0"), Libxml2Validator)
    assert isinstance(second, FastXsd11Validator) and second.form.key == first.form.key
    assert {p: p.stat().st_mtime_ns for p in folders[0].iterdir()} == written
    assert list((cache / "xsd10").iterdir()) == folders  # no partial folder left behind


def test_a_changed_schema_gets_a_new_key(cache: Path, tmp_path: Path) -> None:
    copy = tmp_path / "sets" / "1.8.0"
    shutil.copytree(SHARED_SCHEMAS / "1.8.0", copy)
    with xsd10_form(copy / "OpenDRIVE_Core.xsd") as same:
        pass
    with xsd10_form(_entry("1.8.0")) as original:
        pass
    assert same.key == original.key  # the key is the content, not the place
    lane = copy / "OpenDRIVE_Lane.xsd"
    lane.write_bytes(lane.read_bytes() + b"<!-- edited -->\n")
    with xsd10_form(copy / "OpenDRIVE_Core.xsd") as changed:
        pass
    assert changed.key != original.key
    assert {f.name for f in (cache / "xsd10").iterdir()} == {original.key, changed.key}


def test_an_unwritable_cache_still_validates(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, pairs: dict[str, Pair]
) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    monkeypatch.setenv(CACHE_DIR_ENV, str(blocker / "cache"))
    validator = xsd11_validator(_entry("1.9.0"), Libxml2Validator)
    assert isinstance(validator, FastXsd11Validator) and not validator.form.cached
    assert validator.form.entry is not None and not validator.form.entry.exists()
    path = CORPUS_RAIL / "libopendrive-rs_railways.xodr"
    doc = load_bytes(_as_version(path.read_bytes(), "1.9"), path.name)
    assert _seen(doc, list(validator.hits(doc))) == _seen(doc, list(pairs["1.9.0"].full.hits(doc)))


def test_full_validation_on_request(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(xsd11_fast.MODE_ENV, "full")
    assert isinstance(xsd11_validator(_entry("1.8.0"), Libxml2Validator), Xsd11Validator)


def test_the_fast_path_is_the_default_for_xsd11_sets(tmp_path: Path) -> None:
    validators = SchemaValidators(SchemaFinder(SHARED_SCHEMAS, environment={}, data_dir=tmp_path))
    doc = load_bytes((CORPUS_RAIL / "libopendrive-rs_railways.xodr").read_bytes(), "rs.xodr")
    schema = validators.schema_for(doc)
    assert isinstance(schema, SchemaSet) and schema.version == (1, 8, 1)
    check = validators.start(doc).result()  # as the linter validates
    assert check is not None and len(check.hits) == 4
    assert all(isinstance(v, FastXsd11Validator) for v in validators._compiled.values())


XSD11_SCHEMA = """<?xml version="1.0"?>
<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema"
    xmlns:vc="http://www.w3.org/2007/XMLSchema-versioning" vc:minVersion="1.1">
  {extra}
  <xs:element name="OpenDRIVE">
    <xs:complexType>
      <xs:sequence><xs:element name="header" minOccurs="0"/></xs:sequence>
      <xs:attribute name="a" type="xs:int"/>
      <xs:assert test="not(@a) or @a gt 0"/>
    </xs:complexType>
  </xs:element>
  <xs:element name="only10" vc:maxVersion="1.1"/>
  <xs:element name="only12" vc:minVersion="1.2"/>
</xs:schema>
"""


def test_derivation_resolves_versioning_and_removes_assertions() -> None:
    root = etree.fromstring(XSD11_SCHEMA.format(extra="").encode())
    found = derive_xsd10([root])
    assert (found.asserts, found.alternatives, found.unsupported) == (1, 0, [])
    names = [e.get("name") for e in root.iterchildren(f"{{{XS}}}element")]
    assert names == ["OpenDRIVE"]  # what an XSD 1.1 processor leaves out is left out
    assert b"vc:" not in etree.tostring(root).replace(b"xmlns:vc", b"")
    etree.XMLSchema(root)


@pytest.mark.parametrize(
    ("extra", "why"),
    [
        ("<xs:defaultOpenContent><xs:any/></xs:defaultOpenContent>", "default open content"),
        ('<xs:override schemaLocation="other.xsd"/>', "xs:override"),
        ('<xs:attribute name="i" type="xs:string" inheritable="true"/>', "inheritable"),
        (
            '<xs:simpleType name="s"><xs:restriction base="xs:dateTimeStamp"/></xs:simpleType>',
            "dateTimeStamp",
        ),
    ],
)
def test_sets_the_xsd10_form_cannot_stand_in_for_are_validated_in_full(
    tmp_path: Path, extra: str, why: str
) -> None:
    (tmp_path / "set.xsd").write_text(XSD11_SCHEMA.format(extra=extra))
    (tmp_path / "other.xsd").write_text(XSD11_SCHEMA.format(extra="").replace("OpenDRIVE", "x"))
    with xsd10_form(tmp_path / "set.xsd") as form:
        assert form.entry is None and any(why in item for item in form.unsupported)
    if why != "dateTimeStamp":  # xmlschema itself cannot build that one here
        assert isinstance(xsd11_validator(tmp_path / "set.xsd", Libxml2Validator), Xsd11Validator)


def test_a_set_with_a_broken_assertion_is_never_built_unchecked(
    cache: Path, tmp_path: Path
) -> None:
    # xmlschema's unchecked build would turn the broken XPath into an assertion that
    # always holds: the form records that the strict build failed, and the fast path
    # builds strictly, so the error surfaces
    broken = XSD11_SCHEMA.format(extra="").replace("@a gt 0", "@a gt (")
    (tmp_path / "set.xsd").write_text(broken)
    validator = xsd11_validator(tmp_path / "set.xsd", Libxml2Validator)
    assert isinstance(validator, FastXsd11Validator) and not validator.form.schema_checked
    doc = load_bytes(b'<OpenDRIVE a="-1"><header/></OpenDRIVE>', "a.xodr")
    with pytest.raises(SchemaLoadError):
        list(validator.hits(doc))


@pytest.mark.parametrize(
    ("parts", "split"), [({}, True), (ALTERNATIVE_CASES["junction", ""], False)]
)
def test_the_first_stage_needs_no_xmlschema_model_where_no_alternative_can_apply(
    cache: Path, monkeypatch: pytest.MonkeyPatch, parts: dict[str, str], split: bool
) -> None:
    # the first stage runs beside the rules (a thread); without type marks to set
    # it is libxml2 alone, and the slow model is built by the parent after its rules
    validator = xsd11_validator(_entry("1.9.0"), Libxml2Validator)
    assert isinstance(validator, FastXsd11Validator)
    assert validator.form.alternative_sites == frozenset(
        {
            ("OpenDRIVE", "junction"),
            ("junction", "connection"),
            ("boundary", "segment"),
        }
    )
    doc = load_bytes(_document("1.9.0", parts), "stages.xodr")
    first, finish, thread_safe = validator.stages(doc)
    assert thread_safe == split  # libxml2 alone may run in a thread; marking may not
    model = validator.model

    def no_model() -> Any:
        raise AssertionError("the first stage built the model")

    monkeypatch.setattr(validator, "model", no_model)
    if split:
        raw = first()
        monkeypatch.setattr(validator, "model", model)
        assert finish(lambda: raw) == raw == []
    else:
        with pytest.raises(AssertionError, match="built the model"):
            first()


def test_a_site_the_byte_scan_misses_is_validated_with_its_marks(
    pairs: dict[str, Pair],
) -> None:
    # a prefixed '<od:junction' escapes the scan for '<junction': the first stage runs
    # libxml2 without the marks, and the parent, whose plan finds them, validates again
    data = _document("1.9.0", ALTERNATIVE_CASES["connection", "@type='virtual'"]).decode()
    legacy = "http://code.asam.net/simulation/standard/opendrive_schema"
    data = re.sub(r"<(/?)(?=[A-Za-z])", r"<\1od:", data.split("?>", 1)[1])
    data = data.replace("<od:OpenDRIVE", f'<od:OpenDRIVE xmlns:od="{legacy}"', 1)
    doc = load_bytes(data.encode(), "prefixed.xodr")
    assert doc.tree is not None and doc.tree.getroot().find("junction") is not None
    fast = pairs["1.9.0"].fast
    assert fast.form.alternative_sites is not None
    assert not holds_a_site(doc, doc.tree.getroot(), fast.form.alternative_sites)
    assert _same_findings(pairs["1.9.0"], data.encode(), "prefixed")


def test_the_xmlschema_model_is_unpickled_from_the_cache_and_gives_the_same_findings(
    cache: Path, monkeypatch: pytest.MonkeyPatch, pairs: dict[str, Pair]
) -> None:
    first = xsd11_validator(_entry("1.9.0"), Libxml2Validator)
    assert isinstance(first, FastXsd11Validator)
    first.full  # noqa: B018 - built once, and kept in the form's folder
    assert list((cache / "xsd10" / first.form.key).glob("*.pickle"))

    def no_build(*args: Any, **kwargs: Any) -> Any:
        raise AssertionError("built again")

    import xmlschema

    monkeypatch.setattr(xmlschema, "XMLSchema11", no_build)
    second = xsd11_validator(_entry("1.9.0"), Libxml2Validator)
    assert isinstance(second, FastXsd11Validator)
    pair = Pair(pairs["1.9.0"].full, second)
    for path in sorted(CORPUS_RAIL.glob("*.xodr")):
        _same_findings(pair, _as_version(path.read_bytes(), "1.9"), path.name)
    for owner, test in sorted(_schema_tests("1.9.0", "assert"))[:5]:
        parts, _ = _assert_case(owner, test)
        _same_findings(pair, _document("1.9.0", parts), f"{owner}: {test}")
    # xmlschema's own route on the unpickled model: an assertion whose XPath fails while
    # evaluated (the official multiBoard test compares @dynamic with a boolean) is a
    # finding, not AttributeError ('XPath2Parser' object has no attribute 'source')
    [multiboard] = [
        parts for (owner, test), (parts, _) in ASSERT_CASES.items() if "multiBoard" in test
    ]
    doc = load_bytes(_document("1.9.0", multiboard), "multiboard.xodr")
    messages = [hit.message for hit in second.full.hits(doc)]
    assert messages == [hit.message for hit in pairs["1.9.0"].full.hits(doc)]
    assert any("multiBoard" in message for message in messages), messages


def test_a_broken_pickle_is_built_again(cache: Path) -> None:
    first = xsd11_validator(_entry("1.8.1"), Libxml2Validator)
    assert isinstance(first, FastXsd11Validator)
    first.full  # noqa: B018
    [pickled] = (cache / "xsd10" / first.form.key).glob("*.pickle")
    pickled.write_bytes(b"not a pickle")
    second = xsd11_validator(_entry("1.8.1"), Libxml2Validator)
    assert isinstance(second, FastXsd11Validator) and second.full.schema is not None
    assert pickled.read_bytes() != b"not a pickle"  # written again


@pytest.mark.parametrize("child", ["forked", "dies"])
def test_the_fast_path_in_a_forked_child_marks_types_there_or_in_the_fallback(
    pairs: dict[str, Pair], monkeypatch: pytest.MonkeyPatch, child: str
) -> None:

    fast = pairs["1.9.0"].fast
    data = _document("1.9.0", ALTERNATIVE_CASES["connection", "@type='virtual'"])
    doc = load_bytes(data, "virtual.xodr")
    assert doc.tree is not None
    expected = _seen(doc, list(fast.hits(doc)))
    assert expected  # the virtual connection's missing predecessor: only the marks tell
    monkeypatch.setattr(background, "MIN_BYTES", 0)
    parent = os.getpid()

    def task() -> list[Hit]:
        if child == "dies" and os.getpid() != parent:
            os._exit(9)
        return list(fast.hits(doc))

    started = background.start_hits(task, doc.tree.getroot(), len(doc.data))
    assert _seen(doc, started.result()) == expected


def test_the_assertions_run_before_the_caller_joins_libxml2s_thread(
    cache: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # where xmlschema evaluates the assertions (a form without a translation), the
    # caller's share overlaps libxml2's thread, not follows it
    validator = xsd11_validator(_entry("1.9.0"), Libxml2Validator)
    assert isinstance(validator, FastXsd11Validator)
    validator._selectors, validator._selectors_read = None, True
    doc = load_bytes(_document("1.9.0", {}), "order.xodr")
    order: list[str] = []
    real = validator._assertion_stage

    def assertions(*args: Any) -> Any:
        order.append("assertions")
        return real(*args)

    monkeypatch.setattr(validator, "_assertion_stage", assertions)
    first, finish, thread_safe = validator.stages(doc)
    assert thread_safe

    def joined() -> list[Hit]:
        order.append("libxml2 joined")
        return first()

    assert finish(joined) == []
    assert order == ["assertions", "libxml2 joined"]


# -- the assertions and type alternatives translated into libxml2's XPath ------------------


@pytest.mark.parametrize("version", XSD11_SETS)
def test_every_official_assertion_and_alternative_translates(version: str) -> None:
    with xsd10_form(_entry(version)) as form:
        assert form.translation is not None
        selectors = Selectors(form.translation)
    assert selectors.untranslated == []
    assert len(selectors.translated) == len(
        {(owner, test) for owner, test in _schema_tests(version, "assert")}
    )
    assert selectors.marks_known


@pytest.mark.parametrize("version", XSD11_SETS)
def test_assertions_need_no_xmlschema_model_where_every_value_is_plain(version: str) -> None:
    fast = xsd11_validator(_entry(version), Libxml2Validator)
    assert isinstance(fast, FastXsd11Validator)
    broken = 0
    for owner, test in sorted(_schema_tests(version, "assert")):
        parts, target = _assert_case(owner, test)
        doc = load_bytes(_document(version, parts), "mutated")
        assert doc.tree is not None
        hits = list(fast.hits(doc))
        if target:
            element = doc.tree.getroot().find(target)
            assert any(h.element is element for h in hits), (owner, test)
            broken += 1
        assert fast._model is None and fast._full is None, f"xmlschema was needed: {test}"
    assert broken > 0


def test_an_uncertain_value_is_judged_by_xmlschema(pairs: dict[str, Pair]) -> None:
    fast = xsd11_validator(_entry("1.9.0"), Libxml2Validator)
    assert isinstance(fast, FastXsd11Validator)
    repeat = (
        '<repeat s="0" length="1" distance="{d}" tStart="0" tEnd="0" heightStart="1"'
        ' heightEnd="1" zOffsetStart="0" zOffsetEnd="0"/>'
    )
    for value, model in (("5", False), ("1e3", True)):
        doc = load_bytes(
            _document("1.9.0", _object('type="barrier"', repeat.format(d=value))), value
        )
        assert [h.element.tag for h in fast.hits(doc) if h.element is not None] == ["object"]
        assert (fast._model is not None) is model


def test_an_untranslated_assertion_keeps_xmlschemas_route(
    cache: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a translation whose XPath of one assertion was refused: that assertion alone runs
    # in xmlschema, and the findings stay those of full validation
    real = translation_module.Translator.assertion

    def refusing(self: Any, token: Any) -> tuple[str, str]:
        if "laneOffset" in str(token.source):
            raise translation_module.Untranslatable("refused by the test")
        return real(self, token)

    monkeypatch.setattr(translation_module.Translator, "assertion", refusing)
    fast = xsd11_validator(_entry("1.9.0"), Libxml2Validator)
    assert isinstance(fast, FastXsd11Validator)
    assert "in xmlschema: t_road_lanes" in fast.route
    assert "refused by the test" in fast.route
    full = Xsd11Validator(_entry("1.9.0"))
    lanes = {"lanes": LANES.format(attrs="", offset=OFFSET, section="", width=BORDER)}
    for parts in (lanes, _object('type="pole" width="1"')):
        data = _document("1.9.0", parts)
        _same_findings(Pair(full, fast), data, "partly translated")
    assert fast._model is not None


def test_a_translation_libxml2_cannot_compile_leaves_the_checks_to_xmlschema(
    cache: Path,
) -> None:
    with xsd10_form(_entry("1.9.0")) as form:
        assert form.translation is not None
        broken = json.loads(json.dumps(form.translation))
    broken["types"][0]["assertions"][0]["fails"] = "not((("
    assert form.entry is not None
    fast = FastXsd11Validator(
        _entry("1.9.0"), Libxml2Validator(form.entry), replace(form, translation=broken)
    )
    assert fast.selectors() is None
    assert "no translation" in fast.route
    data = _document("1.9.0", _junction("", _twice('connectingRoad="2"')))
    _same_findings(Pair(Xsd11Validator(_entry("1.9.0")), fast), data, "broken translation")


@pytest.mark.parametrize("version", XSD11_SETS)
def test_each_official_assertion_is_worded(version: str) -> None:
    element = etree.Element("object", type="barrier")
    for _, test in _schema_tests(version, "assert"):
        message = assertion_message(element, test)
        assert "fails the schema's assertion" not in message, test
        assert test not in message
    other = "count(a) = 2"
    assert assertion_message(element, other) == "'object' fails the schema's assertion count(a) = 2"


def test_duplicate_connection_ids_are_named() -> None:
    junction = etree.fromstring(
        '<junction><connection id="1"/><connection id="2"/><connection id="1"/></junction>'
    )
    message = assertion_message(
        junction, "count(connection/@id) = count(distinct-values(connection/@id))"
    )
    assert message == "'junction' has connections that share an @id ('1'); each must be unique"


_KINDS = ["barrier", "building", "crosswalk", "gantry", "obstacle", "parkingSpace", "pole"]
_KINDS += ["roadMark", "roadSurface", "trafficIsland", "tree", "vegetation", "none"]
_CHILDREN = {
    "marking": '<markings><marking color="white" spaceLength="1" lineLength="1" startOffset="0"'
    ' stopOffset="0" side="left"/></markings>',
    "border": '<borders><border width="0.1" type="concrete" outlineId="0"'
    ' useCompleteOutline="true"/></borders>',
    "material": '<material friction="0.5"/>',
    "parkingSpace": _PARKING,
    "skeleton": '<skeleton><polyline id="0"><vertexLocal id="0" u="0" v="0" z="0"/>'
    '<vertexLocal id="1" u="1" v="0" z="0"/></polyline></skeleton>',
}
_NUMBERS = ["0", "-0", "0.0", "5", ".5", "5.", "-5", " 0 ", "\t1\n", "1e3", "INF", "-INF"]
_NUMBERS += ["NaN", " NaN ", "abc", "", "+5", "0x1", "1 2", "0." + "0" * 315 + "1", "-0.0"]


@st.composite
def _mutated_parts(draw: st.DrawFn) -> dict[str, str]:
    """A file part around the assertions: an object of any kind with or without each
    child and size attribute and a repeat distance of any spelling; a junction with
    connection ids that may repeat; lanes with or without an offset and borders; a
    signal that may be a multiBoard; a lateral profile with any of its children."""
    size = "".join(
        f' {name}="{draw(st.sampled_from(_NUMBERS))}"'
        for name in ("radius", "width", "length")
        if draw(st.booleans())
    )
    body = "".join(part for part in _CHILDREN.values() if draw(st.booleans()))
    if draw(st.booleans()):
        body += (
            f'<repeat s="0" length="1" distance="{draw(st.sampled_from(_NUMBERS))}" tStart="0"'
            ' tEnd="0" heightStart="1" heightEnd="1" zOffsetStart="0" zOffsetEnd="0"/>'
        )
    kind = draw(st.sampled_from(_KINDS))
    parts = _object(f'type="{kind}"{size}', body)
    ids = draw(st.lists(st.sampled_from(["1", "2", " 1", "1 ", "01"]), max_size=4))
    junction_type = draw(st.sampled_from(["", 'type="direct"', 'type="virtual"', 'type="x"']))
    road = 'linkedRoad="2"' if "direct" in junction_type else 'connectingRoad="2"'
    parts |= _junction(
        junction_type, "".join(CONNECTION.format(id=i, attrs=road, body="") for i in ids)
    )
    offset = OFFSET if draw(st.booleans()) else ""
    layer = draw(st.sampled_from(["", ' layer="permanent"', ' layer=" permanent"']))
    section = ' length="10"' if draw(st.booleans()) else ""
    width = draw(st.sampled_from([WIDTH, BORDER]))
    parts["lanes"] = LANES.format(attrs=layer, offset=offset, section=section, width=width)
    dynamic = draw(st.sampled_from(["yes", "no", "true", " true", "1"]))
    boards = "".join(draw(st.sets(st.sampled_from(["<vmsBoard/>", "<staticBoard/>"]))))
    signal_type = draw(st.sampled_from(["multiBoard", "205", " multiBoard"]))
    parts["signals"] = (
        f'<signal id="5" s="1" t="0" zOffset="0" dynamic="{dynamic}" orientation="+"'
        f' type="{signal_type}" subtype="-1" country="DE">{boards}</signal>'
    )
    return parts


@pytest.mark.parametrize("version", ["1.8.1", "1.9.0"])
@settings(
    max_examples=40,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(parts=_mutated_parts())
def test_mutated_documents_give_the_findings_of_full_validation(
    pairs: dict[str, Pair], version: str, parts: dict[str, str]
) -> None:
    _same_findings(pairs[version], _document(version, parts), repr(parts))


def test_a_run_whose_assertions_all_translate_never_imports_xmlschema(
    cache: Path, tmp_path: Path
) -> None:
    # a junction (marks), an object breaking its assertion, a 1.9 header: the first run
    # derives the form (xmlschema builds the set once), the second needs no xmlschema
    parts = _object('type="pole" width="1"') | ALTERNATIVE_CASES["junction", "@type='direct'"]
    path = tmp_path / "map.xodr"
    path.write_bytes(_document("1.9.0", parts))
    script = (
        "import sys\n"
        "from xodrlint.api import lint_file\n"
        f"report = lint_file({str(path)!r}, schema={str(SHARED_SCHEMAS / '1.9.0')!r})\n"
        "messages = [f.message for f in report.findings if f.code == 'XS006']\n"
        "print(any('@radius alone' in m for m in messages), len(messages) > 1,"
        " 'xmlschema' in sys.modules, 'elementpath' in sys.modules)\n"
    )
    runs = [
        subprocess.run(
            [sys.executable, "-c", script], capture_output=True, text=True, check=True
        ).stdout.split()
        for _ in range(2)
    ]
    assert runs[0][:2] == ["True", "True"], runs[0]
    assert runs[1] == ["True", "True", "False", "False"], runs[1]


def test_verbose_says_where_the_assertions_ran(cache: Path, tmp_path: Path) -> None:
    path = tmp_path / "map.xodr"
    path.write_bytes(_document("1.9.0", {}))
    schema = str(SHARED_SCHEMAS / "1.9.0")
    result = CliRunner().invoke(app, ["check", "-v", "--schema", schema, str(path)])
    assert "assertions: 24 in libxml2's XPath" in result.stderr, result.stderr
    # a file only full validation reads right says so, and the next file its own route
    odd = tmp_path / "odd.xodr"
    odd.write_bytes(_document("1.9.0", {}).replace(b'revMinor="9"', b'revMinor="9" x="+INF"'))
    result = CliRunner().invoke(app, ["check", "-v", "--schema", schema, str(odd), str(path)])
    lines = {
        Path(line.split(":")[1].strip()).name: line
        for line in result.stderr.splitlines()
        if line.startswith("xodrlint: /")
    }
    odd_line, map_line = lines["odd.xodr"], lines["map.xodr"]
    assert "full XSD 1.1 validation in xmlschema (the file uses xsi:type" in odd_line, odd_line
    assert "assertions: 24 in libxml2's XPath" in map_line, map_line


class _Sides:
    """A pole's split validation, libxml2's part in a thread named "validation": the
    thread of each run of the translated assertions recorded, and libxml2 or the
    assertions held (until :meth:`joined`) where a test says."""

    def __init__(
        self,
        pairs: dict[str, Pair],
        monkeypatch: pytest.MonkeyPatch,
        *,
        hold_libxml2: bool = False,
        hold_checks: bool = False,
    ) -> None:
        fast = pairs["1.9.0"].fast
        selectors = fast.selectors()
        assert selectors is not None
        self.threads: list[str] = []
        self.held = threading.Event()
        self._release = threading.Event()
        real_check, real_hits = selectors.check, fast._libxml2.hits

        def check(root: etree._Element, **options: bool) -> Any:
            self.threads.append(threading.current_thread().name)
            if hold_checks:
                self._hold()
            return real_check(root, **options)

        def hits(doc: Document) -> Iterator[Hit]:
            if hold_libxml2:
                self._hold()
            return real_hits(doc)

        monkeypatch.setattr(selectors, "check", check)
        monkeypatch.setattr(fast._libxml2, "hits", hits)
        doc = load_bytes(_document("1.9.0", _object('type="pole" width="1"')), "pole.xodr")
        self.first, self.finish, self.thread_safe = fast.stages(doc)
        self._done: list[list[Hit]] = []
        self.worker = threading.Thread(
            target=lambda: self._done.append(self.first()), name="validation", daemon=True
        )
        self.worker.start()

    def _hold(self) -> None:
        self.held.set()
        assert self._release.wait(30)

    def joined(self) -> list[Hit]:
        """libxml2's part, its thread let go and joined (what the caller waits for)."""
        self._release.set()
        self.worker.join()
        return self._done[0]


def _tags(hits: list[Hit]) -> list[str]:
    return [str(h.element.tag) for h in hits if h.element is not None]


def test_the_translated_assertions_run_in_the_first_part_beside_the_rules(
    pairs: dict[str, Pair], monkeypatch: pytest.MonkeyPatch
) -> None:
    # libxml2's XPath runs without the GIL: in the validation thread, after libxml2
    sides = _Sides(pairs, monkeypatch)
    assert sides.thread_safe
    sides.worker.join()
    assert _tags(sides.finish(sides.joined)) == ["object"]
    assert sides.threads == ["validation"]


def test_the_caller_runs_the_translated_assertions_when_libxml2_is_still_busy(
    pairs: dict[str, Pair], monkeypatch: pytest.MonkeyPatch
) -> None:
    # a city map: the rules end before libxml2 does, and the caller, free, runs the
    # assertions while libxml2's thread validates; that thread then leaves them alone
    sides = _Sides(pairs, monkeypatch, hold_libxml2=True)
    assert sides.held.wait(30)
    caller = threading.current_thread().name

    def libxml2_result() -> list[Hit]:
        assert sides.threads == [caller]  # run here, before the join
        return sides.joined()

    assert _tags(sides.finish(libxml2_result)) == ["object"]
    assert sides.threads == [caller]  # once: the thread did not


def test_the_caller_leaves_the_assertions_to_libxml2s_thread_that_took_them(
    pairs: dict[str, Pair], monkeypatch: pytest.MonkeyPatch
) -> None:
    # a railway: libxml2's thread is done first and runs them; the caller, done with its
    # rules while they still run, waits for that thread instead of running them again
    sides = _Sides(pairs, monkeypatch, hold_checks=True)
    assert sides.held.wait(30)

    def libxml2_result() -> list[Hit]:
        assert sides.threads == ["validation"]  # the caller did not run them
        return sides.joined()

    assert _tags(sides.finish(libxml2_result)) == ["object"]
    assert sides.threads == ["validation"]


def test_an_error_in_the_callers_assertions_waits_for_libxml2s_thread(
    pairs: dict[str, Pair], monkeypatch: pytest.MonkeyPatch
) -> None:
    # as before the caller ran them: the thread is joined before the error goes on, so no
    # validation is left running beside the next file
    fast = pairs["1.9.0"].fast
    selectors = fast.selectors()
    assert selectors is not None

    def check(root: etree._Element, **options: bool) -> Any:
        raise RuntimeError("broken")

    monkeypatch.setattr(selectors, "check", check)
    doc = load_bytes(_document("1.9.0", _object('type="pole" width="1"')), "pole.xodr")
    first, finish, _ = fast.stages(doc)  # the caller's turn comes first: nothing ran yet
    joined: list[bool] = []

    def libxml2_result() -> list[Hit]:
        joined.append(True)
        return first()

    with pytest.raises(RuntimeError, match="broken"):
        finish(libxml2_result)
    assert joined == [True]


TYPED_SET = """<?xml version="1.0"?>
<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema"
    xmlns:vc="http://www.w3.org/2007/XMLSchema-versioning" vc:minVersion="1.1">
  <xs:element name="OpenDRIVE" type="t_root"/>
  <xs:complexType name="t_root">
    <xs:sequence>
      <xs:element name="q" type="t_q" minOccurs="0" maxOccurs="unbounded"/>
      <xs:element name="r" minOccurs="0" maxOccurs="unbounded">
        <xs:complexType>
          <xs:attribute name="d" type="xs:double"/>
          <xs:assert test="not(@d) or @d > 0"/>
        </xs:complexType>
      </xs:element>
    </xs:sequence>
  </xs:complexType>
  <xs:complexType name="t_q">
    <xs:attribute name="i" type="xs:integer"/>
    <xs:attribute name="f" type="xs:float"/>
    <xs:attribute name="d" type="xs:double"/>
    <xs:assert test="not(@i) or @i > 0"/>
    <xs:assert test="not(@f) or @f > 0"/>
    <xs:assert test="not(@d) or @d > 0"/>
  </xs:complexType>
</xs:schema>
"""
#: A fraction libxml2's number() reads as 0, and xs:double as a tiny positive number.
TINY = "0." + "0" * 315 + "1"


def test_what_xpath_1_reads_otherwise_is_left_to_xmlschema(cache: Path, tmp_path: Path) -> None:
    # an integer (written '5.0' it is none), a float (single precision reads a tiny
    # value as 0), an anonymous type (assertions are told apart by type name): not
    # translated; a double XPath 1.0 reads as 0 goes to xmlschema, document by document
    (tmp_path / "typed.xsd").write_text(TYPED_SET)
    fast = xsd11_validator(tmp_path / "typed.xsd", Libxml2Validator)
    assert isinstance(fast, FastXsd11Validator)
    assert "1 in libxml2's XPath" in fast.route
    for why in ("integer attributes", "float attributes", "'not(@d) or @d > 0' (an anonymous"):
        assert why in fast.route, fast.route
    pair = Pair(Xsd11Validator(tmp_path / "typed.xsd"), fast)
    for value in (TINY, "-1", "2"):
        for tag in ("q", "r"):
            data = f'<OpenDRIVE><{tag} d="{value}"/></OpenDRIVE>'.encode()
            found = _same_findings(pair, data, f"{tag}/@d={value}")
            assert bool(found) is (value == "-1")


@pytest.mark.parametrize("kind", ["building", "barrier", "crosswalk"])
def test_a_fraction_libxml2_reads_as_zero_is_judged_as_xsd_reads_it(
    pairs: dict[str, Pair], kind: str
) -> None:
    repeat = (
        f'<repeat s="0" length="1" distance="{TINY}" tStart="0" tEnd="0" heightStart="1"'
        ' heightEnd="1" zOffsetStart="0" zOffsetEnd="0"/>'
    )
    found = _same_findings(
        pairs["1.9.0"], _document("1.9.0", _object(f'type="{kind}"', repeat)), kind
    )
    assert bool(found) is (kind == "barrier")  # barriers repeat at distance 0


def test_an_xpath_that_fails_when_run_leaves_the_checks_to_xmlschema(cache: Path) -> None:
    with xsd10_form(_entry("1.9.0")) as form:
        assert form.translation is not None and form.entry is not None
        broken = json.loads(json.dumps(form.translation))
    for entry in broken["types"]:
        for item in entry["assertions"]:
            item["fails"] = "foo()"  # compiles, raises when evaluated
    fast = FastXsd11Validator(
        _entry("1.9.0"), Libxml2Validator(form.entry), replace(form, translation=broken)
    )
    assert fast.selectors() is not None
    data = _document("1.9.0", _junction("", _twice('connectingRoad="2"')))
    found = _same_findings(Pair(Xsd11Validator(_entry("1.9.0")), fast), data, "foo()")
    assert found and fast.selectors() is None


def test_blanks_after_nan_in_an_integer_are_no_number(pairs: dict[str, Pair]) -> None:
    # XSD collapses blanks around a double's NaN; an integer's 'NaN ' is no number at all
    for value in ("NaN ", "INF "):
        lanes = LANES.format(attrs="", offset="", section="", width=WIDTH)
        data = _document("1.9.0", {"lanes": lanes.replace('id="-1"', f'id="{value}"')})
        assert _same_findings(pairs["1.9.0"], data, value)


def test_with_type_marks_the_assertions_run_while_libxml2_validates(
    pairs: dict[str, Pair], monkeypatch: pytest.MonkeyPatch
) -> None:
    # a junction: libxml2 validates with the marks set; the assertions' XPath runs in a
    # thread meanwhile, the marks already in place, and the findings stay full validation's
    fast = pairs["1.9.0"].fast
    selectors = fast.selectors()
    assert selectors is not None
    seen: list[tuple[str, bool]] = []
    real = selectors.check

    def check(root: etree._Element, **options: bool) -> Any:
        junction = root.find("junction")
        marked = junction is not None and junction.get(f"{{{XSI}}}type") is not None
        seen.append((threading.current_thread().name, marked))
        return real(root, **options)

    monkeypatch.setattr(selectors, "check", check)
    parts = ALTERNATIVE_CASES["junction", "@type='direct'"] | _object('type="pole" width="1"')
    found = _same_findings(pairs["1.9.0"], _document("1.9.0", parts), "marks beside")
    assert found
    assert seen[0][0] != threading.current_thread().name and seen[0][1]


def test_type_marks_that_fail_when_run_leave_the_checks_to_xmlschema(
    cache: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the alternatives' XPath of an altered manifest raises: this document and the next
    # go xmlschema's way, the selectors dropped at once (not met again per document)
    with xsd10_form(_entry("1.9.0")) as form:
        assert form.translation is not None and form.entry is not None
        broken = json.loads(json.dumps(form.translation))
    assert broken["marks"]
    for mark in broken["marks"]:
        mark["path"] = "foo()"  # compiles, raises when evaluated
    fast = FastXsd11Validator(
        _entry("1.9.0"), Libxml2Validator(form.entry), replace(form, translation=broken)
    )
    selectors = fast.selectors()
    assert selectors is not None
    runs: list[int] = []
    real = selectors.marks

    def marks(root: etree._Element) -> Any:
        runs.append(1)
        return real(root)

    monkeypatch.setattr(selectors, "marks", marks)
    pair = Pair(Xsd11Validator(_entry("1.9.0")), fast)
    parts = ALTERNATIVE_CASES["junction", "@type='direct'"] | _object('type="pole" width="1"')
    assert _same_findings(pair, _document("1.9.0", parts), "foo() marks")
    assert fast.selectors() is None and len(runs) == 1


def test_a_document_is_screened_for_xsi_type_once(
    pairs: dict[str, Pair], monkeypatch: pytest.MonkeyPatch
) -> None:
    # the screen reads the whole file's bytes: once per document, also where the type
    # marks come from the translation (a junction) and the assertions run beside libxml2
    screened: list[int] = []
    real = needs_xsd11_reading

    def counted(doc: Document, root: etree._Element) -> bool:
        screened.append(1)
        return real(doc, root)

    monkeypatch.setattr(xsd11_fast, "needs_xsd11_reading", counted)
    parts = ALTERNATIVE_CASES["junction", "@type='direct'"] | _object('type="pole" width="1"')
    doc = load_bytes(_document("1.9.0", parts), "junction.xodr")
    assert list(pairs["1.9.0"].fast.hits(doc))
    assert len(screened) == 1


def test_a_forked_validation_still_says_why_it_went_to_full_validation(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a map with a junction validates whole, in a forked child when it is large: the
    # document is screened in the parent, so -v names the full route (the child's
    # findings of its own would not come back)
    monkeypatch.setattr(background, "MIN_BYTES", 0)
    forked = record_forks(monkeypatch)
    data = _document("1.9.0", ALTERNATIVE_CASES["junction", "@type='direct'"])
    data = data.replace(b'revMinor="9"', b'revMinor="9" x="+INF"')
    finder = SchemaFinder(SHARED_SCHEMAS / "1.9.0", environment={}, data_dir=tmp_path)
    check = SchemaValidators(finder).start(load_bytes(data, "odd.xodr")).result()
    assert check is not None and check.route is not None
    assert check.route.startswith("full XSD 1.1 validation in xmlschema (the file uses"), (
        check.route
    )
    assert forked  # (the route this is about)


@pytest.mark.parametrize("written", ["INF", " nothing ", "q:t_road", "xs:t_road"])
def test_an_xsi_type_naming_no_type_is_a_finding_and_the_rest_is_validated(
    pairs: dict[str, Pair], written: str
) -> None:
    # xmlschema raised (XMLSchemaKeyError: global component not found) instead of
    # reporting it: an internal error for the file, and none of its findings
    data = _document("1.9.0", _object('type="pole" width="1"')).replace(
        b'<road length="100" id="1"',
        b'<road xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" '
        b'xmlns:xs="http://www.w3.org/2001/XMLSchema" xsi:type="'
        + written.encode()
        + b'" length="100" id="1"',
        1,
    )
    doc = load_bytes(data, "typed.xodr")
    assert doc.tree is not None
    found = [(h.element.tag if h.element is not None else None, h.message) for h in
             pairs["1.9.0"].fast.hits(doc)]  # fmt: skip
    road = doc.tree.getroot().find("road")
    assert ("road", _unresolved(written)) in found
    # the pole's assertion, found on the copy, stands on the document's own object
    objects = [h.element for h in pairs["1.9.0"].fast.hits(doc)
               if h.element is not None and h.element.tag == "object"]  # fmt: skip
    assert road is not None and objects == [road.find("objects/object")]
    assert road is not None and road.get(XSI_TYPE) == written  # the document untouched


def _unresolved(written: str) -> str:
    return (
        f"'road/@xsi:type': the QName value '{written.strip()}' of the xsi:type attribute "
        "does not resolve to a type definition"
    )


def test_an_unpickled_model_evaluates_what_makes_tokens_while_it_runs() -> None:
    # elementpath's parsers pickle without their slots: a `cast as` makes a token while
    # it is evaluated, and raised AttributeError ('next_match') on every element
    import pickle

    import xmlschema

    from xodrlint.validation.xsd11.form import _with_whole_parsers

    schema = xmlschema.XMLSchema11(
        '<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema"><xs:element name="r">'
        '<xs:complexType><xs:attribute name="a" type="xs:string"/>'
        '<xs:assert test="string(string(@a) cast as xs:integer) ne &apos;zz&apos;"/>'
        '<xs:assert test="@a castable as xs:integer"/>'
        "</xs:complexType></xs:element></xs:schema>"
    )
    unpickled = _with_whole_parsers(pickle.loads(pickle.dumps(schema)))
    for written in ("5", "x"):
        document = etree.fromstring(f'<r a="{written}"/>')
        fresh = [str(error.reason) for error in schema.iter_errors(document)]
        assert [str(error.reason) for error in unpickled.iter_errors(document)] == fresh


@pytest.mark.parametrize(
    "signal",
    [
        # skipped content (userData's xs:any): xmlschema does not judge it, nor libxml2
        '<signal id="5" s="1" t="0" zOffset="0" dynamic="no" orientation="+" type="x"'
        ' subtype="-1" country="DE"><userData code="a"><foo xsi:type="nosuch"/></userData>'
        "</signal>",
        # an unexpected element: its own finding, not one for its xsi:type
        '<bogus xsi:type="INF"/>',
    ],
    ids=["in-skipped-content", "on-an-unexpected-element"],
)
def test_an_xsi_type_xmlschema_does_not_judge_is_no_finding(
    pairs: dict[str, Pair], signal: str
) -> None:
    typed = _document("1.9.0", {"signals": signal}).replace(
        b"<OpenDRIVE>", b'<OpenDRIVE xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">', 1
    )
    found = [hit.message for hit in pairs["1.9.0"].fast.hits(load_bytes(typed, "t.xodr"))]
    assert not [message for message in found if "xsi:type" in message], found
    assert len(found) == (0 if "userData" in signal else 1), found
