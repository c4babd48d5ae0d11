"""The rule API's reference in docs/plugins.md, generated from ``xodrlint.rules``.

Every name a pack may import (``xodrlint.rules.__all__`` and
``xodrlint.rules.geometry.__all__``), and every field, property and method of the types
a rule reads, with its type as the source writes it and the
first paragraph of its docstring. The model's types come in the order a rule meets
them, from :class:`~xodrlint.model.RailNetwork` down. ``python -m xodrlint.devtools.docgen``
writes it between the page's markers; tests/test_docs.py fails when it is stale.
"""

from __future__ import annotations

import ast
import inspect
import re
import textwrap
from collections.abc import Iterator
from pathlib import Path
from typing import Final, NamedTuple

BEGIN: Final = "<!-- begin generated: the rule API (python -m xodrlint.devtools.docgen) -->"
END: Final = "<!-- end generated -->"
PAGE: Final = Path("docs") / "plugins.md"
_IDENTIFIER: Final = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_QUOTED: Final = re.compile(r"'([A-Za-z_][A-Za-z0-9_.]*)'")
_ROLE: Final = re.compile(r":(?:class|func|meth|attr|data|mod):`~?([^`]+)`")


class Member(NamedTuple):
    """One row of a type's table: ``roads``, ``shared(kind)``."""

    name: str
    type: str
    doc: str


def reference() -> str:
    """The generated part of docs/plugins.md, markers included."""
    import xodrlint.rules as api

    types = {
        name: getattr(api, name) for name in api.__all__ if inspect.isclass(getattr(api, name))
    }
    model = _reading_order(
        {name: kind for name, kind in types.items() if kind.__module__.startswith("xodrlint.model")}
    )
    others = [name for name in api.__all__ if name not in types]
    version = ".".join(map(str, api.API_VERSION))
    lines = [BEGIN, "", f"### Rule API {version}: the names", ""]
    lines += ["Import them from `xodrlint.rules`; nothing else is part of the rule API.", ""]
    lines += ["| Name | What it is |", "|------|------------|"]
    lines += [
        f"| `{name}` | {_summary(api, name)} |" for name in sorted(api.__all__, key=str.lower)
    ]
    lines += ["", "### The rule API's types", ""]
    for name in ("Hit", "RuleOption", "Severity"):
        lines += _type_section(name, types[name])
    lines += ["### The model a rule reads", ""]
    lines += [
        "What `RailNetwork` holds, type by type. `element` is always the lxml element a value "
        "was read from (what a `Hit` points at); an attribute the file leaves out, or writes "
        "so that it cannot be read, is `None` (the schema rule reports it).",
        "",
    ]
    for name, kind in model.items():
        lines += _type_section(name, kind)
    lines += ["### Functions and constants", ""]
    for name in others:
        lines += [f"- `{name}{_signature(getattr(api, name))}`: {_summary(api, name)}"]
    return "\n".join([*lines, "", *_geometry(), END])


def _geometry() -> list[str]:
    """The section of :mod:`xodrlint.rules.geometry`: its types, then its functions."""
    from xodrlint.rules import geometry

    doc = inspect.getdoc(geometry) or ""
    lines = ["### The track geometry: `xodrlint.rules.geometry`", "", _first_paragraph(doc), ""]
    lines += [_first_paragraph(doc.split("\n\n", 1)[1]), ""] if "\n\n" in doc else []
    names = geometry.__all__
    for name in names:
        value = getattr(geometry, name)
        if inspect.isclass(value):
            lines += _type_section(name, value)
    lines += ["#### Functions", ""]
    for name in names:
        value = getattr(geometry, name)
        if not inspect.isclass(value):
            lines += [f"- `{name}{_signature(value)}`: {_summary(geometry, name)}"]
    return [*lines, ""]


def replace_section(page: str) -> str:
    """``page`` with its generated part brought up to date."""
    start, end = page.index(BEGIN), page.index(END) + len(END)
    return page[:start] + reference() + page[end:]


def _reading_order(kinds: dict[str, type]) -> dict[str, type]:
    """The model's types from ``RailNetwork`` on, each after the first type naming it in
    an annotation; any never named come last, by name."""
    order: list[str] = []
    queue = ["RailNetwork"]
    while queue:
        name = queue.pop(0)
        if name in order or name not in kinds:
            continue
        order.append(name)
        for member in _members(kinds[name]):
            queue += [word for word in _IDENTIFIER.findall(member.type) if word in kinds]
    order += sorted(set(kinds) - set(order))
    return {name: kinds[name] for name in order}


