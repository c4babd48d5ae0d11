"""Type alternatives in a libxml2 run: libxml2 validates by the XSD 1.0 form, where an
element with alternatives keeps its declared type. The alternative an element selects is
handed to libxml2 as an ``xsi:type`` on that element for the time of the validation
(XSD 1.1 requires every alternative to derive from the declared type, which is what
``xsi:type`` needs).

Most documents need no marks at all, which the bytes usually tell at once; a file with
an ``xsi:type`` or ``xsi:nil`` of its own, or a ``+INF`` (a number in XSD 1.1, not in
XSD 1.0), is validated in full.
"""

from __future__ import annotations

import contextlib
import re
from collections.abc import Iterator, Sequence
from typing import Final

from lxml import etree

from xodrlint.document.load import Document

XSI: Final = "http://www.w3.org/2001/XMLSchema-instance"

XSI_TYPE: Final = f"{{{XSI}}}type"


_XSD11_READING: Final = (
    "boolean(//@xsi:type | //@xsi:nil | //@*[contains(., '+INF')] | //text()[contains(., '+INF')])"
)


# Starts at the colon: a pattern that starts with a character class scans a 20 MB map in
# 0.5 s, one that starts with a literal in 10 ms. It also matches what is no prefixed
# attribute (text ending in ':type='): the tree is asked then, which only costs time.
_PREFIXED_TYPE_OR_NIL: Final = re.compile(rb":(?:type|nil)\s*=")


def holds_a_site(doc: Document, root: etree._Element, sites: frozenset[tuple[str, str]]) -> bool:
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


def needs_xsd11_reading(doc: Document, root: etree._Element) -> bool:
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


@contextlib.contextmanager
def xsi_types(marks: Sequence[tuple[etree._Element, str]]) -> Iterator[None]:
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
