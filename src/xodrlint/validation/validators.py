"""Stage 2, validation: validate a document against the XSD of its version.

:class:`SchemaValidators` finds the schema set a document's declared version asks for
(:mod:`~xodrlint.validation.sets`), compiles it once per process, and starts validation
beside the rules (in a thread; a large document whose set cannot be validated in one, in
a forked child).
OpenDRIVE 1.1 to 1.7 schemas are XSD 1.0 and run in libxml2
(:mod:`~xodrlint.validation.libxml2`); 1.8 and 1.9 are XSD 1.1
(:mod:`~xodrlint.validation.xsd11`): libxml2 runs their XSD 1.0 form and the 1.1-only
checks are added (with xmlschema, imported only then). Without an official schema, the
built-in railroad schema checks each ``road/railroad`` and ``station`` subtree. Every
validator error becomes one XS006 hit on the element it is about.
"""

from __future__ import annotations

import contextlib
import os
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import NamedTuple, Protocol, TypeVar

from xodrlint.concurrency import background
from xodrlint.concurrency.background import Pending
from xodrlint.concurrency.memory import GIVE_BACK_FROM, give_back_freed_memory
from xodrlint.document.load import Document, Version, nearest_published
from xodrlint.findings import Hit
from xodrlint.validation.libxml2 import BuiltinRailroadValidator, Libxml2Validator
from xodrlint.validation.sets import SchemaFinder, SchemaSet


class SchemaCheck(NamedTuple):
    schema: SchemaSet
    hits: tuple[Hit, ...]
    seconds: float | None = None
    """The time validating took (its parts beside the caller and in it, without waits);
    ``None`` where a forked child did the first part, whose clock stayed there."""
    route: str | None = None
    """Where an XSD 1.1 set's own checks ran (libxml2's XPath, xmlschema), for
    ``check --verbose``."""


class Validator(Protocol):
    #: :meth:`hits` only reads the document and spends its time in libxml2, which
    #: releases the GIL: it may run in a thread beside the rules.
    thread_safe: bool

    def hits(self, doc: Document) -> Iterator[Hit]: ...


_T = TypeVar("_T")


def _timed(work: Callable[[], _T], seconds: list[float]) -> Callable[[], _T]:
    """``work``, appending the time each call takes to ``seconds``."""

    def run() -> _T:
        began = time.perf_counter()
        try:
            return work()
        finally:
            seconds.append(time.perf_counter() - began)

    return run


def _giving_back(
    work: Callable[[], _T], size: int, rules_done: threading.Event
) -> Callable[[], _T]:
    """``work``, then, for a document of ``size`` bytes worth it, the memory it freed
    given back to the system: while the caller's rules still build their data (a
    railway), what validation freed would add to the run's peak (the 20 MB railway: 528
    MB to 495 MB). Not once the caller waits for the result: the peak is then behind,
    and the call (30 to 110 ms on a 20 MB map) would only delay the end."""
    if size < GIVE_BACK_FROM:
        return work
    here = os.getpid()

    def run() -> _T:
        found = work()
        if not rules_done.is_set() and os.getpid() == here:  # (a forked child's is freed)
            give_back_freed_memory()
        return found

    return run


