"""XSD 1.0 validation in libxml2: an official schema set (OpenDRIVE 1.1 to 1.7, and the
XSD 1.0 form of a 1.8 or 1.9 set), or the built-in railroad schema on the railroad
subtrees. Each libxml2 error becomes one hit on the element it is about, with a message
from :mod:`~xodrlint.validation.messages`.
"""

from __future__ import annotations

import copy as copy_module
import os
import re
import threading
from collections import Counter
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Final

from lxml import etree

from xodrlint.document.load import Document
from xodrlint.document.positions import TreePositions, parser_line
from xodrlint.findings import CHILD_KINDS, Hit
from xodrlint.fixes import moved
from xodrlint.validation.identities import FirstHolders, key_fields, selector_of
from xodrlint.validation.libxml2_direct import SchemaError, direct_schema
from xodrlint.validation.messages import (
    Explained,
    TypeCatalog,
    blank_special_number,
    enumeration_fix,
    explain_libxml2,
)
from xodrlint.validation.sets import SchemaLoadError, SchemaSet
from xodrlint.validation.source import XS, CopyNames, read_schema_source

#: Railroad content appeared in OpenDRIVE 1.4.
FIRST_RAILROAD_MINOR: Final = 4

#: The built-in schema's stand-in root for the ids of the elements it holds.
ROOT_TAG: Final = "OpenDRIVE"
IDENTIFIED_TAGS: Final = ("road", "junction")

#: libxml2's error log counts lines in 16 bits: later lines all read as this one.
LIBXML2_LAST_LINE: Final = 65535


def fix_known_schema_bugs(schema_root: etree._Element) -> None:
    """Repair published schema bugs in memory, recognised by structure, not by file name.

    OpenDRIVE 1.5M declares ``mainTrack/@id`` and ``sideTrack/@id`` as references to
    *switch* ids; they name roads, so every correct file with switches would fail. The
    keyrefs are pointed at the road key, which is what the standard means.
    """
    keys = {
        (
            selector_of(key),
            tuple(f.get("xpath", "").strip() for f in key.iterfind(f"{{{XS}}}field")),
        ): key.get("name")
        for key in schema_root.iter(f"{{{XS}}}key")
    }
    road_key = keys.get(("road", ("@id",)))
    switch_key = keys.get(("road/railroad/switch", ("@id",)))
    if road_key is None or switch_key is None:
        return
    for keyref in schema_root.iter(f"{{{XS}}}keyref"):
        track = selector_of(keyref)
        if keyref.get("refer") == switch_key and track in (
            "road/railroad/switch/mainTrack",
            "road/railroad/switch/sideTrack",
        ):
            keyref.set("refer", road_key)


#: Built-in types whose validation writes into the validated document: ``ID`` and
#: ``IDREF(S)`` register in the document's tables (an IDREF through the document's string
#: dictionary, which another thread's tag lookups read: a crash), ``QName`` and
#: ``NOTATION`` may add the ``xml`` namespace to it; ``ENTITY`` reads its DTD.
_WRITING_TYPES: Final = frozenset(
    {"ID", "IDREF", "IDREFS", "ENTITY", "ENTITIES", "NOTATION", "QName"}
)
_TYPE_REFERENCES: Final = ("type", "base", "itemType", "memberTypes")


def writes_while_validating(schema_root: etree._Element) -> bool:
    """Whether a schema document refers to a type whose validation writes into the
    document (see :data:`_WRITING_TYPES`); a type derived from one refers to it in some
    document of the set, so checking every document's references finds them all."""
    for element in schema_root.iter(etree.Element):
        for name in _TYPE_REFERENCES:
            value = element.get(name)
            if value and any(
                reference.rpartition(":")[2] in _WRITING_TYPES for reference in value.split()
            ):
                return True
    return False


