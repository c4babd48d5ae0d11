"""Stage 5, engine: decide which rules run, run them, and stamp their hits into findings.

The engine is the one place that knows the rules, the document and the options together:
it selects rules by code prefix, leaves out on each file the rules that apply only from a
later OpenDRIVE version than the file declares (unless ``all_versions``), runs the schema
stage when XS006 is selected, builds the model once, stamps code, UID, severity, path,
line, column and XPath on every hit, applies the one-defect-one-finding policy and sorts.
"""

from __future__ import annotations

import contextlib
import gc
import re
import time
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Final, NamedTuple

from lxml import etree

from xodrlint.concurrency.background import Pending
from xodrlint.config.settings import COMMAND_LINE, DEFAULT, DEFAULT_RULE_TIMEOUT, Settings
from xodrlint.config.sizes import DEFAULT_MAX_FILE_SIZE, too_large
from xodrlint.document.load import Document, Version, load_bytes
from xodrlint.engine.fixing import DIFF, Fixed, FixPolicy, Linted, diff_of, fix_source
from xodrlint.engine.guard import RuleClock, RuleTimeout, checked_hit
from xodrlint.engine.suppressions import (
    Suppressions,
    may_hold_directives,
    read_directives,
    unused_hits,
)
from xodrlint.findings import (
    NO_ENTRIES,
    FileReport,
    Finding,
    Hit,
    Location,
    Severity,
    Suppressed,
)
from xodrlint.fixes import FindingFix
from xodrlint.inputs.files import FileTooLarge, NotRegularFile, os_reason, read_regular_file
from xodrlint.messages import one_line
from xodrlint.model import RailNetwork, build_network
from xodrlint.rules import Rule
from xodrlint.rules.options import resolve_rule_options
from xodrlint.rules.registry import Registry
from xodrlint.rules.selection import select_rules, specificity
from xodrlint.validation.sets import Origin, SchemaFinder, SchemaLoadError
from xodrlint.validation.validators import SchemaCheck, SchemaValidators

if TYPE_CHECKING:
    pass

SCHEMA_RULE: Final = "XS006"
#: Reports the includes that cannot be followed (:mod:`xodrlint.document.includes`).
INCLUDE_RULE: Final = "XS007"
#: Reports the suppression comments that withheld nothing: it runs after every other rule.
UNUSED_SUPPRESSION: Final = "XL001"
#: Findings of these rules mean the file is not an OpenDRIVE tree: nothing else runs.
FATAL_CODES: Final = frozenset({"XS001", "XS002"})
DOCUMENT_XPATH: Final = "/"
DOCUMENT_PACK: Final = "xodrlint.rules.document"
WARM_UP_BYTES: Final = 4096
_HEADER_VERSION: Final = re.compile(
    rb"<header\b[^>]*?\brevMajor\s*=\s*[\"'](?P<major>\d+)[\"'][^>]*?"
    rb"\brevMinor\s*=\s*[\"'](?P<minor>\d+)[\"']"
)


