"""Configuration: ``[tool.xodrlint]`` in ``pyproject.toml``, or ``xodrlint.toml`` /
``.xodrlint.toml`` (found by :mod:`xodrlint.config.discovery`), read and checked;
command-line values win.

Every effective value remembers where it came from, for ``xodrlint config``. An unknown
key or a value of the wrong type is a :class:`ConfigError` naming the key and the file.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Final, NamedTuple

from xodrlint.config.sizes import DEFAULT_MAX_FILE_SIZE, format_size, parse_size
from xodrlint.findings import RuleOption, Severity
from xodrlint.inputs.files import os_reason
from xodrlint.inputs.globs import any_match, glob_matches

DEFAULT: Final = "default"
COMMAND_LINE: Final = "command line"
#: Seconds a rule may run on one file unless ``rule-timeout`` says otherwise.
DEFAULT_RULE_TIMEOUT: Final = 60.0
#: GitHub code scanning rejects a SARIF run with more results than this.
DEFAULT_SARIF_MAX_RESULTS: Final = 25_000


class ConfigError(ValueError):
    """A configuration file that cannot be used; the message names the file and the key."""


class ConfigFile(NamedTuple):
    path: Path
    table: Mapping[str, Any]
    section: str | None = None
    """``tool.xodrlint`` when the settings are in that table, ``None`` at the top level."""

    @property
    def base(self) -> Path:
        """Relative paths and globs in the file are relative to its folder."""
        return self.path.parent


def read_config(path: Path, *, required: bool = True) -> ConfigFile | None:
    """Read one file; a ``pyproject.toml`` without ``[tool.xodrlint]`` gives ``None``
    (an error when ``required``).

    A ``pyproject.toml`` holds the settings in ``[tool.xodrlint]``. Any other file (an
    ``xodrlint.toml``, or whatever ``--config`` names) holds them either at its top level
    or in a ``[tool.xodrlint]`` table, as pyproject.toml does; not both.
    """
    import tomllib  # only runs that find a config file pay for it

    try:
        document = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as error:
        raise ConfigError(f"{path}: cannot read: {os_reason(error)}") from error
    except (ValueError, RecursionError) as error:  # TOMLDecodeError is a ValueError
        reason = "nested too deeply" if isinstance(error, RecursionError) else str(error)
        raise ConfigError(f"{path}: not valid TOML: {reason}") from error
    tool = document.get("tool")
    table = tool.get("xodrlint") if isinstance(tool, dict) else None
    if table is None and path.name == "pyproject.toml":
        if required:
            raise ConfigError(f"{path}: has no [tool.xodrlint] table")
        return None
    if table is None:
        return ConfigFile(path, document)
    if not isinstance(table, dict):
        raise ConfigError(f"{path}: [tool.xodrlint] must be a table")
    # beside [tool.xodrlint], a file may hold other tables ([project], [tool.ruff]), but
    # no setting: xodrlint's keys, and any plain value, are settings in the wrong place
    stray = [
        key
        for key, value in document.items()
        if key != "tool" and (key in _READERS or not isinstance(value, dict))
    ]
    if stray:
        raise ConfigError(
            f"{path}: has settings both in [tool.xodrlint] and at its top level "
            f"('{stray[0]}'); keep one of the two"
        )
    return ConfigFile(path, table, "tool.xodrlint")


@dataclass(frozen=True)
class Settings:
    """The effective configuration of a run, with the source of each value."""

    select: tuple[str, ...] = ("ALL",)
    extend_select: tuple[str, ...] = ()
    ignore: tuple[str, ...] = ()
    per_file_ignores: tuple[tuple[str, tuple[str, ...]], ...] = ()
    """(glob, selectors) pairs; globs are relative to :attr:`base`."""
    severity: Mapping[str, Severity] = field(default_factory=dict)
    fail_on: Severity = Severity.WARNING
    schema: Path | None = None
    output_format: str = "text"
    sarif_max_results: int = DEFAULT_SARIF_MAX_RESULTS
    """At most this many results in a SARIF log, the most important; 0: no limit."""
    exclude: tuple[str, ...] = ()
    respect_gitignore: bool = True
    """Whether folder walks leave out what .gitignore, .ignore and info/exclude exclude."""
    rule_options: Mapping[str, float | str] = field(default_factory=dict)
    """The rule options a config file or the command line set; the rest keep defaults."""
    option_defaults: Mapping[str, float | str] = field(default_factory=dict)
    """Every rule option the rules declare, a plugin's too, with its default."""
    warn_unused_suppressions: bool = False
    all_versions: bool = False
    xsd_scope: str = "all"
    """``railroad``: schema errors (XS006) outside the railroad content are counted in a
    note instead of listed (:class:`~xodrlint.engine.linter.LintOptions`)."""
    """Apply every rule to every OpenDRIVE version, also those that apply only from a
    later version than a file declares (RL001, RL002 from 1.7)."""
    max_file_size: int = DEFAULT_MAX_FILE_SIZE
    fix: bool = False
    """Apply the fixes and write the files back (``--fix``, ``fix = true``)."""
    diff: bool = False
    """Show what ``--fix`` would change, write nothing (``--diff``: the command line's)."""
    unsafe_fixes: bool = False
    """Make the unsafe fixes too (``--unsafe-fixes``)."""
    fixable: tuple[str, ...] = ("ALL",)
    """The rules whose fixes count (codes, prefixes, names, UIDs, as ``select``)."""
    unfixable: tuple[str, ...] = ()
    """The rules whose fixes never count, where named more closely than in ``fixable``."""
    rule_timeout: float = DEFAULT_RULE_TIMEOUT
    """Seconds a rule may run on one file; 0: no limit."""
    base: Path = field(default_factory=Path.cwd)
    config_file: Path | None = None
    sources: Mapping[str, str] = field(default_factory=dict)

    @property
    def fix_mode(self) -> str:
        """``diff``, ``apply`` (``--fix``) or empty: what a check does with fixes."""
        return "diff" if self.diff else "apply" if self.fix else ""

    @property
    def selected(self) -> tuple[str, ...]:
        return (*self.select, *self.extend_select)

    def source_of(self, key: str) -> str:
        return self.sources.get(key, DEFAULT)

    def ignored_in(self, path: Path | str) -> tuple[tuple[str, str], ...]:
        """The ``per-file-ignores`` selectors that apply to ``path``, each with where it
        was set: a local file, or the path part of a URL (``maps/a.xodr``), matched as it
        stands (it lies below no local folder)."""
        where = f"per-file-ignores in {self.config_file or 'the command line'}"
        return tuple(
            (selector, f"{where} ({glob})")
            for glob, selectors in self.per_file_ignores
            if (
                any_match([glob], path, self.base)
                if isinstance(path, Path)
                else glob_matches(glob, path)
            )
            for selector in selectors
        )

    def excludes(self, path: Path) -> bool:
        """Whether ``exclude`` leaves the local file ``path`` out (its globs are relative
        to :attr:`base`), also a file named on the command line."""
        return bool(self.exclude) and any_match(self.exclude, path, self.base)

    def as_rows(self) -> list[tuple[str, object, str]]:
        """(key, value, source) for ``xodrlint config``, in a stable order."""
        rows: list[tuple[str, object, str]] = [
            ("select", list(self.select), self.source_of("select")),
            ("extend-select", list(self.extend_select), self.source_of("extend-select")),
            ("ignore", list(self.ignore), self.source_of("ignore")),
            (
                "per-file-ignores",
                {glob: list(codes) for glob, codes in self.per_file_ignores},
                self.source_of("per-file-ignores"),
            ),
            ("severity", {k: str(v) for k, v in self.severity.items()}, self.source_of("severity")),
            ("fail-on", str(self.fail_on), self.source_of("fail-on")),
            ("schema", str(self.schema) if self.schema else None, self.source_of("schema")),
            ("output-format", self.output_format, self.source_of("output-format")),
            ("sarif-max-results", self.sarif_max_results, self.source_of("sarif-max-results")),
            ("exclude", list(self.exclude), self.source_of("exclude")),
            ("respect-gitignore", self.respect_gitignore, self.source_of("respect-gitignore")),
            (
                "warn-unused-suppressions",
                self.warn_unused_suppressions,
                self.source_of("warn-unused-suppressions"),
            ),
            ("all-versions", self.all_versions, self.source_of("all-versions")),
            ("xsd-scope", self.xsd_scope, self.source_of("xsd-scope")),
            ("max-file-size", format_size(self.max_file_size), self.source_of("max-file-size")),
            ("rule-timeout", self.rule_timeout, self.source_of("rule-timeout")),
            ("fix", self.fix, self.source_of("fix")),
            ("unsafe-fixes", self.unsafe_fixes, self.source_of("unsafe-fixes")),
            ("fixable", list(self.fixable), self.source_of("fixable")),
            ("unfixable", list(self.unfixable), self.source_of("unfixable")),
        ]
        values = {**self.option_defaults, **self.rule_options}
        rows += [(name, value, self.source_of(name)) for name, value in sorted(values.items())]
        return rows


