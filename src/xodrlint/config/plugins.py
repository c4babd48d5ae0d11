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

from xodrlint.config import cache

GROUPS: Final = ("xodrlint.rules", "xodrlint.formatters")
CACHE_ENV: Final = cache.ENV
FORMAT: Final = 4
#: Keys kept per environment: ways of starting xodrlint there (console script, ``-m``
#: from a few folders).
KEYS_KEPT: Final = 4


class Plugin(NamedTuple):
    """An entry point, as much of it as xodrlint uses: its name, target, the distribution
    that declares it (name and version, ``""`` where unknown) and ``load``."""

    name: str
    value: str
    group: str
    distribution: str = ""
    version: str = ""

    def load(self) -> object:
        module, _, attribute = self.value.partition(":")
        loaded: object = importlib.import_module(module.strip())
        for part in attribute.strip().split(".") if attribute.strip() else ():
            loaded = getattr(loaded, part)
        return loaded


def cache_dir() -> Path:
    """The user cache folder (``XODRLINT_CACHE_DIR`` overrides it)."""
    return cache.root()


def cache_path() -> Path:
    """This environment's cache file."""
    environment = zlib.crc32(os.fsencode(sys.prefix))
    return cache_dir() / f"entry-points-{environment:08x}.json"


def installed(group: str) -> list[Plugin]:
    """The entry points of ``group`` that installed distributions declare."""
    key = _environment_key()
    path = cache_path()
    entries = _cached_entries(path)
    for index, entry in enumerate(entries):
        if entry["key"] == key:
            if index:  # the most recently used first: a fifth way of starting evicts the oldest
                _keep(path, [entry, *entries[:index], *entries[index + 1 :]])
            return _plugins(entry["groups"], group)
    groups = _scan()
    _keep(path, [{"key": key, "groups": groups}, *entries])
    return _plugins(groups, group)


def _plugins(groups: dict[str, list[list[str]]], group: str) -> list[Plugin]:
    return [
        Plugin(name, value, group, distribution, version)
        for name, value, distribution, version in groups.get(group, [])
    ]


def _keep(path: Path, entries: list[dict[str, Any]]) -> None:
    kept = entries[:KEYS_KEPT]
    cache.write(path, json.dumps({"format": FORMAT, "entries": kept}).encode())


def _cached_entries(path: Path) -> list[dict[str, Any]]:
    """The cache's entries when the file is trusted (see :mod:`xodrlint.config.cache`) and each
    entry has the shape :func:`installed` writes; otherwise none (the scan rebuilds)."""
    content = cache.read(path)
    if content is None:
        return []
    try:
        cached = json.loads(content)
    except (ValueError, RecursionError):
        return []
    if not isinstance(cached, dict) or cached.get("format") != FORMAT:
        return []  # an older release's cache: replaced without a word
    entries = cached.get("entries")
    if not isinstance(entries, list) or not all(_well_formed(entry) for entry in entries):
        cache.warn(path, f"{path} holds entries of another shape")
        return []
    return entries


def _well_formed(entry: object) -> bool:
    if not isinstance(entry, dict) or not isinstance(entry.get("key"), list):
        return False
    groups = entry.get("groups")
    return isinstance(groups, dict) and all(
        isinstance(name, str)
        and isinstance(points, list)
        and all(
            isinstance(point, list) and len(point) == 4 and all(isinstance(p, str) for p in point)
            for point in points
        )
        for name, points in groups.items()
    )


def _environment_key() -> list[list[object]]:
    key: list[list[object]] = [[sys.executable, sys.version]]
    for entry in sys.path:
        with contextlib.suppress(OSError):
            key.append([entry, Path(entry or ".").stat().st_mtime_ns])
    return key


def _scan() -> dict[str, list[list[str]]]:
    from importlib.metadata import entry_points

    return {
        group: sorted(
            [point.name, point.value, *_distribution(point)] for point in entry_points(group=group)
        )
        for group in GROUPS
    }


def _distribution(point: Any) -> list[str]:
    """The name and version of the distribution declaring ``point`` (for warnings and
    ``xodrlint rules``), empty where importlib cannot say."""
    dist = getattr(point, "dist", None)
    if dist is None:
        return ["", ""]
    return [str(dist.name or ""), str(dist.version or "")]
