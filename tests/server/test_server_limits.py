"""Issue 30, item 5 (and 12): the language server stops a lint that runs away and keeps
answering; in a workspace the editor does not trust, a configuration's schema, rule
options and rule timeout are not used; what keeps findings from being complete is shown,
never swallowed."""

from __future__ import annotations

import asyncio
import os
import sys
import tempfile
import time
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
LINT_TIMEOUT = 4


def _site() -> str:
    """A folder in which the runaway pack is installed, as pip would leave it."""
    site = Path(tempfile.mkdtemp(prefix="xodrlint-runaway-site-"))
    info = site / "runaway_pack-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: runaway-pack\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text(
        "[xodrlint.rules]\nrunaway = tests.hostile_pack.runaway\n"
    )
    return str(site)


ENV = {**os.environ, "PYTHONPATH": os.pathsep.join([_site(), str(REPO / "src"), str(REPO)])}
SERVER = ClientServerConfig(
    server_command=[sys.executable, "-m", "xodrlint", "server"], server_env=ENV
)


async def _session(client: LanguageClient, root: Path, **options: object) -> None:
    await client.initialize_session(
        types.InitializeParams(
            capabilities=client_capabilities("visual-studio-code"),
            root_uri=root.as_uri(),
            initialization_options={"lintTimeout": LINT_TIMEOUT, **options},
        )
    )


@pytest_lsp.fixture(config=SERVER)  # type: ignore[untyped-decorator]
async def client(lsp_client: LanguageClient, tmp_path: Path) -> AsyncIterator[None]:
    await _session(lsp_client, tmp_path)
    yield
    await lsp_client.shutdown_session()


@pytest_lsp.fixture(config=SERVER)  # type: ignore[untyped-decorator]
async def untrusting(lsp_client: LanguageClient, tmp_path: Path) -> AsyncIterator[None]:
    await _session(lsp_client, tmp_path, trusted=False)
    yield
    await lsp_client.shutdown_session()


async def _open(client: LanguageClient, path: Path, text: str = EXAMPLE) -> list[types.Diagnostic]:
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(types.TextDocumentItem(path.as_uri(), "xml", 1, text))
    )
    while True:  # a server that never publishes fails the test instead of hanging it
        params = await asyncio.wait_for(client.wait_for_notification(PUBLISH), 90)
        if params.uri == path.as_uri():
            return list(params.diagnostics)


def _folder(root: Path, name: str, config: str) -> Path:
    folder = root / name
    folder.mkdir()
    (folder / "xodrlint.toml").write_text(config, "utf-8")
    return folder


@pytest.mark.asyncio
async def test_a_rule_that_runs_away_is_stopped_by_its_limit(
    client: LanguageClient, tmp_path: Path
) -> None:
    spinning = _folder(tmp_path, "spins", 'select = ["HY001", "PT"]\nrule-timeout = 1\n')
    found = await _open(client, spinning / "a.xodr")
    assert sorted(str(d.code) for d in found if d.code) == ["PT003"]  # the rest is kept
    (gap,) = [d for d in found if not d.code]
    assert gap.message.startswith("internal error: rule HY001 stopped after 1 s")
    assert gap.range.start.line == 0 and gap.severity == types.DiagnosticSeverity.Error


@pytest.mark.asyncio
async def test_a_lint_that_never_ends_is_stopped_and_the_server_goes_on(
    client: LanguageClient, tmp_path: Path
) -> None:
    blocked = _folder(tmp_path, "blocked", 'select = ["HY002"]\n')
    started = time.monotonic()
    (gap,) = await _open(client, blocked / "a.xodr")
    assert LINT_TIMEOUT <= time.monotonic() - started < LINT_TIMEOUT + 30
    assert f"took longer than {LINT_TIMEOUT} s and was stopped" in gap.message
    assert any("was stopped" in m.message for m in client.messages)
    # the next file gets its diagnostics from a fresh process
    plain = _folder(tmp_path, "plain", 'select = ["PT", "ST"]\n')
    assert [d.code for d in await _open(client, plain / "b.xodr")] == ["PT003", "ST004"]


