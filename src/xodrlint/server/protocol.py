"""The language server: pygls over stdio. Lints the editor's buffer (not the file on disk)
on open, on save and after a pause in typing, in a process of its own that the server can
stop (:mod:`.worker`), waited for in a thread so the editor never waits; a newer edit
supersedes a run, whose result is then dropped.

Initialization options (``initializationOptions`` of the client's ``initialize``):
``trusted`` (default ``true``; ``false`` for a workspace the editor does not trust: its
configuration's ``schema``, rule options and ``rule-timeout`` are not used) and
``lintTimeout`` (seconds a lint may take before its process is stopped; default 120)."""

from __future__ import annotations

import asyncio
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Final

from lsprotocol import types
from pygls.lsp.server import LanguageServer
from pygls.uris import to_fs_path

from xodrlint import __version__
from xodrlint.api import default_registry
from xodrlint.inputs.collect import XODR_SUFFIX
from xodrlint.rules.registry import Registry
from xodrlint.server.actions import FIX_ALL, code_actions, covers, fix_all_action, hover_text
from xodrlint.server.convert import SOURCE, diagnostics, document_bytes, document_text
from xodrlint.server.worker import DEFAULT_DEADLINE, LintWorker, Outcome

#: Seconds of quiet after a keystroke before the buffer is linted.
DEBOUNCE: Final = 0.3


class XodrServer(LanguageServer):
    def __init__(self) -> None:
        super().__init__("xodrlint", __version__)
        self.registry = default_registry()
        self.worker = LintWorker()
        # one lint at a time: a newer one queued behind it supersedes it
        self.pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="xodrlint-lint")
        self.latest: dict[str, int] = {}
        self.pending: dict[str, asyncio.Task[None]] = {}
        self.published: dict[str, list[types.Diagnostic]] = {}
        #: The version of the text each published diagnostics list is of.
        self.versions: dict[str, int | None] = {}
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
        found, problems = done
        for problem in problems:
            if problem not in self.told:  # once: not a message per keystroke
                self.told.add(problem)
                self.window_show_message(
                    types.ShowMessageParams(types.MessageType.Warning, f"xodrlint: {problem}")
                )
        self.published[uri] = found
        self.versions[uri] = version
        self.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=uri, diagnostics=found, version=version)
        )

    @property
    def takes_versioned_edits(self) -> bool:
        """Whether the client applies edits that name the text's version (and refuses
        them on another): ``workspace.workspaceEdit.documentChanges``."""
        workspace = self.client_capabilities.workspace
        edits = workspace.workspace_edit if workspace is not None else None
        return bool(edits is not None and edits.document_changes)

    @property
    def encoding(self) -> str:
        return str(self.workspace.position_encoding or types.PositionEncodingKind.Utf16)

    def _diagnose(
        self, uri: str, turn: int, text: str
    ) -> tuple[list[types.Diagnostic], list[str]] | None:
        """In the pool's thread: lint ``text`` in the worker and convert the findings
        (splitting a large map's lines is work too), unless an edit superseded it while
        it waited. Also what the user is to be told (a configuration that could not be
        used, a lint that failed), for the loop to tell (only its thread writes to the
        client)."""
        if self.latest.get(uri) != turn:
            return None
        path = Path(to_fs_path(uri) or "untitled.xodr")
        outcome = self.worker.lint(path, document_bytes(text))
        found, told = _converted(outcome, uri, text, self.encoding, self.registry)
        # a rule pack left out (it failed to load, or breaks the rule API) is said once:
        # the worker loads the packs this process did
        return found, [*self.registry.warnings, *told]

    def fix_all(self, uri: str, text: str) -> str | None:
        """In the pool's thread: ``text`` with its safe fixes made in the worker, as
        ``check --fix`` makes them; ``None`` where none could be (said once)."""
        path = Path(to_fs_path(uri) or "untitled.xodr")
        data = document_bytes(text)
        fixed = self.worker.fix(path, data)
        if isinstance(fixed, str):
            return None
        if fixed == data:
            return text
        try:
            return document_text(fixed, text)
        except UnicodeDecodeError:
            return None

    def close(self, uri: str) -> None:
        self.latest[uri] = self.latest.get(uri, 0) + 1
        waiting = self.pending.pop(uri, None)
        if waiting is not None:
            waiting.cancel()
        self.published.pop(uri, None)
        self.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri, []))