class LintOptions(NamedTuple):
    select: tuple[str, ...] = ("ALL",)
    ignore: tuple[str, ...] = ()
    severity: Mapping[str, Severity] = NO_ENTRIES
    schema: Path | None = None
    schema_origin: Origin = Origin.OPTION
    schema_source: str = ""
    """The config file that set ``schema`` (empty: the command line, or the API)."""
    keep_source: bool = False
    """Attach the text of each finding's line to the report (for ``--show-source``)."""
    rule_options: Mapping[str, float | str] = NO_ENTRIES
    """Rule option values by option name (``rail-min-width``); the rest keep defaults."""
    keep_suppressed: bool = False
    """Keep withheld findings in the report (SARIF lists them as suppressed)."""
    warn_unused_suppressions: bool = False
    """Select XL001 too (unused suppression comments): ``--warn-unused-suppressions``,
    an alias of ``--extend-select XL001``."""
    rule_timeout: float | None = DEFAULT_RULE_TIMEOUT
    """Seconds a rule may run on one file before it is stopped (``None``: no limit)."""
    all_versions: bool = False
    """Apply every rule to every file, also a rule that applies only from a later
    OpenDRIVE version than the file declares (``--all-versions``, ``all-versions =
    true``). Without it such a rule does not judge the file, and the file's report
    names it (:attr:`FileReport.rules_not_applied`)."""
    max_file_size: int = DEFAULT_MAX_FILE_SIZE
    """The largest file an ``include`` may bring in (``max-file-size``)."""
    place_fixes: bool = False
    """Place each fix's edits in the source (JSON and SARIF reports, the editor, ``--fix``
    and ``--diff``); without it a finding's fix says only that it exists."""
    fixes: FixPolicy = FixPolicy()
    """Which fixes count, and whether the run makes them (``--fix``, ``--diff``)."""
    xsd_scope: str = "all"
    """``railroad``: a schema error (XS006) is listed only where it is about the railroad
    content (a ``railroad`` element, a station, a road with a rail or tram lane, and
    everything inside them, and the header); the others are counted
    (:attr:`FileReport.schema_errors_hidden`). ``all`` lists every one."""

    @classmethod
    def of(
        cls, settings: Settings, *, keep_source: bool = False, keep_suppressed: bool = False
    ) -> LintOptions:
        """The options ``settings`` give, the same for every client of the engine (the
        command line, the language server); ``keep_*`` are a report's own needs."""
        from_file = settings.schema is not None and settings.source_of("schema") not in (
            COMMAND_LINE,
            DEFAULT,
        )
        return cls(
            select=settings.selected,
            ignore=settings.ignore,
            severity=settings.severity,
            schema=settings.schema,
            schema_origin=Origin.CONFIG if from_file else Origin.OPTION,
            schema_source=settings.source_of("schema") if from_file else "",
            keep_source=keep_source,
            rule_options=settings.rule_options,
            keep_suppressed=keep_suppressed,
            warn_unused_suppressions=settings.warn_unused_suppressions,
            rule_timeout=settings.rule_timeout or None,
            all_versions=settings.all_versions,
            xsd_scope=settings.xsd_scope,
            max_file_size=settings.max_file_size,
            fixes=FixPolicy(
                mode=settings.fix_mode,
                unsafe=settings.unsafe_fixes,
                fixable=settings.fixable,
                unfixable=settings.unfixable,
            ),
            place_fixes=settings.fix_mode != "",
        )


@contextlib.contextmanager
def _collector_paused(*, freeze: bool = False) -> Iterator[None]:
    """The cyclic garbage collector off while one document is linted.

    A model is millions of young objects and almost no cycles (refcounting frees it);
    each collection walks all of them, so the collector's time grew with the square of
    the map: 0.17 s on 20 MB, 0.71 s on 40 MB. Cycles made meanwhile are collected
    once it is back on. The first collection after that still walks every object the
    lint made and kept (0.2 s on a 20 MB railway): with ``freeze`` they are moved out
    of the collector's sight first, for a process that keeps the last document to the
    end (refcounting still frees them; only cycles among them would stay).
    """
    if not gc.isenabled():  # the caller's choice (or an outer lint): leave it as it is
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        if freeze:
            gc.freeze()
        gc.enable()


class LastDocument(NamedTuple):
    document: Document
    network: RailNetwork | None