class SchemaValidators:
    """Finds and compiles schemas once per process (per worker in batch mode)."""

    def __init__(self, finder: SchemaFinder) -> None:
        self._finder = finder
        self._compiled: dict[tuple[Path, bool], Validator] = {}
        self._found: dict[tuple[int, int], SchemaSet | None] = {}
        # held while a schema compiles: the compile started by compile_soon and the
        # validation that needs it take turns
        self._compiling = threading.Lock()
        self._compiler: threading.Thread | None = None

    def schema_for(self, doc: Document) -> SchemaSet | None:
        if doc.effective is None:
            return None
        return self._schema_of_version(doc.effective)

    def _schema_of_version(self, version: Version) -> SchemaSet | None:
        key = (version.major, version.minor)
        if key not in self._found:  # finding walks schema folders: once per version
            self._found[key] = self._finder.find(*key)
        return self._found[key]

    def compile_soon(self, declared: Version) -> None:
        """Compile the schema of the ``declared`` version (read off the bytes before
        parsing) in a thread, while the caller parses the document: both mostly wait on
        libxml2, which lets go of the GIL, and a small map's run is a few milliseconds
        shorter. Anything that goes wrong is left for :meth:`start` to meet again."""
        if not background.threads_allowed():
            return
        schema = self._schema_of_version(nearest_published(declared))
        if schema is None or (schema.entry, schema.is_builtin) in self._compiled:
            return

        def compile_quietly() -> None:
            with contextlib.suppress(Exception):
                self._validator(schema)

        self._compiler = threading.Thread(
            target=compile_quietly, name="xodrlint-compile", daemon=True
        )
        self._compiler.start()

    def start(self, doc: Document) -> Pending[SchemaCheck | None]:
        """Begin validating ``doc``: libxml2 validates in a thread (a large document of a
        set it cannot validate in a thread: in a forked child) while the caller runs the
        rules; :meth:`Pending.result` gives the check."""
        schema = self.schema_for(doc)
        if schema is None or doc.tree is None:
            return Pending(lambda: None)
        validator = self._validator(schema)  # compiled here, so a child would inherit it
        self._compiler_gone()
        root = doc.tree.getroot()
        # A validator that splits its work (libxml2, then XSD 1.1 checks that need a slow
        # xmlschema model) runs the first part beside the rules (a thread or a child): the
        # caller finishes the rest after its rules, so both cores stay busy.
        split = getattr(validator, "stages", None)
        if split is not None:
            first, finish, thread_safe = split(doc)
        else:
            first, finish = (lambda: list(validator.hits(doc))), (lambda get: list(get()))
            thread_safe = validator.thread_safe
        beside: list[float] = []  # filled where the first part runs in this process
        rules_done = threading.Event()  # the caller came for the result
        hits = background.start_hits(
            _giving_back(_timed(first, beside), len(doc.data), rules_done),
            root,
            len(doc.data),
            thread_safe=thread_safe,
        )

        def check() -> SchemaCheck:
            rules_done.set()
            waited: list[float] = []
            began = time.perf_counter()
            found = tuple(finish(_timed(hits.result, waited)))
            own = time.perf_counter() - began - sum(waited)
            seconds = beside[0] + own if beside else None
            route_of = getattr(validator, "route_of", None)  # (each file's, where it differs)
            route = route_of(doc) if route_of is not None else getattr(validator, "route", None)
            return SchemaCheck(schema, found, seconds, route)

        return Pending(check)

    def prepare(self, doc: Document) -> None:
        """Compile the schema ``doc`` asks for, without validating anything."""
        schema = self.schema_for(doc)
        if schema is not None:
            self._validator(schema)

    def _compiler_gone(self) -> None:
        # A process that still runs the compile thread does not fork its validation, and
        # the thread may not have taken the lock yet, or be ending after letting it go.
        # Python's join returns a moment before the system thread is gone from the
        # process, which is what decides (see background.single_threaded).
        compiler, self._compiler = self._compiler, None
        if compiler is None:
            return
        compiler.join()
        background.until_thread_gone(compiler.native_id)

    def _validator(self, schema: SchemaSet) -> Validator:
        with self._compiling:
            return self._compiled_validator(schema)

    def _compiled_validator(self, schema: SchemaSet) -> Validator:
        key = (schema.entry, schema.is_builtin)
        validator = self._compiled.get(key)
        if validator is None:
            if schema.is_builtin:
                validator = BuiltinRailroadValidator(schema)
            elif schema.is_xsd11:
                # libxml2 on the set's XSD 1.0 form plus the 1.1-only checks (or, when
                # that cannot stand in for it, xmlschema's full XSD 1.1 validation)
                from xodrlint.validation.xsd11.fast import xsd11_validator

                validator = xsd11_validator(schema.entry, Libxml2Validator)
            else:
                validator = Libxml2Validator(schema.entry)
            self._compiled[key] = validator
        return validator
