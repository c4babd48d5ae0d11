"""JUnit test-case names: unique within a suite (GitLab keys test cases by name and keeps
one of each) and the same in every run of the same file."""

from __future__ import annotations

from pathlib import Path

import pytest
from junitparser import Failure, TestSuite

from tests.conftest import REPO
from xodrlint.findings import Severity
from xodrlint.formatters.junit import case_name, unique_names

from .test_formatters import cli, finding, one_report, read_junit, render

SEGMENT = "/OpenDRIVE/station[@id='9']/platform[@id='91']/segment[1]"


def four_schema_errors_on_one_line(folder: Path) -> Path:
    """A map whose first platform segment breaks the schema four ways on its one line."""
    source = REPO / "rules" / "XS006" / "invalid_negative_s_and_side.xodr"
    good = '<segment roadId="1" sStart="-5" sEnd="40" side="right"/>'
    bad = '<segment roadId="1" sStart="-5" sEnd="-40" side="middle" foo="1"/>'
    text = source.read_text("utf-8")
    assert good in text
    target = folder / "four.xodr"
    target.write_text(text.replace(good, bad), "utf-8")
    return target


def suite_of(text: str) -> TestSuite:
    (suite,) = list(read_junit(text))
    assert isinstance(suite, TestSuite)
    return suite


def test_findings_on_one_line_get_unique_stable_names(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    four_schema_errors_on_one_line(tmp_path)
    monkeypatch.chdir(tmp_path)
    args = ("check", "-f", "junit", "--select", "XS006", "four.xodr")
    first, second = cli(*args, code=1), cli(*args, code=1)
    assert first == second  # the same names, in the same order, every run
    suite = suite_of(first)
    cases = list(suite)
    names = [case.name for case in cases]
    assert len(set(names)) == len(names) == suite.tests == 5
    # whatever column the findings carry, the four of one element differ only by ordinal
    base = names[0]
    assert base.startswith("XS006 line 38") and base.endswith(SEGMENT)
    assert names[:4] == [base, f"{base} #2", f"{base} #3", f"{base} #4"]
    assert names[4].startswith("XS006 line 39") and names[4].endswith("segment[2]")
    failures = [item for case in cases for item in case.result]
    assert all(isinstance(item, Failure) for item in failures)
    assert len(failures) == suite.failures == 5


def test_the_name_has_the_column_where_it_is_known() -> None:
    xpath = "/OpenDRIVE/road[@id='1']/railroad/switch[@id='101']"
    assert case_name(finding(line=3, column=None, xpath=xpath)) == f"SW007 line 3 {xpath}"
    assert case_name(finding(line=3, column=7, xpath=xpath)) == f"SW007 line 3 col 7 {xpath}"
    assert case_name(finding(line=3, xpath="")) == "SW007 line 3"


def test_two_elements_on_one_line_are_told_apart_without_an_ordinal() -> None:
    # a minified map: two switches on line 3, with and without their columns
    first = "/OpenDRIVE/road[@id='1']/railroad/switch[@id='101']"
    second = "/OpenDRIVE/road[@id='1']/railroad/switch[@id='102']"
    for columns in ((None, None), (5, 60)):
        findings = [
            finding(line=3, column=column, xpath=xpath)
            for column, xpath in zip(columns, (first, second), strict=True)
        ]
        names = [case.name for case in suite_of(render("junit", one_report(*findings)))]
        assert len(set(names)) == 2
        assert not any("#" in name for name in names)


def test_two_findings_at_one_column_of_one_element_get_an_ordinal() -> None:
    same = [finding(column=12, message=f"problem {i}", severity=Severity.ERROR) for i in range(3)]
    names = [case.name for case in suite_of(render("junit", one_report(*same)))]
    base = case_name(same[0])
    assert names == [base, f"{base} #2", f"{base} #3"]


def test_unique_names_skips_a_name_already_taken() -> None:
    assert unique_names(["a", "a #2", "a", "b", "a"]) == ["a", "a #2", "a #3", "b", "a #4"]
    assert unique_names([]) == []


def test_crashes_of_several_rules_are_unique_cases_too() -> None:
    crashed = one_report(internal_errors=("rule SW001 failed", "rule SW002 failed"))
    suite = suite_of(render("junit", crashed))
    assert [case.name for case in suite] == ["internal error", "internal error #2"]
    assert (suite.tests, suite.errors) == (2, 2)
