"""Byte-exact edits of a document's source: what a fix changes, and nothing else.

A fix is a list of edits on the source as it was read: the value of one attribute
replaced, a run of text removed or inserted. The document is never serialised again:
everything outside the edits keeps its bytes (the encoding and its byte order mark, line
ends, attribute order and quotes, character references, comments, blanks).

:class:`EditableSource` decodes the bytes as the file's encoding says, in a form that
encodes back to exactly the same bytes (a byte order mark stays a character of the
text), and finds each element's start tag and each comment in that text the way the
positions of findings do: the k-th start tag of the text is the k-th element of the
tree. A source whose text would not encode back to its bytes is not editable, nor one in an
encoding whose bytes depend on what came before (ISO-2022, UTF-7: re-encoding would
change bytes outside the edits). Build it from the bytes and the tree as parsed, before
any include joins the tree (its elements are no start tags of this source).
"""

from __future__ import annotations

import codecs
import re
from collections.abc import Iterable
from typing import Final, NamedTuple

from lxml import etree

from xodrlint.document.positions import MARKUP_PATTERN, document_comments


class Edit(NamedTuple):
    """Replace the text from ``start`` to ``end`` (offsets in characters of the decoded
    source, ``end`` excluded) with ``content``; an insertion has ``start == end``."""

    start: int
    end: int
    content: str


class AttributeSpan(NamedTuple):
    """Where an attribute's value stands in a start tag: between its quotes."""

    start: int
    end: int
    quote: str


class EditError(ValueError):
    """An edit that cannot be made: overlapping edits, an element or attribute the source
    does not show where the tree has it, a source that cannot be edited."""


#: A start tag's ``<``, or markup in which a ``<`` starts no element (as the positions
#: scan reads the bytes); a comment is matched whole.
_MARKUP: Final = re.compile(MARKUP_PATTERN.decode("ascii"), re.DOTALL)
#: One attribute of a start tag: its name, blanks, ``=``, blanks and its quoted value
#: (XML's blanks are these four; Python's ``\s`` takes more, some of them name characters).
_ATTRIBUTE: Final = re.compile(
    r"[ \t\r\n]*([^ \t\r\n=/>]+)[ \t\r\n]*=[ \t\r\n]*(?:\"([^\"]*)\"|'([^']*)')"
)
_TAG_NAME: Final = re.compile(r"<([^ \t\r\n/>]+)")
#: An attribute name as a source spells it (a prefix is written as it is, never lxml's
#: ``{namespace}`` form).
_NAME: Final = re.compile(r"[^\W\d][\w.\-]*(?::[^\W\d][\w.\-]*)?")
#: Characters XML 1.0 admits nowhere, not even as a reference.
_NOT_XML: Final = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")
#: Codecs whose bytes Python and libxml2 (iconv) map to the same characters, in both
#: directions: a value's characters are written as themselves in these, as character
#: references in any other (Shift_JIS's backslash is libxml2's yen sign).
_AGREEING: Final = frozenset(
    {
        "utf-8",
        "utf-16-le",
        "utf-16-be",
        "utf-32-le",
        "utf-32-be",
        "ascii",
        "iso8859-1",
        "iso8859-15",
        "cp1251",
        "cp1252",
        "koi8-r",
    }
)
#: Codecs whose bytes for a character depend on those before it.
_STATEFUL: Final = ("iso2022", "utf-7", "hz")
_BOMS: Final = (
    (codecs.BOM_UTF32_LE, "utf-32-le"),
    (codecs.BOM_UTF32_BE, "utf-32-be"),
    (codecs.BOM_UTF8, "utf-8"),
    (codecs.BOM_UTF16_LE, "utf-16-le"),
    (codecs.BOM_UTF16_BE, "utf-16-be"),
)