# --- reading values -------------------------------------------------------------------

_Reader = Callable[[object], object]


def _strings(value: object) -> tuple[str, ...]:
    if isinstance(value, str):
        return (value,)
    if isinstance(value, list) and all(isinstance(item, str) for item in value):
        return tuple(value)
    raise TypeError("a list of strings")


def _severity(value: object) -> Severity:
    if isinstance(value, str) and value in {str(s) for s in Severity}:
        return Severity(value)
    raise TypeError("one of 'error', 'warning', 'info'")


#: ``xsd-scope``: which schema errors a report lists.
XSD_SCOPES: Final = ("all", "railroad")


def _xsd_scope(value: object) -> str:
    if isinstance(value, str) and value in XSD_SCOPES:
        return value
    raise TypeError("one of 'all', 'railroad'")


def _text(value: object) -> str:
    if isinstance(value, str) and value:
        return value
    raise TypeError("a non-empty string")


def _boolean(value: object) -> bool:
    if isinstance(value, bool):
        return value
    raise TypeError("true or false")


def _number(value: object) -> float:
    if isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value):
        return float(value)
    raise TypeError("a finite number")


def _count(value: object) -> int:
    """A whole number, 0 or more (a limit, where 0 means none)."""
    if isinstance(value, int) and not isinstance(value, bool) and value >= 0:
        return value
    raise TypeError("a whole number, 0 or more (0: no limit)")


