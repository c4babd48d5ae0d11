"""``xodrlint server`` end to end: pytest-lsp starts it as a subprocess and speaks LSP to
it over stdio, as an editor does."""

from __future__ import annotations

import os
import sys
from collections.abc import AsyncIterator
from pathlib import Path

import pytest

pytest.importorskip("pygls", reason="the server extra (pygls) is not installed")
pytest_lsp = pytest.importorskip("pytest_lsp", reason="pytest-lsp is not installed")

from lsprotocol import types  # noqa: E402
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = (REPO / "examples" / "two-findings.xodr").read_text("utf-8")
PUBLISH = types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS
ENV = {**os.environ, "PYTHONPATH": str(REPO / "src")}


# pytest-lsp's decorator is untyped
@pytest_lsp.fixture(  # type: ignore[untyped-decorator]
    config=ClientServerConfig(
        server_command=[sys.executable, "-m", "xodrlint", "server"], server_env=ENV
    )
)
async def client(lsp_client: LanguageClient, tmp_path: Path) -> AsyncIterator[None]:
    await lsp_client.initialize_session(
        types.InitializeParams(
            capabilities=client_capabilities("visual-studio-code"),
            root_uri=tmp_path.as_uri(),
        )
    )
    yield
    await lsp_client.shutdown_session()


async def _open(client: LanguageClient, path: Path, text: str) -> list[types.Diagnostic]:
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(types.TextDocumentItem(path.as_uri(), "xml", 1, text))
    )
    await client.wait_for_notification(PUBLISH)
    return list(client.diagnostics[path.as_uri()])


@pytest.mark.asyncio
async def test_diagnostics_on_open(client: LanguageClient, tmp_path: Path) -> None:
    found = await _open(client, tmp_path / "a.xodr", EXAMPLE)
    assert [(d.code, d.range.start.line) for d in found] == [("PT003", 25), ("ST004", 59)]
    partner = found[0]
    # line 26, column 9: `<partner` starts at character 8 and its name ends at 16
    assert partner.range == types.Range(types.Position(25, 8), types.Position(25, 16))
    assert partner.source == "xodrlint"
    assert partner.severity == types.DiagnosticSeverity.Warning
    assert partner.code_description is not None
    assert partner.code_description.href.endswith("/docs/rules/PT003.md")
    assert partner.related_information is not None
    assert partner.related_information[0].location.range.start.line == 27


def _change(client: LanguageClient, path: Path, version: int, text: str) -> None:
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            types.VersionedTextDocumentIdentifier(version=version, uri=path.as_uri()),
            [types.TextDocumentContentChangeWholeDocument(text)],
        )
    )


async def _published(client: LanguageClient) -> types.PublishDiagnosticsParams:
    params = await client.wait_for_notification(PUBLISH)
    assert isinstance(params, types.PublishDiagnosticsParams)
    return params


FIXED = EXAMPLE.replace('<partner name="W3"', '<partner name="W2"')


@pytest.mark.asyncio
async def test_edits_are_linted_once_typing_pauses(client: LanguageClient, tmp_path: Path) -> None:
    path = tmp_path / "a.xodr"
    await _open(client, path, EXAMPLE)
    # three keystrokes in quick succession: one lint, of the last text, after the pause
    _change(client, path, 2, EXAMPLE + " ")
    _change(client, path, 3, EXAMPLE + "  ")
    _change(client, path, 4, FIXED)
    params = await _published(client)
    assert params.version == 4
    assert [d.code for d in params.diagnostics] == ["ST004"]


@pytest.mark.asyncio
async def test_the_buffer_is_linted_not_the_file(client: LanguageClient, tmp_path: Path) -> None:
    path = tmp_path / "a.xodr"
    path.write_text(FIXED, "utf-8")  # on disk: one finding; in the editor: two
    assert [d.code for d in await _open(client, path, EXAMPLE)] == ["PT003", "ST004"]
    client.text_document_did_save(
        types.DidSaveTextDocumentParams(types.TextDocumentIdentifier(path.as_uri()))
    )
    assert [d.code for d in (await _published(client)).diagnostics] == ["PT003", "ST004"]


@pytest.mark.asyncio
async def test_a_file_not_well_formed_shows_only_xs001(
    client: LanguageClient, tmp_path: Path
) -> None:
    broken = EXAMPLE.replace("</station>", "")
    found = await _open(client, tmp_path / "a.xodr", broken)
    assert [d.code for d in found] == ["XS001"]
    assert found[0].severity == types.DiagnosticSeverity.Error


