"""Installed plugins (rule packs, formatters), found through entry points, cached.

Importing ``importlib.metadata`` and scanning every installed distribution costs about
40 ms, a fifth of a pre-commit run on a small map. The entry points of xodrlint's groups
are therefore kept in the user cache folder, keyed by the modification times of the
folders on ``sys.path``: installing or removing a package changes its folder, so the
next run scans again. Without a usable cache folder every run scans. Each environment
(a project's venv, pre-commit's own) has a file of its own, so two of them used in turn
do not rewrite one file on every run; and within a file the last few keys are kept, so
that the console script and ``python -m xodrlint`` (whose ``sys.path`` differ in their
first entry) do not evict each other.
"""

from __future__ import annotations

import contextlib
import importlib
import json
import os
import sys
import zlib
from pathlib import Path
from typing import Any, Final, NamedTuple

from xodrlint.files import write_atomically

GROUPS: Final = ("xodrlint.rules", "xodrlint.formatters")
CACHE_ENV: Final = "XODRLINT_CACHE_DIR"
FORMAT: Final = 2
#: Keys kept per environment: ways of starting xodrlint there (console script, ``-m``
#: from a few folders).
KEYS_KEPT: Final = 4


class Plugin(NamedTuple):
    """An entry point, as much of it as xodrlint uses: its name, target and ``load``."""

    name: str
    value: str
    group: str

    def load(self) -> object:
        module, _, attribute = self.value.partition(":")
        loaded: object = importlib.import_module(module.strip())
        for part in attribute.strip().split(".") if attribute.strip() else ():
            loaded = getattr(loaded, part)
        return loaded


def cache_dir() -> Path:
    """The user cache folder (``XODRLINT_CACHE_DIR`` overrides it)."""
    override = os.environ.get(CACHE_ENV)
    if override:
        return Path(override)
    from platformdirs import user_cache_path

    return user_cache_path("xodrlint")


def cache_path() -> Path:
    """This environment's cache file."""
    environment = zlib.crc32(os.fsencode(sys.prefix))
    return cache_dir() / f"entry-points-{environment:08x}.json"


def installed(group: str) -> list[Plugin]:
    """The entry points of ``group`` that installed distributions declare."""
    key = _environment_key()
    path = cache_path()
    entries: list[dict[str, Any]] = []  # JSON, checked as it is used
    with contextlib.suppress(OSError, ValueError, TypeError, KeyError, AttributeError):
        cached = json.loads(path.read_text(encoding="utf-8"))
        if cached["format"] == FORMAT:
            entries = [entry for entry in cached["entries"] if isinstance(entry, dict)]
            for entry in entries:
                if entry["key"] == key:
                    return [Plugin(name, value, group) for name, value in entry["groups"][group]]
    groups = _scan()
    kept = [{"key": key, "groups": groups}, *entries][:KEYS_KEPT]
    _store(path, {"format": FORMAT, "entries": kept})
    return [Plugin(name, value, group) for name, value in groups.get(group, [])]


def _environment_key() -> list[list[object]]:
    key: list[list[object]] = [[sys.executable, sys.version]]
    for entry in sys.path:
        with contextlib.suppress(OSError):
            key.append([entry, Path(entry or ".").stat().st_mtime_ns])
    return key


def _scan() -> dict[str, list[list[str]]]:
    from importlib.metadata import entry_points

    return {
        group: sorted([point.name, point.value] for point in entry_points(group=group))
        for group in GROUPS
    }


def _store(path: Path, document: dict[str, object]) -> None:
    """Write the cache whole, or not at all (a read-only home is no error)."""
    with contextlib.suppress(OSError):
        path.parent.mkdir(parents=True, exist_ok=True)
        write_atomically(path, json.dumps(document).encode())