def seconds(value: object) -> float:
    """A time limit in seconds: a finite number from 0 (no limit) to a day (a larger one
    is no limit in all but name, and past 1e9 the interval timer cannot hold it)."""
    number = _number(value)
    if not 0 <= number <= MAX_SECONDS:
        raise TypeError(f"a number of seconds from 0 (no limit) to {MAX_SECONDS:g}")
    return number


#: The longest time limit a setting takes: a day.
MAX_SECONDS: Final = 86_400.0
#: The longest rule time limit a configuration found in a folder may set (a repository's
#: file may lower the limit, or raise it for slow rules, but not lift it).
MAX_FOUND_RULE_TIMEOUT: Final = 600.0


def _globs_to_codes(value: object) -> tuple[tuple[str, tuple[str, ...]], ...]:
    if not isinstance(value, dict):
        raise TypeError("a table of glob = [codes]")
    return tuple((str(glob), _strings(codes)) for glob, codes in value.items())


def _code_to_severity(value: object) -> dict[str, Severity]:
    if not isinstance(value, dict):
        raise TypeError("a table of CODE = 'error' | 'warning' | 'info'")
    return {str(code): _severity(level) for code, level in value.items()}


_READERS: Final[Mapping[str, _Reader]] = {
    "select": _strings,
    "extend-select": _strings,
    "ignore": _strings,
    "per-file-ignores": _globs_to_codes,
    "severity": _code_to_severity,
    "fail-on": _severity,
    "schema": _text,
    "output-format": _text,
    "sarif-max-results": _count,
    "exclude": _strings,
    "respect-gitignore": _boolean,
    "warn-unused-suppressions": _boolean,
    "all-versions": _boolean,
    "xsd-scope": _xsd_scope,
    "max-file-size": parse_size,
    "rule-timeout": seconds,
    "fix": _boolean,
    "unsafe-fixes": _boolean,
    "fixable": _strings,
    "unfixable": _strings,
}
#: The keys of the settings themselves: a rule option (a pack's too) may take none of
#: these names, which share the config table and the command line with it.
SETTING_KEYS: Final = frozenset(_READERS)


