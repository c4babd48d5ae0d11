"""Configuration files: discovery, validation, precedence, and ``xodrlint config``."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from collections.abc import Iterator
from pathlib import Path

import pytest
from typer.testing import CliRunner, Result

from tests.conftest import REPO
from xodrlint.api import default_registry
from xodrlint.cli import app
from xodrlint.config.discovery import find_config
from xodrlint.config.settings import ConfigError, read_config
from xodrlint.findings import Hit
from xodrlint.inputs.globs import matches

BROKEN = REPO / "examples" / "broken.xodr"
CLEAN = REPO / "examples" / "clean.xodr"


def run(*args: str | Path, cwd: Path | None = None) -> Result:
    return CliRunner().invoke(app, [str(a) for a in args])


def _project(tmp_path: Path, config_name: str, text: str) -> Path:
    (tmp_path / "maps" / "old").mkdir(parents=True)
    (tmp_path / "maps" / "broken.xodr").write_bytes(BROKEN.read_bytes())
    (tmp_path / "maps" / "old" / "legacy.xodr").write_bytes(BROKEN.read_bytes())
    (tmp_path / config_name).write_text(textwrap.dedent(text), "utf-8")
    return tmp_path


def _codes(result: Result) -> list[str]:
    return [f["code"] for f in json.loads(result.stdout)["findings"]]


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("pyproject.toml", '[project]\nname = "x"\n[tool.xodrlint]\nselect = ["XS"]\n'),
        ("xodrlint.toml", 'select = ["XS"]\n'),
        (".xodrlint.toml", 'select = ["XS"]\n'),
    ],
)
def test_config_is_found_by_walking_up(tmp_path: Path, name: str, text: str) -> None:
    project = _project(tmp_path, name, text)
    found = find_config(project / "maps" / "old" / "legacy.xodr")
    assert found is not None and found.path == project / name
    result = run("check", "-f", "json", project / "maps" / "broken.xodr")
    assert set(_codes(result)) == {"XS006"}


def test_pyproject_without_table_is_skipped(tmp_path: Path) -> None:
    (tmp_path / "pyproject.toml").write_text('[project]\nname = "x"\n', "utf-8")
    (tmp_path / "sub").mkdir()
    assert find_config(tmp_path / "sub") is None or find_config(tmp_path / "sub").path != (  # type: ignore[union-attr]
        tmp_path / "pyproject.toml"
    )


def test_dotted_name_wins_over_plain_and_pyproject(tmp_path: Path) -> None:
    for name in (".xodrlint.toml", "xodrlint.toml"):
        (tmp_path / name).write_text('select = ["XS"]\n', "utf-8")
    (tmp_path / "pyproject.toml").write_text('[tool.xodrlint]\nselect = ["SW"]\n', "utf-8")
    found = find_config(tmp_path)
    assert found is not None and found.path.name == ".xodrlint.toml"


def test_command_line_overrides_the_file(tmp_path: Path) -> None:
    project = _project(tmp_path, "xodrlint.toml", 'select = ["XS"]\nfail-on = "error"\n')
    result = run("check", "-f", "json", "--select", "RL", project / "maps" / "broken.xodr")
    assert _codes(result) == ["RL003"]
    assert result.exit_code == 1


def test_every_key(tmp_path: Path) -> None:
    project = _project(
        tmp_path,
        "xodrlint.toml",
        """
        select = ["XS", "SW"]
        extend-select = ["RL003"]
        ignore = ["SW006"]
        exclude = ["old/"]
        fail-on = "error"
        output-format = "json"
        rail-min-width = 0.9
        refline-tolerance = 0.1
        warn-unused-suppressions = true

        [severity]
        XS006 = "warning"

        [per-file-ignores]
        "maps/b*.xodr" = ["XS006"]
        """,
    )
    result = run("check", project / "maps")
    document = json.loads(result.stdout)
    assert [f["path"] for f in document["files"]] == [f"{project}/maps/broken.xodr"]
    # XS006 withheld by per-file-ignores, SW006 ignored, RL003 satisfied by 0.9 m
    assert document["findings"] == []
    assert result.exit_code == 0

    shown = run("config", project / "maps", "-f", "json")
    settings = json.loads(shown.stdout)["settings"]
    assert settings["rail-min-width"] == {"value": 0.9, "source": str(project / "xodrlint.toml")}
    assert settings["severity"]["value"] == {"XS006": "warning"}
    assert settings["output-format"]["source"] == str(project / "xodrlint.toml")


def test_severity_override_changes_the_exit_code(tmp_path: Path) -> None:
    project = _project(
        tmp_path,
        "xodrlint.toml",
        'select = ["RL003"]\nfail-on = "error"\n[severity]\nRL003 = "warning"\n',
    )
    result = run("check", "-f", "json", project / "maps" / "broken.xodr")
    assert [f["severity"] for f in json.loads(result.stdout)["findings"]] == ["warning"]
    assert result.exit_code == 0


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('selct = ["XS"]\n', "unknown key 'selct'"),
        ('select = "XS006"\nfail-on = "fatal"\n', "'fail-on' must be one of"),
        ("rail-min-width = 'wide'\n", "'rail-min-width' must be a finite number"),
        ("rail-min-width = -1\n", "'rail-min-width' must be a finite number >= 0, got -1"),
        ("[severity]\nXX999 = 'error'\n", "'severity' names no rule 'XX999'"),
        ("[per-file-ignores]\n'*.xodr' = 3\n", "'per-file-ignores' must be"),
        ("select = [\n", "not valid TOML"),
        ('select = ["NOPE"]\n', "'NOPE' matches no rule"),
        ("[per-file-ignores]\n'*.xodr' = ['NOPE']\n", "'NOPE' matches no rule"),
    ],
)
def test_bad_config_is_exit_2_naming_the_file_and_key(
    tmp_path: Path, text: str, message: str
) -> None:
    project = _project(tmp_path, "xodrlint.toml", text)
    result = run("check", project / "maps" / "broken.xodr")
    assert result.exit_code == 2, result.output
    assert message in result.stderr
    if "matches no rule" not in message:
        assert str(project / "xodrlint.toml") in result.stderr
    assert result.stdout == ""


def test_explicit_config_and_isolated(tmp_path: Path) -> None:
    project = _project(tmp_path, "xodrlint.toml", 'select = ["RL"]\n')
    other = tmp_path / "other.toml"
    other.write_text('select = ["ST"]\n', "utf-8")
    target = project / "maps" / "broken.xodr"
    assert _codes(run("check", "-f", "json", target)) == ["RL003"]
    assert _codes(run("check", "-f", "json", "--config", other, target)) == ["ST004"]
    assert len(_codes(run("check", "-f", "json", "--isolated", target))) == 6
    missing = run("check", "--config", tmp_path / "nope.toml", target)
    assert missing.exit_code == 2 and "nope.toml: cannot read" in missing.stderr


@pytest.mark.parametrize(
    "text",
    [
        '[tool.xodrlint]\nselect = ["ST"]\n',
        '[project]\nname = "maps"\n[tool.ruff]\nline-length = 99\n[tool.xodrlint]\nselect = ["ST"]\n',
        'select = ["ST"]\n',
    ],
    ids=["tool-table", "pyproject-like", "top-level"],
)
def test_an_explicit_config_of_any_name_takes_either_layout(tmp_path: Path, text: str) -> None:
    project = _project(tmp_path, "ci.toml", text)
    target = project / "maps" / "broken.xodr"
    assert _codes(run("check", "-f", "json", "--config", project / "ci.toml", target)) == ["ST004"]
    shown = json.loads(run("config", "-f", "json", "--config", project / "ci.toml").stdout)
    assert shown["settings"]["select"] == {"value": ["ST"], "source": str(project / "ci.toml")}


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            'select = ["RL"]\n[tool.xodrlint]\nselect = ["ST"]\n',
            "has settings both in [tool.xodrlint] and at its top level ('select')",
        ),
        (
            "rail-min-width = 1.0\n[tool.xodrlint]\n",
            "has settings both in [tool.xodrlint] and at its top level ('rail-min-width')",
        ),
        ("[tool.xodrlint]\ncolour = 1\n", "[tool.xodrlint]: unknown key 'colour'"),
        ("[tool]\nxodrlint = 3\n", "[tool.xodrlint] must be a table"),
    ],
)
def test_a_config_in_both_layouts_or_a_bad_table_names_the_file(
    tmp_path: Path, text: str, message: str
) -> None:
    project = _project(tmp_path, "ci.toml", text)
    result = run("check", "--config", project / "ci.toml", project / "maps" / "broken.xodr")
    assert result.exit_code == 2
    assert result.stderr.startswith(f"xodrlint: {project / 'ci.toml'}")
    assert message in result.stderr and result.stderr.count("\n") == 1


def test_config_command_shows_defaults_and_sources(tmp_path: Path) -> None:
    project = _project(tmp_path, "pyproject.toml", '[tool.xodrlint]\nignore = ["SW006"]\n')
    out = run("config", project).stdout
    assert f"config file: {project / 'pyproject.toml'}" in out
    assert 'ignore                    ["SW006"]' in out
    assert f"# {project / 'pyproject.toml'}" in out
    assert "# default" in out


def _with_a_plugin_option(monkeypatch: pytest.MonkeyPatch) -> None:
    """A plugin rule declaring an option of its own, installed for ``config``."""
    from xodrlint.findings import RuleOption, Severity
    from xodrlint.rules import RailNetwork, rule
    from xodrlint.rules.registry import Registry

    @rule(
        code="AC002",
        name="gauge-check",
        uid="acme:xodr:1.0.0:gauge",
        severity=Severity.INFO,
        options=[RuleOption("acme-gauge", 1.668, "the Iberian gauge")],
    )
    def gauge(network: RailNetwork) -> Iterator[Hit]:
        yield from ()

    registry = Registry((*default_registry().rules, gauge))
    monkeypatch.setattr("xodrlint.cli.config.default_registry", lambda: registry)


def test_config_shows_every_rule_option_with_its_default(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _with_a_plugin_option(monkeypatch)
    project = _project(tmp_path, "xodrlint.toml", "rail-min-width = 1.0\n")
    settings = json.loads(run("config", "-f", "json", project).stdout)["settings"]
    assert settings["rail-min-width"] == {"value": 1.0, "source": str(project / "xodrlint.toml")}
    assert settings["refline-tolerance"] == {"value": 0.05, "source": "default"}
    assert settings["acme-gauge"] == {"value": 1.668, "source": "default"}
    text = run("config", project).stdout.splitlines()
    assert [line.split() for line in text if line.startswith(("refline-", "acme-"))] == [
        ["acme-gauge", "1.668", "#", "default"],
        ["refline-tolerance", "0.05", "#", "default"],
    ]


def test_schema_path_in_a_config_is_relative_to_the_file(tmp_path: Path) -> None:
    project = _project(tmp_path, "xodrlint.toml", 'schema = "schemas/core.xsd"\n')
    result = run("check", project / "maps" / "broken.xodr")
    assert result.exit_code == 2
    assert (
        f"schema {project / 'schemas' / 'core.xsd'} (from {project / 'xodrlint.toml'}): "
        "no such file or folder" in result.stderr
    )


@pytest.mark.parametrize(
    ("pattern", "path", "expected"),
    [
        ("*.xodr", "a/b/c.xodr", True),
        ("maps/*.xodr", "maps/x.xodr", True),
        ("maps/*.xodr", "maps/sub/x.xodr", False),
        ("maps/**/*.xodr", "maps/sub/deep/x.xodr", True),
        ("maps/**/*.xodr", "maps/x.xodr", True),
        ("old/", "old/x.xodr", True),
        ("old", "maps/old/x.xodr", True),
        ("x?.xodr", "x1.xodr", True),
        ("x?.xodr", "x10.xodr", False),
    ],
)
def test_globs(tmp_path: Path, pattern: str, path: str, expected: bool) -> None:
    assert matches(pattern, tmp_path / path, tmp_path) is expected


def test_read_config_errors_name_the_file(tmp_path: Path) -> None:
    path = tmp_path / "pyproject.toml"
    path.write_text("[tool]\nxodrlint = 3\n", "utf-8")
    with pytest.raises(ConfigError, match="must be a table"):
        read_config(path)


@pytest.mark.parametrize(
    ("pattern", "path", "expected"),
    [
        ("*a*a*a*a*a*a*a*a*c", "a" * 60 + ".xodr", False),
        ("*a*a*a*a*a*a*a*a*c", "a" * 60 + "c", True),
        ("**/**/**/**/x*x*x*x*x*y", "/".join(["x" * 30] * 40), False),
    ],
)
def test_an_exclude_pattern_never_backtracks_for_ever(
    tmp_path: Path, pattern: str, path: str, expected: bool
) -> None:
    # as a backtracking regular expression these took more than 100 s; a hang guard in a
    # child process, not a timing: the matcher's work is bounded by the sizes involved
    code = (
        "import sys; from xodrlint.config.settings import glob_matches; "
        "print(glob_matches(sys.argv[1], sys.argv[2]))"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, pattern, path],
        capture_output=True,
        text=True,
        check=True,
        timeout=30,
    )
    assert done.stdout.strip() == str(expected)


# -- issue 30, item 3: discovery trusts no folder above the repository or the home --------


def test_the_search_stops_at_the_repository_root(tmp_path: Path) -> None:
    (tmp_path / "xodrlint.toml").write_text('select = ["XS"]\n')  # above the checkout
    checkout = tmp_path / "work" / "repo"
    (checkout / ".git").mkdir(parents=True)
    (checkout / "maps").mkdir()
    assert find_config(checkout / "maps" / "x.xodr") is None
    (checkout / "xodrlint.toml").write_text('select = ["SW"]\n')
    found = find_config(checkout / "maps" / "x.xodr")
    assert found is not None and found.path == checkout / "xodrlint.toml"


def test_the_search_stops_at_the_users_home(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "xodrlint.toml").write_text('select = ["XS"]\n')  # above the home
    home = tmp_path / "home" / "me"
    (home / "maps").mkdir(parents=True)
    monkeypatch.setenv("HOME", str(home))
    assert find_config(home / "maps" / "x.xodr") is None
    (home / "xodrlint.toml").write_text('select = ["SW"]\n')
    found = find_config(home / "maps" / "x.xodr")
    assert found is not None and found.path == home / "xodrlint.toml"


def test_a_config_every_user_can_write_is_ignored_with_a_warning(tmp_path: Path) -> None:
    project = _project(tmp_path, "xodrlint.toml", 'select = ["XS"]\n')
    (project / "xodrlint.toml").chmod(0o666)
    skipped: list[str] = []
    assert find_config(project / "maps" / "broken.xodr", skipped) is None
    assert skipped == [
        f"ignoring {project / 'xodrlint.toml'}: every user of the machine can write it"
    ]
    result = run("check", "-f", "json", project / "maps" / "broken.xodr")
    assert set(_codes(result)) != {"XS006"}  # the defaults: every rule
    assert result.stderr.splitlines() == [f"xodrlint: warning: {skipped[0]}"]


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="needs root to chown")
def test_a_config_owned_by_another_user_is_ignored_and_the_search_goes_on(tmp_path: Path) -> None:
    project = _project(tmp_path, "xodrlint.toml", 'select = ["SW"]\n')
    planted = project / "maps" / "xodrlint.toml"
    planted.write_text('select = ["XS"]\n')
    os.chown(planted, 65534, 65534)  # nobody's
    skipped: list[str] = []
    found = find_config(project / "maps" / "broken.xodr", skipped)
    assert found is not None and found.path == project / "xodrlint.toml"
    assert skipped == [f"ignoring {planted}: it is owned by another user (uid 65534)"]


def test_an_explicit_config_is_the_users_choice(tmp_path: Path) -> None:
    project = _project(tmp_path, "xodrlint.toml", 'select = ["XS"]\n')
    (project / "xodrlint.toml").chmod(0o666)
    result = run("check", "-f", "json", "--config", project / "xodrlint.toml", project / "maps")
    assert set(_codes(result)) == {"XS006"} and result.stderr == ""


def test_the_editor_server_tells_why_it_ignores_a_config(tmp_path: Path) -> None:
    from xodrlint.server.folders import Folders

    project = _project(tmp_path, "xodrlint.toml", 'select = ["XS"]\n')
    (project / "xodrlint.toml").chmod(0o666)
    choice = Folders(default_registry()).linter_for(project / "maps" / "broken.xodr")
    assert choice.settings.config_file is None
    assert (
        choice.problem
        == f"ignoring {project / 'xodrlint.toml'}: every user of the machine can write it"
    )


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="needs root to chown")
def test_root_takes_the_config_of_a_checkout_another_user_owns(tmp_path: Path) -> None:
    # a container job as root over the runner's checkout (uid 1001): the repository's
    # own file, as its .git says
    checkout = tmp_path / "repo"
    (checkout / ".git").mkdir(parents=True)
    (checkout / "xodrlint.toml").write_text('select = ["XS"]\n')
    for path in (checkout / ".git", checkout / "xodrlint.toml"):
        os.chown(path, 1001, 1001)
    skipped: list[str] = []
    found = find_config(checkout / "x.xodr", skipped)
    assert found is not None and found.path == checkout / "xodrlint.toml" and not skipped


def test_a_distrusted_config_is_not_even_parsed(tmp_path: Path) -> None:
    project = _project(tmp_path, "xodrlint.toml", "select = [this is not TOML\n")
    (project / "xodrlint.toml").chmod(0o666)
    result = run("check", "-f", "json", project / "maps" / "broken.xodr")
    assert result.exit_code == 1, result.stderr  # linted with the defaults, not exit 2
    assert "every user of the machine can write it" in result.stderr