def _type_section(name: str, kind: type) -> list[str]:
    lines = [f"#### `{name}`", "", _first_paragraph(inspect.getdoc(kind) or ""), ""]
    if issubclass(kind, str):  # an enumeration of strings: its members
        members = ", ".join(f"`{member.name}` (`{member.value}`)" for member in kind)  # type: ignore[attr-defined]
        return [*lines, f"Members: {members}.", ""]
    lines += ["| Member | Type | Meaning |", "|--------|------|---------|"]
    lines += [f"| `{m.name}` | `{_cell(m.type)}` | {m.doc} |" for m in _members(kind)]
    return [*lines, ""]


def _members(kind: type) -> Iterator[Member]:
    """The public fields, properties and methods ``kind``'s own source declares."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(kind)))
    body = tree.body[0].body  # type: ignore[attr-defined]
    fields = [statement for statement in body if isinstance(statement, ast.AnnAssign)]
    for index, statement in enumerate(body):
        if isinstance(statement, ast.AnnAssign) and isinstance(statement.target, ast.Name):
            name = statement.target.id
            if not name.startswith("_"):
                after = body[index + 1] if index + 1 < len(body) else None
                yield Member(name, _annotation(statement.annotation), _string(after))
        elif isinstance(statement, ast.FunctionDef):
            if statement.name == "__init__" and not fields:
                yield from _constructor_fields(statement, kind)
            elif not statement.name.startswith("_"):
                yield _method(statement)


def _constructor_fields(init: ast.FunctionDef, kind: type) -> Iterator[Member]:
    """A plain class's attributes: the arguments of its constructor it keeps as is."""
    slots = getattr(kind, "__slots__", ())
    for argument in init.args.args[1:]:
        if argument.arg in slots and argument.annotation is not None:
            yield Member(argument.arg, _annotation(argument.annotation), "")


def _method(function: ast.FunctionDef) -> Member:
    returns = _annotation(function.returns) if function.returns is not None else "None"
    doc = _first_paragraph(ast.get_docstring(function) or "")
    # read as attributes: a property, and a cached one (functools.cached_property)
    if any(
        isinstance(d, ast.Name) and d.id in ("property", "cached_property")
        for d in function.decorator_list
    ):
        return Member(function.name, returns, doc)
    parameters = ", ".join(argument.arg for argument in function.args.args[1:])
    return Member(f"{function.name}({parameters})", returns, doc)


def _annotation(node: ast.expr) -> str:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value  # a quoted annotation, as the reader would write it
    return _QUOTED.sub(r"\1", ast.unparse(node))  # tuple['RoadLink', ...]


def _cell(text: str) -> str:
    """``text`` in a table cell: a bar would end the cell, even in code."""
    return text.replace("|", "\\|")


def _string(statement: ast.stmt | None) -> str:
    """An attribute's docstring: the string statement after it, if any."""
    if isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant):
        value = statement.value.value
        if isinstance(value, str):
            return _first_paragraph(value)
    return ""


def _first_paragraph(text: str) -> str:
    """The first paragraph of a docstring, as Markdown on one line: ``code`` and Sphinx's
    roles (:class:`~a.B`) become `code`."""
    paragraph = " ".join(inspect.cleandoc(text).split("\n\n", 1)[0].split())
    paragraph = _ROLE.sub(lambda m: f"`{m[1].rpartition('.')[2]}`", paragraph)
    return _cell(paragraph.replace("``", "`"))


def _summary(api: object, name: str) -> str:
    value = getattr(api, name)
    if name == "Settings":
        return "Option values by option name, as a rule with options receives them."
    if isinstance(value, tuple | frozenset | str | int | float):
        shown = sorted(value) if isinstance(value, frozenset) else value
        return f"`{shown!r}`"
    doc = inspect.getdoc(value) if inspect.isclass(value) or inspect.isfunction(value) else ""
    return _first_paragraph(doc or "")


def _signature(value: object) -> str:
    if not inspect.isfunction(value):
        return ""
    return "(" + ", ".join(inspect.signature(value).parameters) + ")"
