"""Hover text and code actions for xodrlint's diagnostics: the rule's summary and why it
matters, and the suppression comments the command line honours
(:mod:`xodrlint.engine.suppressions`)."""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Final

from lsprotocol import types

from xodrlint.rules.registry import Registry
from xodrlint.server.convert import SOURCE

_INDENT: Final = re.compile(r"[ \t]*")
_DECLARATION: Final = re.compile(r"\s*<\?xml[^>]*\?>")
#: The code of a file that is not well-formed, which no comment in it can withhold.
UNPARSED: Final = "XS001"


def hover_text(registry: Registry, codes: Sequence[str]) -> str | None:
    """Markdown for the rules behind the diagnostics under the cursor."""
    parts = []
    for code in dict.fromkeys(codes):
        rule = registry.by_code.get(code)
        if rule is None:
            continue
        meta = rule.meta
        why = meta.section("Why is this bad?")
        text = f"**{meta.code}** {meta.name}: {meta.summary}"
        if why:
            text += "\n\n**Why is this bad?**\n\n" + why
        parts.append(text)
    return "\n\n---\n\n".join(parts) or None


def covers(item: types.Range, at: types.Position) -> bool:
    start, end = item.start, item.end
    return (start.line, start.character) <= (at.line, at.character) <= (end.line, end.character)


def _insert(uri: str, position: types.Position, text: str) -> types.WorkspaceEdit:
    return types.WorkspaceEdit(
        changes={uri: [types.TextEdit(types.Range(position, position), text)]}
    )


def _here(uri: str, lines: Sequence[str], code: str, at: types.Position) -> types.CodeAction:
    """``<!-- xodrlint: ignore[CODE] -->`` right before the element: on a line of its own at
    the element's indentation, or just before its ``<`` where other markup precedes it on
    its line (a comment above that line would stand before another element)."""
    current = lines[at.line] if at.line < len(lines) else ""
    indent = _INDENT.match(current)
    comment = f"<!-- xodrlint: ignore[{code}] -->"
    lead = indent.group() if indent else ""
    if len(lead) >= at.character:
        edit = _insert(uri, types.Position(at.line, 0), f"{lead}{comment}\n")
    else:
        edit = _insert(uri, at, comment)
    return types.CodeAction(
        title=f"Suppress {code} here", kind=types.CodeActionKind.QuickFix, edit=edit
    )


def _file(uri: str, source: str, code: str) -> types.CodeAction:
    """``<!-- xodrlint: ignore-file[CODE] -->`` after the XML declaration (nothing may come
    before that), else on the first line."""
    declaration = _DECLARATION.match(source)
    line = source.count("\n", 0, declaration.end()) + 1 if declaration else 0
    return types.CodeAction(
        title=f"Suppress {code} in this file",
        kind=types.CodeActionKind.QuickFix,
        edit=_insert(uri, types.Position(line, 0), f"<!-- xodrlint: ignore-file[{code}] -->\n"),
    )


def code_actions(
    uri: str, source: str, diagnostics: Sequence[types.Diagnostic]
) -> list[types.CodeAction]:
    lines = source.split("\n")
    actions: list[types.CodeAction] = []
    for item in diagnostics:
        if item.source != SOURCE or not isinstance(item.code, str) or item.code == UNPARSED:
            continue  # a file that does not parse has no comments to read
        for action in (
            _here(uri, lines, item.code, item.range.start),
            _file(uri, source, item.code),
        ):
            action.diagnostics = [item]
            actions.append(action)
    return actions
