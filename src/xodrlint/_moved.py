"""Old import paths, kept working for one release (they go in xodrlint 0.2).

The package took its pipeline layout before 0.2 (``validation/``, ``cli/``, ``workers/``,
``model/``); code written against the flat layout (``xodrlint.schemas``,
``xodrlint.batch``, ...) still imports. An old path gives a stand-in module that hands
out each name from where it lives now, with a ``DeprecationWarning`` naming that place,
once per name. ``python -m`` on an old path runs the new module.

A finder at the end of ``sys.meta_path`` (put there by ``xodrlint/__init__``) serves
the old paths, so the tree holds no stub files a newcomer would open first; an import
that finds a real module never asks it, and this module is read only when one is asked.
"""

from __future__ import annotations

import types
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any, Final, cast

if TYPE_CHECKING:
    from importlib.abc import Loader

#: Where the names of each old module live now (searched in this order).
MOVED: Final[Mapping[str, tuple[str, ...]]] = {
    "xodrlint.schema": ("xodrlint.validation.validators", "xodrlint.validation.libxml2"),
    "xodrlint.schemas": ("xodrlint.validation.sets",),
    "xodrlint.schemas.source": ("xodrlint.validation.source",),
    "xodrlint.schemas.store": ("xodrlint.validation.store",),
    "xodrlint.xsd_messages": ("xodrlint.validation.messages",),
    "xodrlint.xsd11": ("xodrlint.validation.xsd11.full",),
    "xodrlint.xsd10_form": ("xodrlint.validation.xsd11.form",),
    "xodrlint.xsd11_fast": (
        "xodrlint.validation.xsd11.fast",
        "xodrlint.validation.xsd11.alternatives",
        "xodrlint.validation.xsd11.assertions",
        "xodrlint.validation.xsd11.governing",
        "xodrlint.validation.xsd11.recovery",
    ),
    "xodrlint.background": ("xodrlint.workers.background",),
    "xodrlint.forkpool": ("xodrlint.workers.forkpool",),
    "xodrlint.batch": ("xodrlint.workers.batch",),
    "xodrlint.profile": ("xodrlint.model.lane_profiles",),
    "xodrlint.check": ("xodrlint.cli.check",),
    "xodrlint.qc": ("xodrlint.cli.qc",),
    "xodrlint.docgen": ("xodrlint.cli.docgen",),
    "xodrlint.run": ("xodrlint.cli.rules", "xodrlint.cli.schemas", "xodrlint.cli.config"),
    "xodrlint.mapview.command": ("xodrlint.cli.map",),
}
#: Old paths that were packages: their submodules are old paths too.
_PACKAGES: Final = frozenset({"xodrlint.schemas"})
REMOVED_IN: Final = "0.2"

# The spec class of every imported module; taken from this one so that importing
# xodrlint does not import importlib (and warnings) for a path hardly anyone uses.
_ModuleSpec: Final = type(__spec__)


class MovedModule(types.ModuleType):
    """Stands in for a module that moved: each name is looked up where it lives now."""

    def __init__(self, name: str, targets: Sequence[str]) -> None:
        super().__init__(name, f"Moved: {', '.join(targets)}.")
        self.__targets = tuple(targets)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):  # asked by import machinery and tools: not a moved name
            raise AttributeError(name)
        import importlib
        import warnings

        for target in self.__targets:
            module = importlib.import_module(target)
            if hasattr(module, name):
                value = getattr(module, name)
                # a name one new module imports from another is named where it is defined
                home = getattr(value, "__module__", None)
                where = home if home in self.__targets else target
                warnings.warn(
                    f"{self.__name__}.{name} moved to {where}.{name}; the old path "
                    f"goes in xodrlint {REMOVED_IN}",
                    DeprecationWarning,
                    stacklevel=2,
                )
                setattr(self, name, value)  # warned once: later reads find it here
                return value
        raise AttributeError(f"module {self.__name__!r} has no attribute {name!r}")

    def __dir__(self) -> list[str]:
        import importlib

        names = set(super().__dir__())
        for target in self.__targets:
            names.update(n for n in dir(importlib.import_module(target)) if not n.startswith("__"))
        return sorted(names)


class _MovedLoader:
    def create_module(self, spec: Any) -> types.ModuleType:
        return MovedModule(spec.name, MOVED[spec.name])

    def exec_module(self, module: types.ModuleType) -> None:
        """Nothing to run: the names are fetched when asked for."""

    def get_code(self, fullname: str) -> types.CodeType:
        """What ``python -m OLD.PATH`` runs: the module's new path, as ``__main__``."""
        target = MOVED[fullname][0]
        source = (
            "import runpy, sys\n"
            f"print('xodrlint: {fullname} moved to {target}; run python -m {target}',"
            " file=sys.stderr)\n"
            f"runpy.run_module({target!r}, run_name='__main__', alter_sys=True)\n"
        )
        return compile(source, f"<{fullname}, moved to {target}>", "exec")


_LOADER: Final = _MovedLoader()


def find_spec(fullname: str) -> Any:
    """The spec of an old path, or ``None`` (asked by the finder in ``xodrlint/__init__``
    only after every real finder has said no)."""
    if fullname not in MOVED:
        return None
    loader = cast("Loader", _LOADER)  # duck-typed: importlib.abc costs an import
    return _ModuleSpec(fullname, loader, is_package=fullname in _PACKAGES)
