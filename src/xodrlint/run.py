"""What each CLI command does, kept out of ``cli.py`` so commands stay declarations."""

from __future__ import annotations

import io
import os
import sys
import tempfile
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Final, TextIO

from xodrlint import __version__
from xodrlint.api import Input, collect_inputs, default_registry, exit_code, lint_inputs
from xodrlint.engine import Linter, LintOptions, OptionError, SelectorError
from xodrlint.findings import FileReport, RunResult, Severity
from xodrlint.formatters import available, get_formatter
from xodrlint.schemas import SCHEMA_PATH_ENV, SchemaFinder, SchemaLoadError, builtin_set

STDOUT: Final = "-"
_Render = Callable[[TextIO], None]
FULL_VALIDATION_NOTE: Final = (
    "only railroad elements were validated (built-in schema); for full OpenDRIVE "
    f"validation run 'xodrlint schemas fetch', or point {SCHEMA_PATH_ENV} or --schema at "
    "the official ASAM schemas"
)


@dataclass(frozen=True)
class CheckRequest:
    paths: tuple[str, ...]
    output_format: str = "text"
    output: str | None = None
    select: tuple[str, ...] = ("ALL",)
    ignore: tuple[str, ...] = ()
    fail_on: str = "warning"
    exit_zero: bool = False
    schema: Path | None = None
    quiet: bool = False
    show_source: bool = False
    stdin_filename: str | None = None
    rule_options: Mapping[str, float] = field(default_factory=dict)


def _error(message: str) -> None:
    print(f"xodrlint: {message}", file=sys.stderr)


def run_check(request: CheckRequest) -> int:
    registry = default_registry()
    for warning in registry.warnings:
        _error(f"warning: {warning}")
    try:
        formatter = get_formatter(
            request.output_format, show_source=request.show_source, quiet=request.quiet
        )
    except KeyError:
        _error(
            f"unknown output format '{request.output_format}' "
            f"(choose from {', '.join(available())})"
        )
        return 2
    if request.schema is not None and not request.schema.exists():
        _error(f"--schema {request.schema}: no such file or folder")
        return 2
    options = LintOptions(
        select=request.select,
        ignore=request.ignore,
        schema=request.schema,
        keep_source=request.show_source,
        rule_options=request.rule_options,
    )
    try:
        linter = Linter(registry, options)
    except (SelectorError, OptionError) as error:
        _error(str(error))
        return 2
    inputs = list(collect_inputs(request.paths))
    if request.output not in (None, STDOUT):
        problem = _output_problem(Path(request.output), inputs)
        if problem is not None:
            _error(f"--output {request.output}: {problem}")
            return 2
    stdin = sys.stdin.buffer.read() if any(i.is_stdin for i in inputs) else None
    name = request.stdin_filename or "-"
    try:
        reports = list(lint_inputs(linter, inputs, stdin, name))
    except SchemaLoadError as error:
        _error(str(error))
        return 2
    for report in reports:
        if report.error:
            _error(report.error)
        for crash in report.internal_errors:
            _error(f"internal error: {crash}")
    result = RunResult(
        tuple(reports), registry.metas, __version__, notes=_notes(reports), root=os.getcwd()
    )
    try:
        _write(request.output, lambda stream: formatter.render(result, stream))
    except OSError as error:
        _error(f"--output {request.output}: cannot write: {error.strerror or error}")
        return 2
    return exit_code(reports, Severity(request.fail_on), request.exit_zero)


def _notes(reports: list[FileReport]) -> tuple[str, ...]:
    return (FULL_VALIDATION_NOTE,) if any(r.schema_builtin for r in reports) else ()


def _output_problem(output: Path, inputs: list[Input]) -> str | None:
    """Why ``output`` cannot take the report, checked before any linting is done."""
    if _is_input(output, inputs):
        return "is one of the inputs; refusing to overwrite it"
    if output.is_dir():
        return "is a folder"
    if not output.parent.is_dir():
        return f"its folder {output.parent} does not exist"
    return None


def _is_input(output: Path, inputs: list[Input]) -> bool:
    target = os.path.realpath(output)
    return any(item.path is not None and os.path.realpath(item.path) == target for item in inputs)


def _write(output: str | None, render: _Render) -> None:
    """Render to stdout, or to ``output`` whole: a temp file beside it, then a rename."""
    if output in (None, STDOUT):
        render(sys.stdout)
        sys.stdout.flush()
        return
    target = Path(output)
    handle, temporary = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent or ".")
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="\n") as stream:
            render(stream)
        Path(temporary).replace(target)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


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
