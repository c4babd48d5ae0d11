"""Positions of elements: in their tree, and in the source they were read from.

:class:`SourcePositions` gives the exact line and column of an element's start tag:
every finding's position, and what an editor's diagnostic range starts from.
:class:`TreePositions` finds elements in a tree in time that does not grow with their
siblings.

lxml's ``parent.index(child)``, ``parent[i]`` and an XPath step such as ``road[1234]``
walk the siblings every time they are asked: n findings about the children of one
parent (a city map's roads) cost n times n. :class:`TreePositions` lists each parent's
children once, the first time one of them is asked about, so every later question costs
the depth of the element. Used wherever findings cross a boundary as positions: the
libxml2 error paths of the schema stage and the child indices a forked validator sends.
"""

from __future__ import annotations

import codecs
import enum
import functools
import re
from typing import Final

from lxml import etree

#: A step of a libxml2 error path that names an element by its name (no namespace
#: prefix) and, where it has siblings of that name, its 1-based occurrence among them.
_NAMED_STEP: Final = re.compile(r"([A-Za-z_][\w.\-]*)(?:\[([1-9][0-9]*)\])?")


class TreePositions:
    """Children by position and by name, indexed once per parent on first use."""

    def __init__(self) -> None:
        self._children: dict[etree._Element, list[etree._Element]] = {}
        self._index: dict[etree._Element, int] = {}
        self._named: dict[etree._Element, dict[str, list[etree._Element]]] = {}

    def children(self, parent: etree._Element) -> list[etree._Element]:
        """``list(parent)``: every child as lxml counts them (comments and processing
        instructions too), made once per parent."""
        found = self._children.get(parent)
        if found is None:
            found = self._children[parent] = list(parent)
        return found

    def index_of(self, element: etree._Element) -> int | None:
        """``element.getparent().index(element)``; ``None`` for a root."""
        index = self._index.get(element)
        if index is None:
            parent = element.getparent()
            if parent is None:
                return None
            self._index.update((child, i) for i, child in enumerate(self.children(parent)))
            index = self._index[element]
        return index

    def child(self, parent: etree._Element, index: int) -> etree._Element | None:
        """``parent[index]``, or ``None`` where there is no such child."""
        children = self.children(parent)
        return children[index] if 0 <= index < len(children) else None

    def path_from(self, root: etree._Element, steps: list[int]) -> etree._Element | None:
        """The element that ``steps`` (child indices, from ``root`` down) lead to."""
        element: etree._Element | None = root
        for index in steps:
            if element is None:
                return None
            element = self.child(element, index)
        return element

    def steps_to(self, element: etree._Element, root: etree._Element) -> list[int] | None:
        """The child indices that lead from ``root`` down to ``element``; ``None`` when
        ``element`` is not below ``root``."""
        steps: list[int] = []
        current = element
        while current is not root:
            index = self.index_of(current)
            if index is None:  # reached a root that is not ``root``: another tree
                return None
            steps.append(index)
            current = current.getparent()  # type: ignore[assignment]  # index_of: not None
        steps.reverse()
        return steps

    def libxml2_path(self, root: etree._Element, path: str) -> etree._Element | bool | None:
        """The element below ``root`` that a libxml2 error path names (its first step is
        ``root`` itself, as libxml2 writes it for the validated tree): ``False`` where a
        step is not a plain name (a namespace prefix, ``*``, ``text()``), which only an
        XPath engine reads; ``None`` where the path leads nowhere."""
        steps = path.strip("/").split("/")
        if not steps[0]:
            return None
        element = root
        for step in steps[1:]:
            match = _NAMED_STEP.fullmatch(step)
            if match is None:
                return False
            same_name = self._named_children(element).get(match[1])
            occurrence = int(match[2]) if match[2] else 1
            if same_name is None or occurrence > len(same_name):
                return None
            element = same_name[occurrence - 1]
        return element

    def _named_children(self, parent: etree._Element) -> dict[str, list[etree._Element]]:
        named = self._named.get(parent)
        if named is None:
            named = self._named[parent] = {}
            for child in self.children(parent):
                tag = child.tag
                if isinstance(tag, str) and not tag.startswith("{"):
                    named.setdefault(tag, []).append(child)
        return named


