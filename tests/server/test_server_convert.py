"""Findings as LSP diagnostics (xodrlint.server.convert): positions in each encoding a
client may negotiate, ranges without a column, and rule pages."""

from __future__ import annotations

import pytest

pytest.importorskip("lsprotocol", reason="the server extra (pygls) is not installed")

from lsprotocol import types

from xodrlint.api import default_registry
from xodrlint.findings import Severity
from xodrlint.server.convert import Lines, help_uri, tag_range, units

LINE = '  <!-- \U0001f682 é --><switch id="1"/>'


@pytest.mark.parametrize(
    ("encoding", "start", "end"),
    [
        (types.PositionEncodingKind.Utf16, 15, 22),  # the emoji: two units
        (types.PositionEncodingKind.Utf32, 14, 21),  # code points, as the finding's column
        (types.PositionEncodingKind.Utf8, 18, 25),  # four bytes and two bytes
    ],
)
def test_a_range_in_each_position_encoding(encoding: str, start: int, end: int) -> None:
    column = LINE.index("<switch") + 1  # 1-based code points, as Finding.column
    found = tag_range(Lines("first\n" + LINE), 2, column, encoding)
    assert found == types.Range(types.Position(1, start), types.Position(1, end))


def test_a_finding_without_a_column_spans_its_line() -> None:
    found = tag_range(Lines(LINE), 1, None, types.PositionEncodingKind.Utf16)
    assert found == types.Range(types.Position(0, 0), types.Position(0, units(LINE, "utf-16")))


def test_a_position_past_the_text_is_an_empty_range() -> None:
    # the parser's position of XS001 may be past a line's last character
    found = tag_range(Lines("<a>"), 1, 4, types.PositionEncodingKind.Utf16)
    assert found == types.Range(types.Position(0, 3), types.Position(0, 3))


def test_only_builtin_rules_link_a_page() -> None:
    registry = default_registry()
    assert help_uri(registry, "PT003") == (
        "https://github.com/xodrlint/xodrlint/blob/main/docs/rules/PT003.md"
    )
    assert help_uri(registry, "ZZ999") is None


def _example() -> str:
    from tests.conftest import REPO

    return (REPO / "examples" / "broken.xodr").read_text(encoding="utf-8")


def _ranges(text: str) -> list[tuple[str, int, int, int, int]]:
    from xodrlint.api import lint_bytes
    from xodrlint.server.convert import diagnostics, document_bytes

    report = lint_bytes(document_bytes(text), "broken.xodr")
    found = diagnostics(
        report, "file:///broken.xodr", text, types.PositionEncodingKind.Utf16, default_registry()
    )
    return [
        (
            str(d.code),
            d.range.start.line,
            d.range.start.character,
            d.range.end.line,
            d.range.end.character,
        )
        for d in found
    ]


def test_a_buffer_declaring_utf_16_gets_the_diagnostics_of_its_file() -> None:
    # the buffer was encoded as UTF-8 whatever it declared: one XS001 ("blank needed here")
    text = _example()
    declared = text.replace('encoding="UTF-8"', 'encoding="UTF-16"', 1)
    assert declared != text
    expected = _ranges(text)
    assert len(expected) >= 5
    assert _ranges(declared) == expected
    assert _ranges(declared.replace('"UTF-16"', '"ISO-8859-1"', 1)) == expected


def test_a_buffer_of_lone_carriage_returns_gets_each_diagnostic_on_its_line() -> None:
    # lines were counted on "\n" only: every finding on line 1, thousands of columns in
    text = _example()
    expected = _ranges(text)
    assert _ranges(text.replace("\n", "\r")) == expected
    assert _ranges(text.replace("\n", "\r\n")) == expected


def test_a_fix_is_placed_in_the_clients_units_and_fix_all_keeps_crlf() -> None:
    from xodrlint.findings import Finding
    from xodrlint.fixes import Applicability, FindingFix, TextEdit
    from xodrlint.server.actions import fix_all_action
    from xodrlint.server.convert import fix_data

    text = '<a>\r\n  <!-- \U0001f682 --><b c="x"/>\r\n</a>\r\n'
    column = text.split("\r\n")[1].index('"x"') + 2  # 1-based, of the x, in code points
    edit = TextEdit("y", 2, column, 2, column + 1, 0, 0)
    finding = Finding("a", 2, 3, "ZZ001", "u", Severity.ERROR, "m", "/a/b")._replace(
        fix=FindingFix(Applicability.SAFE, "say y", (edit,))
    )
    data = fix_data(finding, Lines(text), types.PositionEncodingKind.Utf16)
    assert data is not None
    (placed,) = data["fix"]["edits"]  # type: ignore[index]
    assert placed["range"]["start"] == {"line": 1, "character": column}  # the emoji: two
    action = fix_all_action("u", text, text.replace('"x"', '"y"'), types.PositionEncodingKind.Utf16)
    assert action is not None and action.edit is not None and action.edit.changes is not None
    (change,) = action.edit.changes["u"]
    assert change.new_text == "y" and change.range.start == types.Position(1, column)
    # a change that ends a line: never between the two characters of its break
    longer = fix_all_action("u", text, text.replace("</a>\r\n", "</a>\r\n\r\n"), "utf-16")
    assert longer is not None and longer.edit is not None and longer.edit.changes is not None
    (added,) = longer.edit.changes["u"]
    assert added.new_text == "\r\n" and added.range.start == types.Position(3, 0)
    # moved back off a break, the edit is still the least one: a lone "\r" inserted
    lone = fix_all_action("u", "\r\n", "\r\r\n", "utf-16")
    assert lone is not None and lone.edit is not None and lone.edit.changes is not None
    (inserted,) = lone.edit.changes["u"]
    assert inserted.new_text == "\r"
    assert inserted.range == types.Range(types.Position(0, 0), types.Position(0, 0))
