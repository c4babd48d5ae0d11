"""Where libxml2 stops looking: after an unexpected child libxml2 skips it and its
following siblings, and it skips an element whose type is abstract; XSD 1.1 validation
(xmlschema) goes on. Those subtrees are validated with xmlschema itself, and when they
hold nodes of the root's keys and keyrefs, those are computed again over the document.
The rare case this cannot cover (a key held below the root) falls back to full.

libxml2's hits are also moved to where xmlschema reports them (child-order errors on the
parent), so both paths place a finding on the same element.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Iterable, Iterator, Sequence
from typing import Any, Final

from lxml import etree

from xodrlint.findings import CHILD_KINDS, Hit
from xodrlint.validation.xsd11 import NeedsFull
from xodrlint.validation.xsd11.governing import SchemaModel

#: libxml2 kinds folded onto xmlschema's: what the XS006 rule and the engine tell apart.
_UNEXPECTED: Final = CHILD_KINDS - {"missing_child"}

_IDENTITY_KINDS: Final = frozenset({"keyref", "duplicate", "key_field"})


def as_xsd11(hit: Hit) -> Hit:
    """A libxml2 hit where and as xmlschema reports it: child-order errors on the parent."""
    element = hit.element
    if hit.kind in _UNEXPECTED and element is not None and element.getparent() is not None:
        element = element.getparent()
    if hit.kind in ("keyref", "duplicate"):
        kind = hit.kind
    elif hit.kind in CHILD_KINDS:
        kind = "missing_child"
    else:
        kind = "other"
    return Hit(
        element, hit.message, line=hit.line, column=hit.column, kind=kind, related=hit.related
    )


class Subtrees:
    """Membership test for the subtrees below a few roots."""

    def __init__(self, roots: Iterable[tuple[etree._Element, Any]]) -> None:
        self._ids = {id(element) for element, _ in roots}
        self._elements = [element for element, _ in roots]

    def holds(self, element: etree._Element | None) -> bool:
        if element is None or not self._ids:
            return False
        if id(element) in self._ids:
            return True
        return any(id(ancestor) in self._ids for ancestor in element.iterancestors())


class RootIdentities:
    """The root's keys, uniques and keyrefs, evaluated over the whole document.

    Errors are made as xmlschema makes them (one per bad value and constraint), so the
    full validator's mapping places them on every element concerned. Field values are
    compared as strings: the 1.1-only path only runs this for ``@attribute`` fields of
    string types, where that is what XSD compares.
    """

    def __init__(self, root: etree._Element, constraints: list[Any]) -> None:
        self.root = root
        self.constraints = constraints
        self._selected = {id(c): _select(root, c) for c in constraints}
        self.selected = {id(n) for nodes in self._selected.values() for n in nodes}
        for constraint in constraints:
            for path in (f.path for f in constraint.fields):
                if not (path.startswith("@") and path[1:].isidentifier()):
                    raise NeedsFull(f"key field {path!r} is not a plain attribute")
            _check_string_fields(constraint)

    def recomputes(self, hit: Hit) -> bool:
        """Is ``hit`` libxml2's word on one of these constraints (computed here again)?"""
        if hit.kind not in _IDENTITY_KINDS:
            return False
        return hit.element is None or id(hit.element) in self.selected

    def all_selected(self) -> Iterator[etree._Element]:
        for nodes in self._selected.values():
            yield from nodes

    def _values(self, constraint: Any) -> Iterator[tuple[etree._Element, tuple[str, ...] | None]]:
        names = [f.path[1:] for f in constraint.fields]
        for node in self._selected[id(constraint)]:
            values = tuple(node.get(name) for name in names)
            if any(v is None for v in values):
                yield node, None
            else:
                yield node, tuple(str(v) for v in values)

    def errors(self, raw: Sequence[Hit]) -> Iterator[Any]:
        from xmlschema import XMLSchemaValidationError

        tables: dict[int, Counter[tuple[str, ...]]] = {}
        required = {
            (id(hit.element), hit.message.rpartition(" '")[2].rstrip("'"))
            for hit in raw
            if hit.kind == "required" and hit.element is not None
        }
        for constraint in self.constraints:
            if _kind(constraint) == "keyref":
                continue
            counter: Counter[tuple[str, ...]] = Counter()
            for node, values in self._values(constraint):
                if values is None:
                    missing = [f.path for f in constraint.fields if node.get(f.path[1:]) is None]
                    if _kind(constraint) == "key" and not any(
                        (id(node), path[1:]) in required for path in missing
                    ):
                        reason = f"missing key field {missing[0]!r} for {constraint!r}"
                        yield XMLSchemaValidationError(constraint, node, reason)
                    continue
                counter[values] += 1
                if counter[values] == 2:
                    reason = f"duplicated value {values!r} for {constraint!r}"
                    yield XMLSchemaValidationError(constraint, node, reason)
            tables[id(constraint)] = counter
        for constraint in self.constraints:
            refer = getattr(constraint, "refer", None)
            if _kind(constraint) != "keyref" or refer is None:
                continue
            if id(refer) not in tables:
                raise NeedsFull(f"keyref {constraint.name} refers to a key below the root")
            counter = Counter(values for _, values in self._values(constraint) if values)
            for values, times in counter.items():
                if values in tables[id(refer)]:
                    continue
                suffix = f" ({times} times)" if times > 1 else ""
                reason = f"value {values!r} not found for {refer!r}{suffix}"
                yield XMLSchemaValidationError(constraint, self.root, reason)


def _select(holder: etree._Element, constraint: Any) -> list[etree._Element]:
    found = holder.xpath(constraint.selector.path)
    return [n for n in found if isinstance(n, etree._Element)] if isinstance(found, list) else []


def _kind(constraint: Any) -> str:
    name = type(constraint).__name__.lower()
    return "keyref" if "keyref" in name else "unique" if "unique" in name else "key"


def _check_string_fields(constraint: Any) -> None:
    elements = getattr(constraint, "elements", None) or {}
    for declaration in elements:
        attributes = getattr(getattr(declaration, "type", None), "attributes", None)
        for path in (f.path for f in constraint.fields):
            attribute = attributes.get(path[1:]) if attributes is not None else None
            simple = getattr(attribute, "type", None)
            primitive = getattr(simple, "primitive_type", None)
            if simple is None or getattr(primitive, "local_name", None) != "string":
                raise NeedsFull(f"key field {path!r} is not a string")
            if getattr(simple, "white_space", "preserve") not in (None, "preserve"):
                raise NeedsFull(f"key field {path!r} is whitespace-normalized")


def skipped_subtrees(
    hits: Sequence[Hit], schema_model: Callable[[], SchemaModel]
) -> list[tuple[etree._Element, Any]]:
    """The subtrees libxml2 did not validate and XSD 1.1 does, with declarations.
    ``schema_model`` is called only when a hit says libxml2 skipped something."""
    roots: dict[etree._Element, Any] = {}
    for hit in hits:
        element = hit.element
        if element is None or hit.kind not in (*_UNEXPECTED, "abstract"):
            continue
        model = schema_model()
        if hit.kind == "abstract":
            declaration = model.declaration_of(element)
            if declaration is not None:
                roots[element] = declaration
            continue
        parent = element.getparent()
        if parent is None:
            continue
        holder = model.declaration_of(parent)
        if holder is None:
            continue
        children = model.children(model.governing_type(holder, parent))
        for sibling in (element, *element.itersiblings()):
            if isinstance(sibling.tag, str) and sibling.tag in children:
                roots.setdefault(sibling, children[sibling.tag])
    return list(roots.items())


def root_identities(
    schema: Any, root: etree._Element, skipped: list[tuple[etree._Element, Any]]
) -> RootIdentities | None:
    """The root's keys and keyrefs, recomputed if libxml2 skipped some of their nodes."""
    inside = Subtrees(skipped)
    root_declaration = schema.elements.get(root.tag)
    for constraint in schema.identities.values():
        holder = getattr(constraint, "parent", None)
        if holder is root_declaration or holder is None:
            continue
        for element, _ in skipped:
            for ancestor in element.iterancestors(holder.local_name):
                if any(inside.holds(n) for n in _select(ancestor, constraint)):
                    raise NeedsFull("a key below the root covers a skipped subtree")
    identities = RootIdentities(root, list(getattr(root_declaration, "identities", ())))
    if not any(inside.holds(node) for node in identities.all_selected()):
        return None
    return identities
