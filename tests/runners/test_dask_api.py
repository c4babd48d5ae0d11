"""The Python API on a Dask cluster (``xodrlint.distributed``) and the section "On a Dask
cluster" of docs/distributed.md: every command and example there runs here, against a
real scheduler and workers on the loopback interface."""

from __future__ import annotations

import contextlib
import os
import re
import shlex
import shutil
import socket
import subprocess
import sys
import time
import tomllib
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from packaging.requirements import Requirement
from typer.testing import CliRunner, Result

pytest.importorskip("distributed", reason="Dask is not installed: pip install 'dask[distributed]'")

from distributed import Client

import xodrlint
from tests.conftest import REPO
from tests.test_benchmarks import GENERATE
from xodrlint.api import default_registry
from xodrlint.cli import app
from xodrlint.distributed import lint_partition, lint_paths
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import FileReport

pytestmark = pytest.mark.loopback

DOC = (REPO / "docs" / "distributed.md").read_text("utf-8")
SECTION = DOC.split("## On a Dask cluster", 1)[1].split("\n## ", 1)[0]
BLOCKS = re.findall(r"```(\w+)\n(.*?)```", SECTION, flags=re.DOTALL)
#: The address the examples give the scheduler, and the port they start it on.
DOC_ADDRESS = "tcp://scheduler:8786"


