"""The published pre-commit hook, run by the real pre-commit against a throwaway repo."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import REPO

PRE_COMMIT = Path(sys.executable).parent / "pre-commit"


@pytest.mark.skipif(not PRE_COMMIT.exists(), reason="pre-commit is not installed")
@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
@pytest.mark.skipif(not (REPO / ".git").exists(), reason="not a git checkout")
def test_hook_passes_a_good_map_and_fails_a_bad_one(tmp_path: Path) -> None:
    maps = tmp_path / "maps"
    maps.mkdir()
    shutil.copy(REPO / "examples" / "clean.xodr", maps / "Good.XODR")
    shutil.copy(REPO / "examples" / "broken.xodr", maps / "bad.xodr")
    (maps / "notes.txt").write_text("not a map\n", "utf-8")
    env = {
        **os.environ,
        "PRE_COMMIT_HOME": str(tmp_path / "cache"),
        "GIT_AUTHOR_NAME": "t",
        "GIT_AUTHOR_EMAIL": "t@example.invalid",
        "GIT_COMMITTER_NAME": "t",
        "GIT_COMMITTER_EMAIL": "t@example.invalid",
    }
    env.pop("XODRLINT_SCHEMA_PATH", None)

    def git(*args: str) -> None:
        subprocess.run(["git", *args], cwd=maps, env=env, check=True, capture_output=True)

    git("init", "-q")
    git("add", ".")

    def hook(*files: str) -> subprocess.CompletedProcess[str]:
        command = [str(PRE_COMMIT), "try-repo", str(REPO), "xodrlint", "--files", *files]
        return subprocess.run(
            command, cwd=maps, env=env, capture_output=True, text=True, timeout=600, check=False
        )

    good = hook("Good.XODR", "notes.txt")
    assert good.returncode == 0, good.stdout + good.stderr
    assert "xodrlint" in good.stdout and "Passed" in good.stdout
    bad = hook("bad.xodr")
    assert bad.returncode == 1, bad.stdout + bad.stderr
    assert "bad.xodr:25: XS006 [error]" in bad.stdout
    assert "Failed" in bad.stdout
