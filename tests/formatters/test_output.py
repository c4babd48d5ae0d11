"""Reports are written whole, shared like any other file, and never over an input."""

from __future__ import annotations

import os
import stat
from pathlib import Path
from typing import TextIO

import pytest
from typer.testing import CliRunner

from tests.conftest import REPO
from xodrlint.cli import app
from xodrlint.formatters.output import write_output

BROKEN = REPO / "examples" / "broken.xodr"


def _victim(tmp_path: Path) -> Path:
    victim = tmp_path / "map.xodr"
    victim.write_bytes(BROKEN.read_bytes())
    return victim


@pytest.mark.parametrize("link", ["symlink", "hardlink"])
def test_output_is_refused_over_an_input_under_another_name(tmp_path: Path, link: str) -> None:
    victim = _victim(tmp_path)
    other = tmp_path / "report.json"
    if link == "symlink":
        other.symlink_to(victim)
    else:
        os.link(victim, other)
    result = CliRunner().invoke(app, ["check", str(victim), "-f", "json", "-o", str(other)])
    assert result.exit_code == 2
    assert result.stderr == (
        f"xodrlint: --output {other}: is one of the inputs; refusing to overwrite it\n"
    )
    assert victim.read_bytes() == BROKEN.read_bytes()


def test_a_report_that_fails_midway_leaves_the_old_file_and_no_temporary(tmp_path: Path) -> None:
    target = tmp_path / "report.json"
    target.write_text("old report\n", "utf-8")

    def render(stream: TextIO) -> None:
        stream.write("half a rep")
        raise OSError(28, "No space left on device")

    with pytest.raises(OSError, match="No space left"):
        write_output(str(target), render)
    assert target.read_text("utf-8") == "old report\n"
    assert [p.name for p in tmp_path.iterdir()] == ["report.json"]


def test_a_written_report_is_shared_like_any_file(tmp_path: Path) -> None:
    def render(stream: TextIO) -> None:
        stream.write("new\n")

    fresh = tmp_path / "fresh.txt"
    umask = os.umask(0o022)
    try:
        write_output(str(fresh), render)
    finally:
        os.umask(umask)
    assert stat.S_IMODE(fresh.stat().st_mode) == 0o644  # not mkstemp's private 0600
    kept = tmp_path / "kept.txt"
    kept.write_text("old\n", "utf-8")
    kept.chmod(0o640)
    write_output(str(kept), render)
    assert stat.S_IMODE(kept.stat().st_mode) == 0o640
    assert kept.read_text("utf-8") == "new\n"
