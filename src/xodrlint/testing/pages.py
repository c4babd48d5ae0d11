"""A rule's doc page: its docstring, then each of its tested cases in full, so that the
examples in the docs are the ones the tests run (``docs/rules/<CODE>.md``)."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

from xodrlint.findings import RuleMeta
from xodrlint.testing.cases import RuleCase


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
        lines += [case.path.read_text(encoding="utf-8", errors="replace").rstrip("\n"), "```", ""]
    return "\n".join(lines).rstrip("\n") + "\n"
