"""Fixes: what a rule proposes to change, and a fix as reports carry it.

A rule attaches a :class:`Fix` to a hit: a message and element-level edits (set an
attribute, rewrite or remove a comment, insert an element beside another), made with
:func:`set_attribute`, :func:`replace_comment`, :func:`remove_comment` and
:func:`insert_element`. The engine turns them into byte-exact text edits of the file as
read (:mod:`xodrlint.document.edits`) and hands each finding's :class:`FindingFix` on:
its edits with the line and column numbering of findings, for reports, the editor and
``--fix``. A **safe** fix keeps what the network means (a value spelled as the standard
spells it); an **unsafe** one changes it, and is applied only with ``--unsafe-fixes``.
"""

# No ``from __future__ import annotations``, as in :mod:`xodrlint.findings`: lxml's types
# stay quoted and are never imported here.
from collections.abc import Callable, Mapping, Sequence
from enum import StrEnum
from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:
    from lxml import etree


class Applicability(StrEnum):
    """Whether ``--fix`` applies a fix (safe) or only ``--unsafe-fixes`` does."""

    SAFE = "safe"
    UNSAFE = "unsafe"


class SetAttribute(NamedTuple):
    """Set ``element``'s attribute ``name`` to ``value``: its value replaced between its
    quotes, or the attribute added at the end of the start tag."""

    element: "etree._Element"
    name: str
    value: str


class ReplaceComment(NamedTuple):
    """Give ``comment`` the text ``text`` (what stands between ``<!--`` and ``-->``);
    ``None`` removes the comment, and its line when it stood alone there."""

    comment: "etree._Element"
    text: str | None


class InsertElement(NamedTuple):
    """Insert an element ``<tag a="v"/>`` ``where`` (``after`` or ``before``)
    ``anchor``, on a line of its own indented as ``anchor`` is (beside it, when
    ``anchor`` shares its line with other markup). ``children`` are empty elements it
    holds, each as ``(tag, attributes)``, one a line, indented one step further."""

    anchor: "etree._Element"
    tag: str
    attributes: tuple[tuple[str, str], ...]
    where: str = "after"
    children: tuple[tuple[str, tuple[tuple[str, str], ...]], ...] = ()


ElementEdit = SetAttribute | ReplaceComment | InsertElement
PLACES = ("after", "before")


class Fix(NamedTuple):
    """A rule's proposed mending of one defect: what it does, in words, and its edits
    (all made, or none)."""

    message: str
    edits: tuple[ElementEdit, ...]
    applicability: Applicability = Applicability.SAFE


def moved(
    fix: Fix | None, node_of: "Callable[[etree._Element], etree._Element | None]"
) -> Fix | None:
    """``fix`` with each node its edits name replaced by ``node_of``'s (a hit found on a
    copy of the tree, put on the original); ``None`` where a node has no counterpart."""
    if fix is None:
        return None
    edits: list[ElementEdit] = []
    for edit in fix.edits:
        node = node_of(edit[0])
        if node is None:
            return None
        edits.append(type(edit)(node, *edit[1:]))
    return fix._replace(edits=tuple(edits))


def set_attribute(element: "etree._Element", name: str, value: str) -> SetAttribute:
    """The edit that sets ``element``'s attribute ``name`` to ``value``."""
    return SetAttribute(element, name, value)


def replace_comment(comment: "etree._Element", text: str) -> ReplaceComment:
    """The edit that gives ``comment`` the text ``text``."""
    return ReplaceComment(comment, text)


def remove_comment(comment: "etree._Element") -> ReplaceComment:
    """The edit that removes ``comment`` (and its line, when it stood alone there)."""
    return ReplaceComment(comment, None)


def insert_element(
    anchor: "etree._Element",
    tag: str,
    attributes: Mapping[str, str],
    *,
    where: str = "after",
    children: Sequence[tuple[str, Mapping[str, str]]] = (),
) -> InsertElement:
    """The edit that inserts ``<tag .../>`` with ``attributes`` (in their order) after
    or before ``anchor``; with ``children``, ``<tag ...>`` holding those empty elements
    (``<link><predecessor .../></link>``)."""
    if where not in PLACES:
        raise ValueError(f"where={where!r}: one of {', '.join(PLACES)}")
    held = tuple((child, tuple(values.items())) for child, values in children)
    return InsertElement(anchor, tag, tuple(attributes.items()), where, held)


class TextEdit(NamedTuple):
    """One edit of the source: the text from (``start_line``, ``start_column``) to
    (``end_line``, ``end_column``), the end excluded, replaced by ``content``. Lines and
    columns are 1-based and counted as a finding's are (columns in characters);
    ``start`` and ``end`` are the same places as offsets in the decoded source."""

    content: str
    start_line: int
    start_column: int
    end_line: int
    end_column: int
    start: int
    end: int

    def as_dict(self) -> dict[str, object]:
        return {
            "content": self.content,
            "line": self.start_line,
            "column": self.start_column,
            "end_line": self.end_line,
            "end_column": self.end_column,
        }


class FindingFix(NamedTuple):
    """A finding's fix as reports carry it; ``edits`` is empty where the run did not
    place them (a text report needs only to know that a fix exists)."""

    applicability: Applicability
    message: str
    edits: tuple[TextEdit, ...] = ()

    def as_dict(self) -> dict[str, object]:
        return {
            "applicability": str(self.applicability),
            "message": self.message,
            "edits": [edit.as_dict() for edit in self.edits],
        }
