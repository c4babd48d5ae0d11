"""Every case under rules/<CODE>/ is linted with only its rule selected; codes and lines
must match the file's expect comments exactly. The runner is the one every rule pack
uses (xodrlint.testing, configured by ``xodrlint_packs`` in pyproject.toml).

rules/families/<pack>/ holds files with several defects that run a whole rule family
(its rule.toml says which rules) to pin down the one-defect-one-finding chains."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.conftest import REPO
from xodrlint.testing import cases_in
from xodrlint.testing.cases import folder_selection
from xodrlint.testing.suite import test_case, test_case_fix, test_every_rule_has_cases

__all__ = ["test_case", "test_case_fix", "test_every_rule_has_cases"]

FAMILIES_DIR = REPO / "rules" / "families"
FAMILY_FOLDERS = sorted(f for f in FAMILIES_DIR.iterdir() if f.is_dir())


@pytest.mark.parametrize("folder", FAMILY_FOLDERS, ids=lambda f: f.name)
def test_every_family_runs_several_rules_on_several_defects(folder: Path) -> None:
    assert len(folder_selection(folder)) >= 1 and (folder / "rule.toml").is_file()
    cases = cases_in(folder)
    assert cases, f"{folder.name} has no case"
    for case in cases:
        assert len({code for _, code in case.expected}) >= 2, case.path.name
