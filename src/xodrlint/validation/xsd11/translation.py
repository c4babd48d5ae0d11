"""XSD 1.1 assertions and type alternatives translated into XPath 1.0, for libxml2.

Done once per schema set, when its XSD 1.0 form is derived
(:mod:`~xodrlint.validation.xsd11.form` keeps the result in its manifest), from the
compiled XPath 2.0 tokens of xmlschema's strict build. At run time
:mod:`~xodrlint.validation.xsd11.selectors` runs the result in libxml2, and neither
xmlschema nor elementpath is imported.

An assertion becomes two XPath 1.0 tests on its element:

- *fails*: true exactly when XSD 1.1 finds the assertion false or its evaluation raises
  an error (an error makes an assertion fail). Each expression is translated into its
  value and the condition under which evaluating it raises, composed as XPath 2.0's
  ``and``, ``or`` and ``if`` evaluate (left to right, stopping early as elementpath does);
- *uncertain*: true where XPath 1.0 and XSD 1.1 might read a value differently (a number
  written ``1e3``, ``INF``, ``+5`` or not at all, a string with blanks its type
  collapses). Such an element is checked by xmlschema, as before.

XSD 1.1 evaluates an assertion on a tree rooted at its element: ``parent::*`` of the
element is empty. Each asserted type is reached by fixed element paths from the root (with
the tests of the type alternatives on the way as predicates), the same walk
:class:`~xodrlint.validation.xsd11.governing.SchemaModel` makes.

What does not translate is said, with why; that assertion keeps xmlschema's route.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Final

from xodrlint.validation.xsd11 import NeedsFull
from xodrlint.validation.xsd11.governing import SchemaModel
from xodrlint.validation.xsd11.selectors import FALSE

#: XPath 1.0 test: the value is a number XPath 1.0 reads as xs:double does (digits, at
#: most one point, an optional minus, blanks around).
_PLAIN_NUMBER: Final = (
    "(string(number(.)) != 'NaN' and contains('||.|-|-.|',"
    " concat('|', translate(normalize-space(.), '0123456789', ''), '|'))"
    # libxml2 reads a fraction past some 308 zeros as 0, where xs:double does not
    " and (number(.) != 0 or translate(normalize-space(.), '-.0', '') = ''))"
)
#: Built-in types whose plain numerals XPath 1.0 compares with 0 as XSD does (xs:float
#: reads a tiny value as 0, an xs:integer refuses a point: neither translates).
_NUMERIC_BUILTINS: Final = frozenset({"double", "decimal"})
#: Elements whose duplicate ids the XPath looks for in quadratic time: more go to xmlschema.
_MAX_DISTINCT: Final = 256
_GENERAL: Final = {"=": "=", "!=": "!=", "<": "<", "<=": "<=", ">": ">", ">=": ">="}
_VALUE: Final = {"eq": "=", "ne": "!=", "lt": "<", "le": "<=", "gt": ">", "ge": ">="}
_FLIPPED: Final = {"=": "=", "!=": "!=", "<": ">", "<=": ">=", ">": "<", ">=": "<="}
#: Paths of one asserted type beyond this many: not worth an XPath (none in OpenDRIVE).
_MAX_PATHS: Final = 64


class Untranslatable(Exception):
    """An expression outside the subset that translates exactly."""


TRUE: Final = "true()"


def and_(*terms: str) -> str:
    kept = [t for t in terms if t != TRUE]
    if FALSE in kept:
        return FALSE
    return " and ".join(f"({t})" for t in kept) if len(kept) > 1 else (kept[0] if kept else TRUE)


def or_(*terms: str) -> str:
    kept = [t for t in terms if t != FALSE]
    if TRUE in kept:
        return TRUE
    return " or ".join(f"({t})" for t in kept) if len(kept) > 1 else (kept[0] if kept else FALSE)


def not_(term: str) -> str:
    return {TRUE: FALSE, FALSE: TRUE}.get(term, f"not({term})")


@dataclass(frozen=True, slots=True)
class Expr:
    """A translated expression: its kind (``elements``, ``attributes``, ``number``,
    ``string``, ``boolean``), its XPath 1.0 text (``None``: an empty node-set), when its
    evaluation raises, and when the translation may read a value otherwise than XSD 1.1.
    A node-set also carries its depth below the context element (``None``: unknown) and,
    for an attribute node-set, the attribute's simple type (``None``: unknown)."""

    kind: str
    text: str | None
    raises: str = FALSE
    uncertain: str = FALSE
    depth: int | None = 0
    xsd_type: Any = None
    owner: Any = None

    @property
    def truth(self) -> str:
        """XPath 2.0's effective boolean value (XPath 1.0's ``boolean()`` for the kinds
        translated here: node-sets, a number, a string, a boolean)."""
        if self.text is None:
            return FALSE
        return self.text if self.kind == "boolean" else f"boolean({self.text})"


