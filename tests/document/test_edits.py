"""Edits of a document's source change what they name and no other byte (issue 33: the
fixes are made of them): every encoding, line end, quote and reference outside an edit
stays as it was read."""

from __future__ import annotations

import codecs

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from xodrlint.document.edits import Edit, EditableSource, EditError, common_ends, common_tail
from xodrlint.document.load import parse_root

SWITCH = (
    '<?xml version="1.0" encoding="{encoding}"?>\n'
    "<OpenDRIVE>\n"
    "  <!-- xodrlint: ignore[SW001] -->\n"
    "  <road id='1' length=\"100\">\n"
    '    <railroad><switch id="10" name="a &amp; b" position="Dynamic">'
    '<partner id="11" name="x&#x41;"/></switch></railroad>\n'
    "  </road>\n"
    "</OpenDRIVE>\n"
)


def _source(data: bytes) -> tuple[EditableSource, etree._Element]:
    root = parse_root(data)
    assert isinstance(root, etree._Element)
    return EditableSource(data, root), root


def _only_inside(before: bytes, after: bytes, edited: bytes) -> None:
    """``after`` is ``before`` with ``edited`` standing in one run of changed bytes."""
    head = 0
    while head < min(len(before), len(after)) and before[head] == after[head]:
        head += 1
    tail = 0
    while tail < min(len(before), len(after)) - head and before[-1 - tail] == after[-1 - tail]:
        tail += 1
    assert edited.find(after[head : len(after) - tail]) >= 0


@pytest.mark.parametrize(
    ("encoding", "mark", "line_end"),
    [
        ("UTF-8", b"", "\n"),
        ("UTF-8", codecs.BOM_UTF8, "\r\n"),
        ("UTF-16", codecs.BOM_UTF16_LE, "\r\n"),
        ("UTF-16", codecs.BOM_UTF16_BE, "\n"),
        ("ISO-8859-1", b"", "\r\n"),
    ],
)
def test_a_value_is_replaced_and_every_other_byte_kept(
    encoding: str, mark: bytes, line_end: str
) -> None:
    text = SWITCH.format(encoding=encoding).replace("\n", line_end).replace("a &amp; b", "Ä & b")
    text = text.replace("Ä & b", "Ä &amp; b")
    codec = {codecs.BOM_UTF16_LE: "utf-16-le", codecs.BOM_UTF16_BE: "utf-16-be"}.get(
        mark, "utf-8" if encoding == "UTF-8" else "latin-1"
    )
    data = mark + text.encode(codec)
    source, root = _source(data)
    switch = root.find("road/railroad/switch")
    assert switch is not None
    fixed = source.apply([source.set_attribute(switch, "position", "dynamic")])
    assert fixed == mark + text.replace('"Dynamic"', '"dynamic"').encode(codec)
    again = parse_root(fixed)
    assert isinstance(again, etree._Element)
    assert again.find("road/railroad/switch").get("name") == "Ä & b"  # type: ignore[union-attr]


def test_a_value_in_single_quotes_is_escaped_for_them() -> None:
    data = SWITCH.format(encoding="UTF-8").encode()
    source, root = _source(data)
    road = root.find("road")
    assert road is not None
    edit = source.set_attribute(road, "id", 'it\'s <1> & "2"\n')
    assert edit.content == 'it&apos;s &lt;1&gt; &amp; "2"&#10;'
    fixed = parse_root(source.apply([edit]))
    assert isinstance(fixed, etree._Element)
    assert fixed.find("road").get("id") == 'it\'s <1> & "2"\n'  # type: ignore[union-attr]


def test_a_character_the_encoding_lacks_becomes_a_reference() -> None:
    data = SWITCH.format(encoding="ISO-8859-1").encode("latin-1")
    source, root = _source(data)
    switch = root.find("road/railroad/switch")
    assert switch is not None
    fixed = source.apply([source.set_attribute(switch, "name", "Łódź")])
    assert b'name="&#321;\xf3d&#378;"' in fixed  # ó is Latin-1's own
    parsed = parse_root(fixed)
    assert isinstance(parsed, etree._Element)
    assert parsed.find("road/railroad/switch").get("name") == "Łódź"  # type: ignore[union-attr]