def without_target_namespace(schema: etree._ElementTree) -> etree._ElementTree:
    """The schema with its target namespace dropped, where it declares one and names it
    only as its default namespace (VIRES' OpenDRIVE 1.1 and 1.2 sets: ``www.vires.com``).
    OpenDRIVE files are read without a namespace (``document`` drops an earlier schema's
    namespace), so the set validates them as the files its version was written for. Other
    schemas are returned as they are."""
    root = schema.getroot()
    target = root.get("targetNamespace")
    if not target or root.nsmap.get(None) != target:
        return schema
    if any(prefix and uri == target for prefix, uri in root.nsmap.items()):
        return schema  # a prefix for it would need rewriting in every reference
    text = etree.tostring(root)  # the root alone: its start tag comes first
    head_end = text.index(b">") + 1
    head = _TARGET_NAMESPACE.sub(b"", text[:head_end])
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    url = schema.docinfo.URL
    return etree.ElementTree(etree.fromstring(head + text[head_end:], parser, base_url=url))


#: The root's own target namespace and default namespace declaration (the same URI).
_TARGET_NAMESPACE: Final = re.compile(rb"""\s(?:targetNamespace|xmlns)\s*=\s*(["'])[^"']*\1""")


class Libxml2Validator:
    """An XSD 1.0 schema set compiled by libxml2."""

    def __init__(self, entry: Path, *, direct: bool = True) -> None:
        """``direct=False`` for a set only ever validated in subtrees (through lxml)."""
        self._source = read_schema_source(entry)
        self._documents = self._source.trees
        self._documents[0] = without_target_namespace(self._documents[0])
        root = self._documents[0].getroot()
        fix_known_schema_bugs(root)
        #: libxml2 reads a whole document with the GIL released (see
        #: ``concurrency.background``), unless the set has types whose validation writes
        #: into the document
        self.thread_safe = not any(writes_while_validating(d.getroot()) for d in self._documents)
        self._lock = threading.Lock()
        self._catalog: TypeCatalog | None = None
        # libxml2's own validation where it can run here (see ``libxml2_direct``);
        # lxml's compiles only where it cannot, or for the subtrees of the built-in
        # schema: each compile costs a small map's run 2.5 ms
        self._entry = entry
        self._lxml: etree.XMLSchema | None = None
        with self._source.compiled_from_copy(self._documents[0]):
            self._direct = direct_schema(root) if direct else None
        if self._direct is None:
            self._lxml = self._compile()

    @property
    def catalog(self) -> TypeCatalog:
        """The set's types, for explaining errors: made on the first error."""
        with self._lock:
            if self._catalog is None:
                self._catalog = TypeCatalog.from_documents(d.getroot() for d in self._documents)
            return self._catalog

    def declares(self, name: str) -> bool:
        """Whether the set's entry declares a global element ``name``."""
        root = self._documents[0].getroot()
        return any(e.get("name") == name for e in root.iterchildren(f"{{{XS}}}element"))

    @property
    def lxml_schema(self) -> etree.XMLSchema:
        """The set compiled by lxml (validates subtrees: the built-in schema)."""
        with self._lock:
            if self._lxml is None:
                self._lxml = self._compile()
            return self._lxml

    def _compile(self) -> etree.XMLSchema:
        with self._source.compiled_from_copy(self._documents[0]) as copies:
            try:
                return etree.XMLSchema(self._documents[0])
            except etree.XMLSchemaParseError as error:
                where = _where(error, self._entry, copies)
                raise SchemaLoadError(f"cannot compile schema {self._entry}: {where}") from error

    def hits(self, doc: Document) -> Iterator[Hit]:
        assert doc.tree is not None
        references = entity_references(doc.tree)
        if references:
            yield from self._hits_past_entities(doc, doc.tree.getroot(), references)
            return
        errors = self._validate(doc.tree)
        if errors:
            yield from errors_to_hits(doc, errors, self.catalog, doc.tree.getroot())

    def _validate(self, tree: etree._ElementTree) -> list[SchemaError]:
        if self._direct is not None:
            return self._direct.validate(tree)
        schema = self.lxml_schema
        schema.validate(tree)
        return lxml_errors(schema.error_log)

    def _hits_past_entities(
        self, doc: Document, root: etree._Element, references: list[etree._Entity]
    ) -> Iterator[Hit]:
        """libxml2's schema validation stops at the first entity reference it meets (an
        internal error, and nothing after it checked); xodrlint expands no entity. So a
        copy without the references is validated, its findings put on the document's own
        elements, and each reference is a finding of its own: what it stands for is the
        one thing not validated."""
        copy, originals = _without_entity_references(root)
        errors = self._validate(etree.ElementTree(copy))
        hits = errors_to_hits(doc, errors, self.catalog, copy)
        yield from _on_originals(hits, originals, references)
        yield from _reference_hits(references)


