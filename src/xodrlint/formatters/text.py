"""The terminal report: findings grouped by file, ``path:line`` first so terminals link it.

Rich draws it; every piece of text goes in as ``Text`` (never markup), so XPath predicates
like ``[@id='3']`` survive, and lines are never wrapped when the output is piped.
"""

from __future__ import annotations

import errno
from typing import Final, TextIO

from rich.console import Console
from rich.text import Text

from xodrlint.findings import FileReport, Finding, RunResult, Severity
from xodrlint.fixes import Applicability
from xodrlint.formatters.output import color_wanted, interactive
from xodrlint.messages import one_line, plural

STYLE: Final = {
    Severity.ERROR: "bold red",
    Severity.WARNING: "yellow",
    Severity.INFO: "cyan",
}


class _Console(Console):
    def on_broken_pipe(self) -> None:
        # rich would point standard output at the null device and exit 1, whatever the
        # run found, and also when the pipe was a FIFO named by -o: the caller decides
        self.quiet = True
        raise BrokenPipeError(errno.EPIPE, "broken pipe")


def styled_console(stream: TextIO, color: str | None) -> Console:
    """A console on ``stream`` that styles text only where :func:`color_wanted` says so:
    never a code in a pipe or under ``NO_COLOR``, colour on demand in a CI log."""
    wanted = color_wanted(color, stream)
    if not wanted:
        system = None  # no style at all: rich's own NO_COLOR keeps bold and underline
    elif interactive(stream):
        system = "auto"
    else:
        system = "standard"  # forced where rich, detecting, would choose none
    return _Console(
        file=stream,
        soft_wrap=True,
        highlight=False,
        emoji=False,
        color_system=system,  # type: ignore[arg-type]  # rich's Literal of the names
        force_terminal=wanted,
        no_color=not wanted,  # else rich reads NO_COLOR itself, over --color always
    )


class TextFormatter:
    # the run's notes go to stderr, after the report (the command says them): standard
    # output holds the report alone, as a file or a pipe wants it
    carries_notes = False
    says_withheld = True  # its summary line

    def __init__(
        self,
        *,
        show_source: bool = False,
        quiet: bool = False,
        color: str | None = None,
        unsafe_fixes: bool = False,
    ) -> None:
        self.show_source = show_source
        self.quiet = quiet
        self.color = color  # one of output.COLOR_CHOICES; None is "auto"
        self.unsafe_fixes = unsafe_fixes  # whether unsafe fixes count as fixable

    def render(self, result: RunResult, stream: TextIO) -> None:
        console = styled_console(stream, self.color)
        for report in result.reports:
            if report.findings:
                self._file(console, report)
        if not self.quiet:
            console.print(_summary(result))
            fixable = _fixable_line(result, self.unsafe_fixes)
            if fixable is not None:
                console.print(fixable)
            # the facts of files without findings, which have no header to say them
            # (--quiet, the pre-commit hook, drops them with the summary); the run's
            # notes, what was not checked, the command says on stderr either way
            for note in _schema_notes(result):
                console.print(Text("note: ", style="bold") + Text(one_line(note)))

    def _file(self, console: Console, report: FileReport) -> None:
        if not self.quiet:
            header = Text(one_line(report.path), style="bold underline")
            facts = [f"OpenDRIVE {report.declared_version}"] if report.declared_version else []
            if report.schema:
                facts.append(f"schema: {report.schema}")
            if report.schema_note:
                facts.append(report.schema_note)
            if facts:
                header.append(f"  ({'; '.join(facts)})", style="dim")
            console.print(header)
        for finding in report.findings:
            console.print(_line(finding, self.unsafe_fixes))
            if self.quiet:
                continue
            console.print(Text(f"    {finding.xpath}", style="dim"))
            # the report keeps its own file's lines (a finding in an included file has none)
            own = self.show_source and finding.path == report.path
            source = report.source_lines.get(finding.line) if own else None
            if source is not None:
                console.print(
                    Text(f"    {finding.line:>6} | ", style="dim") + Text(one_line(source))
                )
        if not self.quiet:
            console.print()