def test_attributes_on_several_lines_and_a_missing_one() -> None:
    data = (
        b"<OpenDRIVE>\n  <road\n     id = \"1\"\n     length='5'\n  >\n"
        b"    <link/><planView/>\n  </road>\n</OpenDRIVE>\n"
    )
    source, root = _source(data)
    road = root.find("road")
    link = root.find("road/link")
    assert road is not None and link is not None
    length = source.attribute(road, "length")
    assert length is not None and data.decode()[length.start : length.end] == "5"
    assert source.attribute(road, "junction") is None
    fixed = source.apply(
        [source.set_attribute(road, "length", "6"), source.set_attribute(link, "kind", "x")]
    )
    assert fixed == data.replace(b"'5'", b"'6'").replace(b"<link/>", b'<link kind="x"/>')


def test_a_comment_is_found_and_removed_whole() -> None:
    data = SWITCH.format(encoding="UTF-8").encode()
    source, root = _source(data)
    [comment] = root.iter(etree.Comment)
    start, end = source.comment(comment)
    assert source.text[start:end] == "<!-- xodrlint: ignore[SW001] -->"
    fixed = source.apply([Edit(start, end, "")])
    assert fixed == data.replace(b"<!-- xodrlint: ignore[SW001] -->", b"")


def test_overlapping_edits_are_refused() -> None:
    data = SWITCH.format(encoding="UTF-8").encode()
    source, _ = _source(data)
    with pytest.raises(EditError, match="overlapping"):
        source.apply([Edit(10, 20, "a"), Edit(15, 25, "b")])


def test_a_source_that_does_not_read_back_is_not_editable() -> None:
    data = '<?xml version="1.0" encoding="windows-1252"?><a b="\x81"/>'.encode("latin-1")
    root = etree.fromstring(b'<a b="x"/>')
    with pytest.raises(EditError):
        EditableSource(data, root)


# what an attribute may hold: any character XML admits (the C0 controls but tab, line
# feed and carriage return are not characters of XML 1.0, not even as references)
_VALUES = st.text(
    st.one_of(
        st.characters(blacklist_categories=["Cs", "Cc", "Co", "Cn"]),
        st.sampled_from("\t\n\r"),
    ),
    max_size=12,
)


@settings(max_examples=60, deadline=None)
@given(value=_VALUES, quote=st.sampled_from(["'", '"']), crlf=st.booleans())
def test_any_value_round_trips_and_only_its_bytes_change(
    value: str, quote: str, crlf: bool
) -> None:
    line_end = "\r\n" if crlf else "\n"
    text = f"<OpenDRIVE>{line_end}  <road id={quote}1{quote} length='2'/>{line_end}</OpenDRIVE>"
    data = text.encode()
    source, root = _source(data)
    road = root.find("road")
    assert road is not None
    fixed = source.apply([source.set_attribute(road, "id", value)])
    parsed = parse_root(fixed)
    assert isinstance(parsed, etree._Element)
    assert parsed.find("road").get("id") == value  # type: ignore[union-attr]
    _only_inside(data, fixed, source.escaped(value, quote).encode())


def test_markup_that_holds_a_start_tag_is_skipped() -> None:
    # an entity's value, a CDATA section and a processing instruction may hold "<a" and
    # "]>": none of them is a start tag, and the comments around the root are paired
    data = (
        b"<!-- before -->\n"
        b"<!DOCTYPE OpenDRIVE [<!ENTITY e \"]><road id='9'><!--\"><!-- ]> -->]>\n"
        b'<OpenDRIVE><?pi <road id="8"?><road id="1"><![CDATA[<road id="7">]]></road>'
        b"<!-- inside --></OpenDRIVE>\n<!-- after -->\n"
    )
    source, root = _source(data)
    road = root.find("road")
    assert road is not None
    fixed = source.apply([source.set_attribute(road, "id", "2")])
    assert fixed == data.replace(b'<road id="1">', b'<road id="2">')
    comments = [*root.itersiblings(etree.Comment, preceding=True), *root.iter(etree.Comment)]
    comments += root.itersiblings(etree.Comment)
    texts = [source.text[slice(*source.comment(c))] for c in comments]
    assert texts == ["<!-- before -->", "<!-- inside -->", "<!-- after -->"]


def test_the_positions_skip_such_markup_too() -> None:
    from xodrlint.document.positions import SourcePositions

    data = b"<!DOCTYPE a [<!ENTITY e \"]><b x='1'/>\">]>\n<a>\n  <b/>\n</a>\n"
    root = parse_root(data)
    assert isinstance(root, etree._Element)
    positions = SourcePositions(data, root, "UTF-8")
    assert positions.position_of(root) == (2, 1)
    assert positions.position_of(root[0]) == (3, 3)


