"""Where command output goes: one-line errors on stderr, reports written whole."""

from __future__ import annotations

import os
import stat
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Final, TextIO

STDOUT: Final = "-"
Render = Callable[[TextIO], None]


def error_line(message: str) -> None:
    print(f"xodrlint: {message}", file=sys.stderr)


def release_stdout() -> None:
    """Let standard output go when its reader stopped early (``check | head``): what is
    still buffered, and anything written later, goes to the null device, so neither the
    rest of the run nor the exit's flush meets the closed pipe again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):  # no descriptor (an embedding's stream)
        sys.stdout = Path(os.devnull).open("w", encoding="utf-8")  # noqa: SIM115 (for the run)


def write_output(output: str | None, render: Render) -> None:
    """Render to stdout, or to ``output`` whole: a temp file beside it, then a rename.

    A target that is no regular file (``/dev/null``, ``/dev/stdout``, a FIFO) is written in
    place: renaming over it would put a regular file where the device was, and with root
    rights that replaces ``/dev/null`` for the whole machine. A symlink keeps pointing
    where it did: the file it names is the one replaced.
    """
    if output in (None, STDOUT):
        render(sys.stdout)
        sys.stdout.flush()
        return
    target = Path(output)
    try:
        is_regular = stat.S_ISREG(target.stat().st_mode)
    except FileNotFoundError:
        is_regular = True
    if not is_regular:
        with target.open("w", encoding="utf-8", newline="\n") as stream:
            render(stream)
        return
    target = target.resolve() if target.is_symlink() else target
    handle, temporary = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent or ".")
    try:
        # mkstemp makes the file private (0600); a report is shared like any file written
        # with open(): it keeps the mode of the file it replaces, or follows the umask.
        os.fchmod(handle, _mode_for(target))
        with os.fdopen(handle, "w", encoding="utf-8", newline="\n") as stream:
            render(stream)
        Path(temporary).replace(target)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def _mode_for(target: Path) -> int:
    try:
        return stat.S_IMODE(target.stat().st_mode)
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask
