"""Stage 2 for OpenDRIVE 1.8 and later, the fast path: libxml2 on an XSD 1.0 form of the
schema, and the XSD 1.1-only constraints checked on just the elements they govern.

The findings equal those of full XSD 1.1 validation (:class:`~xodrlint.xsd11.Xsd11Validator`)
in element, line, XPath and kind; a test proves it on the corpus and on mutated files.

1. **The XSD 1.0 form** (:mod:`xodrlint.xsd10_form`) is a copy of every document of the set with
   ``xs:assert``/``xs:assertion`` and ``xs:alternative`` removed and the ``vc:`` versioning
   attributes resolved as an XSD 1.1 processor would. An element with alternatives keeps
   its declared type; the alternative an instance element selects is handed to libxml2 as
   an ``xsi:type`` on that element for the time of the validation (XSD 1.1 requires every
   alternative to derive from the declared type, which is what ``xsi:type`` needs). The
   form is written once per schema set and machine into the user cache folder, keyed by a
   SHA-256 of the source files. A set using XSD 1.1 features the form cannot express
   (open content, ``xs:override``, inheritable attributes, ...) is validated in full.
2. **The 1.1-only checks** run on the components of the xmlschema model (built lazily,
   once per process): each alternative's test via ``XsdElement.get_alternative_type``,
   each assertion's compiled XPath 2.0 token with a context built as xmlschema builds it,
   on the elements whose governing type carries it. A walk from the root finds them,
   entering only subtrees whose types can hold an assertion or an alternative.
3. **Where libxml2 stops looking**: after an unexpected child libxml2 skips it and its
   following siblings, and it skips an element whose type is abstract; XSD 1.1 validation
   (xmlschema) goes on. Those subtrees are validated with xmlschema itself, and when they
   hold nodes of the root's keys and keyrefs, those are computed again over the document.
   The rare case this cannot cover (a key held below the root) falls back to full, as
   does a file with an ``xsi:type`` or ``xsi:nil`` of its own, or a ``+INF`` (a number
   in XSD 1.1, not in XSD 1.0).

4. **Two stages for a forked child** (:meth:`FastXsd11Validator.stages`): the form's
   cache also records, from one strict xmlschema build of the set, where an element
   with type alternatives can stand. A document with no element there needs no type
   marks, so libxml2 runs alone in the child. The assertions need no libxml2 result:
   on a large document a second child loads the xmlschema model and checks them, while
   the caller runs its rules; the caller only merges, and loads the model itself only
   when libxml2 skipped a subtree. The model (built with the meta-schema check that
   strict build made once) is kept pickled beside the form, so runs load it instead of
   building it.

Messages of libxml2's errors come from ``xsd_messages`` (as for OpenDRIVE 1.7), those of
the 1.1-only checks and of the recovered subtrees from xmlschema's reasons (as in full
validation); key, keyref, assertion, missing-attribute and enumeration messages read the
same on both paths, others say the same in other words. Where xmlschema repeats itself
(a bad number three times, every unknown child of one parent) libxml2 says it once.

One difference is deliberate: xmlschema resolves a key's selector through declared types
only, so it never checks keys and keyrefs below an element with type alternatives (every
``junction/connection/@incomingRoad``, ``@connectingRoad``, ``@linkedRoad``, ...). libxml2
follows the instance, as XSD 1.1 says; the fast path reports those broken references.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import re
from collections import Counter
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final, Protocol

from lxml import etree

from xodrlint import background
from xodrlint.document import Document
from xodrlint.findings import Hit
from xodrlint.schemas import SchemaLoadError
from xodrlint.xsd10_form import Xsd10Form, full_validator, xsd10_form
from xodrlint.xsd_messages import CHILD_KINDS

#: ``full`` validates XSD 1.1 sets with xmlschema alone (slow; the reference behaviour).
MODE_ENV: Final = "XODRLINT_XSD11"

XSI: Final = "http://www.w3.org/2001/XMLSchema-instance"
XSI_TYPE: Final = f"{{{XSI}}}type"

#: libxml2 kinds folded onto xmlschema's: what the XS006 rule and the engine tell apart.
_UNEXPECTED: Final = CHILD_KINDS - {"missing_child"}
_IDENTITY_KINDS: Final = frozenset({"keyref", "duplicate", "key_field"})

# XPath in an assertion that might see past its element, where xmlschema's tree (the whole
# document) and ours (the element) could differ. elementpath stops the parent, ancestor
# and sibling axes at the context root, which is the element in both.
_UNBOUNDED_XPATH: Final = frozenset(
    {
        "preceding",
        "following",
        "id",
        "idref",
        "element-with-id",
        "lang",
        "base-uri",
        "document-uri",
        "doc",
        "doc-available",
        "collection",
    }
)
#: Axes that only lead to ancestors: a pruned copy keeps every ancestor of what it keeps.
_UPWARD_AXES: Final = frozenset({"parent", "ancestor", "ancestor-or-self", ".."})
_XSD11_READING: Final = (
    "boolean(//@xsi:type | //@xsi:nil | //@*[contains(., '+INF')] | //text()[contains(., '+INF')])"
)
# Starts at the colon: a pattern that starts with a character class scans a 20 MB map in
# 0.5 s, one that starts with a literal in 10 ms. It also matches what is no prefixed
# attribute (text ending in ':type='): the tree is asked then, which only costs time.
_PREFIXED_TYPE_OR_NIL: Final = re.compile(rb":(?:type|nil)\s*=")


#: The second part of a split validation: the first part's hits in, the findings out.
Finish = Callable[[list[Hit]], list[Hit]]
#: What the assertion stage found: "checked" with its hits, "marks" (an element stands
#: where a type alternative applies after all) or "full" (with the schema's reason, if
#: the reason is the schema's), as values that cross a fork.
_Stage = tuple[str, str, list[background.SentHit]]


class HitSource(Protocol):
    """A compiled libxml2 validator (``schema.Libxml2Validator``, a layer above)."""

    def hits(self, doc: Document) -> Iterator[Hit]: ...


class _NeedsFull(Exception):
    """This document meets something the fast path cannot reproduce: validate in full."""


# -- choosing a validator ------------------------------------------------------------------


def xsd11_validator(entry: Path, libxml2: Callable[[Path], HitSource]) -> HitSource:
    """The validator for an XSD 1.1 set: the fast path unless it cannot stand in for
    full validation (or ``XODRLINT_XSD11=full`` asks for full validation)."""
    if os.environ.get(MODE_ENV, "").strip().lower() != "full":
        with xsd10_form(entry) as form:
            compiled = None
            if form.entry is not None:
                # XSD 1.1 accepts content models XSD 1.0 refuses (overlapping wildcards)
                with contextlib.suppress(SchemaLoadError):
                    compiled = libxml2(form.entry)
        if compiled is not None:
            return FastXsd11Validator(entry, compiled, form)
    from xodrlint.xsd11 import Xsd11Validator  # xmlschema is slow to import

    return Xsd11Validator(entry)


# -- the XSD 1.1-only checks ---------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class _Plan:
    """What the 1.1-only checks found to do in one document."""

    marks: list[tuple[etree._Element, str]]
    asserted: list[tuple[etree._Element, Any]]


class _Model:
    """The xmlschema components the 1.1-only checks need, with lookups cached."""

    def __init__(self, schema: Any) -> None:
        self.schema = schema
        self._children: dict[int, dict[str, Any]] = {}
        self._assertions: dict[int, _TypeAssertions] = {}
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
                self.assertions_of(xsd_type)  # refuses assertions that might look too far
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
            names = _Names()
            try:
                for alternative in declaration.alternatives:
                    if alternative.token is not None:
                        names.kind_of(alternative.token)
            except _Unprunable:
                self._alternative_reads[key] = None
            else:
                seen = None if names.elements else tuple(sorted(names.attributes))
                self._alternative_reads[key] = seen
        return self._alternative_reads[key]

    def assertions_of(self, xsd_type: Any) -> _TypeAssertions:
        found = self._assertions.get(id(xsd_type))
        if found is None:
            found = self._assertions[id(xsd_type)] = _type_assertions(xsd_type)
        return found

    def plan(self, root: etree._Element) -> _Plan:
        """The elements whose type alternatives or assertions XSD 1.1 evaluates."""
        plan = _Plan([], [])
        declaration = self.schema.elements.get(root.tag)
        if declaration is None:
            return plan
        pending = [(root, declaration)]
        while pending:
            element, declaration = pending.pop()
            xsd_type = self.governing_type(declaration, element)
            if declaration.alternatives and xsd_type is not declaration.type:
                plan.marks.append((element, _type_name(xsd_type)))
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


def _type_name(xsd_type: Any) -> str:
    name = getattr(xsd_type, "local_name", None)
    if not name:
        raise _NeedsFull("a type alternative with an anonymous type")
    return str(name)


def _check_bounded(assertion: Any) -> None:
    """Refuse an assertion whose XPath might see past its element (see _UNBOUNDED_XPATH)."""
    for token in assertion.token.iter():
        symbol = getattr(token, "symbol", "")
        if symbol in _UNBOUNDED_XPATH or (symbol in ("/", "//") and len(token) < 2):
            raise _NeedsFull(f"assertion {assertion.path!r} looks beyond its element")


class FastXsd11Validator:
    """libxml2 on the XSD 1.0 form, then the XSD 1.1-only checks (see the module doc)."""

    def __init__(self, entry: Path, compiled: HitSource, form: Xsd10Form) -> None:
        self.entry = entry
        self.form = form
        self._libxml2 = compiled
        self._full: Any = None
        self._model: _Model | None = None
        self._unsupported: str | None = None

    @property
    def full(self) -> Any:
        """The full XSD 1.1 validator (its model serves the 1.1-only checks)."""
        if self._full is None:
            self._full = full_validator(self.entry, self.form)
        return self._full

    def model(self) -> _Model:
        if self._model is None:
            try:
                self._model = _Model(self.full.schema)
            except _NeedsFull as why:
                self._unsupported = str(why)
                raise
        return self._model

    def hits(self, doc: Document) -> Iterator[Hit]:
        assert doc.tree is not None
        try:
            found = list(self._fast_hits(doc))
        except _NeedsFull:
            found = list(self.full.hits(doc))
        yield from found

    def stages(self, doc: Document) -> tuple[Callable[[], list[Hit]], Finish]:
        """The validation in two parts, for a caller that runs the first one elsewhere (a
        forked child) while it does other work: libxml2 first, then the 1.1-only checks on
        libxml2's hits. Split only when libxml2 needs no type marks, so the first part
        needs no xmlschema model: no element of the document stands where the schema
        allows type alternatives. Otherwise all of it is the first part.

        The assertions of a split validation need no libxml2 result either: on a large
        document they run in a forked child of their own, beside libxml2's child and the
        rules, and the caller, needing no xmlschema model for a valid document, never
        loads one."""
        assert doc.tree is not None
        root = doc.tree.getroot()
        sites = self.form.alternative_sites
        if sites is None or self._unsupported is not None or _holds_a_site(doc, root, sites):
            return (lambda: list(self.hits(doc))), list
        checks = background.start(lambda: self._assertion_stage(doc, root), len(doc.data))
        return (
            (lambda: list(self._libxml2.hits(doc))),
            lambda raw: self._finish(doc, raw, checks.result()),
        )

    def _assertion_stage(self, doc: Document, root: etree._Element) -> _Stage:
        """The assertions' hits as values that cross a fork, or why they cannot stand."""
        try:
            model, plan = self._prepare(doc, root)
            if plan.marks:
                return ("marks", "", [])
            hits = self._assertion_hits(root, model, plan)
        except _NeedsFull:
            return ("full", self._unsupported or "", [])
        return ("checked", "", background.send_hits(hits, root))

    def _finish(self, doc: Document, raw: list[Hit], stage: _Stage) -> list[Hit]:
        assert doc.tree is not None
        root = doc.tree.getroot()
        outcome, unsupported, sent = stage
        try:
            if outcome == "full":
                if unsupported:  # the schema's, not this document's: skip the split next time
                    self._unsupported = unsupported
                raise _NeedsFull(unsupported or "this document")
            if outcome == "marks":  # the sites say this cannot be; if it is, use the marks
                return list(self._fast_hits(doc))
            return list(self._checked(root, raw, background.receive_hits(sent, root)))
        except _NeedsFull:
            return list(self.full.hits(doc))

    def _prepare(self, doc: Document, root: etree._Element) -> tuple[_Model | None, _Plan]:
        if self._unsupported is not None:
            raise _NeedsFull(self._unsupported)
        if _needs_xsd11_reading(doc, root):
            raise _NeedsFull("the file uses xsi:type, xsi:nil or '+INF'")
        needs_model = self.form.asserts or self.form.alternatives
        model = self.model() if needs_model else None
        plan = model.plan(root) if model is not None else _Plan([], [])
        return model, plan

    def _fast_hits(self, doc: Document) -> Iterator[Hit]:
        assert doc.tree is not None
        root = doc.tree.getroot()
        model, plan = self._prepare(doc, root)
        with _xsi_types(plan.marks):
            raw = list(self._libxml2.hits(doc))
        yield from self._checked(root, raw, self._assertion_hits(root, model, plan))

    def _assertion_hits(self, root: etree._Element, model: _Model | None, plan: _Plan) -> list[Hit]:
        """A hit for each failing assertion of the elements ``plan`` found."""
        if model is None:
            return []
        memo: dict[Any, Any] = {}
        try:
            errors = [
                error
                for element, xsd_type in plan.asserted
                for error in _assertion_errors(model, element, xsd_type, memo)
            ]
        except _NeedsFull:
            raise
        except Exception as error:  # (a subtree libxml2 skipped may hold anything)
            raise _NeedsFull(f"an assertion could not be evaluated: {error}") from error
        return list(self.full.error_hits(root, errors)) if errors else []

    def _checked(self, root: etree._Element, raw: list[Hit], asserted: list[Hit]) -> Iterator[Hit]:
        """libxml2's hits on the XSD 1.0 form, completed by the XSD 1.1-only checks: the
        assertions' hits ``asserted``, and what libxml2 skipped."""
        skipped = self._skipped(raw)
        inside = _Subtrees(skipped)
        identity = self._identity_errors(root, skipped) if skipped else None
        for hit in raw:
            if identity is not None and identity.recomputes(hit):
                continue
            moved = _as_xsd11(hit)
            # what libxml2 says inside a skipped subtree, xmlschema says again below
            if not inside.holds(moved.element):
                yield moved
        yield from (hit for hit in asserted if not inside.holds(hit.element))
        errors: list[Any] = []
        for element, declaration in skipped:
            errors.extend(declaration.iter_errors(element))
        if identity is not None:
            errors.extend(identity.errors(raw))
        if errors:
            yield from self.full.error_hits(root, errors)

    def _skipped(self, hits: Sequence[Hit]) -> list[tuple[etree._Element, Any]]:
        """The subtrees libxml2 did not validate and XSD 1.1 does, with declarations."""
        roots: dict[etree._Element, Any] = {}
        for hit in hits:
            element = hit.element
            if element is None or hit.kind not in (*_UNEXPECTED, "abstract"):
                continue
            model = self.model()
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

    def _identity_errors(
        self, root: etree._Element, skipped: list[tuple[etree._Element, Any]]
    ) -> _RootIdentities | None:
        """The root's keys and keyrefs, recomputed if libxml2 skipped some of their nodes."""
        inside = _Subtrees(skipped)
        schema = self.full.schema
        root_declaration = schema.elements.get(root.tag)
        for constraint in schema.identities.values():
            holder = getattr(constraint, "parent", None)
            if holder is root_declaration or holder is None:
                continue
            for element, _ in skipped:
                for ancestor in element.iterancestors(holder.local_name):
                    if any(inside.holds(n) for n in _select(ancestor, constraint)):
                        raise _NeedsFull("a key below the root covers a skipped subtree")
        identities = _RootIdentities(root, list(getattr(root_declaration, "identities", ())))
        if not any(inside.holds(node) for node in identities.all_selected()):
            return None
        return identities


