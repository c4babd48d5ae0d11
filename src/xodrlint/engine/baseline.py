"""The baseline: findings a team has accepted, so only new ones are reported.

``--write-baseline FILE`` records every current finding by its stable fingerprint (rule
code, path relative to the baseline file's folder, XPath; never line numbers, so edits
elsewhere in a map do not break it). ``--baseline FILE`` then withholds the recorded
ones, from whichever folder the run starts: ``cd sub && xodrlint check .. --baseline
../baseline.json`` matches what ``xodrlint check . --baseline baseline.json`` recorded.
A baseline of format 1 (paths relative to the folder it was written in) is read as
before: relative to the working folder.
"""

from __future__ import annotations

import json
from collections import Counter
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Final, NamedTuple

from xodrlint.findings import FileReport, Suppressed, fingerprints, relative_path
from xodrlint.inputs.collect import STDIN
from xodrlint.inputs.files import os_reason
from xodrlint.messages import plural

FORMAT_VERSION: Final = 2
#: Format 1 recorded paths relative to the working folder of the run that wrote it.
OLD_FORMAT: Final = 1
JUSTIFICATION: Final = "recorded in the baseline"


class BaselineError(ValueError):
    """A baseline file that cannot be read."""


class Baseline(NamedTuple):
    """A baseline file as read: its fingerprints, and the folder its paths are relative
    to (the file's own; the working folder for format 1)."""

    path: Path
    recorded: Counter[str]
    root: str
    paths: frozenset[str]
    """The files its entries are about, relative to :attr:`root`."""

    @property
    def name(self) -> str:
        return str(self.path)

    def covers(self, name: str) -> bool:
        """Whether an entry is about the file reported as ``name``."""
        return name != STDIN and relative_path(name, self.root) in self.paths

    def unmatched(self, linted: Iterable[str]) -> str | None:
        """Why the baseline withholds nothing from a run that linted ``linted`` (paths as
        reported), when none of its entries is about one of them; ``None`` otherwise."""
        names = [name for name in linted if name != STDIN]
        if not self.recorded or not names or any(self.covers(name) for name in names):
            return None
        return self.matches_nothing()

    def matches_nothing(self) -> str:
        """The warning for a run none of whose files the baseline's entries are about:
        a baseline written from another folder by an older xodrlint, or for other maps."""
        entries = sum(self.recorded.values())
        return (
            f"--baseline {self.path}: none of its {plural(entries, 'finding')} is about a "
            f"file this run linted (its paths are relative to {self.root})"
        )


def baseline_document(reports: Sequence[FileReport], baseline: Path) -> dict[str, object]:
    """The baseline ``baseline`` records for ``reports``: paths and fingerprints relative
    to its folder."""
    root = str(baseline.absolute().parent)
    entries = []
    for report in reports:
        prints = fingerprints(report.findings, root)
        for finding, fingerprint in zip(report.findings, prints, strict=True):
            entries.append(
                {
                    "fingerprint": fingerprint,
                    "code": finding.code,
                    "path": relative_path(finding.path, root),
                    "xpath": finding.xpath,
                    "message": finding.message,
                }
            )
    return {
        "format_version": FORMAT_VERSION,
        "tool": "xodrlint",
        "paths_relative_to": "the folder of this file",
        "findings": entries,
    }


def load_baseline(path: Path) -> Baseline:
    """A baseline file, as :class:`Baseline`."""
    try:
        document = json.loads(path.read_text(encoding="utf-8"))
    except OSError as error:
        raise BaselineError(f"{path}: cannot read: {os_reason(error)}") from error
    except (ValueError, RecursionError) as error:  # bad JSON, a number past int's limit
        reason = (
            str(error)
            if isinstance(error, json.JSONDecodeError)
            else "nested too deeply"
            if isinstance(error, RecursionError)
            else "a number too long to read"
        )
        raise BaselineError(f"{path}: not a baseline (invalid JSON: {reason})") from error
    entries = document.get("findings") if isinstance(document, dict) else None
    if (
        not isinstance(document, dict)
        or document.get("format_version") not in (FORMAT_VERSION, OLD_FORMAT)
        or not isinstance(entries, list)
        or not all(isinstance(e, dict) and isinstance(e.get("fingerprint"), str) for e in entries)
    ):
        raise BaselineError(f"{path}: not an xodrlint baseline (format {FORMAT_VERSION})")
    old = document["format_version"] == OLD_FORMAT
    root = str(Path.cwd() if old else path.absolute().parent)
    paths = frozenset(e["path"] for e in entries if isinstance(e.get("path"), str))
    return Baseline(path, Counter(entry["fingerprint"] for entry in entries), root, paths)


def apply_baseline(
    reports: Sequence[FileReport], baseline: Baseline, *, keep: bool
) -> tuple[list[FileReport], int]:
    """The reports without the findings ``baseline`` records (kept as suppressed if
    ``keep``), and how many it withheld."""
    remaining = Counter(baseline.recorded)
    kept = [withhold_recorded(report, remaining, baseline.root, keep=keep) for report in reports]
    withheld = sum(len(r.findings) for r in reports) - sum(len(r.findings) for r in kept)
    return kept, withheld


def withhold_recorded(
    report: FileReport, remaining: Counter[str], root: str, *, keep: bool
) -> FileReport:
    """One report without the findings ``remaining`` still records, each taken from it: a
    streaming run applies the baseline file by file, as files complete, with one counter.
    ``root`` is the folder the baseline's paths are relative to."""
    kept, withheld = [], []
    for finding, fingerprint in zip(
        report.findings, fingerprints(report.findings, root), strict=True
    ):
        if remaining[fingerprint] > 0:
            remaining[fingerprint] -= 1
            withheld.append(Suppressed(finding, "external", JUSTIFICATION))
        else:
            kept.append(finding)
    suppressed = (*report.suppressed, *withheld) if keep else report.suppressed
    return report._replace(findings=tuple(kept), suppressed=suppressed)
