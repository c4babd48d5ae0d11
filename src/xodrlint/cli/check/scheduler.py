"""``check --scheduler``: the run's files linted on a Dask cluster
(:mod:`xodrlint.runners.dask`), an engine of the shape every engine has
(:data:`~xodrlint.runners.batch.ReportStream`): reports as files complete, which the
run puts in input order or streams (``jsonl``).

Dask is imported only once a run has files to send: a run without ``--scheduler``, or
one whose options are refused, never pays for it.
"""

from __future__ import annotations

import contextlib
import importlib.util
from collections.abc import Generator, Sequence
from typing import TYPE_CHECKING, Final

from xodrlint.engine.linter import LintOptions
from xodrlint.findings import FileReport
from xodrlint.runners.batch import Engine, Task

if TYPE_CHECKING:
    from xodrlint.cli.check.request import CheckRequest

#: ``--scheduler local``: a cluster of this machine's own, started for the run (the name
#: :data:`xodrlint.runners.dask.LOCAL`, not imported from there: that imports Dask).
LOCAL: Final = "local"
#: Also ``pip install 'xodrlint[dask]'``, once xodrlint is on PyPI under that name.
INSTALL: Final = "pip install 'dask[distributed]' (or xodrlint's dask extra)"


class SchedulerUsageError(ValueError):
    """A ``--scheduler`` run that cannot go on: exit 2 with this one line."""


def check_scheduler(address: str | None, timeout: float | None, jobs: int | None) -> None:
    """Refuse, before anything is read or linted, what a ``--scheduler`` run cannot do."""
    if address is None:
        if timeout is not None:
            raise SchedulerUsageError("--scheduler-timeout applies only with --scheduler")
        return
    if timeout is not None and not timeout > 0:
        raise SchedulerUsageError(f"--scheduler-timeout {timeout:g}: expected seconds above 0")
    if jobs is not None and address != LOCAL:
        raise SchedulerUsageError(
            f"--jobs: the workers of --scheduler {address} are their own "
            "(--jobs sets how many --scheduler local starts)"
        )
    if importlib.util.find_spec("distributed") is None:
        raise SchedulerUsageError(f"--scheduler needs Dask, which is not installed: {INSTALL}")


def scheduler_engine(options: Sequence[LintOptions], request: CheckRequest) -> Engine | None:
    """The engine of a ``--scheduler`` run (``None`` without one): each file's report
    with its task's index, as the cluster completes it; ``options`` are the run's
    profiles' (:mod:`xodrlint.config.resolver`)."""
    address = request.scheduler
    if address is None:
        return None

    def engine(tasks: Sequence[Task]) -> Generator[tuple[int, FileReport], None, None]:
        if not tasks:  # nothing to send: no cluster to reach or start
            return
        from xodrlint.runners.dask import DEFAULT_TIMEOUT, SchedulerError, connect, lint_on_cluster

        timeout = request.scheduler_timeout or DEFAULT_TIMEOUT
        try:
            # closed when the run stops early (Ctrl-C, a reader gone): its work cancelled
            with (
                connect(address, timeout=timeout, workers=request.jobs) as client,
                contextlib.closing(lint_on_cluster(client, options, tasks)) as done,
            ):
                yield from done
        except SchedulerError as error:
            raise SchedulerUsageError(f"--scheduler {address}: {error}") from None

    return engine
