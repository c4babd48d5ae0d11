"""The ``xodrlint`` command line as typer declarations: every command's arguments, options
and help, each handing off to its own module in this package. No logic lives here."""

# No ``from __future__ import annotations``: typer reads the parameters' annotations at
# run time, and a string annotation costs an eval (a compile) each, 20 ms per run.
from enum import StrEnum
from pathlib import Path
from typing import Annotated, Any, NoReturn

import typer
from typer.core import TyperArgument, TyperCommand

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


class Color(StrEnum):
    auto = "auto"
    always = "always"
    never = "never"


_COLOR_HELP = (
    "Style the text: auto (on a terminal, unless NO_COLOR is set; FORCE_COLOR forces "
    "it), always or never."
)

_ALL_VERSIONS_HELP = (
    "Apply every rule to every OpenDRIVE version, also the conventions a later version "
    "introduced (RL001, RL002 apply from 1.7 on; by default files declaring 1.4 to 1.6 "
    "are not judged by them, and a note says so)."
)


class _Command(TyperCommand):
    """A command whose usage line names its arguments as their help does (``PATH...``,
    ``[PATH...]`` when optional), not in the braces typer puts around required ones."""

    # ``Any``: the context is click's, which typer vendors (privately) from 0.20 on
    def collect_usage_pieces(self, ctx: Any) -> list[str]:
        pieces = [self.options_metavar] if self.options_metavar else []
        for param in self.get_params(ctx):
            if isinstance(param, TyperArgument):
                name = param.metavar or (param.name or "").upper()
                pieces.append(name if param.required else f"[{name}]")
            else:
                pieces.extend(param.get_usage_pieces(ctx))
        return pieces


_XSD_SCOPE_HELP = (
    "Which schema errors to list: all (the default), or railroad: only those about "
    "railroad elements, stations, roads with a rail or tram lane and the header; the "
    "others are counted in one note per file."
)


class XsdScope(StrEnum):
    all = "all"
    railroad = "railroad"


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


_CONFIG = "Configuration"
_SELECTION = "Rule selection"
_OUTPUT = "Output"
_RUN = "Run"
_FIXES = "Fixes"
_RULE_OPTIONS = "Rule options"


