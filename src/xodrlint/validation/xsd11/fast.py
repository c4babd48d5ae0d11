"""The fast path for XSD 1.1 sets: libxml2 on the set's XSD 1.0 form, then the XSD
1.1-only checks on just the elements they govern; full validation where it cannot stand in.

:func:`xsd11_validator` chooses: the fast path when the set's form
(:mod:`~xodrlint.validation.xsd11.form`) compiles in libxml2, else full validation
(:class:`~xodrlint.validation.xsd11.full.Xsd11Validator`), which ``XODRLINT_XSD11=full``
also asks for. :class:`FastXsd11Validator` runs one document:

1. the plan (:mod:`~xodrlint.validation.xsd11.governing`): which elements select a type
   alternative and which carry assertions;
2. libxml2 on the form, with the alternatives' ``xsi:type`` marks
   (:mod:`~xodrlint.validation.xsd11.alternatives`);
3. the assertions: those translated into XPath 1.0 run in libxml2
   (:mod:`~xodrlint.validation.xsd11.selectors`), which also finds the type marks of
   step 1; xmlschema's model (:mod:`~xodrlint.validation.xsd11.assertions`, unpickled or
   built only then) evaluates what does not translate and the elements whose values the
   translation cannot read exactly (a number written ``1e3``);
4. what libxml2 skipped, validated again (:mod:`~xodrlint.validation.xsd11.recovery`).

Anything the fast path cannot reproduce raises
:class:`~xodrlint.validation.xsd11.NeedsFull`, and that document is validated in full.

**Two stages, the first beside the rules** (:meth:`FastXsd11Validator.stages`): the form's
cache also records, from one strict xmlschema build of the set, where an element
with type alternatives can stand. A document with no element there needs no type
marks, so libxml2 runs alone in a thread. The assertions need no libxml2 result:
the caller checks them once its rules are done, while libxml2's thread may still be
busy, and merges. The model (built with the meta-schema check that
strict build made once) is kept pickled beside the form, so runs load it instead of
building it.

Messages of libxml2's errors come from :mod:`~xodrlint.validation.messages` (as for
OpenDRIVE 1.7), those of the 1.1-only checks and of the recovered subtrees from
xmlschema's reasons (as in full validation); key, keyref, assertion, missing-attribute and
enumeration messages read the same on both paths, others say the same in other words.
Where xmlschema repeats itself (a bad number three times, every unknown child of one
parent) libxml2 says it once.

One difference is deliberate: xmlschema resolves a key's selector through declared types
only, so it never checks keys and keyrefs below an element with type alternatives (every
``junction/connection/@incomingRoad``, ``@connectingRoad``, ``@linkedRoad``, ...). libxml2
follows the instance, as XSD 1.1 says; the fast path reports those broken references.
"""

from __future__ import annotations

import contextlib
import os
import threading
import weakref
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, Final, Protocol

from lxml import etree

from xodrlint.concurrency import background
from xodrlint.document.load import Document
from xodrlint.findings import Hit
from xodrlint.validation.sets import SchemaLoadError
from xodrlint.validation.xsd11 import NeedsFull
from xodrlint.validation.xsd11.alternatives import holds_a_site, needs_xsd11_reading, xsi_types
from xodrlint.validation.xsd11.assertions import assertion_errors
from xodrlint.validation.xsd11.form import Xsd10Form, full_validator, xsd10_form
from xodrlint.validation.xsd11.governing import Plan, SchemaModel
from xodrlint.validation.xsd11.recovery import Subtrees, as_xsd11, root_identities, skipped_subtrees
from xodrlint.validation.xsd11.selectors import Checked, Selectors
from xodrlint.validation.xsd11.wording import assertion_message

#: ``full`` validates XSD 1.1 sets with xmlschema alone (slow; the reference behaviour).
MODE_ENV: Final = "XODRLINT_XSD11"

#: The second part of a split validation: the first part's hits in, the findings out.
#: The first part's hits are asked for when the second part needs them: the caller's own
#: share of the second part (the assertions) runs while the first may still be running.
Finish = Callable[[Callable[[], list[Hit]]], list[Hit]]

