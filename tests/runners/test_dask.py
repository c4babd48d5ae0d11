"""Dask as the engine (issue 20), on a real LocalCluster of two worker processes: the
report of ``--jobs 1``, byte for byte, also when a worker is killed mid-run; a file that
breaks the linter or its worker stays that file's problem; one linter per worker and a
few batches; Ctrl-C cancels the run's work; an unreachable scheduler is one line."""

from __future__ import annotations

import json
import multiprocessing
import os
import select
import shutil
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner, Result

pytest.importorskip("distributed", reason="Dask is not installed: pip install 'dask[distributed]'")

from distributed import Client, LocalCluster

import xodrlint
from tests.conftest import REPO
from tests.dask_helpers import (
    LINT_KEY,
    BrokenLinterPlugin,
    CountLinters,
    FailOn,
    KillOnce,
    Slow,
    linters_built,
)
from tests.test_benchmarks import GENERATE
from xodrlint.cli import app
from xodrlint.engine.linter import LintOptions
from xodrlint.runners import dask as engine
from xodrlint.runners.batch import Task, schedule
from xodrlint.runners.dask import lint_on_cluster

pytestmark = pytest.mark.loopback

#: Cases of the rule catalogue with findings, beside the generated (clean) maps.
CASES = sorted(REPO.glob("rules/[A-Z]*/invalid_*.xodr"))[:40]
#: Reports of these formats are compared too (the JSON one is the standard output).
FORMATS = ("sarif", "junit", "gitlab", "github", "text", "concise")