@app.command(cls=_Command)
def check(
    ctx: typer.Context,
    paths: Annotated[
        list[str],
        typer.Argument(
            metavar="PATH...",
            help="Files, folders (searched for *.xodr), glob patterns, or '-' for standard input.",
        ),
    ],
    output_format: Annotated[
        str | None,
        typer.Option(
            "--output-format",
            "-f",
            metavar="FORMAT",
            help="text, concise, json, jsonl (written as files are done), sarif, github, "
            "gitlab, junit, xqar, or a plugin's.",
            rich_help_panel=_OUTPUT,
        ),
    ] = None,
    output: Annotated[
        str | None,
        typer.Option(
            "--output",
            "-o",
            metavar="FILE",
            help="Write the report to FILE ('-': stdout).",
            rich_help_panel=_OUTPUT,
        ),
    ] = None,
    report: Annotated[
        list[str] | None,
        typer.Option(
            "--report",
            metavar="FORMAT=FILE",
            help="Also write a report in FORMAT to FILE (repeatable), e.g. "
            "--report gitlab=gl-code-quality.json --report junit=junit.xml.",
            rich_help_panel=_OUTPUT,
        ),
    ] = None,
    select: Annotated[
        list[str] | None,
        typer.Option(
            metavar="CODES",
            help="Rule codes, prefixes, names or UIDs to run (comma-separated).",
            rich_help_panel=_SELECTION,
        ),
    ] = None,
    extend_select: Annotated[
        list[str] | None,
        typer.Option(
            metavar="CODES",
            help="Rules to run in addition to --select.",
            rich_help_panel=_SELECTION,
        ),
    ] = None,
    ignore: Annotated[
        list[str] | None,
        typer.Option(
            metavar="CODES",
            help="Rule codes, prefixes, names or UIDs to skip.",
            rich_help_panel=_SELECTION,
        ),
    ] = None,
    fail_on: Annotated[
        FailOn | None,
        typer.Option(
            metavar="SEVERITY",
            help="Lowest severity that makes the exit code 1: error, warning (the default) "
            "or info.",
            rich_help_panel=_OUTPUT,
        ),
    ] = None,
    exit_zero: Annotated[
        bool,
        typer.Option(
            "--exit-zero", help="Exit 0 even when there are findings.", rich_help_panel=_OUTPUT
        ),
    ] = False,
    schema: Annotated[
        Path | None,
        typer.Option(
            metavar="PATH",
            help="An XSD file, or a folder with one schema set or one per version.",
            rich_help_panel=_CONFIG,
        ),
    ] = None,
    quiet: Annotated[
        bool,
        typer.Option(
            "--quiet",
            "-q",
            help="Print findings only, no summary (notes of what was not checked stay).",
            rich_help_panel=_OUTPUT,
        ),
    ] = False,
    verbose: Annotated[
        bool,
        typer.Option(
            "--verbose",
            "-v",
            help="Say on stderr what the run does: its config and rules, then each file's "
            "declared version, schema and time per stage.",
            rich_help_panel=_OUTPUT,
        ),
    ] = False,
    show_source: Annotated[
        bool,
        typer.Option(
            "--show-source", help="Show the source line of each finding.", rich_help_panel=_OUTPUT
        ),
    ] = False,
    color: Annotated[
        Color | None,
        typer.Option("--color", metavar="WHEN", help=_COLOR_HELP, rich_help_panel=_OUTPUT),
    ] = None,
    statistics: Annotated[
        bool,
        typer.Option(
            "--statistics",
            help="Print counts per rule instead of findings: a table (text, concise) "
            "or a JSON document (json); --report files still hold the findings.",
            rich_help_panel=_OUTPUT,
        ),
    ] = False,
    stdin_filename: Annotated[
        str | None,
        typer.Option(
            metavar="PATH",
            help="The path to report for input read from '-'.",
            rich_help_panel=_RUN,
        ),
    ] = None,
    config: Annotated[
        Path | None,
        typer.Option(
            metavar="FILE",
            help="Use this config file (pyproject.toml, xodrlint.toml) instead of searching.",
            rich_help_panel=_CONFIG,
        ),
    ] = None,
    isolated: Annotated[
        bool,
        typer.Option("--isolated", help="Ignore all config files.", rich_help_panel=_CONFIG),
    ] = False,
    exclude: Annotated[
        list[str] | None,
        typer.Option(
            metavar="GLOBS", help="Glob patterns of files to skip.", rich_help_panel=_CONFIG
        ),
    ] = None,
    respect_gitignore: Annotated[
        bool | None,
        typer.Option(
            "--respect-gitignore/--no-respect-gitignore",
            help="Leave out of folder walks what .gitignore, .ignore and .git/info/exclude "
            "exclude (default: respect them).",
            rich_help_panel=_CONFIG,
        ),
    ] = None,
    show_files: Annotated[
        bool,
        typer.Option(
            "--show-files",
            help="Print the files that would be linted, one per line, and exit.",
            rich_help_panel=_CONFIG,
        ),
    ] = False,
    jobs: Annotated[
        int | None,
        typer.Option(
            "--jobs",
            "-j",
            min=1,
            metavar="N",
            help="Worker processes (default: one per core).",
            rich_help_panel=_RUN,
        ),
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            metavar="ADDRESS",
            help="Lint on a Dask cluster: a running scheduler (tcp://host:8786), or 'local' "
            "for one of --jobs worker processes on this machine. Needs the dask extra: "
            "pip install 'xodrlint[dask]'.",
            rich_help_panel=_RUN,
        ),
    ] = None,
    scheduler_timeout: Annotated[
        float | None,
        typer.Option(
            "--scheduler-timeout",
            metavar="SECONDS",
            help="Give up on a --scheduler not reached, or without a worker, within this "
            "many seconds (default 30).",
            rich_help_panel=_RUN,
        ),
    ] = None,
    shard: Annotated[
        str | None,
        typer.Option(
            "--shard",
            metavar="K/N",
            help="Lint only part K of N (1 to N), parts chosen by a stable hash of each "
            "path as reported: a CI matrix of N jobs lints every file once.",
            rich_help_panel=_RUN,
        ),
    ] = None,
    baseline: Annotated[
        Path | None,
        typer.Option(
            metavar="FILE",
            help="Report only findings not recorded in this baseline file.",
            rich_help_panel=_RUN,
        ),
    ] = None,
    write_baseline: Annotated[
        Path | None,
        typer.Option(
            metavar="FILE",
            help="Record the current findings in this baseline file and exit 0.",
            rich_help_panel=_RUN,
        ),
    ] = None,
    warn_unused_suppressions: Annotated[
        bool | None,
        typer.Option(
            "--warn-unused-suppressions",
            help="Report suppression comments that withhold nothing: an alias of "
            "--extend-select XL001.",
            rich_help_panel=_SELECTION,
        ),
    ] = None,
    all_versions: Annotated[
        bool | None,
        typer.Option(
            "--all-versions",
            help=_ALL_VERSIONS_HELP,
            rich_help_panel=_SELECTION,
        ),
    ] = None,
    xsd_scope: Annotated[
        XsdScope | None,
        typer.Option(
            "--xsd-scope", metavar="SCOPE", help=_XSD_SCOPE_HELP, rich_help_panel=_SELECTION
        ),
    ] = None,
    fix: Annotated[
        bool | None,
        typer.Option(
            "--fix/--no-fix",
            help="Apply the safe fixes and write each changed file back; standard input's "
            "fixed document goes to standard output.",
            rich_help_panel=_FIXES,
            show_default=False,
        ),
    ] = None,
    unsafe_fixes: Annotated[
        bool | None,
        typer.Option(
            "--unsafe-fixes/--no-unsafe-fixes",
            help="Make the unsafe fixes too (they change what the network means).",
            rich_help_panel=_FIXES,
            show_default=False,
        ),
    ] = None,
    diff: Annotated[
        bool,
        typer.Option(
            "--diff",
            help="Print a unified diff of what --fix would change and write nothing; "
            "exit 1 when there is anything to fix.",
            rich_help_panel=_FIXES,
        ),
    ] = False,
    fixable: Annotated[
        list[str] | None,
        typer.Option(
            metavar="CODES",
            help="Only these rules' fixes count (codes, prefixes, names; comma-separated).",
            rich_help_panel=_FIXES,
        ),
    ] = None,
    unfixable: Annotated[
        list[str] | None,
        typer.Option(
            metavar="CODES",
            help="These rules' fixes never count (codes, prefixes, names; comma-separated).",
            rich_help_panel=_FIXES,
        ),
    ] = None,
    show_suppressed: Annotated[
        bool,
        typer.Option(
            "--show-suppressed",
            help="Keep suppressed findings in SARIF output, marked as suppressed.",
            rich_help_panel=_OUTPUT,
        ),
    ] = False,
    sarif_max_results: Annotated[
        int | None,
        typer.Option(
            min=0,
            metavar="N",
            help="At most this many SARIF results, the most important: errors first "
            "(default 25000, the most GitHub code scanning accepts; 0: no limit).",
            rich_help_panel=_OUTPUT,
        ),
    ] = None,
    max_file_size: Annotated[
        str | None,
        typer.Option(
            metavar="SIZE",
            help="Refuse inputs larger than this, before reading them: bytes, or 500MB, "
            "2GiB (default 2GiB).",
            rich_help_panel=_RUN,
        ),
    ] = None,
    rule_timeout: Annotated[
        float | None,
        typer.Option(
            min=0,
            metavar="SECONDS",
            help="Stop a rule that runs longer than this many seconds on one file and "
            "report it as an internal error (default 60; 0: no limit).",
            rich_help_panel=_RUN,
        ),
    ] = None,
    rail_min_width: Annotated[
        float | None,
        typer.Option(
            metavar="METRES",
            help="Narrowest allowed rail/tram lane in metres (RL003; default 1.435).",
            rich_help_panel=_RULE_OPTIONS,
        ),
    ] = None,
    refline_tolerance: Annotated[
        float | None,
        typer.Option(
            metavar="METRES",
            help="Largest allowed distance of a rail lane's centre from the reference line "
            "in metres (RL002; default 0.05).",
            rich_help_panel=_RULE_OPTIONS,
        ),
    ] = None,
    rule_option: Annotated[
        list[str] | None,
        typer.Option(
            metavar="NAME=VALUE",
            help="Any rule option, a plugin's too: NAME=VALUE (repeatable).",
            rich_help_panel=_RULE_OPTIONS,
        ),
    ] = None,
) -> None:
    """Lint OpenDRIVE files and report findings."""
    from xodrlint.cli.check.request import CheckRequest
    from xodrlint.cli.check.run import run_check

    code = run_check(
        CheckRequest(
            paths=tuple(paths),
            output_format=output_format,
            output=output,
            select=_split(select) or None,
            extend_select=_split(extend_select) or None,
            ignore=_split(ignore) or None,
            fail_on=str(fail_on) if fail_on is not None else None,
            exit_zero=exit_zero,
            schema=schema,
            quiet=quiet,
            verbose=verbose,
            color=str(color) if color is not None else None,
            show_source=show_source,
            stdin_filename=stdin_filename,
            rule_options=_rule_options(rule_option, rail_min_width, refline_tolerance),
            config=config,
            isolated=isolated,
            exclude=_split(exclude) or None,
            respect_gitignore=respect_gitignore,
            show_files=show_files,
            jobs=jobs,
            scheduler=scheduler,
            scheduler_timeout=scheduler_timeout,
            baseline=baseline,
            write_baseline=write_baseline,
            warn_unused_suppressions=warn_unused_suppressions,
            all_versions=all_versions,
            xsd_scope=str(xsd_scope) if xsd_scope is not None else None,
            show_suppressed=show_suppressed,
            fix=fix,
            unsafe_fixes=unsafe_fixes,
            diff=diff,
            fixable=_split(fixable) or None,
            unfixable=_split(unfixable) or None,
            sarif_max_results=sarif_max_results,
            statistics=statistics,
            reports=tuple(report or ()),
            max_file_size=max_file_size,
            rule_timeout=rule_timeout,
            shard=shard,
            keep_alive=_keep_alive(ctx),
        )
    )
    raise typer.Exit(code)


