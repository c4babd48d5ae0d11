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
#: Where a report goes when standard output carries a document (``--fix`` on standard
#: input): standard error. No path names it.
STDERR: Final = "\0stderr"
#: ``--color``: ``auto`` follows ``NO_COLOR``, ``FORCE_COLOR`` and whether the stream is
#: a terminal; the others decide alone.
COLOR_CHOICES: Final = ("auto", "always", "never")
Render = Callable[[TextIO], None]


def color_wanted(choice: str | None, stream: TextIO) -> bool:
    """Whether text written to ``stream`` carries styles (colour, bold, underline), as in
    ruff: ``--color always|never`` decides; otherwise a non-empty ``NO_COLOR`` means
    plain text (https://no-color.org), a non-empty ``FORCE_COLOR`` means styles, and
    else a person's terminal gets them."""
    if choice in ("always", "never"):
        return choice == "always"
    if os.environ.get("NO_COLOR"):
        return False
    if os.environ.get("FORCE_COLOR"):
        return True
    return interactive(stream)


def interactive(stream: TextIO) -> bool:
    """Whether ``stream`` is a terminal that obeys escape codes (not a dumb one)."""
    try:
        terminal = stream.isatty()
    except (AttributeError, ValueError):  # a closed or bare stream
        return False
    return terminal and os.environ.get("TERM") != "dumb"


def error_line(message: str) -> None:
    """``message`` on stderr as one ``xodrlint:`` line. A reader of stderr that stopped
    early (``2>&1 | head``) is no error of the run: the rest of what it says is dropped,
    and the run goes on to write its reports and exit as it would have."""
    try:
        print(f"xodrlint: {message}", file=sys.stderr, flush=True)
    except BrokenPipeError:
        release(sys.stderr)


def release(stream: TextIO) -> None:
    """Let a standard stream go when its reader stopped early (``check | head``): what
    is still buffered, and anything written later, goes to the null device, so neither
    the rest of the run nor the exit's flush meets the closed pipe again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, stream.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):  # no descriptor (an embedding's stream)
        replacement = Path(os.devnull).open("w", encoding="utf-8")  # noqa: SIM115 (the run's)
        if stream is sys.stdout:
            sys.stdout = replacement
        elif stream is sys.stderr:
            sys.stderr = replacement


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
    if output == STDERR:
        render(sys.stderr)
        sys.stderr.flush()
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
