"""Edits of a document's source change what they name and no other byte (issue 33: the
fixes are made of them): every encoding, line end, quote and reference outside an edit
stays as it was read."""

from __future__ import annotations

import codecs

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree

from xodrlint.document.edits import Edit, EditableSource, EditError
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