def run(*args: str | Path) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.fixture
def maps(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A working folder with maps/ (clean generated maps and rule cases with findings)."""
    folder = tmp_path / "maps"
    folder.mkdir()
    for number in range(8):
        GENERATE.write_network(folder / f"net-{number}.xodr", 4096 * (number + 1))
    for case in sorted(REPO.glob("rules/[A-Z]*/invalid_*.xodr"))[:6]:
        shutil.copy(case, folder / f"{case.parent.name}-{case.name}")
    monkeypatch.chdir(tmp_path)
    return folder


def _reference(paths: list[Path], options: LintOptions | None = None) -> dict[str, FileReport]:
    linter = Linter(default_registry(), options or LintOptions())
    return {path.as_posix(): linter.lint_path(path, path.as_posix()) for path in paths}


def _same(got: FileReport, expected: FileReport) -> bool:
    return got._replace(timings={}) == expected._replace(timings={})


def _what(report: FileReport) -> list[tuple[object, ...]]:
    """What a report found, wherever its file was read from."""
    return [(f.code, f.line, f.column, f.message, f.xpath) for f in report.findings]


def test_lint_paths_yields_a_report_per_file_as_files_complete(
    maps: Path, dask_client: Client
) -> None:
    got = list(lint_paths(dask_client, ["maps", "missing.xodr", "maps/*.xodr"]))
    expected = _reference(sorted(Path("maps").iterdir()))
    assert got[0] == FileReport("missing.xodr", error="missing.xodr: no such file or directory")
    by_path = {report.path: report for report in got[1:]}
    assert len(by_path) == len(got) - 1 == len(expected)  # each file once, named once
    assert all(_same(by_path[path], report) for path, report in expected.items())


def test_lint_paths_in_input_order_with_options_and_excludes(
    maps: Path, dask_client: Client
) -> None:
    options = LintOptions(select=("SW", "XS"))
    paths = ["maps/net-3.xodr", "nothing-*.xodr", "maps"]
    got = list(lint_paths(dask_client, paths, options=options, exclude=["*net-1*"], ordered=True))
    files = [
        p for p in sorted(Path("maps").iterdir()) if p.name not in ("net-1.xodr", "net-3.xodr")
    ]
    expected = _reference([Path("maps/net-3.xodr"), *files], options)
    assert [report.path for report in got] == [
        "maps/net-3.xodr",
        "nothing-*.xodr",
        *(path.as_posix() for path in files),
    ]
    assert got[1].error == "nothing-*.xodr: no file matches"
    assert all(_same(report, expected[report.path]) for report in got if report.error is None)


def test_lint_paths_lists_a_url_here_and_its_workers_read_it(
    maps: Path, dask_client: Client
) -> None:
    url = f"file://{maps.as_posix()}"
    got = list(lint_paths(dask_client, [url], exclude=["*net-1*"], ordered=True))
    files = [p for p in sorted(maps.iterdir()) if p.name != "net-1.xodr"]
    assert [report.path for report in got] == [f"{url}/{p.name}" for p in files]
    expected = _reference([Path("maps") / p.name for p in files])
    for report, path in zip(got, files, strict=True):
        assert _what(report) == _what(expected[f"maps/{path.name}"])
    (gone,) = lint_paths(dask_client, [f"{url}/gone.xodr"])
    assert gone.error == f"{url}/gone.xodr: no such file or directory"


def test_a_partition_lints_its_paths_in_order_with_one_linter_per_options(maps: Path) -> None:
    paths = [*sorted(Path("maps").iterdir()), Path("maps/gone.xodr")]
    got = lint_partition(paths)
    assert got[-1].error == "maps/gone.xodr: cannot read: no such file or directory"
    expected = _reference(paths[:-1])
    assert all(_same(report, expected[report.path]) for report in got[:-1])
    again = lint_partition(paths[:1])
    assert _same(again[0], got[0])
    url = f"file://{paths[0].resolve().as_posix()}"  # an object by URL, read here
    (by_url,) = lint_partition([url])
    assert by_url.path == url and _what(by_url) == _what(got[0])


#: lint_frame in a process of its own: pandas starts pyarrow's allocator thread, and a
#: process with a thread forks no workers (the batch tests after this one need to).
_FRAME = """
import json, sys
import pandas as pd
from xodrlint.distributed import lint_frame
rows = lint_frame(pd.DataFrame({"path": sys.argv[1:]}))
last = rows.iloc[-1]
print(json.dumps({
    "codes": rows["code"].tolist()[:-1], "lines": rows["line"].tolist()[:-1],
    "last": [last["path"], bool(pd.isna(last["code"])), last["error"]],
}))
"""


def test_a_frame_has_a_row_per_finding_and_one_per_file_not_linted(maps: Path) -> None:
    import json

    paths = [*sorted(Path("maps").iterdir()), Path("maps/gone.xodr")]
    done = subprocess.run(
        [sys.executable, "-c", _FRAME, *(str(p) for p in paths)],
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    rows = json.loads(done.stdout)
    expected = _reference(paths[:-1])
    findings = [f for report in expected.values() for f in report.findings]
    assert rows["codes"] == [f.code for f in findings]
    assert rows["lines"] == [f.line for f in findings]
    assert rows["last"] == [
        "maps/gone.xodr",
        True,
        "maps/gone.xodr: cannot read: no such file or directory",
    ]


# The documentation ------------------------------------------------------------------


def test_the_section_shows_each_way_to_run() -> None:
    kinds = [kind for kind, _ in BLOCKS]
    assert kinds.count("console") == 2 and kinds.count("python") == 4 and kinds.count("sh") == 1
    for heading in ("A cluster of this machine", "A running scheduler", "From Python"):
        assert f"### {heading}" in SECTION
    assert "### Spark and Ray" in SECTION and "### How it scales" in SECTION


def test_the_install_command_names_the_dask_extra() -> None:
    with (REPO / "pyproject.toml").open("rb") as handle:
        extras = tomllib.load(handle)["project"]["optional-dependencies"]
    (command,) = [code for kind, code in BLOCKS if kind == "sh"]
    requirement = Requirement(shlex.split(command.strip())[2])
    assert requirement.name == "xodrlint" and requirement.extras == {"dask"}
    # cryptography: the TLS credentials of --scheduler local
    assert [Requirement(r).name for r in extras["dask"]] == ["dask", "cryptography"]
    assert "distributed" in Requirement(extras["dask"][0]).extras


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


@contextlib.contextmanager
def _started(command: list[str]) -> Iterator[subprocess.Popen[bytes]]:
    # the workers run the xodrlint under test, wherever it is imported from here
    tested = str(Path(xodrlint.__file__).parents[1])
    path = os.pathsep.join([tested, *filter(None, [os.environ.get("PYTHONPATH")])])
    process = subprocess.Popen(
        command,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        env={**os.environ, "PYTHONPATH": path},
    )
    try:
        yield process
    finally:
        process.terminate()
        process.wait(timeout=30)


def _dask(line: str, address: str) -> list[str]:
    """A ``dask`` command of the docs, on the loopback interface, without a dashboard."""
    words = shlex.split(line.replace(DOC_ADDRESS, address))
    if words[1] == "scheduler":
        words[words.index("--port") + 1] = address.rsplit(":", 1)[1]
    return [sys.executable, "-m", "dask", *words[1:], "--host", "127.0.0.1", "--no-dashboard"]


def _on_one_process(words: list[str]) -> list[str]:
    """The same check without Dask: its scheduler options dropped, ``--jobs 1``, and its
    report to another file."""
    plain = []
    skip = False
    for word, following in zip(words, [*words[1:], None], strict=True):
        if skip:
            skip = False
        elif word in ("--scheduler", "--scheduler-timeout", "--jobs"):
            skip = True
        else:
            plain.append(word)
            if word == "--output" and following:
                plain.append(following + ".one")
                skip = True
    return [*plain, "--jobs", "1"]


def test_the_commands_run_against_a_scheduler_and_workers_started_as_shown(maps: Path) -> None:
    lines = [
        line.strip()
        for kind, code in BLOCKS
        if kind == "console"
        for line in code.splitlines()
        if line.strip()
    ]
    address = f"tcp://127.0.0.1:{_free_port()}"
    servers = [_dask(line, address) for line in lines if line.startswith("dask ")]
    checks = [shlex.split(line.replace(DOC_ADDRESS, address))[1:] for line in lines]
    checks = [words for words in checks if words[0] == "check"]
    assert len(servers) == 2 and len(checks) == 4
    with _started(servers[0]), _started(servers[1]):
        _wait_for_workers(address, 2)
        for words in checks:
            done = run(*words)
            one = run(*_on_one_process(words))
            assert done.exit_code == one.exit_code == 1, done.stderr
            assert done.stdout == one.stdout, repr(done.exception)
            if "--output" in words:
                target = words[words.index("--output") + 1]
                assert Path(target).read_bytes() == Path(target + ".one").read_bytes()


def _wait_for_workers(address: str, count: int) -> None:
    deadline = time.monotonic() + 60
    while True:
        try:
            with Client(address, timeout=5, set_as_default=False) as client:
                client.wait_for_workers(count, timeout=60)
                return
        except OSError:
            assert time.monotonic() < deadline, "the scheduler never started"
            time.sleep(0.2)


def test_the_python_examples_run_on_a_cluster(maps: Path) -> None:
    # the examples, the scheduler and the workers each in processes of their own, as a
    # user runs them: the dataframe example loads pyarrow (where its graph is run, and
    # where the scheduler reads it), whose allocator starts a thread for the rest of the
    # process, and a process with a thread forks no workers (the tests after this need to)
    code = [code for kind, code in BLOCKS if kind == "python"]
    address = f"tcp://127.0.0.1:{_free_port()}"
    port = address.rsplit(":", 1)[1]
    scheduler = [sys.executable, "-m", "dask", "scheduler", "--host", "127.0.0.1"]
    scheduler += ["--port", port, "--no-dashboard"]
    workers = [sys.executable, "-m", "dask", "worker", address, "--nworkers", "2"]
    workers += ["--nthreads", "1", "--host", "127.0.0.1", "--no-dashboard"]
    with _started(scheduler), _started(workers):
        _wait_for_workers(address, 2)
        done = subprocess.run(
            [sys.executable, "-c", "\n".join(code[:3]).replace(DOC_ADDRESS, address)],
            capture_output=True,
            text=True,
            timeout=300,
            check=False,
        )
    assert done.returncode == 0, done.stderr[-3000:]
    printed = done.stdout.splitlines()
    paths = sorted(Path("maps").iterdir())
    ignoring = _reference(paths, LintOptions(ignore=("XL001",)))
    assert sorted(printed[: len(paths)]) == sorted(
        f"{path} {len(report.findings)} " for path, report in ignoring.items()
    )
    everything = _reference(paths)
    errors = sum(f.severity == "error" for r in everything.values() for f in r.findings)
    assert printed[len(paths)] == f"errors: {errors}"
    codes = {f.code for r in everything.values() for f in r.findings}
    assert {line.split()[0] for line in printed[len(paths) + 2 : -1]} == codes


def test_the_spark_and_ray_pattern_works_on_what_they_hand_over(maps: Path) -> None:
    import numpy as np

    namespace: dict[str, Any] = {}
    exec([code for kind, code in BLOCKS if kind == "python"][3], namespace)
    paths = sorted(Path("maps").iterdir())
    expected = _reference(paths)
    rows = [
        (f.path, f.line, f.column, f.code, str(f.severity), f.message)
        for report in expected.values()
        for f in report.findings
    ]
    given = [(path.as_posix(), bytearray(path.read_bytes())) for path in paths]  # Spark: bytearray
    assert list(namespace["lint_rows"](iter(given))) == rows
    batch = {
        "path": np.array([path.as_posix() for path in paths]),
        "bytes": np.array([path.read_bytes() for path in paths], dtype=object),
    }
    columns = namespace["lint_batch"](batch)  # Ray: a dict of numpy arrays, by default
    assert list(columns) == list(namespace["COLUMNS"])
    assert list(zip(*columns.values(), strict=True)) == rows
