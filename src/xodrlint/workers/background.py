"""Work that runs beside the rules: schema validation in a forked child process.

libxml2 validates without releasing Python's GIL, so a thread cannot overlap it with the
rules. A forked child can: it shares the parsed tree copy-on-write, validates it on the
second core, and sends back plain values (picklable error entries) while the parent
builds the model and runs the rules. On a 20 MB map that hides most of the rules' time.

Only large documents are worth a fork; without ``os.fork`` (Windows), or when the child
fails for any reason, the work simply runs in the parent.
"""

from __future__ import annotations

import os
import sys
import threading
from collections.abc import Callable
from typing import Final, Generic, TypeVar

from lxml import etree

from xodrlint.findings import Hit

_T = TypeVar("_T")

#: Below this many bytes a fork costs more than the overlap saves.
MIN_BYTES: Final = 4 * 1024 * 1024
#: Set to "0" to keep all work in one process (debugging, measuring).
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
        and threading.active_count() == 1
    )


def start(task: Callable[[], _T], size: int) -> Pending[_T]:
    """Run ``task`` in a forked child when ``size`` makes it worth it, else on demand.

    ``task`` must return picklable values and must not depend on anything the parent
    changes afterwards (the child sees the parent as it was at the fork).
    """
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

#: A hit as plain values: where its element is (child indices from the root), and the rest.
SentHit = tuple[tuple[int, ...] | None, str, int | None, int | None, str]


def start_hits(
    task: Callable[[], list[Hit]], root: etree._Element, size: int
) -> Pending[list[Hit]]:
    """:func:`start` for a task that yields hits about ``root``'s tree: the child sends
    each hit's element as its position in the tree, and the parent finds it again there
    (the trees are the same: the child is a fork)."""
    sent = start(lambda: send_hits(task(), root), size)
    return Pending(lambda: receive_hits(sent.result(), root))


def send_hits(hits: list[Hit], root: etree._Element) -> list[SentHit]:
    """``hits`` about ``root``'s tree as values a forked child can send its parent."""
    return [_send(hit, root) for hit in hits]


def receive_hits(sent: list[SentHit], root: etree._Element) -> list[Hit]:
    """The hits :func:`send_hits` sent, with their elements found again in ``root``'s
    tree (the same tree: the child is a fork)."""
    return [_receive(item, root) for item in sent]


def _send(hit: Hit, root: etree._Element) -> SentHit:
    return (_position(hit.element, root), hit.message, hit.line, hit.column, hit.kind)


def _receive(item: SentHit, root: etree._Element) -> Hit:
    position, message, line, column, kind = item
    element = None
    if position is not None:
        element = root
        for index in position:
            element = element[index]
    return Hit(element, message, line=line, column=column, kind=kind)


def _position(element: etree._Element | None, root: etree._Element) -> tuple[int, ...] | None:
    if element is None:
        return None
    steps: list[int] = []
    current = element
    while current is not root:
        parent = current.getparent()
        if parent is None:  # not in this tree (a sibling of the root): no element to name
            return None
        steps.append(parent.index(current))
        current = parent
    return tuple(reversed(steps))
