"""xodrlint: a linter for the railroad content of ASAM OpenDRIVE (.xodr) files.

``lint_file`` and ``lint_bytes`` are the Python API (see :mod:`xodrlint.api`); they are
imported on first use so that ``import xodrlint`` and the CLI start fast.
"""

from __future__ import annotations

import sys
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, Final

__version__ = "0.1.0"
__all__ = ["__version__", "lint_bytes", "lint_file"]

if TYPE_CHECKING:
    from xodrlint.api import lint_bytes, lint_file

#: Module paths of the flat layout, and the modules their names live in now (searched in
#: this order). They keep working until 0.2 through stand-in modules
#: (:mod:`xodrlint._moved`, loaded only when an old path is imported).
MOVED_MODULES: Final[Mapping[str, tuple[str, ...]]] = {
    "xodrlint.schema": ("xodrlint.validation.validators", "xodrlint.validation.libxml2"),
    "xodrlint.schemas": ("xodrlint.validation.sets",),
    "xodrlint.schemas.source": ("xodrlint.validation.source",),
    "xodrlint.schemas.store": ("xodrlint.validation.store",),
    "xodrlint.xsd_messages": ("xodrlint.validation.messages", "xodrlint.findings"),
    "xodrlint.xsd11": ("xodrlint.validation.xsd11.full",),
    "xodrlint.xsd10_form": ("xodrlint.validation.xsd11.form",),
    "xodrlint.xsd11_fast": (
        "xodrlint.validation.xsd11.fast",
        "xodrlint.validation.xsd11.alternatives",
    ),
    "xodrlint.background": ("xodrlint.workers.background",),
    "xodrlint.forkpool": ("xodrlint.workers.forkpool",),
    "xodrlint.batch": ("xodrlint.workers.batch",),
    "xodrlint.profile": ("xodrlint.model.lane_profiles",),
    "xodrlint.check": ("xodrlint.cli.check", "xodrlint.cli.notes", "xodrlint.cli.inputs"),
    "xodrlint.qc": ("xodrlint.cli.qc",),
    "xodrlint.docgen": ("xodrlint.cli.docgen",),
    "xodrlint.run": ("xodrlint.cli.rules", "xodrlint.cli.schemas", "xodrlint.cli.config"),
    "xodrlint.mapview.command": ("xodrlint.cli.map",),
}


class _OldPathFinder:
    """Answers for the old module paths only; every other import passes it by at the cost
    of one dict lookup."""

    is_xodrlint_old_path_finder = True

    @staticmethod
    def find_spec(fullname: str, path: object = None, target: object = None) -> Any:
        if fullname not in MOVED_MODULES:
            return None
        from xodrlint import _moved

        return _moved.spec_of(fullname, MOVED_MODULES[fullname])


# First in line: a folder left at an old path (a __pycache__ after switching branches in a
# checkout) would otherwise be imported as an empty namespace package.
if not any(getattr(finder, "is_xodrlint_old_path_finder", False) for finder in sys.meta_path):
    sys.meta_path.insert(0, _OldPathFinder)


def __getattr__(name: str) -> Any:
    if name in ("lint_file", "lint_bytes"):
        from xodrlint import api

        return getattr(api, name)
    if f"{__name__}.{name}" in MOVED_MODULES:  # xodrlint.batch without importing it first
        import importlib

        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'xodrlint' has no attribute {name!r}")
