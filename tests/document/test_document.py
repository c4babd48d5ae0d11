"""Stage 1: loading, exact lines, readable XPaths, and every way a file can fail to load."""

from __future__ import annotations

import codecs

import pytest
from lxml import etree

from tests.conftest import REPO
from xodrlint.document.load import ASAM_LEGACY_NAMESPACE, Version, load_bytes, nearest_published

HEADER = '<header revMajor="1" revMinor="7"/>'


def _doc(body: str, declaration: str = '<?xml version="1.0" encoding="UTF-8"?>\n') -> bytes:
    return f"{declaration}<OpenDRIVE>\n  {HEADER}\n{body}</OpenDRIVE>\n".encode()


def test_clean_document_has_no_problems_and_a_version() -> None:
    doc = load_bytes(_doc('  <road id="1" length="10"/>\n'), "a.xodr")
    assert doc.problems == {}
    assert doc.declared == Version(1, 7) == doc.effective


def test_lines_are_exact_beyond_libxml2s_16_bit_limit() -> None:
    filler = "".join(f'  <road id="{i}" length="1"/>\n' for i in range(70_000))
    data = _doc(filler + '  <station id="s" name="last"/>\n')
    doc = load_bytes(data, "big.xodr")
    assert doc.root is not None
    station = doc.root.find("station")
    assert station is not None
    expected = data.decode().splitlines().index('  <station id="s" name="last"/>') + 1
    assert expected > 65_535
    assert doc.line_of(station) == expected
    # libxml2 alone is off past its limit; the scan is what makes this exact
    last_road = doc.root.findall("road")[-1]
    assert doc.line_of(last_road) == expected - 1


def test_line_of_multiline_start_tag_is_where_it_begins() -> None:
    data = _doc(
        '  <road\n     id="1"\n     length="10"/>\n  <!-- <road id="x"/> -->\n'
        "  <![CDATA[ <road> ]]>\r\n  <station id='s'/>\n"
    )
    doc = load_bytes(data.replace(b"<![CDATA[ <road> ]]>", b""), "m.xodr")
    assert doc.root is not None
    road, station = doc.root.find("road"), doc.root.find("station")
    assert road is not None and station is not None
    assert doc.line_of(road) == 4
    assert doc.line_of(station) == 9


def test_crlf_and_comments_containing_tags_do_not_shift_lines() -> None:
    text = '<?xml version="1.0"?>\r\n<!-- <fake/> -->\r\n<OpenDRIVE>\r\n  <header revMajor="1" revMinor="7"/>\r\n  <?pi <no/> ?>\r\n  <road id="1"/>\r\n</OpenDRIVE>'
    doc = load_bytes(text.encode(), "crlf.xodr")
    assert doc.root is not None
    road = doc.root.find("road")
    assert road is not None
    assert doc.line_of(road) == 6


@pytest.mark.parametrize(
    ("encoding", "bom"),
    [
        ("utf-8", codecs.BOM_UTF8),
        ("utf-16-le", codecs.BOM_UTF16_LE),
        ("utf-16-be", codecs.BOM_UTF16_BE),
        ("utf-16-be", b""),  # no byte order mark: the zero byte before '<' tells
        ("utf-16-le", b""),
    ],
)
def test_bom_and_declared_encodings(encoding: str, bom: bytes) -> None:
    label = "UTF-8" if encoding == "utf-8" else "UTF-16"
    text = f'<?xml version="1.0" encoding="{label}"?>\n<OpenDRIVE>\n  {HEADER}\n  <road id="é" length="1"/>\n</OpenDRIVE>\n'
    doc = load_bytes(bom + text.encode(encoding), "enc.xodr")
    assert doc.problems == {}
    assert doc.root is not None
    road = doc.root.find("road")
    assert road is not None and road.get("id") == "é"
    assert doc.line_of(road) == 4


def test_latin1_declaration_is_honoured() -> None:
    text = f'<?xml version="1.0" encoding="ISO-8859-1"?>\n<OpenDRIVE>\n  {HEADER}\n  <road id="Straße"/>\n</OpenDRIVE>'
    doc = load_bytes(text.encode("latin-1"), "latin.xodr")
    assert doc.root is not None and doc.root.find("road") is not None
    road = doc.root.find("road")
    assert road is not None and road.get("id") == "Straße"


