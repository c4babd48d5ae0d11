"""Every `xodrlint check` command in docs/ci.md runs, against the example maps; every
install command and pre-commit snippet users read names the project, its repository and a
revision that exist (nothing on PyPI before a release), without going on the network."""

from __future__ import annotations

import re
import shlex
import tomllib
from pathlib import Path

import pytest
import yaml  # type: ignore[import-untyped, unused-ignore]
from packaging.requirements import Requirement
from typer.testing import CliRunner

from tests.conftest import REPO
from xodrlint.cli import app

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


# The install instructions ------------------------------------------------------------

with (REPO / "pyproject.toml").open("rb") as _handle:
    PROJECT = tomllib.load(_handle)["project"]
NAME: str = PROJECT["name"]
REPOSITORY: str = PROJECT["urls"]["Homepage"]
#: Where users read how to install xodrlint: its commands must work today.
INSTRUCTIONS = ("README.md", "docs/ci.md")
#: pip options followed by a value, which is no requirement
PIP_VALUED = {"-e", "--editable", "-r", "--requirement", "--index-url", "--extra-index-url"}


def _released() -> list[str]:
    """Versions CHANGELOG.md records as released (a heading with a version and a date)."""
    changelog = (REPO / "CHANGELOG.md").read_text("utf-8")
    return re.findall(r"^## (\d+\.\d+\.\d+) \(\d{4}-\d\d-\d\d\)$", changelog, flags=re.MULTILINE)


def _code(name: str) -> str:
    return "".join(re.findall(r"```\w*\n(.*?)```", (REPO / name).read_text("utf-8"), re.DOTALL))


def _requirements(code: str) -> list[str]:
    """What each ``pip install`` in ``code`` asks for, options and their values left out."""
    found = []
    for command in re.findall(r"pip install ([^\n]*)", code):
        words = iter(shlex.split(command, comments=True))
        for word in words:
            if word in ("&&", "||", ";", "|"):
                break  # the next command
            if word in PIP_VALUED:
                next(words, None)
            elif not word.startswith("-"):
                found.append(word)
    return found


def test_install_commands_name_the_project_and_its_repository() -> None:
    released = _released()
    forms = {name: _requirements(_code(name)) for name in INSTRUCTIONS}
    from_repository = []
    for name, requirements in forms.items():
        for text in requirements:
            if text.startswith((".", "/")):  # a clone: README's set-up
                continue
            requirement = Requirement(text)
            if requirement.name != NAME:
                continue  # another tool (atheris, for fuzzing)
            if requirement.url is None:
                # the package index has it only after a release
                assert released, f"{name}: '{text}': xodrlint is not on PyPI yet"
                continue
            pattern = rf"git\+{re.escape(REPOSITORY)}@|{re.escape(REPOSITORY)}/archive/"
            assert re.match(pattern, requirement.url), f"{name}: {text}: not {REPOSITORY}"
            from_repository.append(text)
    assert from_repository, "no install command from the repository"
    releasing = (REPO / "docs" / "releasing.md").read_text("utf-8")
    assert f"pip install {NAME}==X.Y.Z" in (REPO / "docs" / "ci.md").read_text("utf-8")
    assert f"{NAME}==X.Y.Z" in releasing and f"dist/{NAME}-X.Y.Z-py3-none-any.whl" in releasing


def test_pre_commit_snippets_name_the_hook_at_a_rev_that_exists() -> None:
    hooks = {hook["id"] for hook in yaml.safe_load((REPO / ".pre-commit-hooks.yaml").read_text())}
    tags = [f"v{version}" for version in _released()]
    # docs/releasing.md tags vX.Y.Z, the form the docs tell users to write after a release
    assert "git tag -a vX.Y.Z" in (REPO / "docs" / "releasing.md").read_text("utf-8")
    for name in INSTRUCTIONS:
        snippets = [
            config
            for block in re.findall(
                r"```yaml\n(.*?)```", (REPO / name).read_text("utf-8"), re.DOTALL
            )
            if "repos:" in block
            for config in [yaml.safe_load(block)]
        ]
        assert snippets, f"{name} shows no pre-commit configuration"
        for config in snippets:
            (repo,) = config["repos"]
            assert repo["repo"] == REPOSITORY
            assert {hook["id"] for hook in repo["hooks"]} <= hooks
            # a branch works only until `pre-commit autoupdate` pins it, which the text says
            assert repo["rev"] in ["main", *tags], f"{name}: rev {repo['rev']} does not exist"
            assert repo["rev"] != "main" or "pre-commit autoupdate" in (REPO / name).read_text()
