"""Findings: the values every stage of the pipeline hands on (hits in, findings out)."""

# No ``from __future__ import annotations``: each string annotation of a named tuple is
# compiled when the class is made, 2 ms of every run's start-up here (lxml's types,
# which this module does not import, stay quoted).
import os
import re
from collections.abc import Iterable, Mapping
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final, NamedTuple

from xodrlint.fixes import FindingFix, Fix
from xodrlint.inputs.remote import is_url

if TYPE_CHECKING:
    from lxml import etree


#: The default of mapping fields of the value types: a plain dict, because reports and
#: options cross process boundaries and a ``MappingProxyType`` cannot be pickled. Typed
#: read-only; nothing may write to it.
NO_ENTRIES: Final[Mapping[Any, Any]] = {}


class Severity(StrEnum):
    """How bad a finding is; ordered so that ``ERROR`` ranks highest."""

    ERROR = "error"
    WARNING = "warning"
    INFO = "info"

    @property
    def rank(self) -> int:
        return _RANK[self]


_RANK = {Severity.INFO: 1, Severity.WARNING: 2, Severity.ERROR: 3}


class Hit(NamedTuple):
    """What a rule yields: the element a defect is about and a message.

    The engine makes a finding of it: the rule's code, UID and severity, the element's
    line, column and XPath.
    """

    element: "etree._Element | None"
    """What the defect is about. ``None`` only where no element exists (a file that does
    not parse); then ``line`` carries the parser's line."""
    message: str
    """Short, lowercase, no trailing period; ids quoted ('W1'); both sides named."""
    line: int | None = None
    """Where the defect stands when that is not the element's start tag (an unused
    suppression comment is about the element after it, on a line of its own)."""
    column: int | None = None
    """The column on ``line``, where ``line`` is given."""
    related: "tuple[etree._Element, ...]" = ()
    """Other elements the message is about (the first of two duplicates): the engine adds
    their lines to the message and to the finding."""
    kind: str = ""
    """What sort of schema error a schema-stage hit is (``keyref``, ``duplicate``,
    ``missing_child``, ...); a pack's rule leaves it empty."""
    defers_to: tuple[str, ...] | None = None
    """When set, replaces the rule's :attr:`RuleMeta.defers_to` for this hit (the schema
    rule hands a keyref error to SW004 but keeps every other error on the element)."""
    fix: Fix | None = None
    """How to mend the defect, where the right edit is knowable from the file (see
    :mod:`xodrlint.fixes`). Rule API 1.3."""


#: Hit kinds of schema errors about a missing or misplaced child element (libxml2 words a
#: missing child either way, depending on what else the parent holds): the schema stage
#: sets them, XS006 reads them.
CHILD_KINDS: Final = frozenset({"missing_child", "unexpected_element", "unexpected_element_bare"})


class Location(NamedTuple):
    """Another place a finding points to, for reports that can show it."""

    line: int
    xpath: str
    path: str | None = None
    """The file it stands in, where that is not the finding's (an included file)."""

    def as_dict(self) -> dict[str, object]:
        place: dict[str, object] = {"line": self.line, "xpath": self.xpath}
        if self.path is not None:
            place["path"] = self.path
        return place


class Finding(NamedTuple):
    """One reported defect, stamped with everything a report needs."""

    path: str
    line: int
    column: int | None
    code: str
    uid: str
    severity: Severity
    message: str
    xpath: str
    related: tuple[Location, ...] = ()
    fix: FindingFix | None = None
    """The fix the rule proposes; its edits are placed only where the run asked for
    them (``--fix``, ``--diff``, JSON and SARIF reports, the editor)."""

    @property
    def sort_key(self) -> tuple[str, int, int, str, str]:
        """Reports list findings by path, line and column (code and message break ties),
        as an editor lists them."""
        return (self.path, self.line, self.column or 0, self.code, self.message)

    def as_dict(self) -> dict[str, object]:
        return {
            "path": self.path,
            "line": self.line,
            "column": self.column,
            "code": self.code,
            "uid": self.uid,
            "severity": str(self.severity),
            "message": self.message,
            "xpath": self.xpath,
            "related": [location.as_dict() for location in self.related],
            "fix": None if self.fix is None else self.fix.as_dict(),
        }


