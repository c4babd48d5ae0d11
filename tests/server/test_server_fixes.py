"""The editor's fixes: each finding's fix as a quick fix on its diagnostic (a safe one
preferred), and ``source.fixAll.xodrlint`` making every safe fix as ``check --fix``
does; the document then lints clean for those codes."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("pygls", reason="the server extra (pygls) is not installed")
pytest.importorskip("pytest_lsp", reason="pytest-lsp is not installed")

from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.server.test_server import (
    EXAMPLE,
    REPO,
    _change,
    _open,
    _published,
    client,
)

__all__ = ["client"]


def _applied(text: str, edits: list[types.TextEdit]) -> str:
    """``edits`` made on ``text`` (ASCII, so characters are UTF-16 units), last first."""
    lines = text.splitlines(keepends=True)
    starts = [0]
    for line in lines:
        starts.append(starts[-1] + len(line))

    def offset(position: types.Position) -> int:
        return starts[position.line] + position.character

    for edit in sorted(edits, key=lambda e: offset(e.range.start), reverse=True):
        text = text[: offset(edit.range.start)] + edit.new_text + text[offset(edit.range.end) :]
    return text


def _edits(action: types.CodeAction, path: Path, version: int) -> list[types.TextEdit]:
    """The action's edits of ``path``: versioned, as a client that takes them is sent."""
    assert action.edit is not None and action.edit.document_changes is not None
    (change,) = action.edit.document_changes
    assert isinstance(change, types.TextDocumentEdit)
    assert (change.text_document.uri, change.text_document.version) == (path.as_uri(), version)
    return [edit for edit in change.edits if isinstance(edit, types.TextEdit)]


async def _actions(
    client: LanguageClient, path: Path, diagnostics: list[types.Diagnostic], only: list[str] | None
) -> list[types.CodeAction]:
    everything = types.Range(types.Position(0, 0), types.Position(0, 0))
    found = await client.text_document_code_action_async(
        types.CodeActionParams(
            types.TextDocumentIdentifier(path.as_uri()),
            diagnostics[0].range if diagnostics else everything,
            types.CodeActionContext(diagnostics=diagnostics, only=only),
        )
    )
    return [action for action in found or [] if isinstance(action, types.CodeAction)]


@pytest.mark.asyncio
async def test_a_quick_fix_mends_its_finding(client: LanguageClient, tmp_path: Path) -> None:
    path = tmp_path / "a.xodr"
    found = await _open(client, path, EXAMPLE)
    partner = next(d for d in found if d.code == "PT003")
    actions = await _actions(client, path, [partner], None)
    fix = actions[0]  # the fix comes first, before the suppressions
    assert fix.title.startswith("Fix PT003: name the partner") and fix.is_preferred
    assert fix.kind == types.CodeActionKind.QuickFix
    fixed = _applied(EXAMPLE, _edits(fix, path, 1))
    _change(client, path, 2, fixed)
    assert "PT003" not in [d.code for d in (await _published(client)).diagnostics]


@pytest.mark.asyncio
async def test_fix_all_makes_every_safe_fix_as_the_command_line_does(
    client: LanguageClient, tmp_path: Path
) -> None:
    source = (REPO / "rules" / "PT003" / "invalid_name_mismatch.xodr").read_text("utf-8")
    expected = (REPO / "rules" / "PT003" / "invalid_name_mismatch.fixed.xodr").read_text("utf-8")
    path = tmp_path / "b.xodr"
    await _open(client, path, source)
    (action,) = await _actions(client, path, [], ["source.fixAll.xodrlint"])
    assert action.kind == "source.fixAll.xodrlint"
    fixed = _applied(source, _edits(action, path, 1))
    assert fixed == expected
    _change(client, path, 2, fixed)
    assert "PT003" not in [d.code for d in (await _published(client)).diagnostics]
    # a clean document: no action
    assert await _actions(client, path, [], ["source.fixAll.xodrlint"]) == []


@pytest.mark.asyncio
async def test_a_fix_of_an_older_text_is_not_offered(
    client: LanguageClient, tmp_path: Path
) -> None:
    path = tmp_path / "c.xodr"
    found = await _open(client, path, EXAMPLE)
    partner = next(d for d in found if d.code == "PT003")
    # the text changes; its lint has not come back yet
    _change(client, path, 2, "\n" + EXAMPLE)
    actions = await _actions(client, path, [partner], None)
    assert not any(action.title.startswith("Fix") for action in actions)
    await _published(client)
