"""Rule doc pages: every docstring has its sections, its examples are tested cases, and
docs/rules/ is what the generator writes."""

from __future__ import annotations

import re

import pytest

from xodrlint.api import default_registry
from xodrlint.cli.docgen import generate
from xodrlint.findings import RuleMeta

from .conftest import REPO

REQUIRED_SECTIONS = (
    "## What it does",
    "## Why is this bad?",
    "## Example",
    "Use instead:",
    "## Related rules",
    "## References",
)
METAS = default_registry().metas


@pytest.mark.parametrize("meta", METAS, ids=lambda m: m.code)
def test_docstring_has_every_section(meta: RuleMeta) -> None:
    for section in REQUIRED_SECTIONS:
        assert section in meta.doc, f"{meta.code} lacks '{section}'"
    assert meta.doc.startswith(f"{meta.code} {meta.name}: "), meta.doc.splitlines()[0]
    assert meta.uid in meta.doc, f"{meta.code}'s References must name its UID"


def _blocks(text: str) -> list[str]:
    return re.findall(r"```xml\n(.*?)```", text, flags=re.DOTALL)


def _contains(haystack: str, block: str) -> bool:
    wanted = [line.strip() for line in block.strip().splitlines()]
    lines = [line.strip() for line in haystack.splitlines()]
    return any(lines[i : i + len(wanted)] == wanted for i in range(len(lines)))


@pytest.mark.parametrize("meta", METAS, ids=lambda m: m.code)
def test_examples_are_tested_cases(meta: RuleMeta) -> None:
    example, _, use_instead = meta.doc.partition("Use instead:")
    folder = REPO / "rules" / meta.code
    invalid = [p.read_text() for p in folder.glob("invalid_*.xodr")]
    valid = [p.read_text() for p in folder.glob("valid_*.xodr")]
    bad_blocks = _blocks(example.split("## Example", 1)[1])
    good_blocks = _blocks(use_instead.split("\n## ", 1)[0])
    assert bad_blocks and good_blocks, f"{meta.code} needs an example and a fix"
    for block in bad_blocks:
        assert any(_contains(case, block) for case in invalid), f"{meta.code} example not in a case"
        assert f"expect: {meta.code}" in block, f"{meta.code} example must mark the bad line"
    for block in good_blocks:
        assert any(_contains(case, block) for case in valid), f"{meta.code} fix not in a case"


@pytest.mark.parametrize("meta", METAS, ids=lambda m: m.code)
def test_options_and_deferrals_are_documented(meta: RuleMeta) -> None:
    if meta.options:
        options = meta.doc.split("## Options", 1)
        assert len(options) == 2, f"{meta.code} declares options but has no Options section"
        for option in meta.options:
            assert f"`{option.name}`" in options[1].split("\n## ", 1)[0], option.name
            assert f"{option.default:g}" in options[1], f"{option.name} default not documented"
    else:
        assert "## Options" not in meta.doc, f"{meta.code} documents options it does not have"
    related = meta.doc.split("## Related rules", 1)[1].split("\n## ", 1)[0]
    for code in meta.defers_to:
        assert code in related, f"{meta.code} defers to {code}; 'Related rules' must say so"


def test_docs_rules_are_generated() -> None:
    pages = generate(REPO, METAS)
    for path, text in pages.items():
        assert path.is_file(), f"{path.name} missing: run python -m xodrlint.cli.docgen"
        assert path.read_text(encoding="utf-8") == text, (
            f"{path.name} is stale: run python -m xodrlint.cli.docgen"
        )
    extra = {p.name for p in (REPO / "docs" / "rules").glob("*.md")} - {p.name for p in pages}
    assert not extra, f"pages without a rule: {extra}"


# Column "Basis" = I in the catalogue: rules that rest on our reading of the standard.
INFERRED = {
    "XS005", "SW005", "SW006", "SW009", "PT002", "PT003", "PT005", "PT006",
    "ST004", "ST005", "ST006", "ST011", "TR001", "TR002",
}  # fmt: skip


@pytest.mark.parametrize("meta", METAS, ids=lambda m: m.code)
def test_inferred_rules_say_so(meta: RuleMeta) -> None:
    why = meta.doc.split("## Why is this bad?", 1)[1].split("\n## ", 1)[0]
    if meta.code in INFERRED:
        assert "inference" in why, (
            f"{meta.code} rests on an inference; 'Why is this bad?' must say so"
        )


def test_output_formats_page_is_generated() -> None:
    from xodrlint.cli.docgen import formats_page

    page = REPO / "docs" / "output-formats.md"
    assert page.read_text("utf-8") == formats_page(REPO), (
        "docs/output-formats.md is stale: run python -m xodrlint.cli.docgen"
    )
