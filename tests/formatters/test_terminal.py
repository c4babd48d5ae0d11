"""What a person at a terminal sees: colour as --color, NO_COLOR and FORCE_COLOR say,
--verbose, and the progress bar of a long batch (never in a pipe or a CI log)."""

from __future__ import annotations

import io
import os
import pty
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.cli.test_cli import ANSI, BROKEN, CLEAN, cli
from tests.conftest import REPO
from xodrlint.api import default_registry
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.runners import batch
from xodrlint.runners.batch import Task, lint_tasks

CONSOLE_SCRIPT = Path(sys.executable).parent / "xodrlint"
#: Any style: colour, bold (1), dim (2), underline (4).
STYLE = re.compile(rb"\x1b\[[0-9;]*m")


def _on_a_terminal(*args: str | Path, **env: str) -> bytes:
    """Standard output of the console script run on a pseudo-terminal."""
    if not CONSOLE_SCRIPT.is_file():
        pytest.skip(f"no console script at {CONSOLE_SCRIPT}")
    base = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR", "CI")}
    master, slave = pty.openpty()
    try:
        subprocess.run(
            [CONSOLE_SCRIPT, *map(str, args)],
            stdout=slave,
            stderr=subprocess.DEVNULL,
            env={**base, "TERM": "xterm-256color", **env},
            timeout=60,
            check=False,
        )
    finally:
        os.close(slave)
    output = b""
    while True:
        try:
            chunk = os.read(master, 65536)
        except OSError:  # the other side is closed and drained
            break
        if not chunk:
            break
        output += chunk
    os.close(master)
    return output


def test_a_terminal_gets_styles_and_no_color_takes_every_one_away() -> None:
    assert STYLE.search(_on_a_terminal("check", BROKEN))
    plain = _on_a_terminal("check", BROKEN, NO_COLOR="1")
    assert b"examples/broken.xodr:25:7: XS006" in plain
    assert not STYLE.search(plain)  # no bold, dim or underline either
    assert not STYLE.search(_on_a_terminal("check", BROKEN, "--color", "never"))


def test_explain_on_a_terminal_follows_the_same_choice() -> None:
    assert STYLE.search(_on_a_terminal("explain", "SW001"))
    plain = _on_a_terminal("explain", "SW001", NO_COLOR="1")
    assert b"SW001" in plain and not STYLE.search(plain)
    assert not STYLE.search(_on_a_terminal("explain", "SW001", "--color", "never"))


def test_force_color_and_color_always_style_a_pipe() -> None:
    assert ANSI.search(cli("check", BROKEN, code=1, FORCE_COLOR="1").stdout)
    assert ANSI.search(cli("check", BROKEN, "--color", "always", code=1).stdout)
    assert not ANSI.search(cli("check", BROKEN, code=1).stdout)
    # the flag decides over the environment, both ways
    assert not ANSI.search(cli("check", BROKEN, "--color", "never", code=1, FORCE_COLOR="1").stdout)
    assert ANSI.search(cli("check", BROKEN, "--color", "always", code=1, NO_COLOR="1").stdout)


def test_color_is_for_the_text_format_only() -> None:
    out = cli("check", BROKEN, "-f", "json", "--color", "always", code=1).stdout
    assert not ANSI.search(out)
    refused = cli("check", BROKEN, "--color", "sometimes", code=2)
    assert "sometimes" in refused.stderr


def test_the_message_is_not_bold_only_its_location() -> None:
    out = cli("check", BROKEN, "--color", "always", code=1).stdout
    line = next(line for line in out.splitlines() if "'sideways'" in line)
    message = line[line.index("'switch/@position'") :]
    assert not ANSI.search(message)


def test_verbose_names_the_config_rules_and_each_files_schema_and_stages(tmp_path: Path) -> None:
    config = tmp_path / "xodrlint.toml"
    config.write_text('select = ["SW", "XS"]\n', "utf-8")
    done = cli("check", "-v", "--config", config, BROKEN, CLEAN, code=1)
    lines = done.stderr.splitlines()
    assert lines[0] == f"xodrlint: config: {config}"
    assert lines[1].startswith("xodrlint: rules: ") and "SW001" in lines[1]
    assert "ST001" not in lines[1]
    assert lines[2] == "xodrlint: files: 2, linted in this process"
    broken = next(line for line in lines if "examples/broken.xodr:" in line)
    assert "OpenDRIVE 1.7; schema: built-in railroad schema for OpenDRIVE 1.7" in broken
    for stage in ("read", "parse", "model", "rules", "validation", "total"):
        assert re.search(rf"\b{stage}\b[^,]* \d+\.\d (ms|s)\b", broken), (stage, broken)
    said = [line for line in lines if not line.startswith("xodrlint: note: ")]
    assert re.fullmatch(r"xodrlint: linted 2 files in \d+\.\d+ (ms|s)", said[-1])
    assert "XS006" in done.stdout  # the report is as without -v


