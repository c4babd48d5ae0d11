"""The files of a schema set, read once: the entry XSD and every local file it includes,
imports, redefines or overrides, each with its bytes and parsed tree.

Both validators read sets through this: libxml2's (whose type catalogue explains its
errors) and the XSD 1.1 fast path (whose cached form is keyed by these bytes).

A schema may come from a folder xodrlint was merely opened in (a workspace's
``xodrlint.toml`` names it), so it is read as hostile input:

- only regular files of a bounded size (:func:`~xodrlint.validation.sets.read_schema_file`:
  a FIFO would block the run, ``/dev/zero`` would fill the memory);
- no file with a document type declaration: its entities are how a schema would pull
  another file's content into a message (the parser expands none, and a schema needs none);
- every ``schemaLocation`` a relative path to a file inside the entry's folder, through
  no symbolic link that leaves it: no URL, no absolute path.

libxml2 compiles a set from a private copy of exactly these bytes
(:meth:`SchemaSource.compiled_from_copy`): its schema parser reads included files itself,
with entity loading on, and would otherwise read whatever the disk holds by then.
"""

from __future__ import annotations

import contextlib
import os
import re
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Final

from lxml import etree

from xodrlint.config.settings import shown_value
from xodrlint.validation.sets import SchemaLoadError, read_schema_file

XS: Final = "http://www.w3.org/2001/XMLSchema"
_REFERENCES: Final = tuple(
    f"{{{XS}}}{name}" for name in ("include", "import", "redefine", "override")
)

#: A URI scheme (``http:``, ``file:``) or a drive letter at the start of a location.
_SCHEME: Final = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")


@dataclass(frozen=True, slots=True)
class SchemaSource:
    """The files of one schema set: each path with its bytes and parsed tree, the entry
    first."""

    entry: Path
    files: tuple[tuple[Path, bytes, etree._ElementTree], ...]

    @property
    def trees(self) -> list[etree._ElementTree]:
        return [tree for _, _, tree in self.files]

    @property
    def base(self) -> Path:
        """The deepest folder holding every file (relative layout is kept below it)."""
        return Path(os.path.commonpath([str(path.parent) for path, _, _ in self.files]))

    def relative(self, path: Path) -> str:
        return path.relative_to(self.base).as_posix()

    @contextlib.contextmanager
    def compiled_from_copy(self, entry_tree: etree._ElementTree) -> Iterator[CopyNames]:
        """While the context lasts, ``entry_tree`` (the entry's tree, maybe changed in
        memory) has its URL in a private folder that holds the bytes of every other
        file of the set as they were read, at the same relative places: what libxml2
        compiles from it is exactly what was checked here. Yields the names of the
        copies, to put a compile error back on the user's file."""
        docinfo = entry_tree.docinfo
        if len(self.files) == 1:  # nothing for libxml2 to read besides the tree itself
            yield CopyNames({})
            return
        original_url = docinfo.URL
        with tempfile.TemporaryDirectory(prefix="xodrlint-schema-") as folder:
            private = Path(folder)
            names: dict[str, Path] = {}
            for path, data, _ in self.files:
                copy = private / self.relative(path)
                copy.parent.mkdir(parents=True, exist_ok=True)
                copy.write_bytes(data)
                names[os.path.realpath(copy)] = path
            docinfo.URL = str(private / self.relative(self.entry))
            try:
                yield CopyNames(names)
            finally:
                docinfo.URL = original_url


class CopyNames(dict[str, Path]):
    """The files of a private copy of a set, by the user's file each was copied from."""

    def original(self, name: str) -> str:
        """The user's file for ``name`` (a copy's path), else ``name`` as it is."""
        found = self.get(os.path.realpath(name))
        return str(found) if found is not None else name


def read_schema_source(entry: Path) -> SchemaSource:
    """The set ``entry`` starts; a file that cannot be read or parsed, or that breaks
    the rules of the module's docstring, is a :class:`SchemaLoadError`."""
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    real_entry = Path(os.path.realpath(entry))
    folder = real_entry.parent
    files: list[tuple[Path, bytes, etree._ElementTree]] = []
    pending, seen = [real_entry], set()
    while pending:
        path = pending.pop()
        if path in seen:
            continue
        seen.add(path)
        data = read_schema_file(path)
        try:
            tree = etree.ElementTree(etree.fromstring(data, parser, base_url=str(path)))
        except etree.XMLSyntaxError as error:
            raise SchemaLoadError(f"cannot read schema {path}: {error}") from error
        docinfo = tree.docinfo
        if docinfo.doctype or docinfo.internalDTD is not None:  # type: ignore[attr-defined]
            raise SchemaLoadError(
                f"schema {path} has a document type declaration (<!DOCTYPE>): xodrlint reads "
                "no schema with one (its entities could pull other files into messages)"
            )
        files.append((path, data, tree))
        for reference in tree.getroot().iterchildren(*_REFERENCES):
            location = reference.get("schemaLocation")
            if location:
                pending.append(_confined(path, location, folder))
    return SchemaSource(real_entry, tuple(files))


def _confined(including: Path, location: str, folder: Path) -> Path:
    """The file ``location`` names from ``including``, when it lies inside ``folder``."""
    target = None
    if not _SCHEME.match(location) and not Path(location).is_absolute():
        target = Path(os.path.realpath(including.parent / location))
        if os.path.commonpath([folder, target]) != str(folder):
            target = None
    if target is None:
        raise SchemaLoadError(
            f"schema {including} names {shown_value(location)}: xodrlint reads the files of "
            f"a schema set from its own folder ({folder}) only, by relative paths"
        )
    return target
