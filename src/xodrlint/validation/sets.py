"""Where the XSD for a declared OpenDRIVE version comes from.

The official ASAM schemas are not ours to ship. They are looked for, in this order, in
``--schema`` (or ``schema`` in the config), ``XODRLINT_SCHEMA_PATH``, and the user data
folder that ``xodrlint schemas add|fetch`` fills; when none has the version, the
built-in railroad schema (written by us, ``builtin/``) checks the railroad subtrees.
"""

from __future__ import annotations

import functools
import os
import re
from collections.abc import Iterator, Mapping
from enum import StrEnum
from pathlib import Path
from typing import Final, NamedTuple

from platformdirs import user_data_path

from xodrlint.inputs.files import os_reason, read_regular_file, read_regular_head

SCHEMA_PATH_ENV: Final = "XODRLINT_SCHEMA_PATH"
BUILTIN_DIR: Final = Path(__file__).parent / "builtin"

# A top-level declaration of the OpenDRIVE element marks a schema set's entry file.
_DECLARES_ROOT: Final = re.compile(rb"<(?:\w+:)?element\s+(?:[^>]*\s)?name=\"OpenDRIVE\"")
_VERSION_DIR: Final = re.compile(r"^v?(\d+)\.(\d+)(?:\.(\d+))?[A-Za-z]?$")
_VERSION_IN_NAME: Final = re.compile(r"(?:^|[_\-\s])(\d)[._](\d)(?:[._](\d))?[A-Za-z]?(?:[_\-.]|$)")
_VERSION_IN_TEXT: Final = re.compile(rb"OpenDRIVE\s+V?(\d)\.(\d)(?:\.(\d))?")
_SHORT_NAME: Final = re.compile(r"opendrive_(\d)(\d)_core", re.IGNORECASE)


class SchemaLoadError(Exception):
    """A schema file that cannot be read or compiled: a set-up error, not a finding."""


#: The largest schema file read (ASAM's largest is under 300 kB): a schema may come
#: from a folder xodrlint was merely opened in, and ``/dev/zero`` has no end.
MAX_SCHEMA_FILE_BYTES: Final = 16 * 1024 * 1024


def read_schema_file(path: Path) -> bytes:
    """The bytes of one schema file: a regular file of a bounded size (a FIFO would block
    the run), else a :class:`SchemaLoadError` naming it."""
    try:
        return read_regular_file(path, MAX_SCHEMA_FILE_BYTES)
    except OSError as error:
        raise SchemaLoadError(f"cannot read schema {path}: {os_reason(error)}") from error


class Origin(StrEnum):
    """Where a schema was found, as the report names it."""

    OPTION = "--schema"
    CONFIG = "config"
    ENVIRONMENT = SCHEMA_PATH_ENV
    USER_DATA = "user data"
    BUILTIN = "built-in"


class SchemaSet(NamedTuple):
    """One set of XSDs for one OpenDRIVE version (or for any, when ``version`` is None)."""

    entry: Path
    version: tuple[int, int, int] | None
    origin: Origin
    source: str = ""
    """What named the set, for messages, where the origin alone does not say: the config
    file whose ``schema`` it is."""

    @property
    def given_by(self) -> str:
        """Where the set came from, as messages say it (``--schema``, a config file)."""
        return self.source or str(self.origin)

    @property
    def is_builtin(self) -> bool:
        return self.origin is Origin.BUILTIN

    @property
    def is_xsd11(self) -> bool:
        """OpenDRIVE 1.8 and later use XSD 1.1 (assertions, type alternatives): a set is
        taken for XSD 1.1 by the version it carries (its folder, its name, ASAM's header
        comment) or by what any of its files holds, whichever route it came by."""
        if self.is_builtin:
            return False
        version = self.version or version_of_set(self.entry)
        return (version is not None and version >= (1, 8, 0)) or uses_xsd11(self.entry)

    @property
    def serves_every_version(self) -> bool:
        """A set given as one file or one folder: it validates files of every version."""
        return self.version is None and not self.is_builtin

    @property
    def own_version(self) -> tuple[int, int, int] | None:
        """The version the set is of: its own, else read off its folder, name or header."""
        return self.version or version_of_set(self.entry)

    @property
    def label(self) -> str:
        if self.is_builtin and self.version is not None:
            return f"built-in railroad schema for OpenDRIVE {self.version[0]}.{self.version[1]}"
        own = self.own_version
        if own is None:
            return "schema of unknown OpenDRIVE version"
        return f"OpenDRIVE {'.'.join(map(str, own))} schema"

    def version_note(self, declared: tuple[int, int], effective: tuple[int, int]) -> str | None:
        """What a report says of a file that declares ``declared`` (checked as the
        published ``effective``) validated with this set, when the set was given for every
        version and is of another one. Silent where the set's version is unknown: nothing
        tells whether it differs (its label says it is unknown)."""
        own = self.own_version
        if not self.serves_every_version or own is None or own[:2] == effective:
            return None
        checked = "" if declared == effective else f" (checked as {effective[0]}.{effective[1]})"
        return (
            f"the file declares OpenDRIVE {declared[0]}.{declared[1]}{checked}; the "
            f"{self.label} given for every version ({self.given_by}) validated it"
        )

    def describe(self) -> str:
        if self.is_builtin:
            return f"{self.label} (railroad elements only)"
        return f"{self.label} ({self.entry}, from {self.given_by})"


