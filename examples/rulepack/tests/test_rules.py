"""The pack's rules run through xodrlint.testing, the runner xodrlint's own rules use:
each case under rules/ with its expect marks, its fixes against its .fixed.xodr, each
docstring a complete page whose examples are tested cases, a valid_ and an invalid_ case
for every rule, and docs/rules/ as the generator writes it
(python -m xodrlint.devtools.docgen --pack xodrlint_houserules).
The plugin is configured in pyproject.toml ([tool.pytest.ini_options])."""

from xodrlint.testing.suite import (
    test_case,
    test_case_fix,
    test_doc_pages_are_generated,
    test_every_rule_has_cases,
    test_rule_is_documented,
)

__all__ = [
    "test_case",
    "test_case_fix",
    "test_doc_pages_are_generated",
    "test_every_rule_has_cases",
    "test_rule_is_documented",
]
