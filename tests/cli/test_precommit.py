"""The published pre-commit hook, run by the real pre-commit against a throwaway repo."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml  # type: ignore[import-untyped, unused-ignore]

from tests.conftest import REPO
from xodrlint.cli.check.notes import FULL_VALIDATION_NOTE

PRE_COMMIT = Path(sys.executable).parent / "pre-commit"
BAD = tuple(f"bad{n}.xodr" for n in range(8))


@pytest.mark.skipif(not PRE_COMMIT.exists(), reason="pre-commit is not installed")
@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
@pytest.mark.skipif(not (REPO / ".git").exists(), reason="not a git checkout")
def test_hook_passes_a_good_map_and_fails_a_bad_one(tmp_path: Path) -> None:
    maps = tmp_path / "maps"
    maps.mkdir()
    shutil.copy(REPO / "examples" / "clean.xodr", maps / "Good.XODR")
    for name in BAD:
        shutil.copy(REPO / "examples" / "broken.xodr", maps / name)
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
    # Eight maps: pre-commit would split them over one xodrlint per core unless the hook
    # is serial, and each run would print its own note.
    bad = hook(*BAD)
    assert bad.returncode == 1, bad.stdout + bad.stderr
    assert "Failed" in bad.stdout
    lines = bad.stdout.splitlines()
    for name in BAD:
        assert f"{name}:25:7: XS006 [error]" in bad.stdout
    # --quiet keeps the note that only railroad elements were validated, once; no summary
    assert lines.count(f"xodrlint: note: {FULL_VALIDATION_NOTE}") == 1, bad.stdout
    assert not [line for line in lines if line.startswith(("Found ", "All checks passed"))]


def test_hook_is_serial_because_xodrlint_runs_its_own_workers() -> None:
    (hook,) = yaml.safe_load((REPO / ".pre-commit-hooks.yaml").read_text("utf-8"))
    assert hook["id"] == "xodrlint"
    assert hook["require_serial"] is True
    assert hook["entry"] == "xodrlint check --quiet"


@pytest.mark.skipif(not PRE_COMMIT.exists(), reason="pre-commit is not installed")
@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
@pytest.mark.skipif(not (REPO / ".git").exists(), reason="not a git checkout")
def test_documented_snippet_is_pinned_by_autoupdate(tmp_path: Path) -> None:
    # docs/ci.md: paste the snippet, run `pre-commit autoupdate`; pre-commit wants a tag
    # or a SHA. Here against a clone of this repository instead of GitHub (no network).
    docs = (REPO / "docs" / "ci.md").read_text("utf-8")
    snippet = docs.split("## pre-commit", 1)[1].split("```yaml\n", 1)[1].split("```", 1)[0]
    repository = yaml.safe_load(snippet)["repos"][0]["repo"]
    assert f"pre-commit autoupdate --repo {repository}" in docs
    upstream, project = tmp_path / "upstream", tmp_path / "project"
    env = {**os.environ, "PRE_COMMIT_HOME": str(tmp_path / "cache")}

    def run(*command: str, cwd: Path = project) -> str:
        done = subprocess.run(
            command, cwd=cwd, env=env, capture_output=True, text=True, check=False
        )
        assert done.returncode == 0, done.stdout + done.stderr
        return done.stdout.strip()

    project.mkdir()
    run("git", "clone", "-q", str(REPO), str(upstream), cwd=tmp_path)
    run("git", "init", "-q")
    config = project / ".pre-commit-config.yaml"
    config.write_text(snippet.replace(repository, str(upstream)), "utf-8")
    run(str(PRE_COMMIT), "autoupdate", "--repo", str(upstream))
    (pinned,) = yaml.safe_load(config.read_text("utf-8"))["repos"]
    # the newest release tag, or while there is none the newest commit's SHA
    described = subprocess.run(
        ["git", "describe", "--tags", "--abbrev=0", "HEAD"],
        cwd=upstream,
        capture_output=True,
        text=True,
        check=False,
    )
    head = run("git", "rev-parse", "HEAD", cwd=upstream)
    assert pinned["rev"] == (described.stdout.strip() if described.returncode == 0 else head)
    assert [hook["id"] for hook in pinned["hooks"]] == ["xodrlint"]
    run(str(PRE_COMMIT), "validate-config", str(config))
