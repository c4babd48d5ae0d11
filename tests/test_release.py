"""The release: the package data pyproject.toml ships, the checks of the built files
(tests/distributions.py, which .ci/run runs on the real build), and docs/releasing.md
agreeing with .ci/run and the README."""

from __future__ import annotations

import hashlib
import io
import re
import tarfile
import tomllib
import zipfile
from collections.abc import Iterable
from pathlib import Path

from .conftest import REPO
from .distributions import (
    check,
    license_files,
    main,
    project_name,
    sdist_problems,
    source_version,
    tracked_files,
    wheel_problems,
)

PACKAGE_DIR = REPO / "src" / "xodrlint"
#: Data files the package cannot work without: its own schemas, the map page, typing.
ESSENTIAL_DATA = (
    "xodrlint/py.typed",
    "xodrlint/validation/builtin/railroad-1.7.xsd",
    "xodrlint/mapview/map.js",
)
TRACKED = tracked_files()
PACKAGE_FILES = sorted(p.removeprefix("src/") for p in TRACKED if p.startswith("src/xodrlint/"))
LICENSES = license_files()
#: MD5 of the Apache License 2.0 as apache.org publishes it (LICENSE-2.0.txt), the text
#: Debian ships as /usr/share/common-licenses/Apache-2.0.
APACHE_2_MD5 = "3b83ef96387f14655fc854ddc3c6bd57"


def _metadata(licenses: Iterable[str]) -> bytes:
    lines = ["Metadata-Version: 2.4", "Name: xodrlint", *(f"License-File: {p}" for p in licenses)]
    return "\n".join([*lines, "", ""]).encode("utf-8")


def _wheel(
    path: Path,
    names: Iterable[str],
    version: str = "9.9.9",
    licenses: dict[str, bytes] = LICENSES,
    declared: Iterable[str] | None = None,
) -> Path:
    info = f"xodrlint-{version}.dist-info/"
    with zipfile.ZipFile(path, "w") as archive:
        for name in names:
            archive.writestr(name, "")
        archive.writestr(f"{info}METADATA", _metadata(licenses if declared is None else declared))
        for name, text in licenses.items():
            archive.writestr(f"{info}licenses/{name}", text)
    return path


def _sdist(
    path: Path,
    names: Iterable[str],
    version: str = "9.9.9",
    licenses: dict[str, bytes] = LICENSES,
) -> Path:
    def add(archive: tarfile.TarFile, name: str, data: bytes) -> None:
        member = tarfile.TarInfo(f"xodrlint-{version}/{name}")
        member.size = len(data)
        archive.addfile(member, io.BytesIO(data))

    with tarfile.open(path, "w:gz") as archive:
        for name in names:
            add(archive, name, licenses.get(name, b""))
        for name, text in licenses.items():
            if name not in names:
                add(archive, name, text)
        add(archive, "PKG-INFO", _metadata(licenses))
    return path


def test_package_data_globs_ship_every_data_file_of_the_package() -> None:
    with (REPO / "pyproject.toml").open("rb") as handle:
        globs = tomllib.load(handle)["tool"]["setuptools"]["package-data"]["xodrlint"]
    shipped = {
        f"xodrlint/{path.relative_to(PACKAGE_DIR).as_posix()}"
        for pattern in globs
        for path in PACKAGE_DIR.glob(pattern)
    }
    data = {name for name in PACKAGE_FILES if not name.endswith(".py")}
    assert set(ESSENTIAL_DATA) <= data
    assert sorted(data - shipped) == [], "add a glob to [tool.setuptools.package-data]"


def test_a_wheel_without_package_data_or_with_a_stale_file_is_caught(tmp_path: Path) -> None:
    complete = _wheel(tmp_path / "complete.whl", PACKAGE_FILES)
    assert wheel_problems(complete, TRACKED, "xodrlint", "9.9.9") == []
    kept = [name for name in PACKAGE_FILES if name not in ESSENTIAL_DATA]
    broken = _wheel(tmp_path / "broken.whl", [*kept, "xodrlint/removed_module.py"])
    assert wheel_problems(broken, TRACKED, "xodrlint", "9.9.9") == [
        *(f"broken.whl: lacks {name}" for name in sorted(ESSENTIAL_DATA)),
        "broken.whl: holds xodrlint/removed_module.py, no file of the package",
    ]


