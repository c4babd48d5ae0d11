"""Which configuration file governs a folder: the nearest ``.xodrlint.toml``,
``xodrlint.toml`` or ``pyproject.toml`` with ``[tool.xodrlint]``, in the folder or above
it, up to the repository's root or the user's home, and only a file this user may trust
(git's ``safe.directory`` idea): a folder above a checkout may hold a file anyone planted.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Iterator
from functools import lru_cache
from pathlib import Path
from typing import Final

from xodrlint.config.settings import ConfigFile, read_config
from xodrlint.inputs.files import os_reason

#: Looked for in each folder, in this order; a pyproject.toml counts only with [tool.xodrlint].
CONFIG_NAMES: Final = (".xodrlint.toml", "xodrlint.toml", "pyproject.toml")


def find_config(start: Path, skipped: list[str] | None = None) -> ConfigFile | None:
    """The configuration that governs ``start``: the nearest one in it or above it, up
    to the repository's root or the user's home (:func:`config_folders`). A file that
    another user could have written is passed over unread (:func:`distrust`), and why is
    added to ``skipped``: a folder above a checkout (``/tmp``, a shared runner's work
    folder) may hold a file planted by anyone, which would name the schema, the rule
    options and the time limits of this user's run."""
    folders = list(config_folders(start))
    owner = _repository_owner(folders[-1])
    for folder in folders:
        for name in CONFIG_NAMES:
            path = folder / name
            if not path.is_file():
                continue
            reason = distrust(path, owner)
            if reason is not None:
                # someone else's pyproject.toml is said only when it holds our table
                said = name != "pyproject.toml" or _has_our_table(path)
                if said and skipped is not None:
                    skipped.append(f"ignoring {path}: {reason}")
                continue
            found = read_config(path, required=name != "pyproject.toml")
            if found is not None:
                return found
    return None


def config_folders(start: Path) -> Iterator[Path]:
    """The folders whose configuration files may govern ``start``: its own, then each
    above it, up to and including the first that is a repository's root (holds
    ``.git``) or the user's home; past neither, up to the file system's root."""
    folder = start.resolve()
    if not folder.is_dir():
        folder = folder.parent
    for candidate in (folder, *folder.parents):
        yield candidate
        if search_stops_at(candidate):
            return


def search_stops_at(folder: Path) -> bool:
    """Whether the search for configuration files ends at ``folder`` (resolved): a
    repository's root, or the user's home."""
    return folder == _home() or (folder / ".git").exists()


def holds_config(folder: Path) -> bool:
    """Whether ``folder`` holds a file of one of :data:`CONFIG_NAMES`."""
    return any((folder / name).is_file() for name in CONFIG_NAMES)


def _home() -> Path | None:
    # looked up once per value of HOME (what Path.home reads): a run walks up from
    # every folder it lints
    return _resolved_home(os.environ.get("HOME"))


@lru_cache(maxsize=4)
def _resolved_home(_given: str | None) -> Path | None:
    try:
        return Path.home().resolve()
    except (RuntimeError, KeyError, OSError):  # no home known for this user
        return None


def _repository_owner(last: Path) -> int | None:
    """The owner of the repository whose root ``last`` is (the owner of its ``.git``),
    ``None`` where ``last`` is no repository's root."""
    try:
        return (last / ".git").stat().st_uid
    except OSError:
        return None


def distrust(path: Path, repository_owner: int | None = None) -> str | None:
    """Why ``path`` may not be this user's own (git's ``safe.directory`` idea): writable
    by every user, or owned by another user than the one running xodrlint, root, or the
    owner of the repository it lies in (a checkout of another user's, linted by root in
    a container: the repository's own file); ``None`` for a file one of those wrote."""
    if not hasattr(os, "geteuid"):
        return None  # no owners to compare (Windows): as git there, trusted
    try:
        status = path.stat()
    except OSError as error:
        return f"cannot be read: {os_reason(error)}"
    if status.st_mode & stat.S_IWOTH:
        return "every user of the machine can write it"
    if status.st_uid not in (os.geteuid(), 0, repository_owner):
        return f"it is owned by another user (uid {status.st_uid})"
    return None


def _has_our_table(path: Path) -> bool:
    """Whether a ``pyproject.toml`` holds ``[tool.xodrlint]`` (one that cannot be read
    or parsed holds none that matters)."""
    import tomllib

    try:
        tool = tomllib.loads(path.read_text(encoding="utf-8")).get("tool")
    except (OSError, ValueError, RecursionError):
        return False
    return isinstance(tool, dict) and "xodrlint" in tool
