"""Stage 1, load: bytes to a parsed, hardened OpenDRIVE document with exact positions.

Everything that can go wrong while reading a file becomes a hit of a document rule
(XS001 to XS005) on the returned :class:`Document`; nothing here raises for bad input.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Final, NamedTuple

from lxml import etree

from xodrlint.document.positions import SourcePositions, lines_of, parser_position_by_line_ends
from xodrlint.document.xpaths import ReadableXPaths
from xodrlint.findings import Hit
from xodrlint.messages import readable_parser_message

if TYPE_CHECKING:
    from xodrlint.document.edits import EditableSource

#: ASAM's pre-1.6 namespace; files using it are read as if un-namespaced.
ASAM_LEGACY_NAMESPACE: Final = "http://code.asam.net/simulation/standard/opendrive_schema"
#: The namespace of VIRES' OpenDRIVE 1.1 and 1.2 schemas, read the same way.
VIRES_NAMESPACE: Final = "www.vires.com"
#: Namespaces of earlier OpenDRIVE schemas: a file in one is read as if un-namespaced.
LEGACY_NAMESPACES: Final = frozenset({ASAM_LEGACY_NAMESPACE, VIRES_NAMESPACE})

#: The minor versions of OpenDRIVE 1.x that ASAM has published.
KNOWN_MINORS: Final = range(1, 10)


def hardened_parser() -> etree.XMLParser:
    """The one parser configuration xodrlint reads maps with.

    No entity expansion (billion laughs, external entities), no DTD loading, no network,
    no XInclude (lxml only processes it on request, and we never request it). Comments and
    processing instructions are kept: inline suppressions live in comments.

    ``collect_ids`` stays at its default on purpose: lxml turns ``collect_ids=False`` into
    a libxml2 flag that makes it load the external DTD a file names, ``load_dtd=False``
    notwithstanding (a local file read, a hang on a FIFO).

    Blank text stays in the tree, though nothing but validation reads it and it is a
    seventh of a railway's memory: libxml2's ``remove_blank_text`` also drops blanks that
    XSD counts (beside a comment or an element child in an element of empty or simple
    content, which the schema reports as character content).
    """
    return etree.XMLParser(
        resolve_entities=False,
        load_dtd=False,
        dtd_validation=False,
        no_network=True,
        huge_tree=False,
        remove_comments=False,
        remove_pis=False,
    )


class Version(NamedTuple):
    major: int
    minor: int

    def __str__(self) -> str:
        return f"{self.major}.{self.minor}"


@dataclass(eq=False)
class IncludedPart:
    """A file an ``include`` brought into a document (:mod:`xodrlint.document.includes`): the name
    its findings carry, its bytes, and the positions and XPaths of its elements in it."""

    path: str
    data: bytes
    root: etree._Element
    """Its root element as parsed (its children may stand in the document now)."""
    positions: SourcePositions
    xpaths: ReadableXPaths


@dataclass(eq=False)
class Document:
    """A loaded file: its bytes, its tree (if it parsed) and what loading found wrong.

    ``problems`` maps a document rule code to its hits. ``declared`` is the version the
    header states (if readable) and ``effective`` the published version it is checked as.
    ``parts`` are the files its includes brought in; ``spliced`` maps each node an
    include put into the tree (the top of what it brought) to its file. Positions and
    XPaths of a node are those in its own file.
    """

    path: str
    data: bytes
    tree: etree._ElementTree | None = None
    problems: dict[str, list[Hit]] = field(default_factory=dict)
    declared: Version | None = None
    effective: Version | None = None
    parts: list[IncludedPart] = field(default_factory=list)
    spliced: dict[etree._Element, IncludedPart] = field(default_factory=dict)

    @cached_property
    def may_include(self) -> bool:
        """Whether the file may hold an ``include``: a byte search, as most maps hold
        none and walking a city map's tree costs more (a file in UTF-16 or UTF-32, where
        the word is no such run of bytes, may). Searched once: the linter and
        :func:`~xodrlint.document.includes.has_includes` both ask."""
        return b"include" in self.data or b"\0" in self.data[:4]

    @property
    def root(self) -> etree._Element | None:
        return None if self.tree is None else self.tree.getroot()

    @property
    def is_opendrive(self) -> bool:
        """True when the tree parsed and its root is an ``OpenDRIVE`` element."""
        root = self.root
        return root is not None and root.tag == "OpenDRIVE"

    def report(self, code: str, hit: Hit) -> None:
        self.problems.setdefault(code, []).append(hit)

    def part_of(self, node: etree._Element) -> IncludedPart | None:
        """The included file ``node`` comes from; ``None`` for the document's own."""
        spliced = self.spliced
        if not spliced:
            return None
        current: etree._Element | None = node
        while current is not None:
            part = spliced.get(current)
            if part is not None:
                return part
            current = current.getparent()
        return None

    def path_of(self, node: etree._Element) -> str:
        """The name of the file ``node`` stands in: the document's, or an included one's."""
        part = self.part_of(node)
        return self.path if part is None else part.path

    def line_of(self, element: etree._Element) -> int:
        """The exact line of ``element``'s start tag (where its ``<`` stands), in its file."""
        part = self.part_of(element)
        return (self._positions if part is None else part.positions).line_of(element)

    def position_of(self, element: etree._Element) -> tuple[int, int | None]:
        """The exact line and column (1-based, in characters) of ``element``'s ``<`` in
        its file; the column is ``None`` where it cannot be known exactly (see
        :class:`~xodrlint.document.positions.SourcePositions`)."""
        part = self.part_of(element)
        return (self._positions if part is None else part.positions).position_of(element)

    def source_line(self, line: int) -> str | None:
        """The text of ``line`` (1-based) of the document's own file, decoded as the
        document declares."""
        lines = self._text_lines
        return lines[line - 1] if 0 < line <= len(lines) else None

    @cached_property
    def _text_lines(self) -> list[str]:
        encoding = self.tree.docinfo.encoding if self.tree is not None else None
        try:
            text = self.data.decode(encoding or "utf-8-sig", errors="replace")
        except LookupError:
            text = self.data.decode("utf-8", errors="replace")
        return lines_of(text.lstrip("\ufeff"))

    def xpath_of(self, element: etree._Element) -> str:
        """The readable XPath of ``element`` in its file."""
        part = self.part_of(element)
        return (self._xpaths if part is None else part.xpaths).path_of(element)

    def element_at(self, xpath: str, path: str | None = None) -> etree._Element | None:
        """The element :meth:`xpath_of` names ``xpath`` in the file named ``path`` (one it
        includes; any other name is the document's own), found step by step through
        indexed children: evaluating such an XPath scans every sibling its ``[@id=...]``
        predicate filters (10 ms per finding on a city map)."""
        if self.tree is None:
            return None
        part = self.part_named(path)
        if part is not None:
            return part.xpaths.element_at(part.root, xpath)
        return self._xpaths.element_at(self.tree.getroot(), xpath)

    def part_named(self, path: str | None) -> IncludedPart | None:
        """The included file whose findings carry ``path``; ``None`` for any other name."""
        if path is None or path == self.path:
            return None
        return next((part for part in self.parts if part.path == path), None)

    @cached_property
    def _positions(self) -> SourcePositions:
        # made on the first question: a clean map never pays for the scan
        assert self.tree is not None, "line_of needs a parsed tree"
        return SourcePositions(self.data, self.tree.getroot(), self.tree.docinfo.encoding)

    @cached_property
    def _xpaths(self) -> ReadableXPaths:
        return ReadableXPaths(self.spliced)

    @cached_property
    def editable(self) -> EditableSource | str:
        """The document's own source, ready for the edits of fixes; where it cannot be
        edited byte for byte, why not."""
        from xodrlint.document.edits import EditableSource, EditError

        assert self.tree is not None, "only a parsed document is edited"
        try:
            return EditableSource(self.data, self.tree.getroot(), foreign=self.spliced)
        except EditError as error:
            return str(error)

    def fix_positions(self) -> None:
        """Index the positions of the document's own nodes now, before includes add
        nodes of other files to its tree (the index pairs the k-th node with the k-th
        start tag of its bytes)."""
        self._positions.index_comments()