def test_an_sdist_without_the_files_of_the_repository_is_caught(tmp_path: Path) -> None:
    complete = _sdist(tmp_path / "complete.tar.gz", TRACKED)
    assert sdist_problems(complete, TRACKED, "xodrlint", "9.9.9") == []
    left_out = {"tests/conftest.py", "rules/PT002/invalid_one_sided.xodr", "README.md"}
    assert left_out <= set(TRACKED)
    partial = _sdist(tmp_path / "partial.tar.gz", [p for p in TRACKED if p not in left_out])
    assert sdist_problems(partial, TRACKED, "xodrlint", "9.9.9") == [
        f"partial.tar.gz: lacks {name}" for name in sorted(left_out)
    ]


def test_the_licence_is_the_apache_license_2_0_that_pyproject_declares() -> None:
    with (REPO / "pyproject.toml").open("rb") as handle:
        project = tomllib.load(handle)["project"]
    assert project["license"] == "Apache-2.0"
    assert list(LICENSES) == ["LICENSE"] == project["license-files"]
    assert "LICENSE" in TRACKED
    assert hashlib.md5(LICENSES["LICENSE"], usedforsecurity=False).hexdigest() == APACHE_2_MD5


def test_a_wheel_without_the_licence_is_caught(tmp_path: Path) -> None:
    assert (
        wheel_problems(_wheel(tmp_path / "a.whl", PACKAGE_FILES), TRACKED, "xodrlint", "9.9.9")
        == []
    )
    info = "xodrlint-9.9.9.dist-info/"
    bare = _wheel(tmp_path / "bare.whl", PACKAGE_FILES, licenses={})
    assert wheel_problems(bare, TRACKED, "xodrlint", "9.9.9") == [
        f"bare.whl: lacks the licence file {info}licenses/LICENSE",
        "bare.whl: its metadata declares no License-File: LICENSE",
    ]
    other = _wheel(tmp_path / "other.whl", PACKAGE_FILES, licenses={"LICENSE": b"MIT"})
    assert wheel_problems(other, TRACKED, "xodrlint", "9.9.9") == [
        f"other.whl: {info}licenses/LICENSE is not the repository's LICENSE"
    ]
    undeclared = _wheel(tmp_path / "undeclared.whl", PACKAGE_FILES, declared=[])
    assert wheel_problems(undeclared, TRACKED, "xodrlint", "9.9.9") == [
        "undeclared.whl: its metadata declares no License-File: LICENSE"
    ]


def test_an_sdist_without_the_licence_is_caught(tmp_path: Path) -> None:
    assert (
        sdist_problems(_sdist(tmp_path / "a.tar.gz", TRACKED), TRACKED, "xodrlint", "9.9.9") == []
    )
    others = [name for name in TRACKED if name not in LICENSES]
    bare = _sdist(tmp_path / "bare.tar.gz", others, licenses={})
    assert sdist_problems(bare, TRACKED, "xodrlint", "9.9.9") == [
        "bare.tar.gz: lacks LICENSE",
        "bare.tar.gz: lacks the licence file LICENSE",
        "bare.tar.gz: its metadata declares no License-File: LICENSE",
    ]
    assert sdist_problems(bare, others, "xodrlint", "9.9.9", licenses={}) == [
        "pyproject.toml: license-files names no file of the repository"
    ]


def test_dist_holds_the_two_files_of_this_version_and_nothing_else(tmp_path: Path) -> None:
    version = source_version()
    dist = tmp_path / "dist"
    dist.mkdir()
    assert main([str(dist)]) == 1
    assert check(dist) == [
        f"{dist}/xodrlint-{version}-py3-none-any.whl: not built",
        f"{dist}/xodrlint-{version}.tar.gz: not built",
    ]
    _wheel(dist / f"xodrlint-{version}-py3-none-any.whl", PACKAGE_FILES, version)
    _sdist(dist / f"xodrlint-{version}.tar.gz", TRACKED, version)
    assert check(dist) == []
    assert main([str(dist)]) == 0
    (dist / "xodrlint-0.0.1.tar.gz").write_bytes(b"")  # an earlier build: twine would upload it
    assert check(dist) == [f"{dist}/xodrlint-0.0.1.tar.gz: not of this build"]
    assert main([str(tmp_path / "nothing")]) == 2