def user_schema_dir() -> Path:
    """The user data folder ``xodrlint schemas add|fetch`` fills."""
    override = os.environ.get("XODRLINT_DATA_DIR")
    base = Path(override) if override else user_data_path("xodrlint", appauthor=False)
    return base / "schemas"


class SchemaFinder(NamedTuple):
    """Looks up schema sets in the documented order; one per run, results cached."""

    option: Path | None = None
    option_origin: Origin = Origin.OPTION
    environment: Mapping[str, str] | None = None
    data_dir: Path | None = None
    option_source: str = ""
    """The config file that named ``option`` (empty: the command line did)."""

    def locations(self) -> Iterator[tuple[Path, Origin]]:
        if self.option is not None:
            yield self.option, self.option_origin
        for path in self.environment_paths():
            yield path, Origin.ENVIRONMENT
        yield (self.data_dir or user_schema_dir()), Origin.USER_DATA

    def environment_paths(self) -> list[Path]:
        """The paths ``XODRLINT_SCHEMA_PATH`` names."""
        env = os.environ if self.environment is None else self.environment
        parts = env.get(SCHEMA_PATH_ENV, "").split(os.pathsep)
        return [Path(part.strip()).expanduser() for part in parts if part.strip()]

    def find(self, major: int, minor: int) -> SchemaSet:
        """The official set for ``major.minor`` (newest patch), else the built-in one."""
        for location, origin in self.locations():
            found = find_in(location, major, minor, origin)
            if found is not None:
                return self._named(found)
        return builtin_set(major, minor)

    def official_sets(self) -> Iterator[SchemaSet]:
        """Every official set any location offers, for ``xodrlint schemas list``."""
        for location, origin in self.locations():
            yield from map(self._named, _sets_in(location, origin))

    def _named(self, found: SchemaSet) -> SchemaSet:
        if found.origin is self.option_origin and self.option_source:
            return found._replace(source=self.option_source)
        return found


def _names_a_file(location: Path) -> bool:
    """A file, or anything else that is there and no folder (a FIFO named as a schema is
    refused when read, not passed over for the built-in schema)."""
    return location.exists() and not location.is_dir()


def find_in(location: Path, major: int, minor: int, origin: Origin) -> SchemaSet | None:
    if _names_a_file(location):
        return SchemaSet(_real(location), None, origin)
    best: SchemaSet | None = None
    for candidate in _sets_in(location, origin):
        if candidate.version is None:
            return candidate  # a folder holding one set serves every version
        if candidate.version[:2] == (major, minor) and (
            best is None or (best.version or ()) < candidate.version
        ):
            best = candidate
    return best


def _sets_in(location: Path, origin: Origin) -> Iterator[SchemaSet]:
    if _names_a_file(location):
        yield SchemaSet(_real(location), None, origin)
        return
    if not location.is_dir():
        return
    subfolders = sorted(p for p in location.iterdir() if p.is_dir() and _VERSION_DIR.match(p.name))
    if not subfolders:
        entry = entry_xsd(location)
        if entry is not None:
            yield SchemaSet(entry, None, origin)
        return
    for folder in subfolders:
        entry = entry_xsd(folder)
        if entry is not None:
            yield SchemaSet(entry, _version_of_folder(folder.name), origin)


