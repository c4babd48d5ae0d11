"""Stage 4, rules: the rule API and the built-in rule packs.

A rule is a function of the :class:`~xodrlint.model.RailNetwork` that yields
:class:`~xodrlint.findings.Hit` values, wrapped by :func:`rule` with its code, name, UID
and default severity; its module docstring is its doc page. A rule that declares
:class:`~xodrlint.findings.RuleOption` values takes them as a second argument, already
resolved (user value or default). Rules do no I/O, never read configuration themselves
and never print. A rule pack is a package of rule modules, registered
under the ``xodrlint.rules`` entry-point group (see :func:`collect`).

``__all__`` is the rule API: every name a pack may import, from here, and rely on while
:data:`API_VERSION`'s major number stays the same (docs/plugins.md; a test keeps the
list). The model types are re-exported so that a pack imports from one place.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
import sys
from collections.abc import Callable, Iterable, Iterator, Mapping
from types import ModuleType
from typing import Final, NamedTuple

from xodrlint.findings import (
    CHILD_KINDS,
    OPTION_KINDS,
    Hit,
    RuleMeta,
    RuleOption,
    Severity,
    doc_summary,
)
from xodrlint.fixes import (
    Applicability,
    Fix,
    insert_element,
    remove_comment,
    replace_comment,
    set_attribute,
)
from xodrlint.model import (
    NON_TRAFFIC_LANE_TYPES,
    RAIL_LANE_TYPES,
    Connection,
    Cubic,
    Junction,
    JunctionLaneLink,
    Lane,
    LaneLink,
    LaneSection,
    PartnerRef,
    Platform,
    RailNetwork,
    Road,
    RoadLanes,
    RoadLink,
    Segment,
    Station,
    Switch,
    TrackRef,
    integer,
    non_finite,
    number,
    numbers,
    section_ranges,
)
from xodrlint.model.lane_profiles import (
    S_TOLERANCE,
    Extremes,
    Piecewise,
    centre_terms,
    extremes,
    lane_width,
)

__all__ = [
    "API_VERSION",
    "CHILD_KINDS",
    "NON_TRAFFIC_LANE_TYPES",
    "RAIL_LANE_TYPES",
    "RESERVED_PREFIXES",
    "S_TOLERANCE",
    "Applicability",
    "Connection",
    "Cubic",
    "Extremes",
    "Fix",
    "Hit",
    "Junction",
    "JunctionLaneLink",
    "Lane",
    "LaneLink",
    "LaneSection",
    "PartnerRef",
    "Piecewise",
    "Platform",
    "RailNetwork",
    "Road",
    "RoadLanes",
    "RoadLink",
    "Rule",
    "RuleOption",
    "Segment",
    "Settings",
    "Severity",
    "Station",
    "Switch",
    "TrackRef",
    "centre_terms",
    "collect",
    "extremes",
    "insert_element",
    "integer",
    "lane_width",
    "non_finite",
    "number",
    "numbers",
    "remove_comment",
    "replace_comment",
    "rule",
    "section_ranges",
    "set_attribute",
]

#: The rule API's version, ``(major, minor)``: the minor grows when names or fields are
#: added, the major when one is removed, renamed or changes meaning. A pack states the
#: version it was written for as ``XODRLINT_RULE_API`` in the module its entry point
#: names; a pack of another major, or of a newer minor, is not loaded.
API_VERSION: Final = (1, 3)

#: Code prefixes of the built-in rule families, and ``X`` for the linter's own (XS, XL,
#: and families to come). A third-party pack whose codes start with one of them is not
#: loaded: ``--select SW`` must keep meaning the switch rules.
RESERVED_PREFIXES: Final = ("PT", "RL", "ST", "SW", "TR", "X")

Settings = Mapping[str, float | str]
"""Option values by option name (read them with :meth:`RuleOption.number` and
:meth:`RuleOption.text`)."""
PlainCheck = Callable[[RailNetwork], Iterable[Hit]]
ConfiguredCheck = Callable[[RailNetwork, Settings], Iterable[Hit]]

CODE_PATTERN: Final = re.compile(r"^[A-Z]{2,4}\d{3}$")
NAME_PATTERN: Final = re.compile(r"^[a-z][a-z0-9]*(?:-[a-z0-9]+)*$")


class Rule(NamedTuple):
    """A declared rule: what reports know of it (its code, name, UID, doc page) and its
    check. :func:`rule` makes one; calling it runs the check."""

    meta: RuleMeta
    check: ConfiguredCheck

    @property
    def code(self) -> str:
        return self.meta.code

    def __call__(self, network: RailNetwork, settings: Settings | None = None) -> Iterator[Hit]:
        """Run the rule; without ``settings`` its options take their defaults (the engine
        passes every option already resolved)."""
        if settings is None:
            settings = {option.name: option.default for option in self.meta.options}
        yield from self.check(network, settings)


def rule(
    *,
    code: str,
    name: str,
    uid: str,
    severity: Severity,
    aliases: Iterable[str] = (),
    options: Iterable[RuleOption] = (),
    defers_to: Iterable[str] = (),
    opt_in: bool = False,
    since: tuple[int, int] | None = None,
) -> Callable[[PlainCheck | ConfiguredCheck], Rule]:
    """Declare a rule; the docstring of the module defining it is its doc page.

    ``defers_to`` names the more specific rules that report a defect this rule would
    also see on the same element (one defect, one finding); the engine withdraws this
    rule's finding there when one of them reports it. An ``opt_in`` rule is off by
    default: it runs only when a selection names it (see :attr:`RuleMeta.opt_in`).
    ``since`` is the first OpenDRIVE version, ``(major, minor)``, the rule applies to
    (a convention a later version introduced): files declaring an older one are not
    judged by it unless the run asks for every version (see :attr:`RuleMeta.since`).
    Rule API 1.1.
    """
    if not CODE_PATTERN.match(code):
        raise ValueError(f"rule code {code!r} is not two to four capitals and three digits")
    if not NAME_PATTERN.match(name):
        raise ValueError(f"rule name {name!r} is not kebab-case")
    first_version = _checked_since(code, since)
    declared = tuple(options)
    for option in declared:
        _check_declaration(code, option)

    def wrap(check: PlainCheck | ConfiguredCheck) -> Rule:
        module = sys.modules.get(check.__module__)
        doc = inspect.cleandoc(module.__doc__ or "") if module else ""
        pack = check.__module__.rsplit(".", 1)[0]
        meta = RuleMeta(
            code,
            name,
            uid,
            severity,
            doc_summary(doc),
            doc,
            tuple(aliases),
            pack,
            declared,
            tuple(defers_to),
            opt_in,
            since=first_version,
        )
        return Rule(meta, _configured(check, takes_settings=bool(declared)))

    return wrap


def _checked_since(code: str, since: object) -> tuple[int, int] | None:
    """``since`` as the engine compares it; a pack's mistake is its import's error."""
    if since is None:
        return None
    if (
        not isinstance(since, tuple | list)
        or len(since) != 2
        or not all(isinstance(part, int) and not isinstance(part, bool) for part in since)
        or min(since) < 0
    ):
        raise ValueError(
            f"{code}: since={since!r} is not an OpenDRIVE version (major, minor), e.g. (1, 7)"
        )
    return (since[0], since[1])


def _check_declaration(code: str, option: RuleOption) -> None:
    """A pack's mistake in an option is its import's error (the pack is skipped with a
    warning), not every user's error later."""
    if not NAME_PATTERN.match(option.name):
        raise ValueError(f"{code}: option name {option.name!r} is not kebab-case")
    if option.kind not in OPTION_KINDS:
        raise ValueError(f"{code}: option {option.name!r} has kind {option.kind!r}")
    try:
        option.checked(option.default)
    except TypeError as expected:
        raise ValueError(
            f"{code}: option {option.name!r} defaults to {option.default!r}, not {expected}"
        ) from None


def _configured(check: PlainCheck | ConfiguredCheck, *, takes_settings: bool) -> ConfiguredCheck:
    if takes_settings:
        return check  # type: ignore[return-value]
    plain: PlainCheck = check  # type: ignore[assignment]
    return lambda network, _settings: plain(network)


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