def _literal(value: str) -> str:
    if "'" not in value:
        return f"'{value}'"
    if '"' not in value:
        return f'"{value}"'
    raise Untranslatable("a string with both quotes")


class Translator:
    """Translates the XPath 2.0 tokens of one type's assertions (``xsd_type`` is the
    xmlschema type they belong to, read for the types of attributes)."""

    def __init__(self, xsd_type: Any, model: SchemaModel | None) -> None:
        self.xsd_type = xsd_type
        self.model = model

    def assertion(self, token: Any) -> tuple[str, str]:
        """(fails, uncertain) of an assertion's token."""
        expr = self.expr(token)
        return or_(expr.raises, not_(expr.truth)), expr.uncertain

    def expr(self, token: Any) -> Expr:
        symbol = token.symbol
        children = list(token)
        handler = _HANDLERS.get(symbol)
        if handler is not None:
            return handler(self, token, children)
        if symbol in _GENERAL or symbol in _VALUE:
            return self._comparison(symbol, children)
        raise Untranslatable(f"'{symbol}'")

    # -- paths ---------------------------------------------------------------------

    def _name(self, token: Any, _children: list[Any]) -> Expr:
        return self._child_step(Expr("elements", ".", owner=self.xsd_type), token)

    def _child_step(self, base: Expr, token: Any) -> Expr:
        name = str(token.value or "")
        if not name or ":" in name or "{" in name:
            raise Untranslatable(f"the name {name!r}")
        if base.text is None:
            return base
        owner = self._child_types(base.owner, name)
        text = name if base.text == "." else f"{base.text}/{name}"
        depth = None if base.depth is None else base.depth + 1
        return Expr("elements", text, base.raises, base.uncertain, depth, owner=owner)

    def _child_types(self, owners: Any, name: str) -> tuple[Any, ...]:
        """The types an element ``name`` below one of type ``owners`` may have (its
        declared type and those of its type alternatives; empty: unknown)."""
        if self.model is None:
            return ()
        found: list[Any] = []
        for owner in owners if isinstance(owners, tuple) else (owners,):
            declaration = self.model.children(owner).get(name)
            if declaration is None:
                return ()
            found.extend((declaration.type, *(a.type for a in declaration.alternatives)))
        return tuple(found)

    def _attribute(self, token: Any, children: list[Any]) -> Expr:
        return self._attribute_step(Expr("elements", ".", owner=self.xsd_type), children)

    def _attribute_step(self, base: Expr, children: list[Any]) -> Expr:
        if len(children) != 1 or children[0].symbol != "(name)":
            raise Untranslatable("an attribute wildcard")
        name = str(children[0].value or "")
        if not name or ":" in name or "{" in name:
            raise Untranslatable(f"the attribute name {name!r}")
        if base.text is None:
            return Expr("attributes", None)
        text = f"@{name}" if base.text == "." else f"{base.text}/@{name}"
        xsd_type = _attribute_type(base.owner, name)
        return Expr("attributes", text, base.raises, base.uncertain, None, xsd_type)

    def _context(self, _token: Any, _children: list[Any]) -> Expr:
        return Expr("elements", ".", owner=self.xsd_type)

    def _parent(self, _token: Any, children: list[Any]) -> Expr:
        return self._parent_step(Expr("elements", ".", owner=self.xsd_type), children)

    @staticmethod
    def _parent_step(base: Expr, children: list[Any]) -> Expr:
        if len(children) != 1 or children[0].symbol != "*":
            raise Untranslatable("a parent step other than parent::*")
        if base.text is None or base.depth == 0:
            # the assertion's tree is rooted at its element: it has no parent
            return Expr("elements", None, base.raises, base.uncertain)
        if base.depth is None:
            raise Untranslatable("parent::* below a descendant step")
        text = f"{base.text}/.." if base.text != "." else ".."
        return Expr("elements", text, base.raises, base.uncertain, base.depth - 1)

    def _slash(self, _token: Any, children: list[Any]) -> Expr:
        if len(children) != 2:
            raise Untranslatable("a path from the document root")
        base = self.expr(children[0])
        if base.kind != "elements":
            raise Untranslatable("a step after something that is not an element")
        step = children[1]
        if step.symbol == "(name)":
            return self._child_step(base, step)
        if step.symbol == "@":
            return self._attribute_step(base, list(step))
        if step.symbol == "parent":
            return self._parent_step(base, list(step))
        if step.symbol == ".":
            return base
        raise Untranslatable(f"the step '{step.symbol}'")

    def _descendants(self, _token: Any, children: list[Any]) -> Expr:
        if len(children) != 2 or children[1].symbol != "(name)":
            raise Untranslatable("a descendant step other than a name")
        base = self.expr(children[0])
        if base.kind != "elements":
            raise Untranslatable("a step after something that is not an element")
        name = str(children[1].value or "")
        if not name or ":" in name or "{" in name:
            raise Untranslatable(f"the name {name!r}")
        if base.text is None:
            return base
        return Expr("elements", f"{base.text}//{name}", base.raises, base.uncertain, None)

    # -- functions, operators --------------------------------------------------------

    def _group(self, _token: Any, children: list[Any]) -> Expr:
        if len(children) != 1:
            raise Untranslatable("a sequence")
        inner = self.expr(children[0])
        if inner.text is None or inner.kind in ("elements", "attributes"):
            return inner
        return Expr(inner.kind, f"({inner.text})", inner.raises, inner.uncertain)

    def _constant(self, token: Any, children: list[Any]) -> Expr:
        if children:
            raise Untranslatable(f"{token.symbol}() with arguments")
        return Expr("boolean", TRUE if token.symbol == "true" else FALSE)

    def _not(self, _token: Any, children: list[Any]) -> Expr:
        inner = self._one_argument(children)
        return Expr("boolean", not_(inner.truth), inner.raises, inner.uncertain)

    def _exists(self, token: Any, children: list[Any]) -> Expr:
        inner = self._nodes_argument(children)
        truth = inner.truth if token.symbol == "exists" else not_(inner.truth)
        return Expr("boolean", truth, inner.raises, inner.uncertain)

    def _count(self, _token: Any, children: list[Any]) -> Expr:
        inner = self._nodes_argument(children)
        text = "0" if inner.text is None else f"count({inner.text})"
        return Expr("number", text, inner.raises, inner.uncertain)

    def _name_of(self, _token: Any, children: list[Any]) -> Expr:
        inner = self._nodes_argument(children)
        if inner.text is None:
            return Expr("string", "''", inner.raises, inner.uncertain)
        # XPath 2.0's name() takes at most one node; XPath 1.0's takes the first
        several = (
            FALSE
            if inner.depth is not None and inner.text.endswith("..")
            else (f"count({inner.text}) > 1")
        )
        return Expr("string", f"name({inner.text})", or_(inner.raises, several), inner.uncertain)

    def _and_or(self, token: Any, children: list[Any]) -> Expr:
        left, right = (self.expr(child) for child in children)
        if token.symbol == "and":
            truth = and_(left.truth, right.truth)
            # the right side is evaluated only when the left one holds
            raises = or_(left.raises, and_(left.truth, right.raises))
        else:
            truth = or_(left.truth, right.truth)
            raises = or_(left.raises, and_(not_(left.truth), right.raises))
        return Expr("boolean", truth, raises, or_(left.uncertain, right.uncertain))

    def _if(self, _token: Any, children: list[Any]) -> Expr:
        if len(children) != 3:
            raise Untranslatable("an incomplete if")
        test, then, other = (self.expr(child) for child in children)
        truth = or_(and_(test.truth, then.truth), and_(not_(test.truth), other.truth))
        if other.truth == TRUE:
            truth = or_(not_(test.truth), then.truth)
        raises = or_(
            test.raises, and_(test.truth, then.raises), and_(not_(test.truth), other.raises)
        )
        uncertain = or_(test.uncertain, then.uncertain, other.uncertain)
        return Expr("boolean", truth, raises, uncertain)

    def _literal(self, token: Any, _children: list[Any]) -> Expr:
        if token.symbol == "(string)":
            return Expr("string", _literal(str(token.value)))
        value = token.value
        if isinstance(value, bool) or not isinstance(value, int):
            raise Untranslatable("a literal that is not an integer")
        return Expr("number", str(value))

    def _one_argument(self, children: list[Any]) -> Expr:
        if len(children) != 1:
            raise Untranslatable("a function with other than one argument")
        return self.expr(children[0])

    def _nodes_argument(self, children: list[Any]) -> Expr:
        inner = self._one_argument(children)
        if inner.kind not in ("elements", "attributes"):
            raise Untranslatable("a function of values that are not nodes")
        return inner

    def _comparison(self, symbol: str, children: list[Any]) -> Expr:
        if len(children) != 2:
            raise Untranslatable(f"'{symbol}' without two operands")
        distinct = _distinct_count(self, symbol, children)
        if distinct is not None:
            return distinct
        left, right = (self.expr(child) for child in children)
        operator = _GENERAL.get(symbol) or _VALUE[symbol]
        if left.kind not in ("attributes", "elements") and right.kind in ("attributes", "elements"):
            left, right, operator = right, left, _FLIPPED[operator]
        raises = or_(left.raises, right.raises)
        uncertain = or_(left.uncertain, right.uncertain)
        if left.kind == right.kind == "number" or (
            left.kind == right.kind == "string" and operator in ("=", "!=")
        ):
            return Expr("boolean", f"{left.text} {operator} {right.text}", raises, uncertain)
        if left.kind == "attributes":
            return _attribute_comparison(left, operator, right, symbol in _VALUE, raises, uncertain)
        raise Untranslatable(f"a comparison of {left.kind} with {right.kind}")


