"""Testing rule packs, xodrlint's own and third parties' alike, with one runner.

- :class:`RulePack`: a pack under test (its rules, loaded as an installed pack is; its
  ``rules/<CODE>/`` cases; its ``docs/rules/`` pages) and what is wrong with each.
- :class:`RuleCase`, :func:`read_case`, :func:`find_cases`: the cases, with their
  ``<!-- expect: CODE -->`` marks.
- :func:`docstring_problems`: whether a rule's docstring makes a complete doc page.
- :mod:`xodrlint.testing.plugin`: the pytest plugin (``-p xodrlint.testing.plugin``)
  that makes test items of them; :mod:`xodrlint.testing.suite`: the tests.

Nothing here imports pytest (only the plugin and the suite do), so a pack may check
itself with any runner.
"""

from xodrlint.testing.cases import RuleCase, cases_in, find_cases, read_case
from xodrlint.testing.docstrings import REQUIRED_SECTIONS, docstring_problems
from xodrlint.testing.pack import PackError, RulePack
from xodrlint.testing.pages import render_page

__all__ = [
    "REQUIRED_SECTIONS",
    "PackError",
    "RuleCase",
    "RulePack",
    "cases_in",
    "docstring_problems",
    "find_cases",
    "read_case",
    "render_page",
]