class Linter:
    """Lints documents with one set of options; schemas are compiled once and reused."""

    def __init__(
        self,
        registry: Registry,
        options: LintOptions | None = None,
        *,
        keep_last_document: bool = False,
    ) -> None:
        self.registry = registry
        self.options = options or LintOptions()
        # Freeing a 20 MB map's tree and model takes half a second. A process that exits
        # without cleanup (the CLI) keeps the last document and its model alive and never
        # pays it; each lint replaces them, so at most one extra document is held.
        self._keep_last_document = keep_last_document
        self._last_document: LastDocument | None = None
        select = self.options.select
        if self.options.warn_unused_suppressions:
            select = (*select, UNUSED_SUPPRESSION)
        self.rules = select_rules(registry, select, self.options.ignore)
        self._codes = {r.code for r in self.rules}
        self._settings = resolve_rule_options(registry, self.options.rule_options)
        policy = self.options.fixes
        every_code = policy.fixable == ("ALL",) and not policy.unfixable
        self._fixable = None if every_code else policy.fixable_codes(registry)
        # the document rules report what loading and validating found: they run last,
        # and the unused-suppression rule once every other rule's findings are withheld
        self._unused_rules = [r for r in self.rules if r.code == UNUSED_SUPPRESSION]
        self._document_rules = [
            r for r in self.rules if r.meta.pack == DOCUMENT_PACK and r.code != UNUSED_SUPPRESSION
        ]
        # xodrlint's own rules only read the tree, so they run while the validation
        # thread reads it too (libxml2, without the GIL); another pack's rule might
        # change the tree (one that set an attribute on every road while libxml2 walked
        # them crashed the process), so those run once validation is done
        model_rules = [r for r in self.rules if r.meta.pack != DOCUMENT_PACK]
        self._model_rules = [r for r in model_rules if _read_only(r)]
        self._pack_rules = [r for r in model_rules if not _read_only(r)]
        self._since = {
            r.code: r.meta.since
            for r in self.rules
            if r.meta.since is not None and not self.options.all_versions
        }
        finder = SchemaFinder(
            option=self.options.schema,
            option_origin=self.options.schema_origin,
            option_source=self.options.schema_source,
        )
        self._validators = SchemaValidators(finder)

    def warm_up(self, path: Path) -> None:
        """Compile the schema ``path``'s header asks for, without linting it (so that
        worker processes forked afterwards share the compiled schema)."""
        if SCHEMA_RULE not in self._codes:
            return
        try:
            with path.open("rb") as stream:
                head = stream.read(WARM_UP_BYTES)
        except OSError:
            return
        found = _HEADER_VERSION.search(head)
        if found is None:
            return
        stub = b'<OpenDRIVE><header revMajor="%s" revMinor="%s"/></OpenDRIVE>' % (
            found["major"],
            found["minor"],
        )
        with contextlib.suppress(SchemaLoadError):
            self._validators.prepare(load_bytes(stub, "warm-up"))

    def lint_path(
        self,
        path: Path,
        display: str | None = None,
        external: ExternalIgnores = (),
        *,
        root: Path | None = None,
    ) -> FileReport:
        """Lint the file ``path``; with ``--fix``, write it back (``root``: the folder a
        walk found it in, out of which no link is written through)."""
        return self._lint_local(path, display or path.as_posix(), external, None, root)

    def _lint_local(
        self,
        path: Path,
        shown: str,
        external: ExternalIgnores,
        limit: int | None,
        root: Path | None = None,
    ) -> FileReport:
        started = time.perf_counter()
        try:
            data = read_regular_file(path, limit)
        except FileTooLarge:
            assert limit is not None
            return FileReport(shown, error=too_large(shown, limit))
        except NotRegularFile as refused:
            return FileReport(shown, error=f"{shown}: {refused}")
        except OSError as error:
            return FileReport(shown, error=_os_error(error, shown))
        read = time.perf_counter() - started
        if self.options.fixes.mode:
            return _with_read_time(self._fix_file(data, shown, external, path, root), read)
        return _with_read_time(self.lint_bytes(data, shown, external, location=path), read)

    def _fix_file(
        self, data: bytes, shown: str, external: ExternalIgnores, path: Path, root: Path | None
    ) -> FileReport:
        """The report of ``path`` once fixed: written back with ``--fix`` (what cannot be
        written is the report's error, and the report the file's as it stays), or with
        ``--diff`` the diff of what would change."""
        fixed, diff = self._fixed(data, shown, external, path)
        if self.options.fixes.mode == DIFF or fixed.data == data:
            return fixed.report._replace(diff=diff)
        from xodrlint.inputs.files import WriteRefused, replace_file

        try:
            replace_file(path, data, fixed.data, root)
        except WriteRefused as refused:  # the file stays as it was: so does its report
            return fixed.first._replace(error=f"{shown}: not fixed: {refused}")
        return fixed.report

    def lint_url(
        self,
        url: str,
        display: str | None = None,
        external: ExternalIgnores = (),
        max_file_size: int = DEFAULT_MAX_FILE_SIZE,
    ) -> FileReport:
        """Lint the object ``url`` names (``s3://bucket/maps/a.xodr``), read here through
        fsspec; more than ``max_file_size`` bytes is an error, and so is what the store
        or the network refuses (one line, :mod:`xodrlint.inputs.remote`)."""
        from xodrlint.inputs.remote import RemoteError, TooLarge, local_path, read_url, shown_url

        shown = display or shown_url(url)
        local = local_path(url)
        if self.options.fixes.mode and local is None:
            return FileReport(shown, error=f"{shown}: an object by URL cannot be fixed in place")
        if local is not None:
            # a file:// URL's file is read as a path named on the command line: a FIFO or
            # a device is refused unread (file:///dev/zero was read up to the size limit,
            # and a FIFO blocked the run)
            return self._lint_local(Path(local), shown, external, max_file_size)
        started = time.perf_counter()
        try:
            data = read_url(url, max_file_size)
        except TooLarge:
            return FileReport(shown, error=too_large(shown, max_file_size))
        except RemoteError as error:
            return FileReport(shown, error=f"{shown}: {error}")
        read = time.perf_counter() - started
        return _with_read_time(self.lint_bytes(data, shown, external), read)

    @property
    def last_document(self) -> LastDocument | None:
        """The document the last lint read, and its model (``None`` when a fatal problem
        left none), if the linter was made to keep them."""
        return self._last_document

    def lint_bytes(
        self,
        data: bytes,
        path: str,
        external: ExternalIgnores = (),
        *,
        location: Path | None = None,
    ) -> FileReport:
        """Lint one document; ``external`` withholds codes in it from outside the file
        (``per-file-ignores``): (selector, justification) pairs. ``location`` is the file
        the bytes are (or stand for: an editor's unsaved buffer): its includes are read
        from its folder. Without one, an include is an XS007 finding."""
        if self.options.fixes.mode:
            fixed, diff = self._fixed(data, path, external, location)
            if self.options.fixes.mode == DIFF:
                return fixed.report._replace(diff=diff)
            return fixed.report._replace(fixed_source=fixed.data)
        return self._lint_once(data, path, external, location)[0]

    def fixed_source(
        self, data: bytes, path: str, location: Path | None = None
    ) -> tuple[bytes, FileReport]:
        """``data`` with every fix the options allow made (their ``fixes`` policy's mode
        aside), and the report of what the result still has."""
        fixed, _ = self._fixed(data, path, (), location)
        return fixed.data, fixed.report

    def _lint_once(
        self, data: bytes, path: str, external: ExternalIgnores, location: Path | None
    ) -> tuple[FileReport, Document]:
        with _collector_paused(freeze=self._keep_last_document):
            return self._lint_bytes(data, path, external, location)

    def _fixed(
        self, data: bytes, path: str, external: ExternalIgnores, location: Path | None
    ) -> tuple[Fixed, str]:
        """``data`` with the fixes the options allow made (:mod:`xodrlint.engine.fixing`),
        and the diff of what changed."""

        codecs: list[str] = []  # the file's, as its first editable source read it

        def lint(text: bytes) -> Linted:
            report, doc = self._lint_once(text, path, external, location)
            if not doc.is_opendrive:
                problem = next(iter(doc.problems.get("XS001", doc.problems.get("XS002", ()))), None)
                return Linted(report, None, problem.message if problem else "no OpenDRIVE tree")
            if not any(f.fix is not None and f.fix.edits for f in report.findings):
                return Linted(report, None)
            source = doc.editable
            if not isinstance(source, str) and not codecs:
                codecs.append(source.codec)
            return Linted(report, source)

        fixed = fix_source(data, lint, self.options.fixes)
        if fixed.data == data or not codecs:
            return fixed, ""
        return fixed, diff_of(data, fixed.data, codecs[0], path)

    def _lint_bytes(
        self, data: bytes, path: str, external: ExternalIgnores, location: Path | None
    ) -> tuple[FileReport, Document]:
        if SCHEMA_RULE in self._codes:
            declared = _HEADER_VERSION.search(data, 0, WARM_UP_BYTES)
            if declared is not None:  # compiled while the document is parsed
                self._validators.compile_soon(
                    Version(int(declared["major"]), int(declared["minor"]))
                )
        clock = _StageClock()
        doc = load_bytes(data, path)
        clock.lap("parse")
        self._last_document = None
        problems: dict[str, list[Hit]] = {code: list(hits) for code, hits in doc.problems.items()}
        schema_label, builtin = None, False
        fatal = any(code in problems for code in FATAL_CODES)
        # A large document validates in a thread (or a child) while the model and the railroad
        # rules run here; the document rules report the stages' problems afterwards.
        pending = self._validators.start(doc) if not fatal and SCHEMA_RULE in self._codes else None
        validation = _Validation(pending, clock)
        if not fatal and doc.may_include:
            included = self._follow_includes(doc, location, validation)
            if included is not None:
                problems[INCLUDE_RULE] = included
                clock.lap("includes")
        not_applied = self._not_applied(doc)
        network = build_network(None if fatal else doc.root)
        clock.lap("model")
        if self._keep_last_document:
            self._last_document = LastDocument(doc, None if fatal else network)
        runs = [self._run(_applied(self._model_rules, not_applied), network, doc)]
        clock.lap("rules")
        check = validation.result()
        if self._pack_rules:
            runs.append(self._run(_applied(self._pack_rules, not_applied), network, doc))
            clock.lap("other packs' rules")
        schema_note = None
        hidden = 0
        if check is not None:
            problems[SCHEMA_RULE] = _resolved_by_includes(check.hits, doc)
            if self.options.xsd_scope == "railroad":
                problems[SCHEMA_RULE], hidden = _in_railroad_scope(problems[SCHEMA_RULE], network)
            schema_label, builtin = check.schema.describe(), check.schema.is_builtin
            if doc.effective is not None and doc.declared is not None:
                schema_note = check.schema.version_note(doc.declared, doc.effective)
        document_rules = _applied(self._document_rules, not_applied)
        runs.append(self._run(document_rules, RailNetwork(problems=problems), doc))
        stamped = [item for run in runs for item in run.stamped]
        kept, withheld, late = self._apply_suppressions(
            doc, _one_defect_one_finding(stamped), external, not_applied
        )
        crashes = [*(crash for run in runs for crash in run.crashes), *late]
        findings = sorted(kept, key=lambda f: f.sort_key)
        source: dict[int, str] = {}
        if self.options.keep_source:
            for finding in findings:
                # the report keeps the lines of its own file (one included holds others)
                text = doc.source_line(finding.line) if finding.path == path else None
                if text is not None:
                    source[finding.line] = text
        report = FileReport(
            path=path,
            findings=tuple(findings),
            source_lines=source,
            declared_version=str(doc.declared) if doc.declared else None,
            schema=schema_label,
            schema_builtin=builtin,
            internal_errors=tuple(crashes),
            suppressed=tuple(withheld) if self.options.keep_suppressed else (),
            schema_note=schema_note,
            schema_route=check.route if check is not None else None,
            timings=clock.stop(),
            rules_not_applied=tuple(sorted(not_applied)),
            schema_errors_hidden=hidden,
        )
        return report, doc

    def _follow_includes(
        self, doc: Document, location: Path | None, validation: _Validation
    ) -> list[Hit] | None:
        """What following ``doc``'s includes found (XS007 hits); ``None`` when it holds
        none. Only a map that may hold one loads what follows them (most hold none)."""
        from xodrlint.document.includes import expand_includes, has_includes

        if not has_includes(doc):
            return None
        # the schema judges each file as written, so it reads the tree before the
        # included content joins it
        validation.result()
        return expand_includes(doc, location, self.options.max_file_size)

    def _not_applied(self, doc: Document) -> frozenset[str]:
        """The selected rules that do not judge ``doc``: those that apply only from a
        later version than it declares. A file whose version cannot be read (XS003,
        XS004) is judged by every rule: nothing says a convention does not hold in it."""
        declared = doc.declared
        if declared is None or not self._since:
            return frozenset()
        version = (declared.major, declared.minor)
        return frozenset(code for code, since in self._since.items() if version < since)

    def _run(self, rules: Sequence[Rule], network: RailNetwork, doc: Document) -> _Ran:
        """What ``rules`` found in ``network``, and the rules that failed or ran out of
        time (each at worst its own internal error)."""
        stamped: list[_Stamped] = []
        crashes: list[str] = []
        with RuleClock(self.options.rule_timeout) as clock:
            for candidate in rules:
                # whatever a rule does is at worst its own internal error on this file:
                # the other rules' findings stand (see rule_guard)
                try:
                    try:
                        clock.started()
                        produced = [
                            self._stamp(doc, candidate, checked_hit(hit, doc.root))
                            for hit in candidate(network, self._settings)
                        ]
                    finally:  # first thing, so no tick lands in the handlers below
                        clock.stopped()
                except KeyboardInterrupt:
                    raise
                except RuleTimeout as stop:
                    crashes.append(
                        f"rule {candidate.code} stopped after {stop.args[0]:g} s on {doc.path} "
                        "(--rule-timeout)"
                    )
                except BaseException as error:  # SystemExit too: a rule does not end the run
                    crashes.append(f"rule {candidate.code} failed on {doc.path}: {error!r}")
                else:
                    stamped.extend(produced)
        return _Ran(stamped, crashes)

    def _apply_suppressions(
        self,
        doc: Document,
        stamped: list[_Stamped],
        external: ExternalIgnores,
        not_applied: frozenset[str],
    ) -> tuple[list[Finding], list[Suppressed], list[str]]:
        """The findings kept and those withheld, then XL001's on the suppressions that
        withheld nothing, and that rule's failures."""
        # a map without the word has no suppression comment: skip walking its comments
        texts = (doc.data, *(part.data for part in doc.parts))
        held = any(may_hold_directives(text) for text in texts)
        directives = read_directives(doc.root, doc.path_of if doc.parts else None) if held else []
        suppressions = Suppressions(directives, self._selector_matches, doc.path_of)
        kept, withheld = self._withhold(stamped, suppressions, external)
        unused_rules = _applied(self._unused_rules, not_applied)
        if unused_rules and directives:
            # only now is it known which entries withheld something; XL001's own findings
            # then pass the same suppressions (``ignore[PT001, XL001]`` keeps a stale entry)
            ran = self._codes - not_applied

            def judgeable(selector: str) -> bool:
                return self._judgeable(selector, ran)

            hits = list(unused_hits(doc, suppressions, judgeable))
            unused = self._run(unused_rules, RailNetwork(problems={UNUSED_SUPPRESSION: hits}), doc)
            more_kept, more_withheld = self._withhold(unused.stamped, suppressions, external)
            return [*kept, *more_kept], [*withheld, *more_withheld], unused.crashes
        return kept, withheld, []

    def _withhold(
        self, stamped: list[_Stamped], suppressions: Suppressions, external: ExternalIgnores
    ) -> tuple[list[Finding], list[Suppressed]]:
        """``stamped`` sorted into the findings kept and those withheld (by a comment or
        from outside)."""
        kept: list[Finding] = []
        withheld: list[Suppressed] = []
        for item in stamped:
            code = item.finding.code
            directive = suppressions.withholding(code, item.element)
            outside = next(
                (why for sel, why in external if self._selector_matches(sel, code)), None
            )
            if directive is not None:
                withheld.append(Suppressed(item.finding, "inSource", directive.reason))
            elif outside is not None:
                withheld.append(Suppressed(item.finding, "external", outside))
            else:
                kept.append(item.finding)
        return kept, withheld

    def _judgeable(self, selector: str, ran: frozenset[str] | set[str]) -> bool:
        """Whether this run can tell that a suppression entry is stale: it names no
        rule at all (a typo), or one of the rules it names ran on the file (``ran``: a
        rule not applied to the file's version did not). An entry naming XL001 is never
        judged: it withholds the very findings that would judge it."""
        named = [code for code in self.registry.by_code if self._selector_matches(selector, code)]
        if UNUSED_SUPPRESSION in named:
            return False
        return not named or any(code in ran for code in named)

    def _selector_matches(self, selector: str, code: str) -> bool:
        candidate = self.registry.by_code.get(code)
        if candidate is None:
            return selector.upper() == code or (bool(selector) and code.startswith(selector))
        return specificity(selector, candidate) is not None

    def _stamp(self, doc: Document, candidate: Rule, hit: Hit) -> _Stamped:
        meta = candidate.meta
        if hit.element is not None and doc.tree is not None:
            # a hit may name its own place (XL001: the comment, about the element after it)
            line, column = (hit.line, hit.column) if hit.line else doc.position_of(hit.element)
            xpath = doc.xpath_of(hit.element)
        else:
            line, column, xpath = hit.line or 1, hit.column, DOCUMENT_XPATH
        severity = self.options.severity.get(meta.code, meta.severity)
        path = doc.path if hit.element is None else doc.path_of(hit.element)
        related = tuple(_location(doc, el, path) for el in hit.related)
        message = one_line(hit.message)  # messages quote values a map may fill with anything
        if related:
            message += _at(related)
        fix = None
        if hit.fix is not None and (self._fixable is None or meta.code in self._fixable):
            fix = self._finding_fix(doc, hit)
        finding = Finding(
            path=path,
            line=line,
            column=column,
            code=meta.code,
            uid=meta.uid,
            severity=severity,
            message=message,
            xpath=xpath,
            related=related,
            fix=fix,
        )
        defers_to = meta.defers_to if hit.defers_to is None else hit.defers_to
        return _Stamped(finding, defers_to, hit.element)

    def _finding_fix(self, doc: Document, hit: Hit) -> FindingFix | None:
        """The fix of ``hit`` as its finding carries it: its edits placed in the source
        when the run asked for them; ``None`` where they cannot be made (an element an
        include brought in, a source that cannot be edited byte for byte)."""
        fix = hit.fix
        assert fix is not None
        if hit.element is not None and doc.part_of(hit.element) is not None:
            return None
        if not self.options.place_fixes:
            return FindingFix(fix.applicability, one_line(fix.message))
        from xodrlint.document.edits import EditError

        source = doc.editable
        if isinstance(source, str):
            return None
        try:
            edits = source.edits_of(fix)
        except EditError:
            return None
        placed = tuple(source.placed(edit) for edit in edits)
        return FindingFix(fix.applicability, one_line(fix.message), placed)


