"""``xodrlint schemas list|add|fetch``: which schema set each OpenDRIVE version gets,
and filling the user data folder with official sets (the work is
:mod:`xodrlint.validation.store`'s)."""

from __future__ import annotations

import io
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from xodrlint.formatters.output import error_line as _error
from xodrlint.messages import plural
from xodrlint.validation.sets import SchemaFinder, builtin_set

if TYPE_CHECKING:
    from xodrlint.validation.store import Installed


def list_schemas() -> int:
    finder = SchemaFinder()
    out = io.StringIO()
    sets = list(finder.official_sets())
    if sets:
        for found in sets:
            serves = " for every version" if found.serves_every_version else ""
            out.write(f"{found.label:40} {found.entry}  (from {found.origin}{serves})\n")
    else:
        out.write("no official schemas found\n")
    minors = range(4, 10)
    out.write(
        "built-in railroad schemas: "
        + ", ".join(f"1.{m} ({builtin_set(1, m).entry.name})" for m in minors)
        + "\n"
    )
    sys.stdout.write(out.getvalue())
    return 0


def add_schemas(source: Path) -> int:
    from xodrlint.validation.store import add

    return _store(lambda: add(source), "added")


def fetch_schemas(wheel: Path | None) -> int:
    from xodrlint.validation.store import fetch

    return _store(lambda: fetch(wheel=wheel), "installed")


def _store(install: Callable[[], list[Installed]], done: str) -> int:
    """Run one way of filling the user folder and say what it put there."""
    from xodrlint.validation.store import StoreError

    try:
        installed = install()
    except (StoreError, OSError) as error:
        _error(str(error))
        return 2
    for item in installed:
        print(f"{done} OpenDRIVE {item.version} ({plural(item.files, 'file')}) to {item.folder}")
    return 0