def _holds_a_site(doc: Document, root: etree._Element, sites: frozenset[tuple[str, str]]) -> bool:
    """Does an element stand where a type alternative may apply? The bytes rule most
    sites out at once (a site needs both names in the file); the tree is walked, in one
    pass, only for the sites left. A prefixed name the bytes miss costs time, not
    correctness: the plan made afterwards finds the marks, and the parent validates
    with them (:meth:`FastXsd11Validator._finish`)."""
    if _bytes_searchable(doc):
        present: dict[str, bool] = {}

        def named(name: str) -> bool:
            if name not in present:
                present[name] = b"<" + name.encode() in doc.data
            return present[name]

        sites = frozenset(site for site in sites if all(named(n) for n in site if n))
    if not sites:
        return False
    for element in root.iter(*{tag for _, tag in sites}):
        above = element.getparent()
        if ((above.tag if above is not None else ""), element.tag) in sites:
            return True
    return False


def _bytes_searchable(doc: Document) -> bool:
    """Is the file in an encoding where markup is ASCII bytes (not UTF-16 or UTF-32)?"""
    encoding = (doc.tree.docinfo.encoding if doc.tree is not None else None) or "utf-8"
    return not encoding.lower().replace("-", "").startswith(("utf16", "utf32", "ucs"))


