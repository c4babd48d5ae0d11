"""Byte-exact edits of a document's source: what a fix changes, and nothing else.

A fix is a list of edits on the source as it was read: the value of one attribute
replaced, a run of text removed or inserted. The document is never serialised again:
everything outside the edits keeps its bytes (the encoding and its byte order mark, line
ends, attribute order and quotes, character references, comments, blanks).

:class:`EditableSource` decodes the bytes as the file's encoding says, in a form that
encodes back to exactly the same bytes (a byte order mark stays a character of the
text), and finds each element's start tag and each comment in that text the way the
positions of findings do: the k-th start tag of the text is the k-th element of the
tree. A source whose text would not encode back to its bytes is not editable.
"""

from __future__ import annotations

import codecs
import re
from collections.abc import Iterable
from typing import Final, NamedTuple

from lxml import etree

from xodrlint.document.positions import MARKUP_PATTERN


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
#: One attribute of a start tag: its name, blanks, ``=``, blanks and its quoted value.
_ATTRIBUTE: Final = re.compile(r"\s*([^\s=/>]+)\s*=\s*(?:\"([^\"]*)\"|'([^']*)')")
_TAG_NAME: Final = re.compile(r"<([^\s/>]+)")
_BOMS: Final = (
    (codecs.BOM_UTF32_LE, "utf-32-le"),
    (codecs.BOM_UTF32_BE, "utf-32-be"),
    (codecs.BOM_UTF8, "utf-8"),
    (codecs.BOM_UTF16_LE, "utf-16-le"),
    (codecs.BOM_UTF16_BE, "utf-16-be"),
)
_DECLARED: Final = re.compile(rb"""<\?xml[^>]*?encoding\s*=\s*["']([A-Za-z0-9._\-]+)["']""")


class EditableSource:
    """A document's source as text that encodes back to its very bytes, with the places
    of its elements' start tags and of its comments."""

    def __init__(self, data: bytes, root: etree._Element) -> None:
        self.codec = _codec_of(data)
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
        every_comment = [
            *reversed(list(root.itersiblings(etree.Comment, preceding=True))),
            *root.iter(etree.Comment),
            *root.itersiblings(etree.Comment),
        ]
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
        """The edit that sets ``element``'s attribute ``name`` to ``value``: its value
        replaced between its quotes, or the attribute added at the end of the start tag,
        written in double quotes, when the tag has none."""
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
        character the file's encoding cannot hold as a character reference."""
        text = value.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
        text = text.replace(quote, "&quot;" if quote == '"' else "&apos;")
        text = text.replace("\t", "&#9;").replace("\n", "&#10;").replace("\r", "&#13;")
        return text.encode(self.codec, "xmlcharrefreplace").decode(self.codec)

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
        return "".join(pieces).encode(self.codec)


def _codec_of(data: bytes) -> str:
    """The codec that reads ``data`` back to its very bytes: a byte order mark's, read as
    a character of the text; else the declared encoding; else UTF-8 (or UTF-16 without a
    mark, which the zero bytes of its first characters show)."""
    for mark, codec in _BOMS:
        if data.startswith(mark):
            return codec
    head = data[:4]
    if len(head) == 4 and head.count(b"\x00") == 3:
        return "utf-32-be" if head[:1] == b"\x00" else "utf-32-le"
    if len(head) > 1 and b"\x00" in head[:2]:
        return "utf-16-be" if head[:1] == b"\x00" else "utf-16-le"
    declared = _DECLARED.match(data)
    if declared is not None:
        try:
            return codecs.lookup(declared[1].decode("ascii")).name
        except LookupError:
            pass
    return "utf-8"


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