def test_without_verbose_stderr_is_quiet() -> None:
    # the run's notes only (what it did not check), never its progress
    lines = cli("check", BROKEN, code=1).stderr.splitlines()
    assert lines and all(line.startswith("xodrlint: note: ") for line in lines)


def test_every_stage_is_timed_in_worker_processes_too() -> None:
    tasks = [Task(BROKEN, f"b{n}") for n in range(4)]
    reports = lint_tasks(Linter(default_registry(), LintOptions()), tasks, 2)
    for report in reports:
        assert {"read", "parse", "model", "rules", "total"} <= set(report.timings)
        assert report.timings["total"] >= report.timings["rules"] > 0


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _batch_on_a_terminal(monkeypatch: pytest.MonkeyPatch, after: float, **env: str) -> str:
    terminal = _Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    monkeypatch.setattr(batch, "PROGRESS_AFTER_SECONDS", after)
    monkeypatch.delenv("CI", raising=False)
    monkeypatch.setenv("TERM", "xterm")
    for name, value in env.items():
        monkeypatch.setenv(name, value)
    tasks = [Task(REPO / "examples" / "clean.xodr", f"clean-{n}") for n in range(3)]
    lint_tasks(Linter(default_registry(), LintOptions()), tasks, 1, progress=True)
    return terminal.getvalue()


def test_a_long_batch_on_a_terminal_shows_a_progress_bar(monkeypatch: pytest.MonkeyPatch) -> None:
    assert "linting" in _batch_on_a_terminal(monkeypatch, after=0)


def test_a_short_batch_shows_none(monkeypatch: pytest.MonkeyPatch) -> None:
    assert _batch_on_a_terminal(monkeypatch, after=60) == ""


def test_a_ci_log_shows_none_even_on_a_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    assert _batch_on_a_terminal(monkeypatch, after=0, CI="true") == ""
    assert _batch_on_a_terminal(monkeypatch, after=0, TERM="dumb") == ""


def test_a_pipe_shows_none(monkeypatch: pytest.MonkeyPatch) -> None:
    pipe = io.StringIO()
    monkeypatch.setattr(sys, "stderr", pipe)
    monkeypatch.setattr(batch, "PROGRESS_AFTER_SECONDS", 0)
    tasks = [Task(REPO / "examples" / "clean.xodr", f"clean-{n}") for n in range(3)]
    lint_tasks(Linter(default_registry(), LintOptions()), tasks, 1, progress=True)
    assert pipe.getvalue() == ""


#: A colour, not only bold or underline.
COLOUR = re.compile(r"\x1b\[(?:[0-9;]*;)?(?:3[0-7]|9[0-7]|38;)")


def test_color_always_gives_colour_even_under_no_color() -> None:
    out = cli("check", BROKEN, "--color", "always", code=1, NO_COLOR="1").stdout
    assert COLOUR.search(out)
    assert COLOUR.search(cli("check", BROKEN, code=1, FORCE_COLOR="1").stdout)


def test_explain_styles_a_pipe_when_asked() -> None:
    assert ANSI.search(cli("explain", "SW001", "--color", "always", code=0).stdout)
    raw = cli("explain", "SW001", code=0).stdout
    assert raw.startswith("# SW001 ") and not ANSI.search(raw)  # the page's Markdown


def test_verbose_says_where_files_were_linted_and_counts_only_those(tmp_path: Path) -> None:
    done = cli("check", "-v", "-j", "2", CLEAN, BROKEN, tmp_path / "gone.xodr", code=2)
    lines = done.stderr.splitlines()
    assert "xodrlint: files: 2, linted in this process" in lines  # too few for workers
    assert any(re.fullmatch(r"xodrlint: linted 2 files in \d+\.\d+ (ms|s)", x) for x in lines)
    for index in range(4):  # the same path twice is one input
        (tmp_path / f"m{index}.xodr").write_bytes(BROKEN.read_bytes())
    pooled = cli("check", "-v", "-j", "2", tmp_path, code=1).stderr
    assert "xodrlint: files: 4, linted in 2 worker processes" in pooled.splitlines()
