"""Stage 4, rules: the rule API and the built-in rule packs.

A rule is a function of the :class:`~xodrlint.model.RailNetwork` that yields
:class:`~xodrlint.findings.Hit` values, wrapped by :func:`rule` with its code, name, UID
and default severity; its module docstring is its doc page. Rules do no I/O, know no
configuration and never print. A rule pack is a package of rule modules, registered
under the ``xodrlint.rules`` entry-point group (see :func:`collect`).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
import sys
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from types import ModuleType
from typing import Final

from xodrlint.findings import Hit, RuleMeta, Severity
from xodrlint.model import RailNetwork

__all__ = ["Hit", "RailNetwork", "Rule", "Severity", "collect", "rule"]

CheckFunction = Callable[[RailNetwork], Iterable[Hit]]

CODE_PATTERN: Final = re.compile(r"^[A-Z]{2,4}\d{3}$")
NAME_PATTERN: Final = re.compile(r"^[a-z][a-z0-9]*(?:-[a-z0-9]+)*$")


@dataclass(frozen=True, slots=True)
class Rule:
    meta: RuleMeta
    check: CheckFunction

    @property
    def code(self) -> str:
        return self.meta.code

    def __call__(self, network: RailNetwork) -> Iterator[Hit]:
        yield from self.check(network)


def rule(
    *,
    code: str,
    name: str,
    uid: str,
    severity: Severity,
    aliases: Iterable[str] = (),
) -> Callable[[CheckFunction], Rule]:
    """Declare a rule; the docstring of the module defining it is its doc page."""
    if not CODE_PATTERN.match(code):
        raise ValueError(f"rule code {code!r} is not two to four capitals and three digits")
    if not NAME_PATTERN.match(name):
        raise ValueError(f"rule name {name!r} is not kebab-case")

    def wrap(check: CheckFunction) -> Rule:
        module = sys.modules.get(check.__module__)
        doc = inspect.cleandoc(module.__doc__ or "") if module else ""
        first_line = doc.splitlines()[0] if doc else ""
        summary = first_line.split(":", 1)[1].strip() if ":" in first_line else first_line
        pack = check.__module__.rsplit(".", 1)[0]
        meta = RuleMeta(code, name, uid, severity, summary.rstrip("."), doc, tuple(aliases), pack)
        return Rule(meta, check)

    return wrap


def collect(package: ModuleType | str) -> tuple[Rule, ...]:
    """Every :class:`Rule` defined in ``package`` and its submodules, in code order."""
    module = importlib.import_module(package) if isinstance(package, str) else package
    found: dict[str, Rule] = {}
    for candidate in _modules(module):
        for value in vars(candidate).values():
            if isinstance(value, Rule):
                found.setdefault(value.code, value)
    return tuple(sorted(found.values(), key=lambda r: r.code))


def _modules(module: ModuleType) -> Iterator[ModuleType]:
    yield module
    path = getattr(module, "__path__", None)
    if path is None:
        return
    for info in pkgutil.iter_modules(path, module.__name__ + "."):
        yield from _modules(importlib.import_module(info.name))