def test_utf_32_and_a_prefixed_attribute() -> None:
    text = '<a xmlns:p="urn:p" p:id="1" id="0"/>'
    for codec in ("utf-32-le", "utf-32-be"):
        data = text.encode(codec)
        source, root = _source(data)
        fixed = source.apply([source.set_attribute(root, "p:id", "2")])
        assert fixed == text.replace('p:id="1"', 'p:id="2"').encode(codec)


def test_an_encoding_python_and_libxml2_may_read_apart_gets_references() -> None:
    # Shift_JIS's byte for a backslash is libxml2's yen sign: every character but plain
    # ASCII is written as a reference, which reads back the same everywhere
    data = '<?xml version="1.0" encoding="Shift_JIS"?><a x="日"/>'.encode("shift_jis")
    source, root = _source(data)
    fixed = source.apply([source.set_attribute(root, "x", "\\~本")])
    assert fixed.endswith(b'<a x="&#92;&#126;&#26412;"/>')
    parsed = parse_root(fixed)
    assert isinstance(parsed, etree._Element) and parsed.get("x") == "\\~本"


def test_only_the_xml_declaration_names_the_encoding() -> None:
    # a processing instruction whose target starts with "xml" says nothing of it
    data = '<?xml-stylesheet href="a.xsl" encoding="ISO-8859-1"?>\n<a x="é"/>'.encode()
    source, root = _source(data)
    fixed = source.apply([source.set_attribute(root, "x", "ü")])
    assert fixed == data.replace("é".encode(), "ü".encode())


def test_xml_blanks_only_separate_attributes() -> None:
    # U+1680 is a blank to Python's \s, and a name character to XML
    data = '<a x\u1680y="1" id="5"/>'.encode()
    source, root = _source(data)
    fixed = source.apply([source.set_attribute(root, "id", "6")])
    assert fixed == data.replace(b'"5"', b'"6"')


@pytest.mark.parametrize(
    ("data", "reason"),
    [
        (b'<?xml version="1.0" encoding="WINDOWS-874"?><a/>', "not one Python writes"),
        (b'<?xml version="1.0" encoding="ISO-2022-JP"?><a/>', "byte for byte"),
    ],
)
def test_a_source_that_cannot_be_edited_byte_for_byte_is_refused(data: bytes, reason: str) -> None:
    root = parse_root(data)
    assert isinstance(root, etree._Element)
    with pytest.raises(EditError, match=reason):
        EditableSource(data, root)


@pytest.mark.parametrize(
    ("name", "value"),
    [
        ("x", "\x00"),
        ("x", "a\x1fb"),
        ("x", "\ud800"),
        ("x", "\uffff"),
        ("{urn:p}id", "1"),
        ("bad name", "1"),
        ("Ł", "1"),
    ],
)
def test_what_the_file_could_not_hold_is_refused(name: str, value: str) -> None:
    data = b'<?xml version="1.0" encoding="ISO-8859-1"?><a x="1"/>'
    source, root = _source(data)
    with pytest.raises(EditError):
        source.set_attribute(root, name, value)


def test_an_edit_the_encoding_cannot_write_is_an_edit_error() -> None:
    data = b'<?xml version="1.0" encoding="ISO-8859-1"?><a x="1"/>'
    source, _ = _source(data)
    with pytest.raises(EditError, match="cannot write"):
        source.apply([Edit(len(source.text), len(source.text), "<!-- \u0141 -->")])


# --- the edits fixes are made of (comments, insertions, places) --------------------------

STATIONS = (
    "<OpenDRIVE>\r\n"
    "  <!-- alone -->\r\n"
    "  <station id='S1'> <!-- first -->  <platform id='P1'>"
    "<segment side='left'/></platform></station>\r\n"
    "  <station id='S2'/>  <!-- last -->\r\n"
    "  <switch id='W'>\r\n"
    "    <mainTrack id='1'/>\r\n"
    "    <sideTrack id='2'><!-- a </sideTrack> in a comment --></sideTrack>\r\n"
    "  </switch>\r\n"
    "</OpenDRIVE>\r\n"
)


def _comments(root: etree._Element) -> dict[str, etree._Element]:
    return {(c.text or "").strip(): c for c in root.iter(etree.Comment)}