# --- where an element stands in the source ---------------------------------------------

#: libxml2 stores an element's line in 16 bits: from this value on ``sourceline`` is a
#: guess, and below it names the line where the start tag *ends* (its ``>``).
LIBXML2_LINE_CAP: Final = 65535

# Start tags, told apart from the markup that may contain a '<' without being one. A
# '<' cannot stand in an attribute value or in text of well-formed XML (the parser
# refuses it), so comments, CDATA sections, processing instructions and the document
# type declaration are all that hide one.
#: A start tag's ``<`` alone, or whole markup in which a ``<`` starts no element: a
#: comment, CDATA, a processing instruction, a document type declaration (the edits of
#: fixes find start tags and comments by it too, in decoded text).
MARKUP_PATTERN: Final = (
    rb"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>"
    # a document type declaration, whose quoted strings, comments and processing
    # instructions may hold "]>" or "<a" (an entity's value)
    rb"|<!DOCTYPE(?:[^\[>\"']|\"[^\"]*\"|'[^']*')*"
    rb"(?:\[(?:[^\]\"'<]|\"[^\"]*\"|'[^']*'|<!--.*?-->|<\?.*?\?>|<(?!!--|\?))*\][ \t\r\n]*)?>"
    rb"|<(?=[^/!?])"
)
_MARKUP: Final = re.compile(MARKUP_PATTERN, re.DOTALL)
#: The qualified name after a start tag's '<' (the parser has checked it already), and
#: the bytes that may follow a name.
_QNAME: Final = re.compile(rb"[^\s/>]+")
_NAME_ENDS: Final = frozenset((b" ", b"\t", b"\n", b"\r", b"/", b">"))
#: Newline counts and continuation-byte counts are kept per block of this many bytes.
_BLOCK: Final = 4096
#: UTF-8 continuation bytes: a character is every byte but these.
_CONTINUATION: Final = bytes(range(0x80, 0xC0))
#: Codecs that shift between states: a run of bytes in the middle of a line cannot be
#: decoded on its own, and a '<' byte may be half of a character.
_STATEFUL: Final = frozenset({"utf-7", "hz"})


def document_comments(root: etree._Element) -> list[etree._Element]:
    """Every comment of ``root``'s document in source order: before the root, in it and
    after it (the k-th is the k-th ``<!--`` a scan of the source finds)."""
    return [
        *reversed(list(root.itersiblings(etree.Comment, preceding=True))),
        *root.iter(etree.Comment),
        *root.itersiblings(etree.Comment),
    ]


def parser_line(node: etree._Element) -> int:
    """libxml2's line for ``node`` (exact below 65,535; where the start tag ends)."""
    line: object = node.sourceline
    return line if isinstance(line, int) and line > 0 else 1


