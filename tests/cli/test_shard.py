"""``--shard K/N``: stable, disjoint parts that together are the inputs, and the CI matrix
of docs/distributed.md, run part by part."""

from __future__ import annotations

import hashlib
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
from itertools import product
from pathlib import Path

import pytest
import yaml  # type: ignore[import-untyped, unused-ignore]
from typer.testing import CliRunner

from tests.conftest import REPO
from xodrlint.cli import app
from xodrlint.cli.check.inputs import Shard, parse_shard, shard_of

from .test_cli import BROKEN, cli

DISTRIBUTED = REPO / "docs" / "distributed.md"


def _files(*args: str | Path, code: int = 0) -> list[str]:
    return cli("check", "--show-files", *args, code=code).stdout.splitlines()


def _maps(folder: Path, count: int) -> Path:
    for index in range(count):
        target = folder / f"line-{index % 7}" / f"map {index:03}.xodr"
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(BROKEN, target)
    return folder


@pytest.mark.parametrize("parts", [1, 2, 3, 7])
def test_parts_are_disjoint_and_together_are_the_inputs(tmp_path: Path, parts: int) -> None:
    maps = _maps(tmp_path / "maps", 60)
    everything = _files(maps)
    shards = [_files(maps, "--shard", f"{k}/{parts}") for k in range(1, parts + 1)]
    merged = sorted(name for shard in shards for name in shard)
    assert merged == sorted(everything)  # each file in exactly one part
    for shard in shards:  # each part in the inputs' order
        assert shard == [name for name in everything if name in shard]
    if parts > 1:
        assert all(shards)  # 60 files: no part empty (a part by chance gets ~60/N)


def test_a_files_part_does_not_depend_on_the_other_files(tmp_path: Path) -> None:
    maps = _maps(tmp_path / "maps", 30)
    before = set(_files(maps, "--shard", "2/3"))
    _maps(tmp_path / "maps" / "new", 30)  # the collection grows
    after = set(_files(maps, "--shard", "2/3"))
    assert {name for name in after if "/new/" not in name} == before


def test_parts_are_the_same_in_every_process_and_on_every_machine() -> None:
    # pinned values: a change of the hash would move every file of every CI matrix
    names = ["maps/a.xodr", "maps/b.xodr", "rules/PT001/valid_partner.xodr", "-", "ü/ß.xodr"]
    assert [shard_of(name, 4) for name in names] == [1, 2, 4, 2, 2]
    for name, parts in product(names, (1, 2, 3, 4, 1000)):  # as docs/distributed.md says
        digest = hashlib.sha256(name.encode("utf-8")).digest()
        assert shard_of(name, parts) == int.from_bytes(digest[:8], "big") % parts + 1
    program = f"from xodrlint.cli.check.inputs import shard_of; print([shard_of(n, 4) for n in {names!r}])"
    for seed in ("0", "1", "random"):  # Python's own hash() would differ between these
        done = subprocess.run(
            [sys.executable, "-c", program],
            env={**os.environ, "PYTHONHASHSEED": seed},
            capture_output=True,
            text=True,
            check=True,
        )
        assert done.stdout.strip() == "[1, 2, 4, 2, 2]"


def test_shard_values() -> None:
    assert parse_shard("1/4") == Shard(1, 4)
    assert parse_shard(" 4/4 ") == Shard(4, 4)
    assert parse_shard("1/1") == Shard(1, 1)
    assert str(Shard(2, 4)) == "2/4"


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("0/3", "--shard 0/3: K must be from 1 to 3"),
        ("4/3", "--shard 4/3: K must be from 1 to 3"),
        ("1/0", "--shard 1/0: N must be at least 1"),
        ("x", "--shard x: expected K/N, the K-th of N parts (e.g. 2/4)"),
        ("3", "--shard 3: expected K/N, the K-th of N parts (e.g. 2/4)"),
        ("-1/3", "--shard -1/3: expected K/N, the K-th of N parts (e.g. 2/4)"),
        ("1/3/4", "--shard 1/3/4: expected K/N, the K-th of N parts (e.g. 2/4)"),
        ("", "--shard : expected K/N, the K-th of N parts (e.g. 2/4)"),
        ("1/\n3", "--shard 1/\\x0a3: expected K/N, the K-th of N parts (e.g. 2/4)"),
    ],
)
def test_a_shard_that_names_no_part_is_one_line_and_exit_2(value: str, message: str) -> None:
    result = cli("check", "--shard", value, BROKEN, code=2)
    assert (result.stdout, result.stderr) == ("", f"xodrlint: {message}\n")


