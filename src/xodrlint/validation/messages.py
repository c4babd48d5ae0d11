"""Turn XSD validator messages into messages a map engineer understands.

libxml2 and xmlschema word their errors for schema authors ("is not a valid value of the
union type 'e_countryCode'"). Here each becomes: which element and attribute, the bad
value, and what the schema allows, read off the schema's own type definitions.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from typing import Final, NamedTuple

from lxml import etree

from xodrlint.findings import NO_ENTRIES
from xodrlint.fixes import Fix, set_attribute
from xodrlint.validation.source import XS

_ENUM_SHOWN: Final = 12

_BUILTIN_TYPES: Final = {
    "double": "a number",
    "float": "a number",
    "decimal": "a decimal number",
    "integer": "an integer",
    "int": "an integer",
    "long": "an integer",
    "short": "an integer",
    "nonNegativeInteger": "an integer >= 0",
    "positiveInteger": "an integer > 0",
    "unsignedShort": "an integer from 0 to 65535",
    "unsignedInt": "an integer >= 0",
    "boolean": "'true' or 'false'",
    "string": "a string",
    "dateTime": "a date and time (YYYY-MM-DDThh:mm:ss)",
}


#: More restrictions of restrictions than any schema writes: a loop in a broken one ends here.
_LONGEST_CHAIN: Final = 16


class TypeCatalog(NamedTuple):
    """The named simple types of a schema set, for saying what a type allows."""

    types: Mapping[str, etree._Element]
    identities: Mapping[str, etree._Element] = NO_ENTRIES

    @classmethod
    def from_documents(cls, documents: Iterable[etree._Element]) -> TypeCatalog:
        types: dict[str, etree._Element] = {}
        identities: dict[str, etree._Element] = {}
        for document in documents:
            for simple in document.iter(f"{{{XS}}}simpleType"):
                name = simple.get("name")
                if name:
                    types.setdefault(name, simple)
            for identity in document.iter(f"{{{XS}}}key", f"{{{XS}}}keyref", f"{{{XS}}}unique"):
                name = identity.get("name")
                if name:
                    identities.setdefault(name, identity)
        return cls(types, identities)

    def referenced(self, keyref_name: str) -> tuple[str, str] | None:
        """For a keyref, the elements (selector) and attribute (field) it must match."""
        keyref = self.identities.get(keyref_name)
        if keyref is None:
            return None
        refer = keyref.get("refer")
        key = keyref if refer is None else self.identities.get(refer.rpartition(":")[2])
        if key is None:
            return None
        selector = key.find(f"{{{XS}}}selector")
        fields = [f.get("xpath", "") for f in key.iterfind(f"{{{XS}}}field")]
        if selector is None or not fields:
            return None
        return (selector.get("xpath", "").strip(), " and ".join(fields))

    def bounds(self, type_name: str) -> frozenset[str]:
        """The bounding facets (``min``, ``max``) of ``type_name`` and of the types it
        restricts."""
        restrictions, _ = self._restrictions(type_name)
        return frozenset(
            side
            for restriction in restrictions
            for side in ("min", "max")
            for kind in ("Inclusive", "Exclusive")
            if restriction.find(f"{{{XS}}}{side}{kind}") is not None
        )

    def builtin_of(self, type_name: str) -> str | None:
        """The built-in type ``type_name`` restricts (itself if built-in); ``None`` for a
        union, a list or a type not known."""
        _, base = self._restrictions(type_name)
        if base is None:
            return None
        local = base.rpartition(":")[2]
        return local if local in _BUILTIN_TYPES or ":" in base else None

    def _restrictions(self, type_name: str) -> tuple[list[etree._Element], str | None]:
        """The ``xs:restriction`` of each named simple type from ``type_name`` down the
        types it restricts, and the name of the type the chain starts from, which is none
        of the set's (a built-in); ``None`` for that where the chain meets a union, a
        list, or goes on for longer than a schema's would."""
        found: list[etree._Element] = []
        name = type_name
        for _ in range(_LONGEST_CHAIN):
            simple = self.types.get(name.rpartition(":")[2])
            if simple is None:
                return found, name
            restriction = simple.find(f"{{{XS}}}restriction")
            if restriction is None:
                return found, None
            found.append(restriction)
            name = restriction.get("base", "")
        return found, None

    def describe(self, type_name: str, depth: int = 0) -> str | None:
        """What values ``type_name`` accepts, in words; ``None`` if unknown."""
        local = type_name.rpartition(":")[2]
        if local in _BUILTIN_TYPES and local not in self.types:
            return _BUILTIN_TYPES[local]
        simple = self.types.get(local)
        if simple is None or depth > 4:
            return None
        return self._describe_simple(simple, depth)

    def _describe_simple(self, simple: etree._Element, depth: int) -> str | None:
        union = simple.find(f"{{{XS}}}union")
        if union is not None:
            members = (union.get("memberTypes") or "").split()
            parts = [self.describe(member, depth + 1) for member in members]
            parts += [
                self._describe_simple(inline, depth + 1)
                for inline in union.iterfind(f"{{{XS}}}simpleType")
            ]
            known = [part for part in parts if part]
            return " or ".join(known) if known else None
        restriction = simple.find(f"{{{XS}}}restriction")
        if restriction is None:
            return None
        return self._describe_restriction(restriction, depth)

    def _describe_restriction(self, restriction: etree._Element, depth: int) -> str | None:
        enumeration = [e.get("value", "") for e in restriction.iterfind(f"{{{XS}}}enumeration")]
        if enumeration:
            return "one of " + quoted_list(enumeration)
        patterns = [p.get("value", "") for p in restriction.iterfind(f"{{{XS}}}pattern")]
        if patterns:
            return " or ".join(f"a value matching {p}" for p in patterns)
        base = self.describe(restriction.get("base", ""), depth + 1) or "a value"
        bounds = [
            f"{symbol} {facet.get('value')}"
            for tag, symbol in (
                ("minInclusive", ">="),
                ("minExclusive", ">"),
                ("maxInclusive", "<="),
                ("maxExclusive", "<"),
            )
            for facet in restriction.iterfind(f"{{{XS}}}{tag}")
        ]
        return f"{base} {' and '.join(bounds)}" if bounds else base


