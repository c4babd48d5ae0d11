"""The tests every rule pack runs, xodrlint's own included: import them into a test
module of the pack, and the plugin (:mod:`xodrlint.testing.plugin`) runs each once per
case or rule::

    from xodrlint.testing.suite import (
        test_case,
        test_doc_pages_are_generated,
        test_every_rule_has_cases,
        test_rule_is_documented,
    )
"""

from __future__ import annotations

import pytest

from xodrlint.findings import RuleMeta
from xodrlint.testing.cases import RuleCase
from xodrlint.testing.pack import RulePack

__all__ = [
    "test_case",
    "test_case_fix",
    "test_doc_pages_are_generated",
    "test_every_rule_has_cases",
    "test_rule_is_documented",
]


def _report(problems: list[str]) -> None:
    if problems:
        pytest.fail("\n".join(problems), pytrace=False)


def test_case(xodrlint_pack: RulePack, xodrlint_case: RuleCase) -> None:
    """The case's findings are its expect marks, code and line, with its rule selected."""
    _report(xodrlint_pack.case_problems(xodrlint_case))


def test_case_fix(xodrlint_pack: RulePack, xodrlint_case: RuleCase) -> None:
    """A case's fixes give its expected output (``invalid_x.fixed.xodr``), byte for byte."""
    _report(xodrlint_pack.fix_problems(xodrlint_case))


def test_rule_is_documented(xodrlint_pack: RulePack, xodrlint_rule: RuleMeta) -> None:
    """The rule's docstring has every section, and its examples are tested cases."""
    _report(xodrlint_pack.docstring_problems(xodrlint_rule))


def test_every_rule_has_cases(xodrlint_pack: RulePack) -> None:
    """Every rule has a valid_ and an invalid_ case, every case folder a rule."""
    _report(xodrlint_pack.coverage_problems())


def test_doc_pages_are_generated(xodrlint_pack: RulePack) -> None:
    """docs/rules/ is what the pack's docstrings and cases make."""
    _report(xodrlint_pack.page_problems())
