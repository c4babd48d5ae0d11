"""``xodrlint rules`` and ``xodrlint explain``: the rule catalogue, as a table, as JSON,
and one rule's documentation page."""

from __future__ import annotations

import sys

from xodrlint.api import default_registry
from xodrlint.findings import PackInfo, RuleMeta
from xodrlint.formatters.output import color_wanted, interactive
from xodrlint.formatters.output import error_line as _error


def print_rules(output_format: str) -> int:
    registry = default_registry()
    if output_format not in ("text", "json"):
        _error(f"unknown output format '{output_format}' (choose from text, json)")
        return 2
    for warning in registry.warnings:
        _error(f"warning: {warning}")
    if output_format == "json":
        import json

        json.dump([_entry(meta) for meta in registry.metas], sys.stdout, indent=2)
        sys.stdout.write("\n")
        return 0
    _print_table(registry.metas)
    opt_in = [m.code for m in registry.metas if m.opt_in]
    if opt_in:
        print(f"\nOff by default (turn on with --extend-select): {', '.join(opt_in)}")
    by_version: dict[tuple[int, int], list[str]] = {}
    for meta in registry.metas:
        if meta.since is not None:
            by_version.setdefault(meta.since, []).append(meta.code)
    for (major, minor), codes in sorted(by_version.items()):
        print(
            f"\nFrom OpenDRIVE {major}.{minor} on (older files with --all-versions): "
            + ", ".join(codes)
        )
    return 0


def _entry(meta: RuleMeta) -> dict[str, object]:
    return {
        "code": meta.code,
        "name": meta.name,
        "severity": str(meta.severity),
        "uid": meta.uid,
        "aliases": list(meta.aliases),
        "summary": meta.summary,
        "pack": meta.pack,
        "plugin": meta.origin.as_dict() if meta.origin else None,
        "options": [option.as_dict() for option in meta.options],
        "defers_to": list(meta.defers_to),
        "enabled_by_default": not meta.opt_in,
        "since": meta.since_label,
    }


def _print_table(metas: tuple[RuleMeta, ...]) -> None:
    """xodrlint's own rules in one table, then each installed pack's under its name,
    aligned as one table."""
    header = ("Code", "Name", "Severity", "UID")
    groups: dict[str, list[tuple[str, str, str, str]]] = {}
    for m in metas:
        origin = m.origin
        heading = "" if origin is None or origin.builtin else "R" + pack_label(origin)[1:]
        groups.setdefault(heading, []).append((m.code, m.name, str(m.severity), " ".join(m.uids)))
    rows = [header, *(row for group in groups.values() for row in group)]
    widths = [max(len(row[i]) for row in rows) for i in range(3)]

    def line(row: tuple[str, str, str, str]) -> str:
        cells = [cell.ljust(width) for cell, width in zip(row, widths, strict=False)]
        return "  ".join([*cells, row[3]])

    print(line(header))
    for heading, group in sorted(groups.items()):
        if heading:
            print(f"\n{heading}:")
        for row in group:
            print(line(row))


def pack_label(origin: PackInfo) -> str:
    """``rule pack 'house' (xodrlint-houserules 0.1.0)``"""
    installed_by = f" ({origin.distribution} {origin.version})" if origin.distribution else ""
    return f"rule pack '{origin.name}'{installed_by}"


def explain_rule(token: str, color: str | None = None) -> int:
    """Print a rule's page: drawn from its Markdown on a terminal or where ``color``
    (see :func:`~xodrlint.formatters.output.color_wanted`) asks for styles; else the Markdown."""
    registry = default_registry()
    for warning in registry.warnings:  # why a pack's rule may be missing
        _error(f"warning: {warning}")
    found = registry.find(token)
    if found is None:
        _error(f"no rule '{token}' (see 'xodrlint rules')")
        return 2
    from rich.markdown import Markdown

    meta = found.meta
    origin = meta.origin
    header = (
        f"# {meta.code} {meta.name}\n\n"
        f"Severity: {meta.severity} · UID: `{meta.uid}`"
        + "".join(f" · alias `{alias}`" for alias in meta.aliases)
        + (f" · off by default (`--extend-select {meta.code}`)" if meta.opt_in else "")
        + (
            f" · from OpenDRIVE {meta.since_label} on (older files: `--all-versions`)"
            if meta.since_label
            else ""
        )
        + (f" · {pack_label(origin)}" if origin and not origin.builtin else "")
        + "\n\n"
    )
    body = meta.doc.partition("\n")[2]  # the page as its author wrote it, blank lines too
    styled = color_wanted(color, sys.stdout)
    if styled or interactive(sys.stdout):
        from xodrlint.formatters.text import styled_console

        styled_console(sys.stdout, "always" if styled else "never").print(
            Markdown(header + meta.summary + "\n" + body)
        )
    else:
        sys.stdout.write(header + meta.summary + "\n" + body + "\n")
    return 0