@pytest.fixture(scope="module")
def maps(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """200 maps: 160 generated ones of 4 to 20 KB in three versions, 40 rule cases."""
    folder = tmp_path_factory.mktemp("maps")
    for number in range(160):
        size = 4096 + (number * 997) % 16384
        GENERATE.write_network(folder / f"net-{number:03}.xodr", size, (4, 7, 8)[number % 3])
    for number, case in enumerate(CASES):
        shutil.copy(case, folder / f"case-{number:03}-{case.parent.name}-{case.name}")
    return folder


@pytest.fixture(scope="module")
def cluster(dask_cluster: LocalCluster) -> LocalCluster:
    return dask_cluster


@pytest.fixture(scope="module")
def client(dask_client: Client) -> Client:
    return dask_client


@pytest.fixture
def plugin(client: Client) -> Iterator[Callable[[Any, str], None]]:
    """Registers worker plugins for one test; they are gone, and both workers back,
    after it."""
    names: list[str] = []

    def register(planted: Any, name: str) -> None:
        client.register_plugin(planted, name=name)
        names.append(name)

    yield register
    for name in names:
        client.unregister_worker_plugin(name)
    client.wait_for_workers(2, timeout=60)


def run(*args: str | Path) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


def reports(folder: Path, out: Path, *engine: str | Path) -> tuple[Result, dict[str, bytes]]:
    """A JSON run on ``folder`` with ``engine``'s options, and every other format's
    report of it, by format."""
    out.mkdir()
    extra = [f"--report={name}={out / name}" for name in FORMATS]
    result = run("check", "-f", "json", *extra, *engine, folder)
    assert result.exit_code in (0, 1), result.stderr
    return result, {name: (out / name).read_bytes() for name in FORMATS}


def test_a_cluster_gives_the_report_of_one_process(
    maps: Path, cluster: LocalCluster, tmp_path: Path
) -> None:
    one, one_reports = reports(maps, tmp_path / "one", "-j", "1")
    dask_run, dask_reports = reports(
        maps, tmp_path / "dask", "--scheduler", cluster.scheduler_address
    )
    assert one.exit_code == dask_run.exit_code == 1, dask_run.stderr
    assert len(json.loads(one.stdout)["files"]) == 200 and '"code": "' in one.stdout
    assert dask_run.stdout == one.stdout
    assert dask_run.stderr == one.stderr
    assert dask_reports == one_reports


def test_a_worker_killed_mid_run_loses_nothing(
    maps: Path, cluster: LocalCluster, plugin: Callable[[Any, str], None], tmp_path: Path
) -> None:
    marker = tmp_path / "killed"
    plugin(KillOnce(str(marker)), "kill-once")
    one = run("check", "-f", "json", "-j", "1", maps)
    killed = run("check", "-f", "json", "--scheduler", cluster.scheduler_address, maps)
    assert marker.exists(), "no worker was killed"
    assert killed.exit_code == one.exit_code == 1, killed.stderr
    assert killed.stdout == one.stdout


def _with_culprit(folder: Path) -> Path:
    folder.mkdir()
    for number in range(6):
        name = "crash.xodr" if number == 2 else f"map{number}.xodr"
        shutil.copy(REPO / "examples" / "broken.xodr", folder / name)
    return folder


def test_a_file_that_breaks_the_linter_is_its_internal_error_as_with_jobs(
    cluster: LocalCluster,
    plugin: Callable[[Any, str], None],
    tmp_path: Path,
) -> None:
    maps = _with_culprit(tmp_path / "maps")
    plugin(FailOn("crash"), "fail-on-crash")
    on_cluster = run("check", "-f", "json", "--scheduler", cluster.scheduler_address, maps)
    in_process = FailOn("crash")
    in_process.setup(None)  # the same failure in this process, for --jobs 1
    try:
        one = run("check", "-f", "json", "-j", "1", maps)
    finally:
        in_process.teardown(None)
    assert on_cluster.exit_code == one.exit_code == 3
    assert on_cluster.stdout == one.stdout
    line = f"xodrlint: internal error: linting {maps.as_posix()}/crash.xodr failed: "
    assert on_cluster.stderr == one.stderr
    assert f"{line}RuntimeError('simulated failure')\n" in on_cluster.stderr
    counted = {Path(f["path"]).name: f["findings"] for f in json.loads(on_cluster.stdout)["files"]}
    assert counted == {"crash.xodr": 0, **{f"map{n}.xodr": 6 for n in (0, 1, 3, 4, 5)}}


def _allow_failures(count: int, dask_scheduler: Any) -> None:
    dask_scheduler.allowed_failures = count


def test_a_file_that_kills_its_workers_is_an_error_and_the_rest_go_on(
    cluster: LocalCluster, client: Client, plugin: Callable[[Any, str], None], tmp_path: Path
) -> None:
    maps = _with_culprit(tmp_path / "maps")
    plugin(FailOn("crash", kill=True), "kill-on-crash")
    # a task is given up at its first worker's death (each death is a worker restart,
    # seconds): the culprit dies once in its batch, once alone
    client.run_on_scheduler(_allow_failures, 0)
    try:
        result = run("check", "-f", "concise", "--scheduler", cluster.scheduler_address, maps)
    finally:
        client.run_on_scheduler(_allow_failures, 1)
    assert result.exit_code == 2
    crashed = f"xodrlint: {maps.as_posix()}/crash.xodr: the worker linting it crashed"
    assert result.stderr.splitlines()[0] == crashed
    linted = {line.split(":")[0] for line in result.stdout.splitlines() if ".xodr:" in line}
    assert linted == {f"{maps.as_posix()}/map{n}.xodr" for n in (0, 1, 3, 4, 5)}


def test_each_worker_builds_one_linter_and_files_go_in_a_few_batches_largest_first(
    maps: Path, client: Client, plugin: Callable[[Any, str], None], monkeypatch: pytest.MonkeyPatch
) -> None:
    plugin(CountLinters(), "count-linters")
    files = sorted(maps.iterdir())
    tasks = [Task(path, path.name) for path in files]
    submitted: list[list[Task]] = []
    real_submit = client.submit

    def recording_submit(function: Any, plugin_name: str, batch: list[Task], **kwargs: Any) -> Any:
        submitted.append(batch)
        return real_submit(function, plugin_name, batch, **kwargs)

    monkeypatch.setattr(client, "submit", recording_submit)
    done = dict(lint_on_cluster(client, LintOptions(), tasks))
    assert sorted(done) == list(range(len(tasks)))
    assert [done[index].path for index in range(len(tasks))] == [path.name for path in files]
    assert client.run(linters_built) == dict.fromkeys(client.nthreads(), 1)
    sizes = [path.stat().st_size for path in files]
    expected = schedule(range(len(tasks)), sizes, 2)
    assert [[tasks.index(task) for task in batch] for batch in submitted] == expected
    assert len(submitted) <= len(tasks) // 4
    assert max(sizes) == max(task.path.stat().st_size for task in submitted[0])
    plugins = client.run_on_scheduler(lambda dask_scheduler: list(dask_scheduler.worker_plugins))
    assert not [name for name in plugins if name.startswith("xodrlint-")]  # released


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def test_an_unreachable_scheduler_is_one_line_and_exit_2_within_the_timeout(maps: Path) -> None:
    address = f"tcp://127.0.0.1:{_free_port()}"  # bound and let go: nothing listens there
    started = time.monotonic()
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "xodrlint",
            "check",
            "--scheduler",
            address,
            "--scheduler-timeout",
            "3",
            maps,
        ],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    elapsed = time.monotonic() - started
    assert done.returncode == 2
    assert (
        done.stderr == f"xodrlint: --scheduler {address}: cannot reach the scheduler within 3 s\n"
    )
    assert done.stdout == ""
    assert 3 <= elapsed < 10


