"""Element positions: the same answers as lxml's own lookups, each parent's children listed
once however many elements below it are asked about (linear in the findings)."""

from __future__ import annotations

from lxml import etree

from xodrlint.concurrency.background import receive_hits, send_hits
from xodrlint.document.positions import (
    TreePositions,
    decode_wide,
    lines_of,
    lines_with_breaks,
    wide_encoding,
)
from xodrlint.findings import Hit
from xodrlint.validation.libxml2 import _ElementLocator
from xodrlint.validation.messages import Explained

DOCUMENT = (
    b"<OpenDRIVE><header/><!-- c -->"
    + b"".join(
        b'<road id="%d"><type/><type/><railroad><switch/></railroad></road>' % n for n in range(300)
    )
    + b"<station/></OpenDRIVE>"
)


class CountingPositions(TreePositions):
    def __init__(self) -> None:
        super().__init__()
        self.listed: list[etree._Element] = []

    def children(self, parent: etree._Element) -> list[etree._Element]:
        if parent not in self._children:
            self.listed.append(parent)
        return super().children(parent)


def test_positions_match_lxml() -> None:
    root = etree.fromstring(DOCUMENT)
    positions = TreePositions()
    for element in root.iter():
        parent = element.getparent()
        if parent is not None:
            assert positions.index_of(element) == parent.index(element)
            assert positions.child(parent, parent.index(element)) is element
        steps = positions.steps_to(element, root)
        assert steps is not None and positions.path_from(root, steps) is element
    assert positions.index_of(root) is None
    assert positions.child(root, 10_000) is None


def test_libxml2_paths_are_walked_as_libxml2_writes_them() -> None:
    root = etree.fromstring(DOCUMENT)
    positions = TreePositions()
    tree = root.getroottree()
    for element in root.iter(etree.Element):
        assert positions.libxml2_path(root, tree.getpath(element)) is element
    assert positions.libxml2_path(root, "/OpenDRIVE/road[301]") is None
    assert positions.libxml2_path(root, "/OpenDRIVE/nothing") is None
    assert positions.libxml2_path(root, "/OpenDRIVE/road[3]/@id") is False  # for XPath
    assert positions.libxml2_path(root, "") is None


def test_finding_many_siblings_lists_each_parent_once() -> None:
    root = etree.fromstring(DOCUMENT)
    switches = list(root.iter("switch"))
    positions = CountingPositions()
    tree = root.getroottree()
    for switch in switches:
        assert positions.libxml2_path(root, tree.getpath(switch)) is switch
    # the root, and each road and railroad on the way: never the root twice
    assert len(positions.listed) == len(set(positions.listed)) == 1 + 2 * len(switches)
    again = CountingPositions()
    for switch in switches:
        again.steps_to(switch, root)
    assert len(again.listed) == len(set(again.listed))


def test_the_schema_stage_finds_elements_by_path() -> None:
    root = etree.fromstring(DOCUMENT)
    locator = _ElementLocator(root)
    why = Explained("x", "other", None)
    road = root[300]
    assert locator.find("/OpenDRIVE/road[299]", why, 1) is road
    assert locator.find("/OpenDRIVE/road[299]/railroad/switch", why, 1) is road[2][0]


def test_hits_cross_a_fork_as_positions() -> None:
    root = etree.fromstring(DOCUMENT)
    hits = [Hit(switch, "m") for switch in root.iter("switch")] + [Hit(None, "n", line=3)]
    back = receive_hits(send_hits(hits, root), root)
    assert [hit.element for hit in back] == [hit.element for hit in hits]
    assert back[-1].line == 3


def test_lines_break_where_xml_breaks_them() -> None:
    # "\r\n", "\n" and a lone "\r"; not U+2028 or NEL, where splitlines breaks too
    text = "a\r\nb\rc\u2028d\x85e\nf"
    assert lines_of(text) == ["a", "b", "c\u2028d\x85e", "f"]
    assert lines_with_breaks(text) == ["a\r\n", "b\r", "c\u2028d\x85e\n", "f"]
    assert lines_with_breaks("a\n\n") == ["a\n", "\n"] and lines_of("a\n\n") == ["a", "", ""]
    assert lines_with_breaks("") == [] and lines_of("") == [""]


def test_one_sniffer_tells_utf16_and_utf32_with_and_without_a_mark() -> None:
    text = '<?xml version="1.0"?>\n<OpenDRIVE/>'
    for codec in ("utf-16-le", "utf-16-be", "utf-32-le", "utf-32-be"):
        plain = text.encode(codec)
        marked = "\ufeff".encode(codec) + plain
        assert wide_encoding(plain) == (codec, 0)
        assert wide_encoding(marked) == (codec, len(marked) - len(plain))
        assert decode_wide(plain, (codec, 0)) == text == decode_wide(marked, (codec, 0))[1:]
        assert decode_wide(marked, (codec, len(marked) - len(plain))) == text
    for eight_bit in (text.encode(), b"\xef\xbb\xbf" + text.encode(), b"<", b""):
        assert wide_encoding(eight_bit) is None
