"""The rule catalogue by example: read ``rules/<CODE>/`` cases and write ``docs/rules/``.

A case is a complete small OpenDRIVE file. A line that must be reported carries
``<!-- expect: CODE -->`` at its end (several codes separated by commas), or the comment
stands alone on the line before. ``valid_*`` files expect nothing. Each doc page is the
rule's docstring followed by its cases, so the examples in the docs are the tested ones.

Run ``python -m xodrlint.docgen`` from the repository root to regenerate ``docs/rules``.
"""

from __future__ import annotations

import re
import sys
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Final

from xodrlint.findings import RuleMeta

_EXPECT: Final = re.compile(r"<!--\s*expect:\s*(?P<codes>[A-Z0-9,\s]+?)\s*-->")


@dataclass(frozen=True, slots=True)
class Case:
    path: Path
    code: str
    expected: tuple[tuple[int, str], ...]
    """(line, code) pairs, sorted."""

    @property
    def is_valid(self) -> bool:
        return self.path.name.startswith("valid_")


def read_case(path: Path) -> Case:
    expected: list[tuple[int, str]] = []
    lines = path.read_bytes().decode("utf-8", errors="replace").splitlines()
    for number, text in enumerate(lines, start=1):
        for match in _EXPECT.finditer(text):
            alone = text[: match.start()].strip() == ""
            line = number + 1 if alone else number
            codes = [c.strip() for c in match["codes"].split(",") if c.strip()]
            expected.extend((line, code) for code in codes)
    return Case(path, path.parent.name, tuple(sorted(expected)))


def cases_of(folder: Path) -> list[Case]:
    return [read_case(p) for p in sorted(folder.glob("*.xodr"))]


def render_page(meta: RuleMeta, cases: Iterable[Case], root: Path) -> str:
    """The Markdown doc page of a rule: its docstring, then each tested case in full."""
    head = meta.doc.split("\n", 1)
    lines = [
        f"# {meta.code} {meta.name}",
        "",
        f"{meta.summary[:1].upper()}{meta.summary[1:]}.",
        "",
        f"- Severity: `{meta.severity}`",
        f"- UID: `{meta.uid}`",
        *[f"- Alias: `{alias}`" for alias in meta.aliases],
        "",
        head[1].strip() if len(head) > 1 else "",
        "",
        "## Tested cases",
        "",
        "These files live in the repository under `rules/"
        + meta.code
        + "/` and run in the test suite; each `expect` comment marks a line that must be "
        "reported.",
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


def generate(root: Path, metas: Iterable[RuleMeta]) -> dict[Path, str]:
    """Doc pages by path, for every rule that has a case folder."""
    pages = {}
    for meta in metas:
        folder = root / "rules" / meta.code
        pages[root / "docs" / "rules" / f"{meta.code}.md"] = render_page(
            meta, cases_of(folder), root
        )
    return pages


def main() -> int:
    from xodrlint.registry import load_registry

    root = Path.cwd()
    if not (root / "rules").is_dir():
        print("run from the repository root (no rules/ folder here)", file=sys.stderr)
        return 2
    for path, text in generate(root, load_registry().metas).items():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        print(f"wrote {path.relative_to(root)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
