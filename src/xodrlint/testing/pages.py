"""A rule's doc page: its docstring, then each of its tested cases in full, so that the
examples in the docs are the ones the tests run (``docs/rules/<CODE>.md``)."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from xodrlint.findings import RuleMeta
from xodrlint.testing.cases import RuleCase, case_text, fixed_output


def render_page(meta: RuleMeta, cases: Iterable[RuleCase], root: Path) -> str:
    """The Markdown doc page of a rule; case paths are shown relative to ``root``."""
    lines = [
        f"# {meta.code} {meta.name}",
        "",
        f"{meta.summary[:1].upper()}{meta.summary[1:]}.",
        "",
        f"- Severity: `{meta.severity}`",
        f"- UID: `{meta.uid}`",
        *[f"- Alias: `{alias}`" for alias in meta.aliases],
        *(
            [f"- Off by default: turn it on with `--extend-select {meta.code}`"]
            if meta.opt_in
            else []
        ),
        *(
            [
                f"- Applies to files declaring OpenDRIVE {meta.since_label} or later; "
                "older ones only with `--all-versions`"
            ]
            if meta.since_label
            else []
        ),
        "",
        meta.page,
        "",
        "## Tested cases",
        "",
    ]
    cases = list(cases)
    if cases:
        folder = cases[0].path.parent.relative_to(root).as_posix()
        lines += [
            f"These files live in the repository under `{folder}/` and run in the test "
            "suite; each `expect` comment marks a line that must be reported.",
            "",
        ]
    for case in cases:
        relative = case.path.relative_to(root).as_posix()
        verdict = (
            "no finding"
            if not case.expected
            else ", ".join(f"{code} at line {line}" for line, code in case.expected)
        )
        lines += [f"### `{relative}`", "", f"Expected: {verdict}.", "", "```xml"]
        lines += [case_text(case.path).rstrip("\n"), "```", ""]
        fixed = fixed_output(case.path)
        if fixed.is_file():
            lines += [
                f"Fixed (`{fixed.relative_to(root).as_posix()}`):",
                "",
                "```diff",
                _diff(case_text(case.path), case_text(fixed)),
                "```",
                "",
            ]
    return "\n".join(lines).rstrip("\n") + "\n"


def _diff(before: str, after: str) -> str:
    """The changed lines, each with one line of context (no file header)."""
    import difflib

    lines = difflib.unified_diff(before.splitlines(), after.splitlines(), n=1, lineterm="")
    return "\n".join(line for line in lines if not line.startswith(("---", "+++")))
