"""What a careful user trips on (issue 31, item 7): findings on one line by column, an
empty statistics table, --show-source where it shows nothing, and TR002's and SW011's
messages in a railway engineer's words."""

from __future__ import annotations

import re
from pathlib import Path

from typer.testing import CliRunner, Result

from xodrlint.cli import app

from .conftest import REPO

BROKEN = REPO / "examples" / "broken.xodr"
CLEAN = REPO / "examples" / "clean.xodr"


def run(*args: str | Path) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


def test_findings_on_one_line_are_listed_by_column(tmp_path: Path) -> None:
    # every element on one line: RL003, ST004, SW006 and XS006 there, codes and columns
    # in different orders
    one_line = re.sub(r">\s+<", "><", BROKEN.read_text("utf-8"))
    (tmp_path / "one-line.xodr").write_text(one_line, "utf-8")
    lines = run("check", "-f", "concise", tmp_path / "one-line.xodr").stdout.splitlines()
    places = [tuple(int(n) for n in line.split(":")[1:3]) for line in lines if ".xodr:" in line]
    assert places == sorted(places) and len(places) >= 6


def test_statistics_of_a_clean_run_is_an_empty_table() -> None:
    result = run("check", "--statistics", CLEAN)
    assert result.exit_code == 0
    assert result.stdout == "     0  findings\n"


def test_show_source_warns_where_it_shows_nothing() -> None:
    for args, where in (
        (("-q",), "-q"),
        (("-f", "concise"), "-f concise"),
        (("-f", "json"), "-f json"),
    ):
        result = run("check", "--show-source", *args, CLEAN)
        assert f"xodrlint: warning: --show-source shows nothing with {where}" in result.stderr
    shown = run("check", "--show-source", CLEAN)
    assert "--show-source" not in shown.stderr


def test_tr002_says_how_far_a_train_turns() -> None:
    case = REPO / "rules" / "TR002" / "invalid_reversed_link.xodr"
    cases = [case] if case.exists() else sorted((REPO / "rules" / "TR002").glob("invalid_*.xodr"))
    message = run("check", "--select", "TR002", "-f", "concise", cases[0]).stdout
    assert re.search(r"a train from .* onto .* turns by [0-9.]+ degrees at the joint", message)
    assert "leaves at" not in message and "enters at" not in message


def test_sw011_labels_the_two_points() -> None:
    case = REPO / "rules" / "SW011" / "invalid_side_track_apart.xodr"
    message = run("check", "--select", "SW011", "-f", "concise", case).stdout
    assert re.search(r"main track at \([-0-9., ]+\), side track at \([-0-9., ]+\)", message)


def test_os_errors_are_worded_one_way(tmp_path: Path) -> None:
    """The OS's reason, starting lowercase, wherever a file cannot be read (issue 32,
    item 4: seven places said it three ways)."""
    folder = tmp_path / "config.toml"
    folder.mkdir()
    result = run("check", "--config", folder, CLEAN)
    assert result.exit_code == 2
    assert f"{folder}: cannot read: is a directory" in result.stderr
    missing = tmp_path / "baseline.json"
    result = run("check", "--baseline", missing, CLEAN)
    assert result.exit_code == 2
    assert f"{missing}: cannot read: no such file or directory" in result.stderr
