"""Governing types: the type XSD 1.1 validates each element by (the declared one, or
the one the first matching type alternative names), and which elements of a document
the 1.1-only checks must visit.

The components come from xmlschema's model of the set, built lazily, once per process;
lookups are cached, because a city map asks the same questions tens of thousands of
times. A walk from the root enters only subtrees whose types can hold an assertion or a
type alternative.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any

from lxml import etree

from xodrlint.validation.xsd11 import NeedsFull
from xodrlint.validation.xsd11.assertions import (
    TypeAssertions,
    Unprunable,
    XPathNames,
    type_assertions,
)
from xodrlint.validation.xsd11.selectors import Checked


@dataclass(frozen=True, slots=True)
class Plan:
    """What the 1.1-only checks found to do in one document: the type marks, the elements
    whose assertions xmlschema evaluates (with their types), and what the translated
    assertions found (``None`` without a translation)."""

    marks: list[tuple[etree._Element, str]]
    asserted: list[tuple[etree._Element, Any]]
    checked: Checked | None = None


class SchemaModel:
    """The xmlschema components the 1.1-only checks need, with lookups cached.
    ``translated``: (type name, test) of the assertions libxml2 runs in XPath 1.0
    (:mod:`~xodrlint.validation.xsd11.selectors`), which :meth:`assertions_of` leaves out
    unless asked for every assertion."""

    def __init__(self, schema: Any, translated: frozenset[tuple[str, str]] = frozenset()) -> None:
        self.schema = schema
        self.translated = translated
        self._children: dict[int, dict[str, Any]] = {}
        self._assertions: dict[tuple[int, bool], TypeAssertions] = {}
        self._alternatives: dict[tuple[int, tuple[str | None, ...]], Any] = {}
        self._alternative_reads: dict[int, tuple[str, ...] | None] = {}
        self._interesting = self._types_to_enter()

    def _types_to_enter(self) -> set[int]:
        """Types (by id) under which an assertion or a type alternative can occur."""
        below: dict[int, set[int]] = {}
        marked: set[int] = set()
        pending = [d.type for d in self.schema.elements.values()]
        while pending:
            xsd_type = pending.pop()
            if id(xsd_type) in below:
                continue
            below[id(xsd_type)] = set()
            if getattr(xsd_type, "assertions", None):
                # refuses assertions that might look too far
                self.assertions_of(xsd_type, every=True)
                marked.add(id(xsd_type))
            for declaration in self.children(xsd_type).values():
                if declaration.alternatives:
                    marked.add(id(xsd_type))
                for child in (declaration.type, *(a.type for a in declaration.alternatives)):
                    if child is not None:
                        below[id(xsd_type)].add(id(child))
                        pending.append(child)
        changed = True
        while changed:
            changed = False
            for key, children in below.items():
                if key not in marked and children & marked:
                    marked.add(key)
                    changed = True
        return marked

    def children(self, xsd_type: Any) -> dict[str, Any]:
        """Element declarations of a type's content model, by name."""
        found = self._children.get(id(xsd_type))
        if found is None:
            found = {}
            content = getattr(xsd_type, "content", None)
            if content is not None and hasattr(content, "iter_elements"):
                for declaration in content.iter_elements():
                    name = getattr(declaration, "name", None)
                    if name and hasattr(declaration, "alternatives"):
                        found.setdefault(name, declaration)
            self._children[id(xsd_type)] = found
        return found

    def declaration_interesting(self, declaration: Any) -> bool:
        """Can the element hold (or be) one the 1.1-only checks must visit?"""
        return bool(declaration.alternatives) or id(declaration.type) in self._interesting

    def governing_type(self, declaration: Any, element: etree._Element) -> Any:
        """The type XSD 1.1 validates ``element`` by: the declared one, or the one the
        first matching type alternative names."""
        if not declaration.alternatives:
            return declaration.type
        seen = self._alternative_attributes(declaration)
        if seen is None:
            return declaration.get_alternative_type(element)
        # the tests read only these attributes: so does the answer, and it is kept
        values = tuple(element.get(name) for name in seen)
        key = (id(declaration), values)
        found = self._alternatives.get(key)
        if found is None:
            shallow = etree.Element(
                element.tag, {n: v for n, v in zip(seen, values, strict=True) if v is not None}
            )
            found = self._alternatives[key] = declaration.get_alternative_type(shallow)
        return found

    def _alternative_attributes(self, declaration: Any) -> tuple[str, ...] | None:
        key = id(declaration)
        if key not in self._alternative_reads:
            names = XPathNames()
            try:
                for alternative in declaration.alternatives:
                    if alternative.token is not None:
                        names.kind_of(alternative.token)
            except Unprunable:
                self._alternative_reads[key] = None
            else:
                seen = None if names.elements else tuple(sorted(names.attributes))
                self._alternative_reads[key] = seen
        return self._alternative_reads[key]

    def assertions_of(self, xsd_type: Any, *, every: bool = False) -> TypeAssertions:
        """The type's assertions xmlschema evaluates: those not translated, or ``every``
        one (for an element the translation cannot judge exactly)."""
        key = (id(xsd_type), every)
        found = self._assertions.get(key)
        if found is None:
            name = str(getattr(xsd_type, "local_name", "") or "")
            translated = set() if every else self.translated
            found = self._assertions[key] = type_assertions(
                xsd_type, lambda assertion: (name, assertion.path) not in translated
            )
        return found

    def plan(self, root: etree._Element) -> Plan:
        """The elements whose type alternatives or assertions XSD 1.1 evaluates."""
        plan = Plan([], [])
        declaration = self.schema.elements.get(root.tag)
        if declaration is None:
            return plan
        pending = [(root, declaration)]
        while pending:
            element, declaration = pending.pop()
            xsd_type = self.governing_type(declaration, element)
            if declaration.alternatives and xsd_type is not declaration.type:
                plan.marks.append((element, type_name(xsd_type)))
            if getattr(xsd_type, "assertions", None):
                plan.asserted.append((element, xsd_type))
            children = self.children(xsd_type)
            if not children:
                continue
            for child in element.iterchildren(etree.Element):
                found = children.get(child.tag)
                if found is not None and self.declaration_interesting(found):
                    pending.append((child, found))
        return plan

    def declaration_of(self, element: etree._Element) -> Any | None:
        """The declaration XSD 1.1 validates ``element`` by, found from the root down."""
        path = [element, *element.iterancestors()]
        path.reverse()
        declaration = self.schema.elements.get(path[0].tag)
        for parent, step in itertools.pairwise(path):
            if declaration is None:
                return None
            declaration = self.children(self.governing_type(declaration, parent)).get(step.tag)
        return declaration


def type_name(xsd_type: Any) -> str:
    name = getattr(xsd_type, "local_name", None)
    if not name:
        raise NeedsFull("a type alternative with an anonymous type")
    return str(name)