def _attribute_comparison(
    nodes: Expr, operator: str, value: Expr, single: bool, raises: str, uncertain: str
) -> Expr:
    """``nodes operator value`` for attributes typed by the schema and a literal."""
    if nodes.text is None:
        return Expr("boolean", FALSE, raises, uncertain)
    if value.kind not in ("string", "number", "boolean"):
        raise Untranslatable(f"a comparison of attributes with {value.kind}")
    if single:  # a value comparison takes one value at most
        raises = or_(raises, f"count({nodes.text}) > 1")
    primitive = _primitive(nodes.xsd_type)
    if primitive == "string" and value.kind == "string":
        if operator not in ("=", "!="):
            raise Untranslatable("strings compared by order")
        truth = f"{nodes.text} {operator} {value.text}"
        if nodes.xsd_type.white_space != "preserve":  # a value of blanks it collapses
            uncertain = or_(uncertain, f"{nodes.text}[. != normalize-space(.)]")
        return Expr("boolean", truth, raises, uncertain)
    if primitive == "string" and value.kind == "boolean":
        # XSD 1.1 reads the attribute as its type says, a string, and a string compared
        # with a boolean raises XPTY0004, whatever it holds ('true' included)
        return Expr("boolean", FALSE, or_(raises, f"boolean({nodes.text})"), uncertain)
    if (
        _builtin(nodes.xsd_type) in _NUMERIC_BUILTINS
        and value.kind == "number"
        and value.text == "0"
    ):
        # with 0, any plain numeral compares the same read by XPath 1.0 or as xs:double;
        # numerals of other shapes (and nonsense, which raises) go to xmlschema
        truth = f"boolean({nodes.text}[{_PLAIN_NUMBER} and number(.) {operator} 0])"
        return Expr("boolean", truth, raises, or_(uncertain, f"{nodes.text}[not({_PLAIN_NUMBER})]"))
    shown = _builtin(nodes.xsd_type) or "untyped"
    raise Untranslatable(f"a comparison of {shown} attributes with {value.kind} {value.text}")


