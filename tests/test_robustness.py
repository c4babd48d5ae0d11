"""Rules never raise: valid files mutated at random (attributes dropped or set to NaN, inf,
negative, huge or non-numeric values, elements duplicated or removed) run through every
rule with no internal error, and every finding is well formed."""

from __future__ import annotations

import copy
from functools import cache
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree

from xodrlint.api import default_registry
from xodrlint.engine.linter import Linter, LintOptions

from .conftest import REPO, SHARED_SCHEMAS, needs_shared
from .wellformed import assert_well_formed


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
    assert_well_formed(LINTER.lint_bytes(data, source.name))


def test_sources_exist() -> None:
    assert len(SOURCES) >= 100, "the rule cases are the seeds of the mutations"


# Numbers -------------------------------------------------------------------------------

NUMERIC_ATTRIBUTES = (
    ("road", "length"),
    ("mainTrack", "s"),
    ("sideTrack", "s"),
    ("segment", "sStart"),
    ("segment", "sEnd"),
    ("width", "a"),
    ("laneOffset", "a"),
)
RAILROAD_ATTRIBUTES = NUMERIC_ATTRIBUTES[1:5]  # what the built-in schema validates
# Text float() may take (a locale comma does not, Arabic digits and "1_000" do) that is
# no xs:double: the schema must report it, whatever a rule makes of it.
NOT_XSD_DOUBLES = ("", "0x10", "1,5", "\u0661\u0662", "1_000", "Infinity", "nan", "1.5 m")
# Lexically valid xs:double values that are odd as positions and lengths.
ODD_XSD_DOUBLES = ("NaN", "INF", "-INF", "1e999", "-1e999", "-0", "1e-999", " 5 ")


def _with_value(tag: str, attribute: str, value: str) -> bytes:
    root = copy.deepcopy(_tree(REPO / "examples" / "clean.xodr"))
    element = next(el for el in root.iter(tag) if el.get(attribute) is not None)
    element.set(attribute, value)
    return etree.tostring(root, xml_declaration=True, encoding="UTF-8")


@pytest.mark.parametrize("value", NOT_XSD_DOUBLES + ODD_XSD_DOUBLES)
def test_odd_numbers_never_raise(value: str) -> None:
    for tag, attribute in NUMERIC_ATTRIBUTES:
        report = LINTER.lint_bytes(_with_value(tag, attribute, value), "numbers.xodr")
        assert_well_formed(report)
        if value in NOT_XSD_DOUBLES and (tag, attribute) in RAILROAD_ATTRIBUTES:
            assert "XS006" in {f.code for f in report.findings}, (tag, attribute, value)


@needs_shared
@pytest.mark.parametrize("value", NOT_XSD_DOUBLES)
def test_numbers_that_are_no_xsd_double_are_reported_by_the_official_schema(value: str) -> None:
    linter = Linter(default_registry(), LintOptions(schema=SHARED_SCHEMAS))
    for tag, attribute in NUMERIC_ATTRIBUTES:
        report = linter.lint_bytes(_with_value(tag, attribute, value), "numbers.xodr")
        assert_well_formed(report)
        assert "XS006" in {f.code for f in report.findings}, (tag, attribute, value)