@pytest.mark.parametrize("answer", ["nothing", "a frame of 8 GiB"])
def test_a_peer_that_accepts_and_never_answers_is_one_line_and_exit_2(
    maps: Path, answer: str
) -> None:
    # issue 30, item 9: still hanging at 150 s with a 5 s limit
    import struct
    import threading

    server = socket.create_server(("127.0.0.1", 0))
    server.settimeout(0.1)
    held: list[socket.socket] = []
    stop = threading.Event()

    def accept() -> None:
        while not stop.is_set():
            try:
                peer, _ = server.accept()
            except OSError:  # the timeout: look at stop again
                continue
            held.append(peer)
            if answer != "nothing":  # what a hostile peer announces, then nothing
                peer.sendall(struct.pack("<QQQ", 8 * 1024**3, 1, 8 * 1024**3))

    listening = threading.Thread(target=accept, daemon=True)
    listening.start()
    address = f"tcp://127.0.0.1:{server.getsockname()[1]}"
    started = time.monotonic()
    try:
        done = subprocess.run(
            [sys.executable, "-m", "xodrlint", "check", "--scheduler", address,
             "--scheduler-timeout", "2", maps],
            capture_output=True, text=True, timeout=120, check=False,
        )  # fmt: skip
    finally:
        stop.set()
        listening.join()
        server.close()
        for peer in held:
            peer.close()
    assert done.returncode == 2, done.stderr
    (line,) = done.stderr.splitlines()
    assert line == f"xodrlint: --scheduler {address}: the scheduler did not answer within 2 s"
    assert time.monotonic() - started < 30


def test_an_address_that_is_none_is_one_line_and_exit_2(maps: Path) -> None:
    result = run("check", "--scheduler", "scheduler-without-port", maps)
    assert result.exit_code == 2
    assert result.stderr == (
        "xodrlint: --scheduler scheduler-without-port: not a scheduler address: "
        "missing port number in address 'scheduler-without-port'\n"
    )


def _run_tasks(client: Client) -> int:
    keys = client.run_on_scheduler(lambda dask_scheduler: [str(k) for k in dask_scheduler.tasks])
    return sum(key.startswith(LINT_KEY) for key in keys)


