"""Paths that cannot be linted: each is one line on stderr and exit 2 (a FIFO or device met
in a folder walk is skipped with a note), never a hang, and the other paths are linted.

These run the real console script, so stderr and the exit code are exactly what a user
sees, and a read that blocks fails the test at the time limit instead of stalling it."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import threading
from pathlib import Path
from typing import Any

import jsonschema  # type: ignore[import-untyped, unused-ignore]
import pytest
from junitparser import JUnitXml  # type: ignore[import-untyped, unused-ignore]
from typer.testing import CliRunner

from tests.conftest import REPO
from tests.formatters.test_formatters import sarif_validator
from xodrlint.cli import app

CLEAN = REPO / "examples" / "clean.xodr"
BROKEN = REPO / "examples" / "broken.xodr"
CONSOLE_SCRIPT = Path(sys.executable).parent / "xodrlint"
OUTPUT_SCHEMA = json.loads((REPO / "docs" / "json-output.schema.json").read_text("utf-8"))
HANG_GUARD_SECONDS = 60
NOT_UTF8 = os.fsdecode(b"caf\xe9.xodr")  # Latin-1 bytes: a lone surrogate in Python


def console(*args: str | Path, stdin: bytes = b"") -> subprocess.CompletedProcess[str]:
    if not CONSOLE_SCRIPT.is_file():
        pytest.skip(f"no console script at {CONSOLE_SCRIPT}")
    return subprocess.run(
        [os.fsencode(str(CONSOLE_SCRIPT)), *(os.fsencode(str(arg)) for arg in args)],
        capture_output=True,
        input=stdin.decode("latin-1"),
        text=True,
        encoding="latin-1",  # stderr may carry any bytes: decoding must not fail the test
        timeout=HANG_GUARD_SECONDS,
        check=False,
    )


def _folder(tmp_path: Path) -> Path:
    maps = tmp_path / "maps"
    maps.mkdir()
    shutil.copyfile(CLEAN, maps / "a-clean.xodr")
    return maps


def test_special_files_given_by_name_are_one_line_each(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.xodr"
    os.mkfifo(fifo)  # reading it would wait for a writer forever
    done = console("check", fifo, "/dev/zero", CLEAN)
    assert done.returncode == 2
    assert _errors(done).splitlines() == [  # by name, as the reports
        "xodrlint: /dev/zero: is a character device, not a regular file",
        f"xodrlint: {fifo}: is a FIFO, not a regular file",
    ]
    assert "No findings in 1 of 3 files. 2 could not be read." in done.stdout


def test_special_files_met_in_a_folder_walk_are_skipped_with_a_note(tmp_path: Path) -> None:
    maps = _folder(tmp_path)
    os.mkfifo(maps / "b-pipe.xodr")
    (maps / "c-zero.xodr").symlink_to("/dev/zero")
    done = console("check", maps)
    assert done.returncode == 0, done.stderr
    assert _errors(done).splitlines() == [
        f"xodrlint: note: {maps.as_posix()}/b-pipe.xodr: skipped, a FIFO is not a regular file",
        # a link out of the folder is not followed at all (issue 30, item 8)
        f"xodrlint: note: skipped a file link leading out of the folder walked "
        f"({maps.as_posix()}/c-zero.xodr): a walk follows no link out of its folder; name "
        "the file on the command line to lint it",
    ]
    assert "All checks passed: 1 file, no findings." in done.stdout


@pytest.mark.parametrize("how", ["folder", "glob"])
def test_a_walk_follows_no_file_link_out_of_its_folder(tmp_path: Path, how: str) -> None:
    # issue 30, item 8: a repository's link to /proc/self/environ printed the run's
    # environment, secrets included, with --show-source
    maps = _folder(tmp_path)
    secret = tmp_path / "secret.xodr"
    secret.write_text("<OpenDRIVE>TOPSECRET-4711 <unclosed></OpenDRIVE>")
    (maps / "b-env.xodr").symlink_to("/proc/self/environ")
    (maps / "c-secret.xodr").symlink_to(secret)
    (maps / "sub").mkdir()
    (maps / "sub" / "d-inside.xodr").symlink_to("../a-clean.xodr")  # inside: followed
    shutil.copyfile(BROKEN, maps / "sub" / "e-broken.xodr")
    named = [maps] if how == "folder" else [f"{maps}/**/*.xodr"]
    done = console("check", "--show-source", "-f", "json", *named)
    assert "TOPSECRET" not in done.stdout + done.stderr and "PATH=" not in done.stdout
    linted = [entry["path"] for entry in json.loads(done.stdout)["files"]]
    assert linted == [f"{maps}/a-clean.xodr", f"{maps}/sub/e-broken.xodr"]
    # once for the run (beside the warning that JSON shows no source lines)
    (note,) = [line for line in done.stderr.splitlines() if "--show-source" not in line]
    assert note.startswith("xodrlint: note: skipped 2 file links leading out of the folder")
    # named on the command line, a link is still read
    direct = console("check", "-f", "json", maps / "c-secret.xodr")
    assert [f["code"] for f in json.loads(direct.stdout)["findings"]] == ["XS001"]


def test_symlink_loops_in_a_folder_walk(tmp_path: Path) -> None:
    maps = _folder(tmp_path)
    (maps / "b-loop.xodr").symlink_to("b-loop.xodr")
    (maps / "sub").mkdir()
    (maps / "sub" / "up").symlink_to("..")  # a folder cycle: links are not followed
    done = console("check", maps, BROKEN, "-q")
    assert done.returncode == 2
    assert _errors(done) == f"xodrlint: {maps}/b-loop.xodr: too many levels of symbolic links\n"
    assert done.stdout.count("XS006") == 3  # broken.xodr was still linted


def test_recursive_globs_do_not_follow_folder_links_into_loops(tmp_path: Path) -> None:
    maps = _folder(tmp_path)
    (maps / "sub").mkdir()
    shutil.copyfile(BROKEN, maps / "sub" / "b-broken.xodr")
    (maps / "sub" / "up").symlink_to("..")  # two loops: glob.glob followed them for ever
    (maps / "sub" / "again").symlink_to("../sub")
    done = console("check", "-f", "json", f"{maps}/**/*.xodr")
    assert done.returncode == 1, done.stderr
    paths = [entry["path"] for entry in json.loads(done.stdout)["files"]]
    assert paths == [f"{maps}/a-clean.xodr", f"{maps}/sub/b-broken.xodr"]


def test_a_file_named_several_ways_is_linted_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    maps = _folder(tmp_path)
    (tmp_path / "link.xodr").symlink_to(maps / "a-clean.xodr")
    monkeypatch.chdir(tmp_path)
    names = ["maps/a-clean.xodr", "./maps/a-clean.xodr", str(maps / "a-clean.xodr")]
    done = console("check", "-f", "json", *names, "link.xodr", "maps", "maps/*.xodr")
    assert done.returncode == 0, done.stderr
    # the name that sorts first is kept, whatever the order of the paths
    assert [entry["path"] for entry in json.loads(done.stdout)["files"]] == [names[2]]


def test_standard_input_twice_is_a_usage_error() -> None:
    done = console("check", "-", "-", stdin=CLEAN.read_bytes())
    assert done.returncode == 2
    assert done.stderr == "xodrlint: - (standard input) is given more than once\n"


@pytest.mark.parametrize(
    ("pattern", "found"),
    [
        ("maps/*.xodr", ["maps/a-clean.xodr"]),
        ("maps/*", ["maps/a-clean.xodr", "maps/notes.txt", "maps/sub/c.xodr"]),
        ("*.xodr", ["top.xodr"]),
        ("maps/*/c.xodr", ["maps/sub/c.xodr"]),
        ("maps/.hidden/*.xodr", ["maps/.hidden/h.xodr"]),
        ("**/*.xodr", ["maps/a-clean.xodr", "maps/sub/c.xodr", "top.xodr"]),
    ],
)
def test_globs_find_what_the_shell_would(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, pattern: str, found: list[str]
) -> None:
    from xodrlint.api import collect_inputs

    maps = _folder(tmp_path)
    for name in ("notes.txt", "sub/c.xodr", ".hidden/h.xodr", "../top.xodr"):
        (maps / name).parent.mkdir(exist_ok=True)
        (maps / name).write_text("<OpenDRIVE/>")
    monkeypatch.chdir(tmp_path)
    assert [item.display for item in collect_inputs([pattern])] == found


def test_non_utf8_file_names_are_one_line_and_the_rest_is_linted(tmp_path: Path) -> None:
    maps = _folder(tmp_path)
    try:
        shutil.copyfile(CLEAN, maps / NOT_UTF8)
    except (OSError, UnicodeError):
        pytest.skip("the file system takes only UTF-8 names")
    named = console("check", maps / NOT_UTF8, CLEAN)
    walked = console("check", maps, "-f", "json")
    for done in (named, walked):
        assert done.returncode == 2
        assert (
            _errors(done) == f"xodrlint: {maps}/caf\\xe9.xodr: the file name is not valid UTF-8\n"
        )
    report = json.loads(walked.stdout)
    assert [f["error"] is None for f in report["files"]] == [True, False]


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads files whatever their mode")
def test_permission_denied_for_real(tmp_path: Path) -> None:
    maps = _folder(tmp_path)
    locked = maps / "locked.xodr"
    shutil.copyfile(CLEAN, locked)
    locked.chmod(0)
    (maps / "closed").mkdir(mode=0)
    done = console("check", maps)
    assert done.returncode == 2
    assert sorted(done.stderr.splitlines()) == [
        f"xodrlint: {maps}/closed: cannot list: permission denied",
        f"xodrlint: {maps}/locked.xodr: cannot read: permission denied",
    ]


def _refuse(real: Any, refused: Path) -> Any:
    def guarded(path: Any, *args: Any, **kwargs: Any) -> Any:
        if Path(path) == refused:
            raise PermissionError(13, "Permission denied", str(path))
        return real(path, *args, **kwargs)

    return guarded


def test_permission_denied_emulated(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The same refusals as above, raised where the OS would raise them (tests run as root)."""
    maps = _folder(tmp_path)
    shutil.copyfile(CLEAN, maps / "locked.xodr")
    (maps / "closed").mkdir()
    shutil.copyfile(CLEAN, maps / "closed" / "hidden.xodr")
    monkeypatch.setattr(os, "scandir", _refuse(os.scandir, maps / "closed"))
    monkeypatch.setattr(os, "open", _refuse(os.open, maps / "locked.xodr"))
    result = CliRunner().invoke(app, ["check", str(maps), "-f", "json"])
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [
        f"xodrlint: {maps}/closed: cannot list: permission denied",
        f"xodrlint: {maps}/locked.xodr: cannot read: permission denied",
    ]
    report = json.loads(result.stdout)
    assert [f["path"] for f in report["files"]] == [
        f"{maps}/a-clean.xodr",
        f"{maps}/closed",
        f"{maps}/locked.xodr",
    ]


