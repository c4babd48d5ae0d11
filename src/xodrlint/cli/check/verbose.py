"""``check --verbose``: what the run is doing, on stderr, for a person asking why a run
is slow or which schema judged a file: the settings it runs with, then each file with
its declared version, the schema it was validated with and the time of each stage."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from xodrlint.config.settings import Settings
from xodrlint.findings import FileReport
from xodrlint.formatters.output import error_line
from xodrlint.messages import one_line, plural
from xodrlint.runners.batch import uses_workers

#: How stages are named on the line, in the order they run.
STAGE_LABELS = {
    "read": "read",
    "parse": "parse",
    "model": "model",
    "rules": "rules",
    "validation": "validation (beside model and rules)",
    "waiting for validation": "waiting for validation",
    "total": "total",
}


def seconds(value: float) -> str:
    """A duration as people read it: milliseconds below a second."""
    return f"{value * 1000:.1f} ms" if value < 1 else f"{value:.2f} s"


def describe_run(
    settings: Settings, rules: Iterable[str], files: int, jobs: int, scheduler: str | None = None
) -> None:
    config = settings.config_file
    error_line(f"config: {config}" if config is not None else "config: none (defaults)")
    codes = sorted(rules)
    error_line(f"rules: {len(codes)} selected ({', '.join(codes)})")
    workers = f"in {jobs} worker processes" if uses_workers(jobs, files) else "in this process"
    if scheduler == "local":
        workers = f"on a local Dask cluster of {jobs} worker processes"
    elif scheduler is not None:
        workers = f"on the workers of the Dask scheduler {scheduler}"
    error_line(f"files: {files}, linted {workers}")


def describe_file(report: FileReport) -> None:
    """One line for the file: what it declares, what validated it, how long each took."""
    if report.error:
        return  # its error line says what happened
    facts = [
        f"OpenDRIVE {report.declared_version}" if report.declared_version else "no version",
        f"schema: {report.schema}" if report.schema else "schema: not validated",
    ]
    if report.schema_note:
        facts.append(report.schema_note)
    if report.schema_route:
        facts.append(report.schema_route)
    facts.append(_stages(report.timings))
    error_line(f"{one_line(report.path)}: {'; '.join(facts)}")


def _stages(timings: Mapping[str, float]) -> str:
    shown = [
        f"{label} {seconds(timings[stage])}"
        for stage, label in STAGE_LABELS.items()
        if stage in timings
    ]
    return ", ".join(shown) if shown else "no timings"


def describe_end(files: int, elapsed: float) -> None:
    error_line(f"linted {plural(files, 'file')} in {seconds(elapsed)}")
