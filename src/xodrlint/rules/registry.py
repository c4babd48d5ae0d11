"""The rule registry: every rule pack installed under the ``xodrlint.rules`` entry points.

The built-in packs register the same way a third-party pack does. A pack that fails to
load, that was written for another rule API (``XODRLINT_RULE_API``), or that uses a code
prefix reserved for xodrlint's own rules is refused with one warning naming it; a rule
that reuses another pack's code is left out with a warning. The other packs still run.
"""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from types import ModuleType
from typing import Final, Protocol

from xodrlint.config.plugins import installed
from xodrlint.config.settings import SETTING_KEYS
from xodrlint.findings import PackInfo, RuleMeta
from xodrlint.rules import API_VERSION, RESERVED_PREFIXES, Rule, collect

ENTRY_POINT_GROUP: Final = "xodrlint.rules"
#: What a pack names, in the module its entry point names, to state the rule API it was
#: written for: ``XODRLINT_RULE_API = (1, 0)``.
API_DECLARATION: Final = "XODRLINT_RULE_API"
#: The package of the built-in packs: only they may use the reserved code prefixes.
BUILTIN_PACKAGE: Final = "xodrlint.rules"


class _Point(Protocol):
    """What a rule pack's entry point offers: an ``EntryPoint`` or a cached ``Plugin``."""

    @property
    def name(self) -> str: ...

    @property
    def value(self) -> str: ...

    def load(self) -> object: ...


class PackRefused(Exception):
    """A pack xodrlint does not load; the message says why, naming the pack."""


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
    for point in sorted(points, key=lambda p: (not _builtin(p), p.name)):
        try:
            pack = load_pack(point)
        except PackRefused as refusal:
            warnings.append(str(refusal))
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


def load_pack(point: _Point) -> tuple[Rule, ...]:
    """The rules of the pack ``point`` names, each with its :class:`PackInfo`; raises
    :class:`PackRefused` for a pack that cannot or must not run."""
    where = _describe(point)
    try:
        with contextlib.redirect_stdout(sys.stderr):  # a pack that prints on import
            loaded = point.load()
            pack = _rules_of(loaded)
    except KeyboardInterrupt:
        raise
    except BaseException as error:  # a broken pack, or one calling sys.exit, is skipped
        raise PackRefused(f"rule pack {where} failed to load: {error!r}") from None
    module = sys.modules.get(point.value.partition(":")[0].strip())
    declared = getattr(module, API_DECLARATION, None)
    if declared is not None:
        _check_api(where, declared)
    builtin = _builtin(point)
    reserved = [r.code for r in pack if r.code.startswith(RESERVED_PREFIXES) and not builtin]
    if reserved:
        raise PackRefused(
            f"rule pack {where} uses codes reserved for xodrlint's own rules "
            f"({', '.join(reserved)}; reserved: {', '.join(RESERVED_PREFIXES)}...): "
            "none of its rules run"
        )
    taken = sorted({o.name for r in pack for o in r.meta.options if o.name in SETTING_KEYS})
    if taken:
        raise PackRefused(
            f"rule pack {where} declares rule options named as xodrlint's own settings "
            f"({', '.join(taken)}): none of its rules run"
        )
    origin = PackInfo(point.name, *_distribution(point), builtin=builtin)
    return tuple(Rule(r.meta._replace(origin=origin), r.check) for r in pack)


def _check_api(where: str, declared: object) -> None:
    """Refuse a pack written for a rule API this xodrlint does not offer: another major
    (names removed or changed), or a newer minor (names this one lacks)."""
    if not (
        isinstance(declared, tuple)
        and len(declared) == 2
        and all(isinstance(part, int) and not isinstance(part, bool) for part in declared)
    ):
        raise PackRefused(
            f"rule pack {where} declares {API_DECLARATION} = {declared!r}, not (major, minor) "
            f"such as {API_VERSION!r}: none of its rules run"
        )
    major, minor = declared
    if major == API_VERSION[0] and minor <= API_VERSION[1]:
        return
    remedy = (
        "upgrade xodrlint"
        if (major, minor) > API_VERSION
        else f"install a release of the pack for rule API {API_VERSION[0]}.x"
    )
    raise PackRefused(
        f"rule pack {where} is written for rule API {major}.{minor}, but this xodrlint "
        f"has rule API {API_VERSION[0]}.{API_VERSION[1]}: none of its rules run ({remedy})"
    )


def _builtin(point: _Point) -> bool:
    module = point.value.partition(":")[0].strip()
    return module == BUILTIN_PACKAGE or module.startswith(BUILTIN_PACKAGE + ".")


def _distribution(point: _Point) -> tuple[str, str]:
    return getattr(point, "distribution", ""), getattr(point, "version", "")


def _describe(point: _Point) -> str:
    """``'house' (xodrlint_houserules, from xodrlint-houserules 0.1.0)``: the pack's name,
    what its entry point names, and the distribution to upgrade or remove."""
    distribution, version = _distribution(point)
    installed_by = f", from {distribution} {version}".rstrip() if distribution else ""
    return f"'{point.name}' ({point.value}{installed_by})"


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