@pytest.mark.asyncio
async def test_columns_count_utf16_units_past_line_65535(
    client: LanguageClient, tmp_path: Path
) -> None:
    # a non-BMP character (two UTF-16 units) before the partner on its line, and the
    # line past what 16 bits count
    text = EXAMPLE.replace(
        '        <partner name="W3"', '<!-- \U0001f682 --><partner name="W3"'
    ).replace("<OpenDRIVE>", "\n" * 70_000 + "<OpenDRIVE>")
    found = await _open(client, tmp_path / "a.xodr", text)
    partner = next(d for d in found if d.code == "PT003")
    start = len("<!-- \U0001f682 -->") + 1  # the emoji is one code point, two units
    assert partner.range == types.Range(
        types.Position(70_025, start), types.Position(70_025, start + len("<partner"))
    )


@pytest.mark.asyncio
async def test_hover_explains_the_rule(client: LanguageClient, tmp_path: Path) -> None:
    path = tmp_path / "a.xodr"
    await _open(client, path, EXAMPLE)
    hover = await client.text_document_hover_async(
        types.HoverParams(types.TextDocumentIdentifier(path.as_uri()), types.Position(25, 10))
    )
    assert hover is not None
    assert isinstance(hover.contents, types.MarkupContent)
    assert hover.contents.value.startswith("**PT003**")
    assert "**Why is this bad?**" in hover.contents.value
    nothing = await client.text_document_hover_async(
        types.HoverParams(types.TextDocumentIdentifier(path.as_uri()), types.Position(0, 0))
    )
    assert nothing is None


def _apply(text: str, edit: types.WorkspaceEdit, uri: str) -> str:
    assert edit.changes is not None
    (change,) = edit.changes[uri]
    assert change.range.start == change.range.end  # an insertion
    lines = text.split("\n")
    at = change.range.start
    line = lines[at.line]
    lines[at.line] = line[: at.character] + change.new_text + line[at.character :]
    return "\n".join(lines)


@pytest.mark.asyncio
@pytest.mark.parametrize(
    ("title", "inserted"),
    [
        ("Suppress PT003 here", "        <!-- xodrlint: ignore[PT003] -->\n"),
        ("Suppress PT003 in this file", "<!-- xodrlint: ignore-file[PT003] -->\n"),
    ],
)
async def test_suppression_actions_withhold_the_finding(
    client: LanguageClient, tmp_path: Path, title: str, inserted: str
) -> None:
    path = tmp_path / "a.xodr"
    found = await _open(client, path, EXAMPLE)
    actions = await client.text_document_code_action_async(
        types.CodeActionParams(
            types.TextDocumentIdentifier(path.as_uri()),
            found[0].range,
            types.CodeActionContext(diagnostics=[found[0]]),
        )
    )
    assert actions is not None
    (action,) = [a for a in actions if isinstance(a, types.CodeAction) and a.title == title]
    assert action.edit is not None
    edited = _apply(EXAMPLE, action.edit, path.as_uri())
    assert inserted in edited
    # the command line honours the comment: the finding is gone once the edit is applied
    _change(client, path, 2, edited)
    assert [d.code for d in (await _published(client)).diagnostics] == ["ST004"]


@pytest.mark.asyncio
async def test_the_folder_configuration_applies_and_reloads(
    client: LanguageClient, tmp_path: Path
) -> None:
    config = tmp_path / "xodrlint.toml"
    config.write_text('ignore = ["PT003"]\n', "utf-8")
    path = tmp_path / "a.xodr"
    assert [d.code for d in await _open(client, path, EXAMPLE)] == ["ST004"]
    config.write_text('ignore = ["ST004"]\n', "utf-8")
    client.workspace_did_change_watched_files(
        types.DidChangeWatchedFilesParams(
            [types.FileEvent(config.as_uri(), types.FileChangeType.Changed)]
        )
    )
    assert [d.code for d in (await _published(client)).diagnostics] == ["PT003"]


@pytest.mark.asyncio
async def test_an_edited_configuration_applies_on_the_next_lint(
    client: LanguageClient, tmp_path: Path
) -> None:
    # an editor that does not watch files: the configuration's time stamp is checked
    path = tmp_path / "sub" / "a.xodr"
    path.parent.mkdir()
    assert [d.code for d in await _open(client, path, EXAMPLE)] == ["PT003", "ST004"]
    (tmp_path / "pyproject.toml").write_text(
        '[tool.xodrlint]\nper-file-ignores = { "sub/*.xodr" = ["ST004"] }\n', "utf-8"
    )
    client.text_document_did_save(
        types.DidSaveTextDocumentParams(types.TextDocumentIdentifier(path.as_uri()))
    )
    assert [d.code for d in (await _published(client)).diagnostics] == ["PT003"]