def _converted(
    outcome: Outcome, uri: str, text: str, encoding: str, registry: Registry
) -> tuple[list[types.Diagnostic], list[str]]:
    """The diagnostics of a lint, and what to tell the user about it. What kept findings
    from being complete (a lint stopped, a rule's internal error, a file that could not
    be read) is a diagnostic on the first line as well: never a silent gap."""
    told = [outcome.problem] if outcome.problem else []
    report = outcome.report
    gaps = [outcome.failure] if outcome.failure else []
    found: list[types.Diagnostic] = []
    if report is not None:
        found = list(diagnostics(report, uri, text, encoding, registry))
        gaps += [report.error] if report.error else []
        gaps += [f"internal error: {crash}" for crash in report.internal_errors]
    found += [_gap(gap) for gap in gaps]
    told += [gap for gap in gaps if outcome.failure == gap]
    return found, told


def _gap(message: str) -> types.Diagnostic:
    return types.Diagnostic(
        range=types.Range(types.Position(0, 0), types.Position(0, 0)),
        message=message,
        severity=types.DiagnosticSeverity.Error,
        source=SOURCE,
    )


def _option(options: object, name: str, default: object) -> object:
    """One of the client's initialization options (a JSON object), else ``default``."""
    return options.get(name, default) if isinstance(options, dict) else default


def build() -> XodrServer:
    server = XodrServer()

    @server.feature(types.INITIALIZE)
    def initialize(ls: XodrServer, params: types.InitializeParams) -> None:
        options = params.initialization_options
        trusted = _option(options, "trusted", True)
        deadline = _option(options, "lintTimeout", DEFAULT_DEADLINE)
        ls.worker.trusted = trusted is True  # anything but JSON's true: not trusted
        if isinstance(deadline, int | float) and not isinstance(deadline, bool) and deadline > 0:
            ls.worker.deadline = float(deadline)

    @server.feature(types.SHUTDOWN)
    def shutdown(ls: XodrServer, params: None) -> None:
        ls.shut_down = True
        ls.worker.close()  # a lint waiting on it ends at once; no other starts

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
        ls.pool.submit(ls.worker.forget)  # in the pool: after the lint that may be running
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
        types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix, FIX_ALL]),
    )
    async def actions(ls: XodrServer, params: types.CodeActionParams) -> list[types.CodeAction]:
        document = ls.workspace.get_text_document(params.text_document.uri)
        uri, text, version = document.uri, document.source, document.version
        versioned = version if ls.takes_versioned_edits else None
        only = params.context.only
        found: list[types.CodeAction] = []
        if only is None or any(
            kind in (types.CodeActionKind.QuickFix, types.CodeActionKind.Empty) for kind in only
        ):
            # fixes only from diagnostics of the text as it is now
            current = ls.versions.get(uri) == document.version
            published = ls.published.get(uri) if current else None
            found += code_actions(uri, text, params.context.diagnostics, published, versioned)
        if only is not None and any(
            FIX_ALL.startswith(str(kind)) and str(kind) != "" for kind in only
        ):
            loop = asyncio.get_running_loop()
            fixed = await loop.run_in_executor(ls.pool, ls.fix_all, uri, text)
            # the text may have changed while its fixes were made: they are of the old one
            now = ls.workspace.get_text_document(uri).version
            if fixed is not None and now == version:
                action = fix_all_action(uri, text, fixed, ls.encoding, versioned)
                found += [action] if action is not None else []
        return found

    return server


def serve() -> int:
    """Serve until the client's ``exit`` (or the end of its input); the status is the one
    the LSP asks of ``exit``: 0 where ``shutdown`` came first, else 1. pygls ends its loop
    with that status as a SystemExit, but catches it itself: it is decided again here."""
    server = build()
    try:
        server.start_io()
    finally:
        server.worker.close()
    return 0 if server.shut_down else 1
