"""``xodrlint rules`` and ``xodrlint explain``: the rule catalogue, as a table, as JSON,
and one rule's documentation page."""

from __future__ import annotations

import sys

from xodrlint.api import default_registry
from xodrlint.output import color_wanted, interactive
from xodrlint.output import error_line as _error


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
                "enabled_by_default": not m.opt_in,
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
    opt_in = [m.code for m in registry.metas if m.opt_in]
    if opt_in:
        print(f"\nOff by default (turn on with --extend-select): {', '.join(opt_in)}")
    return 0


def explain_rule(token: str, color: str | None = None) -> int:
    """Print a rule's page: drawn from its Markdown on a terminal or where ``color``
    (see :func:`~xodrlint.output.color_wanted`) asks for styles; else the Markdown."""
    found = default_registry().find(token)
    if found is None:
        _error(f"no rule '{token}' (see 'xodrlint rules')")
        return 2
    from rich.markdown import Markdown

    meta = found.meta
    header = (
        f"# {meta.code} {meta.name}\n\n"
        f"Severity: {meta.severity} · UID: `{meta.uid}`"
        + "".join(f" · alias `{alias}`" for alias in meta.aliases)
        + (f" · off by default (`--extend-select {meta.code}`)" if meta.opt_in else "")
        + "\n\n"
    )
    body = meta.doc.split("\n", 1)[1] if "\n" in meta.doc else ""
    styled = color_wanted(color, sys.stdout)
    if styled or interactive(sys.stdout):
        from xodrlint.formatters.text import styled_console

        styled_console(sys.stdout, "always" if styled else "never").print(
            Markdown(header + meta.summary + "\n" + body)
        )
    else:
        sys.stdout.write(header + meta.summary + "\n" + body + "\n")
    return 0
