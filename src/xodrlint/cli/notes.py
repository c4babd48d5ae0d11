"""What a run says beside its findings about files the built-in schema alone validated:
that only their railroad elements were, and where the official set of their version comes
from (``schemas fetch`` brings 1.1 to 1.8.0; ASAM publishes the others)."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Final

from xodrlint.document import Version, nearest_published
from xodrlint.findings import FileReport
from xodrlint.messages import one_line
from xodrlint.output import error_line
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


def run_notes(reports: list[FileReport]) -> tuple[str, ...]:
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
