"""Hostile things handed over beside the map: baselines, configs, streams, file names.
Each ends in one line and exit 2, never an internal error."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import REPO

CLEAN = REPO / "examples" / "clean.xodr"


def _xodrlint(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "xodrlint", *map(str, args)],
        capture_output=True,
        text=True,
        check=False,
    )


def _one_line_exit_2(done: subprocess.CompletedProcess[str], *words: str) -> None:
    assert done.returncode == 2, done.stderr
    assert len(done.stderr.splitlines()) == 1, done.stderr
    assert "internal error" not in done.stderr
    for word in words:
        assert word in done.stderr


@pytest.mark.parametrize(
    ("content", "reason"),
    [
        ("[" * 100_000 + "]" * 100_000, "nested too deeply"),
        ('{"format_version": ' + "1" * 5000 + "}", "a number too long to read"),
    ],
)
def test_a_hostile_baseline_is_a_usage_error(tmp_path: Path, content: str, reason: str) -> None:
    baseline = tmp_path / "baseline.json"
    baseline.write_text(content)
    _one_line_exit_2(_xodrlint("check", "--baseline", baseline, CLEAN), "not a baseline", reason)


def test_a_config_nested_too_deeply_is_a_usage_error(tmp_path: Path) -> None:
    config = tmp_path / "xodrlint.toml"
    config.write_text("a = " + "[" * 100_000 + "]" * 100_000 + "\n")
    _one_line_exit_2(_xodrlint("check", "--config", config, CLEAN), "nested too deeply")


@pytest.mark.parametrize("output_format", ["text", "json"])
def test_a_closed_standard_output_is_a_usage_error(output_format: str) -> None:
    closed = subprocess.run(
        [sys.executable, "-m", "xodrlint", "check", "-f", output_format, str(CLEAN)],
        capture_output=False,
        stderr=subprocess.PIPE,
        text=True,
        check=False,
        preexec_fn=_close_stdout,
    )
    assert closed.returncode == 2, closed.stderr
    assert closed.stderr.strip().endswith("standard output is closed; use -o FILE")
    assert len(closed.stderr.splitlines()) == 1


def test_a_closed_standard_output_does_not_matter_with_o(tmp_path: Path) -> None:
    report = tmp_path / "report.txt"
    done = subprocess.run(
        [sys.executable, "-m", "xodrlint", "check", "-o", str(report), str(CLEAN)],
        stderr=subprocess.PIPE,
        text=True,
        check=False,
        preexec_fn=_close_stdout,
    )
    assert done.returncode == 0, done.stderr
    assert report.read_text()


def _close_stdout() -> None:
    import os

    os.close(1)


@pytest.mark.parametrize("read", ["baseline", "config"])
def test_the_report_is_never_written_over_a_file_the_run_reads(tmp_path: Path, read: str) -> None:
    target = tmp_path / ("b.json" if read == "baseline" else "xodrlint.toml")
    if read == "baseline":
        assert _xodrlint("check", "--write-baseline", target, CLEAN).returncode == 0
        args: tuple[str | Path, ...] = ("--baseline", target)
    else:
        target.write_text('select = ["ALL"]\n')
        args = ("--config", target)
    before = target.read_bytes()
    done = _xodrlint("check", *args, "-o", target, CLEAN)
    what = "the baseline" if read == "baseline" else "a config file"
    _one_line_exit_2(done, f"is {what} this run reads")
    assert target.read_bytes() == before


@pytest.mark.parametrize("output_format", ["text", "concise"])
def test_control_characters_in_file_names_reach_the_terminal_escaped(
    tmp_path: Path, output_format: str
) -> None:
    named = tmp_path / "b\x1b[31mred\x07.xodr"
    named.write_bytes((REPO / "examples" / "broken.xodr").read_bytes())
    done = _xodrlint("check", "-f", output_format, "--show-source", named)
    assert done.returncode == 1
    assert "\x1b" not in done.stdout and "\x07" not in done.stdout
    assert "b\\x1b[31mred\\x07.xodr:25:7: XS006" in done.stdout