def _needs_xsd11_reading(doc: Document, root: etree._Element) -> bool:
    """Does the file hold what libxml2 would read as XSD 1.0 reads it, not as XSD 1.1?

    An ``xsi:type`` (or ``xsi:nil``) of the file's own would meet the ones the type
    alternatives set; ``+INF`` is a number in XSD 1.1 and not in XSD 1.0.
    """
    ascii_bytes = _bytes_searchable(doc)
    # the usual case, answered from the bytes: no prefixed 'type' or 'nil' attribute and
    # no '+INF' at all (the tree is asked only when the bytes cannot tell)
    if ascii_bytes and not _PREFIXED_TYPE_OR_NIL.search(doc.data) and b"+INF" not in doc.data:
        return False
    return bool(root.xpath(_XSD11_READING, namespaces={"xsi": XSI}))


def _as_xsd11(hit: Hit) -> Hit:
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
    return Hit(element, hit.message, line=hit.line, column=hit.column, kind=kind)


class _Subtrees:
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


@contextlib.contextmanager
def _xsi_types(marks: Sequence[tuple[etree._Element, str]]) -> Iterator[None]:
    """Give each element the ``xsi:type`` its type alternative selects, for a while.

    The document is left as it was: attributes removed, and any ``xmlns:xsi`` that lxml
    had to declare for them removed again.
    """
    declared: list[tuple[etree._Element, list[str]]] = []
    try:
        for element, type_name in marks:
            if XSI not in element.nsmap.values():
                declared.append((element, [p for p in element.nsmap if p is not None]))
            element.set(XSI_TYPE, type_name)
        yield
    finally:
        for element, _ in marks:
            if XSI_TYPE in element.attrib:
                del element.attrib[XSI_TYPE]
        for element, prefixes in declared:
            etree.cleanup_namespaces(element, keep_ns_prefixes=prefixes)


