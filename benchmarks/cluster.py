"""The Dask figures of benchmarks/run.py (issue 20): the inputs of ``--only dask``, and the
per-file overhead of a Dask run with the throughput it projects on N machines.

The overhead is measured on a scheduler and two workers started as ``dask scheduler``
and ``dask worker`` (on the loopback interface), so that each process's CPU time is its
own: the scheduler's (it handles every task), the client's (``xodrlint check
--scheduler``: collects the inputs, submits, receives each file's report, writes the
report) and the workers' (linting, and a Dask worker's own work). The model, in
docs/distributed.md, is

    wall(F files, N machines of c cores) = start + max(F * w / (N * c), T * s, F * k)

with w the workers' CPU seconds per file, s the scheduler's per task, k the client's
per file, T the tasks the run sends (its batches: ``runners.batch.schedule`` for N * c
worker threads), and ``start`` the client's start-up; the three terms overlap, as the
workers lint while the scheduler and client handle what came before.
"""

from __future__ import annotations

import os
import socket
import statistics
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

#: The files of the Dask figure, and their sizes (as the batch figure's).
SMALL_MAPS = 2000
#: Machines the model projects throughput for.
MACHINES = (1, 4, 16, 64, 256)
#: Files of the projected run.
PROJECTED_FILES = 1_000_000


def small_maps(folder: Path) -> Path:
    """2,000 maps of 20 to 26 KB in ``folder``/small-2000, written once."""
    from generate import network, write_pieces

    path = folder / f"small-{SMALL_MAPS}"
    if not path.exists():
        partial = path.with_name(f"small-{SMALL_MAPS}.part")
        partial.mkdir(exist_ok=True)
        for number in range(SMALL_MAPS):
            size = 20 * 1024 + (number % 7) * 1024
            write_pieces(partial / f"map-{number:04}.xodr", network(size))
        partial.replace(path)
    return path


@dataclass
class Overhead:
    """CPU seconds of each process of a Dask run, per run."""

    files: int
    tasks: int
    #: a run on one file: the client's start-up, wall and CPU
    one_wall: list[float] = field(default_factory=list)
    one_client: list[float] = field(default_factory=list)
    wall: list[float] = field(default_factory=list)
    scheduler: list[float] = field(default_factory=list)
    client: list[float] = field(default_factory=list)
    workers: list[float] = field(default_factory=list)

    @property
    def per_task_scheduler(self) -> float:
        return statistics.median(self.scheduler) / self.tasks

    @property
    def per_file_scheduler(self) -> float:
        return statistics.median(self.scheduler) / self.files

    @property
    def per_file_client(self) -> float:
        """Beyond its start-up (a run on one file): receiving reports, writing them."""
        more = statistics.median(self.client) - statistics.median(self.one_client)
        return max(0.0, more) / (self.files - 1)

    @property
    def start(self) -> float:
        return statistics.median(self.one_wall)

    @property
    def per_file_workers(self) -> float:
        return statistics.median(self.workers) / self.files


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def _cpu(pid: int) -> float:
    """CPU seconds of a process and every process below it."""
    import psutil  # a dependency of distributed

    top = psutil.Process(pid)
    total = 0.0
    for process in [top, *top.children(recursive=True)]:
        try:
            times = process.cpu_times()
        except psutil.NoSuchProcess:
            continue
        total += times.user + times.system
    return total


@contextmanager
def _cluster(env: dict[str, str], workers: int) -> Iterator[tuple[str, int, int]]:
    """A scheduler and ``workers`` worker processes on the loopback interface: their
    address and the two pids."""
    address = f"tcp://127.0.0.1:{_free_port()}"
    dask = [sys.executable, "-m", "dask"]
    common = ["--host", "127.0.0.1", "--no-dashboard"]
    port = address.rsplit(":", 1)[1]
    started = []
    try:
        for argv in (
            [*dask, "scheduler", "--port", port, *common],
            [*dask, "worker", address, "--nworkers", str(workers), "--nthreads", "1", *common],
        ):
            environment = {**os.environ, **env}
            quiet = subprocess.DEVNULL
            started.append(subprocess.Popen(argv, env=environment, stdout=quiet, stderr=quiet))
        _wait_for_workers(address, workers)
        yield address, started[0].pid, started[1].pid
    finally:
        for process in started:
            process.terminate()
            process.wait(timeout=60)


def _wait_for_workers(address: str, count: int) -> None:
    from distributed import Client

    deadline = time.monotonic() + 120
    while True:
        try:
            with Client(address, timeout=5, set_as_default=False) as client:
                client.wait_for_workers(count, timeout=120)
                return
        except OSError:
            if time.monotonic() > deadline:
                raise SystemExit(f"no Dask scheduler at {address} after 120 s") from None
            time.sleep(0.2)


def _client_run(argv: list[str], env: dict[str, str]) -> tuple[float, float]:
    """Wall and CPU seconds of one run of ``argv``."""
    started = time.perf_counter()
    process = subprocess.Popen(
        argv, env={**os.environ, **env}, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - started
    if os.waitstatus_to_exitcode(status) != 0:
        error = process.stderr.read().decode() if process.stderr else ""
        raise SystemExit(f"the Dask run failed: {error[-400:]}")
    return wall, usage.ru_utime + usage.ru_stime


def measure_overhead(check: list[str], env: dict[str, str], folder: Path, rounds: int) -> Overhead:
    """``rounds`` runs of ``check --scheduler`` on ``folder`` against a scheduler with two
    workers, each process's CPU time measured."""
    from xodrlint.runners.batch import schedule

    files = sorted(folder.iterdir())
    sizes = [path.stat().st_size for path in files]
    found = Overhead(len(files), len(schedule(range(len(files)), sizes, 2)))
    with _cluster(env, 2) as (address, scheduler, workers):
        argv = [*check, "--scheduler", address, str(folder)]
        _client_run(argv, env)  # warm-up: page cache, the workers' first imports
        for _ in range(rounds):
            wall, client = _client_run([*argv[:-1], str(files[0])], env)
            found.one_wall.append(wall)
            found.one_client.append(client)
            before = _cpu(scheduler), _cpu(workers)
            wall, client = _client_run(argv, env)
            after = _cpu(scheduler), _cpu(workers)
            found.wall.append(wall)
            found.client.append(client)
            found.scheduler.append(after[0] - before[0])
            found.workers.append(after[1] - before[1])
    return found


def _terms(found: Overhead, files: int, threads: int, tasks: int) -> dict[str, float]:
    """Seconds each of the three serial parts takes for ``files`` on ``threads``."""
    return {
        "workers": files * found.per_file_workers / threads,
        "scheduler": tasks * found.per_task_scheduler,
        "client": files * found.per_file_client,
    }


def model(found: Overhead, cores: int) -> list[str]:
    """The lines of the projection: files a second on N machines of ``cores`` cores."""
    from xodrlint.runners.batch import schedule

    start = found.start
    lines = [
        f"per file: workers {found.per_file_workers * 1000:.2f} ms CPU, client "
        f"{found.per_file_client * 1000:.3f} ms, "
        f"scheduler {found.per_file_scheduler * 1000:.3f} ms "
        f"({found.per_task_scheduler * 1000:.1f} ms a task, {found.tasks} tasks for "
        f"{found.files} files); run wall {statistics.median(found.wall):.2f} s, "
        f"on one file {start:.2f} s",
        f"projected, {PROJECTED_FILES:,} files on machines of {cores} cores:",
    ]
    sizes = [1] * PROJECTED_FILES
    for machines in MACHINES:
        threads = machines * cores
        tasks = len(schedule(range(PROJECTED_FILES), sizes, threads))
        terms = _terms(found, PROJECTED_FILES, threads, tasks)
        bound = max(terms, key=lambda name: terms[name])
        wall = start + terms[bound]
        lines.append(
            f"  {machines:>4} machines: {PROJECTED_FILES / wall:>8,.0f} files/s "
            f"({wall:,.0f} s, {tasks:,} tasks; bound by the {bound})"
        )
    return lines