class SourcePositions:
    """Where each element's start tag begins in the source: the line and the column of
    its ``<``, both 1-based, the column in characters (Unicode code points, as SARIF's
    ``unicodeCodePoints`` and editors count them).

    libxml2 keeps lines in 16 bits (guessing past 65,535), reports the line where a start
    tag *ends*, and no column at all. One scan of the bytes finds every start tag in
    document order, and the k-th element of the tree is the k-th start tag; the scan runs
    once a document has something to report. A line and its start are then found through
    an index of newlines per 4 KiB block, and a column counts the characters between the
    two, so a lookup costs the same on a minified one-line map as on a pretty one.

    A comment is placed the same way, at its ``<!--`` (an unused suppression is reported
    there); its mapping is made only when a comment is asked about.

    A position is never a guess: where the scan and the tree disagree (a number of start
    tags that differs from the number of elements, a start tag of another name), the
    line is libxml2's and the column ``None``; so is the column of a file in an encoding
    whose characters cannot be counted from the middle of a line (UTF-7, ISO-2022).
    """

    def __init__(self, data: bytes, root: etree._Element, encoding: str | None) -> None:
        text, widened = _ascii_compatible(data)
        self._text = text
        # a wide file was re-encoded as UTF-8 for the scan; a narrow one is in its own
        self._encoding = "utf-8" if widened else (encoding or "utf-8")
        starts = [
            match.start() for match in _MARKUP.finditer(text) if match.end() - match.start() == 1
        ]
        try:
            self._offsets = dict(zip(root.iter(etree.Element), starts, strict=True))
        except ValueError:  # the scan misread some markup: trust none of it
            self._offsets = {}
        self._root = root
        self._comments: dict[etree._Element, int] | None = None
        self._names: dict[str, bytes] = {}
        self._blocks: _Blocks | None = None
        self._counting: _Counting | None = None

    def line_of(self, node: etree._Element) -> int:
        """The line of ``node``'s ``<``; libxml2's line where the scan has none."""
        offset = self._offset(node)
        return parser_line(node) if offset is None else self._locate(offset)[0]

    def position_of(self, node: etree._Element) -> tuple[int, int | None]:
        """``(line, column)`` of ``node``'s ``<``; the column is ``None`` where it cannot
        be known exactly (a processing instruction, an encoding whose characters cannot be
        counted, markup the scan could not place)."""
        offset = self._offset(node)
        if offset is None:
            return parser_line(node), None
        line, line_start = self._locate(offset)
        return line, self._column(line_start, offset)

    def _offset(self, node: etree._Element) -> int | None:
        """Where ``node``'s start tag begins in the scanned text, checked against its name."""
        offset = self._offsets.get(node)
        if offset is None:
            return self._comment_offset(node) if isinstance(node, etree._Comment) else None
        tag = node.tag
        name = self._names.get(tag) if isinstance(tag, str) else None
        if name is None:
            name = self._name(tag)
        text = self._text
        end = offset + 1 + len(name)
        if text.startswith(name, offset + 1) and text[end : end + 1] in _NAME_ENDS:
            return offset  # the common case, a name without a prefix: no regular expression
        found = _QNAME.match(text, offset + 1)
        return offset if name and found and found[0].rpartition(b":")[2] == name else None

    def index_comments(self) -> None:
        """Pair comments with their places now (see :meth:`_comment_offset`)."""
        self._comment_offset(self._root)

    def _comment_offset(self, node: etree._Element) -> int | None:
        """Where a comment's ``<!--`` stands: the k-th comment of the document, before its
        root, in it and after it, is the k-th the scan finds."""
        if self._comments is None:
            text, root = self._text, self._root
            found = [
                m.start() for m in _MARKUP.finditer(text) if text.startswith(b"<!--", m.start())
            ]
            try:
                self._comments = dict(zip(document_comments(root), found, strict=True))
            except ValueError:
                self._comments = {}
        return self._comments.get(node)

    def _name(self, tag: object) -> bytes:
        """A tag's local name as the scanned text spells it (empty where it cannot)."""
        if not isinstance(tag, str):
            return b""
        local = tag.rpartition("}")[2]
        try:
            name = local.encode("ascii" if local.isascii() else self._encoding)
        except (LookupError, UnicodeError):
            name = b""
        self._names[tag] = name
        return name

    def _locate(self, offset: int) -> tuple[int, int]:
        if self._blocks is None:
            self._blocks = _Blocks(self._text)
        return self._blocks.locate(offset)

    def _column(self, line_start: int, offset: int) -> int | None:
        if line_start == 0 and self._text.startswith(codecs.BOM_UTF8):
            line_start = len(codecs.BOM_UTF8)  # a byte order mark is no character
        if self._counting is None:
            self._counting = _counting(self._text, self._encoding)
        blocks = self._blocks
        assert blocks is not None  # made by _locate
        if self._counting is _Counting.BYTES:
            return offset - line_start + 1
        if self._counting is _Counting.UTF8:
            return offset - line_start - blocks.continuations(line_start, offset) + 1
        if self._counting is _Counting.DECODE:
            try:
                return len(self._text[line_start:offset].decode(self._encoding)) + 1
            except (LookupError, UnicodeError):
                return None
        return None


