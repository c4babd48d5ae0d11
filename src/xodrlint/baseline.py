"""The baseline: findings a team has accepted, so only new ones are reported.

``--write-baseline FILE`` records every current finding by its stable fingerprint (rule
code, path relative to the working folder, XPath; never line numbers, so edits elsewhere
in a map do not break it). ``--baseline FILE`` then withholds the recorded ones. The
fingerprints are the ones SARIF's ``partialFingerprints`` carry.
"""

from __future__ import annotations

import json
from collections import Counter
from collections.abc import Sequence
from pathlib import Path
from typing import Final

from xodrlint.findings import FileReport, Suppressed, fingerprints, relative_path

FORMAT_VERSION: Final = 1
JUSTIFICATION: Final = "recorded in the baseline"


class BaselineError(ValueError):
    """A baseline file that cannot be read."""


def baseline_document(reports: Sequence[FileReport], root: str) -> dict[str, object]:
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
    return {"format_version": FORMAT_VERSION, "tool": "xodrlint", "findings": entries}


def load_baseline(path: Path) -> Counter[str]:
    """The fingerprints a baseline file records."""
    try:
        document = json.loads(path.read_text(encoding="utf-8"))
    except OSError as error:
        raise BaselineError(f"{path}: cannot read: {error.strerror or error}") from error
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
        or document.get("format_version") != FORMAT_VERSION
        or not isinstance(entries, list)
        or not all(isinstance(e, dict) and isinstance(e.get("fingerprint"), str) for e in entries)
    ):
        raise BaselineError(f"{path}: not an xodrlint baseline (format {FORMAT_VERSION})")
    return Counter(entry["fingerprint"] for entry in entries)


def apply_baseline(
    reports: Sequence[FileReport], recorded: Counter[str], root: str, *, keep: bool
) -> list[FileReport]:
    """The reports without the findings the baseline records (kept as suppressed if ``keep``)."""
    remaining = Counter(recorded)
    return [withhold_recorded(report, remaining, root, keep=keep) for report in reports]


def withhold_recorded(
    report: FileReport, remaining: Counter[str], root: str, *, keep: bool
) -> FileReport:
    """One report without the findings ``remaining`` still records, each taken from it: a
    streaming run applies the baseline file by file, as files complete, with one counter."""
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