def _resolved_by_includes(hits: Sequence[Hit], doc: Document) -> list[Hit]:
    """The schema's hits, less the key references ``doc``'s included files resolve."""
    if not doc.parts:
        return list(hits)
    from xodrlint.document.includes import unresolved

    return unresolved(hits, doc)


def _location(doc: Document, element: etree._Element, path: str) -> Location:
    """Where a related element stands: its file named where it is not ``path``."""
    own = doc.path_of(element)
    return Location(doc.line_of(element), doc.xpath_of(element), None if own == path else own)


def _at(related: Sequence[Location]) -> str:
    """ " at line 3, 5" in the message; " at parts/x.xml line 3" for another file's."""
    if all(location.path is None for location in related):
        return " at line " + ", ".join(str(location.line) for location in related)
    return " at " + ", ".join(
        f"line {place.line}" if place.path is None else f"{place.path} line {place.line}"
        for place in related
    )


class _Ran(NamedTuple):
    """One run of rules over a network: what they found, and how those that failed did."""

    stamped: list[_Stamped]
    crashes: list[str]


class _Stamped(NamedTuple):
    finding: Finding
    defers_to: tuple[str, ...]
    """Codes whose finding on the same element withdraws this one."""
    element: etree._Element | None


ExternalIgnores = Sequence[tuple[str, str]]