class _Counting(enum.Enum):
    """How characters are counted in the scanned text."""

    BYTES = "one byte, one character"
    UTF8 = "every byte but UTF-8 continuation bytes"
    DECODE = "decode the run of bytes"
    NONE = "not at all"


def _counting(text: bytes, encoding: str) -> _Counting:
    try:
        name = codecs.lookup(encoding).name
    except LookupError:
        return _Counting.NONE
    if name in ("utf-8", "utf-8-sig"):
        return _Counting.BYTES if text.isascii() else _Counting.UTF8
    if name in _STATEFUL or name.startswith("iso2022") or not _ascii_safe(name):
        return _Counting.NONE
    return _Counting.BYTES if text.isascii() or _single_byte(name) else _Counting.DECODE


@functools.cache
def _ascii_safe(codec: str) -> bool:
    """Whether ``codec`` writes ASCII as ASCII, so that the scan's '<' and newlines are
    characters of their own (not so in UTF-16 or EBCDIC)."""
    sample = "".join(map(chr, range(128)))
    try:
        return sample.encode(codec) == sample.encode("ascii")
    except UnicodeError:
        return False


@functools.cache
def _single_byte(codec: str) -> bool:
    """Whether every byte of ``codec`` is a character of its own (ISO-8859-*, cp125*)."""
    return len(bytes(range(256)).decode(codec, errors="replace")) == 256


class _Blocks:
    """Newlines and UTF-8 continuation bytes counted per block of the scanned text,
    made on the first lookup: a line, a line's start and a run's characters then cost
    at most a block's scan each."""

    def __init__(self, text: bytes) -> None:
        self._text = text
        newlines_before = [0]
        last_newline = [-1]  # the offset of the last newline before each block
        count, rfind = text.count, text.rfind
        for start in range(0, len(text), _BLOCK):
            found = count(b"\n", start, start + _BLOCK)
            newlines_before.append(newlines_before[-1] + found)
            last_newline.append(rfind(b"\n", start, start + _BLOCK) if found else last_newline[-1])
        self._newlines_before = newlines_before
        self._last_newline = last_newline
        self._continuations_before: list[int] | None = None

    def locate(self, offset: int) -> tuple[int, int]:
        """The line of ``offset`` and the offset at which that line starts."""
        block = offset // _BLOCK
        start = block * _BLOCK
        line = self._newlines_before[block] + self._text.count(b"\n", start, offset) + 1
        newline = self._text.rfind(b"\n", start, offset)
        if newline < 0:
            newline = self._last_newline[block]
        return line, newline + 1

    def continuations(self, start: int, end: int) -> int:
        """The UTF-8 continuation bytes in ``text[start:end]``."""
        if end - start <= 2 * _BLOCK:
            return _continuations(self._text[start:end])
        return self._continuations_up_to(end) - self._continuations_up_to(start)

    def _continuations_up_to(self, offset: int) -> int:
        table = self._continuations_before
        if table is None:
            table = [0]
            for start in range(0, len(self._text), _BLOCK):
                table.append(table[-1] + _continuations(self._text[start : start + _BLOCK]))
            self._continuations_before = table
        block = offset // _BLOCK
        return table[block] + _continuations(self._text[block * _BLOCK : offset])


def _continuations(run: bytes) -> int:
    return len(run) - len(run.translate(None, _CONTINUATION))


def _ascii_compatible(data: bytes) -> tuple[bytes, bool]:
    """``data`` in an encoding where '<' and newline are single bytes, each line break one
    newline, and whether it had to be re-encoded (from UTF-16 or UTF-32, as UTF-8) to be
    so.

    A line break is "\\r\\n", "\\n" or a lone "\\r", as XML's end-of-line handling and
    every editor (and the language server protocol) take it: libxml2 counts no lone "\\r",
    so a file of old Mac line ends was one line of libxml2's.
    """
    wide = wide_encoding(data)
    if wide is not None:
        data = decode_wide(data, wide).encode("utf-8", "surrogatepass")
    if b"\r" in data:
        data = data.replace(b"\r\n", b"\n").replace(b"\r", b"\n")
    return data, wide is not None


