"""Whole-document XSD 1.0 validation through libxml2's C API, without lxml's error log.

lxml's error log works out each error's XPath (``xmlGetNodePath``) the moment it records
it, and that walks every preceding sibling of the element and of each of its ancestors:
n errors about the children of a large map's root cost n times its roads. 20,000 invalid
switches in a 30 MB railway spent 8.6 s of 10.5 s there; 1,000,000 invalid roads would
spend hours. Here libxml2 hands each error to our own handler with the node it is about,
as a pointer, and the pointer is matched to lxml's element through lxml's public C
structures (``lxml.etree.h``: ``LxmlElement._c_node``): one pass over the elements of the
tags that have errors. The messages and lines are libxml2's own, as in lxml's log.

This runs where it can: CPython, and an lxml module that exports libxml2's functions (the
wheels on PyPI link libxml2 in and do). A self-check on first use confirms that the
structures read as documented; otherwise lxml's ``XMLSchema`` runs, with the same findings
(tests/validation/test_schema_direct.py compares both on the corpus and broken railways).
They differ only where this route does better: an error inside an element of a foreign
namespace is placed on that element (lxml's path for it cannot be read back, so that
route names the document), and a document with an entity reference is validated (lxml's
route raises).
"""

from __future__ import annotations

import ctypes
import functools
import sys
import weakref
from typing import Final, NamedTuple

from lxml import etree

#: libxml2's node types (``xmlElementType``) this module tells apart.
_ELEMENT_NODE: Final = 1
_ATTRIBUTE_NODE: Final = 2


class SchemaError(NamedTuple):
    """One validation error, from lxml's log or from libxml2 directly."""

    message: str
    line: int
    path: str | None
    """libxml2's XPath of the node (lxml's log), ``None`` where ``element`` is given."""
    element: etree._Element | None = None


class _XmlNode(ctypes.Structure):
    """The leading fields of libxml2's ``struct _xmlNode`` (also of ``_xmlAttr``)."""

    _fields_ = (
        ("private", ctypes.c_void_p),
        ("type", ctypes.c_int),
        ("name", ctypes.c_char_p),
        ("children", ctypes.c_void_p),
        ("last", ctypes.c_void_p),
        ("parent", ctypes.c_void_p),
        ("next", ctypes.c_void_p),
        ("prev", ctypes.c_void_p),
        ("doc", ctypes.c_void_p),
    )


class _XmlError(ctypes.Structure):
    """libxml2's ``struct _xmlError``."""

    _fields_ = (
        ("domain", ctypes.c_int),
        ("code", ctypes.c_int),
        ("message", ctypes.c_char_p),
        ("level", ctypes.c_int),
        ("file", ctypes.c_char_p),
        ("line", ctypes.c_int),
        ("str1", ctypes.c_char_p),
        ("str2", ctypes.c_char_p),
        ("str3", ctypes.c_char_p),
        ("int1", ctypes.c_int),
        ("int2", ctypes.c_int),
        ("ctxt", ctypes.c_void_p),
        ("node", ctypes.c_void_p),
    )


class _LxmlElement(ctypes.Structure):
    """lxml's public ``struct LxmlElement`` (``lxml.etree.h``) behind an ``_Element``."""

    _fields_ = (
        ("ob_refcnt", ctypes.c_ssize_t),
        ("ob_type", ctypes.c_void_p),
        ("doc", ctypes.c_void_p),
        ("c_node", ctypes.c_void_p),
    )


_HANDLER: Final = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.POINTER(_XmlError))
_SIGNATURES: Final = {
    "xmlCopyDoc": (ctypes.c_void_p, (ctypes.c_void_p, ctypes.c_int)),
    "xmlSchemaNewDocParserCtxt": (ctypes.c_void_p, (ctypes.c_void_p,)),
    "xmlSchemaParse": (ctypes.c_void_p, (ctypes.c_void_p,)),
    "xmlSchemaFreeParserCtxt": (None, (ctypes.c_void_p,)),
    "xmlSchemaSetParserStructuredErrors": (None, (ctypes.c_void_p, _HANDLER, ctypes.c_void_p)),
    "xmlSchemaNewValidCtxt": (ctypes.c_void_p, (ctypes.c_void_p,)),
    "xmlSchemaFreeValidCtxt": (None, (ctypes.c_void_p,)),
    "xmlSchemaSetValidStructuredErrors": (None, (ctypes.c_void_p, _HANDLER, ctypes.c_void_p)),
    "xmlSchemaValidateDoc": (ctypes.c_int, (ctypes.c_void_p, ctypes.c_void_p)),
    "xmlSchemaFree": (None, (ctypes.c_void_p,)),
    "xmlFreeDoc": (None, (ctypes.c_void_p,)),
}


def _ignore(_: object, __: object) -> None:
    """An error handler that keeps libxml2's messages to itself."""


_QUIET: Final = _HANDLER(_ignore)


def _c_node(element: etree._Element) -> int:
    """The address of libxml2's node behind ``element`` (CPython: ``id`` is the address)."""
    return _LxmlElement.from_address(id(element)).c_node or 0


@functools.cache
def _libxml2() -> ctypes.CDLL | None:
    """libxml2's functions from the library lxml itself runs on, or ``None`` where they
    cannot be reached or lxml's structures do not read as documented."""
    if sys.implementation.name != "cpython" or hasattr(sys, "gettotalrefcount"):
        return None  # ``id`` is no address, or a debug build's object header is longer
    try:
        library = ctypes.CDLL(etree.__file__)  # the loaded module: its libxml2, not another
        for name, (result, arguments) in _SIGNATURES.items():
            function = getattr(library, name)
            function.restype = result
            function.argtypes = arguments
    except (OSError, AttributeError):
        return None
    return library if _structures_read_as_documented() else None


