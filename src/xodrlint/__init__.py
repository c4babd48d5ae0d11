"""xodrlint: a linter for the railroad content of ASAM OpenDRIVE (.xodr) files.

``lint_file`` and ``lint_bytes`` are the Python API (see :mod:`xodrlint.api`); they are
imported on first use so that ``import xodrlint`` and the CLI start fast.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"
__all__ = ["__version__", "lint_bytes", "lint_file"]

if TYPE_CHECKING:
    from xodrlint.api import lint_bytes, lint_file


def __getattr__(name: str) -> Any:
    if name in ("lint_file", "lint_bytes"):
        from xodrlint import api

        return getattr(api, name)
    raise AttributeError(f"module 'xodrlint' has no attribute {name!r}")
