"""Fixes made pass by pass (engine/fixing.py): each checked by linting the result, a fix
that breaks the document or leaves its finding rolled back as its rule's internal error,
the others kept; and the writes of ``--fix`` (atomic, refused where they must be)."""

from __future__ import annotations

import os
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from lxml import etree

from tests.conftest import REPO
from xodrlint.api import default_registry
from xodrlint.engine.fixing import APPLY, DIFF, FixPolicy
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.inputs.files import WriteRefused, replace_file
from xodrlint.rules import (
    Applicability,
    Fix,
    Hit,
    RailNetwork,
    Severity,
    insert_element,
    rule,
    set_attribute,
)
from xodrlint.rules.registry import Registry

MISMATCH = REPO / "rules" / "PT003" / "invalid_name_mismatch.xodr"
MISMATCH_FIXED = REPO / "rules" / "PT003" / "invalid_name_mismatch.fixed.xodr"


def _linter(registry: Registry, select: tuple[str, ...], **policy: object) -> Linter:
    fixes = FixPolicy(**policy)  # type: ignore[arg-type]
    return Linter(registry, LintOptions(select=select, fixes=fixes, place_fixes=True))


@rule(code="ZZ101", name="breaks-the-document", uid="test:breaks", severity=Severity.ERROR)
def breaks_the_document(network: RailNetwork) -> Iterator[Hit]:
    """A hostile pack's fix: a second root element before the first."""
    for switch in network.switches:
        root = switch.element.getroottree().getroot()
        edit = insert_element(root, "OpenDRIVE", {}, where="before")
        yield Hit(switch.element, "breaks", fix=Fix("add a second root", (edit,)))


@rule(code="ZZ102", name="mends-nothing", uid="test:nothing", severity=Severity.ERROR)
def mends_nothing(network: RailNetwork) -> Iterator[Hit]:
    """A fix that leaves its defect where it was."""
    for switch in network.switches:
        edit = set_attribute(switch.element, "name", "still wrong")
        yield Hit(switch.element, "always", fix=Fix("rename", (edit,), Applicability.UNSAFE))


def _with(*extra: object) -> Registry:
    return Registry((*default_registry().rules, *extra))  # type: ignore[arg-type]


def test_a_fix_is_made_and_the_report_is_the_fixed_files() -> None:
    linter = _linter(default_registry(), ("PT003",), mode=DIFF)
    fixed, report = linter.fixed_source(MISMATCH.read_bytes(), "a.xodr")
    assert fixed == MISMATCH_FIXED.read_bytes()
    assert report.findings == () and report.fixed == 1 and report.internal_errors == ()


def test_a_fix_that_breaks_the_document_is_rolled_back_and_the_others_stay() -> None:
    linter = _linter(_with(breaks_the_document), ("PT003", "ZZ101"), mode=DIFF)
    fixed, report = linter.fixed_source(MISMATCH.read_bytes(), "a.xodr")
    assert fixed == MISMATCH_FIXED.read_bytes()  # PT003's fix stands
    assert report.fixed == 1
    errors = [e for e in report.internal_errors if "ZZ101" in e]
    assert errors and "not well-formed" in errors[0], report.internal_errors
    assert [f.code for f in report.findings].count("ZZ101") == 2  # still reported


def test_a_fix_that_leaves_its_finding_is_rolled_back() -> None:
    linter = _linter(_with(mends_nothing), ("ZZ102",), mode=DIFF, unsafe=True)
    data = MISMATCH.read_bytes()
    fixed, report = linter.fixed_source(data, "a.xodr")
    assert fixed == data and report.fixed == 0
    assert any("still has its finding" in e for e in report.internal_errors)


def test_unsafe_fixes_wait_for_unsafe_fixes() -> None:
    data = MISMATCH.read_bytes()
    safe_only = _linter(_with(mends_nothing), ("ZZ102",), mode=DIFF)
    fixed, report = safe_only.fixed_source(data, "a.xodr")
    assert fixed == data and report.internal_errors == ()


