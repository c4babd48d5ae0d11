"""What a run says beside its findings about what it did not check: files the built-in
schema alone validated (only their railroad elements were, and where the official set of
their version comes from: ``schemas fetch`` brings 1.1 to 1.8.0; ASAM publishes the
others), and rules that did not judge files of an older OpenDRIVE version than they apply
from (``--all-versions`` applies them)."""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from typing import Final

from xodrlint.document.load import Version, nearest_published
from xodrlint.findings import FileReport, RuleMeta
from xodrlint.formatters.output import error_line
from xodrlint.messages import one_line, plural
from xodrlint.validation.sets import SCHEMA_PATH_ENV

#: The newest version whose official set ``xodrlint schemas fetch`` brings, and where
#: ASAM publishes the others.
LAST_FETCHED: Final = (1, 8)
ASAM_DOWNLOADS: Final = "https://www.asam.net/standards/detail/opendrive/"
FULL_VALIDATION_NOTE: Final = (
    "only railroad elements were validated (built-in schema); for full OpenDRIVE "
    f"validation run 'xodrlint schemas fetch', or point {SCHEMA_PATH_ENV} or --schema at "
    "the official ASAM schemas"
)


def run_notes(reports: Iterable[FileReport], rules: Iterable[RuleMeta] = ()) -> tuple[str, ...]:
    """What a run says of its ``reports``: of the files the built-in schema alone
    validated, where the official set of their version comes from; of the rules (their
    metadata in ``rules``) that did not judge some files, which and why."""
    reports = list(reports)
    not_applied = NotApplied()
    for report in reports:
        not_applied.add(report)
    hidden = (note for report in reports if (note := hidden_note(report)) is not None)
    return (*schema_notes(reports), *not_applied.notes(rules), *hidden)


def hidden_note(report: FileReport) -> str | None:
    """What ``xsd-scope = "railroad"`` left out of ``report``, one note per file."""
    count = report.schema_errors_hidden
    if not count:
        return None
    errors = "schema error" if count == 1 else "schema errors"
    return (
        f"{report.path}: {count:,} {errors} outside the railroad content not shown "
        "(--xsd-scope all shows them)"
    )


def schema_notes(reports: list[FileReport]) -> tuple[str, ...]:
    """What a run says of files the built-in schema alone validated: where the official
    set of their version comes from (``schemas fetch`` brings 1.1 to 1.8.0, not 1.9)."""
    versions = {_published(r.declared_version) for r in reports if r.schema_builtin}
    notes = []
    if any(version is None or version <= LAST_FETCHED for version in versions):
        notes.append(FULL_VALIDATION_NOTE)
    later = sorted(v for v in versions if v is not None and v > LAST_FETCHED)
    if later:
        named = ", ".join(f"{major}.{minor}" for major, minor in later)
        notes.append(
            "only railroad elements were validated (built-in schema): "
            f"no official schema for OpenDRIVE {named} was found, and 'xodrlint schemas "
            f"fetch' brings sets up to {LAST_FETCHED[0]}.{LAST_FETCHED[1]}.0 only: download "
            f"it from ASAM ({ASAM_DOWNLOADS}) and add it with 'xodrlint schemas add PATH', "
            f"or point {SCHEMA_PATH_ENV} or --schema at it"
        )
    return tuple(notes)


class NotApplied:
    """The files a run's rules did not judge, counted by the rules and the version the
    files declare: all a run keeps of its reports for the note (a streaming run too)."""

    def __init__(self) -> None:
        self.files: Counter[tuple[tuple[str, ...], str]] = Counter()

    def add(self, report: FileReport) -> None:
        if report.rules_not_applied:
            self.files[report.rules_not_applied, report.declared_version or "?"] += 1

    def notes(self, rules: Iterable[RuleMeta]) -> tuple[str, ...]:
        """One note per version the rules apply from: "RL001, RL002 not applied to 3
        files declaring OpenDRIVE 1.4 (they apply from 1.7 on; --all-versions applies
        them)"; none when every rule judged every file."""
        since = {meta.code: meta.since for meta in rules}
        # rules that apply from the same version are left out of the same files
        groups: dict[tuple[int, int] | None, tuple[set[str], Counter[str]]] = {}
        for (codes, version), count in self.files.items():
            for first in {since.get(code) for code in codes}:
                named, versions = groups.setdefault(first, (set(), Counter()))
                named.update(code for code in codes if since.get(code) == first)
                versions[version] += count
        known = sorted(first for first in groups if first is not None)
        order = [*known, *([None] if None in groups else [])]
        return tuple(_not_applied_note(first, *groups[first]) for first in order)


def _not_applied_note(
    first: tuple[int, int] | None, codes: set[str], versions: Counter[str]
) -> str:
    named = ", ".join(sorted(codes))
    many = len(codes) > 1
    counts = sorted(versions.items(), key=lambda item: _version_key(item[0]))
    parts = [
        f"{plural(count, 'file') if i == 0 else count} declaring "
        f"{'OpenDRIVE ' if i == 0 else ''}{version}"
        for i, (version, count) in enumerate(counts)
    ]
    files = " and ".join([", ".join(parts[:-1]), parts[-1]] if len(parts) > 1 else parts)
    they, them = ("they", "them") if many else ("it", "it")
    applies = "apply" if many else "applies"
    when = f"from {first[0]}.{first[1]} on" if first is not None else "to later versions only"
    how = f"--all-versions applies {them}"
    return f"{named} not applied to {files} ({they} {applies} {when}; {how})"


def _version_key(version: str) -> tuple[int, ...]:
    parts = version.split(".")
    return tuple(int(part) if part.isdigit() else -1 for part in parts)


def say_notes(notes: Iterable[str]) -> None:
    """The notes on stderr, one ``xodrlint: note: ...`` line each: where a report holds
    findings only (``concise``, ``jsonl``), after them."""
    for note in notes:
        error_line(f"note: {one_line(note)}")


def _published(declared: str | None) -> tuple[int, int] | None:
    major, _, minor = (declared or "").partition(".")
    if not (major.isdigit() and minor.isdigit()):
        return None
    found = nearest_published(Version(int(major), int(minor)))
    return found.major, found.minor
