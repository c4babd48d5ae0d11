"""The files of a schema set, read once: the entry XSD and every local file it includes,
imports, redefines or overrides, each with its bytes and parsed tree.

Both validators read sets through this: libxml2's (whose type catalogue explains its
errors) and the XSD 1.1 fast path (whose cached form is keyed by these bytes).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Final

from lxml import etree

from xodrlint.validation.sets import SchemaLoadError

XS: Final = "http://www.w3.org/2001/XMLSchema"
_REFERENCES: Final = tuple(
    f"{{{XS}}}{name}" for name in ("include", "import", "redefine", "override")
)


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


def read_schema_source(entry: Path) -> SchemaSource:
    """The set ``entry`` starts; a file that cannot be read or parsed is a
    :class:`SchemaLoadError`. Schemas come from the user's disk: they may name their
    siblings but never reach the network or expand entities."""
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    files: list[tuple[Path, bytes, etree._ElementTree]] = []
    pending, seen = [Path(os.path.realpath(entry))], set()
    while pending:
        path = pending.pop()
        if path in seen:
            continue
        seen.add(path)
        try:
            data = path.read_bytes()
            tree = etree.ElementTree(etree.fromstring(data, parser, base_url=str(path)))
        except (OSError, etree.XMLSyntaxError) as error:
            raise SchemaLoadError(f"cannot read schema {path}: {error}") from error
        files.append((path, data, tree))
        for reference in tree.getroot().iterchildren(*_REFERENCES):
            location = reference.get("schemaLocation")
            if location and "://" not in location:
                pending.append(Path(os.path.realpath(path.parent / location)))
    return SchemaSource(Path(os.path.realpath(entry)), tuple(files))
