"""A rule's docstring is its doc page (``xodrlint explain``, SARIF help, ``docs/rules/``):
the checks that it is complete and that its examples are tested cases."""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Final

from xodrlint.findings import RuleMeta

#: Every rule's page has these; "## Options" and "## Related rules" where they apply.
REQUIRED_SECTIONS: Final = (
    "## What it does",
    "## Why is this bad?",
    "## Example",
    "Use instead:",
    "## References",
)
_XML_BLOCK: Final = re.compile(r"```xml\n(.*?)```", flags=re.DOTALL)


def docstring_problems(meta: RuleMeta, invalid: Sequence[str], valid: Sequence[str]) -> list[str]:
    """What ``meta``'s page lacks; ``invalid`` and ``valid`` are the texts of its cases,
    which its example and its fix must be taken from."""
    problems = [f"lacks '{name}'" for name in REQUIRED_SECTIONS if name not in meta.doc]
    if not meta.doc.startswith(f"{meta.code} {meta.name}: "):
        first = meta.doc.splitlines()[0] if meta.doc else ""
        problems.append(
            f"its first line must read '{meta.code} {meta.name}: summary', not {first!r}"
        )
    if meta.uid not in (meta.section("References") or ""):
        problems.append(f"'References' must name its UID {meta.uid}")
    if "## Example" in meta.doc and "Use instead:" in meta.doc:
        problems += _example_problems(meta, invalid, valid)
    problems += _option_problems(meta)
    related = meta.section("Related rules")
    for code in meta.defers_to:
        if related is None or code not in related:
            problems.append(f"defers to {code}; 'Related rules' must say so")
    return [f"{meta.code}: {problem}" for problem in problems]


def _example_problems(meta: RuleMeta, invalid: Sequence[str], valid: Sequence[str]) -> list[str]:
    example, _, use_instead = meta.doc.partition("Use instead:")
    bad_blocks = _XML_BLOCK.findall(example.split("## Example", 1)[-1])
    good_blocks = _XML_BLOCK.findall(use_instead.split("\n## ", 1)[0])
    problems = []
    if not bad_blocks or not good_blocks:
        problems.append(
            "'Example' needs an ```xml block of the defect and 'Use instead:' one of the fix"
        )
    for block in bad_blocks:
        if not any(_contains(case, block) for case in invalid):
            problems.append("its example is in no invalid_ case")
        if f"expect: {meta.code}" not in block:
            problems.append(f"its example must mark the bad line (<!-- expect: {meta.code} -->)")
    for block in good_blocks:
        if not any(_contains(case, block) for case in valid):
            problems.append("its fix ('Use instead:') is in no valid_ case")
    return problems


def _option_problems(meta: RuleMeta) -> list[str]:
    options = meta.options
    text = meta.section("Options")
    if not options:
        return ["documents options it does not have"] if text is not None else []
    if text is None:
        return ["declares options but has no 'Options' section"]
    problems = []
    for option in options:
        if f"`{option.name}`" not in text:
            problems.append(f"'Options' must name `{option.name}`")
        default = f"{option.default:g}" if isinstance(option.default, float) else option.default
        if str(default) not in text:
            problems.append(f"'Options' must give {option.name}'s default, {default}")
    return problems


def _contains(haystack: str, block: str) -> bool:
    """Whether ``block``'s lines appear in ``haystack`` in a row (indentation aside)."""
    wanted = [line.strip() for line in block.strip().splitlines()]
    lines = [line.strip() for line in haystack.splitlines()]
    return any(lines[i : i + len(wanted)] == wanted for i in range(len(lines)))
