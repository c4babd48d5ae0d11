"""The user cache folder, and what xodrlint may take from it.

A cache is input from outside the run: CI systems restore caches made elsewhere, teams
share a ``XODRLINT_CACHE_DIR``, and two caches hold what would run code if forged (the
entry points name modules to import; the XSD 1.1 model is a pickle). So an entry is used
only when

- the file and every folder from it up to the cache root are owned by the current user
  and writable by nobody else (as ssh judges the folders of its keys), and
- its content still has the hash (BLAKE2b) recorded when it was written (a schema form swapped
  for a permissive one would otherwise lose findings silently).

Anything else is a cache miss: the caller rebuilds, and says why once on stderr. What
xodrlint writes is private to the user (folders 0700, files 0600), whatever the umask,
so that its own entries pass the check.
"""

from __future__ import annotations

import os
import stat
import sys
from pathlib import Path
from typing import Final

from xodrlint.inputs.files import os_reason, write_atomically

try:  # hashlib's BLAKE2b without hashlib, whose OpenSSL import cost 4 ms of every start
    from _blake2 import blake2b
except ImportError:  # pragma: no cover - an interpreter built without it
    from hashlib import blake2b

ENV: Final = "XODRLINT_CACHE_DIR"
#: The first line of a cache file written by :func:`write`: the BLAKE2b of the rest.
_HEADER: Final = b"xodrlint-cache blake2b-256="

_warned: set[str] = set()


def root() -> Path:
    """The user cache folder (``XODRLINT_CACHE_DIR`` overrides it)."""
    override = os.environ.get(ENV)
    if override:
        return Path(override)
    from platformdirs import user_cache_path

    return user_cache_path("xodrlint")


def distrust(path: Path) -> str | None:
    """Why ``path`` (in the cache) must not be used, or ``None`` when it may: it and
    every folder up to the cache root, links resolved, are the user's own and writable
    by no one else. A path that does not exist is no reason (the caller finds it
    missing)."""
    top = root().resolve()
    current = path.resolve()
    uid = os.getuid() if hasattr(os, "getuid") else None
    while True:
        try:
            status = current.stat()
        except FileNotFoundError:
            return None
        except OSError as error:
            return f"{current} cannot be examined ({os_reason(error)})"
        if uid is not None and status.st_uid != uid:
            return f"{current} belongs to another user (uid {status.st_uid})"
        if status.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
            return f"{current} is writable by others (mode {stat.S_IMODE(status.st_mode):04o})"
        if current == top or top not in current.parents:
            return None
        current = current.parent


def warn(path: Path, reason: str) -> None:
    """Say once per run that a cache entry is not used, and why."""
    if reason in _warned:
        return
    _warned.add(reason)
    print(f"xodrlint: not using the cached {path.name}: {reason}; rebuilding", file=sys.stderr)


def read(path: Path) -> bytes | None:
    """The content of a cache file :func:`write` wrote, or ``None`` when it is missing,
    not to be trusted or not what was written (a warning says which)."""
    reason = distrust(path)
    if reason is not None:
        warn(path, reason)
        return None
    try:
        data = path.read_bytes()
    except OSError:
        return None
    header, newline, content = data.partition(b"\n")
    if not newline or not header.startswith(_HEADER):
        warn(path, f"{path} has no content hash")
        return None
    if header[len(_HEADER) :].decode("ascii", "replace") != digest(content):
        warn(path, f"{path} does not hold what was written (its content hash differs)")
        return None
    return content


def write(path: Path, content: bytes) -> bool:
    """Store ``content`` at ``path`` with its hash, in private folders; ``False`` when the
    cache cannot be written (a read-only home is no error) or is not to be trusted."""
    try:
        make_folder(path.parent)
        _tighten(path.parent)
        if distrust(path.parent) is not None:
            return False
        write_atomically(path, _HEADER + digest(content).encode() + b"\n" + content)
    except OSError:
        return False
    return True


def make_folder(folder: Path) -> None:
    """Create ``folder`` and its missing parents, private to the user."""
    missing = [folder, *folder.parents]
    for level in reversed(missing):
        if not level.exists():
            level.mkdir(mode=0o700)


def _tighten(folder: Path) -> None:
    """Take group and other write access from the user's own folders up to the cache
    root (an older xodrlint made them with the umask): what others may have put there is
    still judged file by file."""
    top = root().resolve()
    for level in [folder.resolve(), *folder.resolve().parents]:
        status = level.stat()
        if status.st_uid == os.getuid() and status.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
            level.chmod(stat.S_IMODE(status.st_mode) & ~(stat.S_IWGRP | stat.S_IWOTH))
        if level == top or top not in level.parents:
            return


def digest(content: bytes) -> str:
    """The content hash recorded with a cache entry (BLAKE2b, 256 bits)."""
    return blake2b(content, digest_size=32).hexdigest()