class EditableSource:
    """A document's source as text that encodes back to its very bytes, with the places
    of its elements' start tags and of its comments."""

    def __init__(self, data: bytes, root: etree._Element) -> None:
        self.codec = _codec_of(data, root.getroottree().docinfo.encoding)
        if any(self.codec.startswith(stateful) for stateful in _STATEFUL):
            raise EditError(f"a file in {self.codec} cannot be edited byte for byte")
        try:
            self.text = data.decode(self.codec)
            exact = self.text.encode(self.codec) == data
        except (UnicodeError, LookupError) as error:
            raise EditError(f"the file cannot be edited as {self.codec}: {error}") from error
        if not exact:
            raise EditError(f"the file does not read back byte for byte as {self.codec}")
        tags: list[int] = []
        comments: list[int] = []
        for found in _MARKUP.finditer(self.text):
            if found.end() - found.start() == 1:
                tags.append(found.start())
            elif self.text.startswith("<!--", found.start()):
                comments.append(found.start())
        elements = list(root.iter(etree.Element))
        every_comment = document_comments(root)
        if len(tags) != len(elements) or len(comments) != len(every_comment):
            raise EditError("the source's markup does not match its tree")
        self._tags = dict(zip(elements, tags, strict=True))
        self._comments = dict(zip(every_comment, comments, strict=True))

    def start_tag(self, element: etree._Element) -> tuple[int, int]:
        """Where ``element``'s start tag stands: from its ``<`` to after its ``>``."""
        start = self._tags.get(element)
        if start is None:
            raise EditError("the element is not one of the source's")
        found = _TAG_NAME.match(self.text, start)
        local = etree.QName(element).localname
        if found is None or found[1].rpartition(":")[2] != local:
            raise EditError(f"the source has no start tag of '{local}' where the tree has it")
        end = _tag_end(self.text, found.end())
        return start, end

    def attribute(self, element: etree._Element, name: str) -> AttributeSpan | None:
        """Where the value of ``element``'s attribute ``name`` stands; ``None`` when the
        start tag has no such attribute."""
        start, end = self.start_tag(element)
        at = _TAG_NAME.match(self.text, start)
        assert at is not None  # start_tag found it
        position = at.end()
        while True:
            found = _ATTRIBUTE.match(self.text, position, end)
            if found is None:
                return None
            if found[1] == name:
                group = 2 if found[2] is not None else 3
                quote = '"' if group == 2 else "'"
                return AttributeSpan(found.start(group), found.end(group), quote)
            position = found.end()

    def comment(self, comment: etree._Element) -> tuple[int, int]:
        """Where ``comment`` stands: from its ``<!--`` to after its ``-->``."""
        start = self._comments.get(comment)
        if start is None:
            raise EditError("the comment is not one of the source's")
        end = self.text.find("-->", start + 4)
        if end < 0:
            raise EditError("the comment has no end")
        return start, end + 3

    def set_attribute(self, element: etree._Element, name: str, value: str) -> Edit:
        """The edit that sets ``element``'s attribute ``name`` (as the source spells it,
        with its prefix) to ``value``: its value replaced between its quotes, or the
        attribute added at the end of the start tag, written in double quotes, when the
        tag has none."""
        if _NAME.fullmatch(name) is None or not self._holds(name):
            raise EditError(f"'{name}' is no attribute name this file can hold")
        span = self.attribute(element, name)
        if span is not None:
            return Edit(span.start, span.end, self.escaped(value, span.quote))
        _, end = self.start_tag(element)
        closing = end - 2 if self.text[end - 2 : end] == "/>" else end - 1
        # after the last attribute, before any blanks that precede "/>" or ">"
        at = closing
        while at > 0 and self.text[at - 1] in " \t\r\n":
            at -= 1
        return Edit(at, at, f' {name}="{self.escaped(value, chr(34))}"')

    def escaped(self, value: str, quote: str) -> str:
        """``value`` as an attribute's value in ``quote``: markup characters, the quote
        and the blanks attribute-value normalisation would change as references, and any
        character the file's encoding cannot hold (in an encoding Python and libxml2 may
        read differently, every character but ASCII's letters, digits and plain
        punctuation) as a character reference. A character XML admits nowhere is refused."""
        if _NOT_XML.search(value):
            raise EditError("the value holds a character XML does not admit")
        text = value.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
        text = text.replace(quote, "&quot;" if quote == '"' else "&apos;")
        text = text.replace("\t", "&#9;").replace("\n", "&#10;").replace("\r", "&#13;")
        if self.codec in _AGREEING:
            return text.encode(self.codec, "xmlcharrefreplace").decode(self.codec)
        text = text.replace("\\", "&#92;").replace("~", "&#126;")
        return text.encode("ascii", "xmlcharrefreplace").decode("ascii")

    def _holds(self, text: str) -> bool:
        try:
            text.encode(self.codec)
        except UnicodeEncodeError:
            return False
        return True

    def apply(self, edits: Iterable[Edit]) -> bytes:
        """The source with ``edits`` made, in the file's encoding; the edits must not
        overlap (two insertions at one place keep their order)."""
        ordered = sorted(edits, key=lambda edit: (edit.start, edit.end))
        pieces: list[str] = []
        at = 0
        for edit in ordered:
            if edit.start < at or edit.end < edit.start or edit.end > len(self.text):
                raise EditError(f"overlapping or misplaced edit at {edit.start}")
            pieces += [self.text[at : edit.start], edit.content]
            at = edit.end
        pieces.append(self.text[at:])
        try:
            return "".join(pieces).encode(self.codec)
        except UnicodeEncodeError as error:
            raise EditError(f"an edit holds what {self.codec} cannot write: {error}") from error


def _codec_of(data: bytes, parsed: str | None) -> str:
    """The codec that reads ``data`` back to its very bytes: a byte order mark's, read as
    a character of the text; else the encoding the parser read it in (``parsed``, its
    document information's); else UTF-8 (or UTF-16 or UTF-32 without a mark, which the
    zero bytes of its first characters show)."""
    for mark, codec in _BOMS:
        if data.startswith(mark):
            return codec
    head = data[:4]
    if len(head) == 4 and head.count(b"\x00") == 3:
        return "utf-32-be" if head[:1] == b"\x00" else "utf-32-le"
    if len(head) > 1 and b"\x00" in head[:2]:
        return "utf-16-be" if head[:1] == b"\x00" else "utf-16-le"
    if not parsed:
        return "utf-8"
    try:
        return codecs.lookup(parsed).name
    except LookupError as error:
        raise EditError(f"the file's encoding {parsed} is not one Python writes") from error


def _tag_end(text: str, position: int) -> int:
    """After the ``>`` that ends a start tag whose name ends at ``position`` (a ``>``
    inside a quoted value ends nothing)."""
    quote = None
    for at in range(position, len(text)):
        char = text[at]
        if quote is not None:
            if char == quote:
                quote = None
        elif char in "\"'":
            quote = char
        elif char == ">":
            return at + 1
    raise EditError("a start tag has no end")
