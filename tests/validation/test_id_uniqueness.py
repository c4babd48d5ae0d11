"""Unique road and junction ids (issue 28): the built-in railroad schema keys them as the
official schemas of 1.5 and later do (1.4's keys none), so a repeated id is an XS006
finding on the later element, naming the first one's line, with either schema, and once;
on a map without a repeated id it costs one pass over the root's children."""

from __future__ import annotations

from pathlib import Path

import pytest
from lxml import etree

from tests.conftest import REPO, SHARED_SCHEMAS, needs_shared
from tests.test_benchmarks import RAILWAY
from xodrlint.api import default_registry
from xodrlint.concurrency.background import receive_hits, send_hits
from xodrlint.document.load import load_bytes
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import FileReport, Hit
from xodrlint.validation.libxml2 import BuiltinRailroadValidator, _maybe_repeated
from xodrlint.validation.sets import builtin_set

CLEAN = REPO / "examples" / "clean.xodr"
SIDING_END = "  </road>\n  <station"
VERSIONS = [4, 5, 6, 7, 8, 9]


def _repeated(minor: int) -> tuple[bytes, list[tuple[int, str]]]:
    """``examples/clean.xodr`` declaring 1.``minor``, with its siding (road '2') copied
    after it and two junctions sharing id '9'; and the XS006 findings a schema that keys
    the ids gives: (line, message)."""
    text = CLEAN.read_text("utf-8").replace('revMinor="7"', f'revMinor="{minor}"', 1)
    text = text.replace(' version="1.0"/>', ' version="1.00"/>', 1)  # 1.5M's pattern for it
    start = text.index('  <road name="siding"')
    siding = text[start : text.index(SIDING_END) + len("  </road>\n")]
    copy = siding.replace('name="siding"', 'name="siding again"')
    junctions = '  <junction name="east" id="9"/>\n  <junction name="west" id="9"/>\n'
    at = text.index("  <station")
    text = text[:at] + copy + junctions + text[at:]
    lines = text.splitlines()

    def line_of(marker: str) -> int:
        return next(n for n, line in enumerate(lines, start=1) if marker in line)

    first_road, first_junction = line_of('name="siding"'), line_of('name="east"')
    expected = [
        (
            line_of('name="siding again"'),
            f"road id '2' is not unique: an earlier 'road' has it at line {first_road}",
        ),
        (
            line_of('name="west"'),
            f"junction id '9' is not unique: an earlier 'junction' has it at line {first_junction}",
        ),
    ]
    return text.encode(), expected


def _lint(data: bytes) -> FileReport:
    """XS006 alone, by a linter made now: it finds the schemas the environment names."""
    report = Linter(default_registry(), LintOptions(select=("XS006",))).lint_bytes(data, "n.xodr")
    assert report.internal_errors == ()
    return report


def _unique_findings(data: bytes) -> list[tuple[int, str]]:
    return [(f.line, f.message) for f in _lint(data).findings if "is not unique" in f.message]


@pytest.mark.parametrize("minor", VERSIONS)
def test_the_built_in_schema_keys_road_and_junction_ids(minor: int) -> None:
    data, expected = _repeated(minor)
    report = _lint(data)
    assert report.schema is not None and "built-in" in report.schema
    # the official 1.4 schema keys no ids: neither does the built-in one for 1.4
    assert _unique_findings(data) == (expected if minor >= 5 else [])


@needs_shared
@pytest.mark.parametrize("minor", VERSIONS)
def test_the_official_schema_reports_each_repeat_once_in_the_same_words(
    minor: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("XODRLINT_SCHEMA_PATH", str(SHARED_SCHEMAS))
    data, expected = _repeated(minor)
    report = _lint(data)
    assert report.schema is not None and "built-in" not in report.schema
    assert _unique_findings(data) == (expected if minor >= 5 else [])
    # without the repeats the file is valid against the official schema of its version,
    # but for the junctions' content: nothing else was needed to find them
    others = [f for f in report.findings if "is not unique" not in f.message]
    assert all(f.xpath.startswith("/OpenDRIVE/junction") for f in others), others


def test_every_repeat_names_the_first(tmp_path: Path) -> None:
    text = CLEAN.read_text("utf-8")
    main_end = text.index('  <road name="siding"')
    main_line = text[text.index('  <road name="main line"') : main_end]
    at = text.index("  <station")
    three = text[:at] + main_line + main_line + text[at:]
    found = _unique_findings(three.encode())
    first = next(n for n, line in enumerate(three.splitlines(), 1) if 'name="main line"' in line)
    assert [message for _, message in found] == [
        f"road id '1' is not unique: an earlier 'road' has it at line {first}"
    ] * 2
    assert len({line for line, _ in found}) == 2 and min(line for line, _ in found) > first


def test_ids_compare_as_written_and_a_missing_id_is_no_repeat() -> None:
    text = CLEAN.read_text("utf-8")
    at = text.index("  <station")
    extra = (
        '  <road name="a" length="1" id=" 1" junction="-1"><planView/></road>\n'
        '  <road name="b" length="1" junction="-1"><planView/></road>\n'
        '  <road name="c" length="1" junction="-1"><planView/></road>\n'
        '  <junction name="j" id="1"/>\n'
    )
    assert _unique_findings((text[:at] + extra + text[at:]).encode()) == []


def test_a_repeat_past_line_65535_is_placed_exactly() -> None:
    # libxml2 counts lines in 16 bits; the stand-in's elements are found by position
    text = CLEAN.read_text("utf-8")
    at = text.index("  <station")
    padding = "  <!-- padding -->\n" * 70_000
    road = '  <road name="late" length="1" id="2" junction="-1"><planView/></road>\n'
    data = (text[:at] + padding + road + text[at:]).encode()
    expected_line = text[:at].count("\n") + 70_000 + 1
    siding = next(n for n, line in enumerate(text.splitlines(), 1) if 'name="siding"' in line)
    assert _unique_findings(data) == [
        (expected_line, f"road id '2' is not unique: an earlier 'road' has it at line {siding}")
    ]


def test_a_hit_s_related_elements_cross_the_fork() -> None:
    # validation of a large map runs in a forked child, which sends hits back as positions
    root = etree.fromstring(b"<OpenDRIVE><road id='1'/><road id='1'/><x><y/></x></OpenDRIVE>")
    first, later, holder = list(root)
    hits = [Hit(later, "repeated", kind="duplicate", related=(first, holder[0])), Hit(None, "x")]
    back = receive_hits(send_hits(hits, root), root)
    assert back[0].element is later and back[0].related == (first, holder[0])
    assert back[1].related == ()


def test_only_elements_whose_ids_repeat_go_to_the_stand_in() -> None:
    # libxml2 compares each key with every one before it (18,000 roads of the 20 MB
    # benchmark railway: 0.23 s); the stand-in holds only the repeats, so a map without
    # any costs one pass over the root's children
    doc = load_bytes("".join(RAILWAY.railway(2_000_000, 7)).encode(), "railway.xodr")
    assert doc.root is not None
    assert sum(1 for _ in doc.root.iterchildren("road")) > 1000
    assert _maybe_repeated(doc.root) == []
    assert list(BuiltinRailroadValidator(builtin_set(1, 7)).hits(doc)) == []
    data, _ = _repeated(7)
    repeated = load_bytes(data, "net.xodr").root
    assert repeated is not None
    assert [(e.tag, e.get("name"), i) for e, i in _maybe_repeated(repeated)] == [
        ("road", "siding", "2"),
        ("road", "siding again", "2"),
        ("junction", "east", "9"),
        ("junction", "west", "9"),
    ]
