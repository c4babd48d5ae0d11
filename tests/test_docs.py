"""Rule doc pages: every docstring has its sections, its examples are tested cases, and
docs/rules/ is what the generator writes (the checks every rule pack runs, from
xodrlint.testing); and what xodrlint asks of its own pages beyond them."""

from __future__ import annotations

import pytest

from xodrlint.api import default_registry
from xodrlint.findings import RuleMeta
from xodrlint.testing.suite import test_doc_pages_are_generated, test_rule_is_documented

from .conftest import REPO

__all__ = ["test_doc_pages_are_generated", "test_rule_is_documented"]

#: xodrlint's own rules (another pack installed beside it is its own business)
METAS = tuple(m for m in default_registry().metas if m.origin and m.origin.builtin)


@pytest.mark.parametrize("meta", METAS, ids=lambda m: m.code)
def test_every_page_relates_its_rule_to_others(meta: RuleMeta) -> None:
    # a pack's page needs "Related rules" where its rule defers; ours always have one
    assert meta.section("Related rules"), f"{meta.code} lacks '## Related rules'"


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
    from xodrlint.devtools.docgen import formats_page

    page = REPO / "docs" / "output-formats.md"
    assert page.read_text("utf-8") == formats_page(REPO), (
        "docs/output-formats.md is stale: run python -m xodrlint.devtools.docgen"
    )


def test_plugins_page_reference_is_generated() -> None:
    from xodrlint.devtools.apidoc import PAGE, replace_section

    page = (REPO / PAGE).read_text("utf-8")
    assert page == replace_section(page), (
        "docs/plugins.md's rule API reference is stale: run python -m xodrlint.devtools.docgen"
    )


def test_plugins_page_explains_every_argument_of_the_rule_decorator() -> None:
    import inspect

    from xodrlint.rules import rule

    guide = (REPO / "docs" / "plugins.md").read_text("utf-8").split("## The rule decorator")[1]
    decorator = guide.split("\n## ", 1)[0]
    for parameter in inspect.signature(rule).parameters:
        assert f"- `{parameter}`:" in decorator, f"docs/plugins.md does not explain `{parameter}`"


def test_the_fix_example_in_plugins_md_is_the_example_packs_code() -> None:
    # the page shows a fix a test runs: HR002's, whose case has its .fixed.xodr
    guide = (REPO / "docs" / "plugins.md").read_text("utf-8").split("## Fixes")[1]
    snippet = guide.split("```python\n", 1)[1].split("```", 1)[0]
    pack = REPO / "examples" / "rulepack"
    assert snippet in (pack / "src" / "xodrlint_houserules" / "hr002.py").read_text("utf-8")
    assert (pack / "rules" / "HR002" / "invalid_blanks.fixed.xodr").is_file()


def test_the_generated_reference_names_every_field_of_the_model() -> None:
    import dataclasses

    import xodrlint.model
    from xodrlint.devtools.apidoc import reference

    text = reference()
    for name in ("RailNetwork", "Switch", "Segment", "Lane"):
        kind = getattr(xodrlint.model, name)
        fields = (
            [f.name for f in dataclasses.fields(kind)]
            if dataclasses.is_dataclass(kind)
            else list(kind._fields)
        )
        section = text.split(f"#### `{name}`")[1].split("#### ")[0]
        for field in fields:
            assert f"| `{field}` |" in section, (name, field)


def test_the_api_reference_lists_cached_properties_as_attributes() -> None:
    import ast

    from xodrlint.devtools.apidoc import _method

    tree = ast.parse(
        "@cached_property\ndef rail_roads(self) -> tuple[Road, ...]:\n    '''Roads.'''\n"
        "def shared(self, kind: type) -> int:\n    '''One.'''\n"
    )
    cached, method = (_method(node) for node in tree.body if isinstance(node, ast.FunctionDef))
    assert (cached.name, cached.type) == ("rail_roads", "tuple[Road, ...]")
    assert method.name == "shared(kind)"


def test_rule_docstrings_have_one_reader() -> None:
    """Summary, page and sections come from findings.RuleMeta alone (issue 32, item 4):
    the rule API, SARIF, the editor's hover, explain and the doc checks ask it."""
    from xodrlint.findings import RuleMeta, Severity, doc_summary

    doc = "XX001 odd-thing: reports an odd thing.\n\n## What it does\nA\n\n## Why is this bad?\nB\n"
    meta = RuleMeta("XX001", "odd-thing", "u", Severity.ERROR, doc_summary(doc), doc)
    assert meta.summary == "reports an odd thing"
    assert meta.page == "## What it does\nA\n\n## Why is this bad?\nB"
    assert (meta.section("why is this bad?"), meta.section("What it does")) == ("B", "A")
    assert meta.section("Options") is None
