"""The pack installed, end to end through xodrlint's command line: listed under its name,
explained, selected and ignored, configured, and described in SARIF.

These tests need the pack installed (``pip install .`` or ``pip install -e .``): xodrlint
finds packs through their entry points, never through the search path alone.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from importlib.metadata import entry_points
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: Two stations whose names break the house style, each with a platform of 80 m.
MAP = ROOT / "rules" / "HR002" / "invalid_blanks.xodr"
HOUSE = ["HR001", "HR002", "HR003"]


@pytest.fixture(autouse=True)
def installed() -> None:
    points = entry_points(group="xodrlint.rules", name="house")
    if not any(point.value == "xodrlint_houserules" for point in points):
        pytest.fail("the pack is not installed here: pip install -e . first", pytrace=False)


def xodrlint(*args: str | Path, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    environment = {**os.environ, "NO_COLOR": "1"}
    return subprocess.run(
        [sys.executable, "-m", "xodrlint", *map(str, args)],
        capture_output=True,
        text=True,
        check=False,
        cwd=cwd,
        env=environment,
        timeout=120,
    )


def findings(*args: str | Path, cwd: Path | None = None) -> list[tuple[str, int, str]]:
    done = xodrlint("check", "-f", "json", "--exit-zero", *args, cwd=cwd)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    return [(f["code"], f["line"], f["message"]) for f in report["findings"]]


def test_rules_lists_the_pack_under_its_name() -> None:
    done = xodrlint("rules")
    assert done.returncode == 0 and done.stderr == "", done.stderr
    _, heading, rest = done.stdout.partition("Rule pack 'house' (xodrlint-houserules 0.1.0):\n")
    assert heading, done.stdout
    listed = [line.split()[0] for line in rest.split("\n\n")[0].splitlines()]
    assert listed == HOUSE


def test_explain_shows_a_rule_s_page() -> None:
    done = xodrlint("explain", "station-name-pattern")
    assert done.returncode == 0, done.stderr
    page = done.stdout
    assert page.startswith("# HR002 station-name-pattern\n")
    assert "rule pack 'house' (xodrlint-houserules 0.1.0)" in page
    for heading in ("## What it does", "## Options", "## References"):
        assert heading in page


def test_the_pack_s_rules_run_by_default_and_are_selected_and_ignored() -> None:
    everything = findings(MAP)
    house = [finding for finding in everything if finding[0] in HOUSE]
    assert [(code, line) for code, line, _ in house] == [
        ("HR002", 57),
        ("HR003", 58),
        ("HR002", 62),
        ("HR003", 63),
    ]
    assert findings("--select", "HR", MAP) == house
    assert [code for code, _, _ in findings("--select", "HR", "--ignore", "HR003", MAP)] == [
        "HR002",
        "HR002",
    ]
    assert findings("--ignore", "HR", MAP) == [f for f in everything if f[0] not in HOUSE]
    assert [code for code, _, _ in findings("--select", "platform-too-short", MAP)] == [
        "HR003",
        "HR003",
    ]


def test_options_from_the_configuration_and_the_command_line(tmp_path: Path) -> None:
    (tmp_path / "map.xodr").write_bytes(MAP.read_bytes())
    (tmp_path / "xodrlint.toml").write_text(
        "select = [\"HR\"]\nplatform-min-length = 75\nstation-name-pattern = '.+'\n"
    )
    assert findings("map.xodr", cwd=tmp_path) == []
    short = findings("--rule-option", "platform-min-length=90", "map.xodr", cwd=tmp_path)
    assert [(code, message) for code, _, message in short] == [
        ("HR003", "platform 'Platform 1' is 80 m long, shorter than 90 m (platform-min-length)"),
        ("HR003", "platform 'Platform 2' is 80 m long, shorter than 90 m (platform-min-length)"),
    ]
    names = findings("--rule-option", r"station-name-pattern=\S+ \S+", "map.xodr", cwd=tmp_path)
    assert [message for _, _, message in names] == [
        "station name 'Example  Halt' does not match '\\S+ \\S+' (station-name-pattern)",
        "station name 'Siding Halt ' does not match '\\S+ \\S+' (station-name-pattern)",
    ]
    shown = json.loads(xodrlint("config", "-f", "json", "map.xodr", cwd=tmp_path).stdout)
    config = str(tmp_path / "xodrlint.toml")
    assert shown["settings"]["platform-min-length"] == {"value": 75.0, "source": config}
    assert shown["settings"]["station-name-pattern"] == {"value": ".+", "source": config}


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ("platform-min-length=long", "'platform-min-length' takes a finite number >= 0"),
        ("station-name-pattern=(", "'station-name-pattern' takes a regular expression"),
    ],
)
def test_a_bad_option_value_is_one_line_and_exit_2(given: str, message: str) -> None:
    done = xodrlint("check", "--rule-option", given, MAP)
    assert done.returncode == 2
    assert len(done.stderr.splitlines()) == 1 and message in done.stderr


def test_sarif_describes_the_pack_s_rules() -> None:
    done = xodrlint("check", "-f", "sarif", "--select", "HR", MAP)
    assert done.returncode == 1, done.stderr  # warnings fail the run by default
    run = json.loads(done.stdout)["runs"][0]
    rules = run["tool"]["driver"]["rules"]
    described = {rule["id"]: rule for rule in rules if rule["id"].startswith("HR")}
    assert sorted(described) == HOUSE
    hr003 = described["HR003"]
    assert hr003["name"] == "platform-too-short"
    assert hr003["shortDescription"]["text"] == "a platform is shorter than the house minimum"
    assert "## Options" in hr003["help"]["markdown"]
    assert hr003["defaultConfiguration"] == {"level": "warning"}
    assert (
        hr003["properties"]["uid"]
        == "example-rail.com:xodr:1.4.0:road.railroad.platform.min_length"
    )
    assert hr003["properties"]["pack"] == "house"
    assert hr003["properties"]["packDistribution"] == "xodrlint-houserules"
    assert hr003["properties"]["packVersion"] == "0.1.0"
    assert {rules[result["ruleIndex"]]["id"] for result in run["results"]} == {"HR002", "HR003"}