def entry_xsd(folder: Path) -> Path | None:
    """The XSD of ``folder`` that declares the ``OpenDRIVE`` element."""
    for candidate in sorted(folder.glob("*.xsd")):
        try:
            head = read_schema_file(candidate)
        except SchemaLoadError:
            continue
        if _DECLARES_ROOT.search(head):
            return _real(candidate)
    return None


#: The marker that asks for XSD 1.1 (ASAM's 1.8 files do not always carry it).
_MIN_VERSION_11: Final = re.compile(rb"minVersion\s*=\s*[\"']1\.1[\"']")
#: Elements only XSD 1.1 has, by their local names.
_XSD11_ELEMENTS: Final = (
    b"assert",
    b"assertion",
    b"alternative",
    b"openContent",
    b"defaultOpenContent",
    b"override",
)
_AFTER_A_NAME: Final = frozenset((b" ", b"\t", b"\r", b"\n", b"/", b">"))
_SCHEMA_LOCATION: Final = re.compile(rb"schemaLocation\s*=\s*[\"']([^\"']+)[\"']")


@functools.cache
def uses_xsd11(entry: Path) -> bool:
    """Whether ``entry`` or a local file it includes or imports (followed through their
    ``schemaLocation``) holds XSD 1.1 content. Read as bytes: a file that cannot be read
    is left to the compile, which says so."""
    pending, seen = [entry], set()
    while pending:
        path = pending.pop()
        if path in seen:
            continue
        seen.add(path)
        try:
            data = read_schema_file(path)
        except SchemaLoadError:
            continue
        if _holds_xsd11(data):
            return True
        for location in _SCHEMA_LOCATION.findall(data):
            if b"://" not in location:
                # normalised, not resolved: a link per include cost a set a millisecond
                pending.append(Path(os.path.normpath(path.parent / os.fsdecode(location))))
    return False


def _holds_xsd11(data: bytes) -> bool:
    """An element only XSD 1.1 has (``xs:assert``, ``xs:alternative``, ...; any prefix)
    or the 1.1 marker. The words are found by byte search, then their neighbours read: a
    regular expression tried at every byte took milliseconds per set, on every run."""
    for word in _XSD11_ELEMENTS:
        at = data.find(word)
        while at > 0:
            after = data[at + len(word) : at + len(word) + 1]
            if data[at - 1 : at] in (b"<", b":") and after in _AFTER_A_NAME:
                return True
            at = data.find(word, at + 1)
    return b"minVersion" in data and _MIN_VERSION_11.search(data) is not None


def _version_of_folder(name: str) -> tuple[int, int, int]:
    match = _VERSION_DIR.match(name)
    assert match is not None
    return int(match[1]), int(match[2]), int(match[3] or 0)


@functools.lru_cache(maxsize=64)
def version_of_set(entry: Path) -> tuple[int, int, int] | None:
    """Guess a schema set's version from its folder, file name or ASAM's header comment."""
    folder = _VERSION_DIR.match(entry.parent.name)
    if folder:
        return _version_of_folder(entry.parent.name)
    short = _SHORT_NAME.search(entry.name)
    if short:
        return int(short[1]), int(short[2]), 0
    named = _VERSION_IN_NAME.search(entry.stem)
    if named:
        return int(named[1]), int(named[2]), int(named[3] or 0)
    try:
        head = read_regular_head(entry, 2048)
    except OSError:  # the compile says so, in one line
        return None
    text = _VERSION_IN_TEXT.search(head)
    if text:
        return int(text[1]), int(text[2]), int(text[3] or 0)
    return None


# The built-in railroad schema files, by the first minor version each covers.
_BUILTIN_FILES: Final = {
    4: "railroad-1.4.xsd",
    5: "railroad-1.5.xsd",
    6: "railroad-1.6.xsd",
    7: "railroad-1.7.xsd",
    8: "railroad-1.8.xsd",
}


def builtin_set(major: int, minor: int) -> SchemaSet:
    """Our own railroad schema for ``major.minor`` (railroad content starts in 1.4)."""
    first = max((m for m in _BUILTIN_FILES if m <= minor), default=min(_BUILTIN_FILES))
    return SchemaSet(BUILTIN_DIR / _BUILTIN_FILES[first], (major, minor, 0), Origin.BUILTIN)


def _real(path: Path) -> Path:
    # libxml2 resolves xs:include relative to the including file's URL; a path with '..'
    # makes the 1.6/1.7 sets include their core twice, so always use the real path.
    return Path(os.path.realpath(path))
