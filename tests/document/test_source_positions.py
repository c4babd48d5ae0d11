"""Source positions: the line and column of every element's '<', exact or ``None``.

The oracle is independent of the scan: each element of a test document carries a
``k="N"`` attribute no other element has, so its '<' is found in the decoded text by a
search for its name and that attribute, decoys in comments, CDATA and processing
instructions being numbered apart.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from xodrlint.document.load import Document, load_bytes
from xodrlint.document.positions import LIBXML2_LINE_CAP, SourcePositions, parser_line

HEADER = '<header k="header" revMajor="1" revMinor="7"/>'


def _text(body: str, declaration: str = '<?xml version="1.0" encoding="UTF-8"?>\n') -> str:
    return f'{declaration}<OpenDRIVE k="root">\n  {HEADER}\n{body}</OpenDRIVE>\n'


def _expected(text: str, element: etree._Element) -> tuple[int, int]:
    """Where the '<' of ``element`` stands in ``text``, found by its unique ``k``."""
    name = etree.QName(element).localname
    found = re.search(rf'<(?:\w+:)?{name}\s+k="{element.get("k")}"', text)
    assert found is not None, element.get("k")
    start = found.start()
    line_start = text.rfind("\n", 0, start) + 1
    return text.count("\n", 0, start) + 1, start - line_start + 1


def _marked(doc: Document) -> Iterator[etree._Element]:
    assert doc.root is not None, doc.problems
    yield from (el for el in doc.root.iter(etree.Element) if el.get("k") is not None)


def _assert_exact(doc: Document, text: str) -> int:
    checked = 0
    for element in _marked(doc):
        assert doc.position_of(element) == _expected(text, element), element.get("k")
        assert doc.line_of(element) == doc.position_of(element)[0]
        checked += 1
    return checked


def test_a_start_tag_over_several_lines_is_where_its_less_than_sign_stands() -> None:
    text = _text(
        '  <road\n     k="1"\n     length="10"/>\n  <station k="2"\n   id="s"></station>\n'
    )
    doc = load_bytes(text.encode(), "multi.xodr")
    assert doc.root is not None
    road = doc.root.find("road")
    assert road is not None
    assert doc.position_of(road) == (4, 3)
    # libxml2 alone names the line where the start tag ends, and no column at all
    assert parser_line(road) == 6
    assert _assert_exact(doc, text) == 4


def test_several_start_tags_on_one_line_each_get_their_own_column() -> None:
    text = _text('  <road k="1"><lanes k="2"/><lanes k="3"/></road><road k="4"/><road k="5"/>\n')
    doc = load_bytes(text.encode(), "minified.xodr")
    roads = list(_marked(doc))[2:]
    assert [doc.position_of(el) for el in roads] == [(4, 3), (4, 15), (4, 29), (4, 50), (4, 63)]
    _assert_exact(doc, text)


def test_comments_cdata_and_processing_instructions_hide_their_less_than_signs() -> None:
    text = _text(
        '  <!-- <road k="decoy1"/> --><road k="1"><![CDATA[ <road k="decoy2"> ]]></road>'
        '<?pi <road k="decoy3"/> ?><road k="2" name="a &lt;road k=&quot;decoy4&quot; >"/>\n'
        '  <road k="3" name="&lt;road"/><!--<road k="decoy5">--><road k="4"/>\n'
    )
    doc = load_bytes(text.encode(), "decoys.xodr")
    roads = [el for el in _marked(doc) if el.tag == "road"]
    assert [doc.position_of(el) for el in roads] == [(4, 30), (4, 106), (5, 3), (5, 56)]
    assert _assert_exact(doc, text) == 6


def test_non_ascii_text_before_a_tag_counts_characters_not_bytes() -> None:
    text = _text(
        '  <userData k="1" value="Straße — 東京 🚆"/><road k="2"/>\n'
        '  <!-- Überweg ✓ --><road k="3" name="Zürich"/>\n'
    )
    doc = load_bytes(text.encode(), "utf8.xodr")
    roads = [el for el in _marked(doc) if el.tag == "road"]
    # '  <userData k="1" value="Straße — 東京 🚆"/>' is 41 characters (51 bytes)
    assert [doc.position_of(el) for el in roads] == [(4, 42), (5, 21)]
    _assert_exact(doc, text)


def test_a_byte_order_mark_is_no_column() -> None:
    text = '<OpenDRIVE k="root"><header k="header" revMajor="1" revMinor="7"/></OpenDRIVE>'
    doc = load_bytes(b"\xef\xbb\xbf" + text.encode(), "bom.xodr")
    assert [doc.position_of(el) for el in _marked(doc)] == [(1, 1), (1, 21)]


@pytest.mark.parametrize(
    ("codec", "label", "bom"),
    [
        ("utf-8", "UTF-8", b""),
        ("utf-16-le", "UTF-16", b"\xff\xfe"),
        ("utf-16-be", "UTF-16", b"\xfe\xff"),
        ("utf-16-le", "UTF-16", b""),
        ("iso-8859-1", "ISO-8859-1", b""),
        ("cp1252", "windows-1252", b""),
        ("shift_jis", "Shift_JIS", b""),
    ],
)
def test_other_encodings_give_exact_columns(codec: str, label: str, bom: bytes) -> None:
    accented = "東京駅" if codec == "shift_jis" else "Straße €" if codec == "cp1252" else "Straße"
    text = _text(
        f'  <road k="1" name="{accented}"/><road k="2"/>\r\n  <!-- {accented} --><road k="3"/>\n',
        f'<?xml version="1.0" encoding="{label}"?>\n',
    )
    doc = load_bytes(bom + text.encode(codec), f"{codec}.xodr")
    assert doc.problems == {}
    assert _assert_exact(doc, text.replace("\r\n", "\n")) == 5


def test_an_encoding_that_shifts_state_gives_no_column_but_the_line() -> None:
    text = _text(
        '  <road k="1" name="東京"/><road k="2"/>\n',
        '<?xml version="1.0" encoding="ISO-2022-JP"?>\n',
    )
    doc = load_bytes(text.encode("iso2022_jp"), "jis.xodr")
    assert doc.problems == {}
    for element in _marked(doc):
        line, _ = _expected(text, element)
        assert doc.position_of(element) == (line, None)


def test_positions_stay_exact_past_libxml2s_line_limit() -> None:
    filler = "".join(f'  <road id="{i}" length="1"/>\n' for i in range(70_000))
    text = _text(
        filler + '  <!-- <road k="decoy"/> --><road k="1" name="é"/><station\n    k="2"/>\n'
    )
    doc = load_bytes(text.encode(), "big.xodr")
    road, station = list(_marked(doc))[2:]
    line = text.count("\n", 0, text.index('<road k="1"')) + 1
    assert line > LIBXML2_LINE_CAP
    assert doc.position_of(road) == (line, 29)
    assert doc.position_of(station) == (line, 51)
    # libxml2's own lines are a guess this far down (the line of some node after them)
    assert (parser_line(road), parser_line(station)) != (line, line)


def test_a_minified_map_on_one_long_line_gives_exact_columns() -> None:
    # far longer than the blocks the index counts in, with characters of 2, 3 and 4 bytes
    roads = "".join(f'<road k="{i}" name="{"äß東🚆"[i % 4] * (i % 7)}"/>' for i in range(3000))
    text = f'<OpenDRIVE k="root">{HEADER}{roads}</OpenDRIVE>'
    doc = load_bytes(text.encode(), "one-line.xodr")
    assert _assert_exact(doc, text) == 3002


def test_an_entity_value_holding_a_start_tag_is_no_start_tag() -> None:
    # an entity value may hold "]>" and a '<': the scan reads the declaration's quoted
    # strings whole, so it ends where the parser's does
    text = _text('  <road k="1"/><road k="2"\n  />\n').replace(
        "<OpenDRIVE", '<!DOCTYPE OpenDRIVE [<!ENTITY odd "]><fake/>">]>\n<OpenDRIVE', 1
    )
    doc = load_bytes(text.encode(), "doctype.xodr")
    assert doc.problems == {}
    assert _assert_exact(doc, text) == 4


def test_a_scan_that_disagrees_with_the_tree_gives_libxml2s_lines_and_no_column() -> None:
    # one start tag more than the tree has elements: no position is then trusted
    root = etree.fromstring(b"<a>\n<b/>\n</a>")
    positions = SourcePositions(b"<a>\n<b/><c/>\n</a>", root, "UTF-8")
    for element in (root, root[0]):
        assert positions.position_of(element) == (parser_line(element), None)


def test_a_start_tag_of_another_name_gives_no_position() -> None:
    root = etree.fromstring(b"<a><b/></a>")
    positions = SourcePositions(b"<a><c/></a>", root, "UTF-8")
    assert positions.position_of(root) == (1, 1)
    assert positions.position_of(root[0]) == (1, None)


def test_a_prefixed_start_tag_is_found_by_its_local_name() -> None:
    text = _text('  <o:road k="1" xmlns:o="urn:x"/><road k="2"/>\n')
    doc = load_bytes(text.encode(), "prefixed.xodr")
    assert _assert_exact(doc, text) == 4


def test_a_comment_stands_where_its_opening_does() -> None:
    text = (
        _text(
            '  <road k="1"/><!-- é <road k="d1"/> --><!--second-->\n  <![CDATA[<!-- no -->]]>\n'
            "  <?pi <!-- no --> ?><!-- third -->\n",
            '<?xml version="1.0"?>\n<!-- before the root -->\n',
        )
        + "<!-- after it -->\n"
    )
    doc = load_bytes(text.encode(), "comments.xodr")
    assert doc.root is not None
    comments = [
        *doc.root.itersiblings(etree.Comment, preceding=True),
        *doc.root.iter(etree.Comment),
        *doc.root.itersiblings(etree.Comment),
    ]
    assert [doc.position_of(c) for c in comments] == [(2, 1), (5, 16), (5, 41), (7, 22), (9, 1)]


def test_a_processing_instruction_has_a_line_and_no_column() -> None:
    doc = load_bytes(_text('  <?pi data?>\n  <road k="1"/>\n').encode(), "pi.xodr")
    assert doc.root is not None
    instruction = doc.root[1]
    assert isinstance(instruction, etree._ProcessingInstruction)
    assert doc.position_of(instruction) == (4, None)


_PIECES = st.sampled_from(
    [
        "element",
        "element over lines",
        "decoy comment",
        "decoy cdata",
        "decoy pi",
        "text",
        "newline",
        "crlf",
        "lone cr",
        "awkward attribute",
    ]
)
# Characters well-formed XML takes in text, attribute values and comments alike, in
# runs of one, two, three and four bytes of UTF-8.
_TEXT = st.text(
    st.characters(codec="latin-1", exclude_categories=["Cc"], exclude_characters='<&]"-')
    | st.sampled_from("\t é東🚆—"),
    max_size=6,
)


def _piece(kind: str, number: int, text: str) -> str:
    return {
        "element": f'<road k="{number}"/>',
        "element over lines": f'<road\n  k="{number}"\n  name="{text}"\n/>',
        "decoy comment": f'<!-- <road k="d{number}"/> {text} -->',
        "decoy cdata": f'<![CDATA[<road k="d{number}"> {text}]]>',
        "decoy pi": f'<?pi <road k="d{number}"/> ?>',
        "text": text,
        "newline": "\n",
        "crlf": "\r\n",
        "lone cr": "\r",
        "awkward attribute": f'<road k="{number}" a="&lt;road k=&quot;d{number}&quot; >"/>',
    }[kind]


@settings(max_examples=60, deadline=None)
@given(
    pieces=st.lists(st.tuples(_PIECES, _TEXT), max_size=40),
    codec=st.sampled_from(["utf-8", "utf-16-le", "utf-16-be", "iso-8859-1"]),
)
def test_every_position_is_exact_whatever_the_markup_around_it(
    pieces: list[tuple[str, str]], codec: str
) -> None:
    body = "".join(_piece(kind, number, text) for number, (kind, text) in enumerate(pieces))
    label = {"utf-16-le": "UTF-16", "utf-16-be": "UTF-16"}.get(codec, codec.upper())
    text = _text(body + "\n", f'<?xml version="1.0" encoding="{label}"?>\n')
    try:
        data = ("\ufeff" if codec.startswith("utf-16") else "") + text
        encoded = data.encode(codec)
    except UnicodeEncodeError:
        return  # a character the encoding has not got: nothing to read back
    doc = load_bytes(encoded, f"{codec}.xodr")
    assert doc.problems == {}
    _assert_exact(doc, text.replace("\r\n", "\n").replace("\r", "\n"))


def test_a_lone_carriage_return_ends_a_line_as_editors_count_it() -> None:
    # a file of old Mac line ends was one line of libxml2's: every finding on line 1 at a
    # column in the thousands, and nowhere in an editor (the language server's lines)
    text = _text('  <road k="1"/>\r  <road\r k="2"/>\r\n  <road k="3"/>\r')
    doc = load_bytes(text.encode(), "mac.xodr")
    assert _assert_exact(doc, text.replace("\r\n", "\n").replace("\r", "\n")) == 5
    assert doc.source_line(4) == '  <road k="1"/>'


@pytest.mark.parametrize("line_end", ["\r", "\r\n", "\n"])
def test_a_syntax_error_is_where_an_editor_shows_it_whatever_the_line_ends(
    line_end: str,
) -> None:
    # libxml2 counts no lone "\r": its line and column are counted again as the lines are
    lines = ['<?xml version="1.0"?>', "<OpenDRIVE>", '  <header revMajor="1" revMinor="7"/>']
    text = line_end.join([*lines, "  <road id=1/>", "</OpenDRIVE>", ""])
    doc = load_bytes(text.encode(), "broken.xodr")
    (hit,) = doc.problems["XS001"]
    assert (hit.line, hit.column) == (4, 12)
    assert doc.source_line(4) == "  <road id=1/>"
