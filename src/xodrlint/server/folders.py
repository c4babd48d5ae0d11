"""The linter for a document: the configuration that governs its folder, found as the
command line finds it (the nearest ``xodrlint.toml`` or ``pyproject.toml`` with
``[tool.xodrlint]``), reloaded when that file changes."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import NamedTuple

from xodrlint.config.discovery import CONFIG_NAMES, config_folders, find_config
from xodrlint.config.settings import (
    DEFAULT,
    DEFAULT_RULE_TIMEOUT,
    ConfigError,
    ConfigFile,
    Settings,
    settings_from,
)
from xodrlint.engine.fixing import FixPolicy
from xodrlint.engine.linter import Linter, LintOptions
from xodrlint.rules.options import declared_options
from xodrlint.rules.registry import Registry
from xodrlint.rules.selection import SelectorError


class Choice(NamedTuple):
    """A folder's settings and linter and, when its configuration could not be used, why
    not (the defaults apply then)."""

    settings: Settings
    linter: Linter
    problem: str | None = None

    def excluded(self, path: Path) -> bool:
        """Whether the configuration's ``exclude`` leaves ``path`` out, as it does on the
        command line even for a file named there."""
        return self.settings.excludes(path)

    def external(self, path: Path) -> tuple[tuple[str, str], ...]:
        """The ``per-file-ignores`` selectors that apply to ``path``, as ``check`` applies
        them: (selector, where it was set)."""
        return self.settings.ignored_in(path)


def _stamp(folder: Path) -> tuple[tuple[str, int], ...]:
    """What decides a folder's configuration: the config files in it and above it, with
    their modification times, so an edit (or a new file) is noticed on the next lint."""
    found = []
    for candidate in config_folders(folder):
        for name in CONFIG_NAMES:
            try:
                found.append((str(candidate / name), (candidate / name).stat().st_mtime_ns))
            except OSError:
                continue
    return tuple(found)


class Folders:
    """One linter per folder, rebuilt when the folder's configuration files change.

    In a workspace the editor does not trust (``trusted=False``), a configuration file
    still selects rules and sets severities, but what would let a repository's content
    run or read on the user's machine is not taken from it: the ``schema`` (a file
    xodrlint reads and compiles), rule options (values rules run with, patterns among
    them) and ``rule-timeout`` (how long a rule may run)."""

    def __init__(self, registry: Registry, *, trusted: bool = True) -> None:
        self._registry = registry
        self._trusted = trusted
        self._chosen: dict[Path, tuple[tuple[tuple[str, int], ...], Choice]] = {}

    def linter_for(self, path: Path) -> Choice:
        folder = path.parent.resolve()
        stamp = _stamp(folder)
        cached = self._chosen.get(folder)
        if cached is not None and cached[0] == stamp:
            return cached[1]
        choice = self._choose(folder)
        self._chosen[folder] = (stamp, choice)
        return choice

    def forget(self) -> None:
        """Drop every linter (a watched configuration file changed)."""
        self._chosen.clear()

    def _choose(self, folder: Path) -> Choice:
        problems: list[str] = []
        try:
            found = find_config(folder, problems)
            settings = self._settings(found, problems)
            return Choice(settings, self._linter(settings), "; ".join(problems) or None)
        except (ConfigError, SelectorError, ValueError) as error:
            # the defaults, and the reason, rather than no diagnostics at all
            defaults = self._settings(None, [])
            return Choice(defaults, self._linter(defaults), str(error))

    def _settings(self, found: ConfigFile | None, problems: list[str]) -> Settings:
        registry = self._registry
        settings = settings_from(
            found, {}, rule_options=declared_options(registry), known_codes=registry.by_code
        )
        if not self._trusted and found is not None:
            settings, dropped = _without_workspace_powers(settings)
            if dropped:
                problems.append(
                    f"the workspace is not trusted: {', '.join(dropped)} from {found.path} not used"
                )
        if settings.schema is not None and not settings.schema.exists():
            raise ConfigError(f"schema {settings.schema}: no such file or folder")
        return settings

    def _linter(self, settings: Settings) -> Linter:
        # the editor's fixes: every finding's edits placed, safe ones made by fixAll (a
        # configuration's ``fix`` never writes a file from here)
        options = LintOptions.of(settings)._replace(
            place_fixes=True,
            fixes=FixPolicy(fixable=settings.fixable, unfixable=settings.unfixable),
        )
        return Linter(self._registry, options)


def _without_workspace_powers(settings: Settings) -> tuple[Settings, list[str]]:
    """``settings`` without the schema, rule options and rule timeout a file set; the
    keys dropped."""
    dropped = [
        key
        for key in ("schema", *sorted(settings.rule_options), "rule-timeout")
        if settings.source_of(key) != DEFAULT
    ]
    kept = {key: source for key, source in settings.sources.items() if key not in dropped}
    return (
        replace(
            settings,
            schema=None,
            rule_options={},
            rule_timeout=DEFAULT_RULE_TIMEOUT,
            sources=kept,
        ),
        dropped,
    )