@dataclass(frozen=True, slots=True)
class _TypeAssertions:
    """A type's assertions: those that see only named children and attributes (run on a
    pruned copy of the element, results shared between equal copies) and the others."""

    pruned: tuple[Any, ...]
    elements: tuple[str, ...]
    attributes: frozenset[str]
    whole: tuple[Any, ...]


def _type_assertions(xsd_type: Any) -> _TypeAssertions:
    pruned: list[Any] = []
    whole: list[Any] = []
    elements: set[str] = set()
    attributes: set[str] = set()
    for assertion in xsd_type.assertions:
        _check_bounded(assertion)
        names = _Names()
        try:
            names.kind_of(assertion.token)
        except _Unprunable:
            whole.append(assertion)
            continue
        pruned.append(assertion)
        elements |= names.elements
        attributes |= names.attributes
    return _TypeAssertions(
        tuple(pruned), tuple(sorted(elements)), frozenset(attributes), tuple(whole)
    )


class _Unprunable(Exception):
    """An assertion that may see more of its element than named children and attributes."""


# Functions whose arguments are only counted or tested for existence, or atomized; and
# those that need no argument. Anything else keeps the assertion on the whole element.
_EXISTENCE_FUNCTIONS: Final = frozenset({"count", "exists", "empty", "not", "boolean"})
_ATOMIZING_FUNCTIONS: Final = frozenset(
    {"distinct-values", "sum", "min", "max", "avg", "data", "number", "string"}
)
_CONSTANT_FUNCTIONS: Final = frozenset({"true", "false"})
_NAME_FUNCTIONS: Final = frozenset({"name", "local-name"})
_ATOMIZING_OPERATORS: Final = frozenset(
    {"=", "!=", "<", ">", "<=", ">=", "eq", "ne", "lt", "gt", "le", "ge"}
    | {"+", "-", "div", "idiv", "mod"}
)
_LITERALS: Final = frozenset({"(string)", "(integer)", "(decimal)", "(float)", "$"})