def _distinct_count(translator: Translator, symbol: str, children: list[Any]) -> Expr | None:
    """``count(E/@a) = count(distinct-values(E/@a))``: no ``E`` has an earlier sibling
    ``E`` with the same ``@a`` (for ``E`` one child step and ``@a`` a string kept as
    written)."""
    if symbol not in ("=", "eq"):
        return None
    left, right = children
    if right.symbol == "count" and left.symbol == "count":
        inner = list(right)
        if len(inner) == 1 and inner[0].symbol == "distinct-values":
            counted = translator.expr(left[0])
            distinct = translator.expr(inner[0][0])
            if counted != distinct or counted.kind != "attributes" or counted.text is None:
                raise Untranslatable("distinct-values of another sequence than is counted")
            element, _, attribute = counted.text.rpartition("/@")
            if not element or "/" in element or element == ".":
                raise Untranslatable("distinct-values beyond one child step")
            if (
                _primitive(counted.xsd_type) != "string"
                or counted.xsd_type.white_space != "preserve"
            ):
                raise Untranslatable("distinct-values of values that are not plain strings")
            test = f"not({element}[@{attribute} = preceding-sibling::{element}/@{attribute}])"
            many = f"count({element}) > {_MAX_DISTINCT}"
            return Expr("boolean", test, counted.raises, or_(counted.uncertain, many))
    return None


