"""Rule options: the values rules declare (``RuleOption``), checked and resolved once per
run, before any file is linted.

A value comes from a config file (already of its TOML type), from the command line
(``--rule-option NAME=VALUE``: text, read as its option takes it) or from the Python API;
every option the rules declare takes its default where none is given.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from xodrlint.config.settings import shown_value
from xodrlint.findings import RuleOption

if TYPE_CHECKING:
    from xodrlint.rules.registry import Registry

__all__ = ["OptionError", "command_line_options", "declared_options", "resolve_rule_options"]


class OptionError(ValueError):
    """A rule option that no rule declares, or a value the option does not take."""


def declared_options(registry: Registry) -> dict[str, RuleOption]:
    """Every option the registry's rules declare, by name (the first rule's declaration
    where two share a name)."""
    declared: dict[str, RuleOption] = {}
    for candidate in registry.rules:
        for option in candidate.meta.options:
            declared.setdefault(option.name, option)
    return declared


def resolve_rule_options(
    registry: Registry, values: Mapping[str, float | str]
) -> dict[str, float | str]:
    """Every option the registry's rules declare, with ``values`` laid over the defaults."""
    declared = declared_options(registry)
    resolved = {name: option.default for name, option in declared.items()}
    for name, value in values.items():
        if name not in declared:
            known = ", ".join(sorted(declared)) or "none"
            raise OptionError(f"unknown rule option '{name}' (known: {known})")
        try:
            resolved[name] = declared[name].checked(value)
        except TypeError as expected:
            shown = shown_value(value)
            raise OptionError(f"rule option '{name}' must be {expected}, got {shown}") from None
    return resolved


def command_line_options(
    registry: Registry, given: Mapping[str, float | str]
) -> dict[str, float | str]:
    """The rule options of a command line with each one's text (``--rule-option
    NAME=VALUE``) read as its option takes it: a number, a text, a regular expression."""
    declared = declared_options(registry)
    values: dict[str, float | str] = {}
    for name, value in given.items():
        option = declared.get(name)
        if option is None or not isinstance(value, str):
            values[name] = value  # an unknown name or a flag's number: resolve says
            continue
        try:
            values[name] = option.parsed(value)
        except TypeError as expected:
            shape = "NAME=NUMBER" if option.is_number else "NAME=VALUE"
            raise OptionError(
                f"--rule-option {name}={value}: expected {shape}, '{name}' takes {expected}"
            ) from None
    return values