def test_a_folder_given_as_a_file_is_walked_and_a_missing_one_is_an_error(tmp_path: Path) -> None:
    maps = _folder(tmp_path)
    done = console("check", maps, tmp_path / "gone", "-q")
    assert done.returncode == 2
    assert _errors(done) == f"xodrlint: {tmp_path / 'gone'}: no such file or directory\n"


def test_max_file_size_refuses_larger_inputs_before_reading(tmp_path: Path) -> None:
    size = CLEAN.stat().st_size
    done = console("check", CLEAN, BROKEN, "--max-file-size", str(size), "-q")
    assert done.returncode == 2
    assert _errors(done) == (
        f"xodrlint: {BROKEN}: larger than the maximum file size ({size}, see --max-file-size)\n"
    )
    piped = console("check", "-", "--max-file-size", "1KiB", stdin=CLEAN.read_bytes())
    assert piped.returncode == 2
    assert (
        piped.stderr
        == "xodrlint: -: larger than the maximum file size (1KiB, see --max-file-size)\n"
    )
    assert console("check", CLEAN, "--max-file-size", "2GiB").returncode == 0


@pytest.mark.parametrize("value", ["0", "lots", "-5", "1.5GB", "10PB"])
def test_a_bad_max_file_size_is_a_usage_error(value: str) -> None:
    done = console("check", CLEAN, "--max-file-size", value)
    assert (done.returncode, done.stdout) == (2, "")
    assert done.stderr == (
        f"xodrlint: --max-file-size {value}: expected a positive size such as 500MB or 2GiB\n"
    )