@pytest.mark.asyncio
async def test_an_unusable_configuration_is_said_once_and_the_defaults_apply(
    client: LanguageClient, tmp_path: Path
) -> None:
    (tmp_path / "xodrlint.toml").write_text("ignore = 3\n", "utf-8")
    path = tmp_path / "a.xodr"
    assert [d.code for d in await _open(client, path, EXAMPLE)] == ["PT003", "ST004"]
    _change(client, path, 2, EXAMPLE + " ")
    await _published(client)
    (message,) = client.messages
    assert message.type == types.MessageType.Warning
    assert message.message.startswith("xodrlint: ")
    assert "ignore" in message.message


#: A map that takes the linter a while: many copies of the example's railroad content.
def _large(copies: int) -> str:
    head, _, tail = EXAMPLE.partition("  <station")
    body = head.split("<OpenDRIVE>\n", 1)[1]
    return head.split("<OpenDRIVE>", 1)[0] + "<OpenDRIVE>\n" + body * copies + "  <station" + tail


@pytest.mark.asyncio
async def test_a_long_lint_neither_blocks_requests_nor_publishes_stale_results(
    client: LanguageClient, tmp_path: Path
) -> None:
    path = tmp_path / "a.xodr"
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            types.TextDocumentItem(path.as_uri(), "xml", 1, _large(3000))
        )
    )
    # the server answers while it lints (hover has nothing yet: no diagnostics published)
    hover = await client.text_document_hover_async(
        types.HoverParams(types.TextDocumentIdentifier(path.as_uri()), types.Position(0, 0))
    )
    assert hover is None
    assert path.as_uri() not in client.diagnostics  # the lint is still running
    # an edit during the run supersedes it: the first result is never published
    _change(client, path, 2, FIXED)
    params = await _published(client)
    assert params.version == 2
    assert [d.code for d in params.diagnostics] == ["ST004"]


async def _actions(
    client: LanguageClient, path: Path, diagnostic: types.Diagnostic
) -> list[types.CodeAction]:
    actions = await client.text_document_code_action_async(
        types.CodeActionParams(
            types.TextDocumentIdentifier(path.as_uri()),
            diagnostic.range,
            types.CodeActionContext(diagnostics=[diagnostic]),
        )
    )
    return [a for a in actions or [] if isinstance(a, types.CodeAction)]


@pytest.mark.asyncio
async def test_suppressing_an_element_after_others_on_its_line(
    client: LanguageClient, tmp_path: Path
) -> None:
    # a comment above the line would stand before the sideTrack, not the partner
    text = EXAMPLE.replace('dir="+"/>\n        <partner name="W3"', 'dir="+"/><partner name="W3"')
    path = tmp_path / "a.xodr"
    found = await _open(client, path, text)
    (_fix, here, _) = await _actions(client, path, found[0])  # the fix, then the two
    assert here.edit is not None
    edited = _apply(text, here.edit, path.as_uri())
    assert 'dir="+"/><!-- xodrlint: ignore[PT003] --><partner name="W3"' in edited
    _change(client, path, 2, edited)
    assert [d.code for d in (await _published(client)).diagnostics] == ["ST004"]


@pytest.mark.asyncio
async def test_a_file_that_does_not_parse_offers_no_suppression(
    client: LanguageClient, tmp_path: Path
) -> None:
    path = tmp_path / "a.xodr"
    (broken,) = await _open(client, path, EXAMPLE.replace("</station>", ""))
    assert await _actions(client, path, broken) == []


@pytest.mark.asyncio
async def test_only_xodr_files_are_linted(client: LanguageClient, tmp_path: Path) -> None:
    other = tmp_path / "a.xml"
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(types.TextDocumentItem(other.as_uri(), "xml", 1, EXAMPLE))
    )
    await _open(client, tmp_path / "b.XODR", EXAMPLE)
    assert list(client.diagnostics) == [(tmp_path / "b.XODR").as_uri()]


@pytest.mark.asyncio
async def test_closing_a_file_clears_its_diagnostics(
    client: LanguageClient, tmp_path: Path
) -> None:
    path = tmp_path / "a.xodr"
    assert await _open(client, path, EXAMPLE)
    client.text_document_did_close(
        types.DidCloseTextDocumentParams(types.TextDocumentIdentifier(path.as_uri()))
    )
    params = await _published(client)
    assert params.uri == path.as_uri()
    assert list(params.diagnostics) == []
