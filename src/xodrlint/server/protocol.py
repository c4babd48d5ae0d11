"""The language server: pygls over stdio. Lints the editor's buffer (not the file on disk)
on open, on save and after a pause in typing, in a worker thread so the editor never
waits; a newer edit supersedes a run, whose result is then dropped."""

from __future__ import annotations

import asyncio
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Final

from lsprotocol import types
from pygls.lsp.server import LanguageServer
from pygls.uris import to_fs_path

from xodrlint import __version__
from xodrlint.api import XODR_SUFFIX, default_registry
from xodrlint.findings import FileReport
from xodrlint.server.actions import code_actions, covers, hover_text
from xodrlint.server.convert import diagnostics, document_bytes
from xodrlint.server.folders import Folders

#: Seconds of quiet after a keystroke before the buffer is linted.
DEBOUNCE: Final = 0.3


class XodrServer(LanguageServer):
    def __init__(self) -> None:
        super().__init__("xodrlint", __version__)
        self.registry = default_registry()
        self.folders = Folders(self.registry)
        # one lint at a time: a newer one queued behind it supersedes it
        self.pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="xodrlint-lint")
        self.latest: dict[str, int] = {}
        self.pending: dict[str, asyncio.Task[None]] = {}
        self.published: dict[str, list[types.Diagnostic]] = {}
        self.told: set[str] = set()
        #: The client asked for ``shutdown``: an ``exit`` after it ends the server with 0.
        self.shut_down = False

    def schedule(self, uri: str, delay: float) -> None:
        """Lint ``uri`` after ``delay`` seconds; any lint asked for earlier is superseded.
        Only ``.xodr`` files: an editor may send every XML file it opens."""
        if not uri.lower().endswith(XODR_SUFFIX):
            return
        self.latest[uri] = self.latest.get(uri, 0) + 1
        waiting = self.pending.pop(uri, None)
        if waiting is not None:
            waiting.cancel()
        self.pending[uri] = asyncio.ensure_future(self._lint_later(uri, self.latest[uri], delay))

    async def _lint_later(self, uri: str, turn: int, delay: float) -> None:
        if delay:
            await asyncio.sleep(delay)
        document = self.workspace.get_text_document(uri)
        text, version = document.source, document.version
        loop = asyncio.get_running_loop()
        done = await loop.run_in_executor(self.pool, self._diagnose, uri, turn, text)
        if done is None or self.latest.get(uri) != turn:
            return  # an edit came in meanwhile: its own lint publishes
        found, problem = done
        if problem and problem not in self.told:  # once: not a message per keystroke
            self.told.add(problem)
            self.window_show_message(
                types.ShowMessageParams(types.MessageType.Warning, f"xodrlint: {problem}")
            )
        self.published[uri] = found
        self.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=uri, diagnostics=found, version=version)
        )

    @property
    def encoding(self) -> str:
        return str(self.workspace.position_encoding or types.PositionEncodingKind.Utf16)

    def _diagnose(
        self, uri: str, turn: int, text: str
    ) -> tuple[list[types.Diagnostic], str | None] | None:
        """In the worker thread: lint ``text`` and convert the findings (splitting a large
        map's lines is work too), unless an edit superseded it while it waited. Also why
        the folder's configuration could not be used, for the loop to tell the user (only
        the loop's thread writes to the client)."""
        if self.latest.get(uri) != turn:
            return None
        path = Path(to_fs_path(uri) or "untitled.xodr")
        choice = self.folders.linter_for(path)
        if choice.excluded(path):
            report = FileReport(str(path))
        else:
            data = document_bytes(text)
            report = choice.linter.lint_bytes(data, str(path), choice.external(path))
        found = list(diagnostics(report, uri, text, self.encoding, self.registry))
        return found, choice.problem

    def close(self, uri: str) -> None:
        self.latest[uri] = self.latest.get(uri, 0) + 1
        waiting = self.pending.pop(uri, None)
        if waiting is not None:
            waiting.cancel()
        self.published.pop(uri, None)
        self.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri, []))


def build() -> XodrServer:
    server = XodrServer()

    @server.feature(types.SHUTDOWN)
    def shutdown(ls: XodrServer, params: None) -> None:
        ls.shut_down = True

    @server.feature(types.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: XodrServer, params: types.DidOpenTextDocumentParams) -> None:
        ls.schedule(params.text_document.uri, 0)

    @server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: XodrServer, params: types.DidChangeTextDocumentParams) -> None:
        ls.schedule(params.text_document.uri, DEBOUNCE)

    @server.feature(types.TEXT_DOCUMENT_DID_SAVE)
    def did_save(ls: XodrServer, params: types.DidSaveTextDocumentParams) -> None:
        ls.schedule(params.text_document.uri, 0)

    @server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: XodrServer, params: types.DidCloseTextDocumentParams) -> None:
        ls.close(params.text_document.uri)

    @server.feature(types.WORKSPACE_DID_CHANGE_WATCHED_FILES)
    def watched(ls: XodrServer, params: types.DidChangeWatchedFilesParams) -> None:
        ls.folders.forget()
        for uri in list(ls.published):
            ls.schedule(uri, 0)

    @server.feature(types.TEXT_DOCUMENT_HOVER)
    def hover(ls: XodrServer, params: types.HoverParams) -> types.Hover | None:
        codes = [
            str(item.code)
            for item in ls.published.get(params.text_document.uri, [])
            if covers(item.range, params.position)
        ]
        text = hover_text(ls.registry, codes)
        if text is None:
            return None
        return types.Hover(types.MarkupContent(types.MarkupKind.Markdown, text))

    @server.feature(
        types.TEXT_DOCUMENT_CODE_ACTION,
        types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix]),
    )
    def actions(ls: XodrServer, params: types.CodeActionParams) -> list[types.CodeAction]:
        document = ls.workspace.get_text_document(params.text_document.uri)
        return code_actions(document.uri, document.source, params.context.diagnostics)

    return server


def serve() -> int:
    """Serve until the client's ``exit`` (or the end of its input); the status is the one
    the LSP asks of ``exit``: 0 where ``shutdown`` came first, else 1. pygls ends its loop
    with that status as a SystemExit, but catches it itself: it is decided again here."""
    server = build()
    server.start_io()
    return 0 if server.shut_down else 1