def test_unfixable_names_rules_whose_fixes_never_count() -> None:
    registry = default_registry()
    data = MISMATCH.read_bytes()
    for policy in ({"unfixable": ("PT003",)}, {"fixable": ("SW",)}, {"unfixable": ("PT",)}):
        linter = _linter(registry, ("PT003",), mode=DIFF, **policy)
        fixed, report = linter.fixed_source(data, "a.xodr")
        assert fixed == data, policy
        assert report.findings[0].fix is None  # no fix is offered either
    # the closer name wins: PT's fixes off, PT003's on
    linter = _linter(registry, ("PT003",), mode=DIFF, fixable=("PT003",), unfixable=("PT",))
    assert linter.fixed_source(data, "a.xodr")[0] == MISMATCH_FIXED.read_bytes()


def test_fix_edits_are_placed_as_findings_are_numbered() -> None:
    linter = Linter(default_registry(), LintOptions(select=("PT003",), place_fixes=True))
    (finding,) = linter.lint_path(MISMATCH).findings
    assert finding.fix is not None and finding.fix.applicability is Applicability.SAFE
    (edit,) = finding.fix.edits
    line = MISMATCH.read_text().splitlines()[edit.start_line - 1]
    assert edit.start_line == edit.end_line == finding.line
    assert line[edit.start_column - 1 : edit.end_column - 1] == "W23"
    assert edit.content == "W32"
    # without placing, a finding says only that a fix exists
    plain = Linter(default_registry(), LintOptions(select=("PT003",)))
    (unplaced,) = plain.lint_path(MISMATCH).findings
    assert unplaced.fix is not None and unplaced.fix.edits == ()


def test_fix_writes_the_file_back_keeping_its_mode(tmp_path: Path) -> None:
    target = tmp_path / "a.xodr"
    target.write_bytes(MISMATCH.read_bytes())
    target.chmod(0o640)
    linter = _linter(default_registry(), ("PT003",), mode=APPLY)
    report = linter.lint_path(target)
    assert report.fixed == 1 and report.error is None
    assert target.read_bytes() == MISMATCH_FIXED.read_bytes()
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.xodr"]  # no temporary left
    again = linter.lint_path(target)
    assert again.fixed == 0 and target.read_bytes() == MISMATCH_FIXED.read_bytes()


