"""Many files on a Dask cluster: the engine of ``check --scheduler`` and of
:mod:`xodrlint.distributed`.

Each worker process builds the run's :class:`~xodrlint.engine.linter.Linter` once, when a
:class:`LinterPlugin` registered for the run sets it up (so each schema is compiled once
per worker, as in the forked pool), and lints batches of files: the largest first, in
batches that shrink as the work left does (:func:`~xodrlint.runners.batch.schedule`), so
that the scheduler handles tens of tasks for thousands of files. A task sends back one
small :class:`~xodrlint.findings.FileReport` per file, never a map.

Faults: Dask runs again the tasks of a worker that died (up to the scheduler's
``allowed-failures``) and a task that raised (``retries``); a batch that kept killing
its workers is split, each file retried alone, and a file that kills its worker even so
is that file's error. The run's plugin and futures are released when it ends, however it
ends (Ctrl-C included).

Imported only when a run asks for Dask: it imports ``distributed``.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import tempfile
import threading
import uuid
from collections.abc import Generator, Iterator, Sequence
from contextlib import contextmanager
from types import FrameType
from typing import Final

from distributed import Client, Future, LocalCluster, WorkerPlugin, as_completed, get_worker
from distributed.client import FutureCancelledError
from distributed.comm.addressing import get_address_host_port
from distributed.scheduler import KilledWorker
from distributed.security import Security

from xodrlint import __version__
from xodrlint.concurrency import background
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import FileReport
from xodrlint.rules.registry import Registry, load_registry
from xodrlint.runners.batch import Task, default_jobs, lint_task, schedule, task_size

#: ``--scheduler`` for a cluster of this machine's own, started for the run.
LOCAL: Final = "local"
#: Times Dask runs a task again after it raised (a worker's transient failure: memory,
#: a network file system); a worker's death is the scheduler's ``allowed-failures``.
DEFAULT_RETRIES: Final = 2
#: Seconds to reach a scheduler, and for a worker to join it, unless told otherwise.
DEFAULT_TIMEOUT: Final = 30.0
#: Held while a local cluster starts: Ctrl-C, and what a cancelled CI job sends.
_HELD_SIGNALS: Final = (signal.SIGINT, signal.SIGTERM)


class SchedulerError(Exception):
    """The cluster cannot be used: the scheduler is out of reach, or has no worker."""


class LinterPlugin(WorkerPlugin):
    """Warm linters per worker process for one run, one per profile (the configurations
    the run's files fall under), built from the run's options when the worker joins (or
    when the run starts, on a worker already there)."""

    def __init__(self, options: Sequence[LintOptions], rules: Sequence[tuple[str, ...]]) -> None:
        self.options = tuple(options)
        self.rules = tuple(rules)
        """Each profile's rule codes in the client's run: the worker's must be these."""
        self.linters: list[Linter] | None = None
        self.lock: threading.Lock | None = None

    def setup(self, worker: object) -> None:
        # beside other workers that keep every core busy: a thread of its own for each
        # file's validation would only add switches (as in batch's workers)
        os.environ[background.ENV] = "0"
        registry = load_registry()
        linters = []
        for options, rules in zip(self.options, self.rules, strict=True):
            schema = options.schema
            if schema is not None and not schema.exists():  # else: the built-in, silently
                raise RuntimeError(f"the schema {schema} is not there on the worker")
            linter = Linter(registry, options)
            _same_rules(tuple(rule.code for rule in linter.rules), rules)
            linters.append(linter)
        self.linters = linters
        # a worker with several threads runs several tasks at once: they take turns,
        # as a linter is made for one caller at a time
        self.lock = threading.Lock()


def _same_rules(found: tuple[str, ...], expected: tuple[str, ...]) -> None:
    if found != expected:  # other rule packs there: another report than --jobs's
        lacking = sorted(set(expected) - set(found))
        more = sorted(set(found) - set(expected))
        raise RuntimeError(
            "its rules differ from this run's"
            + (f"; it lacks {', '.join(lacking)}" if lacking else "")
            + (f"; it has {', '.join(more)} too" if more else "")
        )


def lint_batch(plugin: str, tasks: Sequence[Task]) -> list[FileReport]:
    """A task on a worker: ``tasks``' reports, in their order, each with the linter of
    its profile in the run's plugin (named ``plugin``)."""
    worker = get_worker()
    found = worker.plugins.get(plugin)
    if not isinstance(found, LinterPlugin) or found.linters is None or found.lock is None:
        raise RuntimeError(f"worker {worker.address} has no linter for this run ({plugin})")
    linters = found.linters
    with found.lock:
        return [lint_task(linters[task.profile], task) for task in tasks]


@contextmanager
def connect(
    address: str, *, timeout: float = DEFAULT_TIMEOUT, workers: int | None = None
) -> Iterator[Client]:
    """A client of the scheduler at ``address``, or of a cluster of ``workers`` processes
    (default: one per core) started on this machine for :data:`LOCAL`; closed, and the
    local cluster stopped, on the way out."""
    if address == LOCAL:
        # A LocalCluster interrupted while it starts is left half made, and nothing closes
        # it (it closes itself on an Exception, and KeyboardInterrupt is none): its worker
        # processes outlive the run's clean-up, and the semaphores of its nannies' queues
        # are left to multiprocessing's resource tracker, which warns of them. So Ctrl-C
        # waits for the start (seconds), then stops the run as it would have stopped it
        # a moment later, the cluster closed on the way out.
        with tempfile.TemporaryDirectory(prefix="xodrlint-dask-") as scratch:
            with _held_signals() as came:
                cluster = _local_cluster(workers or default_jobs(), scratch)
            with cluster, Client(cluster) as client:
                if came:
                    signal.raise_signal(came[0])  # its handler, given back, raises here
                yield client
        return
    if address.startswith("tls://") and not _tls_configured():
        # checked first: a Client that fails on it leaves a traceback from its __del__
        raise SchedulerError(
            "a tls:// scheduler needs dask's TLS configuration (distributed.comm.tls)"
        )
    try:
        # an address that cannot be one is said before any client is made (a half-made
        # client's finalizer complains later, in whatever code collects it)
        get_address_host_port(address)
        client = _client_within(address, timeout)
    except ValueError as error:  # dask names what is wrong with the address
        raise SchedulerError(f"not a scheduler address: {error}") from None
    except TypeError:  # tls:// without dask's TLS configuration (its certificates)
        raise SchedulerError(
            "a tls:// scheduler needs dask's TLS configuration (distributed.comm.tls)"
        ) from None
    except OSError:
        raise SchedulerError(f"cannot reach the scheduler within {timeout:g} s") from None
    with client:
        try:
            client.wait_for_workers(1, timeout=timeout)
        except TimeoutError:
            raise SchedulerError(f"no worker joined the scheduler within {timeout:g} s") from None
        yield client


def _client_within(address: str, timeout: float) -> Client:
    """A client of ``address``, made within ``timeout`` seconds (and a little more for
    the client's own start): Dask's ``timeout`` bounds the connection, not the answer,
    and a peer that accepted and never answered held a run for ever. Past the deadline
    the attempt is left to its daemon thread, and the run ends (exit 2)."""
    made: list[Client] = []
    failed: list[BaseException] = []
    lock, abandoned = threading.Lock(), threading.Event()

    def make() -> None:
        try:
            client = Client(address, timeout=timeout, set_as_default=False)
        except BaseException as error:  # handed to the caller, whatever it is
            failed.append(error)
            return
        with lock:
            if not abandoned.is_set():
                made.append(client)
                return
        with contextlib.suppress(Exception):  # too late: nobody else would close it
            client.close()

    attempt = threading.Thread(target=make, name="xodrlint-connect", daemon=True)
    attempt.start()
    attempt.join(timeout + _CLIENT_START_SECONDS)
    with lock:
        if not made:
            abandoned.set()
    if failed:
        error = failed[0]
        if isinstance(error, MemoryError):  # a frame announced larger than the memory
            raise SchedulerError("the scheduler's answer could not be read (MemoryError)")
        raise error
    if not made:
        raise SchedulerError(f"the scheduler did not answer within {timeout:g} s")
    return made[0]


#: Seconds a client takes to start besides connecting (its thread, its event loop).
_CLIENT_START_SECONDS: Final = 5.0


@contextmanager
def _held_signals() -> Iterator[list[int]]:
    """Holds SIGINT and SIGTERM while the block runs, and yields those that came, for the
    caller to deliver (:func:`signal.raise_signal`) once it can clean up. A second one of
    the same is not held but handled at once: the user insists. Only the main thread sets
    handlers, and only a handler Python set can be given back: elsewhere nothing is held,
    and neither is an ignored signal."""
    came: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield came
        return
    given = {number: signal.getsignal(number) for number in _HELD_SIGNALS}
    held = {
        number: handler
        for number, handler in given.items()
        if handler is not None and handler != signal.SIG_IGN
    }

    def hold(number: int, frame: FrameType | None) -> None:
        if number not in came:
            came.append(number)
            return
        handler = held[signal.Signals(number)]
        signal.signal(number, handler)
        if callable(handler):
            handler(number, frame)
        else:  # the default action: the process ends
            signal.raise_signal(number)

    for number in held:
        signal.signal(number, hold)
    try:
        yield came
    finally:
        for number, handler in held.items():
            signal.signal(number, handler)


def _tls_configured() -> bool:
    import dask

    return bool(dask.config.get("distributed.comm.tls.ca-file", None))


def _local_cluster(workers: int, scratch: str) -> LocalCluster:
    """Processes with one thread each (the linter holds the GIL for most of a file), on
    the loopback interface, without a dashboard; the scheduler's HTTP routes (health,
    metrics), which it serves even then, take any free port, so that a run beside
    another cluster does not warn about 8787.

    The loopback interface is no boundary on a machine with other users (a shared CI
    runner): any local process can connect to a port there, and a Dask client that
    connects runs code in the scheduler and the workers. So the cluster speaks TLS with
    credentials made for this run alone (a self-signed authority in memory, never on
    disk), and requires them of every peer: a client without them is refused. Its
    workers keep their spill files in ``scratch``, this run's private folder, not in the
    shared ``/tmp/dask-scratch-space``.
    """
    try:
        security = Security.temporary()
    except ImportError:
        raise SchedulerError(
            "--scheduler local needs the 'cryptography' package for the cluster's TLS "
            "credentials: pip install 'xodrlint[dask]'"
        ) from None
    import dask

    # the scheduler's and workers' HTTP servers speak no TLS: of their routes, only the
    # health check (the others show logs, task errors and call stacks to any local user)
    only_health = ["distributed.http.health"]
    try:
        with dask.config.set(
            {
                "distributed.scheduler.http.routes": only_health,
                "distributed.worker.http.routes": only_health,
            }
        ):
            return _started_cluster(workers, scratch, security)
    except OSError as error:
        raise SchedulerError(f"cannot start a local cluster: {error}") from None


def _started_cluster(workers: int, scratch: str, security: Security) -> LocalCluster:
    return LocalCluster(
        n_workers=workers,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        protocol="tls://",
        security=security,
        local_directory=scratch,
        dashboard_address=None,
        scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
        # its workers' logs are no report of the run (a failed task or a dead worker is
        # said through the futures): at ERROR, a heartbeat that met the scheduler
        # closing on Ctrl-C printed a traceback, now and then, slower with TLS
        silence_logs=logging.CRITICAL,
    )


def lint_on_cluster(
    client: Client,
    options: LintOptions | Sequence[LintOptions],
    tasks: Sequence[Task],
    *,
    retries: int = DEFAULT_RETRIES,
) -> Generator[tuple[int, FileReport], None, None]:
    """Lint ``tasks`` on ``client``'s cluster: each report with its index in ``tasks``,
    as it completes (an ``Iterator[tuple[int, FileReport]]``, as every engine's). The
    run's worker plugin and futures are released when it ends or is closed."""
    if not tasks:
        return
    # a worker's working folder is not this process's: each file by its absolute path
    # (its reports name it as it was given)
    tasks = [task._replace(path=task.path.absolute()) for task in tasks]
    profiles = [options] if isinstance(options, LintOptions) else list(options)
    profiles = [
        each._replace(schema=each.schema.absolute()) if each.schema is not None else each
        for each in profiles
    ]
    registry = load_registry()
    rules = [_selected(registry, each) for each in profiles]
    plugin = f"xodrlint-{uuid.uuid4().hex}"
    try:
        client.register_plugin(LinterPlugin(profiles, rules), name=plugin)
    except Exception as error:  # raised on a worker: its xodrlint is missing or another
        raise SchedulerError(
            f"the workers cannot build a linter ({error}): install this xodrlint, "
            f"{__version__}, with the same rule plugins, where they run"
        ) from None
    try:
        yield from _lint_all(client, plugin, tasks, retries)
    finally:
        # a scheduler already gone takes the plugin with it: nothing is left to release
        with contextlib.suppress(OSError):
            client.unregister_worker_plugin(plugin)


def _selected(registry: Registry, options: LintOptions) -> tuple[str, ...]:
    """The codes of the rules a linter with ``options`` runs (XL001 with
    ``warn_unused_suppressions``, as the linter adds it)."""
    return tuple(rule.code for rule in Linter(registry, options).rules)


def _lint_all(
    client: Client, plugin: str, tasks: Sequence[Task], retries: int
) -> Iterator[tuple[int, FileReport]]:
    threads = max(1, sum(client.nthreads().values()))
    chunks = schedule(range(len(tasks)), [task_size(task) for task in tasks], threads)
    lost: list[int] = []
    alone: list[int] = []
    for chunk, reports in _run(client, plugin, tasks, chunks, retries):
        if reports is None:
            (lost if len(chunk) > 1 else alone).extend(chunk)
        else:
            yield from zip(chunk, reports, strict=True)
    # Each file of a batch that kept killing its workers in a task of its own, then each
    # one that failed in a task of its own alone on the cluster: a worker's death counts
    # against every task it held, so a file queued behind the culprit may have failed
    # beside it.
    for chunk, reports in _run(client, plugin, tasks, [[index] for index in lost], retries):
        if reports is None:
            alone.extend(chunk)
        else:
            yield chunk[0], reports[0]
    for index in sorted(alone):
        for _, reports in _run(client, plugin, tasks, [[index]], retries):
            shown = tasks[index].display
            crashed = FileReport(shown, error=f"{shown}: the worker linting it crashed")
            yield index, crashed if reports is None else reports[0]


def _run(
    client: Client, plugin: str, tasks: Sequence[Task], chunks: list[list[int]], retries: int
) -> Iterator[tuple[list[int], list[FileReport] | None]]:
    """Each chunk with its reports as it completes, or ``None`` when workers kept dying
    while running it; what is still pending when this ends early is cancelled."""
    futures: dict[Future[list[FileReport]], list[int]] = {}
    run = uuid.uuid4().hex[:8]
    for number, chunk in enumerate(chunks):
        future = client.submit(
            lint_batch,
            plugin,
            [tasks[index] for index in chunk],
            key=f"xodrlint-lint-{run}-{number}",
            retries=retries,
            priority=len(chunks) - number,  # the largest files first, as scheduled
            pure=False,
        )
        futures[future] = chunk
    try:
        for future in as_completed(list(futures), loop=client.loop):
            chunk = futures.pop(future)
            try:
                reports: list[FileReport] | None = future.result()
            except KilledWorker:
                reports = None
            except FutureCancelledError as error:  # the scheduler was lost, or restarted
                raise SchedulerError(f"the run's work was cancelled: {error}") from None
            future.release()
            yield chunk, reports
    finally:
        if futures:
            with contextlib.suppress(OSError):  # no scheduler left: nothing to cancel
                client.cancel(list(futures))