def test_only_the_shards_files_are_linted_and_reported(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    maps = _maps(Path("maps"), 12)
    missing = "maps/missing.xodr"
    owner = shard_of(missing, 3)  # the part that reports the path it cannot read
    reported: list[str] = []
    for k in (1, 2, 3):
        code = 2 if k == owner else 0
        shown = _files(maps, missing, "--shard", f"{k}/3", code=code)
        result = cli("check", "-f", "json", maps, missing, "--shard", f"{k}/3", code=code or 1)
        files = [entry["path"] for entry in json.loads(result.stdout)["files"]]
        assert files == shown + ([missing] if k == owner else [])
        reported += files
    assert sorted(reported) == sorted([*_files(maps), missing])


def test_standard_input_is_placed_by_its_reported_name(tmp_path: Path) -> None:
    part = shard_of("maps/from-stdin.xodr", 2)
    for k in (1, 2):
        args = ("check", "-f", "jsonl", "-", "--stdin-filename", "maps/from-stdin.xodr")
        result = cli(
            *args, "--shard", f"{k}/2", code=1 if k == part else 0, stdin=BROKEN.read_bytes()
        )
        assert bool(result.stdout) == (k == part)


def test_a_part_that_holds_none_of_the_inputs_says_so(tmp_path: Path) -> None:
    target = tmp_path / "only.xodr"
    shutil.copyfile(BROKEN, target)
    empty = 1 if shard_of(str(target), 2) == 2 else 2
    result = cli("check", target, "--shard", f"{empty}/2", code=0)
    assert result.stderr == f"xodrlint: warning: shard {empty}/2 holds none of the 1 input\n"


# docs/distributed.md: "## A CI matrix" ------------------------------------------------


def _section(title: str) -> str:
    text = DISTRIBUTED.read_text("utf-8")
    start = text.index(f"\n## {title}\n")
    end = text.find("\n## ", start + 1)
    return text[start : end if end != -1 else len(text)]


def _blocks(section: str, language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", section, flags=re.DOTALL)


def _run(command: str) -> list[str]:
    """Run ``xodrlint check ...`` as the command line would; returns the files it lints
    (the same command's ``--show-files``)."""
    args = shlex.split(command)
    assert args[:2] == ["xodrlint", "check"], command
    result = CliRunner().invoke(app, args[1:])
    assert result.exit_code in (0, 1), result.output
    assert "Traceback" not in result.output
    return _files(*args[2:])


def test_the_github_matrix_lints_every_map_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    workflow = yaml.safe_load(_blocks(_section("A CI matrix"), "yaml")[0])
    job = workflow["jobs"]["lint-maps"]
    parts = job["strategy"]["matrix"]["shard"]
    assert parts == [1, 2, 3, 4]
    commands = [step["run"] for step in job["steps"] if "xodrlint check" in step.get("run", "")]
    assert len(commands) == 2
    assert all("--shard ${{ matrix.shard }}/4" in command for command in commands)
    monkeypatch.chdir(tmp_path)
    everything = _files(_maps(Path("maps"), 40))
    for command in commands:
        linted = [
            name
            for part in parts
            for name in _run(command.replace("${{ matrix.shard }}", str(part)))
        ]
        assert sorted(linted) == sorted(everything)


def test_the_gitlab_job_and_the_show_files_command(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    section = _section("A CI matrix")
    job = yaml.safe_load(_blocks(section, "yaml")[1])["xodrlint"]
    [command] = [line for line in job["script"] if line.startswith("xodrlint check")]
    monkeypatch.chdir(tmp_path)
    everything = _files(_maps(Path("maps"), 20))
    total = str(job["parallel"])
    linted = []
    for index in range(1, job["parallel"] + 1):
        part = command.replace("$CI_NODE_INDEX", str(index)).replace("$CI_NODE_TOTAL", total)
        linted += _run(part)
    assert sorted(linted) == sorted(everything)
    [shown] = [line for block in _blocks(section, "sh") for line in block.splitlines()]
    listed = cli(*shlex.split(shown)[1:], code=0).stdout.splitlines()
    assert listed and listed == _run(command.replace("$CI_NODE_INDEX/$CI_NODE_TOTAL", "2/4"))