def quoted_list(values: list[str]) -> str:
    shown = ", ".join(f"'{value}'" for value in values[:_ENUM_SHOWN])
    hidden = len(values) - _ENUM_SHOWN
    return shown + (f" and {hidden} more" if hidden > 0 else "")


# The patterns stay strings, compiled (and cached by ``re``) when a schema error is
# first explained: compiling them all on import cost every run 3 ms, clean maps included.
# "Element 'switch', attribute 'position': <body>" as libxml2 writes it.
_SUBJECT: Final = r"^Element '(?P<element>[^']*)'(?:, attribute '(?P<attr>[^']*)')?: "
_REWRITES: Final[tuple[tuple[str, str], ...]] = (
    (
        (
            r"\[facet 'enumeration'\] The value '(?P<v>.*)' is not an element of the set"
            r" \{(?P<set>.*)\}\.?$"
        ),
        "enumeration",
    ),
    (
        r"^'(?P<v>.*)' is not a valid value of the \w+ type '(?P<type>[^']*)'\.?$",
        "type",
    ),
    (r"^The attribute '(?P<a>[^']*)' is required but missing\.?$", "required"),
    (r"^The attribute '(?P<a>[^']*)' is not allowed\.?$", "unexpected_attribute"),
    (
        r"^This element is not expected\. Expected is (?:one of )?\( (?P<e>.*) \)\.?$",
        "unexpected_element",
    ),
    (r"^This element is not expected\.?$", "unexpected_element_bare"),
    (
        r"^Missing child element\(s\)\. Expected is (?:one of )?\( (?P<e>.*) \)\.?$",
        "missing_child",
    ),
    (
        r"^No match found for key-sequence \[(?P<v>.*)\] of keyref '(?P<k>[^']*)'\.?$",
        "keyref",
    ),
    (
        (
            r"^Duplicate key-sequence \[(?P<v>.*)\] in (?:key|unique) identity-constraint"
            r" '(?P<k>[^']*)'\.?$"
        ),
        "duplicate",
    ),
    (
        (
            r"^\[facet '(?P<f>min|max)(?P<kind>Inclusive|Exclusive)'\] The value '(?P<v>.*)'"
            r" is (?:less|greater) than the (?:minimum|maximum) value allowed \('(?P<lim>.*)'\)"
            r"\.?$"
        ),
        "bound",
    ),
    (
        # libxml2 words the exclusive bounds differently from the inclusive ones
        (
            r"^\[facet '(?P<f>min|max)(?P<kind>Exclusive)'\] The value '(?P<v>.*)'"
            r" must be (?:greater|less) than '(?P<lim>.*)'\.?$"
        ),
        "bound",
    ),
    (
        (
            r"^\[facet 'pattern'\] The value '(?P<v>.*)' is not accepted by the pattern"
            r" '(?P<p>.*)'\.?$"
        ),
        "pattern",
    ),
    (
        (
            r"^The value '(?P<v>.*)' does not match the fixed value constraint"
            r" '(?P<fixed>.*)'\.?$"
        ),
        "fixed",
    ),
)

_ABSTRACT: Final = r"^The type definition is abstract\.?$"