def _without_entity_references(
    element: etree._Element,
) -> tuple[etree._Element, dict[etree._Element, etree._Element]]:
    """A copy of ``element`` without its entity references, and the original of each
    node of the copy."""
    copy = copy_module.deepcopy(element)
    originals = dict(zip(copy.iter(), element.iter(), strict=True))
    for reference in list(copy.iter(etree.Entity)):
        _remove_keeping_tail(reference)
    return copy, originals


def _on_originals(
    hits: Iterable[Hit],
    originals: dict[etree._Element, etree._Element],
    references: Iterable[etree._Entity],
) -> Iterator[Hit]:
    """``hits`` about a copy without ``references``, put on the elements it was copied
    from; but not one about the children of an element that holds a reference (a child
    missing, or out of place): what the reference stands for may be those very children,
    and the reference's own finding says it is not validated."""
    holders = {reference.getparent() for reference in references}
    for hit in hits:
        element = originals.get(hit.element) if hit.element is not None else None
        if (
            hit.kind in CHILD_KINDS
            and element is not None
            and (element in holders or element.getparent() in holders)
        ):
            continue
        related = tuple(originals[other] for other in hit.related if other in originals)
        yield hit._replace(element=element, related=related, fix=moved(hit.fix, originals.get))


def _reference_hits(references: Iterable[etree._Entity]) -> Iterator[Hit]:
    for reference in references:
        parent = reference.getparent()
        assert parent is not None  # a reference stands in an element's content
        yield Hit(
            parent,
            f"'{parent.tag}' holds the entity reference '&{reference.name};': xodrlint expands "
            "no entity, so what it stands for is not validated against the schema (the rest "
            "of the document is)",
        )


def entity_references(tree: etree._ElementTree) -> list[etree._Entity]:
    """The entity references the parser kept in ``tree`` (it expands none): only a
    document with a DOCTYPE can hold one, so a map without costs no walk."""
    if not tree.docinfo.doctype:  # type: ignore[attr-defined]  # (lxml-stubs lack it)
        return []
    root = tree.getroot()
    return list(root.iter(etree.Entity)) if root is not None else []


def _remove_keeping_tail(node: etree._Entity) -> None:
    """Takes ``node`` out of its parent; the text after it stays where it was."""
    parent = node.getparent()
    if parent is None:
        return
    tail = node.tail or ""
    previous = node.getprevious()
    if previous is not None:
        previous.tail = (previous.tail or "") + tail
    else:
        parent.text = (parent.text or "") + tail
    parent.remove(node)


def _where(error: etree.XMLSchemaParseError, entry: Path, copies: CopyNames) -> str:
    """The error with the file and line that failed: lxml's message names only the line,
    and the failing file is often another file of the set than its entry (compiled from
    its private copy: named as the user's file)."""
    last = error.error_log.last_error if error.error_log else None
    if last is None or not last.filename or last.filename == "<string>":
        return str(error)
    failed = os.path.realpath(copies.original(last.filename))
    place = f"line {last.line}" if failed == os.path.realpath(entry) else f"{failed}:{last.line}"
    return f"{place}: {last.message.strip()}"