def relative_path(path: str, root: str) -> str:
    """``path`` as a POSIX path relative to ``root`` when it lies below it, else as given.

    Reports and fingerprints name files this way, so they do not change with the folder a
    checkout lives in. A URL (``s3://bucket/a.xodr``) is no path below any folder: as given.
    """
    if is_url(path):
        return path
    if path == "-" or not root:
        return path.replace(os.sep, "/")
    # normpath, not resolve(): a path through a symlink is reported as the user wrote it
    absolute = os.path.normpath(Path(path).absolute())
    base = os.path.normpath(Path(root).absolute())
    if absolute == base or absolute.startswith(base.rstrip(os.sep) + os.sep):
        return os.path.relpath(absolute, base).replace(os.sep, "/")
    return path.replace(os.sep, "/")


def fingerprints(findings: Iterable[Finding], root: str) -> list[str]:
    """A stable fingerprint per finding: rule code, relative path and XPath, never lines.

    Findings that share all three (two overlaps reported on one segment) are told apart by
    their rank among them, so every fingerprint of a run is unique. SARIF
    ``partialFingerprints``, GitLab's ``fingerprint`` and the baseline all use these.
    """
    import hashlib  # only reports that need fingerprints pay for it

    seen: dict[str, int] = {}
    result = []
    for finding in findings:
        key = "\x1f".join((finding.code, relative_path(finding.path, root), finding.xpath))
        rank = seen.get(key, 0)
        seen[key] = rank + 1
        digest = hashlib.sha256(f"{key}\x1f{rank}".encode()).hexdigest()
        result.append(digest[:32])
    return result


class Suppressed(NamedTuple):
    """A finding that a suppression or the baseline withheld, with why."""

    finding: Finding
    kind: str
    """``inSource`` (an XML comment in the file) or ``external`` (config or baseline)."""
    justification: str = ""


#: What a rule option holds: a number (with a unit and a minimum), any text, or a regular
#: expression (text that must compile; the rule matches names or ids against it).
OPTION_KINDS: Final = ("number", "text", "regex")


#: The longest regular expression a rule option takes: a house style's pattern is a line;
#: a config found in a folder may hold anything (a 10 MB one took 18 s to compile).
MAX_PATTERN_LENGTH: Final = 1000


def _check_pattern(value: str) -> None:
    """A ``TypeError`` saying what is wrong with ``value`` as a regex option's value."""
    import re

    if len(value) > MAX_PATTERN_LENGTH:
        raise TypeError(
            f"a regular expression of at most {MAX_PATTERN_LENGTH} characters "
            f"(this one has {len(value):,})"
        )
    try:
        re.compile(value)
    except re.error as error:
        raise TypeError(f"a regular expression ({error})") from None
    except (RecursionError, OverflowError, MemoryError):  # nested beyond what re compiles
        raise TypeError("a regular expression (nested too deeply to compile)") from None


class RuleOption(NamedTuple):
    """A value a user may set for a rule (``--rail-min-width``, ``rail-min-width = ...``,
    ``--rule-option NAME=VALUE``).

    Options are global by name: rules that share a name share the value. ``kind`` says
    what the value is (see :data:`OPTION_KINDS`); ``unit`` and ``minimum`` apply to
    numbers only. A rule reads its value with :meth:`number` or :meth:`text`.
    """

    name: str
    """Kebab-case, global: the config key and ``--rule-option NAME=VALUE``'s name."""
    default: float | str
    """The value where the user sets none: a number, or text for ``text`` and ``regex``."""
    description: str
    """One line for ``xodrlint config`` and ``xodrlint rules -f json``."""
    unit: str = "m"
    """A number's unit (``m``, ``degrees``)."""
    minimum: float = 0.0
    """Values below this are refused (a negative width or tolerance makes no sense)."""
    kind: str = "number"
    """``number``, ``text`` or ``regex`` (text that must compile as a Python regular
    expression)."""

    @property
    def is_number(self) -> bool:
        return self.kind == "number"

    def number(self, settings: Mapping[str, "float | str"]) -> float:
        """This number option's value in ``settings`` (its default where unset)."""
        value = settings.get(self.name, self.default)
        if not self.is_number or isinstance(value, str):
            raise TypeError(f"rule option '{self.name}' is {self.kind}, not a number")
        return float(value)

    def text(self, settings: Mapping[str, "float | str"]) -> str:
        """This text or regex option's value in ``settings`` (its default where unset)."""
        value = settings.get(self.name, self.default)
        if self.is_number or not isinstance(value, str):
            raise TypeError(f"rule option '{self.name}' is a number, not text")
        return value

    def checked(self, value: object) -> "float | str":
        """``value`` as this option takes it (an int becomes a float); a ``TypeError``
        saying what the option takes when it does not (a config file's wrong type, a
        negative width, a pattern that does not compile)."""
        if self.is_number:
            import math

            if isinstance(value, bool) or not isinstance(value, int | float):
                raise TypeError(f"a finite number >= {self.minimum:g}")
            if not math.isfinite(value) or value < self.minimum:
                raise TypeError(f"a finite number >= {self.minimum:g}")
            return float(value)
        if not isinstance(value, str):
            raise TypeError("a regular expression" if self.kind == "regex" else "a string")
        if self.kind == "regex":
            _check_pattern(value)
        return value

    def parsed(self, raw: str) -> "float | str":
        """A value typed on the command line (``--rule-option NAME=VALUE``), checked."""
        if not self.is_number:
            return self.checked(raw)
        try:
            number = float(raw)
        except ValueError:
            raise TypeError(f"a finite number >= {self.minimum:g}") from None
        return self.checked(number)

    def as_dict(self) -> dict[str, object]:
        return {
            "name": self.name,
            "kind": self.kind,
            "default": self.default,
            "unit": self.unit if self.is_number else None,
            "minimum": self.minimum if self.is_number else None,
            "description": self.description,
        }


class PackInfo(NamedTuple):
    """The rule pack a rule came from: its entry point's name (``switches``, ``house``)
    and the distribution that installed it (``""`` where unknown)."""

    name: str
    distribution: str = ""
    version: str = ""
    builtin: bool = False
    """One of xodrlint's own packs."""

    def as_dict(self) -> dict[str, object]:
        return {
            "name": self.name,
            "distribution": self.distribution or None,
            "version": self.version or None,
            "builtin": self.builtin,
        }


#: A section heading of a rule's doc page.
_DOC_HEADING: Final = re.compile(r"^## +(?P<title>.+?)\s*$", re.MULTILINE)


def doc_summary(doc: str) -> str:
    """The summary a rule's docstring opens with: its first line after ``CODE name:``,
    without a final period."""
    first = doc.splitlines()[0] if doc else ""
    summary = first.split(":", 1)[1].strip() if ":" in first else first
    return summary.rstrip(".")


class RuleMeta(NamedTuple):
    """What reports need to know about a rule, without its code.

    ``doc`` is the rule's doc page (Markdown, from its module docstring); ``summary`` is
    its first line without the leading code and name.
    """

    code: str
    name: str
    uid: str
    severity: Severity
    summary: str
    doc: str
    aliases: tuple[str, ...] = ()
    pack: str = ""
    options: tuple[RuleOption, ...] = ()
    defers_to: tuple[str, ...] = ()
    """Codes of more specific rules: when one of them reports on the same element, this
    rule's (deferrable) finding there is withdrawn."""
    opt_in: bool = False
    """Off by default: ``ALL`` (the default selection) and a prefix shorter than its
    family (``X`` for ``XL001``) do not name it; its family, code, name or a UID do."""
    origin: PackInfo | None = None
    """The pack that registered the rule (``None`` for a rule no entry point loaded)."""
    since: tuple[int, int] | None = None
    """The first OpenDRIVE version, ``(major, minor)``, the rule applies to: a file that
    declares an older one is not judged by it unless the run applies every rule to every
    version (``--all-versions``); ``None``: every version."""

    @property
    def uids(self) -> tuple[str, ...]:
        return (self.uid, *self.aliases)

    @property
    def page(self) -> str:
        """The rule's doc page: its docstring without the ``CODE name: summary`` line."""
        return self.doc.partition("\n")[2].strip()

    def section(self, title: str) -> str | None:
        """The body of the page's ``## title`` section (any case), without the blanks
        around it; ``None`` when the page has no such section. The one reader of rule
        docstrings: reports, the editor, ``explain`` and the doc checks all ask it."""
        headings = list(_DOC_HEADING.finditer(self.doc))
        for number, heading in enumerate(headings):
            if heading["title"].lower() == title.lower():
                end = headings[number + 1].start() if number + 1 < len(headings) else None
                return self.doc[heading.end() : end].strip()
        return None

    @property
    def since_label(self) -> str | None:
        """``since`` as a version is written (``1.7``), ``None`` when the rule has none."""
        return None if self.since is None else f"{self.since[0]}.{self.since[1]}"


