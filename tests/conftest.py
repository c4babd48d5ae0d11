"""Shared fixtures: an isolated schema environment and paths to the shared reference data."""

from __future__ import annotations

import os
import socket
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

# numpy's OpenBLAS starts a thread per core when it is imported (scipy, dask and pandas
# import it in this process): xodrlint forks workers and validation children only from
# a process that runs no thread but its own (Python 3.12 and later warn of deadlocks
# otherwise), so the tests that need a fork would silently take the other path
for _pool in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_pool, "1")

#: The plugin that runs xodrlint's own rules as a pack under test (tests/rules/test_rule_cases.py,
#: tests/test_docs.py), loaded by name as a third-party pack loads it with -p.
pytest_plugins = ["xodrlint.testing.plugin"]

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"
SHARED_SCHEMAS = SHARED / "schemas"
CORPUS_RAIL = SHARED / "corpus" / "rail"

needs_shared = pytest.mark.skipif(
    not SHARED_SCHEMAS.is_dir(), reason="../shared (official ASAM schemas, corpus) is absent"
)


@pytest.fixture(autouse=True)
def isolated_schemas(
    tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch
) -> Iterator[Path]:
    """No test sees the developer's schemas: empty user data folder, no schema path."""
    data = tmp_path_factory.mktemp("xodrlint-data")
    monkeypatch.setenv("XODRLINT_DATA_DIR", str(data))
    monkeypatch.setenv("XODRLINT_CACHE_DIR", str(tmp_path_factory.mktemp("xodrlint-cache")))
    monkeypatch.delenv("XODRLINT_SCHEMA_PATH", raising=False)
    monkeypatch.delenv("XODRLINT_DEBUG", raising=False)
    # a CI service's checkout folder would root the CI formats' paths there
    monkeypatch.delenv("CI_PROJECT_DIR", raising=False)
    monkeypatch.delenv("GITHUB_WORKSPACE", raising=False)
    # a worker's setup run in this process (a Dask plugin's, a batch chunk's) sets
    # XODRLINT_FORK=0 for its process: undone here, or every later test would validate
    # without threads
    from xodrlint.concurrency.background import ENV as FORK_SETTING

    monkeypatch.delenv(FORK_SETTING, raising=False)
    yield data


NETWORK_FAMILIES = (socket.AF_INET, socket.AF_INET6)


LOOPBACK_HOSTS = frozenset({"localhost", "127.0.0.1", "::1"})


@pytest.fixture(autouse=True)
def network_attempts(
    monkeypatch: pytest.MonkeyPatch, request: pytest.FixtureRequest
) -> Iterator[list[str]]:
    """xodrlint never goes on the network (schemas are fetched in tests from a local wheel),
    so any TCP or UDP connection a test makes is refused and fails it at teardown, even if
    the code under test swallowed the error. Local sockets (pipes of worker pools) pass,
    and so does loopback in a test marked ``loopback`` (selenium talks to chromedriver)."""
    attempts: list[str] = []
    loopback = request.node.get_closest_marker("loopback") is not None

    def allowed(address: Any) -> bool:
        return loopback and isinstance(address, tuple) and address[0] in LOOPBACK_HOSTS

    def guarded(real: Callable[..., Any]) -> Callable[..., Any]:
        def connect(self: socket.socket, address: Any, *args: Any) -> Any:
            if self.family in NETWORK_FAMILIES and not allowed(address):
                attempts.append(repr(address))
                raise ConnectionRefusedError(f"test network guard: connection to {address!r}")
            return real(self, address, *args)

        return connect

    real_create_connection = socket.create_connection

    def create_connection(address: Any, *args: Any, **kwargs: Any) -> socket.socket:
        if allowed(address):
            return real_create_connection(address, *args, **kwargs)
        attempts.append(repr(address))
        raise ConnectionRefusedError(f"test network guard: connection to {address!r}")

    monkeypatch.setattr(socket.socket, "connect", guarded(socket.socket.connect))
    monkeypatch.setattr(socket.socket, "connect_ex", guarded(socket.socket.connect_ex))
    monkeypatch.setattr(socket, "create_connection", create_connection)
    yield attempts
    assert not attempts, f"the test attempted network connections: {attempts}"


@pytest.fixture(scope="module")
def dask_cluster(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Any]:
    """A LocalCluster of two worker processes for a module (a start costs seconds), on
    the loopback interface. Its workers see no schemas of the developer's, as the tests'
    own process does not; a task whose workers die twice is given up (so that a test of
    a file that kills its worker stays short). Skipped where Dask is not installed."""
    pytest.importorskip(
        "distributed", reason="Dask is not installed: pip install 'dask[distributed]'"
    )
    import logging

    import dask
    from distributed import LocalCluster

    with pytest.MonkeyPatch.context() as patch:
        patch.delenv("XODRLINT_SCHEMA_PATH", raising=False)
        patch.setenv("XODRLINT_DATA_DIR", str(tmp_path_factory.mktemp("worker-data")))
        patch.setenv("XODRLINT_CACHE_DIR", str(tmp_path_factory.mktemp("worker-cache")))
        with (
            dask.config.set({"distributed.scheduler.allowed-failures": 1}),
            LocalCluster(  # type: ignore[no-untyped-call]
                n_workers=2,
                threads_per_worker=1,
                processes=True,
                host="127.0.0.1",
                dashboard_address=None,
                scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
                silence_logs=logging.CRITICAL,
            ) as started,
        ):
            yield started
    _release_dask_threads()


def _release_dask_threads() -> None:
    """Dask keeps a thread for the rest of the process's life once it has used it (its
    offload executor): the tests after a Dask module get a process without threads again,
    as a command-line run is, or their pools would not fork (``runners.batch``)."""
    import gc
    import threading
    import time
    from concurrent.futures import ThreadPoolExecutor

    from distributed import utils

    utils._offload_executor.shutdown(wait=True)
    utils._offload_executor = ThreadPoolExecutor(1, thread_name_prefix="Dask-Offload")
    # Every cluster and client of the module is closed by now; an event loop still
    # registered belongs to one that nothing closed (seen with distributed 2026.8 in the
    # whole test_dask module only, on main before the track-network work too, while
    # collecting garbage did not always end it): stopped here, so the next module starts
    # without threads
    gc.collect()
    for _count, runner in list(utils.LoopRunner._all_loops.values()):
        if runner is not None and runner._loop_thread is not None:
            runner._real_stop(timeout=10)  # type: ignore[no-untyped-call]
    deadline = time.monotonic() + 30
    while threading.active_count() > 1:  # the clients' event loops end as they close
        # an unreferenced Dask client or cluster held in a reference cycle stops its event
        # loop only when collected, and nothing allocates here to set the collector going:
        # its "IO loop" thread stayed, idle, until this gave up (distributed 2026.8, the
        # whole test_dask module; on main before the track-network work too)
        gc.collect()
        names = [thread.name for thread in threading.enumerate()]
        assert time.monotonic() < deadline, f"threads outlived the Dask tests: {names}"
        time.sleep(0.05)


@pytest.fixture(scope="module")
def dask_client(dask_cluster: Any) -> Iterator[Any]:
    """A client of :func:`dask_cluster` (the default one while it lives)."""
    from distributed import Client

    with Client(dask_cluster) as connected:  # type: ignore[no-untyped-call]
        yield connected


def record_forks(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The pids of the children ``os.fork`` makes from now on in this test."""
    forked: list[int] = []
    real_fork = os.fork

    def recorded_fork() -> int:
        pid = real_fork()
        if pid:
            forked.append(pid)
        return pid

    monkeypatch.setattr(os, "fork", recorded_fork)
    return forked
