"""The identity constraints of a schema set (keys, uniques, keyrefs), for explaining
their errors: the attributes a key compares, and the element that first holds a value
another element repeats, which a duplicate's finding names beside it."""

from __future__ import annotations

from lxml import etree

from xodrlint.validation.messages import Explained, TypeCatalog
from xodrlint.validation.source import XS


def selector_of(identity: etree._Element) -> str:
    """The XPath of the elements a key, unique or keyref selects (``road``)."""
    selector = identity.find(f"{{{XS}}}selector")
    return "" if selector is None else (selector.get("xpath") or "").strip()


def key_fields(catalog: TypeCatalog, why: Explained) -> tuple[str, ...] | None:
    """The attributes a key or keyref compares, when each field is a plain ``@attr``."""
    identity = catalog.identities.get(why.constraint or "")
    if identity is None:
        return None
    paths = [field.get("xpath", "") for field in identity.iterfind(f"{{{XS}}}field")]
    if not paths or not all(p.startswith("@") and p[1:].isidentifier() for p in paths):
        return None
    return tuple(p[1:] for p in paths)


class FirstHolders:
    """The element that first holds a duplicated key value, for a duplicate's finding to
    name (as the rules name the first of two switches with one id). Each constraint's
    elements are read once per scope, and only for a run with duplicates."""

    def __init__(self, catalog: TypeCatalog) -> None:
        self._catalog = catalog
        self._firsts: dict[tuple[str, etree._Element], dict[tuple[str, ...], etree._Element]]
        self._firsts = {}

    def of(self, element: etree._Element | None, why: Explained) -> etree._Element | None:
        identity = self._catalog.identities.get(why.constraint or "")
        fields = key_fields(self._catalog, why)
        if element is None or identity is None or fields is None or not why.constraint:
            return None
        declared = identity.getparent()
        if declared is None:
            return None
        scope_tag = declared.get("name")
        scope = next((a for a in element.iterancestors() if _local(a) == scope_tag), None)
        if scope is None:
            return None
        key = (why.constraint, scope)
        firsts = self._firsts.get(key)
        if firsts is None:
            firsts = self._firsts[key] = self._holders(scope, selector_of(identity), fields)
        first = firsts.get(tuple(element.get(name) or "" for name in fields))
        return first if first is not None and first is not element else None

    @staticmethod
    def _holders(
        scope: etree._Element, selector: str, fields: tuple[str, ...]
    ) -> dict[tuple[str, ...], etree._Element]:
        try:
            selected = scope.xpath(selector)
        except etree.XPathError:
            return {}
        holders: dict[tuple[str, ...], etree._Element] = {}
        for item in selected if isinstance(selected, list) else []:
            if isinstance(item, etree._Element):
                values = tuple(item.get(name) for name in fields)
                if all(value is not None for value in values):
                    holders.setdefault(tuple(v or "" for v in values), item)
        return holders


def _local(element: etree._Element) -> str:
    return etree.QName(element).localname