class _Names:
    """The child elements and attributes an XPath 2.0 expression can see, if that is all
    it can see: exact names on child, descendant and attribute steps from the context,
    never the text of an element (no element is atomized)."""

    def __init__(self) -> None:
        self.elements: set[str] = set()
        self.attributes: set[str] = set()

    def kind_of(self, token: Any) -> str:
        """``elements``, ``attributes`` or ``atomic``: what the expression yields."""
        symbol = getattr(token, "symbol", None)
        children = list(token)
        if symbol == "(name)":
            return self._name(token, self.elements, "elements")
        if symbol == "@" and len(children) == 1 and children[0].symbol == "(name)":
            return self._name(children[0], self.attributes, "attributes")
        if symbol in (".", ".."):
            return "elements"
        if symbol in _UPWARD_AXES and len(children) == 1:
            if children[0].symbol != "*":
                self.kind_of(children[0])
            return "elements"
        if symbol in ("/", "//") and len(children) == 2:
            if self.kind_of(children[0]) != "elements":
                raise _Unprunable
            step = children[1].symbol
            if step not in ("(name)", "@", ".", *_UPWARD_AXES):
                raise _Unprunable
            return self.kind_of(children[1])
        if symbol == "(" and len(children) == 1:
            return self.kind_of(children[0])
        if symbol in _LITERALS or (symbol in _CONSTANT_FUNCTIONS and not children):
            return "atomic"
        if (
            symbol in _EXISTENCE_FUNCTIONS
            or symbol in ("and", "or")
            or (
                symbol in _NAME_FUNCTIONS and children  # names are kept in a pruned copy
            )
        ):
            for child in children:
                self.kind_of(child)
            return "atomic"
        if (symbol in _ATOMIZING_FUNCTIONS and children) or symbol in _ATOMIZING_OPERATORS:
            if getattr(token, "label", "") not in ("function", "operator"):
                raise _Unprunable
            if any(self.kind_of(child) == "elements" for child in children):
                raise _Unprunable  # an element's string value depends on all its text
            return "atomic"
        if symbol == "if" and len(children) == 3:
            self.kind_of(children[0])
            kinds = {self.kind_of(children[1]), self.kind_of(children[2])}
            return next(k for k in ("elements", "attributes", "atomic") if k in kinds)
        raise _Unprunable

    @staticmethod
    def _name(token: Any, names: set[str], kind: str) -> str:
        name = str(getattr(token, "value", "") or "")
        if not name or ":" in name or "{" in name or "*" in name:
            raise _Unprunable
        names.add(name)
        return kind


