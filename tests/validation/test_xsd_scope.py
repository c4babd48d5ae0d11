"""``xsd-scope = "railroad"`` (issue 31, item 5): with the official schemas, the schema
errors outside the railroad content are counted in one note per file, not listed."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from tests.conftest import REPO, SHARED_SCHEMAS, needs_shared
from xodrlint.cli import app

BROKEN = REPO / "examples" / "broken.xodr"


def run(*args: str | Path) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.fixture
def mixed(tmp_path: Path) -> Path:
    """broken.xodr (schema errors on two switches and a segment) with a junction for road
    traffic whose @type is not OpenDRIVE's, before the station (a line down)."""
    text = BROKEN.read_text("utf-8").replace(
        "  <station",
        '  <junction id="900" name="j" type="sideways"/>\n  <station',
        1,
    )
    path = tmp_path / "mixed.xodr"
    path.write_text(text, "utf-8")
    return path


def _schema_lines(result: Result) -> list[int]:
    return [f["line"] for f in json.loads(result.stdout)["findings"] if f["code"] == "XS006"]


@needs_shared
def test_railroad_scope_lists_the_railroad_errors_and_counts_the_rest(mixed: Path) -> None:
    every = run("check", "-f", "json", "--schema", SHARED_SCHEMAS, mixed)
    railroad = run(
        "check", "-f", "json", "--schema", SHARED_SCHEMAS, "--xsd-scope", "railroad", mixed
    )
    junction = next(
        number
        for number, line in enumerate(mixed.read_text("utf-8").splitlines(), 1)
        if "<junction" in line
    )
    assert junction in _schema_lines(every)
    assert _schema_lines(railroad) == [line for line in _schema_lines(every) if line != junction]
    assert _schema_lines(railroad) == [25, 30, 63]  # the switches and the segment
    hidden = _schema_lines(every).count(junction)
    note = (
        f"{mixed}: {hidden} schema errors outside the railroad content not shown "
        "(--xsd-scope all shows them)"
    )
    assert note in json.loads(railroad.stdout)["notes"]
    assert note not in json.loads(every.stdout)["notes"]
    text = run("check", "--schema", SHARED_SCHEMAS, "--xsd-scope", "railroad", mixed)
    assert f"xodrlint: note: {note}" in text.stderr


@needs_shared
def test_the_scope_is_a_setting_and_a_bad_one_is_exit_2(mixed: Path, tmp_path: Path) -> None:
    (tmp_path / "xodrlint.toml").write_text('xsd-scope = "railroad"\n', "utf-8")
    result = run("check", "-f", "json", "--schema", SHARED_SCHEMAS, mixed)
    assert _schema_lines(result) == [25, 30, 63]
    shown = json.loads(run("config", "-f", "json", mixed).stdout)["settings"]["xsd-scope"]
    assert shown == {"value": "railroad", "source": str(tmp_path / "xodrlint.toml")}
    (tmp_path / "xodrlint.toml").write_text('xsd-scope = "rail"\n', "utf-8")
    refused = run("check", mixed)
    assert refused.exit_code == 2 and "'xsd-scope' must be one of 'all', 'railroad'" in (
        refused.stderr
    )
    assert run("check", "--xsd-scope", "rail", mixed).exit_code == 2