def load_bytes(data: bytes, path: str) -> Document:
    """Parse ``data`` (the contents of ``path``) into a :class:`Document`."""
    doc = Document(path=path, data=data)
    root = parse_root(data)
    if isinstance(root, Unparsed):
        doc.report("XS001", root.hit("the file"))
        return doc
    doc.tree = root.getroottree()
    if root.tag != "OpenDRIVE":
        doc.report("XS002", Hit(root, _root_message(root)))
        return doc
    _read_header(doc, root)
    return doc


class Unparsed(NamedTuple):
    """Why bytes hold no XML tree: they are not well-formed (``line`` and ``column``
    where the parser stopped), lxml cannot even hand them to libxml2 (an unknown codec:
    ``line`` 1), or they hold no element."""

    reason: str
    """``malformed``, ``unreadable`` or ``empty``."""
    detail: str
    """The parser's message (``malformed``), the codec's (``unreadable``), else empty."""
    line: int
    column: int | None = None

    def hit(self, subject: str) -> Hit:
        """The XS001 finding of a file (``subject``: how the message names it)."""
        if self.reason == "malformed":
            return Hit(None, self.detail, line=self.line, column=self.column)
        if self.reason == "unreadable":
            return Hit(None, f"cannot read {subject} as XML: {self.detail}", line=1)
        return Hit(None, f"{subject} holds no XML element", line=1)


