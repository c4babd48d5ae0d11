"""XSD 1.1 assertions (``xs:assert``) checked on just the elements that carry them.

Each assertion's compiled XPath 2.0 token is evaluated with a context built as xmlschema
builds it (``XsdAssert.__call__``). An assertion that sees only named children and
attributes runs on a pruned copy of its element, and elements whose pruned copies are
equal share one evaluation. An assertion that might look past its element is refused,
and the set is validated in full.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any, Final

from lxml import etree

from xodrlint.validation.xsd11 import NeedsFull

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


@dataclass(frozen=True, slots=True)
class TypeAssertions:
    """A type's assertions: those that see only named children and attributes (run on a
    pruned copy of the element, results shared between equal copies) and the others."""

    pruned: tuple[Any, ...]
    elements: tuple[str, ...]
    attributes: frozenset[str]
    whole: tuple[Any, ...]


def type_assertions(xsd_type: Any, keep: Callable[[Any], bool] = bool) -> TypeAssertions:
    """The type's assertions that ``keep`` keeps, grouped."""
    pruned: list[Any] = []
    whole: list[Any] = []
    elements: set[str] = set()
    attributes: set[str] = set()
    for assertion in xsd_type.assertions:
        if not keep(assertion):
            continue
        check_bounded(assertion)
        names = XPathNames()
        try:
            names.kind_of(assertion.token)
        except Unprunable:
            whole.append(assertion)
            continue
        pruned.append(assertion)
        elements |= names.elements
        attributes |= names.attributes
    return TypeAssertions(
        tuple(pruned), tuple(sorted(elements)), frozenset(attributes), tuple(whole)
    )


def check_bounded(assertion: Any) -> None:
    """Refuse an assertion whose XPath might see past its element (see _UNBOUNDED_XPATH)."""
    for token in assertion.token.iter():
        symbol = getattr(token, "symbol", "")
        if symbol in _UNBOUNDED_XPATH or (symbol in ("/", "//") and len(token) < 2):
            raise NeedsFull(f"assertion {assertion.path!r} looks beyond its element")


class Unprunable(Exception):
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


class XPathNames:
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
                raise Unprunable
            step = children[1].symbol
            if step not in ("(name)", "@", ".", *_UPWARD_AXES):
                raise Unprunable
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
                raise Unprunable
            if any(self.kind_of(child) == "elements" for child in children):
                raise Unprunable  # an element's string value depends on all its text
            return "atomic"
        if symbol == "if" and len(children) == 3:
            self.kind_of(children[0])
            kinds = {self.kind_of(children[1]), self.kind_of(children[2])}
            return next(k for k in ("elements", "attributes", "atomic") if k in kinds)
        raise Unprunable

    @staticmethod
    def _name(token: Any, names: set[str], kind: str) -> str:
        name = str(getattr(token, "value", "") or "")
        if not name or ":" in name or "{" in name or "*" in name:
            raise Unprunable
        names.add(name)
        return kind


def assertion_errors(
    group: TypeAssertions, element: etree._Element, xsd_type: Any, memo: dict[Any, Any]
) -> Iterator[Any]:
    """xmlschema's errors for the assertions of ``element``'s type (``group``, as
    :func:`type_assertions` made them), evaluated as ``XsdAssert.__call__`` evaluates
    them."""
    from xmlschema import XMLSchemaValidationError

    if not (group.pruned or group.whole):
        return
    text = element.text if xsd_type.has_simple_content() else None
    outcome: list[tuple[Any, str]] = []
    if group.pruned:
        kept = _kept_nodes(element, group.elements)
        key = (id(group), _signature(element, kept, group.attributes), text)
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
    attributes: all an assertion of :class:`XPathNames` sees."""

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
