"""What a rule may do to a run: nothing but yield hits.

Rules come from plugins, and a plugin is code nobody here reviewed. Whatever one does
(raise anything, call ``sys.exit``, print, loop for ever, yield something that is not a
hit) becomes at worst an internal error of that rule on that file; the run goes on and
every other rule's findings are kept. :class:`RuleClock` bounds a rule's time and sends its
prints to stderr; :func:`checked_hit` refuses output that is not a :class:`Hit` about
the document being linted.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
import time
from typing import Any, Final

from lxml import etree

from xodrlint.findings import Hit
from xodrlint.fixes import Applicability, Fix, InsertElement, ReplaceComment, SetAttribute


class RuleTimeout(BaseException):
    """Raised into a rule that ran out of time. A ``BaseException``, so that a rule's own
    ``except Exception`` cannot swallow it."""


class RuleOutputError(TypeError):
    """A rule yielded something that is not a hit about the linted document."""


#: The clock looks at the running rule this many times per limit: a rule is stopped
#: between the limit and a quarter past it.
_TICKS_PER_LIMIT: Final = 4


class RuleClock:
    """The time limit and stdout redirection for one file's rules, set up once per file:
    arming a timer for each rule cost 0.3 ms a file, half the time of linting a small
    map. An interval timer ticks a few times per limit instead; each rule only notes
    when it started (:meth:`started`), and a tick that finds the running rule over its
    limit raises :class:`RuleTimeout` in it.

    The limit needs ``SIGALRM`` and the main thread (the command line and batch
    workers); elsewhere rules run without one. What rules print goes to stderr, so that
    a report on stdout stays intact.
    """

    def __init__(self, timeout: float | None) -> None:
        self.timeout = timeout if timeout and timeout > 0 else None
        self._since: float | None = None

    def __enter__(self) -> RuleClock:
        self._redirect = contextlib.redirect_stdout(sys.stderr)
        self._redirect.__enter__()
        self._timed = self.timeout is not None and _can_time()
        if self._timed:
            assert self.timeout is not None
            self._previous = signal.signal(signal.SIGALRM, self._tick)
            period = self.timeout / _TICKS_PER_LIMIT
            signal.setitimer(signal.ITIMER_REAL, period, period)
        return self

    def __exit__(self, *exc_info: object) -> None:
        if self._timed:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, self._previous)
        self._redirect.__exit__(None, None, None)

    def started(self) -> None:
        """A rule begins now."""
        self._since = time.monotonic()

    def stopped(self) -> None:
        """No rule runs now (the time between rules is nobody's)."""
        self._since = None

    def _tick(self, signum: int, frame: Any) -> None:
        since, limit = self._since, self.timeout
        if since is not None and limit is not None and time.monotonic() - since >= limit:
            self._since = None
            raise RuleTimeout(limit)


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
    # an int subclass writes whatever its __str__ says into every report (a new "::"
    # command in GitHub's output): plain ints from here on
    if hit.line is not None and type(hit.line) is not int:
        hit = hit._replace(line=int(hit.line))
    if hit.column is not None and type(hit.column) is not int:
        hit = hit._replace(column=int(hit.column))
    if not isinstance(hit.related, tuple):
        raise RuleOutputError(f"yielded a hit whose related is {_shown(hit.related)}")
    for element in (hit.element, *hit.related):
        if element is None and element is hit.element:
            continue
        if not isinstance(element, etree._Element) or not _inside(element, root):
            raise RuleOutputError(
                f"yielded a hit about {_shown(element)}, not an element of this document"
            )
    if hit.fix is not None:
        _check_fix(hit.fix, root)
    return hit


def _check_fix(fix: object, root: etree._Element | None) -> None:
    """A pack's fix is made of the rule API's edits, with text where text goes and
    nodes of this document where nodes go: else :class:`RuleOutputError`."""
    if not isinstance(fix, Fix) or not isinstance(fix.message, str):
        raise RuleOutputError(f"yielded a hit whose fix is {_shown(fix)}, not a Fix")
    if not isinstance(fix.applicability, Applicability) or not isinstance(fix.edits, tuple):
        raise RuleOutputError(f"yielded a fix whose fields are {_shown(fix)}")
    for edit in fix.edits:
        texts: tuple[object, ...]
        if isinstance(edit, SetAttribute):
            node, texts = edit.element, (edit.name, edit.value)
        elif isinstance(edit, ReplaceComment):
            node, texts = edit.comment, (() if edit.text is None else (edit.text,))
        elif isinstance(edit, InsertElement):
            pairs = edit.attributes
            if not isinstance(pairs, tuple) or not all(
                isinstance(pair, tuple) and len(pair) == 2 for pair in pairs
            ):
                raise RuleOutputError(f"yielded an insertion whose attributes are {_shown(pairs)}")
            held = edit.children
            if not isinstance(held, tuple) or not all(
                isinstance(child, tuple)
                and len(child) == 2
                and isinstance(child[1], tuple)
                and all(isinstance(pair, tuple) and len(pair) == 2 for pair in child[1])
                for child in held
            ):
                raise RuleOutputError(f"yielded an insertion whose children are {_shown(held)}")
            node = edit.anchor
            texts = (
                edit.tag,
                edit.where,
                *(text for pair in pairs for text in pair),
                *(child[0] for child in held),
                *(text for child in held for pair in child[1] for text in pair),
            )
        else:
            raise RuleOutputError(f"yielded a fix with the edit {_shown(edit)}")
        if not all(type(text) is str for text in texts):
            raise RuleOutputError(f"yielded an edit whose text is not a str: {_shown(edit)}")
        if not isinstance(node, etree._Element) or not _inside(node, root):
            raise RuleOutputError(f"yielded an edit of {_shown(node)}, not a node of this document")


def _inside(element: etree._Element, root: etree._Element | None) -> bool:
    return root is not None and element.getroottree().getroot() is root


def _shown(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