def parse_root(data: bytes) -> etree._Element | Unparsed:
    """The root element of ``data`` parsed by the hardened parser, elements of an
    earlier schema's namespace renamed to their local names; or why there is none.
    The one parse of every file xodrlint reads: a checked file, and each it includes."""
    parser = hardened_parser()
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as error:
        return _syntax_error(data, error, parser.error_log)
    except (ValueError, LookupError) as error:
        # lxml raises these for input it cannot even hand to libxml2 (an unknown codec).
        return Unparsed("unreadable", str(error), 1)
    if root is None:
        return Unparsed("empty", "", 1)
    legacy = etree.QName(root).namespace
    if legacy in LEGACY_NAMESPACES:
        _drop_legacy_namespace(root, legacy)
    return root


def _syntax_error(data: bytes, error: etree.XMLSyntaxError, log: etree._ListErrorLog) -> Unparsed:
    """The first error of this parse: later ones are usually consequences of it.

    The parser's own log is used, not the exception's: lxml's global log also holds
    errors of earlier parses in the same thread.
    """
    entries = list(log.filter_from_errors())
    if entries:
        first = entries[0]
        line, column, message = first.line, first.column, first.message
    else:
        line, column = error.position
        message = error.msg or "not well-formed XML"
    message = _LIBXML2_POSITION_SUFFIX.sub("", message.strip()).rstrip(".")
    line, column = parser_position_by_line_ends(data, max(line, 1), column or None)
    return Unparsed("malformed", readable_parser_message(message), line, column)


_LIBXML2_POSITION_SUFFIX: Final = re.compile(r",\s*line \d+, column \d+$")


def _drop_legacy_namespace(root: etree._Element, namespace: str) -> None:
    """Rename elements of an earlier schema's namespace to their local names, on the tree
    only."""
    prefix = "{" + namespace + "}"
    for element in root.iter(etree.Element):
        tag = element.tag
        if isinstance(tag, str) and tag.startswith(prefix):
            element.tag = tag[len(prefix) :]
    etree.cleanup_namespaces(root)


def _root_message(root: etree._Element) -> str:
    qname = etree.QName(root)
    if qname.namespace:
        return (
            f"root element is '{qname.localname}' in namespace '{qname.namespace}', "
            "expected 'OpenDRIVE' without a namespace"
        )
    return f"root element is '{qname.localname}', expected 'OpenDRIVE'"


def _read_header(doc: Document, root: etree._Element) -> None:
    first = next(root.iterchildren(etree.Element), None)
    if first is None or first.tag != "header":
        found = "no child element" if first is None else f"'{first.tag}'"
        doc.report("XS003", Hit(root, f"'OpenDRIVE' must start with 'header', found {found}"))
        return
    header = first
    major = _version_number(doc, header, "revMajor")
    minor = _version_number(doc, header, "revMinor")
    if major is None or minor is None:
        return
    doc.declared = Version(major, minor)
    doc.effective = nearest_published(doc.declared)
    if doc.effective != doc.declared:
        doc.report(
            "XS005",
            Hit(
                header,
                f"OpenDRIVE {doc.declared} is not a published version; "
                f"checked as OpenDRIVE {doc.effective}",
            ),
        )


def _version_number(doc: Document, header: etree._Element, attribute: str) -> int | None:
    raw = header.get(attribute)
    if raw is None:
        doc.report("XS004", Hit(header, f"'header' has no '{attribute}'"))
        return None
    text = raw.strip()
    if not text.isascii() or not text.isdigit():
        doc.report(
            "XS004",
            Hit(header, f"'header/@{attribute}' is '{raw}', expected a non-negative integer"),
        )
        return None
    return int(text)


def nearest_published(version: Version) -> Version:
    """The published OpenDRIVE version closest to ``version`` (itself if published)."""
    if version.major < 1:
        return Version(1, KNOWN_MINORS[0])
    if version.major > 1:
        return Version(1, KNOWN_MINORS[-1])
    minor = min(max(version.minor, KNOWN_MINORS[0]), KNOWN_MINORS[-1])
    return Version(1, minor)
