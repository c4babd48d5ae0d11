"""``xodrlint server``'s exit status, through a real LSP client (pytest-lsp) as an editor
ends a session: 0 after ``shutdown`` then ``exit``, 1 after ``exit`` alone, as the LSP
specification says of the ``exit`` notification."""

from __future__ import annotations

import asyncio
import os
import sys
from pathlib import Path

import pytest

pytest.importorskip("pygls", reason="the server extra (pygls) is not installed")
pytest.importorskip("pytest_lsp", reason="pytest-lsp is not installed")

from lsprotocol import types
from pygls.protocol import default_converter
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities
from pytest_lsp.client import register_lsp_features

REPO = Path(__file__).resolve().parents[2]
ENV = {**os.environ, "PYTHONPATH": str(REPO / "src")}
#: Seconds a session may take to start or end before the test fails rather than hangs.
PATIENCE = 60


class StatusClient(LanguageClient):
    """pytest-lsp's test client that also keeps the exit status of the server it started
    (pygls calls ``server_exit`` once the process has ended)."""

    def __init__(self) -> None:
        super().__init__(converter_factory=default_converter)
        register_lsp_features(self)
        self.statuses: list[int | None] = []
        self.ended = asyncio.Event()

    async def server_exit(self, server: asyncio.subprocess.Process) -> None:
        self.statuses.append(server.returncode)
        self.ended.set()
        await super().server_exit(server)


async def _session(tmp_path: Path) -> StatusClient:
    config = ClientServerConfig(
        server_command=[sys.executable, "-m", "xodrlint", "server"],
        server_env=ENV,
        client_factory=StatusClient,
    )
    client = await asyncio.wait_for(config.start(), PATIENCE)
    assert isinstance(client, StatusClient)
    await asyncio.wait_for(
        client.initialize_session(
            types.InitializeParams(
                capabilities=client_capabilities("visual-studio-code"),
                root_uri=tmp_path.as_uri(),
            )
        ),
        PATIENCE,
    )
    return client


@pytest.mark.asyncio
async def test_exit_after_shutdown_ends_the_server_with_status_0(tmp_path: Path) -> None:
    client = await _session(tmp_path)
    await asyncio.wait_for(client.shutdown_async(None), PATIENCE)
    client.exit(None)
    await asyncio.wait_for(client.ended.wait(), PATIENCE)
    assert client.statuses == [0]


@pytest.mark.asyncio
async def test_exit_without_shutdown_ends_the_server_with_status_1(tmp_path: Path) -> None:
    client = await _session(tmp_path)
    client.exit(None)
    await asyncio.wait_for(client.ended.wait(), PATIENCE)
    assert client.statuses == [1]
