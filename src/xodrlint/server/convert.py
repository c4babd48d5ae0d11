"""Findings as LSP diagnostics: ranges in the client's position encoding, the rule's page,
related locations. Pure functions over a snapshot of the text that was linted."""

from __future__ import annotations

import codecs
import re
from collections.abc import Sequence
from typing import Final

from lsprotocol import types

from xodrlint.document.positions import lines_of
from xodrlint.findings import FileReport, Finding, Severity
from xodrlint.rules.registry import Registry

SOURCE: Final = "xodrlint"
HELP_URI: Final = "https://github.com/xodrlint/xodrlint/blob/main/docs/rules/{code}.md"
BUILTIN_PACK_PREFIX: Final = "xodrlint.rules"
SEVERITY: Final = {
    Severity.ERROR: types.DiagnosticSeverity.Error,
    Severity.WARNING: types.DiagnosticSeverity.Warning,
    Severity.INFO: types.DiagnosticSeverity.Information,
}
#: An XML name after ``<``: the range of a diagnostic ends where the start tag's name does.
_NAME: Final = re.compile(r"[^\s/>]+")
#: The encoding an XML declaration names (after an optional byte order mark).
_DECLARED: Final = re.compile(
    r"\ufeff?<\?xml\s[^>]*?\bencoding\s*=\s*[\"']([A-Za-z][A-Za-z0-9._-]*)[\"']"
)


def document_codec(text: str) -> str:
    """The codec an editor's ``text`` is written in on disk: the one its XML declaration
    names where the text can be written in it, else UTF-8."""
    declared = _DECLARED.match(text)
    if declared is not None:
        try:
            codec = codecs.lookup(declared.group(1)).name
            text.removeprefix("\ufeff").encode(codec)
        except (LookupError, UnicodeEncodeError):
            return "utf-8"
        return codec
    return "utf-8"


def document_bytes(text: str) -> bytes:
    """The bytes of an editor's ``text`` as its file holds them: in the encoding its XML
    declaration names (a document declaring UTF-16 is UTF-16 on disk, and the parser
    refuses UTF-8 under that declaration), UTF-8 where it names none, or one the text
    cannot be written in (the parser then says what it finds wrong)."""
    codec = document_codec(text)
    if codec != "utf-8":
        # a byte order mark the editor kept: the codec writes its own, or none
        return text.removeprefix("\ufeff").encode(codec)
    # a lone surrogate (an editor may send one) is written as the bytes it stands for:
    # not UTF-8, so the parser reports it where it stands (XS001) instead of no lint
    return text.encode("utf-8", "surrogatepass")


def document_text(data: bytes, text: str) -> str:
    """Bytes :func:`document_bytes` made of ``text`` (then edited) as the editor's text."""
    codec = document_codec(text)
    decoded = data.decode(codec) if codec != "utf-8" else data.decode("utf-8", "surrogatepass")
    if decoded.startswith("\ufeff") and not text.startswith("\ufeff"):
        decoded = decoded[1:]  # the codec's own mark, which the editor's text lacks
    return decoded


class Lines:
    """The lines of the linted text, split once at each line break the protocol counts
    (``\\r\\n``, ``\\n`` or a lone ``\\r``; xodrlint's positions count the same)."""

    def __init__(self, text: str) -> None:
        self._lines = lines_of(text)

    def get(self, line: int) -> str:
        """The 1-based ``line``'s text, empty past the end (a finding of a stale tree)."""
        return self._lines[line - 1] if 0 < line <= len(self._lines) else ""


def units(text: str, encoding: str) -> int:
    """How long ``text`` is in the client's position units: UTF-16 code units (LSP's
    default: a character outside the BMP counts two), UTF-8 bytes or code points."""
    if encoding == types.PositionEncodingKind.Utf32:
        return len(text)
    if encoding == types.PositionEncodingKind.Utf8:
        return len(text.encode("utf-8", "surrogatepass"))
    return len(text.encode("utf-16-le", "surrogatepass")) // 2


def tag_range(lines: Lines, line: int, column: int | None, encoding: str) -> types.Range:
    """From the start tag's ``<`` to the end of its name; the whole line where the finding
    has no column (a file in an encoding whose columns cannot be counted)."""
    text = lines.get(line)
    row = max(line - 1, 0)
    if column is None:
        return types.Range(types.Position(row, 0), types.Position(row, units(text, encoding)))
    start = column - 1
    name = _NAME.match(text, start + 1) if text[start : start + 1] == "<" else None
    end = name.end() if name else min(start + 1, len(text))
    first = units(text[:start], encoding)
    return types.Range(
        types.Position(row, first), types.Position(row, first + units(text[start:end], encoding))
    )


def help_uri(registry: Registry, code: str) -> str | None:
    """The rule's page in the repository, as SARIF's ``helpUri``: built-in rules only."""
    rule = registry.by_code.get(code)
    if rule is None:
        return None
    pack = rule.meta.pack
    builtin = pack == BUILTIN_PACK_PREFIX or pack.startswith(BUILTIN_PACK_PREFIX + ".")
    return HELP_URI.format(code=code) if builtin else None


def diagnostic(
    finding: Finding, uri: str, lines: Lines, encoding: str, registry: Registry
) -> types.Diagnostic:
    href = help_uri(registry, finding.code)
    related = [
        types.DiagnosticRelatedInformation(
            types.Location(uri, tag_range(lines, place.line, None, encoding)), place.xpath
        )
        for place in finding.related
    ]
    return types.Diagnostic(
        range=tag_range(lines, finding.line, finding.column, encoding),
        message=finding.message,
        severity=SEVERITY.get(finding.severity, types.DiagnosticSeverity.Warning),
        code=finding.code,
        code_description=types.CodeDescription(href) if href else None,
        source=SOURCE,
        related_information=related or None,
        data=fix_data(finding, lines, encoding),
    )


def fix_data(finding: Finding, lines: Lines, encoding: str) -> dict[str, object] | None:
    """A finding's fix as a diagnostic's ``data``: what its quick fix does, in the
    client's position encoding (the server turns it into the action's edit)."""
    fix = finding.fix
    if fix is None or not fix.edits:
        return None
    edits = [
        {
            "range": {
                "start": _position(lines, edit.start_line, edit.start_column, encoding),
                "end": _position(lines, edit.end_line, edit.end_column, encoding),
            },
            "newText": edit.content,
        }
        for edit in fix.edits
    ]
    return {
        "fix": {"applicability": str(fix.applicability), "message": fix.message, "edits": edits}
    }


def _position(lines: Lines, line: int, column: int, encoding: str) -> dict[str, int]:
    text = lines.get(line)
    return {"line": line - 1, "character": units(text[: column - 1], encoding)}


def diagnostics(
    report: FileReport, uri: str, text: str, encoding: str, registry: Registry
) -> Sequence[types.Diagnostic]:
    lines = Lines(text)
    # a finding in a file the document includes has its line in that file: the
    # document's own diagnostics leave it out (that file's own lint shows it)
    return [
        diagnostic(f, uri, lines, encoding, registry)
        for f in report.findings
        if f.path == report.path
    ]