def _assertion_errors(
    model: _Model, element: etree._Element, xsd_type: Any, memo: dict[Any, Any]
) -> Iterator[Any]:
    """xmlschema's errors for the assertions of ``element``'s type, evaluated as
    ``XsdAssert.__call__`` evaluates them."""
    from xmlschema import XMLSchemaValidationError

    group = model.assertions_of(xsd_type)
    text = element.text if xsd_type.has_simple_content() else None
    outcome: list[tuple[Any, str]] = []
    if group.pruned:
        kept = _kept_nodes(element, group.elements)
        key = (id(xsd_type), _signature(element, kept, group.attributes), text)
        shared = memo.get(key)
        if shared is None:
            copy = _pruned(element, kept, group.attributes)
            shared = memo[key] = _evaluate(group.pruned, _xpath_node(copy), text)
        outcome.extend(shared)
    if group.whole:
        outcome.extend(_evaluate(group.whole, _xpath_node(element), text))
    for assertion, reason in outcome:
        yield XMLSchemaValidationError(assertion, element, reason)


def _evaluate(assertions: Sequence[Any], node: Any, text: str | None) -> list[tuple[Any, str]]:
    """Each failing assertion with xmlschema's reason, one XPath context for them all."""
    from elementpath import ElementPathError, XPathContext

    first = assertions[0]
    value = first.base_type.text_decode(text) if text is not None else None
    for assertion in assertions:
        if not assertion.parser.is_schema_bound() and assertion.parser.schema:
            assertion.parser.schema.bind_parser(assertion.parser)
    # what xmlschema builds per assertion; the typing it applies to the tree is the same
    # for every assertion of one type, so the context is built once
    context = XPathContext(
        root=node, fragment=True, variables={"value": value}, schema=first.parser.schema
    )
    failed: list[tuple[Any, str]] = []
    for assertion in assertions:
        context.item, context.position, context.size, context.axis = node, 1, 1, None
        try:
            if not assertion.token.evaluate(context):
                failed.append((assertion, "assertion test is false"))
        except ElementPathError as error:
            failed.append((assertion, str(error)))
    return failed


