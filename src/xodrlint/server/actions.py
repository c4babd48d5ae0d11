"""Hover text and code actions for xodrlint's diagnostics: the rule's summary and why it
matters, and the suppression comments the command line honours (:mod:`xodrlint.suppress`)."""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Final

from lsprotocol import types

from xodrlint.registry import Registry
from xodrlint.server.convert import SOURCE

_WHY: Final = re.compile(r"^## Why is this bad\?\s*$(?P<body>.*?)(?=^## |\Z)", re.M | re.S)
_INDENT: Final = re.compile(r"[ \t]*")
_DECLARATION: Final = re.compile(r"\s*<\?xml[^>]*\?>")


def hover_text(registry: Registry, codes: Sequence[str]) -> str | None:
    """Markdown for the rules behind the diagnostics under the cursor."""
    parts = []
    for code in dict.fromkeys(codes):
        rule = registry.by_code.get(code)
        if rule is None:
            continue
        meta = rule.meta
        why = _WHY.search(meta.doc)
        text = f"**{meta.code}** {meta.name}: {meta.summary}"
        if why and why.group("body").strip():
            text += "\n\n**Why is this bad?**\n\n" + why.group("body").strip()
        parts.append(text)
    return "\n\n---\n\n".join(parts) or None


def covers(item: types.Range, at: types.Position) -> bool:
    start, end = item.start, item.end
    return (start.line, start.character) <= (at.line, at.character) <= (end.line, end.character)


def _insert(uri: str, line: int, text: str) -> types.WorkspaceEdit:
    position = types.Position(line, 0)
    return types.WorkspaceEdit(
        changes={uri: [types.TextEdit(types.Range(position, position), text)]}
    )


def _here(uri: str, lines: Sequence[str], code: str, line: int) -> types.CodeAction:
    """``<!-- xodrlint: ignore[CODE] -->`` on its own line right before the element, at the
    element's own indentation."""
    current = lines[line] if line < len(lines) else ""
    indent = _INDENT.match(current)
    text = f"{indent.group() if indent else ''}<!-- xodrlint: ignore[{code}] -->\n"
    return types.CodeAction(
        title=f"Suppress {code} here",
        kind=types.CodeActionKind.QuickFix,
        edit=_insert(uri, line, text),
    )


def _file(uri: str, source: str, code: str) -> types.CodeAction:
    """``<!-- xodrlint: ignore-file[CODE] -->`` after the XML declaration (nothing may come
    before that), else on the first line."""
    declaration = _DECLARATION.match(source)
    line = source.count("\n", 0, declaration.end()) + 1 if declaration else 0
    return types.CodeAction(
        title=f"Suppress {code} in this file",
        kind=types.CodeActionKind.QuickFix,
        edit=_insert(uri, line, f"<!-- xodrlint: ignore-file[{code}] -->\n"),
    )


def code_actions(
    uri: str, source: str, diagnostics: Sequence[types.Diagnostic]
) -> list[types.CodeAction]:
    lines = source.split("\n")
    actions: list[types.CodeAction] = []
    for item in diagnostics:
        if item.source != SOURCE or not isinstance(item.code, str):
            continue
        for action in (
            _here(uri, lines, item.code, item.range.start.line),
            _file(uri, source, item.code),
        ):
            action.diagnostics = [item]
            actions.append(action)
    return actions