def _keep_alive(ctx: typer.Context) -> list[object] | None:
    """The entry point's list of what outlives a run (see ``CheckRequest.keep_alive``)."""
    kept = ctx.find_root().obj
    return kept if isinstance(kept, list) else None


def _rule_options(
    named: list[str] | None, rail_min_width: float | None, refline_tolerance: float | None
) -> dict[str, float | str]:
    """The rule options a command line gave: ``--rule-option NAME=VALUE`` entries (their
    text, read once the rules are known: a number option takes a number, a text option
    any text), and the built-in rules' own flags, which win."""
    flags = {"rail-min-width": rail_min_width, "refline-tolerance": refline_tolerance}
    given = {name: value for name, value in flags.items() if value is not None}
    return {**_named_options(named or []), **given}


def _named_options(entries: list[str]) -> dict[str, float | str]:
    values: dict[str, float | str] = {}
    for entry in entries:
        name, sign, raw = entry.partition("=")
        if not sign or not name.strip():
            _fail(f"--rule-option {entry}: expected NAME=VALUE")
        values[name.strip()] = raw
    return values


@app.command("qc", cls=_Command)
def qc_command(
    ctx: typer.Context,
    input_file: Annotated[
        str | None,
        typer.Argument(metavar="FILE", help="The file to check, when no configuration names it."),
    ] = None,
    config: Annotated[
        Path | None,
        typer.Option(
            "--config",
            "-c",
            metavar="FILE",
            help="The ASAM Quality Checker configuration (XML).",
        ),
    ] = None,
    output: Annotated[
        str | None,
        typer.Option(
            "--output",
            "-o",
            metavar="FILE",
            help="The result file (default: the configuration's).",
        ),
    ] = None,
    manifest: Annotated[
        str | None,
        typer.Option(
            metavar="FILE",
            help="Write the framework's module manifest for xodrlint here and stop.",
        ),
    ] = None,
) -> None:
    """Run as a checker bundle of the ASAM Quality Checker framework (writes XQAR)."""
    from xodrlint.cli.qc import run_qc

    raise typer.Exit(run_qc(config, input_file, output, manifest, _keep_alive(ctx)))


