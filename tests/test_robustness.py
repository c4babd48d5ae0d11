"""Rules never raise: valid files mutated at random (attributes dropped or set to NaN, inf,
negative, huge or non-numeric values, elements duplicated or removed) run through every
rule with no internal error, and every finding is well formed."""

from __future__ import annotations

import copy
from functools import cache
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree

from xodrlint.api import default_registry
from xodrlint.engine import Linter, LintOptions

from .conftest import REPO


def _parses_as_opendrive(path: Path) -> bool:
    try:
        return etree.fromstring(path.read_bytes()).tag == "OpenDRIVE"
    except etree.XMLSyntaxError:
        return False


SOURCES = [
    path
    for path in sorted([*REPO.glob("rules/**/*.xodr"), *REPO.glob("examples/*.xodr")])
    if _parses_as_opendrive(path)
]
HOSTILE_VALUES = (
    "NaN",
    "nan",
    "INF",
    "-INF",
    "inf",
    "-1",
    "-0",
    "0",
    "1e308",
    "1e999",
    "-1e999",
    "",
    " ",
    "abc",
    "1,5",
    "0x10",
    " 5 ",
    "-1e-7",
    "1" * 400,
    "+",
    "1",
    "2",
    "101",
    "-1",
    "rail",
    "tram",
    "driving",
    "bus",
    "dynamic",
    "turn",
    "straight",
    "left",
    "right",
    "+",
    "-",
)
LINTER = Linter(default_registry(), LintOptions())


@cache
def _tree(path: Path) -> etree._Element:
    return etree.fromstring(path.read_bytes())


mutation = st.tuples(
    st.sampled_from(["drop", "set", "duplicate", "remove", "clear"]),
    st.integers(min_value=0, max_value=10_000),
    st.integers(min_value=0, max_value=10_000),
    st.sampled_from(HOSTILE_VALUES),
)


def _mutate(root: etree._Element, change: tuple[str, int, int, str]) -> None:
    kind, which, attribute, value = change
    elements = [el for el in root.iter() if isinstance(el.tag, str)]
    element = elements[which % len(elements)]
    names = list(element.attrib)
    parent = element.getparent()
    if kind == "drop" and names:
        del element.attrib[names[attribute % len(names)]]
    elif kind == "set" and names:
        element.set(names[attribute % len(names)], value)
    elif kind == "duplicate" and parent is not None:
        element.addnext(copy.deepcopy(element))
    elif kind == "remove" and parent is not None:
        parent.remove(element)
    elif kind == "clear" and parent is not None:
        for child in list(element):
            element.remove(child)


@settings(
    max_examples=300,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(source=st.sampled_from(SOURCES), changes=st.lists(mutation, min_size=1, max_size=6))
def test_mutated_files_never_break_a_rule(
    source: Path, changes: list[tuple[str, int, int, str]]
) -> None:
    root = copy.deepcopy(_tree(source))
    for change in changes:
        _mutate(root, change)
    data = etree.tostring(root, xml_declaration=True, encoding="UTF-8")
    report = LINTER.lint_bytes(data, source.name)
    assert report.internal_errors == ()
    codes = {meta.code for meta in default_registry().metas}
    for finding in report.findings:
        assert finding.code in codes
        assert finding.line >= 1
        assert finding.xpath.startswith("/")
        assert finding.message and "\n" not in finding.message


def test_sources_exist() -> None:
    assert len(SOURCES) >= 100, "the rule cases are the seeds of the mutations"
