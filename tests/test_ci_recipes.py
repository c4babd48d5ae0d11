"""Every `xodrlint check` command in docs/ci.md runs, against the example maps."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
from typer.testing import CliRunner

from xodrlint.cli import app

from .conftest import REPO

# commands as they stand in the recipes: a line of their own, or a YAML list item
COMMANDS = re.findall(
    r"^\s*(?:- (?:run: )?)?xodrlint (check [^\n#]*)",
    (REPO / "docs" / "ci.md").read_text("utf-8"),
    flags=re.MULTILINE,
)


def test_recipes_exist() -> None:
    assert len(COMMANDS) >= 6


@pytest.mark.parametrize("command", COMMANDS)
def test_recipe_runs(command: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    for folder in ("maps", "archive/tmp", "archive/2024"):
        (tmp_path / folder).mkdir(parents=True, exist_ok=True)
    for folder in ("maps", "archive/2024", "archive/tmp"):
        (tmp_path / folder / "broken.xodr").write_bytes(
            (REPO / "examples/broken.xodr").read_bytes()
        )
    result = CliRunner().invoke(app, shlex.split(command.strip()))
    assert result.exit_code in (0, 1), result.output + result.stderr
    assert "Traceback" not in result.output