def test_legacy_asam_namespace_is_dropped_on_the_tree() -> None:
    data = _doc('  <road id="1"/>\n').replace(
        b"<OpenDRIVE>", f'<OpenDRIVE xmlns="{ASAM_LEGACY_NAMESPACE}">'.encode()
    )
    doc = load_bytes(data, "legacy.xodr")
    assert doc.problems == {}
    assert doc.root is not None
    assert doc.root.tag == "OpenDRIVE" and doc.root.find("road") is not None
    assert doc.declared == Version(1, 7)


def test_truncated_file_gives_exactly_one_xs001_at_every_cut() -> None:
    data = _doc('  <road id="1" length="10"><railroad/></road>\n')
    for cut in range(len(data) - 1):
        doc = load_bytes(data[:cut], "cut.xodr")
        assert list(doc.problems) == ["XS001"], cut
        assert len(doc.problems["XS001"]) == 1, cut
        hit = doc.problems["XS001"][0]
        assert hit.element is None and hit.line is not None and hit.line >= 1


@pytest.mark.parametrize(
    ("data", "fragment"),
    [
        (b"", "empty"),
        (b"   \n\t ", ""),
        (b"\x00\x01\x02\xff\xfe binary", ""),
        (b'<?xml version="1.0"?><OpenDRIVE><header a="&undefined;"/></OpenDRIVE>', "undefined"),
        (b'<?xml version="1.0" encoding="UTF-8"?><OpenDRIVE name="\xff\xfe"/>', ""),
        (b"a,b,c\n1,2,3\n", ""),
    ],
)
def test_unreadable_content_is_one_xs001(data: bytes, fragment: str) -> None:
    doc = load_bytes(data, "bad.xodr")
    assert list(doc.problems) == ["XS001"]
    assert fragment in doc.problems["XS001"][0].message.lower()


def test_entities_are_never_expanded() -> None:
    data = (
        b'<?xml version="1.0"?>\n<!DOCTYPE OpenDRIVE [<!ENTITY a "aaaaaaaaaa">'
        b'<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">'
        b'<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
        b'<OpenDRIVE><header revMajor="1" revMinor="7" name="&b;&x;"/></OpenDRIVE>'
    )
    doc = load_bytes(data, "bomb.xodr")
    header = doc.root.find("header") if doc.root is not None else None
    name = header.get("name") if header is not None else ""
    assert "root:" not in (name or "")
    assert "aaaaaaaaaa" * 10 not in (name or "")


@pytest.mark.parametrize(
    ("root", "message"),
    [("<OpenSCENARIO/>", "'OpenSCENARIO'"), ('<OpenDRIVE xmlns="urn:x"/>', "namespace 'urn:x'")],
)
def test_wrong_root_is_xs002(root: str, message: str) -> None:
    doc = load_bytes(root.encode(), "r.xodr")
    assert list(doc.problems) == ["XS002"]
    assert message in doc.problems["XS002"][0].message


def test_missing_header_is_xs003_and_no_version() -> None:
    doc = load_bytes(b"<OpenDRIVE><road id='1'/></OpenDRIVE>", "h.xodr")
    assert list(doc.problems) == ["XS003"]
    assert doc.declared is None


@pytest.mark.parametrize(
    ("major", "minor", "expected"), [("1", "", 1), ("a", "7", 1), ("1", "-3", 1), ("x", "y", 2)]
)
def test_bad_version_numbers_are_xs004(major: str, minor: str, expected: int) -> None:
    doc = load_bytes(
        f'<OpenDRIVE><header revMajor="{major}" revMinor="{minor}"/></OpenDRIVE>'.encode(), "v"
    )
    assert len(doc.problems["XS004"]) == expected
    assert doc.effective is None


@pytest.mark.parametrize(
    ("declared", "effective"),
    [
        (Version(1, 12), Version(1, 9)),
        (Version(2, 0), Version(1, 9)),
        (Version(1, 0), Version(1, 1)),
        (Version(0, 5), Version(1, 1)),
        (Version(1, 3), Version(1, 3)),
    ],
)
def test_nearest_published_version(declared: Version, effective: Version) -> None:
    assert nearest_published(declared) == effective


