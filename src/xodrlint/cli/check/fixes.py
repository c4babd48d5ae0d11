"""What ``check --fix`` and ``--diff`` write besides a report: the diffs of ``--diff``
(standard output, and their count on standard error) and the fixed document of standard
input (standard output)."""

from __future__ import annotations

import sys
from collections.abc import Sequence

from xodrlint.findings import FileReport
from xodrlint.formatters.output import error_line, release
from xodrlint.messages import plural


def show_diffs(reports: Sequence[FileReport]) -> int:
    """Print each file's diff, say how many findings ``--fix`` would mend, and return the
    exit code: 2 for a file that could not be read, 3 for an internal error (a fix rolled
    back), 1 when there is anything to fix, else 0 (the errors themselves the run has
    said already)."""
    try:
        for report in reports:
            if report.diff:
                sys.stdout.write(report.diff)
        sys.stdout.flush()
    except BrokenPipeError:
        release(sys.stdout)
    fixable = sum(report.fixed for report in reports)
    files = sum(1 for report in reports if report.fixed)
    if fixable:
        error_line(f"would fix {plural(fixable, 'finding')} in {plural(files, 'file')}")
    else:
        error_line("no fixes available")
    if any(report.error for report in reports):
        return 2
    if any(report.internal_errors for report in reports):
        return 3
    return 1 if fixable else 0


def write_document(data: bytes) -> bool:
    """Write the fixed document to standard output, byte for byte; whether it was."""
    try:
        sys.stdout.flush()
        sys.stdout.buffer.write(data)
        sys.stdout.buffer.flush()
    except BrokenPipeError:
        release(sys.stdout)
    except OSError as error:
        error_line(f"standard output: cannot write: {error.strerror or error}")
        return False
    return True