def _structures_read_as_documented() -> bool:
    probe = etree.fromstring(b"<probe><child/></probe>")
    child = probe[0]
    if _LxmlElement.from_address(id(probe)).ob_type != id(type(probe)):
        return False
    node, child_node = _c_node(probe), _c_node(child)
    if not node or not child_node:
        return False
    parent, inner = _XmlNode.from_address(node), _XmlNode.from_address(child_node)
    return (
        parent.type == _ELEMENT_NODE
        and parent.name == b"probe"
        and inner.name == b"child"
        and inner.parent == node
        and parent.children == child_node
        and bool(parent.doc)
        and inner.doc == parent.doc
    )


class DirectSchema:
    """An XSD 1.0 schema compiled by libxml2 for :meth:`validate`."""

    def __init__(self, library: ctypes.CDLL, schema_root: etree._Element) -> None:
        self._library = library
        # libxml2 strips blank nodes off the document it compiles: give it a copy, as lxml
        # does, and keep it for as long as the schema (which points into it) lives
        document = _XmlNode.from_address(_c_node(schema_root)).doc
        self._copy = library.xmlCopyDoc(document, 1)
        parser = library.xmlSchemaNewDocParserCtxt(self._copy) if self._copy else None
        self._schema = None
        if parser:
            # a schema that does not compile is said once, by lxml's compile (with its
            # message); here libxml2 would print its errors to stderr
            library.xmlSchemaSetParserStructuredErrors(parser, _QUIET, None)
            self._schema = library.xmlSchemaParse(parser)
            library.xmlSchemaFreeParserCtxt(parser)
        # freed with this object: an API caller's linters come and go with their options.
        # Never at interpreter exit: a daemon validation thread (concurrency.background) may
        # still be inside xmlSchemaValidateDoc with this schema, and freeing it under that
        # thread crashed the process (SIGSEGV, 7 of 10 runs on a 30 MB map interrupted);
        # the system takes the memory back at exit anyway. While a validation runs, the
        # thread's reference to this object keeps the finalizer from running at all.
        self._finalizer = weakref.finalize(self, _free, library, self._schema, self._copy)
        self._finalizer.atexit = False

    @property
    def compiled(self) -> bool:
        return bool(self._schema)

    def validate(self, tree: etree._ElementTree) -> list[SchemaError]:
        """Every error libxml2 reports on ``tree``, in its order, each with its element."""
        library = self._library
        root = tree.getroot()
        document = _XmlNode.from_address(_c_node(root)).doc
        raw: list[tuple[bytes, int, int]] = []

        def receive(_: object, error: ctypes._Pointer[_XmlError]) -> None:
            found = error.contents
            raw.append((found.message or b"unknown error", found.line, found.node or 0))

        handler = _HANDLER(receive)  # referenced until validation ends
        context = library.xmlSchemaNewValidCtxt(self._schema)
        if not context:
            raise MemoryError("libxml2 could not make a validation context")
        try:
            library.xmlSchemaSetValidStructuredErrors(context, handler, None)
            outcome = library.xmlSchemaValidateDoc(context, document)  # without the GIL
        finally:
            library.xmlSchemaFreeValidCtxt(context)
        if outcome < 0 and not raw:  # as lxml says it: no error, yet no verdict either
            raise RuntimeError("libxml2 could not validate the document (internal error)")
        elements = _elements_of(root, {node for _, _, node in raw if node})
        return [
            SchemaError(
                message.decode("utf-8", "replace").rstrip("\n"),
                line,
                None,
                elements.get(node),
            )
            for message, line, node in raw
        ]


def _elements_of(root: etree._Element, nodes: set[int]) -> dict[int, etree._Element]:
    """The elements behind libxml2's ``nodes`` (an attribute stands for its element),
    found in one pass over the elements whose names the nodes have."""
    owners: dict[int, int] = {}
    names: set[str] = set()
    for node in nodes:
        owner = node
        record = _XmlNode.from_address(owner)
        if record.type == _ATTRIBUTE_NODE and record.parent:
            owner = record.parent
            record = _XmlNode.from_address(owner)
        if record.type == _ELEMENT_NODE and record.name:
            owners[node] = owner
            names.add(record.name.decode("utf-8", "replace"))
    found: dict[int, etree._Element] = {}
    wanted = set(owners.values())
    if wanted:
        for element in root.iter(*(f"{{*}}{name}" for name in names)):
            address = _c_node(element)
            if address in wanted:
                found[address] = element
                if len(found) == len(wanted):
                    break
    return {node: found[owner] for node, owner in owners.items() if owner in found}


def _free(library: ctypes.CDLL, schema: int | None, copy: int | None) -> None:
    """The compiled schema first: it points into the copy of its document."""
    if schema:
        library.xmlSchemaFree(schema)
    if copy:
        library.xmlFreeDoc(copy)


def direct_schema(schema_root: etree._Element) -> DirectSchema | None:
    """The schema whose document ``schema_root`` roots, compiled for direct validation;
    ``None`` where that cannot run here (lxml's own validation serves instead)."""
    library = _libxml2()
    if library is None:
        return None
    schema = DirectSchema(library, schema_root)
    return schema if schema.compiled else None
