"""Which configuration governs each file of a run, as ruff resolves it: the nearest
``xodrlint.toml``, ``.xodrlint.toml`` or ``pyproject.toml`` with ``[tool.xodrlint]`` in
the file's folder or above it (:func:`~xodrlint.config.discovery.find_config`), with the command
line's options on top; ``--config FILE`` (or ``--isolated``: none) for every file alike.

A run's files fall into *profiles*, one per configuration file met, numbered in the
order they were met: a task names its profile, and each engine's workers keep one linter
per profile (:class:`~xodrlint.engine.profiles.Linters`). Profile 0 is the run's own: the
configuration of the folder that holds all its paths (``folders``), which also gives
what belongs to the run rather than to a file (:data:`RUN_KEYS`: the output format,
SARIF's result limit, whether walks respect ``.gitignore``, the file size limit), so
the order of the paths never changes a report.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Final

from xodrlint.config.discovery import config_folders, find_config, holds_config, search_stops_at
from xodrlint.config.settings import (
    COMMAND_LINE,
    DEFAULT_RULE_TIMEOUT,
    MAX_FOUND_RULE_TIMEOUT,
    ConfigError,
    ConfigFile,
    Settings,
    read_config,
    settings_from,
)
from xodrlint.engine.linter import LintOptions
from xodrlint.rules.options import declared_options
from xodrlint.rules.registry import Registry
from xodrlint.rules.selection import SelectorError, select_rules

Warn = Callable[[str], None]


class Resolver:
    """The settings and lint options of each path of a run (see the module's doc)."""

    def __init__(
        self,
        registry: Registry,
        overrides: Mapping[str, object] | None = None,
        *,
        config: Path | None = None,
        isolated: bool = False,
        folders: Sequence[Path] = (),
        warn: Warn | None = None,
        keep_source: bool = False,
        keep_suppressed: bool = False,
        check: bool = True,
    ) -> None:
        self._registry = registry
        self._check = check
        self._overrides = dict(overrides or {})
        self._said: set[str] = set()  # each warning once, however many folders meet it
        self._say = warn or (lambda _message: None)
        self._keep = {"keep_source": keep_source, "keep_suppressed": keep_suppressed}
        # --config and --isolated govern every file alike: no file is looked up
        self._fixed = isolated or config is not None
        self._by_folder: dict[Path, int] = {}
        self._by_file: dict[Path | None, int] = {}
        self.settings: list[Settings] = []
        """Each profile's settings, by profile number."""
        self.options: list[LintOptions] = []
        """Each profile's lint options, by profile number."""
        if isolated:
            first = None
        elif config is not None:
            first = read_config(config)
        else:
            first = self._run_config(folders)
        self._add(first, limit=config is None)

    def _run_config(self, folders: Sequence[Path]) -> ConfigFile | None:
        """The configuration of the deepest folder holding all of ``folders`` (those of
        the local paths a run lints; none: the working folder), when the search from one
        of them reaches it: a folder above two repositories governs neither."""
        if not folders:
            return self._found(Path.cwd())
        top = Path(os.path.commonpath(folders))  # absolute, as run_folders gives them
        found = self._found(top)
        if found is None or len(folders) == 1:
            return found
        home = found.path.parent.resolve()
        reached = any(home in config_folders(folder) for folder in folders)
        return found if reached else None

    @property
    def run(self) -> Settings:
        """The run's own settings: profile 0."""
        return self.settings[0]

    def profile_of(self, path: Path, *, folder: bool = False) -> int:
        """The profile of the file ``path`` (of the folder, with ``folder``): the nearest
        configuration above it, read once however many files it governs. Raises
        :class:`ConfigError` for a configuration that cannot be used."""
        if self._fixed:
            return 0
        return self._folder_profile(path if folder else path.parent)

    def working_profile(self) -> int:
        """The profile of what lies in no local folder (standard input without
        ``--stdin-filename``, an object by URL): the working folder's."""
        return self.profile_of(Path.cwd(), folder=True)

    def _folder_profile(self, folder: Path) -> int:
        # a folder without a configuration file of its own has its parent's: the walk up
        # is done once per folder of a run, not once per folder below it
        known = self._by_folder.get(folder)
        if known is not None:
            return known
        real = folder.resolve()
        profile = self._by_folder.get(real)
        if profile is None:
            if real.parent != real and not holds_config(real) and not search_stops_at(real):
                profile = self._folder_profile(real.parent)
            else:
                profile = self._add(self._found(real), limit=True)
        self._by_folder[folder] = self._by_folder[real] = profile
        return profile

    def settings_for(self, path: Path) -> Settings:
        """The settings that govern ``path``."""
        return self.settings[self.profile_of(path)]

    def _warn(self, message: str) -> None:
        if message not in self._said:
            self._said.add(message)
            self._say(message)

    def _found(self, folder: Path) -> ConfigFile | None:
        skipped: list[str] = []
        found = find_config(folder, skipped)
        for reason in skipped:
            self._warn(f"warning: {reason}")
        return found

    def _add(self, found: ConfigFile | None, *, limit: bool) -> int:
        key = found.path if found is not None else None
        known = self._by_file.get(key)
        if known is not None:
            return known
        registry = self._registry
        settings = settings_from(
            found,
            self._overrides,
            rule_options=declared_options(registry),
            known_codes=registry.by_code,
        )
        if found is not None and limit:
            settings = limited(settings, found.path, self._warn)
        if self.settings:  # a file's own: what belongs to the run is the run's
            settings = self._with_run_keys(settings, found)
        if self._check:
            _check(registry, settings)
        self._by_file[key] = len(self.settings)
        self.settings.append(settings)
        self.options.append(LintOptions.of(settings, **self._keep))
        return len(self.settings) - 1

    def _with_run_keys(self, settings: Settings, found: ConfigFile | None) -> Settings:
        """``settings`` with the run's values of :data:`RUN_KEYS`, and a warning when
        ``found`` set one of them otherwise (it applies only to a run from its folder)."""
        run = self.run
        differs = [
            key
            for key, field in RUN_KEYS.items()
            if getattr(settings, field) != getattr(run, field)
            and found is not None
            and settings.source_of(key) == str(found.path)
        ]
        if differs:
            self._warn(
                f"warning: {settings.config_file}: {', '.join(differs)} "
                f"{'applies' if len(differs) == 1 else 'apply'} to a whole run, whose "
                "own configuration is the one of the folder holding all its paths "
                f"({run.config_file or 'none'}): not used here"
            )
        sources = {**settings.sources}
        for key in RUN_KEYS:
            sources.pop(key, None)
            if key in run.sources:
                sources[key] = run.sources[key]
        values = {field: getattr(run, field) for field in RUN_KEYS.values()}
        return replace(settings, sources=sources, **values)


#: The settings of a whole run, not of a file (key: field of Settings): a run's output
#: and what it reads; a configuration below the run's folder does not change them.
RUN_KEYS: Final = {
    "output-format": "output_format",
    "sarif-max-results": "sarif_max_results",
    "respect-gitignore": "respect_gitignore",
    "max-file-size": "max_file_size",
}


#: The keys whose entries name rules, by the Settings field that holds them.
_SELECTIONS: Final = {"select": "select", "extend-select": "extend_select", "ignore": "ignore"}


def _check(registry: Registry, settings: Settings) -> None:
    """Refuse, before linting, settings no file could be linted with; an entry of a
    configuration file that names no rule is said with the file's name."""
    found = str(settings.config_file) if settings.config_file is not None else None
    for key, field in _SELECTIONS.items():
        if found is not None and settings.source_of(key) == found:
            try:
                select_rules(registry, getattr(settings, field), ())
            except SelectorError as error:
                raise ConfigError(f"{found}: '{key}': {error}") from None
    select_rules(registry, settings.selected, settings.ignore)  # the command line's
    if settings.schema is not None and not settings.schema.exists():
        source = settings.source_of("schema")
        if source == COMMAND_LINE:
            raise ConfigError(f"--schema {settings.schema}: no such file or folder")
        raise ConfigError(f"schema {settings.schema} (from {source}): no such file or folder")
    for _, selectors in settings.per_file_ignores:
        select_rules(registry, selectors, ())  # an entry that names no rule is an error


def limited(settings: Settings, found: Path, warn: Warn) -> Settings:
    """``settings`` with the rule time limit on, where a configuration found in a folder
    turned it off (0) or set it past :data:`~xodrlint.config.settings.MAX_FOUND_RULE_TIMEOUT`: the
    limit is what stops a runaway rule (a pattern of that very file), and only the user's
    own command line (``--rule-timeout``, or ``--config``) may lift it."""
    timeout = settings.rule_timeout
    if 0 < timeout <= MAX_FOUND_RULE_TIMEOUT or settings.source_of("rule-timeout") != str(found):
        return settings
    kept = DEFAULT_RULE_TIMEOUT if timeout == 0 else MAX_FOUND_RULE_TIMEOUT
    asked = "0 (no limit)" if timeout == 0 else f"{timeout:g}"
    warn(
        f"warning: {found}: rule-timeout = {asked} is taken only from the command line "
        f"or --config; rules keep a {kept:g} s limit"
    )
    sources = {**settings.sources, "rule-timeout": f"{found}, limited to {kept:g} s"}
    return replace(settings, rule_timeout=kept, sources=sources)
