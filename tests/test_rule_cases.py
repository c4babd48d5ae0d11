"""Every case under rules/<CODE>/ is linted with only its rule selected; codes and lines
must match the file's expect comments exactly.

rules/families/<pack>/ holds files with several defects that run a whole rule family
(its rule.toml says which rules) to pin down the one-defect-one-finding chains."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from xodrlint.api import default_registry
from xodrlint.cli.docgen import Case, cases_of
from xodrlint.engine import Linter, LintOptions

from .conftest import REPO

RULES_DIR = REPO / "rules"
FAMILIES_DIR = RULES_DIR / "families"
RULE_FOLDERS = [f for f in sorted(RULES_DIR.iterdir()) if f.is_dir() and f != FAMILIES_DIR]
FAMILY_FOLDERS = sorted(f for f in FAMILIES_DIR.iterdir() if f.is_dir())
CASES = [case for folder in RULE_FOLDERS + FAMILY_FOLDERS for case in cases_of(folder)]


def _select(folder: Path) -> tuple[str, ...]:
    settings = folder / "rule.toml"
    if settings.is_file():
        return tuple(tomllib.loads(settings.read_text())["select"])
    return (folder.name,)


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c.code}/{c.path.name}")
def test_case(case: Case) -> None:
    linter = Linter(default_registry(), LintOptions(select=_select(case.path.parent)))
    report = linter.lint_path(case.path)
    found = sorted((f.line, f.code) for f in report.findings)
    assert found == list(case.expected), [f.message for f in report.findings]
    if not case.is_valid:
        assert case.expected, f"{case.path.name} expects no finding; name it valid_*"


def test_every_rule_has_valid_and_invalid_cases() -> None:
    for meta in default_registry().metas:
        names = [p.name for p in (RULES_DIR / meta.code).glob("*.xodr")]
        assert any(n.startswith("valid_") for n in names), f"{meta.code} has no valid_ case"
        assert any(n.startswith("invalid_") for n in names), f"{meta.code} has no invalid_ case"


def test_every_case_folder_has_a_rule() -> None:
    codes = {meta.code for meta in default_registry().metas}
    folders = {p.name for p in RULE_FOLDERS}
    assert folders <= codes, f"case folders without a rule: {sorted(folders - codes)}"


@pytest.mark.parametrize("folder", FAMILY_FOLDERS, ids=lambda f: f.name)
def test_every_family_runs_several_rules_on_several_defects(folder: Path) -> None:
    assert len(_select(folder)) >= 1 and (folder / "rule.toml").is_file()
    cases = cases_of(folder)
    assert cases, f"{folder.name} has no case"
    for case in cases:
        assert len({code for _, code in case.expected}) >= 2, case.path.name


def test_case_files_are_named_valid_or_invalid() -> None:
    for case in CASES:
        assert case.path.name.startswith(("valid_", "invalid_")), case.path
