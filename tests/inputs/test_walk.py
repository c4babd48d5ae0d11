"""Folder walks follow .gitignore, .ignore, info/exclude and hidden names as git and ruff
do (issue 19, item 7); ``--show-files`` lists what a check would lint; a run that finds
nothing to lint says so (item 11).

The repositories here are folders with a ``.git`` folder made by hand: the walk needs no
git. Where git is installed, one test compares the walk with git's own answer."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from tests.conftest import REPO
from xodrlint.api import collect_inputs
from xodrlint.cli import app

CLEAN = REPO / "examples" / "clean.xodr"
HANG_GUARD_SECONDS = 60


def run(*args: str | Path) -> Result:
    return CliRunner().invoke(app, [str(arg) for arg in args])


def console(*args: str | Path) -> subprocess.CompletedProcess[str]:
    """The real command (its own process), under a time limit: a hang fails the test."""
    return subprocess.run(
        [sys.executable, "-m", "xodrlint", *(str(arg) for arg in args)],
        capture_output=True,
        text=True,
        timeout=HANG_GUARD_SECONDS,
        check=False,
    )


def make(root: Path, files: dict[str, str]) -> Path:
    """``files`` under ``root``: a ``.xodr`` name gets a clean map, others their text."""
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if name.endswith(".xodr"):
            shutil.copyfile(CLEAN, path)
        else:
            path.write_text(text, "utf-8")
    return root


def shown(result: Result) -> list[str]:
    assert result.exit_code == 0, result.output
    return result.stdout.splitlines()


@pytest.fixture
def repo(tmp_path: Path) -> Path:
    """A repository with an ignored build folder, a negation, a nested .gitignore, an
    .ignore file, info/exclude, and hidden files and folders."""
    return make(
        tmp_path / "repo",
        {
            ".git/info/exclude": "*.local.xodr\n",
            ".gitignore": "# build output\nbuild/\n/generated/*\n!/generated/keep/\n",
            "build/out.xodr": "",
            "build/deep/more.xodr": "",
            "generated/keep/k.xodr": "",
            "generated/other/o.xodr": "",
            "maps/a.xodr": "",
            "maps/b.local.xodr": "",
            "maps/.ignore": "draft.xodr\n",
            "maps/draft.xodr": "",
            "maps/.x.xodr": "",
            "maps/sub/.gitignore": "scratch.xodr\n",
            "maps/sub/b.xodr": "",
            "maps/sub/scratch.xodr": "",
            ".hidden/h.xodr": "",
        },
    )


def test_a_folder_walk_follows_the_ignore_files_and_skips_hidden_names(repo: Path) -> None:
    assert shown(run("check", repo, "--show-files")) == [
        f"{repo}/generated/keep/k.xodr",
        f"{repo}/maps/a.xodr",
        f"{repo}/maps/sub/b.xodr",
    ]


def test_an_excluded_folder_is_never_entered(repo: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # a large ignored build/ costs nothing: listing it would fail here
    listed: list[str] = []
    scandir = os.scandir

    def watched(path: str) -> object:
        listed.append(os.fspath(path))
        return scandir(path)

    monkeypatch.setattr(os, "scandir", watched)
    assert len(shown(run("check", repo, "--show-files"))) == 3
    assert sorted(Path(path).relative_to(repo).as_posix() for path in listed) == [
        ".",
        "generated",
        "generated/keep",
        "maps",
        "maps/sub",
    ]


def test_no_respect_gitignore_lints_what_they_exclude_but_not_hidden_names(repo: Path) -> None:
    assert shown(run("check", repo, "--show-files", "--no-respect-gitignore")) == [
        f"{repo}/build/deep/more.xodr",
        f"{repo}/build/out.xodr",
        f"{repo}/generated/keep/k.xodr",
        f"{repo}/generated/other/o.xodr",
        f"{repo}/maps/a.xodr",
        f"{repo}/maps/b.local.xodr",
        f"{repo}/maps/draft.xodr",
        f"{repo}/maps/sub/b.xodr",
        f"{repo}/maps/sub/scratch.xodr",
    ]


def test_a_file_named_explicitly_is_always_linted(repo: Path) -> None:
    named = [repo / ".hidden/h.xodr", repo / "build/out.xodr", repo / "maps/draft.xodr"]
    result = run("check", *named, "-f", "json")
    assert result.exit_code == 0, result.output
    assert [f["path"] for f in json.loads(result.stdout)["files"]] == [str(p) for p in named]


def test_a_walk_below_the_top_reads_the_ignore_files_above(repo: Path) -> None:
    # /generated/* is anchored at the repository's top, not at the folder walked
    assert shown(run("check", repo / "generated", "--show-files")) == [
        f"{repo}/generated/keep/k.xodr"
    ]
    assert shown(run("check", repo / "maps" / "sub", "--show-files")) == [f"{repo}/maps/sub/b.xodr"]


def test_an_excluded_folder_named_on_the_command_line_is_linted(repo: Path) -> None:
    # named, it is walked as ripgrep and ruff walk it: the ignore files above do not apply
    assert shown(run("check", repo / "build", "--show-files")) == [
        f"{repo}/build/deep/more.xodr",
        f"{repo}/build/out.xodr",
    ]
    result = run("check", repo / "build" / "deep", "-f", "json")
    assert result.exit_code == 0, result.output
    assert result.stderr == ""
    assert [f["path"] for f in json.loads(result.stdout)["files"]] == [
        f"{repo}/build/deep/more.xodr"
    ]
    # a glob that starts from it, too
    assert shown(run("check", f"{repo}/build/*.xodr", "--show-files")) == [f"{repo}/build/out.xodr"]


def test_the_ignore_files_inside_a_named_excluded_folder_still_apply(repo: Path) -> None:
    (repo / "build" / ".gitignore").write_text("deep/\n", "utf-8")
    assert shown(run("check", repo / "build", "--show-files")) == [f"{repo}/build/out.xodr"]
    every = run("check", repo / "build", "--show-files", "--no-respect-gitignore")
    assert shown(every) == [f"{repo}/build/deep/more.xodr", f"{repo}/build/out.xodr"]


def test_a_walk_from_the_top_leaves_the_excluded_folder_out(
    repo: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert not [path for path in shown(run("check", repo, "--show-files")) if "/build/" in path]
    monkeypatch.chdir(repo / "maps")  # the repository's ignore files apply from below too
    assert "../build/out.xodr" not in shown(run("check", "..", "--show-files"))
    assert shown(run("check", "../build", "--show-files")) == [
        "../build/deep/more.xodr",
        "../build/out.xodr",
    ]


def test_globs_follow_the_ignore_files(repo: Path) -> None:
    assert shown(run("check", f"{repo}/**/*.xodr", "--show-files")) == [
        f"{repo}/generated/keep/k.xodr",
        f"{repo}/maps/a.xodr",
        f"{repo}/maps/sub/b.xodr",
    ]
    result = run("check", f"{repo}/maps/**/draft.xodr")  # maps/.ignore names it
    assert result.exit_code == 2
    assert result.stderr == (
        f"xodrlint: {repo}/maps/**/draft.xodr: no file matches (outside what .gitignore and "
        ".ignore files exclude; --no-respect-gitignore lints that too)\n"
    )
    every = run("check", f"{repo}/maps/**/draft.xodr", "--show-files", "--no-respect-gitignore")
    assert shown(every) == [f"{repo}/maps/draft.xodr"]


@pytest.mark.parametrize(
    ("files", "kept"),
    [
        # a deeper .gitignore overrides a higher one
        ({".gitignore": "*.xodr\n", "m/.gitignore": "!*.xodr\nold.xodr\n"}, ["m/a.xodr"]),
        # .ignore overrides .gitignore, at any depth (ripgrep's and ruff's order)
        ({"m/.gitignore": "*.xodr\n", ".ignore": "!old.xodr\n"}, ["m/old.xodr"]),
        # info/exclude is overridden by any .gitignore
        ({".git/info/exclude": "*.xodr\n", ".gitignore": "!a.xodr\n"}, ["m/a.xodr"]),
        # git cannot re-include a file whose folder is excluded, and neither can we
        ({".gitignore": "m/\n!m/a.xodr\n"}, []),
        ({".gitignore": "m/*\n!m/a.xodr\n"}, ["m/a.xodr"]),
        # "everything but maps": a folder is re-included by !*/, its files by !*.xodr
        ({".gitignore": "*\n!*/\n!*.xodr\n"}, ["m/a.xodr", "m/old.xodr"]),
        # a line that names a folder only does not name a file
        ({".gitignore": "a.xodr/\n"}, ["m/a.xodr", "m/old.xodr"]),
    ],
)
def test_which_ignore_file_wins(tmp_path: Path, files: dict[str, str], kept: list[str]) -> None:
    repo = make(tmp_path, {".git/HEAD": "", "m/a.xodr": "", "m/old.xodr": "", **files})
    assert shown(run("check", repo, "--show-files")) == [f"{repo}/{name}" for name in kept]


def test_outside_a_repository_the_walked_folders_ignore_files_apply(tmp_path: Path) -> None:
    plain = make(
        tmp_path,
        {
            ".gitignore": "a.xodr\n",
            "maps/.gitignore": "b.xodr\n",
            "maps/a.xodr": "",
            "maps/b.xodr": "",
        },
    )
    # no .git above: the folder walked is the top, its parent's .gitignore is not read
    assert shown(run("check", plain / "maps", "--show-files")) == [f"{plain}/maps/a.xodr"]
    assert shown(run("check", plain, "--show-files")) == []


def test_a_worktree_reads_info_exclude_from_its_common_folder(tmp_path: Path) -> None:
    make(
        tmp_path / "main",
        {".git/info/exclude": "a.xodr\n", ".git/worktrees/w/commondir": "../..\n"},
    )
    tree = make(tmp_path / "w", {"a.xodr": "", "b.xodr": ""})
    (tree / ".git").write_text(f"gitdir: {tmp_path}/main/.git/worktrees/w\n", "utf-8")
    assert shown(run("check", tree, "--show-files")) == [f"{tree}/b.xodr"]


def test_respect_gitignore_in_the_config_and_the_command_line_wins(repo: Path) -> None:
    (repo / "xodrlint.toml").write_text("respect-gitignore = false\n", "utf-8")
    assert f"{repo}/build/out.xodr" in shown(run("check", repo, "--show-files"))
    assert f"{repo}/build/out.xodr" not in shown(
        run("check", repo, "--show-files", "--respect-gitignore")
    )
    settings = json.loads(run("config", repo, "-f", "json").stdout)["settings"]
    assert settings["respect-gitignore"] == {
        "value": False,
        "source": str(repo / "xodrlint.toml"),
    }
    assert "respect-gitignore         false" in run("config", repo).stdout
    (repo / "xodrlint.toml").write_text('respect-gitignore = "no"\n', "utf-8")
    refused = run("check", repo)
    assert refused.exit_code == 2
    assert "'respect-gitignore' must be true or false, got 'no'" in refused.stderr


def test_show_files_lists_in_report_order_as_reports_name_files(
    repo: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(repo)
    args = ["maps/sub/b.xodr", "-", "maps", "maps/*.xodr", "--stdin-filename", "in.xodr"]
    listed = CliRunner().invoke(app, ["check", *args, "--show-files"], input="<OpenDRIVE/>")
    linted = CliRunner().invoke(app, ["check", *args, "-f", "json"], input=CLEAN.read_text())
    assert listed.exit_code == 0, listed.output
    # by name, whatever the order given, standard input by --stdin-filename
    assert listed.stdout.splitlines() == ["in.xodr", "maps/a.xodr", "maps/sub/b.xodr"]
    assert [f["path"] for f in json.loads(linted.stdout)["files"]] == listed.stdout.splitlines()


def test_show_files_says_what_cannot_be_linted_and_exits_2(repo: Path) -> None:
    result = run("check", repo / "maps" / "sub", repo / "gone.xodr", "--show-files")
    assert result.exit_code == 2
    assert result.stdout == f"{repo}/maps/sub/b.xodr\n"
    assert result.stderr == f"xodrlint: {repo}/gone.xodr: no such file or directory\n"


def test_show_files_into_a_pipe_closed_early(tmp_path: Path) -> None:
    make(tmp_path, {f"maps/{n:05}-{'x' * 40}.xodr": "" for n in range(1500)})  # > a pipe
    done = subprocess.run(
        [
            "bash",
            "-c",
            f"set -o pipefail; {sys.executable} -m xodrlint check {tmp_path}/maps "
            "--show-files | head -1",
        ],
        capture_output=True,
        text=True,
        timeout=HANG_GUARD_SECONDS,
        check=False,
    )
    assert (done.returncode, done.stderr) == (0, "")
    assert done.stdout == f"{tmp_path}/maps/00000-{'x' * 40}.xodr\n"


def test_a_line_that_would_backtrack_for_ever_is_left_out_with_a_note(tmp_path: Path) -> None:
    # as a backtracking regular expression this takes minutes on a 60-character name
    name = "a" * 60 + ".xodr"
    repo = make(tmp_path, {".git/HEAD": "", ".gitignore": "*a*a*a*a*a*a*a*a*c\n*.tmp\n", name: ""})
    done = console("check", repo, "--show-files")
    assert done.returncode == 0, done.stderr
    assert done.stdout == f"{repo}/{name}\n"
    assert done.stderr == (
        f"xodrlint: note: {repo}/.gitignore:1: pattern left out: more than 4 '*' wildcards "
        "could take minutes to match\n"
    )


def test_ignore_files_that_cannot_be_used_are_notes_never_a_hang(tmp_path: Path) -> None:
    repo = make(
        tmp_path,
        {".git/HEAD": "", ".gitignore": "b.xodr\nlast\\\n", "m/a.xodr": "", "m/b.xodr": ""},
    )
    os.mkfifo(repo / "m" / ".gitignore")  # reading it would wait for a writer for ever
    (repo / "m" / ".ignore").mkdir()
    done = console("check", repo, "--show-files")
    assert done.returncode == 0, done.stderr
    assert done.stdout == f"{repo}/m/a.xodr\n"
    assert done.stderr == (
        f"xodrlint: note: {repo}/.gitignore:2: pattern left out: not a valid gitignore pattern\n"
    )


def test_the_python_api_respects_ignore_files_unless_told(repo: Path) -> None:
    assert not [i for i in collect_inputs([str(repo)]) if i.path and "build" in i.path.parts]
    every = collect_inputs([str(repo)], respect_gitignore=False)
    assert repo / "build/out.xodr" in [item.path for item in every]
    named = collect_inputs([str(repo / "build")])
    assert [item.path for item in named] == [repo / "build/deep/more.xodr", repo / "build/out.xodr"]


# --- the walk against git itself --------------------------------------------------------

GIT_FILES = [
    "a.xodr",
    "keep.xodr",
    "d/a.xodr",
    "d/keep.xodr",
    "d/e/a.xodr",
    "d/e/keep.xodr",
    "build/a.xodr",
    "x/build/a.xodr",
    "dx/a.xodr",
    "dy/a.xodr",
    "a/b/c.xodr",
    "a/x/b/c.xodr",
    "sub/a.xodr",
    "sub/build/a.xodr",
    "sub/deep/a.xodr",
]
GIT_CASES = [
    {"": "*\n!*/\n!*.xodr\n"},
    {"": "build/\n"},
    {"": "build/*\n!build/keep.xodr\n"},
    {"": "build/\n!build/keep.xodr\n"},
    {"": "d/**\n!d/keep.xodr\n"},
    {"": "d/**\n!d/**/\n!d/**/keep.xodr\n"},
    {"": "/build\n"},
    {"": "*\n!d/\n!d/*.xodr\n"},
    {"": "d*/\n!dx/\n"},
    {"": "a/**/b\n"},
    {"": "a/*\n"},
    {"": "*.xodr\n!keep.xodr\n"},
    {"": "*.xodr\n", "sub": "!a.xodr\n"},
    {"": "build/\n", "sub": "!build/\n"},
    {"sub": "/build\ndeep\n"},
    {"": "sub/*\n!sub/deep\n", "sub": "a.xodr\n"},
    {"": "keep.xodr\n", "d": "!keep.xodr\n", "d/e": "keep.xodr\n"},
    {"": "[abc].xodr\n\\!x\n  # not a comment\nd/e/\n"},
]


@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
@pytest.mark.parametrize("ignores", GIT_CASES)
def test_the_walk_lists_what_git_lists(tmp_path: Path, ignores: dict[str, str]) -> None:
    repo = make(tmp_path, dict.fromkeys(GIT_FILES, ""))
    subprocess.run(["git", "init", "-q", str(repo)], check=True, timeout=HANG_GUARD_SECONDS)
    for folder, text in ignores.items():
        (repo / folder / ".gitignore").write_text(text, "utf-8")
    listed = subprocess.run(
        ["git", "ls-files", "--others", "--exclude-standard", "*.xodr"],
        capture_output=True,
        text=True,
        check=True,
        cwd=repo,
        timeout=HANG_GUARD_SECONDS,
    )
    expected = sorted(f"{repo}/{name}" for name in listed.stdout.splitlines())
    assert sorted(shown(run("check", repo, "--show-files"))) == expected


# --- nothing to lint (item 11) -----------------------------------------------------------


def test_an_empty_folder_is_a_warning_exit_0_and_an_empty_report(tmp_path: Path) -> None:
    (tmp_path / "empty").mkdir()
    report = tmp_path / "report.json"
    result = run("check", tmp_path / "empty", "-f", "json", "-o", report)
    assert result.exit_code == 0
    assert result.stderr == f"xodrlint: warning: no .xodr files found under {tmp_path}/empty\n"
    document = json.loads(report.read_text("utf-8"))
    assert (document["files"], document["summary"]["files"]) == ([], 0)
    text = run("check", tmp_path / "empty")
    assert "All checks passed: 0 files" in text.stdout


def test_everything_excluded_or_ignored_is_the_same_warning(repo: Path) -> None:
    excluded = run("check", repo / "maps" / "sub", "--exclude", "b.xodr")
    named = run("check", repo / "maps" / "sub" / "scratch.xodr", repo / "build")
    assert excluded.exit_code == 0
    assert excluded.stderr == f"xodrlint: warning: no .xodr files found under {repo}/maps/sub\n"
    assert named.exit_code == 0  # a file named is linted: no warning
    assert "no .xodr files found" not in named.stderr
    (repo / "empty").mkdir()
    nothing = run("check", repo / "empty", repo / "maps" / "sub", "--exclude", "b.xodr", "-q")
    assert nothing.stderr.splitlines()[-1] == (
        f"xodrlint: warning: no .xodr files found under {repo}/empty {repo}/maps/sub"
    )


def test_a_missing_path_is_an_error_not_the_warning(tmp_path: Path) -> None:
    result = run("check", tmp_path / "gone")
    assert result.exit_code == 2
    assert result.stderr == f"xodrlint: {tmp_path}/gone: no such file or directory\n"


def test_a_nested_repository_follows_its_own_ignore_files(tmp_path: Path) -> None:
    # git: the outer repository's patterns stop where another repository starts
    outer = make(
        tmp_path / "outer",
        {
            ".git/info/exclude": "i.xodr\n",
            ".gitignore": "*.tmp.xodr\n",
            "i.xodr": "",
            "nested/.git/info/exclude": "",
            "nested/inner/i.xodr": "",
            "nested/x.tmp.xodr": "",
            "nested/.gitignore": "own.xodr\n",
            "nested/own.xodr": "",
        },
    )
    listed = shown(run("check", outer, "--show-files"))
    assert listed == [f"{outer}/nested/inner/i.xodr", f"{outer}/nested/x.tmp.xodr"]
    assert shown(run("check", outer / "nested", "--show-files")) == listed
