"""What a rule may do to a run: nothing but yield hits.

Rules come from plugins, and a plugin is code nobody here reviewed. Whatever one does
(raise anything, call ``sys.exit``, print, loop for ever, yield something that is not a
hit) becomes at worst an internal error of that rule on that file; the run goes on and
every other rule's findings are kept. :func:`guarded` bounds a rule's time and sends its
prints to stderr; :func:`checked_hit` refuses output that is not a :class:`Hit` about
the document being linted.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from collections.abc import Iterator
from typing import Any

from lxml import etree

from xodrlint.findings import Hit


class RuleTimeout(BaseException):
    """Raised into a rule that ran out of time. A ``BaseException``, so that a rule's own
    ``except Exception`` cannot swallow it."""


class RuleOutputError(TypeError):
    """A rule yielded something that is not a hit about the linted document."""


@contextlib.contextmanager
def guarded(timeout: float | None) -> Iterator[None]:
    """Run a rule's code: what it prints goes to stderr (a report on stdout stays
    intact), and after ``timeout`` seconds (``None`` or 0: no limit) it is stopped by
    :class:`RuleTimeout`. The limit needs ``SIGALRM`` and the main thread (the command
    line and batch workers); elsewhere rules run without one."""
    with contextlib.redirect_stdout(sys.stderr):
        if not timeout or not _can_time() or timeout <= 0:
            yield
            return

        def stop(signum: int, frame: Any) -> None:
            raise RuleTimeout(timeout)

        previous = signal.signal(signal.SIGALRM, stop)
        signal.setitimer(signal.ITIMER_REAL, timeout)
        try:
            yield
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)


def _can_time() -> bool:
    return hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()


def checked_hit(hit: object, root: etree._Element | None) -> Hit:
    """``hit`` when it is a :class:`Hit` whose fields have their types and whose elements
    belong to the document under ``root``; else :class:`RuleOutputError`."""
    if not isinstance(hit, Hit):
        raise RuleOutputError(f"yielded {_shown(hit)}, not a Hit")
    if not isinstance(hit.message, str):
        raise RuleOutputError(f"yielded a hit whose message is {_shown(hit.message)}")
    for name in ("line", "column"):
        value = getattr(hit, name)
        if value is not None and (not isinstance(value, int) or isinstance(value, bool)):
            raise RuleOutputError(f"yielded a hit whose {name} is {_shown(value)}")
    if not isinstance(hit.related, tuple):
        raise RuleOutputError(f"yielded a hit whose related is {_shown(hit.related)}")
    for element in (hit.element, *hit.related):
        if element is None and element is hit.element:
            continue
        if not isinstance(element, etree._Element) or not _inside(element, root):
            raise RuleOutputError(
                f"yielded a hit about {_shown(element)}, not an element of this document"
            )
    return hit


def _inside(element: etree._Element, root: etree._Element | None) -> bool:
    return root is not None and element.getroottree().getroot() is root


def _shown(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
