"""Full XSD 1.1 validation with xmlschema: the reference the fast path must equal, and its
fallback.

Imported only when a 1.8/1.9 file meets an official schema: xmlschema takes a while to
import and to build a schema. Its errors are mapped to the same XS006 hits as libxml2's:
identity-constraint errors, which xmlschema reports on the element that declares the
constraint, are moved to each element whose value is missing or repeated.
"""

from __future__ import annotations

import ast
import copy as copy_module
import re
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any, Final

import xmlschema
from lxml import etree
from xmlschema.exceptions import XMLSchemaKeyError
from xmlschema.validators import XsdAssert

from xodrlint.concurrency import background
from xodrlint.document.load import Document
from xodrlint.document.positions import TreePositions
from xodrlint.findings import Hit
from xodrlint.validation.messages import (
    duplicate_key_message,
    missing_reference_message,
    quoted_list,
    sentence,
)
from xodrlint.validation.sets import SchemaLoadError
from xodrlint.validation.xsd11.alternatives import XSI, XSI_TYPE
from xodrlint.validation.xsd11.wording import assertion_message

_KEY_NOT_FOUND: Final = re.compile(r"value (?P<v>\(.*\)) not found for \w+\(name='(?P<k>[^']+)'\)")
_DUPLICATE: Final = re.compile(r"duplicated value (?P<v>\(.*\)) for \w+\(name='(?P<k>[^']+)'\)")
_ENUMERATION: Final = re.compile(
    r"^attribute (?P<a>[\w:]+)='(?P<v>.*)': value must be one of \[(?P<e>.*)\]$"
)
_ATTRIBUTE_VALUE: Final = re.compile(r"^attribute (?P<a>[\w:]+)='(?P<v>.*)': (?P<why>.*)$")
_MISSING_ATTRIBUTE: Final = re.compile(r"^missing required attribute '(?P<a>[^']+)'$")
_MISSING_CHILD: Final = ("is not complete", "Unexpected child")


class Xsd11Validator:
    #: xmlschema is Python: a thread would wait for the GIL (a forked child does not)
    thread_safe = False

    def __init__(self, entry: Path, *, schema_checked: bool = False) -> None:
        """``schema_checked``: these very files passed a strict build before (the fast
        path's cache says so), so the meta-schema check, 80% of a build, is skipped.
        Never pass it for files not checked: a skipped build turns a broken XPath into
        an assertion that always holds."""
        try:
            self._schema = xmlschema.XMLSchema11(
                str(entry),
                base_url=str(entry.parent),
                allow="sandbox",
                defuse="always",
                validation="skip" if schema_checked else "strict",
            )
        except (xmlschema.XMLSchemaException, OSError) as error:
            raise SchemaLoadError(f"cannot compile schema {entry}: {error}") from error

    @classmethod
    def of_schema(cls, schema: Any) -> Xsd11Validator:
        """A validator for an ``xmlschema.XMLSchema11`` built before (the fast path keeps
        one in its cache)."""
        validator = cls.__new__(cls)
        validator._schema = schema
        return validator

    @property
    def schema(self) -> Any:
        """The compiled ``xmlschema.XMLSchema11`` (the fast path reads its components)."""
        return self._schema

    def hits(self, doc: Document) -> Iterator[Hit]:
        assert doc.tree is not None
        root = doc.tree.getroot()
        try:
            errors = list(self._schema.iter_errors(doc.tree))
        except XMLSchemaKeyError:
            # an xsi:type that names no type of the set, on an element in a model group:
            # xmlschema's XSD 1.1 check of its dynamic type raises instead of reporting
            yield from self._hits_past_unknown_types(root)
            return
        yield from self.error_hits(root, errors)

    def _hits_past_unknown_types(self, root: etree._Element) -> Iterator[Hit]:
        """The document validated on a copy without the ``xsi:type`` attributes that name
        no type, its findings put back on the document's own elements; each such
        attribute is said as libxml2 says it, where xmlschema validates its element (one
        in skipped content, as in ``userData``, or an unexpected one, is not judged)."""
        unresolved = [e for e in _typed(root) if not self._resolves(e)]
        copied = copy_module.deepcopy(root)
        positions = TreePositions()
        twins: list[tuple[etree._Element, etree._Element]] = []
        for element in unresolved:
            steps = positions.steps_to(element, root)
            twin = positions.path_from(copied, steps) if steps is not None else None
            if twin is not None and XSI_TYPE in twin.attrib:
                del twin.attrib[XSI_TYPE]
                twins.append((element, twin))
        validated: set[etree._Element] = set()

        def seen(element: Any, declaration: Any) -> bool:
            validated.add(element)
            return False  # go on validating it

        errors = self._schema.iter_errors(copied, validation_hook=seen)
        found = list(self.error_hits(copied, errors))
        for element, twin in twins:
            if twin in validated:
                yield Hit(element, _unresolved_message(element), kind="other")
        yield from background.receive_hits(background.send_hits(found, copied), root)

    def _resolves(self, element: etree._Element) -> bool:
        """Whether ``element``'s ``xsi:type`` names a type of the set (or a built-in)."""
        written = (element.get(XSI_TYPE) or "").strip()
        prefix, _, local = written.rpartition(":")
        namespace = element.nsmap.get(prefix or None)
        if prefix and namespace is None:
            return False
        try:
            self._schema.maps.types[f"{{{namespace}}}{local}" if namespace else local]
        except (KeyError, TypeError):
            return False
        return True

    def error_hits(self, root: etree._Element, errors: Iterable[Any]) -> Iterator[Hit]:
        """One hit per xmlschema validation error (``root`` is the document's root)."""
        missing: set[int] = set()
        for error in errors:
            element = error.elem if isinstance(error.elem, etree._Element) else None
            if element is not None and isinstance(getattr(error, "validator", None), XsdAssert):
                # an error evaluating the test fails the assertion too: worded alike
                yield Hit(element, assertion_message(element, error.validator.path), kind="other")
                continue
            reason = str(error.reason or error.message)
            identity = _KEY_NOT_FOUND.search(reason) or _DUPLICATE.search(reason)
            if identity is not None:
                yield from self._identity_hits(root, identity, duplicate="duplicated" in reason)
                continue
            if reason.startswith("missing key field"):
                if element is not None and id(element) in missing:
                    continue
            elif element is not None and _MISSING_ATTRIBUTE.match(reason):
                missing.add(id(element))
            # xmlschema words a missing child either way, depending on what else the
            # parent holds; the kind is what lets ST001/ST002 take it over
            missing_child = any(words in reason for words in _MISSING_CHILD)
            yield Hit(
                element,
                _message(element, reason),
                line=None if element is not None else 1,
                kind="missing_child" if missing_child else "other",
            )

    def _identity_hits(
        self, root: etree._Element, match: re.Match[str], *, duplicate: bool
    ) -> Iterator[Hit]:
        values = _tuple(match["v"])
        key = match["k"]
        for name, constraint in self._constraints():
            refers = getattr(getattr(constraint, "refer", None), "name", None)
            if duplicate and name != key:
                continue
            if not duplicate and refers != key:
                continue
            first: etree._Element | None = None
            for element, field_values in _selected(root, constraint):
                if field_values != values:
                    continue
                if duplicate and first is None:
                    first = element  # named beside each later one, as libxml2's path does
                    continue
                where = f"'{etree.QName(element).localname}'"
                shown = quoted_list(list(values))
                kind = "duplicate" if duplicate else "keyref"
                yield Hit(
                    element,
                    _identity_message(where, shown, constraint, duplicate),
                    kind=kind,
                    related=(first,) if first is not None else (),
                )

    def _constraints(self) -> Iterator[tuple[str, Any]]:
        for name, constraint in self._schema.identities.items():
            yield str(getattr(constraint, "local_name", None) or name), constraint


