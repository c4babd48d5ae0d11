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

REPO = Path(__file__).resolve().parents[1]
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
