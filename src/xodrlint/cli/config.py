"""``xodrlint config``: the effective configuration and where each value comes from."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from xodrlint.api import default_registry
from xodrlint.cli.check.run import resolve_settings
from xodrlint.config.settings import ConfigError
from xodrlint.formatters.output import error_line as _error


def show_config(paths: tuple[str, ...], config: Path | None, output_format: str) -> int:
    """The effective configuration for ``paths`` and where each value comes from."""
    registry = default_registry()
    for warning in registry.warnings:  # a refused pack's options are unknown keys
        _error(f"warning: {warning}")
    try:
        settings = resolve_settings(registry, paths, config=config)
    except ConfigError as error:
        _error(str(error))
        return 2
    rows = settings.as_rows()
    if output_format == "json":
        document = {
            "config_file": str(settings.config_file) if settings.config_file else None,
            "settings": {key: {"value": value, "source": source} for key, value, source in rows},
        }
        json.dump(document, sys.stdout, indent=2)
        sys.stdout.write("\n")
        return 0
    print(f"config file: {settings.config_file or '(none)'}")
    width = max(len(key) for key, _, _ in rows)
    for key, value, source in rows:
        print(f"{key:<{width}}  {_toml(value):<40}  # {source}")
    return 0


def _toml(value: object) -> str:
    """A value the way it would be written in the config file."""
    if value is None:
        return "(not set)"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        # a regular expression's backslashes read as written in a literal string
        literal = ("\\" in value or '"' in value) and "'" not in value and "\n" not in value
        return f"'{value}'" if literal else json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(_toml(item) for item in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f'"{k}" = {_toml(v)}' for k, v in value.items()) + "}"
    return f"{value:g}" if isinstance(value, float) else str(value)
