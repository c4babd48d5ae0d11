"""Inline suppressions: XML comments that withhold findings, read from the parsed tree.

``<!-- xodrlint: ignore[PT001,SW] reason -->`` right before an element withholds those
codes on that element and everything inside it; ``<!-- xodrlint: ignore-file[ST011] -->``
anywhere withholds them in the whole file. Entries are what ``--select`` takes: codes,
code prefixes, rule names or UIDs. The engine applies them after the one-defect-one-
finding policy, so a withheld finding never lets a less specific one through.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Final

from lxml import etree

from xodrlint.document.load import Document
from xodrlint.document.positions import document_comments, wide_encoding
from xodrlint.findings import Hit
from xodrlint.fixes import Fix, remove_comment, replace_comment

DIRECTIVE: Final = re.compile(
    r"^\s*xodrlint:\s*(?P<scope>ignore-file|ignore)\s*\[(?P<codes>[^\]]*)\]\s*(?P<reason>.*?)\s*$",
    re.DOTALL,
)
FILE_SCOPE: Final = "ignore-file"
#: Every directive holds this word, in whatever encoding the file is in.
#: A directive starts "xodrlint:" (a map merely naming the tool, as the benchmark's header
#: does, holds none): that text in UTF-8 (and every encoding whose ASCII is one byte), and
#: in UTF-16 and UTF-32 of either byte order, written out (encoding it at import loaded
#: four codecs, a millisecond of every run).
_MARKER: Final = b"xodrlint:"
_WIDE_MARKERS: Final = {
    "utf-16-le": b"x\0o\0d\0r\0l\0i\0n\0t\0:\0",
    "utf-16-be": b"\0x\0o\0d\0r\0l\0i\0n\0t\0:",
    "utf-32-le": b"x\0\0\0o\0\0\0d\0\0\0r\0\0\0l\0\0\0i\0\0\0n\0\0\0t\0\0\0:\0\0\0",
    "utf-32-be": b"\0\0\0x\0\0\0o\0\0\0d\0\0\0r\0\0\0l\0\0\0i\0\0\0n\0\0\0t\0\0\0:",
}


def may_hold_directives(data: bytes) -> bool:
    """False when the file cannot hold a suppression comment (most files): a byte search
    is far cheaper than walking every comment of a large map. One search, for the
    marker in the file's own encoding (five took 31 ms of a 20 MB map's run)."""
    wide = wide_encoding(data)
    return (_MARKER if wide is None else _WIDE_MARKERS[wide[0]]) in data


#: Whether a selector (code, prefix, name or UID) names a rule code.
Matcher = Callable[[str, str], bool]


@dataclass
class Directive:
    comment: etree._Element
    scope: str
    selectors: tuple[str, ...]
    reason: str
    target: etree._Element | None
    """The element an ``ignore`` comment stands before; ``None`` for ``ignore-file`` and
    for a comment with no element after it."""
    used: set[str] = field(default_factory=set)
    """The selectors that withheld at least one finding."""

    @property
    def is_file_wide(self) -> bool:
        return self.scope == FILE_SCOPE


def read_directives(
    root: etree._Element | None, file_of: Callable[[etree._Element], str] | None = None
) -> list[Directive]:
    """Every suppression comment of the document, in document order. ``file_of`` names
    the file a node stands in, where includes brought others' nodes into the tree: an
    ``ignore`` comment then applies to the next element of its own file only."""
    if root is None:
        return []
    found = []
    for comment in document_comments(root):
        match = DIRECTIVE.match(comment.text or "")
        if match is None:
            continue
        selectors = tuple(s.strip() for s in match["codes"].split(",") if s.strip())
        file_wide = match["scope"] == FILE_SCOPE
        target = None if file_wide else _next_element(comment, file_of)
        found.append(Directive(comment, match["scope"], selectors, match["reason"], target))
    return found


def _next_element(
    comment: etree._Element, file_of: Callable[[etree._Element], str] | None
) -> etree._Element | None:
    for sibling in comment.itersiblings():
        if isinstance(sibling.tag, str):
            if file_of is not None and file_of(sibling) != file_of(comment):
                return None
            return sibling
    return None


class Suppressions:
    """Answers "is this code withheld on this element?" for one document."""

    def __init__(
        self,
        directives: list[Directive],
        matches: Matcher,
        file_of: Callable[[etree._Element], str] | None = None,
    ) -> None:
        self.directives = directives
        self._matches = matches
        # an ignore-file comment in an included file withholds in that file only
        self._file_of = file_of
        self._by_target: dict[etree._Element, list[Directive]] = {}
        self._file_wide = [d for d in directives if d.is_file_wide]
        for directive in directives:
            if directive.target is not None:
                self._by_target.setdefault(directive.target, []).append(directive)

    def withholding(self, code: str, element: etree._Element | None) -> Directive | None:
        """The directive that withholds ``code`` on ``element``, marking it used."""
        for directive in self._candidates(element):
            for selector in directive.selectors:
                if self._matches(selector, code):
                    directive.used.add(selector)
                    return directive
        return None

    def _candidates(self, element: etree._Element | None) -> Iterator[Directive]:
        current = element
        while current is not None and self._by_target:
            yield from self._by_target.get(current, ())
            current = current.getparent()
        file_of = self._file_of
        if file_of is None or element is None or not self._file_wide:
            yield from self._file_wide
            return
        where = file_of(element)
        yield from (d for d in self._file_wide if file_of(d.comment) == where)

    def unused(
        self, judgeable: Callable[[str], bool]
    ) -> Iterator[tuple[Directive, tuple[str, ...]]]:
        """Each directive with the selectors that withheld nothing. Only ``judgeable``
        selectors count: one whose rules did not run may well be needed."""
        for directive in self.directives:
            idle = tuple(s for s in directive.selectors if s not in directive.used and judgeable(s))
            if idle or not directive.selectors:
                yield directive, idle


def unused_hits(
    doc: Document, suppressions: Suppressions, judgeable: Callable[[str], bool]
) -> Iterator[Hit]:
    """A hit per suppression comment with entries that withheld nothing (the XL001 rule
    reports them). It is about the element the comment stands before (for a file-wide
    comment, the one holding it), so a suppression of that element covers it, but its
    line is the comment's."""
    for directive, idle in suppressions.unused(judgeable):
        anchor = directive.target if directive.target is not None else _holder(doc, directive)
        shown = ", ".join(idle) if idle else "nothing"
        line, column = doc.position_of(directive.comment)
        yield Hit(
            anchor,
            f"'xodrlint: {directive.scope}[{', '.join(directive.selectors)}]' "
            f"withholds no finding ({shown})",
            line=line,
            column=column,
            fix=_without(directive, idle),
        )


