"""Hover text and code actions for xodrlint's diagnostics: the rule's summary and why it
matters, and the suppression comments the command line honours
(:mod:`xodrlint.engine.suppressions`)."""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Final

from lsprotocol import types

from xodrlint.document.edits import common_head, common_tail
from xodrlint.document.positions import LINE_BREAK
from xodrlint.rules.registry import Registry
from xodrlint.server.convert import SOURCE, units

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


#: The kind of the action that makes every safe fix of a document (as ruff's server
#: offers ``source.fixAll.ruff``); an editor runs it on save where asked to.
FIX_ALL: Final = "source.fixAll.xodrlint"


def code_actions(
    uri: str,
    source: str,
    diagnostics: Sequence[types.Diagnostic],
    published: Sequence[types.Diagnostic] | None = None,
    version: int | None = None,
) -> list[types.CodeAction]:
    """Each diagnostic's fix (where ``published``, the diagnostics of the text as it is
    now, has it: a fix of an older text would edit the wrong places), then its
    suppressions. With the text's ``version`` (a client that takes versioned edits), a fix
    says which text it is for, and the client refuses it on any other."""
    lines = source.split("\n")
    actions: list[types.CodeAction] = []
    for item in diagnostics:
        if item.source != SOURCE or not isinstance(item.code, str) or item.code == UNPARSED:
            continue  # a file that does not parse has no comments to read
        fix = _fix_action(uri, item, published, version)
        for action in (
            *((fix,) if fix is not None else ()),
            _here(uri, lines, item.code, item.range.start),
            _file(uri, source, item.code),
        ):
            action.diagnostics = [item]
            actions.append(action)
    return actions


def _fix_action(
    uri: str,
    item: types.Diagnostic,
    published: Sequence[types.Diagnostic] | None,
    version: int | None,
) -> types.CodeAction | None:
    """The quick fix of ``item``: its fix's edits, from the published diagnostic it is
    (never from what the client sends back, which a client may have kept from before)."""
    current = next(
        (
            known
            for known in published or ()
            if known.code == item.code
            and known.range == item.range
            and known.message == item.message
        ),
        None,
    )
    data = current.data if current is not None else None
    fix = data.get("fix") if isinstance(data, dict) else None
    if not isinstance(fix, dict):
        return None
    safe = fix["applicability"] == "safe"
    edits = [
        types.TextEdit(
            types.Range(
                types.Position(**edit["range"]["start"]), types.Position(**edit["range"]["end"])
            ),
            edit["newText"],
        )
        for edit in fix["edits"]
    ]
    title = f"Fix {item.code}: {fix['message']}" + ("" if safe else " (unsafe)")
    return types.CodeAction(
        title=title,
        kind=types.CodeActionKind.QuickFix,
        edit=workspace_edit(uri, edits, version),
        is_preferred=safe,
    )


def workspace_edit(
    uri: str, edits: list[types.TextEdit], version: int | None
) -> types.WorkspaceEdit:
    """``edits`` of ``uri``; for the text of ``version`` alone where one is given."""
    if version is None:
        return types.WorkspaceEdit(changes={uri: edits})
    document = types.OptionalVersionedTextDocumentIdentifier(version=version, uri=uri)
    return types.WorkspaceEdit(document_changes=[types.TextDocumentEdit(document, list(edits))])


def fix_all_action(
    uri: str, before: str, after: str, encoding: str, version: int | None = None
) -> types.CodeAction | None:
    """``source.fixAll.xodrlint``: the text ``before`` becomes ``after`` (the safe fixes
    made as ``check --fix`` makes them), as one edit of the run that differs; ``None``
    where nothing changes."""
    if before == after:
        return None
    head = common_head(before, after)
    if 0 < head < len(before) and before[head - 1 : head + 1] == "\r\n":
        head -= 1  # never between the two characters of one line break
    tail = common_tail(before, after, head)
    end = len(before) - tail
    if tail and 0 < end < len(before) and before[end - 1 : end + 1] == "\r\n":
        tail -= 1
    edit = types.TextEdit(
        types.Range(
            _position_at(before, head, encoding), _position_at(before, len(before) - tail, encoding)
        ),
        after[head : len(after) - tail],
    )
    return types.CodeAction(
        title="Fix all safe xodrlint findings",
        kind=FIX_ALL,
        edit=workspace_edit(uri, [edit], version),
    )


def _position_at(text: str, offset: int, encoding: str) -> types.Position:
    """Where ``offset`` of ``text`` is, as the protocol counts lines ("\\r\\n", "\\n" or a
    lone "\\r") and characters (the client's encoding)."""
    line_start = max(text.rfind("\n", 0, offset), text.rfind("\r", 0, offset)) + 1
    line = len(LINE_BREAK.findall(text, 0, line_start))
    return types.Position(line, units(text[line_start:offset], encoding))
