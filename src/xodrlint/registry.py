"""The rule registry: every rule pack installed under the ``xodrlint.rules`` entry points.

The built-in packs register the same way a third-party pack does. A pack that fails to
load, or that reuses a code, is a warning; the other packs still run.
"""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from types import ModuleType
from typing import Final, Protocol

from xodrlint.findings import RuleMeta
from xodrlint.plugins import installed
from xodrlint.rules import Rule, collect

ENTRY_POINT_GROUP: Final = "xodrlint.rules"


class _Point(Protocol):
    """What a rule pack's entry point offers: an ``EntryPoint`` or a cached ``Plugin``."""

    @property
    def name(self) -> str: ...

    @property
    def value(self) -> str: ...

    def load(self) -> object: ...


@dataclass(frozen=True)
class Registry:
    rules: tuple[Rule, ...]
    warnings: tuple[str, ...] = ()
    by_code: Mapping[str, Rule] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "by_code", {r.code: r for r in self.rules})

    @property
    def metas(self) -> tuple[RuleMeta, ...]:
        return tuple(r.meta for r in self.rules)

    def find(self, token: str) -> Rule | None:
        """A rule by code, name or any of its UIDs (case-insensitive code and name)."""
        upper = token.upper()
        for candidate in self.rules:
            meta = candidate.meta
            if upper == meta.code or token.lower() == meta.name or token in meta.uids:
                return candidate
        return None


def load_registry(points: Iterable[_Point] | None = None) -> Registry:
    if points is None:
        points = installed(ENTRY_POINT_GROUP)
    rules: dict[str, Rule] = {}
    warnings: list[str] = []
    for point in sorted(points, key=lambda p: (p.value.startswith("xodrlint.") is False, p.name)):
        try:
            with contextlib.redirect_stdout(sys.stderr):  # a pack that prints on import
                loaded = point.load()
                pack = _rules_of(loaded)
        except KeyboardInterrupt:
            raise
        except BaseException as error:  # a broken pack, or one calling sys.exit, is skipped
            warnings.append(f"rule pack '{point.name}' ({point.value}) failed to load: {error!r}")
            continue
        for candidate in pack:
            if candidate.code in rules:
                warnings.append(
                    f"rule pack '{point.name}' redefines {candidate.code}; "
                    f"keeping the one from '{rules[candidate.code].meta.pack}'"
                )
                continue
            rules[candidate.code] = candidate
    ordered = tuple(sorted(rules.values(), key=lambda r: r.code))
    return Registry(ordered, tuple(warnings))


def _rules_of(loaded: object) -> tuple[Rule, ...]:
    if isinstance(loaded, ModuleType):
        return collect(loaded)
    if isinstance(loaded, Rule):
        return (loaded,)
    if isinstance(loaded, Iterable):
        items = tuple(loaded)
        if all(isinstance(item, Rule) for item in items):
            return items
    raise TypeError(f"expected a module, a Rule or rules, got {type(loaded).__name__}")