@app.command("map", cls=_Command)
def map_command(
    ctx: typer.Context,
    path: Annotated[str, typer.Argument(metavar="FILE", help="The .xodr file to draw.")],
    output: Annotated[
        str,
        typer.Option(
            "--output",
            "-o",
            metavar="FILE",
            help="The page to write: FILE.html (interactive) or FILE.svg.",
        ),
    ],
    select: Annotated[list[str] | None, typer.Option(metavar="CODES", help="As for check.")] = None,
    extend_select: Annotated[
        list[str] | None, typer.Option(metavar="CODES", help="As for check.")
    ] = None,
    ignore: Annotated[list[str] | None, typer.Option(metavar="CODES", help="As for check.")] = None,
    fail_on: Annotated[
        FailOn | None, typer.Option(metavar="SEVERITY", help="As for check.")
    ] = None,
    schema: Annotated[Path | None, typer.Option(metavar="PATH", help="As for check.")] = None,
    config: Annotated[Path | None, typer.Option(metavar="FILE", help="As for check.")] = None,
    isolated: Annotated[bool, typer.Option("--isolated", help="As for check.")] = False,
    all_versions: Annotated[
        bool | None, typer.Option("--all-versions", help="As for check.")
    ] = None,
    xsd_scope: Annotated[
        XsdScope | None, typer.Option("--xsd-scope", metavar="SCOPE", help="As for check.")
    ] = None,
    rail_min_width: Annotated[
        float | None, typer.Option(metavar="METRES", help="As for check.")
    ] = None,
    refline_tolerance: Annotated[
        float | None, typer.Option(metavar="METRES", help="As for check.")
    ] = None,
    rule_option: Annotated[
        list[str] | None, typer.Option(metavar="NAME=VALUE", help="As for check.")
    ] = None,
    exit_zero: Annotated[
        bool, typer.Option("--exit-zero", help="Exit 0 even when there are findings.")
    ] = False,
    quiet: Annotated[
        bool,
        typer.Option(
            "--quiet",
            "-q",
            help="Print findings only: no header, summary or 'wrote' line (notes stay).",
        ),
    ] = False,
) -> None:
    """Draw the network with every finding on it: a self-contained HTML page or an SVG."""
    from xodrlint.cli.check.request import CheckRequest
    from xodrlint.cli.map import MapRequest, run_map

    lint = CheckRequest(
        paths=(path,),
        select=_split(select) or None,
        extend_select=_split(extend_select) or None,
        ignore=_split(ignore) or None,
        fail_on=str(fail_on) if fail_on is not None else None,
        schema=schema,
        config=config,
        isolated=isolated,
        all_versions=all_versions,
        xsd_scope=str(xsd_scope) if xsd_scope is not None else None,
        rule_options=_rule_options(rule_option, rail_min_width, refline_tolerance),
        exit_zero=exit_zero,
        quiet=quiet,
        keep_alive=_keep_alive(ctx),
        fix=False,  # the map draws the file as it is: no `fix` from a configuration
    )
    raise typer.Exit(run_map(MapRequest(lint, output)))


