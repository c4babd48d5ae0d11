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

import bisect
import codecs
import itertools
import re
from collections.abc import Collection, Iterable, Sequence
from typing import Final, NamedTuple

from lxml import etree

from xodrlint.document.positions import (
    LINE_BREAK,
    MARKUP_PATTERN,
    document_comments,
    wide_encoding,
)
from xodrlint.fixes import Fix, InsertElement, ReplaceComment, SetAttribute, TextEdit


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
#: Any markup after a start tag, read whole: comments, CDATA sections, processing
#: instructions, end tags and start tags (a ``>`` in a quoted value ends none).
_NODE: Final = re.compile(
    r"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>|</[^>]*>|<(?:[^>\"']|\"[^\"]*\"|'[^']*')*>",
    re.DOTALL,
)
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


class EditableSource:
    """A document's source as text that encodes back to its very bytes, with the places
    of its elements' start tags and of its comments."""

    def __init__(
        self,
        data: bytes,
        root: etree._Element,
        foreign: Collection[etree._Element] = (),
    ) -> None:
        """``foreign`` are the nodes includes brought into the tree (each with what is
        inside it): none of them stands in this source."""
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
        if foreign:
            brought = {node for top in foreign for node in top.iter()}
            elements = [node for node in elements if node not in brought]
            every_comment = [node for node in every_comment if node not in brought]
        if len(tags) != len(elements) or len(comments) != len(every_comment):
            raise EditError("the source's markup does not match its tree")
        self._tags = dict(zip(elements, tags, strict=True))
        self._line_starts: list[int] | None = None
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

    def element_end(self, element: etree._Element) -> int:
        """After the end of ``element``: its ``/>``, or the ``>`` of its end tag."""
        _, end = self.start_tag(element)
        if self.text[end - 2 : end] == "/>":
            return end
        depth = 1
        for found in _NODE.finditer(self.text, end):
            token = found.group()
            if token.startswith("</"):
                depth -= 1
                if depth == 0:
                    return found.end()
            elif token[1] not in "!?" and not token.endswith("/>"):
                depth += 1
        raise EditError(f"'{etree.QName(element).localname}' has no end tag")

    def comment_edit(self, comment: etree._Element, text: str | None) -> Edit:
        """The edit that gives ``comment`` the text ``text`` (as lxml reads a comment's
        text: every line break a newline), changing only the characters that differ; or,
        with ``None``, removes it, with its line when it stood alone there."""
        start, end = self.comment(comment)
        if text is None:
            line_start = _line_start(self.text, start)
            if line_start == 0 and self.text.startswith("\ufeff"):
                line_start = 1  # a byte order mark is no content of the first line
            line_end = _line_end(self.text, end)
            blank = " \t"
            before = self.text[line_start:start]
            if not self.text[end:line_end].strip(blank):
                if not before.strip(blank):  # alone on its line: the line goes
                    return Edit(line_start, _after_break(self.text, line_end), "")
                # last on its line: the blanks before it go, no trailing blank is left
                return Edit(start - (len(before) - len(before.rstrip(blank))), line_end, "")
            # markup follows on its line: the blanks after it go, the indentation stays
            after = end
            while after < line_end and self.text[after] in blank:
                after += 1
            return Edit(start, after, "")
        if "--" in text or text.endswith("-") or _NOT_XML.search(text) or not self._holds(text):
            raise EditError("the text cannot stand in a comment of this file")
        raw = self.text[start + 4 : end - 3]
        old = _normalised(raw)
        prefix, suffix = common_ends(old, text)
        middle = text[prefix : len(text) - suffix].replace("\n", self._line_break(start))
        begin = start + 4 + _raw_index(raw, prefix)
        stop = start + 4 + _raw_index(raw, len(old) - suffix)
        return Edit(begin, stop, middle)

    def insert_element(
        self,
        anchor: etree._Element,
        tag: str,
        attributes: Sequence[tuple[str, str]],
        where: str,
        children: Sequence[tuple[str, Sequence[tuple[str, str]]]] = (),
    ) -> Edit:
        """The edit that inserts ``<tag a="v"/>`` (holding ``children``, one a line) after
        or before ``anchor``: on a line of its own indented as ``anchor``, where
        ``anchor`` starts its line; else beside it."""
        start, _ = self.start_tag(anchor)
        line_start = _line_start(self.text, start)
        indent = self.text[line_start:start]
        alone = not indent.strip(" \t")
        line_break = self._line_break(start) if alone else ""
        if not alone:
            indent = ""
        if children:
            # beside other markup, the children stand beside each other too
            inner = indent + self._indent_step(anchor) if alone else ""
            held = "".join(
                f"{line_break}{inner}{self._empty_element(child, values)}"
                for child, values in children
            )
            markup = (
                f"{self._empty_element(tag, attributes)[:-2]}>{held}{line_break}{indent}</{tag}>"
            )
        else:
            markup = self._empty_element(tag, attributes)
        if where == "before":
            return Edit(start, start, markup + line_break + indent)
        at = self.element_end(anchor)
        return Edit(at, at, line_break + indent + markup)

    def _empty_element(self, tag: str, attributes: Sequence[tuple[str, str]]) -> str:
        for name in (tag, *(name for name, _ in attributes)):
            if _NAME.fullmatch(name) is None or not self._holds(name):
                raise EditError(f"'{name}' is no name this file can hold")
        written = "".join(f' {name}="{self.escaped(value, chr(34))}"' for name, value in attributes)
        return f"<{tag}{written}/>"

    def _indent_step(self, element: etree._Element) -> str:
        """How much deeper the file indents a child than its parent: ``element``'s
        indentation less its parent's, where both stand alone on their lines; else two
        blanks."""
        parent = element.getparent()
        if parent is None:
            return "  "
        own, above = self._indentation(element), self._indentation(parent)
        if own is not None and above is not None and own.startswith(above) and own != above:
            return own[len(above) :]
        return "  "

    def _indentation(self, element: etree._Element) -> str | None:
        start, _ = self.start_tag(element)
        before = self.text[_line_start(self.text, start) : start]
        return before if not before.strip(" \t") else None

    def _line_break(self, offset: int) -> str:
        """The line break the file uses near ``offset``: that of the line before it, or
        of the first line, or a newline."""
        before = _line_start(self.text, offset)
        if before >= 2 and self.text[before - 2 : before] == "\r\n":
            return "\r\n"
        if before >= 1:
            return self.text[before - 1]
        found = LINE_BREAK.search(self.text)
        return found.group() if found else "\n"

    def position(self, offset: int) -> tuple[int, int]:
        """The line and column (1-based, in characters, a byte order mark not counted)
        of ``offset``, as a finding's are counted."""
        if self._line_starts is None:
            self._line_starts = [0, *(found.end() for found in LINE_BREAK.finditer(self.text))]
        line = bisect.bisect_right(self._line_starts, offset)
        column = offset - self._line_starts[line - 1] + 1
        if line == 1 and self.text.startswith("\ufeff"):
            column -= 1
        return line, column

    def placed(self, edit: Edit) -> TextEdit:
        """``edit`` with the lines and columns reports and editors use."""
        start_line, start_column = self.position(edit.start)
        end_line, end_column = self.position(edit.end)
        return TextEdit(
            edit.content, start_line, start_column, end_line, end_column, edit.start, edit.end
        )

    def edits_of(self, fix: Fix) -> list[Edit]:
        """The text edits that make ``fix``'s element edits; :class:`EditError` when one
        cannot be made or two of them overlap."""
        made: list[Edit] = []
        for edit in fix.edits:
            if isinstance(edit, SetAttribute):
                made.append(self.set_attribute(edit.element, edit.name, edit.value))
            elif isinstance(edit, ReplaceComment):
                made.append(self.comment_edit(edit.comment, edit.text))
            elif isinstance(edit, InsertElement):
                made.append(
                    self.insert_element(
                        edit.anchor, edit.tag, edit.attributes, edit.where, edit.children
                    )
                )
            else:
                raise EditError(f"{type(edit).__name__} is no edit")
        if overlapping(made):
            raise EditError("the fix's edits overlap")
        return made

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