def _identity_message(where: str, shown: str, constraint: Any, duplicate: bool) -> str:
    """Worded like the libxml2 path's messages, from the constraint's selector and fields."""
    tag = where.strip("'")
    fields = " and ".join(field.path for field in constraint.fields)
    key = constraint if duplicate else getattr(constraint, "refer", None)
    if key is None:
        return f"{where} refers to {shown}, which is not defined"
    key_fields = " and ".join(field.path for field in key.fields)
    if duplicate:
        return duplicate_key_message(tag, fields, shown, key.selector.path)
    return missing_reference_message(tag, fields, shown, key.selector.path, key_fields)


def _typed(root: etree._Element) -> list[etree._Element]:
    """The elements that carry an ``xsi:type``."""
    found = root.xpath("descendant-or-self::*[@xsi:type]", namespaces={"xsi": XSI})
    return found if isinstance(found, list) else []  # type: ignore[return-value]


def _unresolved_message(element: etree._Element) -> str:
    """libxml2's words for an ``xsi:type`` that names no type (XSD 1.0 files get them)."""
    return (
        f"'{etree.QName(element).localname}/@xsi:type': the QName value "
        f"'{(element.get(XSI_TYPE) or '').strip()}' of the xsi:type attribute does not "
        "resolve to a type definition"
    )


def _tuple(text: str) -> tuple[str, ...]:
    try:
        value = ast.literal_eval(text)
    except (ValueError, SyntaxError):
        return ()
    return tuple(str(v) for v in value) if isinstance(value, tuple) else (str(value),)


def _selected(
    root: etree._Element, constraint: Any
) -> Iterator[tuple[etree._Element, tuple[str, ...]]]:
    """Elements a key or keyref selects, with their field values, under every holder."""
    holder_name = getattr(getattr(constraint, "parent", None), "local_name", None)
    holders = [root] if holder_name in (None, root.tag) else list(root.iter(holder_name))
    selector = constraint.selector.path
    fields = [field.path for field in constraint.fields]
    for holder in holders:
        selected = holder.xpath(selector)
        for element in selected if isinstance(selected, list) else ():
            if not isinstance(element, etree._Element):
                continue
            values: list[str] = []
            for path in fields:
                found = element.xpath(path)
                values.append(str(found[0]) if isinstance(found, list) and found else "")
            yield element, tuple(values)


def _message(element: etree._Element | None, reason: str) -> str:
    tag = etree.QName(element).localname if element is not None else "the document"
    enumeration = _ENUMERATION.match(reason)
    if enumeration:
        allowed = re.findall(r"'((?:[^'\\]|\\.)*)'", enumeration["e"])
        return (
            f"'{tag}/@{enumeration['a']}' is '{enumeration['v']}', "
            f"expected one of {quoted_list(allowed)}"
        )
    missing = _MISSING_ATTRIBUTE.match(reason)
    if missing:
        return f"'{tag}' lacks the required attribute '{missing['a']}'"
    value = _ATTRIBUTE_VALUE.match(reason)
    if value:
        return f"'{tag}/@{value['a']}' is '{value['v']}': {sentence(value['why'])}"
    return f"'{tag}': {sentence(reason)}"
