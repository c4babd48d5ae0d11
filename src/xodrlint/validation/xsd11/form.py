"""The XSD 1.0 form of an XSD 1.1 schema set, made once per set and machine and cached.

:func:`derive_xsd10` copies every document of the set with ``xs:assert``/``xs:assertion``
and ``xs:alternative`` removed and the ``vc:`` versioning attributes resolved as an XSD 1.1
processor would; a set using what the form cannot express is marked for full validation.
The form is written into the user cache folder, keyed by a SHA-256 of the source files,
with a manifest of what the derivation did, the result of one strict xmlschema build of
the set (later builds may skip the meta-schema check), where type alternatives can
apply, and, once built, xmlschema's model of the set pickled beside it.
:mod:`xodrlint.validation.xsd11.fast` validates with it.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import pickle
import shutil
import sys
import tempfile
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Final

from lxml import etree

from xodrlint.config import cache, plugins
from xodrlint.validation.sets import SchemaLoadError
from xodrlint.validation.source import XS, SchemaSource, read_schema_source

#: Where derived schema forms are cached (default: the user cache folder).
CACHE_DIR_ENV: Final = plugins.CACHE_ENV
#: Part of the cache key: bump it whenever :func:`derive_xsd10` changes its output.
DERIVATION_VERSION: Final = "xsd10-form/2"
MANIFEST: Final = "xodrlint-xsd10.json"

VC: Final = "http://www.w3.org/2007/XMLSchema-versioning"
#: The XSD version the derived form stands in for (vc:minVersion/maxVersion are read so).
_PROCESSOR_VERSION: Final = (1, 1)

# XSD 1.1 syntax the XSD 1.0 form cannot stand in for: the set is validated in full.
_UNSUPPORTED_ELEMENTS: Final = {
    "openContent": "open content",
    "defaultOpenContent": "default open content",
    "override": "xs:override",
}
_XSD11_TYPES: Final = frozenset(
    {"anyAtomicType", "dateTimeStamp", "dayTimeDuration", "yearMonthDuration", "error"}
)


def source_key(source: SchemaSource) -> str:
    """SHA-256 of the derivation version and of every file, by its relative path: the
    content, not the place, names a cached form."""
    digest = hashlib.sha256(DERIVATION_VERSION.encode())
    for path, data, _ in sorted(source.files, key=lambda item: source.relative(item[0])):
        digest.update(b"\0" + source.relative(path).encode() + b"\0")
        digest.update(hashlib.sha256(data).digest())
    return digest.hexdigest()


@dataclass
class Derivation:
    """What :func:`derive_xsd10` did to a set, and what it could not do."""

    asserts: int = 0
    alternatives: int = 0
    unsupported: list[str] = field(default_factory=list)
    schema_checked: bool = False
    """xmlschema built the source set in strict mode (its documents checked against the
    XSD meta-schema, every XPath compiled) without an error."""
    alternative_sites: list[list[str]] | None = None
    """Where an element with type alternatives can stand, as [parent tag, tag] pairs
    (parent "" for the root), read off that strict build; ``None`` when unknown."""
    translation: dict[str, Any] | None = None
    """The assertions and type alternatives in XPath 1.0
    (:func:`~xodrlint.validation.xsd11.translation.translate_set`), from that strict
    build; ``None`` when it did not run."""

    def note(self, problem: str) -> None:
        if problem not in self.unsupported:
            self.unsupported.append(problem)


def derive_xsd10(documents: Iterable[etree._Element]) -> Derivation:
    """Rewrite each schema document (in place) to its XSD 1.0 form; report what it did."""
    found = Derivation()
    roots = list(documents)
    for root in roots:
        _apply_conditional_inclusion(root, found)
        for tag in ("assert", "assertion"):
            for element in list(root.iter(f"{{{XS}}}{tag}")):
                if tag == "assertion":
                    # a facet of a simple type: the 1.1 checks only cover complex types
                    found.note("xs:assertion on a simple type")
                found.asserts += 1
                _remove(element)
        for alternative in list(root.iter(f"{{{XS}}}alternative")):
            declaration = alternative.getparent()
            if alternative.get("type") is None:
                found.note("a type alternative with an anonymous type")
            elif alternative.get("type", "").rpartition(":")[2] == "error":
                found.note("a type alternative to xs:error")
            if declaration is not None and declaration.get("block"):
                found.note("a type alternative on an element that blocks substitution")
            found.alternatives += 1
            _remove(alternative)
        _note_unsupported(root, found)
    blocking = any(
        element.get("block") or element.get("final")
        for root in roots
        for element in root.iter(f"{{{XS}}}complexType")
    )
    if found.alternatives and (blocking or any(r.get("blockDefault") for r in roots)):
        found.note("type alternatives with blocked substitution")
    return found


def _apply_conditional_inclusion(root: etree._Element, found: Derivation) -> None:
    """Keep what an XSD 1.1 processor keeps (vc:minVersion <= 1.1 < vc:maxVersion)."""
    for element in list(root.iter(etree.Element)):
        low = element.get(f"{{{VC}}}minVersion")
        high = element.get(f"{{{VC}}}maxVersion")
        if (low and _version(low) > _PROCESSOR_VERSION) or (
            high and _version(high) <= _PROCESSOR_VERSION
        ):
            if element is not root:
                _remove(element)
            continue
        for name in [str(n) for n in element.attrib]:
            if name.startswith(f"{{{VC}}}"):
                local = etree.QName(name).localname
                if local not in ("minVersion", "maxVersion"):
                    found.note(f"vc:{local}")
                del element.attrib[name]


def _version(text: str) -> tuple[int, ...]:
    try:
        return tuple(int(part) for part in text.strip().split("."))
    except ValueError:
        return (0,)


def _note_unsupported(root: etree._Element, found: Derivation) -> None:
    if root.get("defaultAttributes") or root.get("xpathDefaultNamespace"):
        found.note("schema-wide defaultAttributes or xpathDefaultNamespace")
    for element in root.iter(f"{{{XS}}}*"):
        local = etree.QName(element).localname
        if local in _UNSUPPORTED_ELEMENTS:
            found.note(_UNSUPPORTED_ELEMENTS[local])
        elif local == "explicitTimezone":
            found.note("the explicitTimezone facet")
        if element.get("inheritable") is not None:
            found.note("inheritable attributes")
        if element.get("notQName") is not None or element.get("notNamespace") is not None:
            found.note("wildcards with notQName or notNamespace")
        if element.get("xpathDefaultNamespace") is not None:
            found.note("xpathDefaultNamespace")
        if local in ("element", "attribute") and element.get("targetNamespace") is not None:
            found.note("targetNamespace on a local declaration")
        if local in ("key", "keyref", "unique") and element.get("ref") is not None:
            found.note("identity constraints by reference")
        if local == "all" and _all_needs_xsd11(element):
            found.note("xs:all beyond XSD 1.0")
        for attribute in ("type", "base", "itemType", "memberTypes"):
            for name in (element.get(attribute) or "").split():
                prefix, _, type_name = name.rpartition(":")
                if type_name in _XSD11_TYPES and element.nsmap.get(prefix or None) == XS:
                    found.note(f"the XSD 1.1 type xs:{type_name}")


def _all_needs_xsd11(group: etree._Element) -> bool:
    if group.get("maxOccurs", "1") != "1":
        return True
    for particle in group.iterchildren(etree.Element):
        local = etree.QName(particle).localname
        if local in ("any", "group", "all", "choice", "sequence"):
            return True
        if local == "element" and particle.get("maxOccurs", "1") not in ("0", "1"):
            return True
    return False


def _remove(element: etree._Element) -> None:
    parent = element.getparent()
    if parent is None:
        return
    # text after the element (never more than whitespace in a schema) stays in place
    previous = element.getprevious()
    if element.tail and element.tail.strip():
        if previous is not None:
            previous.tail = (previous.tail or "") + element.tail
        else:
            parent.text = (parent.text or "") + element.tail
    parent.remove(element)


def cache_dir() -> Path:
    """The folder holding derived schema forms, in the user cache folder (which
    ``XODRLINT_CACHE_DIR`` overrides)."""
    return plugins.cache_dir() / "xsd10"


@dataclass(frozen=True, slots=True)
class Xsd10Form:
    """The XSD 1.0 form of one set: its entry file (``None`` if the set needs XSD 1.1)."""

    entry: Path | None
    key: str
    asserts: int
    alternatives: int
    unsupported: tuple[str, ...]
    cached: bool
    schema_checked: bool = False
    """The source set passed xmlschema's strict build when the form was derived: later
    builds of the same files (same key) may skip that check, which is 80% of their cost."""
    alternative_sites: frozenset[tuple[str, str]] | None = None
    """(parent tag, tag) of every element that may have type alternatives ("" for the
    root's parent); ``None`` when the strict build did not run."""
    translation: dict[str, Any] | None = None
    """The set's assertions and type alternatives in XPath 1.0 (see
    :mod:`~xodrlint.validation.xsd11.selectors`); ``None`` when the strict build did not
    run."""


@contextlib.contextmanager
def xsd10_form(entry: Path) -> Iterator[Xsd10Form]:
    """The derived form of the set ``entry`` belongs to, from the cache or made now.

    The form is written to a temporary folder and renamed into place, so a reader never
    sees half a form; when the cache cannot be written the form lives in a temporary
    folder for as long as this context lasts (long enough to compile it).
    """
    source = read_schema_source(entry)
    key = source_key(source)
    folder = cache_dir() / key
    form = _read_form(folder, source, key)
    if form is not None:
        yield form
        return
    derivation = derive_xsd10(tree.getroot() for _, _, tree in source.files)
    written = None
    with contextlib.suppress(OSError):
        cache.make_folder(cache_dir())  # no cache, no point in checking
        _check_strictly(entry, derivation)
        _write_form(folder, source, derivation)
        written = _read_form(folder, source, key)
    if written is not None:
        yield written
        return
    # the cache cannot be written (read-only home, a file in the way): derive for now
    with tempfile.TemporaryDirectory(prefix="xodrlint-xsd10-") as scratch:
        _write_files(Path(scratch), source, derivation)
        form = _read_form(Path(scratch), source, key, cached=False)
        assert form is not None
        yield form


def _read_form(
    folder: Path, source: SchemaSource, key: str, *, cached: bool = True
) -> Xsd10Form | None:
    """The form in ``folder``, or ``None`` when there is none or it is not to be used:
    not trusted (see :mod:`xodrlint.config.cache`), a manifest of another shape, or a file
    whose content is not what was written (each case said once on stderr)."""
    manifest_path = folder / MANIFEST
    reason = cache.distrust(manifest_path) if cached else None
    if reason is not None:
        cache.warn(manifest_path, reason)
        return None
    try:
        manifest = json.loads(manifest_path.read_text("utf-8"))
    except (OSError, ValueError, RecursionError):
        return None
    shape = _manifest_shape(manifest)
    if shape is not None:
        cache.warn(manifest_path, f"{manifest_path} {shape}")
        return None
    altered = _altered_file(folder, manifest["files"])
    if altered is not None:
        cache.warn(manifest_path, f"{altered} does not hold what was written")
        return None
    entry = folder / source.relative(source.entry)
    unsupported = tuple(manifest["unsupported"])
    if not unsupported and source.relative(source.entry) not in manifest["files"]:
        return None
    return Xsd10Form(
        entry=None if unsupported else entry,
        key=key,
        asserts=manifest["asserts"],
        alternatives=manifest["alternatives"],
        unsupported=unsupported,
        cached=cached,
        schema_checked=manifest["schema_checked"] is True,
        alternative_sites=_sites_of(manifest.get("alternative_sites")),
        translation=_translation_of(manifest.get("translation")),
    )


#: The manifest's fields and the types :func:`_write_files` gives them.
_MANIFEST_FIELDS: Final = {
    "asserts": int,
    "alternatives": int,
    "unsupported": list,
    "schema_checked": bool,
    "files": dict,
}


def _manifest_shape(manifest: object) -> str | None:
    """What is wrong with the manifest's shape, or ``None``."""
    if not isinstance(manifest, dict):
        return "is not a JSON object"
    for name, kind in _MANIFEST_FIELDS.items():
        value = manifest.get(name)
        if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
            return f"has no {kind.__name__} '{name}'"
    if not all(isinstance(item, str) for item in manifest["unsupported"]):
        return "lists reasons that are not strings"
    files = manifest["files"]
    if not all(isinstance(k, str) and isinstance(v, str) for k, v in files.items()):
        return "records file hashes of another shape"
    return None


def _altered_file(folder: Path, hashes: dict[str, str]) -> Path | None:
    """The first form file whose content is not the one recorded, or that is missing,
    lies outside the folder, or is not to be trusted."""
    for relative, expected in hashes.items():
        path = folder / relative
        if folder.resolve() not in path.resolve().parents or cache.distrust(path) is not None:
            return path
        try:
            if cache.digest(path.read_bytes()) != expected:
                return path
        except OSError:
            return path
    return None


def full_validator(entry: Path, form: Xsd10Form) -> Any:
    """xmlschema's XSD 1.1 validator of the set, unpickled from the form's folder when an
    earlier run left it there (0.13 s instead of a 0.44 s build on the 1.8 sets). Only a
    set that passed the strict build is kept, so the pickle always holds a checked one;
    it is keyed by the versions of xmlschema, elementpath and Python that wrote it."""
    from xodrlint.validation.xsd11.full import Xsd11Validator

    if not (form.cached and form.schema_checked):
        return Xsd11Validator(entry, schema_checked=form.schema_checked)
    path = cache_dir() / form.key / _pickle_name()
    # unpickled only from a trusted file with the hash it was written with (a pickle
    # runs code); of another type, or damaged in a way the hash missed: build again
    content = cache.read(path)
    if content is not None:
        with contextlib.suppress(Exception):
            from xmlschema.validators import XMLSchemaBase

            schema = pickle.loads(content)
            if isinstance(schema, XMLSchemaBase) and schema.XSD_VERSION == "1.1":
                return Xsd11Validator.of_schema(_with_whole_parsers(schema))
        cache.warn(path, f"{path} does not hold an XSD 1.1 schema model")
    validator = Xsd11Validator(entry, schema_checked=True)
    with contextlib.suppress(pickle.PicklingError, RecursionError, TypeError):
        cache.write(path, pickle.dumps(validator.schema, pickle.HIGHEST_PROTOCOL))
    return validator


def _with_whole_parsers(schema: Any) -> Any:
    """``schema`` with its XPath parsers whole again: elementpath's parsers pickle their
    ``__dict__`` only, and ``source``, ``tokens``, ``token``, ``next_token`` and
    ``next_match`` are slots. Without them, an assertion whose XPath raised while it was
    evaluated (a type error, as the official multiBoard test's on every multiBoard)
    could not say where, and a ``cast as`` made no token: xmlschema raised
    AttributeError for the file instead of reporting. Each assertion has a parser of its
    own, which parsed the assertion's test; the others are put back as a new parser
    starts."""
    for component in schema.maps.iter_components():
        for owner in (component, getattr(component, "selector", None), *_fields(component)):
            parser = getattr(owner, "parser", None)
            if parser is not None:
                test = getattr(owner, "path", None)
                with contextlib.suppress(Exception):  # another parser's shape: as it was
                    _restore_slots(parser, test if isinstance(test, str) else "")
    return schema


def _fields(component: Any) -> tuple[Any, ...]:
    fields = getattr(component, "fields", None)
    return tuple(fields) if isinstance(fields, list | tuple) else ()


def _restore_slots(parser: Any, source: str) -> None:
    """What ``Parser.__init__`` sets, where the pickle lost it."""
    if not hasattr(parser, "source"):
        parser.source = source
    if not hasattr(parser, "tokens"):
        parser.tokens = iter(())
    if not hasattr(parser, "next_match"):
        parser.next_match = None
    if not hasattr(parser, "_start_token"):
        parser._start_token = parser.symbol_table["(start)"](parser)
    if not hasattr(parser, "token"):
        parser.token = parser._start_token
    if not hasattr(parser, "next_token"):
        parser.next_token = parser._start_token


def _pickle_name() -> str:
    import elementpath
    import xmlschema

    python = f"{sys.version_info.major}{sys.version_info.minor}"
    return (
        f"xmlschema-{xmlschema.__version__}-elementpath-{elementpath.__version__}-py{python}.pickle"
    )


def _sites_of(value: object) -> frozenset[tuple[str, str]] | None:
    if not isinstance(value, list):
        return None
    pairs = [item for item in value if isinstance(item, list) and len(item) == 2]
    if len(pairs) != len(value) or not all(isinstance(n, str) for pair in pairs for n in pair):
        return None
    return frozenset((parent, tag) for parent, tag in pairs)


def _translation_of(value: object) -> dict[str, Any] | None:
    """The manifest's translation if it has the shape written (its XPath is compiled, and
    refused if broken, by the fast path)."""
    if not isinstance(value, dict) or not isinstance(value.get("types"), list):
        return None
    for entry in value["types"]:
        if not (
            isinstance(entry, dict)
            and isinstance(entry.get("type"), str)
            and isinstance(entry.get("paths"), list)
            and all(isinstance(p, str) for p in entry["paths"])
            and isinstance(entry.get("assertions"), list)
            and all(_assertion_shape(a) for a in entry["assertions"])
        ):
            return None
    marks = value.get("marks")
    if marks is not None and not (
        isinstance(marks, list)
        and all(
            isinstance(m, dict)
            and isinstance(m.get("path"), str)
            and isinstance(m.get("type"), str)
            for m in marks
        )
    ):
        return None
    return value


def _assertion_shape(item: object) -> bool:
    if not isinstance(item, dict) or not isinstance(item.get("test"), str):
        return False
    if "fails" in item:
        return isinstance(item["fails"], str) and isinstance(item.get("uncertain"), str)
    return isinstance(item.get("why"), str)


def _check_strictly(entry: Path, derivation: Derivation) -> None:
    """Build the source set strictly once, and note what later runs may rely on."""
    from xodrlint.validation.xsd11.full import Xsd11Validator

    try:
        schema = Xsd11Validator(entry).schema
    except SchemaLoadError:
        return
    derivation.schema_checked = True
    derivation.alternative_sites = sorted([*site] for site in _alternative_sites(schema))
    from xodrlint.validation.xsd11.translation import translate_set

    derivation.translation = translate_set(schema).as_json()


def _alternative_sites(schema: Any) -> set[tuple[str, str]]:
    """(parent tag, tag) of every declaration with type alternatives, found by walking the
    content models down from the global elements (through every alternative type too)."""
    sites: set[tuple[str, str]] = set()
    seen: set[int] = set()
    pending: list[tuple[str, Any]] = [("", d) for d in schema.elements.values()]
    while pending:
        parent, declaration = pending.pop()
        if declaration.alternatives:
            sites.add((parent, declaration.local_name))
        if id(declaration) in seen:
            continue
        seen.add(id(declaration))
        types = (declaration.type, *(a.type for a in declaration.alternatives))
        for xsd_type in types:
            content = getattr(xsd_type, "content", None)
            if content is None or not hasattr(content, "iter_elements"):
                continue
            for child in content.iter_elements():
                if getattr(child, "local_name", None) and hasattr(child, "alternatives"):
                    pending.append((declaration.local_name, child))
    return sites


def _write_form(folder: Path, source: SchemaSource, derivation: Derivation) -> None:
    cache.make_folder(folder.parent)
    if cache.distrust(folder.parent) is not None:
        raise PermissionError(f"{folder.parent} is not to be trusted")
    if folder.exists() and cache.distrust(folder) is None:
        # our own form that did not pass (altered, of another shape): replaced, not kept
        stale = Path(tempfile.mkdtemp(prefix=".stale-", dir=folder.parent))
        with contextlib.suppress(OSError):
            folder.rename(stale / "form")
        shutil.rmtree(stale, ignore_errors=True)
    scratch = Path(tempfile.mkdtemp(prefix=".partial-", dir=folder.parent))
    try:
        _write_files(scratch, source, derivation)
        try:
            scratch.rename(folder)
        except OSError:
            if not (folder / MANIFEST).is_file():
                raise
            # another process wrote the same form first: theirs is as good as ours
    finally:
        if scratch.exists():
            shutil.rmtree(scratch, ignore_errors=True)


def _write_files(folder: Path, source: SchemaSource, derivation: Derivation) -> None:
    hashes: dict[str, str] = {}
    for path, _, tree in source.files:
        relative = source.relative(path)
        target = folder / relative
        cache.make_folder(target.parent)
        data = etree.tostring(tree, xml_declaration=True, encoding="utf-8")
        target.write_bytes(data)
        target.chmod(0o600)
        hashes[relative] = cache.digest(data)
    manifest = {
        "derivation": DERIVATION_VERSION,
        "derived_from": str(source.entry),
        "entry": source.relative(source.entry),
        "asserts": derivation.asserts,
        "alternatives": derivation.alternatives,
        "unsupported": derivation.unsupported,
        "schema_checked": derivation.schema_checked,
        "alternative_sites": derivation.alternative_sites,
        "translation": derivation.translation,
        # what later runs verify before libxml2 reads the form: a form swapped for a
        # permissive schema would lose findings without a word
        "files": hashes,
    }
    (folder / MANIFEST).write_text(json.dumps(manifest, indent=1), "utf-8")
    (folder / MANIFEST).chmod(0o600)