class BuiltinRailroadValidator:
    """Our railroad schema, applied to each ``road/railroad`` and ``station`` subtree, and
    (where the set declares the stand-in root, 1.5 and later, as the official sets key
    them) to the ids of the file's roads and junctions."""

    #: lxml validates a subtree by re-parenting its children for the time being: another
    #: thread walking the tree meanwhile would see the stand-in parent
    thread_safe = False

    def __init__(self, schema: SchemaSet) -> None:
        self._minor = schema.version[1] if schema.version else FIRST_RAILROAD_MINOR
        self._inner = Libxml2Validator(schema.entry, direct=False)
        self._checks_ids = self._inner.declares(ROOT_TAG)

    def hits(self, doc: Document) -> Iterator[Hit]:
        root = doc.root
        assert root is not None
        subtrees = [
            rr for road in root.iterchildren("road") for rr in road.iterchildren("railroad")
        ]
        subtrees += list(root.iterchildren("station"))
        if self._minor < FIRST_RAILROAD_MINOR and doc.effective is not None:
            for subtree in subtrees:
                yield Hit(
                    subtree,
                    f"'{subtree.tag}' does not exist in OpenDRIVE {doc.effective}; "
                    "railroad content starts with OpenDRIVE 1.4",
                )
            return
        schema = self._inner.lxml_schema
        assert doc.tree is not None
        with_references = bool(entity_references(doc.tree))
        for subtree in subtrees:
            references = list(subtree.iter(etree.Entity)) if with_references else []
            if references:  # see Libxml2Validator._hits_past_entities
                copy, originals = _without_entity_references(subtree)
                if not schema.validate(copy):
                    errors = lxml_errors(schema.error_log)
                    hits = errors_to_hits(doc, errors, self._inner.catalog, copy)
                    yield from _on_originals(hits, originals, references)
                yield from _reference_hits(references)
            elif not schema.validate(subtree):
                errors = lxml_errors(schema.error_log)
                yield from errors_to_hits(doc, errors, self._inner.catalog, subtree)
        if self._checks_ids:
            yield from self._id_hits(doc, root, schema)

    def _id_hits(
        self, doc: Document, root: etree._Element, schema: etree.XMLSchema
    ) -> Iterator[Hit]:
        """The uniqueness of road and junction ids, validated on a stand-in root that
        holds, in document order, each road and junction whose id another of its kind
        shares, with that id only. Validating the map itself would walk millions of
        elements, and libxml2 compares each key with every one before it (18,000 roads:
        0.23 s); a map without a repeated id costs one pass over the root's children."""
        candidates = _maybe_repeated(root)
        if not candidates:
            return
        stand_in = etree.Element(ROOT_TAG)
        originals: dict[etree._Element, etree._Element] = {}
        for element, identifier in candidates:
            copy = etree.SubElement(stand_in, element.tag, id=identifier)
            originals[copy] = element
        if schema.validate(stand_in):
            return
        errors = lxml_errors(schema.error_log)
        for hit in errors_to_hits(doc, errors, self._inner.catalog, stand_in):
            original = originals.get(hit.element) if hit.element is not None else None
            related = tuple(originals[copy] for copy in hit.related if copy in originals)
            if original is not None:
                fix = moved(hit.fix, originals.get)
                yield hit._replace(element=original, related=related, fix=fix)


def _maybe_repeated(root: etree._Element) -> list[tuple[etree._Element, str]]:
    """The roads and junctions whose id another of their kind shares, each with its id:
    equal strings, as the schema's ``xs:string`` ids compare (the schema then decides,
    and words the finding). A pass over the root's children reading one attribute, and
    a second only for a tag whose ids repeat."""
    found: list[tuple[etree._Element, str]] = []
    for tag in IDENTIFIED_TAGS:
        ids = [i for i in (e.get("id") for e in root.iterchildren(tag)) if i is not None]
        if len(set(ids)) == len(ids):
            continue
        repeated = {i for i, count in Counter(ids).items() if count > 1}
        found += [(e, i) for e in root.iterchildren(tag) if (i := e.get("id") or "") in repeated]
    return found


def lxml_errors(log: etree._ListErrorLog) -> list[SchemaError]:
    """The entries of lxml's error log, each with libxml2's XPath of its node."""
    return [SchemaError(entry.message, entry.line, entry.path) for entry in log]