def test_a_read_only_file_is_not_written(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "a.xodr"
    target.write_bytes(MISMATCH.read_bytes())
    target.chmod(0o444)
    linter = _linter(default_registry(), ("PT003",), mode=APPLY)
    linted: list[bytes] = []
    real = linter._lint_once

    def counted(data: bytes, *args: Any) -> Any:
        linted.append(data)
        return real(data, *args)

    monkeypatch.setattr(linter, "_lint_once", counted)
    report = linter.lint_path(target, "a.xodr")
    assert report.error == "a.xodr: not fixed: is read-only"
    assert target.read_bytes() == MISMATCH.read_bytes()
    assert [f.code for f in report.findings] == ["PT003"]  # the file's, as it stays
    # the file as read, then as fixed: its report is the first lint's, not a third one
    assert linted == [MISMATCH.read_bytes(), MISMATCH_FIXED.read_bytes()]


def test_a_file_changed_since_it_was_read_is_not_written(tmp_path: Path) -> None:
    target = tmp_path / "a.xodr"
    target.write_bytes(b"<OpenDRIVE/>  ")
    with pytest.raises(WriteRefused, match="changed on disk since it was read"):
        replace_file(target, b"<OpenDRIVE/>", b"<OpenDRIVE />")
    assert target.read_bytes() == b"<OpenDRIVE/>  "


def test_a_link_out_of_the_folder_walked_is_not_written(tmp_path: Path) -> None:
    outside = tmp_path / "outside.xodr"
    outside.write_bytes(b"<OpenDRIVE/>")
    walked = tmp_path / "walked"
    walked.mkdir()
    link = walked / "a.xodr"
    link.symlink_to(outside)
    with pytest.raises(WriteRefused, match="link leading out of the folder walked"):
        replace_file(link, b"<OpenDRIVE/>", b"<OpenDRIVE />", root=walked)
    inside = walked / "b.xodr"
    inside.write_bytes(b"<OpenDRIVE/>")
    other = walked / "c.xodr"
    other.symlink_to(inside)
    replace_file(other, b"<OpenDRIVE/>", b"<OpenDRIVE />", root=walked)
    assert other.is_symlink() and inside.read_bytes() == b"<OpenDRIVE />"


def test_a_hostile_fix_is_the_rules_internal_error(tmp_path: Path) -> None:
    @rule(code="ZZ103", name="bad-fix", uid="test:badfix", severity=Severity.ERROR)
    def bad_fix(network: RailNetwork) -> Iterator[Hit]:
        for switch in network.switches:
            yield Hit(switch.element, "bad", fix=Fix("x", (etree.Element("x"),)))  # type: ignore[arg-type]

    report = Linter(_with(bad_fix), LintOptions(select=("ZZ103",))).lint_path(MISMATCH)
    assert report.findings == ()
    assert report.internal_errors and "with the edit" in report.internal_errors[0]


def test_unsafe_fixes_that_depend_on_each_other_are_made_one_rule_a_pass() -> None:
    # a side track at s=45 of a road written 60 m long whose plan view is 50 m: SW006
    # would move it to s=60 while TR009 makes the road 50 m; made in one pass they would
    # leave it off the road. One rule a pass: the length first, then the side track.
    data = MISMATCH.read_bytes()
    data = data.replace(b'<road name="branch2" length="50"', b'<road name="branch2" length="60"')
    data = data.replace(
        b'<sideTrack id="2" s="50" dir="-"/>', b'<sideTrack id="2" s="45" dir="-"/>'
    )
    selected = ("PT003", "SW", "TR009")
    linter = _linter(default_registry(), selected, mode=DIFF, unsafe=True)
    fixed, report = linter.fixed_source(data, "a.xodr")
    assert report.internal_errors == () and report.findings == ()
    assert report.fixed == 3
    assert b'<road name="branch2" length="50"' in fixed
    assert b'<sideTrack id="2" s="50" dir="-"/>' in fixed


@rule(code="ZZ104", name="no-w12", uid="test:w12", severity=Severity.ERROR)
def no_w12(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        if switch.name == "W12":
            yield Hit(
                switch.element, "W12", fix=Fix("X", (set_attribute(switch.element, "name", "X"),))
            )


@rule(code="ZZ105", name="no-x", uid="test:x", severity=Severity.ERROR)
def no_x(network: RailNetwork) -> Iterator[Hit]:
    for switch in network.switches:
        if switch.name == "X":
            yield Hit(
                switch.element, "X", fix=Fix("W12", (set_attribute(switch.element, "name", "W12"),))
            )


def test_fixes_that_undo_each_other_stop_as_an_internal_error() -> None:
    linter = _linter(_with(no_w12, no_x), ("ZZ104", "ZZ105"), mode=DIFF)
    _, report = linter.fixed_source(MISMATCH.read_bytes(), "a.xodr")
    assert report.fixed == 1
    assert any("undo each other" in error for error in report.internal_errors)


def test_a_folder_swapped_for_a_link_out_of_the_walk_is_not_written_through(
    tmp_path: Path,
) -> None:
    walked = tmp_path / "walked"
    (walked / "sub").mkdir(parents=True)
    listed = walked / "sub" / "f.xodr"
    listed.write_bytes(b"<OpenDRIVE/>")
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "f.xodr").write_bytes(b"<OpenDRIVE/>")
    # after the listing, the folder becomes a link to one out of the walk
    (walked / "sub" / "f.xodr").unlink()
    (walked / "sub").rmdir()
    (walked / "sub").symlink_to(outside)
    with pytest.raises(WriteRefused, match="link leading out of the folder walked"):
        replace_file(listed, b"<OpenDRIVE/>", b"<OpenDRIVE />", root=walked)
    assert (outside / "f.xodr").read_bytes() == b"<OpenDRIVE/>"


def test_a_diff_counts_lines_as_xml_does() -> None:
    from xodrlint.engine.fixing import diff_of

    before = "<a>\n<!-- \u2028 \x85 -->\n<b c='1'/>\n</a>\n".encode()
    after = before.replace(b"c='1'", b"c='2'")
    diff = diff_of(before, after, "utf-8", "a.xodr")
    assert "@@ -1,4 +1,4 @@" in diff and "-<b c='1'/>\n+<b c='2'/>\n" in diff


def test_an_enumerated_value_is_mended_for_xml_blanks_and_plain_case_alone() -> None:
    from xodrlint.validation.messages import Explained, enumeration_fix

    def fix_of(value: str, allowed: tuple[str, ...] = ("dynamic",)) -> object:
        switch = etree.Element("switch", position=value)
        why = Explained("m", "enumeration", "switch", attribute="position", allowed=allowed)
        return enumeration_fix(switch, why)

    assert fix_of(" Dynamic\t") is not None
    assert fix_of("dynamic\u00a0") is None  # a no-break space is no blank of XML's
    assert fix_of("DYNAMIC") is not None
    assert fix_of("Kink", ("kink",)) is not None
    assert fix_of("\u212aink", ("kink",)) is None  # the Kelvin sign lowers to a plain k


def test_an_idle_entry_leaves_the_brackets_as_they_were_written() -> None:
    data = MISMATCH.read_bytes().replace(
        b'      <switch name="W12"',
        b'      <!-- xodrlint: ignore[ PT003, XS006 ] why -->\n      <switch name="W12"',
    )
    options = LintOptions(
        select=("PT003", "XS006", "XL001"), fixes=FixPolicy(mode=DIFF), place_fixes=True
    )
    fixed, report = Linter(default_registry(), options).fixed_source(data, "a.xodr")
    assert b"<!-- xodrlint: ignore[ PT003 ] why -->" in fixed and report.fixed == 1


def test_a_folder_swapped_while_the_write_opens_its_folders_is_not_written_through(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:

    root = tmp_path / "root"
    (root / "sub" / "deep").mkdir(parents=True)
    (root / "sub" / "deep" / "a.xodr").write_bytes(b"old")
    outside = tmp_path / "outside"
    (outside / "deep").mkdir(parents=True)
    (outside / "deep" / "a.xodr").write_bytes(b"old")
    real_open = os.open

    def racing_open(path: object, flags: int, *args: object, **named: object) -> int:
        # the folder becomes a link out of the walk just as the write opens it
        if path == "sub" and not (root / "sub").is_symlink():
            (root / "sub").rename(root / "moved")
            (root / "sub").symlink_to(outside)
        return real_open(path, flags, *args, **named)  # type: ignore[arg-type]

    monkeypatch.setattr(os, "open", racing_open)
    with pytest.raises(WriteRefused, match="link leading out of the folder walked"):
        replace_file(root / "sub" / "deep" / "a.xodr", b"old", b"new", root=root)
    assert (outside / "deep" / "a.xodr").read_bytes() == b"old"


def test_a_file_with_other_hard_links_is_not_parted_from_them(tmp_path: Path) -> None:
    target = tmp_path / "a.xodr"
    target.write_bytes(b"old")
    (tmp_path / "b.xodr").hardlink_to(target)
    with pytest.raises(WriteRefused, match="has 2 hard links"):
        replace_file(target, b"old", b"new")
    assert (tmp_path / "b.xodr").read_bytes() == b"old"


def test_an_empty_entry_leaves_no_stray_comma() -> None:
    data = MISMATCH.read_bytes().replace(
        b'      <switch name="W12"',
        b'      <!-- xodrlint: ignore[XS006,,PT003] -->\n      <switch name="W12"',
    )
    options = LintOptions(
        select=("PT003", "XS006", "XL001"), fixes=FixPolicy(mode=DIFF), place_fixes=True
    )
    fixed, _ = Linter(default_registry(), options).fixed_source(data, "a.xodr")
    assert b"<!-- xodrlint: ignore[PT003] -->" in fixed