def test_the_version_is_written_once() -> None:
    with (REPO / "pyproject.toml").open("rb") as handle:
        config = tomllib.load(handle)
    assert "version" not in config["project"] and "version" in config["project"]["dynamic"]
    assert config["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "xodrlint.__version__"}
    from xodrlint import __version__

    assert source_version() == __version__
    assert project_name() == config["project"]["name"]


def _blocks(text: str, language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", text, flags=re.DOTALL)


def test_releasing_builds_and_checks_as_ci_does() -> None:
    releasing = (REPO / "docs" / "releasing.md").read_text("utf-8")
    build_and_check = releasing.split("## 2. Build and check", 1)[1]
    commands = _blocks(build_and_check, "sh")[0].splitlines()
    ci = (REPO / ".ci" / "run").read_text("utf-8").splitlines()
    assert [command for command in commands if command not in ci] == []
    assert any("twine check --strict" in command for command in commands)
    for step in ("git tag -a vX.Y.Z", "twine upload", "CHANGELOG.md", "__version__"):
        assert step in releasing, step


def _readme_set_up() -> list[str]:
    """The README's set-up commands from a clone (its "Set-up" section, subsections
    included): the shell blocks that make the ``.venv`` the suite runs in."""
    readme = (REPO / "README.md").read_text("utf-8")
    section = readme.split("\n## Set-up\n", 1)[1].split("\n## ", 1)[0]
    blocks = [block.strip() for block in _blocks(section, "sh")]
    return [block for block in blocks if block.startswith("python3 -m venv .venv ")]


def _ci_commands() -> list[str]:
    """.ci/run's lines that run something, in order: no comments, no blank lines, a line
    continued with a backslash joined to the next."""
    text = (REPO / ".ci" / "run").read_text("utf-8").replace("\\\n", "")
    return [
        line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")
    ]


def test_ci_runs_the_readme_set_up_commands_as_written_before_anything_else() -> None:
    example, tests = _readme_set_up()
    assert "pip install . " in example and "xodrlint check examples/" in example
    assert "pip install -e '.[dev]' " in tests
    assert tests.endswith(" -m pytest -q -p no:cacheprovider")
    # the shell's set-up, then the two commands verbatim: no pip, no upgrade before them;
    # `|| exit` ends the run where a command before an `&&` fails (set -e does not)
    assert _ci_commands()[:4] == [
        "set -euo pipefail",
        'cd "$(dirname "$0")/.."',
        f"{example} || exit",
        f"{tests} || exit",
    ]


def test_ci_runs_the_whole_suite_once() -> None:
    """The README's test command runs the suite; the other pytest runs of .ci/run name
    their tests (those whose prerequisites come later) or run in the example pack."""
    runs = [line for line in _ci_commands() if " -m pytest " in line or line.endswith(" -m pytest")]
    whole = [line for line in runs if re.search(r"-m pytest -q -p no:cacheprovider( \|\||$)", line)]
    assert whole == [f"{_readme_set_up()[1]} || exit"]
    for line in runs:
        assert line in whole or "tests/" in line or "cd examples/rulepack" in line, line


def test_the_lowest_environment_pins_each_direct_floor() -> None:
    from tests.lowest import constraints, floors

    assert list(
        floors(
            [
                "typer>=0.19,<0.29",
                "dask[distributed]>=2024.1",
                "dask[distributed,dataframe]>=2024.7",
                "xodrlint[test]",
                "free",
                "scipy >= 1.11.1 ; python_version < '3.14'",
            ],
            "xodrlint",
        )
    ) == ["dask==2024.7", "scipy==1.11.1", "typer==0.19"]
    pinned = dict(line.split("==") for line in constraints(["test"]))
    # the package's own floors and the test extra's, each once
    assert {"typer", "lxml", "xmlschema", "pytest", "moto", "click"} <= pinned.keys()
    assert "ruff" not in pinned  # the dev extra is not asked for
    assert "python -m tests.lowest test" in (REPO / ".ci" / "run").read_text()
