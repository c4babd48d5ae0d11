"""OpenDRIVE's ``<include file="..."/>``: what an included file holds joins the document.

The standard leaves "the processing of the files" to the application. xodrlint reads an
include the way SUMO's importer does: the included file's content stands where the
``include`` stands. When the included file's root element has the tag of the include's
parent (an ``OpenDRIVE`` file included in ``OpenDRIVE``, a ``planView`` in a
``planView``), its children join that parent, but for a ``header`` (the including file's
governs); otherwise its root element itself does (a ``road`` file included in
``OpenDRIVE``). So references resolve across files, and the rules judge the whole network.

Each node keeps its file: a finding on it carries that file's name, line and XPath
(:class:`~xodrlint.document.load.IncludedPart`). The schema check judges the checked file as
written, and only it (an included fragment has no header of its own, and its elements
may stand where the schema's order would not put them): it runs before the included
content joins the tree. Included content is judged by the rules.

What is read, and what is an XS007 finding on the ``include`` instead: only files inside
the folder of the file the run was given (and below it), after symbolic links are
resolved; never a URL; at most :data:`MAX_DEPTH` includes deep; never a file that
includes itself; regular files only, no larger than the run's ``max-file-size``, parsed
with the same hardened parser as a map. A file included twice joins once: the work is
bounded by the files of the folder, whatever a hostile tree of includes asks for.
"""

from __future__ import annotations

import os
import posixpath
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Final

from lxml import etree

from xodrlint.document.load import Document, IncludedPart, Unparsed, parse_root
from xodrlint.document.positions import SourcePositions
from xodrlint.document.xpaths import ReadableXPaths
from xodrlint.findings import Hit
from xodrlint.inputs.files import FileTooLarge, NotRegularFile, os_reason, read_regular_file
from xodrlint.validation.messages import missing_reference

#: How many includes deep a chain is followed (the main file's own includes are depth 1).
MAX_DEPTH: Final = 8
#: Content inside these elements is the application's own, not OpenDRIVE: an ``include``
#: there is not one of OpenDRIVE's.
_OPAQUE: Final = frozenset({"userData"})
#: ``scheme:`` at the start of a name: a URL (one letter is a Windows drive, no scheme).
_URL: Final = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]+:")


def has_includes(doc: Document) -> bool:
    """Whether ``doc`` holds an ``include`` to follow (a byte search first: most maps
    hold none, and walking a city map's tree costs more; a file in UTF-16 or UTF-32,
    where the word is no such run of bytes, is walked)."""
    if doc.root is None or not doc.may_include:
        return False
    return next(_includes_in(doc.root), None) is not None


def expand_includes(doc: Document, location: Path | None, limit: int | None) -> list[Hit]:
    """Bring what ``doc``'s includes name into its tree; an XS007 hit for each include
    that cannot be followed. ``location`` is the file ``doc`` was read from (``None``:
    standard input without a name, an object by URL), ``limit`` the largest file read."""
    assert doc.root is not None
    doc.fix_positions()
    includes = list(_includes_in(doc.root))
    if location is None:
        reason = "is not read: the file being checked was not read from a folder"
        return [Hit(include, _about(include, reason)) for include in includes]
    # names resolve from the folder the file was named in (as any reader opens them);
    # what is read must lie in that folder's real tree
    given = location if location.is_absolute() else Path.cwd() / location
    walk = _Walk(doc, Path(os.path.realpath(given.parent)), limit)
    walk.follow(includes, _Includer(given, Path(os.path.realpath(given)), doc.path, ()))
    return walk.hits


@dataclass(frozen=True)
class _Includer:
    """A file whose includes are followed: the path it was reached by (its includes'
    names start from its folder), the file that is, its name in reports, and the files
    that include it (outermost first)."""

    given: Path
    real: Path
    shown: str
    chain: tuple[Path, ...]