def settings_from(
    config: ConfigFile | None,
    overrides: Mapping[str, object],
    *,
    rule_options: Mapping[str, RuleOption] | None = None,
    known_codes: Iterable[str] = (),
) -> Settings:
    """The effective settings: defaults, then ``config``, then ``overrides`` (the command
    line, ``None`` meaning not given). ``rule_options`` are the options the rules declare
    (a plugin's too), by name: a config file may set them, and ``xodrlint config`` shows
    each with its default; ``known_codes`` are the codes ``severity`` may name."""
    options = dict(rule_options or {})
    values: dict[str, object] = {}
    sources: dict[str, str] = {}
    if config is not None:
        values.update(_validated(config, options, set(known_codes)))
        sources.update(dict.fromkeys(values, str(config.path)))
    for key, value in overrides.items():
        if value is not None:
            values[key] = value
            sources[key] = COMMAND_LINE
    base = config.base if config is not None else Path.cwd()
    schema = values.get("schema")
    if isinstance(schema, str) and sources.get("schema") != COMMAND_LINE:
        schema = base / schema  # a relative schema path in a file is relative to the file
    return Settings(
        select=tuple(_get(values, "select", ("ALL",))),
        extend_select=tuple(_get(values, "extend-select", ())),
        ignore=tuple(_get(values, "ignore", ())),
        per_file_ignores=tuple(_get(values, "per-file-ignores", ())),
        severity=dict(_get(values, "severity", {})),
        fail_on=Severity(_get(values, "fail-on", Severity.WARNING)),
        schema=Path(schema) if isinstance(schema, str | Path) else None,
        output_format=str(_get(values, "output-format", "text")),
        sarif_max_results=int(_get(values, "sarif-max-results", DEFAULT_SARIF_MAX_RESULTS)),
        exclude=tuple(_get(values, "exclude", ())),
        respect_gitignore=bool(values.get("respect-gitignore", True)),
        rule_options={name: values[name] for name in options if name in values},  # type: ignore[misc]
        option_defaults={name: option.default for name, option in options.items()},
        warn_unused_suppressions=bool(values.get("warn-unused-suppressions", False)),
        all_versions=bool(values.get("all-versions", False)),
        xsd_scope=str(values.get("xsd-scope", "all")),
        max_file_size=int(_get(values, "max-file-size", DEFAULT_MAX_FILE_SIZE)),
        rule_timeout=float(_get(values, "rule-timeout", DEFAULT_RULE_TIMEOUT)),
        fix=bool(values.get("fix", False)),
        diff=bool(values.get("diff", False)),
        unsafe_fixes=bool(values.get("unsafe-fixes", False)),
        fixable=tuple(_get(values, "fixable", ("ALL",))),
        unfixable=tuple(_get(values, "unfixable", ())),
        base=base,
        config_file=config.path if config is not None else None,
        sources=sources,
    )


def _get(values: Mapping[str, object], key: str, default: Any) -> Any:
    return values.get(key, default)


def shown_value(value: object, limit: int = 80) -> str:
    """``repr(value)`` for a message, cut to ``limit`` characters: a value in a config
    file may be megabytes long, and a message is one line."""
    text = repr(value[: limit + 1] if isinstance(value, str) else value)
    return text if len(text) <= limit else f"{text[: limit - 3]}..."


def _validated(
    config: ConfigFile, options: Mapping[str, RuleOption], codes: set[str]
) -> dict[str, object]:
    where = f"{config.path} [{config.section}]" if config.section else config.path
    values: dict[str, object] = {}
    for key, raw in config.table.items():
        option = options.get(key)
        reader = _READERS.get(key) or (option.checked if option is not None else None)
        if reader is None:
            known = ", ".join(sorted([*_READERS, *options]))
            raise ConfigError(f"{where}: unknown key '{key}' (known: {known})")
        try:
            values[key] = reader(raw)
        except TypeError as expected:
            shown = shown_value(raw)
            raise ConfigError(f"{where}: '{key}' must be {expected}, got {shown}") from None
    unknown = [code for code in _get(values, "severity", {}) if codes and code not in codes]
    if unknown:
        raise ConfigError(f"{where}: 'severity' names no rule '{unknown[0]}'")
    return values


# --- globs -----------------------------------------------------------------------------
