"""The entry-point cache: used when the environment is unchanged, rebuilt when it is not."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from xodrlint.config import cache, plugins


def test_cache_is_written_then_used(tmp_path: Path) -> None:
    first = plugins.installed("xodrlint.rules")
    assert {p.name for p in first} >= {"document", "switches", "partners", "stations", "lanes"}
    cached = json.loads(cache.read(plugins.cache_path()) or b"")
    assert cached["entries"][0]["groups"]["xodrlint.rules"]
    # a process like the last one reads the cache and never imports importlib.metadata
    # (pytest's own sys.path differs from a plain interpreter's: run two of those)
    code = (
        "import sys; from xodrlint.config.plugins import installed; "
        "points = installed('xodrlint.rules'); "
        "print(len(points), 'importlib.metadata' in sys.modules)"
    )
    runs = [
        subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, check=True, env=os.environ
        ).stdout.split()
        for _ in range(2)
    ]
    assert runs == [[str(len(first)), "True"], [str(len(first)), "False"]]


def test_a_changed_environment_is_scanned_again(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    plugins.installed("xodrlint.rules")
    path = plugins.cache_path()
    stale = json.loads(cache.read(path) or b"")
    stale["entries"][0]["groups"]["xodrlint.rules"] = [["ghost", "nowhere:nothing", "", ""]]
    assert cache.write(path, json.dumps(stale).encode())
    assert [p.name for p in plugins.installed("xodrlint.rules")] == ["ghost"]  # trusted
    extra = tmp_path / "site"
    extra.mkdir()
    monkeypatch.syspath_prepend(str(extra))  # as installing a package would change a folder
    assert "ghost" not in [p.name for p in plugins.installed("xodrlint.rules")]


def test_an_unwritable_cache_folder_is_no_error(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(plugins.CACHE_ENV, "/proc/no-such-place")
    assert plugins.installed("xodrlint.rules")


def test_plugin_load_resolves_module_and_attribute() -> None:
    loaded = plugins.Plugin("x", "xodrlint.config.plugins:Plugin.load", "g").load()
    assert loaded is plugins.Plugin.load
    assert plugins.Plugin("x", "xodrlint.config.plugins", "g").load() is plugins


def test_each_environment_has_a_cache_file_of_its_own(monkeypatch: pytest.MonkeyPatch) -> None:
    here = plugins.cache_path()
    monkeypatch.setattr(sys, "prefix", "/opt/another-venv")
    assert plugins.cache_path().parent == here.parent
    assert plugins.cache_path() != here


def test_ways_of_starting_xodrlint_in_one_environment_keep_their_own_keys(
    tmp_path: Path,
) -> None:
    # the console script has its bin folder first on sys.path, python -m the current one
    code = (
        "import sys; sys.path[0] = sys.argv[1]; from xodrlint.config.plugins import installed; "
        "installed('xodrlint.rules'); print('importlib.metadata' in sys.modules)"
    )
    starts = [tmp_path / "bin", tmp_path / "project"]
    for start in starts:
        start.mkdir()
    scanned = [
        subprocess.run(
            [sys.executable, "-c", code, str(start)],
            capture_output=True,
            text=True,
            check=True,
            env=os.environ,
        ).stdout.strip()
        for start in starts * 2
    ]
    assert scanned == ["True", "True", "False", "False"]


def test_a_key_in_use_is_not_evicted_by_others(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the most recently used key goes first: KEYS_KEPT other ways of starting, each used
    # once, must not push out the one used between them
    monkeypatch.setenv(plugins.CACHE_ENV, str(tmp_path / "cache"))
    scans: list[int] = []
    real_scan = plugins._scan

    def counted() -> dict[str, list[list[str]]]:
        scans.append(1)
        return real_scan()

    monkeypatch.setattr(plugins, "_scan", counted)
    keys = iter(range(100))
    main = [["main"]]
    monkeypatch.setattr(plugins, "_environment_key", lambda: main)
    plugins.installed("xodrlint.rules")
    for _ in range(plugins.KEYS_KEPT * 2):
        other = [[f"other {next(keys)}"]]
        monkeypatch.setattr(plugins, "_environment_key", lambda other=other: other)
        plugins.installed("xodrlint.rules")
        monkeypatch.setattr(plugins, "_environment_key", lambda: main)
        plugins.installed("xodrlint.rules")
    assert len(scans) == 1 + plugins.KEYS_KEPT * 2  # main was scanned once


def test_a_cache_of_an_older_format_is_replaced(tmp_path: Path) -> None:
    path = plugins.cache_path()
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"format": 1, "key": [], "groups": {}}), "utf-8")
    assert plugins.installed("xodrlint.rules")
    assert json.loads(cache.read(path) or b"")["format"] == plugins.FORMAT