def test_a_removed_comment_takes_its_line_or_the_blanks_beside_it() -> None:
    data = STATIONS.encode()
    source, root = _source(data)
    comments = _comments(root)
    alone = source.apply([source.comment_edit(comments["alone"], None)])
    assert alone == data.replace(b"  <!-- alone -->\r\n", b"")
    first = source.apply([source.comment_edit(comments["first"], None)])
    assert first == data.replace(b"<!-- first -->  ", b"")
    last = source.apply([source.comment_edit(comments["last"], None)])
    assert last == data.replace(b"  <!-- last -->", b"")


def test_a_comment_rewritten_changes_only_what_differs() -> None:
    data = b"<a><!-- xodrlint: ignore[X,\r\n Y] why --></a>"
    source, root = _source(data)
    (comment,) = root.iter(etree.Comment)
    assert comment.text == " xodrlint: ignore[X,\n Y] why "
    edit = source.comment_edit(comment, " xodrlint: ignore[X] why ")
    assert source.apply([edit]) == b"<a><!-- xodrlint: ignore[X] why --></a>"
    kept_break = source.comment_edit(comment, " xodrlint: ignore[X,\n Z] why ")
    assert source.apply([kept_break]) == b"<a><!-- xodrlint: ignore[X,\r\n Z] why --></a>"
    with pytest.raises(EditError):
        source.comment_edit(comment, "a -- b")


def test_an_element_is_inserted_on_its_own_line_indented_as_its_sibling() -> None:
    data = STATIONS.encode()
    source, root = _source(data)
    side = root.find("switch/sideTrack")
    assert side is not None
    edit = source.insert_element(side, "partner", [("id", "X & Y"), ("name", "n")], "after")
    after = source.apply([edit])
    assert after == data.replace(
        b"in a comment --></sideTrack>\r\n",
        b'in a comment --></sideTrack>\r\n    <partner id="X &amp; Y" name="n"/>\r\n',
    )
    main = root.find("switch/mainTrack")
    assert main is not None
    before = source.apply([source.insert_element(main, "x", [], "before")])
    assert before == data.replace(b"    <mainTrack", b"    <x/>\r\n    <mainTrack")
    # an anchor that shares its line: the new element stands beside it
    platform = root.find("station/platform")
    assert platform is not None
    beside = source.apply([source.insert_element(platform, "y", [], "after")])
    assert beside == data.replace(b"</platform>", b"</platform><y/>")


def test_an_edit_is_placed_in_lines_and_columns_as_findings_are() -> None:
    data = codecs.BOM_UTF8 + "<a>\r\n <b c='é'/>\r<d/></a>".encode()
    source, root = _source(data)
    d = root.find("d")
    b = root.find("b")
    assert d is not None and b is not None
    assert source.position(source.start_tag(root)[0]) == (1, 1)  # the mark is no character
    assert source.position(source.start_tag(b)[0]) == (2, 2)
    assert source.position(source.start_tag(d)[0]) == (3, 1)
    placed = source.placed(source.set_attribute(b, "c", "e"))
    assert (placed.start_line, placed.start_column, placed.end_column) == (2, 8, 9)


def test_a_first_line_comment_after_a_byte_order_mark_goes_with_its_line() -> None:
    data = codecs.BOM_UTF8 + b"<!-- c -->\r\n<a/>"
    source, root = _source(data)
    (comment,) = list(root.itersiblings(etree.Comment, preceding=True))
    assert source.apply([source.comment_edit(comment, None)]) == codecs.BOM_UTF8 + b"<a/>"


def test_children_inserted_beside_other_markup_stand_beside_each_other() -> None:
    data = b"<road><planView/></road>"
    source, root = _source(data)
    plan = root.find("planView")
    assert plan is not None
    edit = source.insert_element(plan, "link", [], "before", [("predecessor", [("a", "1")])])
    assert source.apply([edit]) == b'<road><link><predecessor a="1"/></link><planView/></road>'


def test_common_ends_never_count_a_character_twice() -> None:
    assert common_ends("abcabc", "abc") == (3, 0)
    assert common_ends("aXb", "aYb") == (1, 1)
    assert common_ends("aaa", "aaaa") == (3, 0)
    assert common_ends("", "x") == (0, 0)
    assert common_ends("same", "same") == (4, 0)
    # the tail alone, past a head the caller chose
    assert common_tail("\r\n", "\r\r\n", 0) == 2 and common_tail("\r\n", "\r\r\n", 1) == 1