class Explained(NamedTuple):
    message: str
    kind: str
    element: str | None
    key_values: tuple[str, ...] = ()
    constraint: str | None = None
    attribute: str | None = None
    """The attribute the error is about, where it is about one."""
    allowed: tuple[str, ...] = ()
    """An enumeration's values, every one (the message shows the first few)."""
    value_type: str | None = None
    """The simple type a value is not valid for, where libxml2 names it."""


def explain_libxml2(raw: str, catalog: TypeCatalog, version: str | None) -> Explained:
    """Rewrite one libxml2 schema error for a person."""
    raw = raw.strip()
    subject = re.match(_SUBJECT, raw)
    element = subject["element"] if subject else None
    attr = subject["attr"] if subject else None
    body = raw[subject.end() :] if subject else raw
    where = f"'{element}/@{attr}'" if attr else f"'{element}'" if element else "the document"
    for pattern, kind in _REWRITES:
        match = re.search(pattern, body)
        if match is None:
            continue
        fields = match.groupdict()
        return Explained(
            _render(kind, where, element or "", fields, catalog, version),
            kind,
            element,
            _key_values(fields.get("v", "")) if kind in ("keyref", "duplicate") else (),
            fields.get("k"),
            attr,
            tuple(_enumeration(fields["set"])) if kind == "enumeration" else (),
            fields.get("type"),
        )
    if re.match(_ABSTRACT, body):
        # the element's declared type is abstract and nothing chose a concrete one; libxml2
        # skips the element's content then (the XSD 1.1 fast path checks it another way)
        return Explained(f"{where}: {sentence(body)}", "abstract", element)
    if "evaluate to a node" in body:
        return Explained(f"{where}: {sentence(body)}", "key_field", element)
    return Explained(f"{where}: {sentence(body)}", "other", element)


#: XML's blanks, which XSD collapses around a number before reading it.
_XML_BLANKS: Final = " \t\n\r"


def blank_special_number(why: Explained, value: str | None, catalog: TypeCatalog) -> bool:
    """Is this libxml2's error for a number XSD accepts: ``NaN``, ``INF`` or ``-INF``
    with blanks after it? libxml2 refuses those blanks, though XSD collapses them for
    xs:double and xs:float as for any number (it accepts ``" 1 "``, and ``" INF"``). The
    value read without them is judged as libxml2 judges it written so: NaN meets any
    bound, INF breaks only a maximum and -INF only a minimum."""
    if why.kind != "type" or value is None or why.value_type is None:
        return False
    number = value.strip(_XML_BLANKS)
    if number == value or number not in ("NaN", "INF", "-INF"):
        return False
    if catalog.builtin_of(why.value_type) not in ("double", "float"):
        return False  # (an integer's 'NaN ' is no number at all; a union: left to libxml2)
    bounds = catalog.bounds(why.value_type)
    return number == "NaN" or ("max" if number == "INF" else "min") not in bounds


def _render(
    kind: str,
    where: str,
    element: str,
    f: dict[str, str],
    catalog: TypeCatalog,
    version: str | None,
) -> str:
    in_version = f" in OpenDRIVE {version}" if version else ""
    if kind == "enumeration":
        return f"{where} is '{f['v']}', expected one of {quoted_list(_enumeration(f['set']))}"
    if kind == "type":
        description = catalog.describe(f["type"])
        expectation = f"expected {description}" if description else f"not a valid '{f['type']}'"
        declared = (
            f", which OpenDRIVE {version} (the version the header declares)" if version else ""
        )
        return f"{where} is '{f['v']}'{declared} does not allow: {expectation}"
    if kind == "required":
        return f"'{element}' lacks the required attribute '{f['a']}'"
    if kind == "unexpected_attribute":
        return f"'{element}' has an attribute '{f['a']}' the schema{in_version} does not define"
    if kind == "unexpected_element":
        return f"'{element}' is not allowed here{in_version}; expected {_names(f['e'])}"
    if kind == "unexpected_element_bare":
        return f"'{element}' is not allowed here{in_version}"
    if kind == "missing_child":
        return f"'{element}' lacks a required child: expected {_names(f['e'])}"
    if kind == "keyref":
        target = catalog.referenced(f["k"])
        if target is None:
            return f"{where} refers to {f['v']}, which no element of '{f['k']}' defines"
        keyref = catalog.identities[f["k"]]
        field_xpath = " and ".join(x.get("xpath", "") for x in keyref.iterfind(f"{{{XS}}}field"))
        return missing_reference_message(element, field_xpath, f["v"], target[0], target[1])
    if kind == "duplicate":
        key = catalog.referenced(f["k"])
        if key is None:
            return f"{where} repeats the key {f['v']} of '{f['k']}'"
        return duplicate_key_message(element, key[1], f["v"], key[0])
    if kind == "bound":
        relation = {
            ("min", "Inclusive"): ">=",
            ("min", "Exclusive"): ">",
            ("max", "Inclusive"): "<=",
            ("max", "Exclusive"): "<",
        }[f["f"], f["kind"]]
        return f"{where} is '{f['v']}', expected a value {relation} {f['lim']}"
    if kind == "pattern":
        return f"{where} is '{f['v']}', expected a value matching {f['p']}"
    return f"{where} is '{f['v']}', but the schema{in_version} fixes it to '{f['fixed']}'"


