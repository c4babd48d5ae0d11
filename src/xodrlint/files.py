"""Reading an input file without blocking: what is no regular file is refused, not read."""

from __future__ import annotations

import os
import stat
from pathlib import Path


class NotRegularFile(OSError):
    """The path is a FIFO, a device or a socket: reading it would block or never end."""


def special_kind(mode: int) -> str | None:
    """What a path that is neither a file nor a folder is; reading it would block (a
    FIFO, a socket) or never end (``/dev/zero``)."""
    for test, kind in (
        (stat.S_ISFIFO, "a FIFO"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    ):
        if test(mode):
            return kind
    return None


def read_regular_file(path: Path) -> bytes:
    """The bytes of ``path``; :class:`NotRegularFile` when it is no regular file.

    Opened without blocking and checked on the open descriptor: a FIFO opened for
    reading would wait for a writer, and a file swapped after a check would be read.
    """
    descriptor = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    with os.fdopen(descriptor, "rb") as stream:
        kind = special_kind(os.fstat(descriptor).st_mode)
        if kind is not None:
            raise NotRegularFile(f"is {kind}, not a regular file")
        return stream.read()
