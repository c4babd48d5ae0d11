"""The ``xodrlint`` command: gathers options, builds a run, hands off. No logic lives here."""

from __future__ import annotations

import os
import sys
from enum import StrEnum
from pathlib import Path
from typing import Annotated, NoReturn

import typer

from xodrlint import __version__

app = typer.Typer(
    name="xodrlint",
    help="Lint the railroad content of ASAM OpenDRIVE (.xodr) files.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
    context_settings={"help_option_names": ["-h", "--help"]},
)
schemas_app = typer.Typer(
    help="Manage the official OpenDRIVE schemas used for full validation.",
    no_args_is_help=True,
)
app.add_typer(schemas_app, name="schemas")


class FailOn(StrEnum):
    error = "error"
    warning = "warning"
    info = "info"


def _fail(message: str, code: int = 2) -> NoReturn:
    typer.echo(f"xodrlint: {message}", err=True)
    raise typer.Exit(code)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"xodrlint {__version__}")
        raise typer.Exit(0)


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option(
            "--version", callback=_version, is_eager=True, help="Show the version and exit."
        ),
    ] = False,
) -> None:
    """Lint the railroad content of ASAM OpenDRIVE (.xodr) files."""


def _split(values: list[str] | None) -> tuple[str, ...]:
    return tuple(v.strip() for raw in values or [] for v in raw.split(",") if v.strip())


@app.command()
def check(
    paths: Annotated[
        list[str],
        typer.Argument(help="Files, folders (searched for *.xodr) or '-' for standard input."),
    ],
    output_format: Annotated[
        str, typer.Option("--output-format", "-f", help="text or json (or a plugin's format).")
    ] = "text",
    output: Annotated[
        str | None, typer.Option("--output", "-o", help="Write the report to FILE ('-': stdout).")
    ] = None,
    select: Annotated[
        list[str] | None,
        typer.Option(help="Rule codes, prefixes, names or UIDs to run (comma-separated)."),
    ] = None,
    ignore: Annotated[
        list[str] | None, typer.Option(help="Rule codes, prefixes, names or UIDs to skip.")
    ] = None,
    fail_on: Annotated[
        FailOn, typer.Option(help="Lowest severity that makes the exit code 1.")
    ] = FailOn.warning,
    exit_zero: Annotated[
        bool, typer.Option("--exit-zero", help="Exit 0 even when there are findings.")
    ] = False,
    schema: Annotated[
        Path | None,
        typer.Option(help="An XSD file, or a folder with one schema set or one per version."),
    ] = None,
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="Print findings only, no summary.")
    ] = False,
    show_source: Annotated[
        bool, typer.Option("--show-source", help="Show the source line of each finding.")
    ] = False,
    stdin_filename: Annotated[
        str | None, typer.Option(help="The path to report for input read from '-'.")
    ] = None,
    rail_min_width: Annotated[
        float | None,
        typer.Option(
            help="Narrowest allowed rail/tram lane in metres (RL003; default 1.435).",
            rich_help_panel="Rule options",
        ),
    ] = None,
    refline_tolerance: Annotated[
        float | None,
        typer.Option(
            help="Largest allowed distance of a rail lane's centre from the reference line "
            "in metres (RL002; default 0.05).",
            rich_help_panel="Rule options",
        ),
    ] = None,
) -> None:
    """Lint OpenDRIVE files and report findings."""
    from xodrlint.run import CheckRequest, run_check

    code = run_check(
        CheckRequest(
            paths=tuple(paths),
            output_format=output_format,
            output=output,
            select=_split(select) or ("ALL",),
            ignore=_split(ignore),
            fail_on=str(fail_on),
            exit_zero=exit_zero,
            schema=schema,
            quiet=quiet,
            show_source=show_source,
            stdin_filename=stdin_filename,
            rule_options=_rule_options(
                {"rail-min-width": rail_min_width, "refline-tolerance": refline_tolerance}
            ),
        )
    )
    raise typer.Exit(code)


def _rule_options(given: dict[str, float | None]) -> dict[str, float]:
    return {name: value for name, value in given.items() if value is not None}


@app.command("rules")
def rules_command(
    output_format: Annotated[
        str, typer.Option("--output-format", "-f", help="text or json.")
    ] = "text",
) -> None:
    """List every rule: code, name, severity and ASAM rule UID."""
    from xodrlint.run import print_rules

    raise typer.Exit(print_rules(output_format))


@app.command()
def explain(code: Annotated[str, typer.Argument(help="A rule code, name or UID.")]) -> None:
    """Show a rule's documentation."""
    from xodrlint.run import explain_rule

    raise typer.Exit(explain_rule(code))


@schemas_app.command("list")
def schemas_list() -> None:
    """Show which schema each OpenDRIVE version is validated with."""
    from xodrlint.run import list_schemas

    raise typer.Exit(list_schemas())


@schemas_app.command("add")
def schemas_add(
    source: Annotated[Path, typer.Argument(help="An ASAM schema download: a folder or a zip.")],
) -> None:
    """Copy official schema sets into the user data folder."""
    from xodrlint.run import add_schemas

    raise typer.Exit(add_schemas(source))


@schemas_app.command("fetch")
def schemas_fetch(
    wheel: Annotated[
        Path | None,
        typer.Option(help="Use this already downloaded asam-qc-opendrive wheel (offline)."),
    ] = None,
) -> None:
    """Download ASAM's schemas (1.1 to 1.8.0) from the asam-qc-opendrive wheel on PyPI."""
    from xodrlint.run import fetch_schemas

    raise typer.Exit(fetch_schemas(wheel))


def main() -> None:
    """Console entry point: every failure ends in one line and a documented exit code."""
    try:
        app()
    except KeyboardInterrupt:
        typer.echo("xodrlint: interrupted", err=True)
        sys.exit(130)
    except SystemExit:
        raise
    except Exception as error:  # the last line of defence: exit 3, never a traceback
        if os.environ.get("XODRLINT_DEBUG"):
            raise
        typer.echo(
            f"xodrlint: internal error: {type(error).__name__}: {error} "
            "(set XODRLINT_DEBUG=1 for the traceback, and please report it)",
            err=True,
        )
        sys.exit(3)