_HANDLERS: Final = {
    "(name)": Translator._name,
    "@": Translator._attribute,
    ".": Translator._context,
    "parent": Translator._parent,
    "/": Translator._slash,
    "//": Translator._descendants,
    "(": Translator._group,
    "true": Translator._constant,
    "false": Translator._constant,
    "not": Translator._not,
    "exists": Translator._exists,
    "empty": Translator._exists,
    "count": Translator._count,
    "name": Translator._name_of,
    "and": Translator._and_or,
    "or": Translator._and_or,
    "if": Translator._if,
    "(string)": Translator._literal,
    "(integer)": Translator._literal,
}


def _builtin(xsd_type: Any) -> str | None:
    """The built-in type ``xsd_type`` restricts (``double`` for ``t_grEqZero``)."""
    for _ in range(32):
        if xsd_type is None:
            return None
        name = str(getattr(xsd_type, "name", "") or "")
        if name.startswith("{http://www.w3.org/2001/XMLSchema}"):
            return name.rpartition("}")[2]
        xsd_type = getattr(xsd_type, "base_type", None)
    return None


def _primitive(xsd_type: Any) -> str | None:
    primitive = getattr(xsd_type, "primitive_type", None)
    name = getattr(primitive, "local_name", None)
    return str(name) if name else None


def _attribute_type(owners: Any, name: str) -> Any:
    """The simple type of attribute ``name`` of elements of type ``owners``, if every one
    reads it alike (same primitive type and blanks); ``None`` otherwise."""
    found = None
    for owner in owners if isinstance(owners, tuple) else (owners,):
        attributes = getattr(owner, "attributes", None)
        attribute = attributes.get(name) if attributes is not None else None
        xsd_type = getattr(attribute, "type", None)
        if xsd_type is None:
            return None
        if found is not None and (
            _primitive(found) != _primitive(xsd_type)
            or getattr(found, "white_space", None) != getattr(xsd_type, "white_space", None)
        ):
            return None
        found = xsd_type
    return found


# -- the whole set ----------------------------------------------------------------------


@dataclass
class Translation:
    """A set's assertions and type alternatives in XPath 1.0, as the manifest keeps it."""

    types: list[dict[str, Any]] = field(default_factory=list)
    """Per asserted type: ``type``, ``paths`` and ``assertions`` (each ``test`` with
    ``fails`` and ``uncertain``, or ``why`` it does not translate)."""
    marks: list[dict[str, str]] | None = field(default_factory=list)
    """Per type an alternative selects: ``path`` (with the alternative's test) and
    ``type``; ``None`` when the alternatives do not translate."""
    why_not_marks: str = ""

    def as_json(self) -> dict[str, Any]:
        return {"types": self.types, "marks": self.marks, "why_not_marks": self.why_not_marks}


def translate_set(schema: Any) -> Translation:
    """The XPath 1.0 form of every assertion and type alternative of ``schema`` (an
    ``xmlschema.XMLSchema11``)."""
    translation = Translation()
    try:
        model = SchemaModel(schema)
    except NeedsFull as why:  # the set is validated in full: nothing to translate
        translation.marks = None
        translation.why_not_marks = str(why)
        for xsd_type in _asserted_types(schema):
            translation.types.append(_untranslated(xsd_type, str(why)))
        return translation
    try:
        paths, marks = _element_paths(schema, model)
    except Untranslatable as why:
        translation.marks = None
        translation.why_not_marks = str(why)
        for xsd_type in _asserted_types(schema):
            translation.types.append(_untranslated(xsd_type, f"its elements: {why}"))
        return translation
    translation.marks = marks
    for xsd_type, type_paths in paths:
        if not getattr(xsd_type, "local_name", None):
            # assertions are told apart by type name and test: an anonymous type has none
            translation.types.append(_untranslated(xsd_type, "an anonymous type"))
            continue
        entry: dict[str, Any] = {
            "type": str(xsd_type.local_name),
            "paths": type_paths,
            "assertions": [],
        }
        translator = Translator(xsd_type, model)
        for assertion in xsd_type.assertions:
            try:
                fails, uncertain = translator.assertion(assertion.token)
            except Untranslatable as why:
                entry["assertions"].append({"test": assertion.path, "why": str(why)})
                continue
            entry["assertions"].append(
                {"test": assertion.path, "fails": fails, "uncertain": uncertain}
            )
        translation.types.append(entry)
    return translation