@app.command("server")
def server_command() -> None:
    """Run the language server over standard input and output, for editors (see
    docs/editors.md; needs the server extra: pip install 'xodrlint[server]')."""
    try:
        from xodrlint.server.protocol import serve
    except ImportError as error:
        _fail(f"the language server needs pygls ({error}): pip install 'xodrlint[server]'")
    raise typer.Exit(serve())


@app.command("config", cls=_Command)
def config_command(
    paths: Annotated[
        list[str] | None,
        typer.Argument(
            metavar="PATH...",
            help=(
                "The file or folder whose settings to show (the first path given; "
                "default: the working folder). Each file has its nearest configuration."
            ),
        ),
    ] = None,
    config: Annotated[
        Path | None, typer.Option(metavar="FILE", help="Use this config file.")
    ] = None,
    output_format: Annotated[
        str, typer.Option("--output-format", "-f", metavar="FORMAT", help="text or json.")
    ] = "text",
) -> None:
    """Show the effective configuration and where each value comes from."""
    from xodrlint.cli.config import show_config

    raise typer.Exit(show_config(tuple(paths or ["."]), config, output_format))


@app.command("rules")
def rules_command(
    output_format: Annotated[
        str, typer.Option("--output-format", "-f", metavar="FORMAT", help="text or json.")
    ] = "text",
) -> None:
    """List every rule: code, name, severity and ASAM rule UID."""
    from xodrlint.cli.rules import print_rules

    raise typer.Exit(print_rules(output_format))


@app.command(cls=_Command)
def explain(
    code: Annotated[str, typer.Argument(metavar="RULE", help="A rule code, name or UID.")],
    color: Annotated[
        Color | None, typer.Option("--color", metavar="WHEN", help=_COLOR_HELP)
    ] = None,
) -> None:
    """Show a rule's documentation."""
    from xodrlint.cli.rules import explain_rule

    raise typer.Exit(explain_rule(code, str(color) if color is not None else None))


@schemas_app.command("list")
def schemas_list() -> None:
    """Show which schema each OpenDRIVE version is validated with."""
    from xodrlint.cli.schemas import list_schemas

    raise typer.Exit(list_schemas())


@schemas_app.command("add", cls=_Command)
def schemas_add(
    source: Annotated[
        Path, typer.Argument(metavar="PATH", help="An ASAM schema download: a folder or a zip.")
    ],
) -> None:
    """Copy official schema sets into the user data folder."""
    from xodrlint.cli.schemas import add_schemas

    raise typer.Exit(add_schemas(source))


@schemas_app.command("fetch")
def schemas_fetch(
    wheel: Annotated[
        Path | None,
        typer.Option(
            metavar="FILE", help="Use this already downloaded asam-qc-opendrive wheel (offline)."
        ),
    ] = None,
) -> None:
    """Download ASAM's schemas (1.1 to 1.8.0) from the asam-qc-opendrive wheel on PyPI."""
    from xodrlint.cli.schemas import fetch_schemas

    raise typer.Exit(fetch_schemas(wheel))
