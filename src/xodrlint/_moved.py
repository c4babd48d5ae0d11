"""Old import paths, kept working for one release (they go in xodrlint 0.2).

The package took its pipeline layout (``validation/``, ``cli/``, ``workers/``,
``model/``) before 0.2; code written against the flat layout (``xodrlint.schemas``,
``xodrlint.batch``, ...) still imports. An old path gives a stand-in module that hands
out each name from where it lives now, with a ``DeprecationWarning`` naming that place
(once per name); a name set or deleted through it (``mock.patch``, ``monkeypatch``) is
set or deleted where the code that reads it lives. ``python -m`` on an old path runs the
new module. Names of the old modules that began with ``_`` were never API and are not
kept.

The table of old paths is ``xodrlint.MOVED_MODULES``; the finder that serves them
(in ``xodrlint/__init__``) loads this module only when one is imported, so the tree holds
no stub files a newcomer would open first. Type checkers do not see old paths: typed
code must import from the new ones.
"""

from __future__ import annotations

import importlib
import types
import warnings
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Final, cast

if TYPE_CHECKING:
    from importlib.abc import Loader

REMOVED_IN: Final = "0.2"
#: Old paths that were packages: their submodules are old paths too.
_PACKAGES: Final = frozenset({"xodrlint.schemas"})
#: Where a name is best imported from when the module defining it re-exports it.
_PUBLIC_HOME: Final = {"xodrlint.model.network": "xodrlint.model"}
_TARGETS: Final = "__xodrlint_targets__"
_WARNED: Final = "__xodrlint_warned__"
_PATCHED: Final = "__xodrlint_patched__"
_ABSENT: Final = object()


def moved_name(old_module: str, name: str, targets: Sequence[str], warned: set[str]) -> Any:
    """``name`` of ``old_module``, found in ``targets``, with a warning naming its home
    the first time (``warned`` remembers). ``AttributeError`` when no target has it."""
    for target in targets:
        module = importlib.import_module(target)
        if hasattr(module, name):
            value = getattr(module, name)
            if name not in warned:
                warned.add(name)
                warnings.warn(
                    f"{old_module}.{name} moved to {_home(value, name, target)}.{name}; "
                    f"the old path goes in xodrlint {REMOVED_IN}",
                    DeprecationWarning,
                    stacklevel=3,
                )
            return value
    raise AttributeError(f"module {old_module!r} has no attribute {name!r}")


def _home(value: object, name: str, found_in: str) -> str:
    """Where ``value`` is defined (or publicly re-exported) under ``name``, else where it
    was found: constants carry no module of their own, and an alias kept for an old name
    (``Case`` for ``RuleCase``) lives only where it was found."""
    defined = getattr(value, "__module__", None)
    if isinstance(defined, str) and defined.startswith("xodrlint."):
        home = _PUBLIC_HOME.get(defined, defined)
        if getattr(importlib.import_module(home), name, _ABSENT) is value:
            return home
    return found_in


def _dunder(name: str) -> bool:
    return name.startswith("__") and name.endswith("__")


class MovedModule(types.ModuleType):
    """Stands in for a module that moved: each name is looked up, set and deleted where it
    lives now, never kept here (a patched name must stay patched for its readers)."""

    def __init__(self, name: str, targets: Sequence[str]) -> None:
        super().__init__(name, f"Moved: {', '.join(targets)}.")
        self.__dict__[_TARGETS] = tuple(targets)
        self.__dict__[_WARNED] = set()
        self.__dict__[_PATCHED] = {}

    def __getattr__(self, name: str) -> Any:
        targets: tuple[str, ...] = self.__dict__[_TARGETS]
        if name == "__all__":  # what ``from OLD import *`` takes
            return sorted({n for t in targets for n in _public_names(t)})
        if _dunder(name):  # asked by import machinery and tools: not a moved name
            raise AttributeError(name)
        return moved_name(self.__name__, name, targets, self.__dict__[_WARNED])

    def __setattr__(self, name: str, value: Any) -> None:
        if _dunder(name):
            super().__setattr__(name, value)
            return
        holders = self._holders(name) or [importlib.import_module(self.__dict__[_TARGETS][0])]
        patched: dict[str, list[tuple[types.ModuleType, Any]]] = self.__dict__[_PATCHED]
        # the first value set is remembered: deleting the name puts it back (see below)
        patched.setdefault(name, [(module, vars(module).get(name, _ABSENT)) for module in holders])
        for module in holders:
            setattr(module, name, value)

    def __delattr__(self, name: str) -> None:
        """Undo what was set through this stand-in, or delete the name where it lives.
        Patching tools that see no ``name`` in this module's ``__dict__`` (mock, pytest's
        monkeypatch) undo a patch by deleting: that must bring the original back."""
        if _dunder(name):
            super().__delattr__(name)
            return
        originals = self.__dict__[_PATCHED].pop(name, None)
        if originals is None:
            holders = self._holders(name)
            if not holders:
                raise AttributeError(name)
            originals = [(module, _ABSENT) for module in holders]
        for module, original in originals:
            if original is _ABSENT:
                vars(module).pop(name, None)
            else:
                setattr(module, name, original)

    def _holders(self, name: str) -> list[types.ModuleType]:
        """The new modules that hold ``name``: the old module's one binding is now read
        in each of them."""
        modules = [importlib.import_module(t) for t in self.__dict__[_TARGETS]]
        return [module for module in modules if name in vars(module)]

    def __dir__(self) -> list[str]:
        names = set(super().__dir__()) - {_TARGETS, _WARNED, _PATCHED}
        for target in self.__dict__[_TARGETS]:
            names.update(_public_names(target))
        return sorted(names)


def _public_names(target: str) -> list[str]:
    module = importlib.import_module(target)
    return [name for name in vars(module) if not name.startswith("_")]


class _MovedLoader:
    def __init__(self, targets: tuple[str, ...]) -> None:
        self.targets = targets

    def create_module(self, spec: Any) -> types.ModuleType:
        return MovedModule(spec.name, self.targets)

    def exec_module(self, module: types.ModuleType) -> None:
        """Nothing to run: the names are fetched when asked for."""

    def get_code(self, fullname: str) -> types.CodeType:
        """What ``python -m OLD.PATH`` runs: the module's new path, as ``__main__``."""
        target = self.targets[0]
        source = (
            "import runpy, sys\n"
            f"print('xodrlint: {fullname} moved to {target}; run python -m {target}',"
            " file=sys.stderr)\n"
            f"runpy.run_module({target!r}, run_name='__main__', alter_sys=True)\n"
        )
        return compile(source, f"<{fullname}, moved to {target}>", "exec")


def spec_of(fullname: str, targets: tuple[str, ...]) -> Any:
    """The spec of the stand-in for the old path ``fullname``, whose names now live in
    ``targets``."""
    from importlib.machinery import ModuleSpec

    loader = cast("Loader", _MovedLoader(targets))  # duck-typed, as importlib accepts
    return ModuleSpec(fullname, loader, is_package=fullname in _PACKAGES)