def _without(directive: Directive, idle: tuple[str, ...]) -> Fix:
    """XL001's fix: the idle entries taken out of the comment, or the whole comment (and
    its line, where it stood alone there) when none is left."""
    comment = directive.comment
    kept = [selector for selector in directive.selectors if selector not in idle]
    match = DIRECTIVE.match(comment.text or "")
    if not kept or match is None:
        return Fix("remove the suppression comment", (remove_comment(comment),))
    text = comment.text or ""
    written = match["codes"]
    # an empty entry (``[A,,B]``) goes with the idle ones: no stray comma is left
    remaining = [
        entry for entry in written.split(",") if entry.strip() and entry.strip() not in idle
    ]
    # the blanks inside the brackets as written, around the entries that are left
    lead = written[: len(written) - len(written.lstrip())]
    trail = written[len(written.rstrip()) :]
    codes = lead + ",".join(remaining).strip() + trail
    rewritten = text[: match.start("codes")] + codes + text[match.end("codes") :]
    removed = ", ".join(idle)
    return Fix(f"remove {removed} from the suppression", (replace_comment(comment, rewritten),))


def _holder(doc: Document, directive: Directive) -> etree._Element | None:
    """The element a comment without a target is about: the one holding it, or where an
    include brought it in from another file, an element of that file beside it (the
    finding then names the comment's file)."""
    comment = directive.comment
    holder = comment.getparent()
    if holder is None or doc.part_of(comment) is doc.part_of(holder):
        return holder
    part = doc.part_of(comment)
    siblings = [*comment.itersiblings(preceding=True), *comment.itersiblings()]
    return next(
        (node for node in siblings if isinstance(node.tag, str) and doc.part_of(node) is part),
        holder,
    )