def errors_to_hits(
    doc: Document,
    errors: Iterable[SchemaError],
    catalog: TypeCatalog,
    validation_root: etree._Element,
) -> Iterator[Hit]:
    """One hit per libxml2 error, on the element it is about (an error said twice of one
    element, once)."""
    version = str(doc.declared) if doc.declared else None
    locator = _ElementLocator(validation_root)
    explained: list[tuple[Explained, etree._Element | None, int]] = []
    for error in errors:
        why = explain_libxml2(error.message, catalog, version)
        element = error.element
        if element is None:
            element = locator.find(error.path, why, error.line, key_fields(catalog, why))
        explained.append((why, element, error.line))
    # A missing keyed attribute is one defect: libxml2 reports it twice (required, and
    # "not all fields of key ... evaluate to a node"); keep the first.
    missing = {id(el) for why, el, _ in explained if why.kind == "required" and el is not None}
    # An error libxml2 repeats word for word on one element is one defect too: "character
    # content is not allowed" comes once for each blank text node of an empty element.
    said: set[tuple[int, str]] = set()
    firsts = FirstHolders(catalog)
    for why, element, line in explained:
        if why.kind == "key_field" and element is not None and id(element) in missing:
            continue
        if element is not None:
            if (id(element), why.message) in said:
                continue
            said.add((id(element), why.message))
        value = element.get(why.attribute) if element is not None and why.attribute else None
        if blank_special_number(why, value, catalog):
            continue
        first = firsts.of(element, why) if why.kind == "duplicate" else None
        yield Hit(
            element,
            why.message,
            line=None if element is not None else line,
            kind=why.kind,
            related=(first,) if first is not None else (),
            fix=enumeration_fix(element, why) if element is not None else None,
        )


class _ElementLocator:
    """Find the element a libxml2 error is about: by its path, else by name, line and key."""

    def __init__(self, validation_root: etree._Element) -> None:
        self._root = validation_root
        self._positions = TreePositions()
        self._by_tag_line: dict[tuple[str, int], list[etree._Element]] | None = None

    def find(
        self, path: str | None, why: Explained, line: int, fields: tuple[str, ...] | None = None
    ) -> etree._Element | None:
        if path:
            found = self._by_path(path)
            if found is not None:
                return found
        if why.element is None:
            return None
        candidates = self._candidates(why.element, line)
        for candidate in candidates:
            if fields is not None and len(fields) == len(why.key_values):
                # compare the key's own attributes, in order: another attribute of a
                # neighbour on the same line may well hold the same value
                if tuple(candidate.get(name) for name in fields) == why.key_values:
                    return candidate
            elif all(value in set(candidate.attrib.values()) for value in why.key_values):
                return candidate
        return candidates[0] if candidates else None

    def _candidates(self, tag: str, line: int) -> list[etree._Element]:
        if line < LIBXML2_LAST_LINE:
            return self._index().get((tag, line), [])
        # libxml2 reports every line past its 16-bit counter as 65535: any element of the
        # tag from there on may be the one
        return [
            element
            for (name, at), elements in self._index().items()
            if name == tag and at >= LIBXML2_LAST_LINE - 1
            for element in elements
        ]

    def _by_path(self, path: str) -> etree._Element | None:
        # libxml2 paths start at the validation root: "/OpenDRIVE/road[1]/type" for a
        # whole document, "/railroad/switch" for a subtree. Plain steps are walked through
        # children indexed once per parent (an XPath "road[1234]" scans the roads before
        # it: quadratic in the findings of a large map); anything else goes to XPath.
        found = self._positions.libxml2_path(self._root, path)
        if found is not False:
            return found if isinstance(found, etree._Element) else None
        steps = path.strip("/").split("/", 1)
        try:
            selected = self._root.xpath(steps[1]) if len(steps) > 1 else [self._root]
        except etree.XPathError:
            return None
        first = selected[0] if isinstance(selected, list) and selected else None
        return first if isinstance(first, etree._Element) else None

    def _index(self) -> dict[tuple[str, int], list[etree._Element]]:
        if self._by_tag_line is None:
            index: dict[tuple[str, int], list[etree._Element]] = {}
            for element in self._root.iter(etree.Element):
                key = (etree.QName(element).localname, parser_line(element))
                index.setdefault(key, []).append(element)
            self._by_tag_line = index
        return self._by_tag_line
