"""Where command output goes: one-line errors on stderr, reports written whole."""

from __future__ import annotations

import os
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Final, TextIO

STDOUT: Final = "-"
Render = Callable[[TextIO], None]


def error_line(message: str) -> None:
    print(f"xodrlint: {message}", file=sys.stderr)


def write_output(output: str | None, render: Render) -> None:
    """Render to stdout, or to ``output`` whole: a temp file beside it, then a rename."""
    if output in (None, STDOUT):
        render(sys.stdout)
        sys.stdout.flush()
        return
    target = Path(output)
    handle, temporary = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent or ".")
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="\n") as stream:
            render(stream)
        Path(temporary).replace(target)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