def _kept_nodes(element: etree._Element, elements: Sequence[str]) -> set[etree._Element]:
    """The descendants named ``elements`` and the elements on the way to them."""
    keep: set[etree._Element] = set()  # the proxies themselves: their ids stay unique
    if elements:
        for found in element.iter(*elements):
            for node in (found, *found.iterancestors()):
                if node is element or node in keep:
                    break
                keep.add(node)
    return keep


def _signature(
    element: etree._Element, keep: set[etree._Element], attributes: frozenset[str]
) -> tuple[Any, ...]:
    """What the pruned copy of ``element`` holds, as a key: equal keys, equal copies.
    Building it costs a third of building the copy, which is made only for a new key."""
    values = tuple(element.get(name) for name in sorted(attributes))
    children = tuple(
        _signature(child, keep, attributes)
        for child in element.iterchildren(etree.Element)
        if child in keep
    )
    return (element.tag, values, children)


def _pruned(
    element: etree._Element, keep: set[etree._Element], attributes: frozenset[str]
) -> etree._Element:
    """A copy of ``element`` with only the ``keep`` descendants and only the named
    attributes: all an assertion of :class:`_Names` sees."""

    def copy(source: etree._Element) -> etree._Element:
        target = etree.Element(source.tag)
        for name in attributes:
            value = source.get(name)
            if value is not None:
                target.set(name, value)
        for child in source.iterchildren(etree.Element):
            if child in keep:
                target.append(copy(child))
        return target

    return copy(element)


def _xpath_node(element: etree._Element) -> Any:
    """The element as the root of an XPath tree, built as it is visited.

    xmlschema takes the element's node out of a tree of the whole document, but with the
    element as the context root (``fragment=True``) elementpath never leaves its subtree.
    """
    from elementpath import LazyElementNode

    return LazyElementNode(element)


def _select(holder: etree._Element, constraint: Any) -> list[etree._Element]:
    found = holder.xpath(constraint.selector.path)
    return [n for n in found if isinstance(n, etree._Element)] if isinstance(found, list) else []


class _RootIdentities:
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
                    raise _NeedsFull(f"key field {path!r} is not a plain attribute")
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
                raise _NeedsFull(f"keyref {constraint.name} refers to a key below the root")
            counter = Counter(values for _, values in self._values(constraint) if values)
            for values, times in counter.items():
                if values in tables[id(refer)]:
                    continue
                suffix = f" ({times} times)" if times > 1 else ""
                reason = f"value {values!r} not found for {refer!r}{suffix}"
                yield XMLSchemaValidationError(constraint, self.root, reason)


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
                raise _NeedsFull(f"key field {path!r} is not a string")
            if getattr(simple, "white_space", "preserve") not in (None, "preserve"):
                raise _NeedsFull(f"key field {path!r} is whitespace-normalized")