def test_ctrl_c_cancels_the_runs_work_on_the_cluster(
    maps: Path, cluster: LocalCluster, client: Client, plugin: Callable[[Any, str], None]
) -> None:
    plugin(Slow(0.05), "slow")  # 200 files: 5 s on two workers
    command = [sys.executable, "-m", "xodrlint", "check", "-f", "json", "-o", os.devnull]
    interrupted = subprocess.Popen(
        [*command, "--scheduler", cluster.scheduler_address, maps],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 60
    while _run_tasks(client) == 0:
        assert interrupted.poll() is None and time.monotonic() < deadline, "the run never started"
        time.sleep(0.05)
    interrupted.send_signal(signal.SIGINT)
    _, err = interrupted.communicate(timeout=60)
    assert interrupted.returncode == 130, err
    assert "Traceback" not in err and "Warning" not in err, err
    deadline = time.monotonic() + 10
    while _run_tasks(client):  # cancelled: the scheduler forgets them
        assert time.monotonic() < deadline, "the run's tasks stayed on the cluster"
        time.sleep(0.05)
    plugins = client.run_on_scheduler(lambda dask_scheduler: list(dask_scheduler.worker_plugins))
    assert not [name for name in plugins if name.startswith("xodrlint-")]


def test_a_local_cluster_gives_the_same_report_and_stops_with_the_run(maps: Path) -> None:
    before = set(multiprocessing.active_children())
    some = sorted(maps.iterdir())[::10]
    one = run("check", "-f", "json", "-j", "1", *some)
    local = run("check", "-f", "json", "--scheduler", "local", "--jobs", "2", *some)
    assert local.exit_code == one.exit_code == 1, local.stderr
    assert local.stdout == one.stdout
    assert local.stderr == one.stderr
    assert set(multiprocessing.active_children()) <= before  # its workers are gone


def _members(group: int) -> list[int]:
    members = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[2]) == group and fields[0] != "Z":
                members.append(int(entry.name))
    return members


def _interrupted_locally(
    tmp_path: Path, output: list[str], ready: Callable[[subprocess.Popen[str]], bool]
) -> str:
    """Ctrl-C to a run on a local cluster of two workers (3000 maps) once ``ready`` says
    so; checks that it stops as a Ctrl-C should, whatever the machine's load: exit 130,
    no traceback, nothing left to the resource tracker of multiprocessing (which says
    what a run leaked: the semaphores of a cluster never closed), and none of its
    processes left. Returns its standard error."""
    maps = tmp_path / "maps"
    maps.mkdir()
    for number in range(3000):
        shutil.copyfile(REPO / "examples" / "broken.xodr", maps / f"m{number:04}.xodr")
    command = [sys.executable, "-m", "xodrlint", "check", *output]
    interrupted = subprocess.Popen(
        [*command, "--scheduler", "local", "--jobs", "2", maps],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group: its workers are found by it
    )
    try:
        deadline = time.monotonic() + 120
        while not ready(interrupted):
            assert interrupted.poll() is None, interrupted.communicate()[1]
            assert time.monotonic() < deadline, "the run never got there"
            time.sleep(0.02)
        interrupted.send_signal(signal.SIGINT)
        _, err = interrupted.communicate(timeout=120)
    finally:
        if interrupted.poll() is None:
            os.killpg(interrupted.pid, signal.SIGKILL)
    assert interrupted.returncode == 130, err
    assert "Traceback" not in err, err
    assert "resource_tracker" not in err and "leaked" not in err, err
    deadline = time.monotonic() + 30
    while _members(interrupted.pid):
        assert time.monotonic() < deadline, "the local cluster's processes outlived the run"
        time.sleep(0.05)
    return err


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc to see the workers")
def test_ctrl_c_while_a_local_cluster_starts_stops_it(tmp_path: Path) -> None:
    # a process of the cluster beside the run's own: its start is under way (a second or
    # two, or many on a busy machine), and Ctrl-C waits for it to close it
    report = tmp_path / "report.json"
    _interrupted_locally(
        tmp_path, ["-f", "json", "-o", str(report)], lambda run: len(_members(run.pid)) >= 2
    )
    assert not report.exists()


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc to see the workers")
def test_ctrl_c_while_a_local_cluster_lints_stops_it(tmp_path: Path) -> None:
    def linting(run: subprocess.Popen[str]) -> bool:
        assert run.stdout is not None
        if not select.select([run.stdout], [], [], 0.5)[0]:
            return False
        return bool(run.stdout.readline())  # the first reports: the workers lint

    _interrupted_locally(tmp_path, ["-f", "jsonl"], linting)


