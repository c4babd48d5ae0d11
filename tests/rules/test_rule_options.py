"""Rule options of every kind (number, text, regex): declared by a rule, set in a config
file or with ``--rule-option NAME=VALUE``, checked before any file is linted."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from tests.conftest import REPO
from xodrlint.api import default_registry
from xodrlint.cli import app
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.findings import RuleOption
from xodrlint.rules import Hit, RailNetwork, Settings, Severity, rule
from xodrlint.rules.options import OptionError
from xodrlint.rules.registry import Registry

CLEAN = REPO / "examples" / "clean.xodr"
PATTERN = RuleOption("acme-station-name", r"[A-Z][a-z]+", "Station names", kind="regex")
LABEL = RuleOption("acme-label", "north", "A text", kind="text")
LENGTH = RuleOption("acme-length", 100.0, "A length", minimum=10.0)


@rule(
    code="AC001",
    name="station-name-scheme",
    uid="acme:xodr:1.0.0:station_name",
    severity=Severity.WARNING,
    options=[PATTERN, LABEL, LENGTH],
)
def station_names(network: RailNetwork, settings: Settings) -> Iterator[Hit]:
    pattern = re.compile(PATTERN.text(settings))
    for station in network.stations:
        if station.name is not None and not pattern.fullmatch(station.name):
            yield Hit(station.element, f"{station.name!r} {LABEL.text(settings)}")


@pytest.fixture
def with_pack(monkeypatch: pytest.MonkeyPatch) -> Registry:
    registry = Registry((*default_registry().rules, station_names))
    for module in ("check.run", "config"):
        monkeypatch.setattr(f"xodrlint.cli.{module}.default_registry", lambda: registry)
    return registry


def _run(*args: str | Path) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


def _messages(result: Result) -> list[str]:
    return [f["message"] for f in json.loads(result.stdout)["findings"]]


def _station_map(tmp_path: Path, name: str) -> Path:
    """The clean example, its one station named ``name``."""
    path = tmp_path / "map.xodr"
    path.write_text(CLEAN.read_text().replace('name="Example Halt"', f'name="{name}"'))
    return path


@pytest.mark.parametrize(
    ("option", "value", "expected"),
    [
        (LENGTH, 12, 12.0),
        (LENGTH, 12.5, 12.5),
        (PATTERN, "[0-9]+", "[0-9]+"),
        (LABEL, "", ""),
    ],
)
def test_a_value_of_the_right_kind_is_taken(
    option: RuleOption, value: object, expected: object
) -> None:
    assert option.checked(value) == expected


@pytest.mark.parametrize(
    ("option", "value", "expected"),
    [
        (LENGTH, 5, "a finite number >= 10"),
        (LENGTH, float("nan"), "a finite number >= 10"),
        (LENGTH, True, "a finite number >= 10"),
        (LENGTH, "12", "a finite number >= 10"),
        (LABEL, 3, "a string"),
        (PATTERN, "[a-", "a regular expression (unterminated character set at position 0)"),
        (PATTERN, 3, "a regular expression"),
    ],
)
def test_a_value_of_the_wrong_kind_says_what_the_option_takes(
    option: RuleOption, value: object, expected: str
) -> None:
    with pytest.raises(TypeError) as refused:
        option.checked(value)
    assert str(refused.value) == expected


def test_a_rule_reads_each_kind_as_its_type() -> None:
    settings: Settings = {"acme-length": 20.0, "acme-label": "south"}
    assert LENGTH.number(settings) == 20.0
    assert LABEL.text(settings) == "south"
    assert PATTERN.text(settings) == PATTERN.default  # unset: the default
    with pytest.raises(TypeError, match="not a number"):
        PATTERN.number(settings)
    with pytest.raises(TypeError, match="not text"):
        LENGTH.text(settings)


@pytest.mark.parametrize(
    ("option", "message"),
    [
        (RuleOption("acme-x", "[", "bad default", kind="regex"), "not a regular expression"),
        (RuleOption("acme-x", 1.0, "wrong kind", kind="colour"), "has kind 'colour'"),
        (RuleOption("acme-x", "1", "number as text"), "not a finite number >= 0"),
        (RuleOption("Acme X", 1.0, "bad name"), "is not kebab-case"),
    ],
)
def test_a_pack_declaring_a_bad_option_fails_on_import(option: RuleOption, message: str) -> None:
    with pytest.raises(ValueError, match=re.escape(message)):
        rule(code="AC009", name="x", uid="acme:x", severity=Severity.INFO, options=[option])


def test_a_regex_option_from_a_config_file(tmp_path: Path, with_pack: Registry) -> None:
    path = _station_map(tmp_path, "Berlin Hbf")
    assert _messages(_run("check", "-f", "json", "--select", "AC", path)) == ["'Berlin Hbf' north"]
    (tmp_path / "xodrlint.toml").write_text(
        "acme-station-name = '[A-Z][a-z]+( [A-Z][a-z]*)*'\nacme-label = 'west'\n"
    )
    assert _messages(_run("check", "-f", "json", "--select", "AC", path)) == []
    (tmp_path / "xodrlint.toml").write_text("acme-station-name = '[A-Z'\n")
    refused = _run("check", "--select", "AC", path)
    assert refused.exit_code == 2
    assert refused.stderr.splitlines() == [
        f"xodrlint: {tmp_path / 'xodrlint.toml'}: 'acme-station-name' must be a regular "
        "expression (unterminated character set at position 0), got '[A-Z'"
    ]


def test_a_regex_option_on_the_command_line(tmp_path: Path, with_pack: Registry) -> None:
    path = _station_map(tmp_path, "Berlin Hbf")
    given = ["--rule-option", r"acme-station-name=\w+ \w+", "--rule-option", "acme-label=x=y"]
    assert _messages(_run("check", "-f", "json", "--select", "AC", *given, path)) == []
    given = ["--rule-option", r"acme-station-name=\w+", "--rule-option", "acme-label=x=y"]
    assert _messages(_run("check", "-f", "json", "--select", "AC", *given, path)) == [
        "'Berlin Hbf' x=y"
    ]
    refused = _run("check", "--rule-option", "acme-station-name=(", path)
    assert refused.exit_code == 2
    assert refused.stderr.splitlines() == [
        "xodrlint: --rule-option acme-station-name=(: expected NAME=VALUE, "
        "'acme-station-name' takes a regular expression (missing ), unterminated subpattern "
        "at position 0)"
    ]


def test_the_command_line_wins_over_the_config_file(tmp_path: Path, with_pack: Registry) -> None:
    path = _station_map(tmp_path, "Adlershof")
    (tmp_path / "xodrlint.toml").write_text("acme-station-name = '[0-9]+'\n")
    assert _messages(_run("check", "-f", "json", "--select", "AC", path)) == ["'Adlershof' north"]
    given = ["--rule-option", "acme-station-name=[A-Z][a-z]+"]
    assert _messages(_run("check", "-f", "json", "--select", "AC", *given, path)) == []


def test_config_shows_text_options_as_toml(tmp_path: Path, with_pack: Registry) -> None:
    (tmp_path / "xodrlint.toml").write_text("acme-station-name = '\\d+ \"x\"'\n")
    lines = _run("config", tmp_path).stdout.splitlines()
    shown = {line.split()[0]: line.split("#")[0].split(None, 1)[1].strip() for line in lines[1:]}
    assert shown["acme-station-name"] == "'\\d+ \"x\"'"
    assert shown["acme-label"] == '"north"'
    assert shown["acme-length"] == "100"


def test_the_engine_refuses_a_bad_value_given_through_the_api(with_pack: Registry) -> None:
    with pytest.raises(OptionError, match="'acme-station-name' must be a regular expression"):
        Linter(with_pack, LintOptions(rule_options={"acme-station-name": "("}))
    with pytest.raises(OptionError, match="'acme-length' must be a finite number >= 10"):
        Linter(with_pack, LintOptions(rule_options={"acme-length": "long"}))


def test_rules_json_describes_each_kind(
    with_pack: Registry, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr("xodrlint.cli.rules.default_registry", lambda: with_pack)
    entries = json.loads(_run("rules", "-f", "json").stdout)
    [entry] = [e for e in entries if e["code"] == "AC001"]
    assert entry["options"][0] == {
        "name": "acme-station-name",
        "kind": "regex",
        "default": "[A-Z][a-z]+",
        "unit": None,
        "minimum": None,
        "description": "Station names",
    }
    assert entry["options"][2]["unit"] == "m" and entry["options"][2]["minimum"] == 10.0


@pytest.mark.parametrize(
    ("pattern", "expected"),
    [
        ("(" * 499 + "a" + ")" * 499, "nested too deeply to compile"),
        ("a" * 10_000_000, "of at most 1000 characters (this one has 10,000,000)"),
    ],
    ids=["nested", "huge"],
)
def test_a_hostile_regex_option_is_one_line_and_exit_2(
    tmp_path: Path, with_pack: Registry, pattern: str, expected: str
) -> None:
    # issue 30, item 11: RecursionError (exit 3) and 18 s of compiling before
    path = _station_map(tmp_path, "Berlin Hbf")
    (tmp_path / "xodrlint.toml").write_text(f"acme-station-name = '{pattern}'\n")
    refused = _run("check", "--select", "AC", path)
    assert refused.exit_code == 2
    (line,) = refused.stderr.splitlines()
    assert expected in line and len(line) < 500