def _untranslated(xsd_type: Any, why: str) -> dict[str, Any]:
    return {
        "type": str(getattr(xsd_type, "local_name", "") or ""),
        "paths": [],
        "assertions": [{"test": a.path, "why": why} for a in xsd_type.assertions],
    }


def _asserted_types(schema: Any) -> list[Any]:
    seen: dict[int, Any] = {}
    for xsd_type in schema.maps.types.values():
        if getattr(xsd_type, "assertions", None):
            seen.setdefault(id(xsd_type), xsd_type)
    return list(seen.values())


def _element_paths(
    schema: Any, model: SchemaModel
) -> tuple[list[tuple[Any, list[str]]], list[dict[str, str]]]:
    """Each asserted type with the XPath 1.0 paths of the elements it governs, and the
    type marks of the alternatives: walked down from the global elements through the
    declared children that can hold either, as the assertion plan walks a document."""
    if schema.target_namespace:
        raise Untranslatable("a target namespace")
    asserted: dict[int, tuple[Any, list[str]]] = {}
    marks: list[dict[str, str]] = []
    pending: list[tuple[str, Any, frozenset[int]]] = [
        ("", declaration, frozenset()) for declaration in schema.elements.values()
    ]
    while pending:
        above, declaration, seen = pending.pop()
        if id(declaration) in seen:
            raise Untranslatable("elements that hold themselves")
        seen = seen | {id(declaration)}
        if declaration.name != declaration.local_name:
            raise Untranslatable("an element of a namespace")
        path = f"{above}/{declaration.local_name}"
        for predicate, xsd_type in _governing(declaration):
            here = path + predicate
            if xsd_type is not declaration.type:
                marks.append({"path": here, "type": _type_name(xsd_type)})
            if getattr(xsd_type, "assertions", None):
                found = asserted.setdefault(id(xsd_type), (xsd_type, []))[1]
                found.append(here)
                if len(found) > _MAX_PATHS:
                    raise Untranslatable(f"more than {_MAX_PATHS} paths to one type")
            for child in model.children(xsd_type).values():
                if model.declaration_interesting(child):
                    pending.append((here, child, seen))
    return sorted(asserted.values(), key=lambda item: item[1][0]), marks


def _governing(declaration: Any) -> list[tuple[str, Any]]:
    """(predicate, type) for each type the declaration's elements may be validated by:
    the alternatives in order (each test true and every earlier one false), then the
    declared type where none applies."""
    if not declaration.alternatives:
        return [("", declaration.type)]
    governing: list[tuple[str, Any]] = []
    earlier: list[str] = []
    for alternative in declaration.alternatives:
        if alternative.token is None:  # the default: every element no test took
            governing.append((_predicate(and_(*map(not_, earlier))), alternative.type))
            return governing
        test = _alternative_test(alternative)
        governing.append((_predicate(and_(test, *map(not_, earlier))), alternative.type))
        earlier.append(test)
    governing.append((_predicate(and_(*map(not_, earlier))), declaration.type))
    return governing


def _alternative_test(alternative: Any) -> str:
    """An alternative's test: XSD 1.1 evaluates it on the element's attributes, untyped,
    and an error counts as false; translated are tests of attributes compared with
    strings, which neither raise nor read a value otherwise than XPath 1.0."""
    expr = _AlternativeTranslator(None, None).expr(alternative.token)
    if expr.raises != FALSE or expr.uncertain != FALSE:
        raise Untranslatable(f"the type alternative test {alternative.path!r}")
    return expr.truth


class _AlternativeTranslator(Translator):
    """An alternative's test sees the element's attributes as untyped text."""

    def _child_step(self, base: Expr, token: Any) -> Expr:
        raise Untranslatable("a type alternative test that reads children")

    def _comparison(self, symbol: str, children: list[Any]) -> Expr:
        left, right = (self.expr(child) for child in children)
        operator = _GENERAL.get(symbol)
        if left.kind == "string":
            left, right = right, left
        if (
            operator not in ("=", "!=")
            or left.kind != "attributes"
            or left.text is None
            or right.kind != "string"
            or "/" in left.text
        ):
            raise Untranslatable(f"the type alternative comparison '{symbol}'")
        return Expr("boolean", f"{left.text} {operator} {right.text}")


def _predicate(test: str) -> str:
    return "" if test == TRUE else f"[{test}]"


def _type_name(xsd_type: Any) -> str:
    name = getattr(xsd_type, "local_name", None)
    if not name:
        raise Untranslatable("a type alternative with an anonymous type")
    return str(name)