def test_readable_xpaths_use_ids_and_positions_only_where_needed() -> None:
    data = _doc(
        '  <road id="3"><lanes><laneSection s="0"/><laneSection s="5"><right><lane id="-1"/>'
        '</right></laneSection></lanes><railroad><switch id="31"><partner id="2"/></switch>'
        '<switch id="31"/></railroad></road>\n  <road id="o\'k&quot;"/>\n'
    )
    doc = load_bytes(data, "x.xodr")
    root = doc.root
    assert root is not None
    lane = root.find("road/lanes/laneSection[2]/right/lane")
    partner = root.find("road/railroad/switch/partner")
    second = root.findall("road/railroad/switch")[1]
    odd = root.findall("road")[1]
    assert lane is not None and partner is not None
    assert (
        doc.xpath_of(lane) == "/OpenDRIVE/road[@id='3']/lanes/laneSection[2]/right/lane[@id='-1']"
    )
    assert doc.xpath_of(partner) == "/OpenDRIVE/road[@id='3']/railroad/switch[@id='31'][1]/partner"
    assert doc.xpath_of(second) == "/OpenDRIVE/road[@id='3']/railroad/switch[@id='31'][2]"
    for element in (lane, partner, second, odd):
        assert root.getroottree().xpath(doc.xpath_of(element)) == [element]
    header = root.find("header")
    assert header is not None and doc.xpath_of(header) == "/OpenDRIVE/header"


def test_every_readable_xpath_leads_back_to_its_element() -> None:
    data = _doc(
        '  <road id="a/b]"><lanes><laneSection/><laneSection><right><lane id="-1"/><lane id="-1"/>'
        '</right></laneSection></lanes></road>\n  <road id="o\'k&quot;/"/>\n'
        '  <road id="[x]"/><road/><road/><controller id="c"/>\n'
    )
    doc = load_bytes(data, "x.xodr")
    root = doc.root
    assert root is not None
    elements = list(root.iter(etree.Element))
    fresh = load_bytes(data, "x.xodr")  # no step named before the first lookup
    for element, again in zip(elements, fresh.root.iter(etree.Element), strict=True):  # type: ignore[union-attr]
        path = doc.xpath_of(element)
        assert doc.element_at(path) is element, path
        assert fresh.element_at(path) is again, path
        assert root.getroottree().xpath(path) == [element]
    for missing in ("/OpenDRIVE/road[@id='zz']", "/Other/road", "road", "", "/OpenDRIVE/road[9]"):
        assert doc.element_at(missing) is None, missing


def test_xpath_steps_are_built_once_per_sibling_group() -> None:
    filler = "".join(f'  <road length="{i}"/>\n' for i in range(3000))
    doc = load_bytes(_doc(filler), "many.xodr")
    assert doc.root is not None
    roads = doc.root.findall("road")
    assert doc.xpath_of(roads[2999]) == "/OpenDRIVE/road[3000]"
    assert doc.root.getroottree().xpath(doc.xpath_of(roads[1234])) == [roads[1234]]
    assert isinstance(roads[0], etree._Element)


def test_a_file_in_the_namespace_of_the_11_and_12_schemas_is_read_without_it() -> None:
    from xodrlint.document.load import load_bytes

    doc = load_bytes(
        b'<OpenDRIVE xmlns="www.vires.com"><header revMajor="1" revMinor="2"/></OpenDRIVE>',
        "vires.xodr",
    )
    assert doc.problems == {}
    assert doc.root is not None and doc.root.tag == "OpenDRIVE"
    assert doc.root[0].tag == "header" and str(doc.declared) == "1.2"


@pytest.mark.parametrize(
    ("inside", "messages"),
    [
        ("\n          <!-- the main line -->\n        ", ["character content is not allowed"]),
        ("\n          <?note x?>\n        ", ["character content is not allowed"]),
        (
            "\n          <extra/>\n        ",
            ["character content is not allowed", "element content is not allowed"],
        ),
    ],
)
def test_blanks_the_schema_counts_stay_in_the_tree(inside: str, messages: list[str]) -> None:
    # an element of empty content may hold no blank either: libxml2's remove_blank_text
    # would drop those beside a comment, a processing instruction or an element child
    from xodrlint.api import lint_bytes

    data = (REPO / "rules" / "SW001" / "valid_crossover.xodr").read_bytes()
    tag = b'<mainTrack id="1" s="30" dir="+"/>'
    assert tag in data
    broken = data.replace(tag, tag[:-2] + b">" + inside.encode() + b"</mainTrack>", 1)
    report = lint_bytes(broken, "a.xodr", select=("XS006",))
    # (libxml2 says "character content" once per blank text node: one finding)
    found = sorted(f.message.split(": ", 1)[1].split(",")[0] for f in report.findings)
    assert found == messages, [f.message for f in report.findings]
