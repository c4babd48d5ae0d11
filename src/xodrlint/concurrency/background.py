"""Work that runs beside the rules: schema validation in a thread or a forked child.

lxml releases Python's GIL while libxml2 validates a whole document, so a thread
overlaps that validation with the model and the rules at no cost: no copy of the tree,
no pickling, and no copy-on-write page faults, which a forked child causes on every page
of the tree the parent touches after the fork (on a 20 MB map the thread made the whole
run 10% faster than the fork). A task may run in a thread only when it reads the tree
and spends its time in such C code (``thread_safe``): lxml validates a *subtree* by
pointing its children at a stand-in root for the time of the validation, which another
thread walking the tree would see.

Other work that is worth running beside the rules (XSD 1.1 checks in Python) runs in a
forked child: it shares the parsed tree copy-on-write, computes on the second core, and
sends back plain values (picklable error entries). Without ``os.fork`` (Windows), or when
the child fails for any reason, the work simply runs in the caller.

Only large documents are worth either.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, Final, Generic, TypeVar, cast

from lxml import etree

from xodrlint.document.positions import TreePositions
from xodrlint.findings import Hit
from xodrlint.fixes import Applicability, Fix, InsertElement, ReplaceComment, SetAttribute

_T = TypeVar("_T")

#: Below this many bytes a fork is not worth it: the overlap saves little
#: (the fork costs more than it saves).
MIN_BYTES: Final = 4 * 1024 * 1024
#: Set to "0" to keep all work in the calling thread (debugging, measuring).
ENV: Final = "XODRLINT_FORK"


class Pending(Generic[_T]):
    """A value being computed; :meth:`result` waits for it."""

    def __init__(self, compute: Callable[[], _T]) -> None:
        self._compute = compute
        self._done = False
        self._value: _T | None = None

    def result(self) -> _T:
        if not self._done:
            self._value = self._compute()
            self._done = True
        return self._value  # type: ignore[return-value]


def can_fork(size: int) -> bool:
    # Never fork a process that runs other threads (an application calling the API from
    # a thread pool): a lock one of them holds would stay locked in the child for ever.
    return (
        size >= MIN_BYTES
        and hasattr(os, "fork")
        and sys.platform.startswith("linux")
        and os.environ.get(ENV, "1") != "0"
        and single_threaded()
    )


def single_threaded() -> bool:
    """Whether this process runs one thread, the caller's: Python's threads and those a
    C library started on its own (a BLAS pool, a Dask loop's), which
    ``threading.active_count`` does not see, and which made Python 3.12 and later warn
    that a fork may deadlock. Linux lists a process's threads in ``/proc/self/task``."""
    if threading.active_count() != 1:
        return False
    try:
        threads = Path("/proc/self/task").iterdir()
        return next(threads, None) is not None and next(threads, None) is None
    except OSError:  # no /proc (another system): Python's own threads are all it knows
        return True


def until_thread_gone(native_id: int | None, seconds: float = 1.0) -> None:
    """Wait, at most ``seconds``, until the system thread ``native_id`` of a thread
    Python has joined is gone from this process (Linux lists it until its stack is freed,
    a few microseconds after the join)."""
    if native_id is None:
        return
    task = Path(f"/proc/self/task/{native_id}")
    deadline = time.monotonic() + seconds
    while task.exists() and time.monotonic() < deadline:
        time.sleep(0.0001)


def threads_allowed() -> bool:
    """Whether work may run beside the caller (``XODRLINT_FORK=0`` keeps it all in the
    calling thread)."""
    return os.environ.get(ENV, "1") != "0"


def start(task: Callable[[], _T], size: int, *, thread_safe: bool = False) -> Pending[_T]:
    """Run ``task`` beside the caller: in a thread when it is ``thread_safe`` (see the
    module's doc), else in a forked child when ``size`` makes that worth it, else on
    demand.

    For a child, ``task`` must return picklable values and must not depend on anything
    the parent changes afterwards (the child sees the parent as it was at the fork).
    """
    # a thread costs a tenth of a millisecond: worth it for any document
    if thread_safe and threads_allowed():
        return _in_thread(task)
    if not can_fork(size):
        return Pending(task)
    import pickle  # here: only large documents fork, and the import costs small ones 3 ms

    read_end, write_end = os.pipe()
    try:
        pid = os.fork()
    except OSError:
        os.close(read_end)
        os.close(write_end)
        return Pending(task)
    if pid == 0:  # the child: compute, send, and leave without running any cleanup
        os.close(read_end)
        status = 1
        try:
            payload = pickle.dumps(task(), protocol=pickle.HIGHEST_PROTOCOL)
            with os.fdopen(write_end, "wb") as stream:
                stream.write(payload)
            status = 0
        finally:
            os._exit(status)
    os.close(write_end)
    return Pending(lambda: _collect(pid, read_end, task))


def _in_thread(task: Callable[[], _T]) -> Pending[_T]:
    outcome: list[tuple[bool, object]] = []

    def run() -> None:
        try:
            outcome.append((True, task()))
        except BaseException as error:  # handed to the caller, who would have raised it
            outcome.append((False, error))

    # a daemon: an interrupted run exits without waiting for libxml2 to finish
    worker = threading.Thread(target=run, name="xodrlint-validation", daemon=True)
    worker.start()

    def wait() -> _T:
        worker.join()
        done, value = outcome[0]
        if not done:
            raise cast(BaseException, value)
        return cast(_T, value)

    return Pending(wait)


def _collect(pid: int, read_end: int, task: Callable[[], _T]) -> _T:
    with os.fdopen(read_end, "rb") as stream:
        payload = stream.read()
    _, status = os.waitpid(pid, 0)
    if os.waitstatus_to_exitcode(status) == 0 and payload:
        import pickle

        value: _T = pickle.loads(payload)
        return value
    return task()  # the child died (killed, out of memory): do it here instead


# -- hits across the fork ------------------------------------------------------------------

#: A hit as plain values: where its element is (child indices from the root), the rest,
#: and where its related elements are.
SentHit = tuple[
    tuple[int, ...] | None,
    str,
    int | None,
    int | None,
    str,
    tuple[tuple[int, ...] | None, ...],
    "SentFix | None",
]
#: A fix as plain values: its message, its applicability, and each edit's kind, the
#: position of the node it edits and its other fields.
SentFix = tuple[str, str, tuple[tuple[object, ...], ...]]
_EDITS: Final = {kind.__name__: kind for kind in (SetAttribute, ReplaceComment, InsertElement)}


def start_hits(
    task: Callable[[], list[Hit]], root: etree._Element, size: int, *, thread_safe: bool = False
) -> Pending[list[Hit]]:
    """:func:`start` for a task that yields hits about ``root``'s tree: a child sends
    each hit's element as its position in the tree, and the parent finds it again there
    (the trees are the same: the child is a fork); a thread hands over the hits."""
    if thread_safe:
        return start(task, size, thread_safe=True)
    sent = start(lambda: send_hits(task(), root), size)
    return Pending(lambda: receive_hits(sent.result(), root))


def send_hits(hits: list[Hit], root: etree._Element) -> list[SentHit]:
    """``hits`` about ``root``'s tree as values a forked child can send its parent."""
    positions = TreePositions()
    return [
        (
            _position(hit.element, root, positions),
            hit.message,
            hit.line,
            hit.column,
            hit.kind,
            tuple(_position(other, root, positions) for other in hit.related),
            _sent_fix(hit.fix, root, positions),
        )
        for hit in hits
    ]


def _sent_fix(fix: Fix | None, root: etree._Element, positions: TreePositions) -> SentFix | None:
    if fix is None:
        return None
    edits = tuple(
        (type(edit).__name__, _position(edit[0], root, positions), *edit[1:]) for edit in fix.edits
    )
    return fix.message, str(fix.applicability), edits


def _received_fix(
    sent: SentFix | None, found: Callable[[tuple[int, ...] | None], etree._Element | None]
) -> Fix | None:
    if sent is None:
        return None
    message, applicability, sent_edits = sent
    edits = []
    for kind, position, *fields in sent_edits:
        node = found(position)  # type: ignore[arg-type]
        if node is None:
            return None
        edits.append(cast("Any", _EDITS[str(kind)])(node, *fields))
    return Fix(message, tuple(edits), Applicability(applicability))


def receive_hits(sent: list[SentHit], root: etree._Element) -> list[Hit]:
    """The hits :func:`send_hits` sent, with their elements found again in ``root``'s
    tree (the same tree: the child is a fork)."""
    positions = TreePositions()

    def found(position: tuple[int, ...] | None) -> etree._Element | None:
        return positions.path_from(root, list(position)) if position is not None else None

    return [
        Hit(
            found(position),
            message,
            line=line,
            column=column,
            kind=kind,
            related=tuple(e for e in map(found, others) if e is not None),
            fix=_received_fix(fix, found),
        )
        for position, message, line, column, kind, others, fix in sent
    ]


def _position(
    element: etree._Element | None, root: etree._Element, positions: TreePositions
) -> tuple[int, ...] | None:
    if element is None:
        return None
    steps = positions.steps_to(element, root)
    return None if steps is None else tuple(steps)