def _schema_notes(result: RunResult) -> list[str]:
    """What the file headers do not say for files without findings: the schema each was
    validated with (every report names it), and when it was not of the file's version."""
    shown = {r.schema for r in result.reports if r.findings}
    notes: list[str] = []
    for report in result.reports:
        if report.findings or report.schema is None or report.schema_builtin:
            continue
        if report.schema_note:
            notes.append(f"{report.path}: {report.schema_note}")
        if report.schema not in shown:
            shown.add(report.schema)
            notes.append(f"validated with the {report.schema}")
    return notes


def _marked(finding: Finding, unsafe_fixes: bool) -> bool:
    """Whether ``--fix`` (with ``--unsafe-fixes`` where the run has it) mends ``finding``."""
    fix = finding.fix
    return fix is not None and (unsafe_fixes or fix.applicability is Applicability.SAFE)


def _fixable_line(result: RunResult, unsafe_fixes: bool) -> Text | None:
    """``[*] 3 fixable with --fix (2 more with --unsafe-fixes).``, where there are any."""
    findings = result.findings
    fixable = sum(1 for finding in findings if _marked(finding, unsafe_fixes))
    hidden = sum(1 for finding in findings if finding.fix is not None) - fixable
    if not fixable and not hidden:
        return None
    if not fixable:
        return Text(f"No fixes available with --fix ({hidden} with --unsafe-fixes).")
    flag = "--fix --unsafe-fixes" if unsafe_fixes else "--fix"
    text = f"[*] {fixable} fixable with {flag}"
    if hidden:
        text += f" ({hidden} more with --unsafe-fixes)"
    return Text(text + ".")


def _line(finding: Finding, unsafe_fixes: bool = False) -> Text:
    # a file name may hold anything a terminal obeys (ESC, line breaks): escaped
    location = f"{one_line(finding.path)}:{finding.line}"
    if finding.column is not None:
        location += f":{finding.column}"
    text = Text()
    text.append(location, style="bold")  # the location alone: the message stays plain
    text.append(": ")
    text.append(finding.code, style=STYLE[finding.severity])
    text.append(f" [{finding.severity}] ", style=STYLE[finding.severity])
    if _marked(finding, unsafe_fixes):
        text.append("[*] ", style="bold")
    text.append(finding.message)
    return text


def _summary(result: RunResult) -> Text:
    files = len(result.reports)
    counts = result.count_by_severity()
    total = sum(counts.values())
    unreadable = sum(1 for r in result.reports if r.error)
    # a rule failed or ran out of time there, or the whole lint failed: what it did not
    # check did not pass
    broken = sum(1 for r in result.reports if r.internal_errors and not r.error)
    new = " new" if result.baseline is not None else ""
    if total == 0 and not unreadable and not broken:
        text = Text(f"All checks passed: {plural(files, 'file')}, no{new} findings", style="green")
    elif total == 0:
        text = Text(f"No{new} findings in {files - unreadable} of {plural(files, 'file')}")
    else:
        # "info" is a mass noun: "2 info", as the map page says
        parts = ", ".join(
            plural(n, severity, "info" if severity == "info" else None)
            for severity, n in counts.items()
            if n
        )
        with_findings = sum(1 for r in result.reports if r.findings)
        text = Text(
            f"Found {plural(total, f'{new.strip()} finding'.strip())} ({parts}) "
            f"in {with_findings} of {plural(files, 'file')}"
        )
    fixed = sum(report.fixed for report in result.reports)
    if fixed:
        # ruff's words: what was found is what is left and what was mended
        text = Text(
            f"Found {plural(total + fixed, 'finding')} ({fixed} fixed, {total} remaining) "
            f"in {plural(files, 'file')}"
        )
    if result.baseline is not None:  # what it took away belongs beside what is left
        text.append(f"; {result.withheld} withheld by {result.baseline}")
    text.append(".")
    if unreadable:
        text.append(f" {unreadable} could not be read.", style="red")
    if broken:
        text.append(f" {broken} not fully checked.", style="red")
    return text