def test_max_file_size_in_the_config(tmp_path: Path) -> None:
    (tmp_path / "xodrlint.toml").write_text('max-file-size = "1kB"\n', "utf-8")
    shutil.copyfile(CLEAN, tmp_path / "clean.xodr")
    done = console("check", tmp_path / "clean.xodr")
    assert done.returncode == 2 and "(1KB, see --max-file-size)" in done.stderr
    shown = json.loads(console("config", tmp_path, "-f", "json").stdout)
    assert shown["settings"]["max-file-size"] == {
        "value": "1KB",
        "source": str(tmp_path / "xodrlint.toml"),
    }
    (tmp_path / "xodrlint.toml").write_text("max-file-size = -1\n", "utf-8")
    bad = console("check", tmp_path / "clean.xodr")
    assert bad.returncode == 2 and "'max-file-size' must be a positive size" in bad.stderr


def shell(command: str) -> subprocess.CompletedProcess[str]:
    """``command`` run by the shell: for redirections subprocess cannot express."""
    if not CONSOLE_SCRIPT.is_file():
        pytest.skip(f"no console script at {CONSOLE_SCRIPT}")
    return subprocess.run(
        command, shell=True, capture_output=True, text=True, timeout=HANG_GUARD_SECONDS, check=False
    )


def test_closed_stdin_is_one_line() -> None:
    assert shell(f"{CONSOLE_SCRIPT} check - </dev/null").returncode == 1  # empty: one XS001
    closed = shell(f"{CONSOLE_SCRIPT} check - <&-")
    assert closed.returncode == 2
    assert closed.stderr == "xodrlint: -: cannot read standard input: it is closed\n"