class _Validation:
    """The schema check under way beside the rules, waited for once."""

    def __init__(self, pending: Pending[SchemaCheck | None] | None, clock: _StageClock) -> None:
        self._pending = pending
        self._clock = clock
        self._started = time.perf_counter()
        self._check: SchemaCheck | None = None

    def result(self) -> SchemaCheck | None:
        if self._pending is None:
            return self._check
        self._check = check = self._pending.result()
        self._pending = None
        if check is not None:  # its own time, or (a forked child's) until its result
            self._clock.add("validation", check.seconds or time.perf_counter() - self._started)
        self._clock.lap("waiting for validation")
        return check


class _StageClock:
    """Seconds per stage of one lint, for ``--verbose``: a few clock reads a file."""

    def __init__(self) -> None:
        self._started = self._last = time.perf_counter()
        self._laps: dict[str, float] = {}

    def lap(self, stage: str) -> None:
        now = time.perf_counter()
        self._laps[stage] = now - self._last
        self._last = now

    def add(self, stage: str, seconds: float) -> None:
        self._laps[stage] = seconds

    def stop(self) -> dict[str, float]:
        self._laps["total"] = time.perf_counter() - self._started
        return self._laps


def _read_only(rule: Rule) -> bool:
    """Whether ``rule`` is known to leave the tree as it is: one of xodrlint's own."""
    origin = rule.meta.origin
    return origin is not None and origin.builtin


def _applied(rules: list[Rule], not_applied: frozenset[str]) -> list[Rule]:
    """``rules`` without those that do not judge this file."""
    return [r for r in rules if r.code not in not_applied] if not_applied else rules


def _one_defect_one_finding(stamped: list[_Stamped]) -> list[_Stamped]:
    """Withdraw each finding a more specific rule reports on the same element.

    Rules declare what they defer to (the catalogue's chains, and the schema rule's
    key, keyref and missing-child errors that the railroad rules report better); only
    rules that ran count, so a rule selected alone reports everything it sees.
    """
    reported = {(s.finding.xpath, s.finding.code) for s in stamped}
    return [
        s for s in stamped if not any((s.finding.xpath, code) in reported for code in s.defers_to)
    ]


def _with_read_time(report: FileReport, read: float) -> FileReport:
    """``report`` with the seconds its file took to read added."""
    timings = {"read": read, **report.timings}
    timings["total"] = timings.get("total", 0.0) + read
    return report._replace(timings=timings)


def _os_error(error: OSError, shown: str) -> str:
    return f"{shown}: cannot read: {os_reason(error)}"


#: Elements whose schema errors ``xsd-scope = "railroad"`` lists, with all inside them.
_RAILROAD_SCOPE: Final = frozenset({"railroad", "station", "header"})


def _in_railroad_scope(hits: Iterable[Hit], network: RailNetwork) -> tuple[list[Hit], int]:
    """The schema hits about the railroad content, and how many others there were: a hit
    on or inside a ``railroad`` element, a station, the header, or a road with a rail or
    tram lane; a hit on no element (the document itself) is kept."""
    rail_roads = {road.element for road in network.rail_roads}
    kept, hidden = [], 0
    for hit in hits:
        element = hit.element
        inside = element is None or any(
            node.tag in _RAILROAD_SCOPE or node in rail_roads
            for node in (element, *element.iterancestors())
            if isinstance(node.tag, str)
        )
        if inside:
            kept.append(hit)
        else:
            hidden += 1
    return kept, hidden