def _enumeration(values: str) -> list[str]:
    """The values of libxml2's ``{'a', 'b'}``."""
    return re.findall(r"'((?:[^']|'')*)'", values)


#: The elements whose enumerated attributes XS006 mends (a value written in another case,
#: or with blanks around it): the railroad elements, and a lane's type.
_MENDED_ENUMERATIONS: Final = frozenset(
    {
        ("switch", "position"),
        ("mainTrack", "dir"),
        ("sideTrack", "dir"),
        ("station", "type"),
        ("segment", "side"),
        ("lane", "type"),
    }
)


def enumeration_fix(element: etree._Element, why: Explained) -> Fix | None:
    """XS006's fix of an enumerated attribute whose value is exactly one allowed value
    when compared without case and surrounding blanks (``position="Dynamic"``): that
    value. Only for the railroad elements' enumerations and a lane's ``type``."""
    attribute = why.attribute
    if why.kind != "enumeration" or attribute is None:
        return None
    tag = etree.QName(element).localname
    if (tag, attribute) not in _MENDED_ENUMERATIONS:
        return None
    value = element.get(attribute)
    if value is None:
        return None
    # XML's blanks and plain case: a no-break space, or a long s, is no spelling of a value
    wanted = value.strip(" \t\r\n")
    if not wanted.isascii():  # the Kelvin sign lowers to a "k": no spelling of a value
        return None
    matches = [allowed for allowed in why.allowed if allowed.lower() == wanted.lower()]
    if len(matches) != 1 or matches[0] == value:
        return None
    return Fix(
        f"write '{matches[0]}', as the standard spells it",
        (set_attribute(element, attribute, matches[0]),),
    )


def missing_reference_message(
    tag: str, fields: str, values: str, key_selector: str, key_fields: str
) -> str:
    """A keyref value no key defines: the same words for libxml2 and xmlschema."""
    return f"'{tag}/{fields}' names {values}, but no '{key_selector}' has that {key_fields}"


_MISSING_REFERENCE: Final = re.compile(
    r"^'[^']*/@(?P<field>[\w.-]+)' names '(?P<value>[^']*)', "
    r"but no '(?P<holder>[\w.-]+)' has that @(?P<key>[\w.-]+)$"
)


def missing_reference(message: str) -> tuple[str, str, str] | None:
    """What a :func:`missing_reference_message` of one attribute says is missing: the
    value, and the element and attribute that would define it (``('2', 'road', 'id')``);
    ``None`` for any other message, a key of several fields or a selector of a path."""
    found = _MISSING_REFERENCE.match(message)
    return None if found is None else (found["value"], found["holder"], found["key"])


def duplicate_key_message(tag: str, fields: str, values: str, key_selector: str) -> str:
    """A key value used twice: the same words for libxml2 and xmlschema. A key of one
    attribute reads as the rules word a duplicate: ``road id '3' is not unique: an earlier
    'road' has it`` (the finding adds that road's line)."""
    attribute = fields.strip()
    if re.fullmatch(r"@[A-Za-z_][\w.-]*", attribute):
        last_step = key_selector.strip().split("|")[0].strip().rsplit("/", 1)[-1]
        holder = last_step if re.fullmatch(r"[A-Za-z_][\w.-]*", last_step) else key_selector
        return f"{tag} {attribute[1:]} {values} is not unique: an earlier '{holder}' has it"
    return f"'{tag}/{fields}' is {values}, which an earlier '{key_selector}' already has"


def _names(expected: str) -> str:
    names = [name.strip().rpartition("}")[2] for name in expected.split(",") if name.strip()]
    if len(names) == 1:
        return f"'{names[0]}'"
    return "one of " + quoted_list(names)


def _key_values(raw: str) -> tuple[str, ...]:
    return tuple(value.replace("''", "'") for value in re.findall(r"'((?:[^']|'')*)'", raw))


def sentence(body: str) -> str:
    """A validator's sentence as a message fragment: lowercase start, no final period."""
    body = body.strip().rstrip(".")
    return body[:1].lower() + body[1:]
