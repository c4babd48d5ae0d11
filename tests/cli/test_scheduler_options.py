"""``check --scheduler``'s options, refused before anything is linted, Dask installed or
not; and what a plain run, or ``import xodrlint``, never imports."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from tests.conftest import REPO
from xodrlint.cli import app
from xodrlint.cli.check import scheduler as cli_scheduler

BROKEN = REPO / "examples" / "broken.xodr"


def run(*args: str | Path) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["--scheduler-timeout", "5"],
            "--scheduler-timeout applies only with --scheduler",
        ),
        (
            ["--scheduler", "local", "--scheduler-timeout", "0"],
            "--scheduler-timeout 0: expected seconds above 0",
        ),
        (
            ["--scheduler", "tcp://127.0.0.1:8786", "--jobs", "4"],
            "--jobs: the workers of --scheduler tcp://127.0.0.1:8786 are their own "
            "(--jobs sets how many --scheduler local starts)",
        ),
    ],
)
def test_options_a_scheduler_run_cannot_take_are_one_line_and_exit_2(
    args: list[str], message: str
) -> None:
    result = run("check", *args, BROKEN)
    assert result.exit_code == 2
    assert result.stderr == f"xodrlint: {message}\n"
    assert result.stdout == ""


def test_without_dask_a_scheduler_run_says_how_to_install_it(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if it were not installed
    result = run("check", "--scheduler", "local", BROKEN)
    assert result.exit_code == 2
    assert result.stderr == (
        "xodrlint: --scheduler needs Dask, which is not installed: pip install "
        "'dask[distributed]' (or xodrlint's dask extra)\n"
    )


def test_a_scheduler_run_with_nothing_to_send_starts_no_cluster(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setitem(sys.modules, "xodrlint.runners.dask", None)  # importing it fails
    missing = tmp_path / "missing.xodr"
    result = run("check", "--scheduler", "tcp://127.0.0.1:9", missing, "-")
    assert result.exit_code == 2
    assert "missing.xodr: no such file or directory" in result.stderr.lower()


def test_the_name_of_a_local_cluster_is_the_engines() -> None:
    pytest.importorskip("distributed", reason="Dask is not installed")
    from xodrlint.runners import dask

    assert cli_scheduler.LOCAL == dask.LOCAL


def test_import_xodrlint_and_the_api_import_no_dask() -> None:
    code = (
        "import sys, xodrlint, xodrlint.api, xodrlint.cli.check.run; xodrlint.lint_file; "
        "print(sorted(m for m in sys.modules if m.split('.')[0] in ('dask', 'distributed')))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout == "[]\n"


@pytest.mark.parametrize(
    ("scheduler", "said"),
    [
        (None, "files: 8, linted in 2 worker processes"),
        ("local", "files: 8, linted on a local Dask cluster of 2 worker processes"),
        (
            "tcp://10.0.0.5:8786",
            "files: 8, linted on the workers of the Dask scheduler tcp://10.0.0.5:8786",
        ),
    ],
)
def test_verbose_says_where_the_files_are_linted(
    scheduler: str | None, said: str, capsys: pytest.CaptureFixture[str]
) -> None:
    from xodrlint.cli.check.verbose import describe_run
    from xodrlint.config.settings import settings_from

    describe_run(settings_from(None, {}), ["SW001"], 8, 2, scheduler)
    assert capsys.readouterr().err.splitlines()[-1] == f"xodrlint: {said}"
