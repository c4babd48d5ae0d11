"""Every case under rules/<CODE>/ is linted with only its rule selected; codes and lines
must match the file's expect comments exactly."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from xodrlint.api import default_registry
from xodrlint.docgen import Case, cases_of
from xodrlint.engine import Linter, LintOptions

from .conftest import REPO

RULES_DIR = REPO / "rules"
CASES = [
    case for folder in sorted(RULES_DIR.iterdir()) if folder.is_dir() for case in cases_of(folder)
]


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
    folders = {p.name for p in RULES_DIR.iterdir() if p.is_dir()}
    assert folders <= codes, f"case folders without a rule: {sorted(folders - codes)}"


def test_case_files_are_named_valid_or_invalid() -> None:
    for case in CASES:
        assert case.path.name.startswith(("valid_", "invalid_")), case.path