def _unreadable_inputs(tmp_path: Path) -> list[Path]:
    fifo = tmp_path / "pipe.xodr"
    os.mkfifo(fifo)
    return [BROKEN, tmp_path / "missing.xodr", fifo]


def _check_document(output_format: str, text: str) -> None:
    if output_format == "json":
        document = json.loads(text)
        jsonschema.validate(document, OUTPUT_SCHEMA)
        assert document["summary"]["unreadable_files"] == 2
    elif output_format == "sarif":
        log = json.loads(text)
        assert not list(sarif_validator().iter_errors(log))
        notifications = log["runs"][0]["invocations"][0]["toolExecutionNotifications"]
        assert sum("pipe.xodr" in n["message"]["text"] for n in notifications) == 1
    elif output_format == "junit":
        suites = JUnitXml.fromstring(text.encode("utf-8"))
        assert suites.errors == 2
    else:
        issues = json.loads(text)
        assert [i["check_name"] for i in issues].count("xodrlint:unreadable") == 2


@pytest.mark.parametrize("output_format", ["json", "sarif", "junit", "gitlab"])
def test_machine_formats_stay_complete_when_inputs_are_unreadable(
    tmp_path: Path, output_format: str
) -> None:
    done = console("check", "-f", output_format, *_unreadable_inputs(tmp_path))
    assert done.returncode == 2
    # one line per unreadable input; a report without a place for the run's notes (what
    # was not checked: junit, gitlab) leaves them to stderr too
    lines = [line for line in done.stderr.splitlines() if not line.startswith("xodrlint: note:")]
    assert len(lines) == 2 and "Traceback" not in done.stderr
    _check_document(output_format, done.stdout)


def test_the_python_api_refuses_a_fifo_without_blocking(tmp_path: Path) -> None:
    # lint_file opens without blocking and checks the open file: a FIFO with no writer
    # would otherwise keep the caller waiting for ever
    from xodrlint import lint_file

    fifo = tmp_path / "pipe.xodr"
    os.mkfifo(fifo)
    done: list[Any] = []
    worker = threading.Thread(target=lambda: done.append(lint_file(fifo)), daemon=True)
    worker.start()
    worker.join(timeout=30)
    assert done, "lint_file blocked on a FIFO"
    assert done[0].error == f"{fifo.as_posix()}: is a FIFO, not a regular file"


def _errors(done: subprocess.CompletedProcess[str]) -> str:
    """``done``'s stderr but the run's notes (what was not checked), which the text
    format says there after its report."""
    return "".join(
        line
        for line in done.stderr.splitlines(keepends=True)
        if not line.startswith("xodrlint: note: only railroad")
    )
