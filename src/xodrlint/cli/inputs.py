"""``xodrlint check``'s inputs: what the paths on its command line name, after
``exclude`` and the ignore files, and ``--show-files``, which lists them and stops."""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Final

from xodrlint.api import STDIN, Input, collect_inputs, printable_path, too_large
from xodrlint.config import Settings, any_match
from xodrlint.messages import one_line
from xodrlint.output import error_line


class InputsError(ValueError):
    """Inputs a check cannot take (``-`` twice): exit 2 with this one line, before
    linting."""


def check_stdin(paths: Sequence[str], stdin_filename: str | None) -> None:
    if stdin_filename is not None and printable_path(stdin_filename) != stdin_filename:
        shown = printable_path(stdin_filename)
        raise InputsError(f"--stdin-filename {shown}: the name is not valid UTF-8")
    if list(paths).count(STDIN) > 1:
        raise InputsError(f"{STDIN} (standard input) is given more than once")


def collect(paths: Sequence[str], settings: Settings) -> list[Input]:
    """What to lint; files a folder walk met but cannot lint (a FIFO, a device) are left
    out with a note on stderr, and a warning says when nothing at all is left (exit 0,
    as ruff: an empty folder is no error)."""
    inputs = []
    found = collect_inputs(
        paths,
        _excluder(settings),
        settings.max_file_size,
        respect_gitignore=settings.respect_gitignore,
    )
    for item in found:
        if item.skipped is not None:
            error_line(f"note: {item.skipped}")
        else:
            inputs.append(item)
    if not inputs:
        named = " ".join(printable_path(path) for path in paths)
        error_line(f"warning: no .xodr files found under {named}")
    return inputs


def _excluder(settings: Settings) -> Callable[[Path], bool] | None:
    if not settings.exclude:
        return None
    return lambda path: any_match(settings.exclude, path, settings.base)


def show_files(inputs: list[Input], stdin_filename: str | None) -> int:
    """``--show-files``: the files a check would lint, in its order and named as its
    reports name them; what it could not read is a line on stderr and exit 2."""
    for item in inputs:
        if item.error is not None:
            error_line(one_line(item.error))
    names = [
        (stdin_filename or STDIN) if item.is_stdin else item.display
        for item in inputs
        if item.error is None
    ]
    from xodrlint.cli.reports import write_reports

    listed = write_reports(
        [("--show-files", None, lambda stream: stream.writelines(f"{n}\n" for n in names))]
    )
    return 2 if not listed or any(item.error for item in inputs) else 0


#: Standard input is read in pieces this large, so that a limit of gigabytes is never
#: allocated up front.
STDIN_CHUNK: Final = 1024 * 1024


def read_stdin(limit: int) -> tuple[bytes, str | None]:
    """Standard input, at most ``limit`` bytes: (contents, why it cannot be linted)."""
    if sys.stdin is None:  # started with standard input closed
        return b"", f"{STDIN}: cannot read standard input: it is closed"
    pieces: list[bytes] = []
    size = 0
    try:
        while size <= limit:
            piece = sys.stdin.buffer.read(min(STDIN_CHUNK, limit + 1 - size))
            if not piece:
                break
            pieces.append(piece)
            size += len(piece)
    except (OSError, ValueError) as error:  # a closed or unreadable stream
        return b"", f"{STDIN}: cannot read standard input: {error}"
    if size > limit:
        return b"", too_large(STDIN, limit)
    return b"".join(pieces), None