#: What the assertion stage found: "checked" with its hits, "marks" (an element stands
#: where a type alternative applies after all), "full" (only full validation reads the
#: document right, and why) or "unsupported" (nor any document of the schema, and why),
#: its hits as positions in the tree.
_Stage = tuple[str, str, list[background.SentHit]]


class HitSource(Protocol):
    """A compiled libxml2 validator (:class:`~xodrlint.validation.libxml2.Libxml2Validator`)."""

    thread_safe: bool

    def hits(self, doc: Document) -> Iterator[Hit]: ...


def xsd11_validator(entry: Path, libxml2: Callable[[Path], HitSource]) -> HitSource:
    """The validator for an XSD 1.1 set: the fast path unless it cannot stand in for
    full validation (or ``XODRLINT_XSD11=full`` asks for full validation)."""
    if os.environ.get(MODE_ENV, "").strip().lower() != "full":
        with xsd10_form(entry) as form:
            compiled = None
            if form.entry is not None:
                # XSD 1.1 accepts content models XSD 1.0 refuses (overlapping wildcards)
                with contextlib.suppress(SchemaLoadError):
                    compiled = libxml2(form.entry)
        if compiled is not None:
            return FastXsd11Validator(entry, compiled, form)
    from xodrlint.validation.xsd11.full import Xsd11Validator  # xmlschema is slow to import

    return Xsd11Validator(entry)


class FastXsd11Validator:
    """libxml2 on the XSD 1.0 form, then the XSD 1.1-only checks (see the module doc)."""

    #: whole, it marks elements while libxml2 runs (see :meth:`stages` for the part that
    #: may run in a thread)
    thread_safe = False

    def __init__(self, entry: Path, compiled: HitSource, form: Xsd10Form) -> None:
        self.entry = entry
        self.form = form
        self._libxml2 = compiled
        self._full: Any = None
        self._model: SchemaModel | None = None
        self._unsupported: str | None = None
        self._selectors: Selectors | None = None
        self._selectors_read = False
        # the documents full validation judged, and why (``-v`` says so for each)
        self._judged_in_full: weakref.WeakKeyDictionary[Document, str] = weakref.WeakKeyDictionary()

    @property
    def full(self) -> Any:
        """The full XSD 1.1 validator (its model serves the 1.1-only checks)."""
        if self._full is None:
            self._full = full_validator(self.entry, self.form)
        return self._full

    def selectors(self) -> Selectors | None:
        """The set's assertions and type alternatives in XPath 1.0, compiled (``None``
        where the form has no translation, or one libxml2 does not compile or run)."""
        if not self._selectors_read:
            translation = self.form.translation
            if translation is not None:
                # the manifest's shape was checked; XPath it holds that does not compile
                # leaves the checks to xmlschema, as a form without a translation does
                with contextlib.suppress(etree.XPathError, KeyError, TypeError, ValueError):
                    self._selectors = Selectors(translation)
            self._selectors_read = True  # (after: another thread meanwhile compiles too)
        return self._selectors

    def _translated_checks(
        self, doc: Document, root: etree._Element, *, marks: bool = True
    ) -> Checked | None:
        """What the translated checks find (``marks``: the type marks too), or ``None``
        where there are none to run or their XPath fails (a manifest altered since the
        translation): xmlschema's route then serves, for this document and the next."""
        selectors = self.selectors()
        if selectors is None:
            return None
        try:
            return selectors.check(root, marks=marks)
        except etree.XPathError:
            self._drop_selectors()
            return None

    def _drop_selectors(self) -> None:
        """Hand the translated checks back to xmlschema, for this document and the next."""
        self._selectors = None
        if self._model is not None and self._model.translated:
            self._model = None  # it left out what the XPath was to check

    @property
    def route(self) -> str:
        """Which checks run where, for ``check --verbose``."""
        selectors = self.selectors()
        if not self.form.asserts:
            return "XSD 1.1 checks: libxml2"
        if selectors is None:
            return f"assertions: {self.form.asserts} in xmlschema (no translation cached)"
        words = [f"assertions: {len(selectors.translated)} in libxml2's XPath"]
        for type_name, test, why in selectors.untranslated:
            words.append(f"in xmlschema: {' '.join((type_name, repr(test))).strip()} ({why})")
        if not selectors.marks_known:
            words.append(f"type alternatives in xmlschema ({selectors.why_not_marks})")
        return "; ".join(words)

    def route_of(self, doc: Document) -> str:
        """:attr:`route` for ``doc``, or why it went to full validation."""
        why = self._judged_in_full.get(doc)
        if why is None:
            return self.route
        return f"full XSD 1.1 validation in xmlschema ({why})"

    def _in_full(self, doc: Document, why: NeedsFull) -> list[Hit]:
        self._say_in_full(doc, why)
        return list(self.full.hits(doc))

    def _say_in_full(self, doc: Document, why: NeedsFull) -> None:
        self._judged_in_full[doc] = str(why) or "this document"

    def model(self) -> SchemaModel:
        if self._model is None:
            selectors = self.selectors()
            translated = frozenset(selectors.translated) if selectors is not None else frozenset()
            try:
                self._model = SchemaModel(self.full.schema, translated)
            except NeedsFull as why:
                self._unsupported = str(why)
                raise
        return self._model

    def hits(self, doc: Document) -> Iterator[Hit]:
        yield from self._hits(doc)

    def _hits(self, doc: Document, *, screened: bool = False) -> list[Hit]:
        """:meth:`hits` (``screened``: the caller has :meth:`_screen`-ed ``doc``)."""
        assert doc.tree is not None
        try:
            return list(self._fast_hits(doc, screened=screened))
        except NeedsFull as why:
            return self._in_full(doc, why)

    def stages(self, doc: Document) -> tuple[Callable[[], list[Hit]], Finish, bool]:
        """The validation in two parts, for a caller that runs the first one elsewhere (a
        thread) while it does other work: libxml2 first, then the 1.1-only checks on
        libxml2's hits. Split only when libxml2 needs no type marks, so the first part
        needs no xmlschema model: no element of the document stands where the schema
        allows type alternatives. Otherwise all of it is the first part. The third value
        says whether the first part may run in a thread: libxml2 alone may, the whole
        validation may not (it marks elements with ``xsi:type`` while libxml2 runs).

        The assertions of a split validation need no libxml2 result either: xmlschema's
        run in the caller once its rules are done, while libxml2's thread may still be
        busy; the translated ones on whichever side is free first. (They ran in a forked
        child of their own, but a fork before the model is built costs the caller a
        copy-on-write fault on every page of the tree its model and rules touch: on a
        railway, where they touch every road, more than the assertions cost. 20 MB
        railway declared 1.8: 1.75 s forked, 1.49 s in the caller; a city map: equal.)"""
        assert doc.tree is not None
        root = doc.tree.getroot()
        sites = self.form.alternative_sites
        if sites is None or self._unsupported is not None or holds_a_site(doc, root, sites):
            # screened here, not where the first part runs: a forked child's reason for
            # full validation would not come back for -v
            try:
                self._screen(doc, root)
            except NeedsFull as why:
                self._say_in_full(doc, why)
                return (lambda: list(self.full.hits(doc))), (lambda first: list(first())), False
            return (lambda: self._hits(doc, screened=True)), (lambda first: list(first())), False
        selectors = self.selectors()
        if selectors is None:
            # xmlschema evaluates the assertions in the caller while libxml2's thread runs
            checks = background.Pending(lambda: self._assertion_stage(doc, root))
            return (
                (lambda: list(self._libxml2.hits(doc))),
                lambda first: self._finish_in_order(doc, first, checks.result, stage_first=True),
                self._libxml2.thread_safe,
            )
        # The translated assertions are libxml2's XPath, which runs without the GIL. They
        # need nothing of libxml2's validation, so whichever side is free first runs them:
        # libxml2's thread after validating, when the caller's rules still run (a railway,
        # where the rules are the longer part: 0.28 s of the caller's time on the 20 MB
        # one declared 1.8), or the caller once its rules are done, when libxml2 is still
        # busy (a city map, where validation is the longer part: 0.15 s of the 20 MB
        # mixed map's wait). A third thread beside both from the start only shared two
        # cores three ways.
        checked: list[Checked] = []
        claimed = threading.Lock()
        here = os.getpid()

        def translated() -> None:
            if not claimed.acquire(blocking=False):
                return  # the other side runs them (and has, once it returns its part)
            found = self._translated_checks(doc, root)
            if found is not None:
                checked.append(found)

        def first() -> list[Hit]:
            hits = list(self._libxml2.hits(doc))
            if os.getpid() == here:  # what a forked child finds would not come back
                translated()
            return hits

        def finish(first: Callable[[], list[Hit]]) -> list[Hit]:
            try:
                translated()
            except BaseException:
                with contextlib.suppress(Exception):
                    first()  # libxml2's thread ends before the error goes on, as it did
                raise
            # ``first`` returns once libxml2's thread is done, the checks too if it took them
            return self._finish_in_order(doc, first, stage, stage_first=False)

        def stage() -> _Stage:  # (after both: it holds what the XPath found)
            return self._assertion_stage(doc, root, checked[0] if checked else None)

        return first, finish, self._libxml2.thread_safe

    def _assertion_stage(
        self, doc: Document, root: etree._Element, checked: Checked | None = None
    ) -> _Stage:
        """The assertions' hits as values that cross a fork, or why they cannot stand
        (``checked``: what the translated assertions found, if they ran already)."""
        try:
            self._screen(doc, root)
            model, plan = self._prepare(doc, root, checked)
            if plan.marks:
                return ("marks", "", [])
            hits = self._assertion_hits(root, model, plan)
        except NeedsFull as why:
            if self._unsupported is not None:
                return ("unsupported", self._unsupported, [])
            return ("full", str(why), [])
        return ("checked", "", background.send_hits(hits, root))

    def _finish_in_order(
        self,
        doc: Document,
        first: Callable[[], list[Hit]],
        stage: Callable[[], _Stage],
        *,
        stage_first: bool,
    ) -> list[Hit]:
        """:meth:`_finish` with libxml2's hits (``first``) and the assertion stage, the
        stage taken first (xmlschema's assertions, while libxml2's thread may still run)
        or after (the translated ones, run by the caller or by ``first``'s thread)."""
        if stage_first:
            found = stage()
            return self._finish(doc, first(), found)
        raw = first()
        return self._finish(doc, raw, stage())

    def _finish(self, doc: Document, raw: list[Hit], stage: _Stage) -> list[Hit]:
        assert doc.tree is not None
        root = doc.tree.getroot()
        outcome, why, sent = stage
        if outcome == "unsupported":  # the schema's reason: skip the split next time
            self._unsupported = why
        if outcome in ("full", "unsupported"):
            return self._in_full(doc, NeedsFull(why or "this document"))
        try:
            if outcome == "marks":  # the sites say this cannot be; if it is, use the marks
                return list(self._fast_hits(doc))
            return list(self._checked(root, raw, background.receive_hits(sent, root)))
        except NeedsFull as why:
            return self._in_full(doc, why)

    def _prepare(
        self, doc: Document, root: etree._Element, checked: Checked | None = None
    ) -> tuple[SchemaModel | None, Plan]:
        """What the 1.1-only checks do in this document: libxml2's XPath runs the
        translated assertions and type alternatives; xmlschema's model (built or unpickled
        only then) is needed for what does not translate and for elements the
        translation cannot judge exactly. The caller has :meth:`_screen`-ed the
        document."""
        if not (self.form.asserts or self.form.alternatives):
            return None, Plan([], [])
        if checked is None:
            checked = self._translated_checks(doc, root)
        selectors = self.selectors()
        if checked is None or selectors is None:
            model = self.model()
            return model, model.plan(root)
        marks = checked.marks
        if marks is not None and not selectors.untranslated and not checked.uncertain:
            return None, Plan(marks, [], checked)
        model = self.model()
        plan = model.plan(root)
        return model, Plan(plan.marks if marks is None else marks, plan.asserted, checked)

    def _fast_hits(self, doc: Document, *, screened: bool = False) -> Iterator[Hit]:
        assert doc.tree is not None
        root = doc.tree.getroot()
        if not screened:
            self._screen(doc, root)
        marks = self._translated_marks(root)
        if marks is None:
            model, plan = self._prepare(doc, root)
            with xsi_types(plan.marks):
                raw = list(self._libxml2.hits(doc))
        else:
            # the assertions' XPath runs in a thread while libxml2 validates: both read
            # the tree without the GIL, the marks set before either starts
            with xsi_types(marks):
                beside = background.start(
                    lambda: self._translated_checks(doc, root, marks=False), 0, thread_safe=True
                )
                raw = list(self._libxml2.hits(doc))
                checked = beside.result()
            if checked is not None:
                checked.marks = marks
            model, plan = self._prepare(doc, root, checked)
        yield from self._checked(root, raw, self._assertion_hits(root, model, plan))

    def _screen(self, doc: Document, root: etree._Element) -> None:
        """Raise :class:`NeedsFull` where only full validation reads the document (or
        the schema) right: once per document, before the 1.1-only checks."""
        if self._unsupported is not None:
            raise NeedsFull(self._unsupported)
        if needs_xsd11_reading(doc, root):
            raise NeedsFull("the file uses xsi:type, xsi:nil or '+INF'")

    def _translated_marks(self, root: etree._Element) -> list[tuple[etree._Element, str]] | None:
        """The type marks, from the translated alternatives, where the translated
        assertions may run beside libxml2; ``None`` where the document goes the way
        :meth:`_prepare` chooses."""
        selectors = self.selectors()
        if selectors is None or not self._libxml2.thread_safe:
            return None
        if not (self.form.asserts or self.form.alternatives):
            return None
        try:
            return selectors.marks(root)
        except etree.XPathError:
            self._drop_selectors()
            return None

    def _assertion_hits(
        self, root: etree._Element, model: SchemaModel | None, plan: Plan
    ) -> list[Hit]:
        """A hit for each failing assertion of the elements ``plan`` found: those the
        translated assertions found, and those xmlschema finds where it evaluates them."""
        hits = []
        uncertain: set[etree._Element] = set()
        if plan.checked is not None:
            hits = [
                Hit(element, assertion_message(element, test), kind="other")
                for element, test in plan.checked.failed
            ]
            uncertain = set(plan.checked.uncertain)
        if model is None:
            return hits
        memo: dict[Any, Any] = {}
        try:
            errors = [
                error
                for element, xsd_type in plan.asserted
                for error in assertion_errors(
                    model.assertions_of(xsd_type, every=element in uncertain),
                    element,
                    xsd_type,
                    memo,
                )
            ]
        except NeedsFull:
            raise
        except Exception as error:  # (a subtree libxml2 skipped may hold anything)
            raise NeedsFull(f"an assertion could not be evaluated: {error}") from error
        return [*hits, *self.full.error_hits(root, errors)] if errors else hits

    def _checked(self, root: etree._Element, raw: list[Hit], asserted: list[Hit]) -> Iterator[Hit]:
        """libxml2's hits on the XSD 1.0 form, completed by the XSD 1.1-only checks: the
        assertions' hits ``asserted``, and what libxml2 skipped."""
        skipped = skipped_subtrees(raw, self.model)
        inside = Subtrees(skipped)
        identity = root_identities(self.full.schema, root, skipped) if skipped else None
        for hit in raw:
            if identity is not None and identity.recomputes(hit):
                continue
            moved = as_xsd11(hit)
            # what libxml2 says inside a skipped subtree, xmlschema says again below
            if not inside.holds(moved.element):
                yield moved
        yield from (hit for hit in asserted if not inside.holds(hit.element))
        errors: list[Any] = []
        for element, declaration in skipped:
            errors.extend(declaration.iter_errors(element))
        if identity is not None:
            errors.extend(identity.errors(raw))
        if errors:
            yield from self.full.error_hits(root, errors)
