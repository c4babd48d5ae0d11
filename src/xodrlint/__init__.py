"""xodrlint: a linter for the railroad content of ASAM OpenDRIVE (.xodr) files.

``lint_file`` and ``lint_bytes`` are the Python API (see :mod:`xodrlint.api`); they are
imported on first use so that ``import xodrlint`` and the CLI start fast.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"
__all__ = ["__version__", "lint_bytes", "lint_file"]


class _OldPathFinder:
    """Paths of the flat layout (``xodrlint.schemas``, ``xodrlint.batch``, ...) keep
    working until 0.2. Asked last, so only for a module no real finder has; the table
    (:mod:`xodrlint._moved`) is read only then."""

    @staticmethod
    def find_spec(fullname: str, path: object = None, target: object = None) -> Any:
        if not fullname.startswith("xodrlint.") or fullname == "xodrlint._moved":
            return None
        from xodrlint import _moved

        return _moved.find_spec(fullname)


sys.meta_path.append(_OldPathFinder)

if TYPE_CHECKING:
    from xodrlint.api import lint_bytes, lint_file


def __getattr__(name: str) -> Any:
    if name in ("lint_file", "lint_bytes"):
        from xodrlint import api

        return getattr(api, name)
    raise AttributeError(f"module 'xodrlint' has no attribute {name!r}")