class FileReport(NamedTuple):
    """Everything one file's lint produced, for the formatters.

    ``error`` is set when the input could not be read at all (a missing file, a
    directory, no permission): that is not a finding but a usage error (exit 2).
    ``schema`` names the schema the file was validated with, ``None`` when the schema
    check did not run; ``schema_builtin`` is true when only the built-in railroad schema
    was available.
    """

    path: str
    findings: tuple[Finding, ...] = ()
    declared_version: str | None = None
    schema: str | None = None
    schema_builtin: bool = False
    error: str | None = None
    internal_errors: tuple[str, ...] = ()
    source_lines: Mapping[int, str] = NO_ENTRIES
    """The text of each line a finding is on, when the run asked to show source."""
    suppressed: tuple[Suppressed, ...] = ()
    """Findings withheld by suppressions, kept only when the run asked for them."""
    schema_note: str | None = None
    """Set when the schema was given for every version and is not the file's own: the
    file declares another version (a 1.4 file checked with a 1.7 set passes where its
    own set would not), and every report says so."""
    schema_route: str | None = None
    """Where an XSD 1.1 set's assertions ran (libxml2's XPath, or xmlschema for those
    that do not translate): ``check --verbose`` shows it."""
    timings: Mapping[str, float] = NO_ENTRIES
    """Seconds each stage took (``read``, ``parse``, ``model``, ``rules``,
    ``validation``: beside the model and the rules, ``waiting for validation``: after
    the rules, and ``total``), for ``--verbose``; reports never print them."""
    rules_not_applied: tuple[str, ...] = ()
    """Codes of the selected rules that did not judge the file because it declares an
    OpenDRIVE version older than the one they apply from (:attr:`RuleMeta.since`),
    sorted; empty when every selected rule ran (or with ``--all-versions``)."""
    schema_errors_hidden: int = 0
    """Schema errors outside the railroad content that ``xsd-scope = "railroad"`` left
    out of :attr:`findings` (the run's notes count them)."""
    fixed: int = 0
    """How many findings ``--fix`` mended in the file (written, or shown by ``--diff``);
    :attr:`findings` are what the fixed file still has."""
    diff: str = ""
    """With ``--diff``: the unified diff of what ``--fix`` would change."""
    fixed_source: bytes | None = None
    """With ``--fix`` on standard input: the fixed document, which goes to standard
    output."""


class RunResult(NamedTuple):
    """One invocation's results, in input order, with the rule table and notes."""

    reports: tuple[FileReport, ...]
    rules: tuple[RuleMeta, ...]
    tool_version: str
    notes: tuple[str, ...] = ()
    root: str = "."
    """The folder paths are reported relative to (SARIF's ``%SRCROOT%``): the working
    folder of the run."""
    selected: tuple[str, ...] | None = None
    """Codes of the rules that ran; ``None`` when not known (then all of them did)."""
    baseline: str | None = None
    """The name of the baseline file the run applied (``None``: none)."""
    withheld: int = 0
    """How many findings :attr:`baseline` withheld."""

    @property
    def findings(self) -> tuple[Finding, ...]:
        return tuple(f for report in self.reports for f in report.findings)

    def count_by_severity(self) -> dict[str, int]:
        counts = {str(severity): 0 for severity in Severity}
        for finding in self.findings:
            counts[str(finding.severity)] += 1
        return counts