def overlapping(edits: Iterable[Edit]) -> bool:
    """Whether two of ``edits`` touch the same text (two insertions at one place do)."""
    ordered = sorted(edits, key=lambda edit: (edit.start, edit.end))
    return any(
        later.start < earlier.end or later.start == earlier.start
        for earlier, later in itertools.pairwise(ordered)
    )


def _line_start(text: str, offset: int) -> int:
    return max(text.rfind("\n", 0, offset), text.rfind("\r", 0, offset)) + 1


def _line_end(text: str, offset: int) -> int:
    found = LINE_BREAK.search(text, offset)
    return len(text) if found is None else found.start()


def _after_break(text: str, offset: int) -> int:
    found = LINE_BREAK.match(text, offset)
    return offset if found is None else found.end()


def _normalised(raw: str) -> str:
    """Text as the parser reads it: every line break a newline."""
    return raw.replace("\r\n", "\n").replace("\r", "\n")


def _raw_index(raw: str, index: int) -> int:
    """The offset in ``raw`` of the character at ``index`` of its normalised form."""
    at = 0
    for _ in range(index):
        at += 2 if raw.startswith("\r\n", at) else 1
    return at


def common_ends(before: str, after: str) -> tuple[int, int]:
    """How many characters ``before`` and ``after`` share at their start, and then at
    their end (never the same character twice): what lies between is all that differs."""
    head = common_head(before, after)
    return head, common_tail(before, after, head)


def common_head(before: str, after: str) -> int:
    """How many characters ``before`` and ``after`` share at their start."""
    limit = min(len(before), len(after))
    head = 0
    while head < limit and before[head] == after[head]:
        head += 1
    return head


def common_tail(before: str, after: str, head: int) -> int:
    """How many characters ``before`` and ``after`` share at their end, none of their
    first ``head``."""
    limit = min(len(before), len(after)) - head
    tail = 0
    while tail < limit and before[-1 - tail] == after[-1 - tail]:
        tail += 1
    return tail


def _codec_of(data: bytes, parsed: str | None) -> str:
    """The codec that reads ``data`` back to its very bytes: a byte order mark's, read as
    a character of the text; else the encoding the parser read it in (``parsed``, its
    document information's); else UTF-8 (or UTF-16 or UTF-32 without a mark, which the
    zero bytes of its first characters show)."""
    wide = wide_encoding(data)  # (a codec of one byte order, which reads a mark as text)
    if wide is not None:
        return wide[0]
    if data.startswith(codecs.BOM_UTF8) or not parsed:
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
