"""How soon ``xodrlint server`` publishes fresh diagnostics after a keystroke (issue 22).

    python benchmarks/lsp_latency.py [--schemas ../shared/schemas] [--edits 20]
                                     [--large-edits 5] [--size-mb 20] [--workdir DIR]

Generates the 0.2 MB and the 20 MB mixed networks (benchmarks/generate.py), starts the
server through pytest-lsp's client (as tests/server/test_server.py does), opens each, and times
edits: each edit changes one attribute value in place (an incremental change, as editors
send them); the time counted is from the end of the server's 300 ms debounce to the
diagnostics of that version arriving. Prints the median over ``--edits`` edits on the
small file (the goal: 150 ms at most), and over ``--large-edits`` on the large one beside
the median wall time of ``xodrlint check`` on it (the goal: at most that plus 10%).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Final

from lsprotocol import types
from pytest_lsp import LanguageClient, client_capabilities, make_test_lsp_client

HERE: Final = Path(__file__).resolve().parent
SRC: Final = HERE.parent / "src"
#: The server's debounce (xodrlint.server.protocol.DEBOUNCE), subtracted from each wait.
DEBOUNCE: Final = 0.3
#: The attribute each edit rewrites: the header's name, on one line near the top.
TARGET: Final = 'name="'


def _generate(size_mb: float, folder: Path) -> Path:
    path = folder / f"network-{size_mb:g}mb-1.7.xodr"
    if not path.exists():
        command = [sys.executable, str(HERE / "generate.py"), "--size-mb", str(size_mb)]
        subprocess.run([*command, "-o", str(path)], check=True)
    return path


async def _start(env: dict[str, str]) -> LanguageClient:
    client = make_test_lsp_client()
    await client.start_io(sys.executable, "-m", "xodrlint", "server", env=env)
    await client.initialize_session(
        types.InitializeParams(capabilities=client_capabilities("visual-studio-code"))
    )
    return client


def _edit(text: str, number: int) -> tuple[types.Range, str]:
    """An in-place edit of the first ``name="..."`` value: one character, a new digit."""
    offset = text.index(TARGET) + len(TARGET)
    line = text.count("\n", 0, offset)
    column = offset - (text.rfind("\n", 0, offset) + 1)
    at = types.Range(types.Position(line, column), types.Position(line, column + 1))
    return at, str(number % 10)


async def _latencies(client: LanguageClient, path: Path, edits: int) -> list[float]:
    uri = path.as_uri()
    text = path.read_text("utf-8")
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(types.TextDocumentItem(uri, "xml", 1, text))
    )
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    found = []
    for number in range(edits):
        version = number + 2
        at, new = _edit(text, number)
        change = types.TextDocumentContentChangePartial(range=at, text=new)
        started = time.perf_counter()
        client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                types.VersionedTextDocumentIdentifier(version=version, uri=uri), [change]
            )
        )
        while True:
            params = await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
            if params.version == version:
                break
        found.append(time.perf_counter() - started - DEBOUNCE)
    return found


def _check_time(path: Path, env: dict[str, str], repeat: int) -> float:
    command = [sys.executable, "-m", "xodrlint", "check", "-f", "json", "-o", os.devnull]
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        subprocess.run([*command, str(path)], env=env, check=False, stdout=subprocess.DEVNULL)
        times.append(time.perf_counter() - started)
    return statistics.median(times)


async def _measure(args: argparse.Namespace, folder: Path, env: dict[str, str]) -> None:
    small = _generate(0.2, folder)
    large = _generate(args.size_mb, folder)
    client = await _start(env)
    try:
        fast = await _latencies(client, small, args.edits)
        slow = await _latencies(client, large, args.large_edits)
    finally:
        await client.shutdown_session()
    check = _check_time(large, env, args.large_edits)
    small_ms = statistics.median(fast) * 1000
    print(f"0.2 MB: median {small_ms:.0f} ms after the debounce over {len(fast)} edits")
    print(f"  (min {min(fast) * 1000:.0f} ms, max {max(fast) * 1000:.0f} ms; goal <= 150 ms)")
    large_s = statistics.median(slow)
    print(f"{args.size_mb:g} MB: median {large_s:.2f} s after the debounce over {len(slow)} edits")
    print(f"  xodrlint check on it: median {check:.2f} s; goal <= {check * 1.1:.2f} s")
    print(f"  ratio: {large_s / check:.2f}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    default_schemas = os.environ.get(
        "XODRLINT_SCHEMA_PATH", str(HERE.parent.parent / "shared" / "schemas")
    )
    parser.add_argument("--schemas", type=Path, default=Path(default_schemas))
    parser.add_argument("--edits", type=int, default=20)
    parser.add_argument("--large-edits", type=int, default=5)
    parser.add_argument("--size-mb", type=float, default=20.0)
    parser.add_argument("--workdir", type=Path, help="keep the networks here (a temp folder)")
    args = parser.parse_args(argv)
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    if args.schemas.is_dir():  # the official schemas, as benchmarks/run.py validates with
        env["XODRLINT_SCHEMA_PATH"] = str(args.schemas.resolve())
    if args.workdir is not None:
        args.workdir.mkdir(parents=True, exist_ok=True)
        asyncio.run(_measure(args, args.workdir, env))
        return 0
    with tempfile.TemporaryDirectory() as folder:
        asyncio.run(_measure(args, Path(folder), env))
    return 0


if __name__ == "__main__":
    sys.exit(main())