def parser_position_by_line_ends(
    data: bytes, line: int, column: int | None
) -> tuple[int, int | None]:
    """libxml2's ``line`` and ``column`` of a parse error, counted as the positions count
    lines (a lone "\\r" ends one; libxml2 counts none): unchanged in a file without one.
    The column counts characters from the line's start, as libxml2's does."""
    if b"\r" not in data.replace(b"\r\n", b""):
        return line, column
    wide = wide_encoding(data)
    raw = decode_wide(data, wide) if wide is not None else data.decode("utf-8", "replace")
    libxml2_lines = raw.replace("\r\n", "\n")  # libxml2's lines: split at "\n" alone
    start = 0
    for _ in range(max(line, 1) - 1):
        found = libxml2_lines.find("\n", start)
        if found < 0:
            return line, column  # past the end: leave libxml2's words as they are
        start = found + 1
    offset = min(start + max((column or 1) - 1, 0), len(libxml2_lines))
    ours = libxml2_lines.replace("\r", "\n")  # the same length: offsets hold
    line_start = ours.rfind("\n", 0, offset) + 1
    return ours.count("\n", 0, offset) + 1, (offset - line_start + 1 if column else None)


#: A line break as XML, the positions, the fixes and ``patch`` count lines: "\\r\\n", "\\n"
#: or a lone "\\r" (Python's ``splitlines`` also breaks at U+2028 and others).
LINE_BREAK: Final = re.compile(r"\r\n|\r|\n")
#: A line with its line break, or the last line without one.
_LINE_AND_BREAK: Final = re.compile(r"[^\r\n]*(?:\r\n|\r|\n)|[^\r\n]+\Z")


def lines_of(text: str) -> list[str]:
    """``text``'s lines, split at each :data:`LINE_BREAK` (``--show-source`` and the
    language server read them)."""
    return LINE_BREAK.split(text)


def lines_with_breaks(text: str) -> list[str]:
    """``text``'s lines, each with its :data:`LINE_BREAK` (the last one may have none):
    joined, they are ``text`` again."""
    return _LINE_AND_BREAK.findall(text)


#: The byte order marks of UTF-32 and UTF-16, longest first (UTF-32 LE's begins with
#: UTF-16 LE's).
_WIDE_MARKS: Final = (
    (b"\xff\xfe\x00\x00", "utf-32-le"),
    (b"\x00\x00\xfe\xff", "utf-32-be"),
    (b"\xff\xfe", "utf-16-le"),
    (b"\xfe\xff", "utf-16-be"),
)


def wide_encoding(data: bytes) -> tuple[str, int] | None:
    """The UTF-32 or UTF-16 codec ``data`` is written in, byte order included, and the
    length of its byte order mark (0 without one); ``None`` for an encoding whose '<' is
    one byte (UTF-8, or what the declaration names). Without a mark, the zero bytes of
    the first character tell, as libxml2 reads them: three of four for UTF-32, one of two
    for UTF-16, "<\\0" little-endian and "\\0<" big-endian. The one sniffer of the
    positions, the edits and the rule cases."""
    for mark, codec in _WIDE_MARKS:
        if data.startswith(mark):
            return codec, len(mark)
    head = data[:4]
    if len(head) == 4 and head.count(b"\x00") == 3:
        return ("utf-32-be" if head[:1] == b"\x00" else "utf-32-le"), 0
    if len(head) > 1 and b"\x00" in head[:2]:
        return ("utf-16-be" if head[:1] == b"\x00" else "utf-16-le"), 0
    return None


def decode_wide(data: bytes, wide: tuple[str, int]) -> str:
    """UTF-32 or UTF-16 ``data`` (:func:`wide_encoding` said which) as text, without its
    byte order mark; a malformed sequence becomes U+FFFD."""
    codec, mark = wide
    return data[mark:].decode(codec, "replace")