@pytest.mark.asyncio
async def test_an_untrusted_workspace_takes_no_schema_options_or_timeout(
    untrusting: LanguageClient, tmp_path: Path
) -> None:
    (tmp_path / "evil.xsd").write_text("not a schema")
    (tmp_path / "xodrlint.toml").write_text(
        'schema = "evil.xsd"\nrule-timeout = 0\nignore = ["ST"]\nrail-min-width = 9.0\n'
        'select = ["PT", "ST", "RL", "XS"]\n'
    )
    found = await _open(untrusting, tmp_path / "a.xodr")
    assert [d.code for d in found] == ["PT003"]  # select and ignore still apply
    (message,) = untrusting.messages
    assert message.message == (
        f"xodrlint: the workspace is not trusted: schema, rail-min-width, rule-timeout from "
        f"{tmp_path / 'xodrlint.toml'} not used"
    )


@pytest.mark.asyncio
async def test_a_schema_that_does_not_load_is_shown(client: LanguageClient, tmp_path: Path) -> None:
    (tmp_path / "bad.xsd").write_text("<xs:schema xmlns:xs='http://www.w3.org/2001/XMLSchema'>")
    (tmp_path / "xodrlint.toml").write_text('schema = "bad.xsd"\nignore = ["HY"]\n')
    (gap,) = await _open(client, tmp_path / "a.xodr")
    assert gap.message.startswith(f"cannot lint {tmp_path / 'a.xodr'}: cannot read schema")
    assert any("cannot read schema" in m.message for m in client.messages)


@pytest.mark.asyncio
async def test_a_lone_surrogate_in_the_buffer_is_an_xs001_where_it_stands(
    client: LanguageClient, tmp_path: Path
) -> None:
    (tmp_path / "xodrlint.toml").write_text('ignore = ["HY"]\n')  # the runaway pack's
    text = EXAMPLE.replace('<partner name="W3"', '<partner name="W\ud8003"')
    found = await _open(client, tmp_path / "a.xodr", text)
    assert [(d.code, d.range.start.line) for d in found] == [("XS001", 25)], found[0].message


def test_a_worker_that_does_not_start_is_said_and_the_next_lint_starts_afresh(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from xodrlint.server import worker

    path, data = tmp_path / "a.xodr", EXAMPLE.encode()
    (tmp_path / "xodrlint.toml").write_text('select = ["PT", "ST"]\n')
    linting = worker.LintWorker()
    monkeypatch.setattr(worker, "STARTUP_SECONDS", 0.0)  # no process is ready that soon
    outcome = linting.lint(path, data)
    assert outcome.report is None
    assert (
        outcome.failure
        == f"the linting process did not start in time: linting {path} is left undone"
    )
    monkeypatch.setattr(worker, "STARTUP_SECONDS", 60.0)
    report = linting.lint(path, data).report
    assert report is not None and [f.code for f in report.findings] == ["PT003", "ST004"]
    linting.close()  # the server ends: no lint starts a process again
    closed = linting.lint(path, data)
    assert closed.failure is not None and closed.failure.startswith("the server is shutting down")


def test_a_hit_carries_plain_ints_whatever_a_rule_gave() -> None:
    from lxml import etree

    from xodrlint.engine.guard import checked_hit
    from xodrlint.findings import Hit

    class Sneaky(int):
        def __str__(self) -> str:
            return "1\n::error::injected"

    root = etree.fromstring("<OpenDRIVE/>")
    hit = checked_hit(Hit(root, "m", line=Sneaky(3), column=Sneaky(4)), root)
    assert (type(hit.line), type(hit.column), hit.line, hit.column) == (int, int, 3, 4)
