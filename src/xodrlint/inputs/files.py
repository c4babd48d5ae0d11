"""Files xodrlint reads and keeps: an input is read without blocking (what is no regular
file is refused, not read); a cache file is written whole or not at all."""

from __future__ import annotations

import contextlib
import errno
import os
import stat
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import BinaryIO


def os_reason(error: OSError) -> str:
    """The reason for ``error`` as xodrlint's messages say it: the OS's words (else the
    error's own, else its kind), starting lowercase ("no such file or directory")."""
    reason = error.strerror or str(error) or type(error).__name__
    return reason[:1].lower() + reason[1:]


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


def overwrites(output: Path, inputs: Iterable[Path]) -> bool:
    """Whether writing ``output`` would replace one of ``inputs``: the same file under
    any name, through a symbolic link or a hard link.

    Compared by device and inode, one ``stat`` each: resolving every input's path
    instead cost 20 ms on a folder of 200 maps, in the serial start of a batch run.
    """
    try:
        written = output.stat()
    except OSError:  # not there yet (or out of reach): no input can be it
        return False
    for path in inputs:
        try:
            status = path.stat()
        except OSError:  # the input is gone; its report says so
            continue
        if (status.st_dev, status.st_ino) == (written.st_dev, written.st_ino):
            return True
    return False


class FileTooLarge(OSError):
    """The file holds more bytes than the reader takes."""


def read_regular_file(path: Path, limit: int | None = None) -> bytes:
    """The bytes of ``path``; :class:`NotRegularFile` when it is no regular file, and
    :class:`FileTooLarge` when it holds more than ``limit`` bytes (at most ``limit + 1``
    are read, whatever the file says its size is)."""
    with _opened_regular(path) as stream:
        if limit is None:
            return stream.read()
        data = stream.read(limit + 1)
    if len(data) > limit:
        raise FileTooLarge(f"is larger than {limit:,} bytes")
    return data


def read_regular_head(path: Path, size: int) -> bytes:
    """The first ``size`` bytes of ``path`` (:class:`NotRegularFile` as above)."""
    with _opened_regular(path) as stream:
        return stream.read(size)


@contextlib.contextmanager
def _opened_regular(path: Path) -> Iterator[BinaryIO]:
    # opened without blocking and checked on the open descriptor: a FIFO opened for
    # reading would wait for a writer, and a file swapped after a check would be read
    descriptor = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    with os.fdopen(descriptor, "rb") as stream:
        kind = special_kind(os.fstat(descriptor).st_mode)
        if kind is not None:
            raise NotRegularFile(f"is {kind}, not a regular file")
        yield stream


def write_atomically(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` whole: a temporary file beside it, then a rename, so a
    reader (another run sharing the cache) never sees half a file."""
    import tempfile  # only runs that write a cache pay for it

    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
        Path(temporary).replace(path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


class WriteRefused(Exception):
    """A fixed file that is not written back, with why (one line)."""


def replace_file(path: Path, original: bytes, data: bytes, root: Path | None = None) -> None:
    """Replace the file ``path`` holds, read as ``original``, with ``data``: atomically
    (a temporary file beside it, then a rename), keeping its mode (and owner, where the
    run may give it). Refused (:class:`WriteRefused`) for a read-only file, a file that
    changed since it was read, a file with other hard links (a new file would part them),
    and a path that leads out of ``root`` (the folder a walk found it in) through a link,
    its own or a folder's.

    Below ``root`` the folders are opened one by one, none through a link, and every step
    works from the last one's descriptor: a folder or a link swapped after the check
    cannot turn the write elsewhere."""
    import secrets

    target = path.resolve()
    try:
        folder = _folder_of(target, root)
    except OSError as error:
        if root is not None and error.errno in (errno.ELOOP, errno.ENOTDIR):
            raise WriteRefused("is a link leading out of the folder walked") from None
        raise WriteRefused(f"cannot be written: {os_reason(error)}") from None
    try:
        _replace_in(folder, target.name, original, data, secrets.token_hex(6))
    except OSError as error:
        raise WriteRefused(f"cannot be written: {os_reason(error)}") from None
    finally:
        os.close(folder)


_NO_FOLLOW = getattr(os, "O_NOFOLLOW", 0)
_FOLDER = os.O_RDONLY | os.O_DIRECTORY


def _folder_of(target: Path, root: Path | None) -> int:
    """A descriptor of the folder ``target`` stands in: opened from ``root`` down, one
    folder at a time and none through a link, where a walk found the file there."""
    if root is None:
        return os.open(target.parent, _FOLDER)
    top = root.resolve()
    if not target.is_relative_to(top):
        raise WriteRefused("is a link leading out of the folder walked")
    folder = os.open(top, _FOLDER)
    try:
        for part in target.parent.relative_to(top).parts:
            inner = os.open(part, _FOLDER | _NO_FOLLOW, dir_fd=folder)
            os.close(folder)
            folder = inner
    except BaseException:
        os.close(folder)
        raise
    return folder


def _replace_in(folder: int, name: str, original: bytes, data: bytes, token: str) -> None:
    """:func:`replace_file`'s steps in the folder open as ``folder``."""
    try:
        current = os.open(name, os.O_RDONLY | _NO_FOLLOW | os.O_NONBLOCK, dir_fd=folder)
    except OSError as error:
        if error.errno == errno.ELOOP:
            raise WriteRefused("is a link leading out of the folder walked") from None
        raise WriteRefused(f"cannot be read again: {os_reason(error)}") from None
    with os.fdopen(current, "rb") as stream:
        status = os.fstat(current)
        if not stat.S_ISREG(status.st_mode):
            raise WriteRefused("is no longer a regular file")
        if stream.read() != original:
            raise WriteRefused("changed on disk since it was read")
    if not status.st_mode & 0o222 or not os.access(name, os.W_OK, dir_fd=folder):
        raise WriteRefused("is read-only")
    if status.st_nlink > 1:
        raise WriteRefused(f"has {status.st_nlink} hard links: a new file would part them")
    temporary = f".xodrlint-{token}.tmp"  # short: a name near the limit still fits
    handle = os.open(
        temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | _NO_FOLLOW, 0o600, dir_fd=folder
    )
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
            stream.flush()
            os.fchmod(stream.fileno(), stat.S_IMODE(status.st_mode))
            with contextlib.suppress(OSError):  # only the owner's own, or root, may
                os.fchown(stream.fileno(), status.st_uid, status.st_gid)
            os.fsync(stream.fileno())
        os.replace(temporary, name, src_dir_fd=folder, dst_dir_fd=folder)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary, dir_fd=folder)
        raise
    with contextlib.suppress(OSError):
        os.fsync(folder)  # the rename itself survives a crash
