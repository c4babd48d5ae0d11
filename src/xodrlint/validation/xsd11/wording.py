"""What a failed XSD 1.1 assertion means, in words.

Both routes (the assertion translated into XPath 1.0, and xmlschema) word a failed
assertion here, so a finding reads the same whichever route judged it. Each assertion of
the official OpenDRIVE 1.8 and 1.9 sets has a sentence; an assertion of another set is
quoted as written.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Final

from lxml import etree

from xodrlint.validation.messages import quoted_list

_OBJECT_KIND: Final = re.compile(
    r"^if \(@type = '(?P<kind>\w+)'\) then \((?P<body>.*)\) else true\(\)$"
)
_FORBIDDEN: Final = re.compile(r"not\((@?\w+)\)")
_DISTANCE: Final = {
    "repeat/@distance = 0": "its repeat/@distance must be 0",
    "repeat/@distance > 0": "its repeat/@distance must be greater than 0",
    "repeat/@distance != 0": "its repeat/@distance must not be 0",
}


def _duplicate_connections(element: etree._Element) -> str:
    seen: set[str] = set()
    repeated: list[str] = []
    for connection in element.iterchildren("connection"):
        value = connection.get("id")
        if value is None:
            continue
        if value in seen and value not in repeated:
            repeated.append(value)
        seen.add(value)
    ids = f" ({quoted_list(repeated)})" if repeated else ""
    return f"'{element.tag}' has connections that share an @id{ids}; each must be unique"


_SENTENCES: Final[dict[str, Callable[[etree._Element], str]]] = {
    "count(connection/@id) = count(distinct-values(connection/@id))": _duplicate_connections,
    "if (count(laneOffset) > 0) then count(laneSection//border) = 0 else true()": lambda e: (
        f"'{e.tag}' has a laneOffset, so no lane of it may use border"
    ),
    "if (@layer = 'permanent') then not(laneSection/@length) else true()": lambda e: (
        f"'{e.tag}' has @layer 'permanent', so no laneSection of it may have @length"
    ),
    "not(exists(crossSectionSurface)) or (not(exists(superelevation)) and not(exists(shape)))": (
        lambda e: f"'{e.tag}' has a crossSectionSurface, so it may have no superelevation or shape"
    ),
    "not(@radius or @width or @length) or (@radius and not(@width or @length)) or "
    "(@width and @length and not(@radius))": lambda e: (
        f"'{e.tag}' must give its size as @radius alone or as both @width and @length"
    ),
    "if (@useCompleteOutline) then not(cornerReference) else count(cornerReference) gt 1": (
        lambda e: (
            f"'{e.tag}' must have @useCompleteOutline or at least two cornerReference, not both"
        )
    ),
    "if (@side) then not(cornerReference) else count(cornerReference) gt 1": lambda e: (
        f"'{e.tag}' must have @side (whatever its value) or at least two cornerReference, not both"
    ),
    "if (name(parent::*) = 'outline') then not(parent::*/parent::*/parent::*/markings) "
    "else true()": lambda e: f"'{e.tag}' of an outline may not stand beside markings of its object",
    "if (name(parent::*) = 'object') then count(cornerReference) = 0 else true()": lambda e: (
        f"'{e.tag}' of an object's marking may hold no cornerReference"
    ),
    "not(@type = 'multiBoard') or (@type = 'multiBoard' and @dynamic = true() and "
    "count(./vmsBoard) gt 0 and count(./staticBoard) gt 0)": lambda e: (
        f"'{e.tag}' of type 'multiBoard' fails the schema's test, which asks for @dynamic ="
        " true() and a vmsBoard and a staticBoard: @dynamic is 'yes' or 'no', never a"
        " boolean, so no multiBoard signal passes it"
    ),
}


def _object_sentence(element: etree._Element, test: str) -> str | None:
    """The sentence of one of the official sets' assertions by object @type."""
    match = _OBJECT_KIND.match(test)
    if match is None:
        return None
    body = match["body"]
    demands = [words for condition, words in _DISTANCE.items() if f"or {condition})" in body]
    forbidden = _FORBIDDEN.findall(body)
    if not forbidden or len(demands) > 1:
        return None
    tag = etree.QName(element).localname
    sentence = f"'{tag}' of type '{match['kind']}' may have no {_names(forbidden)}"
    return f"{sentence}, and {demands[0]}" if demands else sentence


def _names(names: list[str]) -> str:
    return ", ".join(names[:-1]) + f" or {names[-1]}" if len(names) > 1 else names[0]


def assertion_message(element: etree._Element, test: str) -> str:
    """The finding's message for ``element`` failing the assertion ``test``."""
    written = " ".join(test.split())
    sentence = _SENTENCES.get(written)
    if sentence is not None:
        return sentence(element)
    by_kind = _object_sentence(element, written)
    if by_kind is not None:
        return by_kind
    tag = etree.QName(element).localname
    return f"'{tag}' fails the schema's assertion {written}"