def test_a_first_ctrl_c_is_held_while_a_cluster_starts_and_a_second_is_not() -> None:
    before = signal.getsignal(signal.SIGINT)
    with engine._held_signals() as came:
        signal.raise_signal(signal.SIGINT)  # held: the start goes on
        assert came == [signal.SIGINT]
    assert signal.getsignal(signal.SIGINT) is before
    with pytest.raises(KeyboardInterrupt), engine._held_signals() as came:
        signal.raise_signal(signal.SIGINT)
        signal.raise_signal(signal.SIGINT)  # the user insists: at once
        pytest.fail("the second Ctrl-C was held too")
    assert signal.getsignal(signal.SIGINT) is before


def test_workers_that_cannot_build_a_linter_are_one_line_and_exit_2(
    maps: Path, cluster: LocalCluster, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(engine, "LinterPlugin", BrokenLinterPlugin)
    result = run("check", "--scheduler", cluster.scheduler_address, maps)
    assert result.exit_code == 2
    assert result.stderr == (
        f"xodrlint: --scheduler {cluster.scheduler_address}: the workers cannot build a linter "
        "(No module named 'xodrlint.runners.dask'): install this xodrlint, "
        f"{xodrlint.__version__}, with the same rule plugins, where they run\n"
    )


def test_jsonl_streams_from_the_cluster_the_lines_of_one_process(
    maps: Path, cluster: LocalCluster
) -> None:
    one = run("check", "-f", "jsonl", "-j", "1", maps)
    streamed = run("check", "-f", "jsonl", "--scheduler", cluster.scheduler_address, maps)
    assert streamed.exit_code == one.exit_code == 1, streamed.stderr
    lines = streamed.stdout.splitlines()
    assert len(lines) > 40 and sorted(lines) == sorted(one.stdout.splitlines())
    assert streamed.stderr == one.stderr


def test_workers_with_other_rules_than_the_run_are_one_line_and_exit_2(
    maps: Path, cluster: LocalCluster, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a pack installed here and not there (or the other way): their reports would differ
    # from --jobs's in silence
    selected = engine._selected

    def one_rule_fewer(*args: Any) -> tuple[str, ...]:
        return selected(*args)[1:]

    monkeypatch.setattr(engine, "_selected", one_rule_fewer)
    result = run("check", "--scheduler", cluster.scheduler_address, maps)
    assert result.exit_code == 2
    (line,) = result.stderr.splitlines()
    assert (
        "the workers cannot build a linter (its rules differ from this run's; it has PT001" in line
    )


def test_a_relative_schema_goes_out_absolute(
    cluster: LocalCluster, client: Client, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the workers' working folder is not this one's
    made: list[Any] = []

    class Capture(BrokenLinterPlugin):
        def __init__(self, options: Any, rules: Any = ()) -> None:
            super().__init__(options)
            made.append(options)

    monkeypatch.setattr(engine, "LinterPlugin", Capture)
    monkeypatch.chdir(REPO)
    tasks = [Task(Path("examples/clean.xodr"), "examples/clean.xodr")]
    with pytest.raises(engine.SchedulerError):
        list(lint_on_cluster(client, LintOptions(schema=Path("examples")), tasks))
    assert [options.schema for options in made[0]] == [REPO / "examples"]


def test_a_schema_a_worker_cannot_see_stops_the_run() -> None:
    plugin = engine.LinterPlugin([LintOptions(schema=Path("/nonexistent/schemas"))], [()])
    with pytest.raises(RuntimeError, match="the schema /nonexistent/schemas is not there"):
        plugin.setup(None)


# -- issue 30, item 1: a local cluster is no open door to the other users of the machine ---


def _refused(address: str, security: Any) -> None:
    """A peer of ``address`` with ``security`` (``None``: none) is turned away, fast:
    refused, not timed out. It speaks Dask's protocol itself (a comm, not a Client: a
    Client that failed to start leaves a half-made object whose finalizer complains)."""
    import asyncio

    from distributed.comm.core import CommClosedError, connect

    async def ask_identity() -> object:
        arguments = security.get_connection_args("client") if security is not None else {}
        comm = await connect(address, timeout=10, **arguments)
        try:  # what the review's script did next: ask, then run code
            await comm.write({"op": "identity"})
            return await comm.read()
        finally:
            await comm.close()

    started = time.monotonic()
    with pytest.raises((CommClosedError, OSError)):
        asyncio.run(ask_identity())
    assert time.monotonic() - started < 10, "not refused: the attempt timed out"


@pytest.mark.loopback  # the scheduler's HTTP routes, asked on 127.0.0.1
def test_a_local_cluster_refuses_peers_without_the_runs_credentials() -> None:
    import urllib.error
    import urllib.request

    from distributed.security import Security

    with engine.connect(engine.LOCAL, workers=1) as client:
        # its HTTP server speaks no TLS: it serves the health check alone (not the
        # logs, task errors and call stacks of the other routes)
        port = client.run_on_scheduler(lambda dask_scheduler: dask_scheduler.http_server.port)
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/health", timeout=10) as answer:
            assert answer.status == 200
        for route in ("info/main/workers.html", "json/counts.json", "metrics"):
            with pytest.raises(urllib.error.HTTPError, match="404"):
                urllib.request.urlopen(f"http://127.0.0.1:{port}/{route}", timeout=10)
        scheduler = str(client.scheduler_info()["address"])
        folders = client.run(lambda dask_worker: dask_worker.local_directory)
        assert scheduler.startswith("tls://127.0.0.1:")
        (worker,) = folders
        for address in (scheduler, worker):
            _refused(address.replace("tls://", "tcp://"), None)  # no TLS at all
            _refused(address, Security.temporary())  # TLS, but another authority's
        # the run's own client is served, and the workers spill into a private folder
        assert client.run(os.getpid)
        (folder,) = folders.values()
        private = Path(folder).parents[1]
        assert private.name.startswith("xodrlint-dask-")
        assert private.stat().st_mode & 0o077 == 0 and private.stat().st_uid == os.getuid()
    assert not private.exists()  # removed with the cluster


def test_a_local_cluster_without_cryptography_is_one_line(monkeypatch: pytest.MonkeyPatch) -> None:
    from distributed.security import Security

    def missing(cls: Any) -> Any:
        raise ImportError("Using `Security.temporary` requires `cryptography`")

    monkeypatch.setattr(Security, "temporary", classmethod(missing))
    with (
        pytest.raises(engine.SchedulerError, match=r"needs the 'cryptography' package"),
        engine.connect(engine.LOCAL, workers=1),
    ):
        pass  # pragma: no cover


def test_each_file_is_linted_under_its_own_configuration_on_the_cluster(
    cluster: LocalCluster, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a/ ignores what broken.xodr holds, b/ has no configuration: the workers keep a
    # linter per configuration and lint each file with its own
    (tmp_path / ".git").mkdir()
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        for copy in range(3):
            shutil.copy(REPO / "examples" / "broken.xodr", tmp_path / folder / f"{copy}.xodr")
    (tmp_path / "a" / "xodrlint.toml").write_text('ignore = ["XS", "SW", "RL", "ST"]\n', "utf-8")
    (tmp_path / "b" / "xodrlint.toml").write_text("warn-unused-suppressions = true\n", "utf-8")
    monkeypatch.chdir(tmp_path)
    alone = run("check", "-f", "json", "-j", "1", ".")
    on_cluster = run("check", "-f", "json", "--scheduler", cluster.scheduler_address, ".")
    assert on_cluster.exit_code == alone.exit_code == 1, on_cluster.stderr
    assert on_cluster.stdout == alone.stdout
    paths = {f["path"].split("/")[0] for f in json.loads(alone.stdout)["findings"]}
    assert paths == {"b"}