@dataclass
class _Walk:
    doc: Document
    folder: Path
    limit: int | None
    seen: set[Path] = field(default_factory=set)
    hits: list[Hit] = field(default_factory=list)

    def follow(self, includes: list[etree._Element], includer: _Includer) -> None:
        for include in includes:
            reason = self._follow(include, includer)
            if reason is not None:
                self.hits.append(Hit(include, _about(include, reason)))

    def _follow(self, include: etree._Element, includer: _Includer) -> str | None:
        """Splice one include's content after it; why it cannot be, if it cannot."""
        name = include.get("file") or ""
        if not name.strip():
            return "names no file"
        if _URL.match(name):
            return "is a URL: xodrlint reads no include from the network"
        given = includer.given.parent / name
        real = Path(os.path.realpath(given))
        if not real.is_relative_to(self.folder):
            folder = posixpath.dirname(self.doc.path) or "."
            return f"lies outside {folder}, the folder of the file being checked"
        chain = (*includer.chain, includer.real)
        if real in chain:
            loop = " -> ".join(path.name for path in (*chain[chain.index(real) :], real))
            return f"includes itself ({loop})"
        if len(chain) > MAX_DEPTH:
            return f"is more than {MAX_DEPTH} includes deep"
        if real in self.seen:
            return None  # its content joined the document at its first include
        try:
            data = read_regular_file(real, self.limit)
        except (FileTooLarge, NotRegularFile) as error:
            return str(error)
        except OSError as error:
            return f"cannot be read: {os_reason(error)}"
        parsed = _parse(data)
        if isinstance(parsed, str):
            return parsed
        if parsed.tag == "include":
            return "holds an include as its root element: include the file it names instead"
        self.seen.add(real)
        shown = _shown(includer.shown, name)
        part = IncludedPart(
            shown,
            data,
            parsed,
            SourcePositions(data, parsed, parsed.getroottree().docinfo.encoding),
            ReadableXPaths(self.doc.spliced),
        )
        part.positions.index_comments()
        for node in _content(parsed, include):  # XPaths in their own file, before moves
            if isinstance(node.tag, str):
                part.xpaths.path_of(node)
        self.follow(list(_includes_in(parsed)), _Includer(given, real, shown, chain))
        self.doc.parts.append(part)
        anchor = include
        # what its own includes brought in comes along, and keeps its own file
        for node in _content(parsed, include):
            anchor.addnext(node)
            self.doc.spliced.setdefault(node, part)
            anchor = node
        return None


def unresolved(hits: Sequence[Hit], doc: Document) -> list[Hit]:
    """Schema hits of ``doc`` without the key references its included files resolve.

    The schema judged the file as written, where a ``sideTrack`` may name a road an
    include brings: that reference is sound. A reference is dropped only where an
    included element of the tag and attribute the key names holds the value; the rules
    judge the railroad's references on the whole network anyway (SW004, PT001, ST001).
    """
    if not doc.parts:
        return list(hits)
    defined: set[tuple[str, str, str]] | None = None
    kept = []
    for hit in hits:
        missing = missing_reference(hit.message) if hit.kind == "keyref" else None
        if missing is not None:
            if defined is None:
                defined = _included_keys(doc)
            value, holder, attribute = missing
            if (holder, attribute, value) in defined:
                continue
        kept.append(hit)
    return kept


def _included_keys(doc: Document) -> set[tuple[str, str, str]]:
    """(tag, attribute, value) of every attribute of the elements includes brought."""
    return {
        (element.tag, str(name), str(value))
        for node in doc.spliced
        if isinstance(node.tag, str)
        for element in node.iter(etree.Element)
        if isinstance(element.tag, str)
        for name, value in element.attrib.items()
    }


def _parse(data: bytes) -> etree._Element | str:
    """The root element of an included file, or why it has none."""
    root = parse_root(data)
    if not isinstance(root, Unparsed):
        return root
    if root.reason == "malformed":
        return f"is not well-formed XML at line {root.line}: {root.detail}"
    if root.reason == "unreadable":
        return f"cannot be read as XML: {root.detail}"
    return "holds no XML element"


def _shown(includer: str, name: str) -> str:
    """An included file's name in reports: as the include names it, from the folder of
    its includer's name (an absolute name as it is)."""
    if posixpath.isabs(name):
        return posixpath.normpath(name)
    return posixpath.normpath(posixpath.join(posixpath.dirname(includer), name))


def _content(root: etree._Element, include: etree._Element) -> list[etree._Element]:
    """The nodes of an included file that join the include's parent, with the comments
    before its root (a suppression comment may stand there)."""
    before = list(root.itersiblings(etree.Comment, preceding=True))[::-1]
    parent = include.getparent()
    if parent is None or root.tag != parent.tag:
        return [*before, root]
    nodes: list[etree._Element] = before
    for node in root:
        if node.tag == "header" and parent.tag == "OpenDRIVE":
            continue
        nodes.append(node)
    return nodes


def _includes_in(root: etree._Element) -> Iterator[etree._Element]:
    """The ``include`` elements below ``root``, in document order, but for those inside
    an application's own data."""
    for include in root.iterdescendants("include"):
        if not any(ancestor.tag in _OPAQUE for ancestor in include.iterancestors()):
            yield include


#: The longest file name a message repeats in full.
_SHOWN_NAME: Final = 120


def _about(include: etree._Element, reason: str) -> str:
    name = include.get("file", "")
    if len(name) > _SHOWN_NAME:
        name = name[: _SHOWN_NAME - 3] + "..."
    return f"include '{name}' {reason}"
